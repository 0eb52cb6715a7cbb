"""Paths drawn by hand with their timing: noisy four-bar curves whose points come with the crank's angle or time.

Run ``python benchmarks/bench_freehand_timed.py`` (``--count N`` curves per kind, ``--points``, ``--noise``,
``--kinds angle time speed``). The small atlas of closed paths comes from the data folder (``$DOMES_HOME/atlas/``),
built the first time. Each case: a random crank-rocker (random lengths and coupler point, not an atlas point),
``--points`` points at random crank angles, noise of ``--noise`` of the size added to each coordinate; the timing
given as crank angles (``angle``, zero free), as times with the speed unknown (``time``, 90° a unit, found by the
fit) or given (``speed``). Reported: the share recovered within 2% of the size (the kernel driving the found
linkage to its crank angles at the points puts the coupler point within 2% of the size of each noise-free point,
and every point of the noise-free curve is within 2% of its traced curve), the timed worst error against the noisy
points, the speed found, and CPU seconds per case. Numbers in docs/curves.md.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "motion"))


from test_freehand_timing import _dense_distances, timed_sample  # noqa: E402  the tests' cases and brute force


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--count", type=int, default=20, help="curves per kind (default 20)")
    parser.add_argument("--points", type=int, default=60, help="points per curve (default 60)")
    parser.add_argument("--noise", type=float, default=0.01, help="the noise, a share of the size (default 0.01)")
    parser.add_argument("--kinds", nargs="+", default=["angle", "time", "speed"], choices=["angle", "time", "speed"])
    args = parser.parse_args()

    from domes.execution.threads import limited_threads
    from domes.io.atlas import default_atlas
    from domes.motion.coupler.atlas import Atlas
    from domes.motion.coupler.freehand import match_drawn
    from domes.motion.coupler.timing import Timing, driven

    with limited_threads(1):
        atlas = Atlas(default_atlas("small"))
        print("kind   case  timed-vs-clean %  curve-vs-clean %  timed worst %  speed  cpu s")
        for kind in args.kinds:
            good, cpu = 0, []
            for case in range(args.count):
                curve, size, clean, angles, noisy = timed_sample(1000 + case, args.points, args.noise)
                t = (angles - angles[0]) / 90.0 + 3.0
                timing = {"angle": Timing(tuple(angles - angles[0] + 17.0)), "time": Timing(tuple(t), "time"),
                          "speed": Timing(tuple(t), "time", 90.0)}[kind]
                c0 = time.process_time()
                m = match_drawn(noisy, atlas, results=1, closed=True, timing=timing)
                cpu.append(time.process_time() - c0)
                f = m.fits[0]
                pts, _ = driven(f.mechanism, np.radians(f.angles))
                timed = float(np.max(np.hypot(*(pts - clean).T))) / size
                along = float(np.max(_dense_distances(f.mechanism, curve[::4]))) / size
                good += timed <= 0.02 and along <= 0.02
                speed = "" if f.speed is None else f"{f.speed:.2f}"
                print(f"{kind:6s} {case:4d}  {100 * timed:15.2f}  {100 * along:16.2f}  {100 * f.after[0] / size:13.2f}"
                      f"  {speed:>5s}  {cpu[-1]:.1f}", flush=True)
            print(f"# {kind}: {good} of {args.count} within 2% of the noise-free curve at the given timing; CPU s per "
                  f"case median {statistics.median(cpu):.1f}, longest {max(cpu):.1f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
