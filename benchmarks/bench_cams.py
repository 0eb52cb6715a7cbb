"""Cams, gears, motion laws and Geneva wheels beside the linkage kernel (issue 26).

Run ``python benchmarks/bench_cams.py``. It prints, in one table, the median
of ``--repeat`` runs of:

- a disc cam's design (profile, pressure angle, radius of curvature) at
  ``--steps`` points, for a translating roller and an oscillating roller
  follower;
- the follower's motion on it (``domes.design.cam.follow``) at ``--steps``
  angles, from the exact pitch curve and from the profile's points, with
  the largest error of lift, velocity and acceleration against the law;
- the Geneva wheel's closed form at ``--steps`` angles;
- a four-bar driven by a motion law in time (``domes.motion.planar.timed``)
  at ``--steps`` times;
- gear pairs in the kernel: a planetary train (``examples/mechanisms/planetary.json``)
  and a sector gear on a four-bar's rocker swept over ``--steps`` steps,
  order 2, with the largest error against Willis' formula;
- a cam-driven linkage (``examples/mechanisms/cam-rocker.json``: a cam, its
  translating follower, a rod and a rocker) swept the same way, with the
  follower's largest acceleration error against the law's closed form;
- the sector gear and the cam-driven linkage also step by step (the scalar
  path, each step solved from the loop equations), with the largest
  difference of the kernel's table from it;
- beside them, the kinematics kernel's sweep of the same four-bar over
  ``--steps`` steps (positions, and order 2).

No peer designs cams or Geneva wheels, and neither Pyslvs nor pylinkage has
gear pairs; the kernel's own sweep is the yardstick.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_kernel import median_time  # noqa: E402

from domes.design.cam import Follower, design_cam, follow  # noqa: E402
from domes.execution.threads import limited_threads  # noqa: E402
from domes.io.mechanisms import load_mechanism  # noqa: E402
from domes.model.gears import GearPair  # noqa: E402
from domes.model.laws import Motion  # noqa: E402
from domes.model.mechanism import Joint, Mechanism  # noqa: E402
from domes.motion.geneva import Geneva  # noqa: E402
from domes.motion.planar.continuation import Continuation, grid  # noqa: E402
from domes.motion.planar.examples import four_bar  # noqa: E402
from domes.motion.planar.query import Kinematics  # noqa: E402
from domes.motion.planar.sweep import _scalar_sweep, sweep  # noqa: E402
from domes.motion.planar.timed import timed  # noqa: E402


def rows(steps: int, repeat: int) -> list[tuple[str, float, str]]:
    out = []
    th = np.linspace(0, 2 * math.pi, steps, endpoint=False)
    cases = [
        ("translating roller", Motion.cam([("cycloidal", 120, 20), ("dwell", 60), ("3-4-5", 120, -20), ("dwell", 60)]),
         Follower("translating", "roller", roller=10, offset=5)),
        ("oscillating roller", Motion.cam([("cycloidal", 120, math.radians(15)), ("dwell", 60),
                                           ("3-4-5", 120, -math.radians(15)), ("dwell", 60)]),
         Follower("oscillating", "roller", roller=8, pivot=100, arm=80)),
    ]
    for name, law, f in cases:
        t, cam = median_time(lambda: design_cam(law, f, 40, points=steps), repeat)
        out.append((f"cam design, {name}", t, f"largest pressure angle {cam.max_pressure_angle_deg:.2f}°"))
        want = law.evaluate(th)
        for source, label in ((cam, "exact pitch curve"), (cam.profile, f"{steps} profile points")):
            t, got = median_time(lambda: follow(source, f, 40, th), repeat)
            err = [float(np.max(np.abs(a - b))) for a, b in zip((got.s, got.ds, got.dds), want)]
            out.append((f"follower on the cam, {name}, {label}", t,
                        f"errors: lift {err[0]:.1e}, velocity {err[1]:.1e}, acceleration {err[2]:.1e}"))
    g = Geneva(4)
    t, _ = median_time(lambda: g.wheel(th), repeat)
    out.append(("Geneva wheel, 4 slots (closed form)", t, ""))
    law = Motion([("3-4-5", 0.4, 2.0), ("dwell", 0.2), ("simple harmonic", 0.4, -2.0)])
    times = np.linspace(0, 1, steps)
    t, run = median_time(lambda: timed(four_bar(), law, times, outputs=["angle:rocker"]), repeat)
    out.append(("four-bar driven by a motion law in time (order 2)", t, f"max residual {np.max(run.residuals):.1e}"))
    planetary = load_mechanism(ROOT / "examples/mechanisms/planetary.json")
    t, sw = median_time(lambda: sweep(planetary, 0.0, 2 * math.pi, 2 * math.pi / steps,
                                      outputs=["angle:arm", "angle:planet"], order=2), repeat)
    ws = planetary.inputs[0].speed
    err = max(float(np.max(np.abs(sw.table["angle:arm'"] - ws * 20 / 72))),
              float(np.max(np.abs(sw.table["angle:planet'"] - ws * 20 / 72 * (1 - 52 / 16)))))
    out.append(("planetary gear train, order 2 (kernel, arrays)", t, f"largest rate error against Willis {err:.1e}"))
    fb = four_bar()
    sector = Mechanism.build("sector", list(fb.links) + ["pinion"], "frame",
                             list(fb.joints) + [Joint("E", "R", ("frame", "pinion"), (3.0, -1.5))], list(fb.inputs),
                             gears=[GearPair("M", ("rocker", "pinion"), (3.0, -1.0))])
    t, sw = median_time(lambda: sweep(sector, 0.0, 2 * math.pi, 2 * math.pi / steps,
                                      outputs=["angle:pinion", "angle:rocker"], order=2), repeat)
    err = float(np.max(np.abs(sw.table["angle:pinion''"] + 2 * sw.table["angle:rocker''"])))
    out.append(("sector gear on a four-bar's rocker, order 2 (kernel, arrays)", t,
                f"largest acceleration error against Willis {err:.1e}"))
    out.append(_step_by_step("sector gear on a four-bar's rocker", sector, ["angle:pinion", "angle:rocker"], sw,
                             steps, repeat))
    cams = load_mechanism(ROOT / "examples/mechanisms/cam-rocker.json")
    outs = ["slide:S", "angle:rocker", "point:E"]
    t, sw = median_time(lambda: sweep(cams, 0.0, 2 * math.pi, 2 * math.pi / steps, outputs=outs, order=2), repeat)
    law, ws = cams.cams[0].law, cams.inputs[0].speed
    err = float(np.max(np.abs(sw.table["slide:S''"] - ws * ws * law.evaluate(sw.inputs)[2])))
    out.append(("cam-driven linkage (cam, follower, rod, rocker), order 2 (kernel, arrays)", t,
                f"largest follower acceleration error against the law {err:.1e}"))
    out.append(_step_by_step("cam-driven linkage", cams, outs, sw, steps, repeat))
    for order in (0, 2):
        t, sw = median_time(lambda: sweep(four_bar(), 0.0, 2 * math.pi, 2 * math.pi / steps, outputs=["angle:rocker"],
                                      order=order), repeat)
        out.append((f"kernel sweep of the four-bar, order {order} (yardstick)", t, f"{sw.inputs.size} steps"))
    return out


def _step_by_step(name, mech, outputs, fast, steps, repeat):
    """The same sweep on the scalar path, and the largest difference of the kernel's table from it."""
    kin = Kinematics(mech, outputs, 2)
    qs = grid(0.0, 2 * math.pi, 2 * math.pi / steps)
    t, slow = median_time(lambda: _scalar_sweep(kin, Continuation(kin), qs, None), repeat)
    diff = max(float(np.max(np.abs(fast.table[c] - slow.table[c]) / np.maximum(1.0, np.max(np.abs(slow.table[c])))))
               for c in slow.columns)
    return f"{name}, order 2 (scalar path, step by step)", t, f"kernel's table differs by {diff:.1e} (relative)"


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--steps", type=int, default=3600, help="points, angles or times of each run (default 3600)")
    p.add_argument("--repeat", type=int, default=5, help="runs of each, the median reported (default 5)")
    args = p.parse_args(argv)
    with limited_threads():
        table = rows(args.steps, args.repeat)
    print(f"| run ({args.steps} steps) | median time | quality |")
    print("|---|---|---|")
    for name, t, note in table:
        print(f"| {name} | {t * 1e3:.1f} ms | {note} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
