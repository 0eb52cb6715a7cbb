"""Run a command; print its wall time and the peak of the summed memory of it and all its child processes.

``python benchmarks/measure.py domes chains --links 14 --dof 1 --count --yes --workers 2`` (docs/scale.md):
the memory is the resident set of the command and every process it starts (a Dask cluster's scheduler and
workers), sampled every 0.25 s.
"""

import subprocess
import sys
import time

import psutil


def main(argv: list[str]) -> int:
    if not argv or argv[0] in ("-h", "--help"):
        print("usage: measure.py COMMAND [ARGS...]\n\n" + __doc__)
        return 0
    start = time.time()
    process = subprocess.Popen(argv)
    watched = psutil.Process(process.pid)
    peak = 0
    while process.poll() is None:
        try:
            total = watched.memory_info().rss + sum(c.memory_info().rss for c in watched.children(recursive=True))
            peak = max(peak, total)
        except psutil.Error:
            pass
        time.sleep(0.25)
    print(f"exit {process.returncode}; wall {time.time() - start:.1f} s; peak summed RSS {peak / 2**30:.2f} GiB",
          file=sys.stderr)
    return process.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
