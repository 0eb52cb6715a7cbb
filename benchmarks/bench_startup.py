"""Start-up of the command line: CPU time of short commands, each in a fresh process, median of several runs.

A command's start is imports: the parser registers only the named subcommand's options and each subcommand
imports its numerical modules when it runs (domes.cli). This measures what a user waits for before any work
(``domes --help``), a command that does little (the six-link atlas count) and one that loads the kernel.

    python benchmarks/bench_startup.py [--repeat 7]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import subprocess
import sys

COMMANDS = (
    ("domes --help", ["--help"]),
    ("domes chains --links 6 --dof 1 --count", ["chains", "--links", "6", "--dof", "1", "--count"]),
    ("domes kinematics examples/mechanisms/four-bar.json --at 30",
     ["kinematics", "examples/mechanisms/four-bar.json", "--at", "30"]),
    ("python -c 'import domes'", None),
)


def cpu_of(argv: list[str]) -> float:
    """User + system CPU seconds of one child process running ``argv``."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run(argv, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=7, help="runs of each command (default 7; the median is shown)")
    args = parser.parse_args(argv)
    print("| command | CPU s (median) | min | max |")
    print("|---|---:|---:|---:|")
    for label, words in COMMANDS:
        cmd = [sys.executable, "-c", "import domes"] if words is None else [sys.executable, "-m", "domes", *words]
        runs = [cpu_of(cmd) for _ in range(args.repeat)]
        print(f"| `{label}` | {statistics.median(runs):.2f} | {min(runs):.2f} | {max(runs):.2f} |")


if __name__ == "__main__":
    main()
