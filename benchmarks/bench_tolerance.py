"""Benchmark: tolerance analysis, time against error (first order against Monte Carlo of growing size).

For the four-bar and the slider-crank of ``examples/mechanisms`` (tolerances
1e-4 of each length, 36 input values), the first-order standard deviation
and Monte Carlo runs of 10^3 to 10^6 samples: the time of each, and the
Monte Carlo standard deviation's distance from the first-order one (the
sampling error, about 1/√(2n)). With ``--workers N`` the Monte Carlo
batches run on a local Dask cluster too.

    python benchmarks/bench_tolerance.py                 # docs/benchmarks.md
    python benchmarks/bench_tolerance.py --workers 2
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from domes.design.tolerance import Tolerancing, monte_carlo, sensitivity
from domes.execution import executor
from domes.io.mechanisms import load_mechanism

ROOT = Path(__file__).resolve().parents[1]
CASES = [("four-bar", "angle:rocker"), ("slider-crank", "point:M")]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--largest", type=int, default=1_000_000, help="largest sample count (default 10^6)")
    args = parser.parse_args()
    inputs = np.radians(np.arange(0.0, 360.0, 10.0))
    with executor(args.workers) as run:
        where = None if args.workers is None else run
        print(f"{'mechanism':<14s} {'method':<22s} {'time':>9s} {'σ / σ first order - 1':>22s}")
        for name, output in CASES:
            tol = Tolerancing(load_mechanism(ROOT / f"examples/mechanisms/{name}.json"), output, inputs, relative=1e-4)
            start = time.perf_counter()
            first = sensitivity(tol)
            print(f"{name:<14s} {'first order':<22s} {time.perf_counter() - start:8.3f}s {0:22.4f}")
            n = 1000
            while n <= args.largest:
                start = time.perf_counter()
                mc = monte_carlo(tol, n, seed=1, executor=where)
                seconds = time.perf_counter() - start
                error = float(np.max(np.abs(mc.std / first.std - 1)))
                print(f"{name:<14s} {f'Monte Carlo {n:,}':<22s} {seconds:8.3f}s {error:22.4f}")
                n *= 10
    print(f"(Monte Carlo {run.where})")


if __name__ == "__main__":
    main()
