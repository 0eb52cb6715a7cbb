"""Nine-point path synthesis: every solution for random generic point sets, and Morgan & Wampler's Problem 7.

For each of ``--queries`` point sets (nine points uniform in the unit square, seeded) the solver
(:func:`domes.design.synthesis.ninepoint.nine_point_path`) tracks the 1,442 stored class representatives; the
script reports the classes found, the solutions (six a class), the real classes, the usable linkages (real, no
branch, order or dead-point defect, the kernel on every point), the largest Newton residual of all solutions
(the points scaled to size 1; for a solution far out, refined in extended precision, measured there), how many
solutions were refined in extended precision, the largest kernel distance of a usable linkage from a point over
the size, the paths tracked again, and the time per query (CPU and wall). Then Problem 7 (five points, two
pivots).

    python benchmarks/bench_ninepoint.py [--queries 20] [--seed 0] [--first 0] [--no-check]
"""

import argparse
import time

import numpy as np

from domes.design.synthesis.fivepoint import PROBLEM_7, five_point_pivots
from domes.design.synthesis.ninepoint import CLASSES, nine_point_path


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--queries", type=int, default=20)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--first", type=int, default=0, help="skip the first queries (their points are still drawn)")
    ap.add_argument("--no-check", action="store_true", help="skip the kernel checks of the real solutions")
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    rows = []
    print("query classes solutions real usable max-residual extended max-usable-distance/size retracked cpu-s "
          "wall-s")
    for q in range(args.queries):
        points = rng.uniform(0, 1, (9, 2))
        if q < args.first:
            continue
        c0, w0 = time.process_time(), time.perf_counter()
        r = nine_point_path(points, seed=q, check_mechanisms=not args.no_check)
        cpu, wall = time.process_time() - c0, time.perf_counter() - w0
        res = max(s.residual for s in r.solutions)
        far = max((max(s.distances) / r.size for s in r.usable), default=0.0)
        real = sum(1 for c in r.classes if c[0].real)
        fine = sum(1 for s in r.solutions if s.extended is not None)
        rows.append((len(r.classes), res, far, cpu, wall))
        print(f"{q:5d} {len(r.classes):7d} {len(r.solutions):9d} {real:4d} {len(r.usable):6d} {res:12.1e} {fine:8d} "
              f"{far:25.1e} {r.retracked:9d} {cpu:5.1f} {wall:6.1f}", flush=True)
    A = np.array(rows)
    print(f"all {CLASSES} classes in {int((A[:, 0] == CLASSES).sum())} of {len(A)} queries; largest residual "
          f"{A[:, 1].max():.1e}; largest usable distance {A[:, 2].max():.1e} of the size; CPU per query median "
          f"{np.median(A[:, 3]):.1f} s (max {A[:, 3].max():.1f}), wall median {np.median(A[:, 4]):.1f} s")
    c0 = time.process_time()
    r7 = five_point_pivots(PROBLEM_7, (0.0, 0.0), (1.0, 0.0))
    print(f"Problem 7: {r7.message} ({time.process_time() - c0:.2f} s CPU)")


if __name__ == "__main__":
    main()
