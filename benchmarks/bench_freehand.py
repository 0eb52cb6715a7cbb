"""Paths drawn by hand: the 26 letters and noisy four-bar curves, matched as sketches (issue 27, item 3).

Run ``python benchmarks/bench_freehand.py`` (``--letters ABC`` for some, ``--noisy N`` curves, ``--noise``).
The small atlases (closed paths, and the window index of open ones) come from the data folder
(``$DOMES_HOME/atlas/``), built the first time. For each letter of ``examples/curves/letters.json`` (one
stroke, a hand's uneven speed and tremor; made by ``examples/curves/letters.py``): closed or open as read,
its corners, its scatter, and the best linkage's largest and RMS distance of the letter's own points from
its traced curve, as a share of the letter's size, with the time. Then ``--noisy`` random four-bars' curves
(150 points at random places, noise of ``--noise`` of the size added): the share recovered within 2% (every
point of the noise-free curve within 2% of the size of the found linkage's curve, from 20,000 samples per
turn), and the times. Numbers in docs/curves.md.
"""

from __future__ import annotations

import argparse
import json
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def _curve_error(mech, points) -> float:
    from domes.motion.coupler.curves import trace

    per = [np.array([np.min(np.hypot(*(c.points - p).T)) for p in points]) for c in trace(mech, "P", 20000).circuits]
    return float(np.max(min(per, key=lambda d: np.mean(d ** 2))))


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--letters", default="ABCDEFGHIJKLMNOPQRSTUVWXYZ", help="the letters to match (default all)")
    parser.add_argument("--noisy", type=int, default=20, help="noisy four-bar curves to match (default 20)")
    parser.add_argument("--noise", type=float, default=0.01, help="the noise, a share of the size (default 0.01)")
    args = parser.parse_args()

    from domes.errors import InputError
    from domes.execution.threads import limited_threads
    from domes.io.atlas import default_atlas
    from domes.motion.coupler.atlas import Atlas, OpenAtlas
    from domes.motion.coupler.curves import trace
    from domes.motion.coupler.fourbar import four_bar
    from domes.motion.coupler.freehand import drawn, match_drawn

    with limited_threads(1):
        t = time.perf_counter()
        closed, opened = Atlas(default_atlas("small")), OpenAtlas(default_atlas("small", kind="open"))
        print(f"# atlases read (or built) in {time.perf_counter() - t:.1f} s")
        letters = json.loads((ROOT / "examples/curves/letters.json").read_text())["letters"]
        print("letter  kind    points  corners  scatter %  worst %  RMS %   time s")
        times = []
        for k in args.letters:
            points = np.array(letters[k])
            sketch = drawn(points)
            t = time.perf_counter()
            m = match_drawn(points, closed if sketch.closed else opened, results=1)
            times.append(time.perf_counter() - t)
            best = m.fits[0]
            print(f"{k:6}  {'closed' if sketch.closed else 'open':6}  {len(sketch.points):6}  {len(sketch.corners):7}  "
                  f"{100 * sketch.noise / sketch.size:9.2f}  {100 * best.after[0] / sketch.size:7.2f}  "
                  f"{100 * best.after[1] / sketch.size:5.2f}  {times[-1]:7.1f}")
        if times:
            print(f"# letters: median {statistics.median(times):.1f} s, longest {max(times):.1f} s")
        if args.noisy:
            rng = np.random.default_rng(27)
            hits, spent, worst = 0, [], []
            while len(spent) < args.noisy:
                lengths, uv = rng.uniform(0.3, 1.7, 4), rng.uniform(-3, 3, 2)
                try:
                    curve = trace(four_bar(*lengths, *uv), "P", 720).circuits[0].points
                except InputError:
                    continue
                size = float(np.max(np.ptp(curve, axis=0)))
                picked = curve[np.sort(rng.choice(len(curve), 150, replace=False))]
                noisy = picked + rng.normal(0, args.noise * size, picked.shape)
                t = time.perf_counter()
                m = match_drawn(noisy, closed, results=1, closed=True)
                spent.append(time.perf_counter() - t)
                worst.append(_curve_error(m.fits[0].mechanism, curve[::4]) / size)
                hits += worst[-1] <= 0.02
            print(f"# noisy four-bar curves ({args.noise:.1%} noise, 150 points each): {hits} of {args.noisy} "
                  f"recovered within 2% (the noise-free curve's worst distance: median "
                  f"{100 * statistics.median(worst):.2f}%, largest {100 * max(worst):.2f}%); time median "
                  f"{statistics.median(spent):.1f} s, longest {max(spent):.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
