"""Benchmark: commands that fit and solve in loops, idle and beside a CPU-bound process (issue 25, item 1).

Each command runs as a user runs it (a subprocess of the installed ``domes``), first on an idle machine,
then with a second process spinning on one core the whole time (pure Python: it takes a core and no more,
as another user's job would). The slowdown is the ratio of the wall times. With BLAS and OpenMP held to
one thread a command (``domes.execution.threads``), two busy processes on two cores should cost little;
``--threads all`` sets ``DOMES_THREADS`` to show what oversubscription costs.

    python benchmarks/bench_busy.py
    python benchmarks/bench_busy.py --threads all     # the libraries' own defaults (a thread per core)
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DOMES = Path(sys.executable).with_name("domes")
COMMANDS = {
    "curves match (figure-eight)": ["curves", "match", "examples/curves/figure-eight.csv"],
    "synthesize (path, twelve points)": ["synthesize", "examples/synthesis/path-twelve-points.json"],
}


def spin(stop) -> None:
    """Take one core until told to stop."""
    x = 0
    while not stop.is_set():
        for _ in range(100_000):
            x = (x * 1103515245 + 12345) & 0x7FFFFFFF


def wall(argv: list[str], env: dict) -> float:
    start = time.perf_counter()
    done = subprocess.run([str(DOMES), *argv], cwd=ROOT, env=env, capture_output=True, text=True)
    seconds = time.perf_counter() - start
    if done.returncode != 0:
        raise SystemExit(f"domes {' '.join(argv)} failed: {done.stderr[-500:]}")
    return seconds


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--threads", help="DOMES_THREADS for the commands: a number or all (default: unset, one)")
    parser.add_argument("--repeat", type=int, default=1, help="runs of each command in each condition (the least)")
    args = parser.parse_args()
    env = dict(os.environ)
    if args.threads is not None:
        env["DOMES_THREADS"] = args.threads
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
          f"DOMES_THREADS={env.get('DOMES_THREADS', 'unset (1)')}")
    print(f"{'command':<36} {'idle s':>8} {'busy s':>8} {'slowdown':>9}")
    for name, argv in COMMANDS.items():
        idle = min(wall(argv, env) for _ in range(args.repeat))
        stop = multiprocessing.Event()
        other = multiprocessing.Process(target=spin, args=(stop,))
        other.start()
        try:
            busy = min(wall(argv, env) for _ in range(args.repeat))
        finally:
            stop.set()
            other.join()
        print(f"{name:<36} {idle:8.1f} {busy:8.1f} {busy / idle:8.2f}x", flush=True)


if __name__ == "__main__":
    main()
