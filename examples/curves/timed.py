"""A closed path drawn with its times, as a tablet records a pen: ``python examples/curves/timed.py`` writes
``timed-loop.csv`` beside it (x, y in millimetres and the time of each point in seconds).

The pen follows the coupler point of a crank-rocker (crank 10 mm, coupler 35, rocker 30, frame 20, coupler
point 20 mm square off the crank pin), its crank turning at 180° a second: one loop in 2 s. The tablet
samples about 36 times a second at irregular instants, which it records exactly; the hand adds a tremor of
1% of the loop's size to every coordinate (seeded, so the file is the same every time). Matched with its
times, ``domes curves match examples/curves/timed-loop.csv --drawn`` fits the crank's speed and its angle at
the first point; ``--speed 180`` gives the speed.

>>> rows = timed_loop()
>>> len(rows), rows[0][2], rows[-1][2] < 2.0
(72, 0.0, True)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

#: The linkage (mm): crank, coupler, rocker, frame and the coupler point (u, v) from the crank pin.
LINKAGE = (10.0, 35.0, 30.0, 20.0, 0.0, 20.0)
#: The crank's speed (degrees a second), its angle at the first point (degrees), the samples, the tremor (a share
#: of the loop's size).
SPEED, FIRST, SAMPLES, TREMOR = 180.0, 40.0, 72, 0.01


def timed_loop() -> list[tuple[float, float, float]]:
    """``(x, y, t)`` of each sample: the coupler point at the crank angle of time ``t``, with the hand's tremor."""
    from domes.motion.coupler.fourbar import four_bar
    from domes.motion.planar.batch import batch

    rng = np.random.default_rng(2026)
    t = np.sort(rng.uniform(0.0, 2.0, SAMPLES - 1))
    t = np.r_[0.0, t]                                       # the first sample starts the clock
    mech = four_bar(*LINKAGE, theta=np.radians(FIRST))
    b = batch(mech, inputs=np.radians(FIRST + SPEED * t), outputs=["point:P"])
    xy = np.c_[b.values["point:P.x"][0], b.values["point:P.y"][0]]
    size = float(np.max(np.ptp(xy, axis=0)))
    xy = xy + rng.normal(0.0, TREMOR * size, xy.shape)
    return [(round(float(x), 3), round(float(y), 3), round(float(s), 4)) for (x, y), s in zip(xy, t)]


def loop_csv(rows) -> str:
    """The samples as a path file with a time column."""
    return "x,y,time\n" + "".join(f"{x!r},{y!r},{s!r}\n" for x, y, s in rows)


if __name__ == "__main__":
    here = Path(__file__).resolve().parent
    (here / "timed-loop.csv").write_text(loop_csv(timed_loop()))
    sys.stdout.write(f"wrote {here / 'timed-loop.csv'}\n")
