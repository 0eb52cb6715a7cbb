"""Benchmark: spatial kinematics and synthesis, time against accuracy.

* The RSSR of seed 001 over one crank turn: the closed form (arrays, all
  inputs at once) against the loop closure on rigid transforms (a sweep,
  Newton at every step with the analytic Jacobian), at steps from 10° to
  0.1°: the time per step, the largest difference of β, β̇, β̈ between the
  two, the largest loop-closure residual, and the error of Table 1's β̈
  minimum as sampled (a peak between steps is missed).
* A random RCCC and a two-loop chain: the loop closure's time per step.
* The four-position RCCC synthesis (the planted linkage and Table 1): the
  time of the search and the driver's min–max slide it reaches.

No peer in these benchmarks (Pyslvs, pylinkage) solves spatial linkages, so none is run.

    python benchmarks/bench_spatial.py                 # docs/benchmarks.md
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

from domes.design.synthesis.rccc import search
from domes.io.mechanisms import load_spatial
from domes.io.tasks import load_spatial_task
from domes.motion.spatial.rssr import RSSR
from domes.motion.spatial.sweep import spatial_sweep

ROOT = Path(__file__).resolve().parents[1]
EXACT_MIN = -137.58700


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def rssr(finest: float) -> None:
    mech = load_spatial(ROOT / "examples/spatial/rssr-seed001.json")
    r = RSSR.paper()
    print("RSSR of seed 001, one crank turn: closed form against loop closure")
    print(f"{'step':>7s} {'steps':>6s} {'closed form':>12s} {'loop closure':>13s} {'|Δβ|':>9s} {'|Δβ̇|':>9s} "
          f"{'|Δβ̈|/max':>10s} {'residual':>9s} {'β̈ min error':>12s}")
    for step in (10.0, 5.0, 1.0, 0.5, 0.1):
        if step < finest:
            break
        alpha = np.radians(np.arange(0.0, 360.0 + 1e-9, step))
        (beta, (bd, bdd)), t_closed = timed(lambda a: (np.unwrap(r.beta(a)), r.rates(a, np.unwrap(r.beta(a)), 10.0)),
                                            alpha)
        sw, t_loop = timed(spatial_sweep, mech, 0.0, 2 * math.pi, math.radians(step), outputs=["angle:B0"], order=2)
        n = sw.inputs.size
        d0 = np.max(np.abs(sw.table["angle:B0"] - beta[:n]))
        d1 = np.max(np.abs(sw.table["angle:B0'"] - bd[:n]))
        d2 = np.max(np.abs(sw.table["angle:B0''"] - bdd[:n])) / np.max(np.abs(bdd))
        print(f"{step:6.1f}° {n:6d} {t_closed / n * 1e6:9.2f} µs {t_loop / n * 1e3:10.3f} ms {d0:9.1e} {d1:9.1e} "
              f"{d2:10.1e} {np.max(sw.residuals):9.1e} {abs(bdd.min() - EXACT_MIN):12.2e}")


def loops() -> None:
    print("\nloop closure, time per step (order 2)")
    for name, path, stop in (("RCCC (planted)", "examples/spatial/rccc-planted.json", 80.0),):
        mech = load_spatial(ROOT / path)
        sw, t = timed(spatial_sweep, mech, 0.0, math.radians(stop), math.radians(1.0), order=2)
        print(f"  {name:<22s} {sw.inputs.size:5d} steps  {t / sw.inputs.size * 1e3:7.3f} ms a step  "
              f"residual ≤ {np.max(sw.residuals):.1e}")
    sys.path.insert(0, str(ROOT / "tests" / "motion"))
    from test_spatial import two_loop  # the two-loop chain of the tests (an RSSR with an S-S link to a slider)

    mech = two_loop(np.random.default_rng(200))
    sw, t = timed(spatial_sweep, mech, 0.0, math.radians(30), math.radians(0.5), order=2)
    print(f"  {'two loops (7 links)':<22s} {sw.inputs.size:5d} steps  {t / sw.inputs.size * 1e3:7.3f} ms a step  "
          f"residual ≤ {np.max(sw.residuals):.1e}")


def synthesis() -> None:
    print("\nfour-position RCCC synthesis (search over the circle-point curve)")
    planted = load_spatial_task(ROOT / "examples/synthesis/rccc-planted.json")
    table = load_spatial_task(ROOT / "examples/synthesis/rccc-table-1.json")
    for name, task in (("planted", planted), ("Table 1 (assumed convention)", table)):
        for meridians in (45, 90, 180):
            sol, t = timed(search, list(task.moves), meridians)
            print(f"  {name:<29s} {meridians:4d} meridians {t:7.2f} s  max slide {max(np.abs(sol.slides)):.3g}  "
                  f"{sol.label}, translation error ≤ {max(sol.translation_errors):.3g}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--finest", type=float, default=0.1, help="finest RSSR step in degrees (default 0.1)")
    args = parser.parse_args()
    rssr(args.finest)
    loops()
    synthesis()


if __name__ == "__main__":
    main()
