"""Benchmark: inverse dynamics, time against error as the step grows finer.

The forces at a step are exact to round-off whatever the step (the
kinematics' accelerations are analytic; the power balance shows it); the
step decides what a run sees between its steps. Measured:

* the single-cylinder engine of ``examples/dynamics`` over one crank turn
  at steps from 10° down to 0.1°: the time, the error of the peak crank
  torque against a run at 0.001° (a peak between steps is missed), the cycle
  work of the input (0 for a full turn: the gas force is constant and
  gravity conservative; the trapezoid rule's error), and the worst power
  balance;
* the 2-RPR scriber on the digest's stadium (D-14) from 100 to 10^6 points:
  the time, the error of the force spread on the arcs against 10^6 points,
  the contour's work (0 over a lap; the midpoint rule's error), and the
  worst power balance;
* the Newton–Euler solve of the scriber as a mechanism file (prescribed
  motion, step by step) against its closed-form Lagrange model.

No peer (Pyslvs, pylinkage) computes forces; they are not run here.

    python benchmarks/bench_dynamics.py                 # docs/benchmarks.md
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

import numpy as np

from domes.design.dynamics import inverse_dynamics
from domes.design.scriber import follow
from domes.io.mechanisms import load_mechanism, load_scriber_task

ROOT = Path(__file__).resolve().parents[1]


def timed(fn, *args, **kwargs):
    start = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - start


def engine(finest: float) -> None:
    mech = load_mechanism(ROOT / "examples/dynamics/slider-crank-engine.json")
    lo = math.radians(3.7)  # a start off the peak's angle, so that coarse grids can miss it
    ref, _ = timed(inverse_dynamics, mech, lo, lo + 2 * math.pi, math.radians(0.001))
    peak = float(np.max(np.abs(ref.driving["A"])))
    print(f"engine, one crank turn from 3.7° (reference: 0.001°, {ref.inputs.size:,} steps, peak torque {peak:.6g} N·m)")
    print(f"{'step':>8s} {'steps':>7s} {'time':>9s} {'peak error':>11s} {'cycle work / (P·T)':>19s} {'balance':>9s}")
    for step in (10.0, 5.0, 2.0, 1.0, 0.5, 0.2, 0.1):
        if step < finest:
            break
        dyn, seconds = timed(inverse_dynamics, mech, lo, lo + 2 * math.pi, math.radians(step))
        err = abs(float(np.max(np.abs(dyn.driving["A"]))) - peak) / peak
        work = np.trapezoid(dyn.input_power, dyn.time) / (dyn.peak_power * dyn.time[-1])
        print(f"{step:7.2f}° {dyn.inputs.size:7,d} {seconds:8.3f}s {err:11.2e} {abs(work):19.2e} "
              f"{dyn.max_imbalance:9.1e}")


def scriber(largest: int) -> None:
    task = load_scriber_task(ROOT / "examples/dynamics/scriber-stadium.json")
    ref, _ = timed(follow, task.scriber, task.contour, task.speed, largest)
    lo, hi = ref.spreads()["arc"]
    print(f"\nscriber on the stadium (reference: {largest:,} points, arc spread {hi - lo:.6g} N)")
    print(f"{'points':>9s} {'time':>9s} {'spread error':>13s} {'lap work / (P·T)':>17s} {'balance':>9s}")
    n = 100
    while n <= largest:
        run, seconds = timed(follow, task.scriber, task.contour, task.speed, n)
        a, b = run.spreads()["arc"]
        lap = task.contour.length / task.speed
        print(f"{n:9,d} {seconds:8.3f}s {abs((b - a) - (hi - lo)) / (hi - lo):13.2e} "
              f"{abs(run.work) / (run.peak_power * lap):17.2e} {run.max_imbalance:9.1e}")
        n *= 10


def newton_euler(points: int) -> None:
    task = load_scriber_task(ROOT / "examples/dynamics/scriber-stadium.json")
    s = task.scriber
    run = follow(s, task.contour, task.speed, points)
    mech = s.mechanism(run.P[0])
    motion = {"q1": (run.q[0], run.qd[0], run.qdd[0]), "q2": (run.q[1], run.qd[1], run.qdd[1])}
    dyn, seconds = timed(inverse_dynamics, mech, motion=motion)
    diff = np.max(np.abs(np.stack([dyn.driving["q1"], dyn.driving["q2"]], 1) - run.Q)) / np.max(np.abs(run.Q))
    _, closed = timed(follow, s, task.contour, task.speed, points)
    print(f"\nscriber as a mechanism file, {points:,} points: Newton–Euler {seconds:.3f}s (step by step, a 4-link "
          f"Newton group), closed-form Lagrange {closed:.4f}s; largest difference {diff:.1e} of the peak force")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--finest", type=float, default=0.1, help="finest engine step in degrees (default 0.1)")
    parser.add_argument("--largest", type=int, default=1_000_000, help="largest scriber sample (default 10^6)")
    args = parser.parse_args()
    engine(args.finest)
    scriber(args.largest)
    newton_euler(1000)


if __name__ == "__main__":
    main()
