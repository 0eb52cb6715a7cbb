"""Run a command; print its wall and CPU time and the peak memory of it and its child processes.

``python benchmarks/measure.py domes chains --links 14 --dof 1 --count --yes --workers 2`` (docs/scale.md):
the memory is the resident set of the command and every process it starts (a Dask cluster's scheduler and
workers), sampled every 0.25 s: the peak of their sum, and the peak of each process on its own (the largest
is the "per worker" figure). The CPU time is the sum over all of them (user + system, as last sampled).
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
    each: dict[int, tuple[int, str]] = {}              # pid -> (peak RSS, command line, shortened)
    cpu: dict[int, float] = {}
    while process.poll() is None:
        try:
            procs = [watched, *watched.children(recursive=True)]
        except psutil.Error:
            break
        total = 0
        for p in procs:
            try:
                rss = p.memory_info().rss
                times = p.cpu_times()
                cpu[p.pid] = times.user + times.system
                name = " ".join(p.cmdline())[-60:]
            except psutil.Error:
                continue
            total += rss
            if rss > each.get(p.pid, (0, ""))[0]:
                each[p.pid] = (rss, name)
        peak = max(peak, total)
        time.sleep(0.25)
    wall = time.time() - start
    print(f"exit {process.returncode}; wall {wall:.1f} s; CPU {sum(cpu.values()):.1f} s (all processes); "
          f"peak summed RSS {peak / 2**30:.2f} GiB", file=sys.stderr)
    for pid, (rss, name) in sorted(each.items(), key=lambda item: -item[1][0])[:6]:
        print(f"  peak {rss / 2**20:7.0f} MiB  pid {pid}  ...{name}", file=sys.stderr)
    return process.returncode


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
