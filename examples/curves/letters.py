"""The 26 capital letters drawn as one stroke each, as a hand draws them: ``python examples/curves/letters.py``
writes ``letters.json`` beside it (points per letter, in millimetres), and the O as a path file,
``letter-O.csv``.

Each letter is a single pen stroke (in the manner of the one-stroke alphabets of pen computers: A is an
inverted V, T goes back along its bar) built from lines and circular arcs in a box 60 mm high. The pen's
speed varies along the stroke (slower into corners, faster on straights) so the points are unevenly spaced,
and the hand trembles: a slow wander of about 0.4 mm and a jitter of 0.15 mm (seeded per letter, so the
file is the same every time). Closed letters (D, O) end where they began.

>>> letters = strokes()
>>> sorted(letters) == [chr(c) for c in range(ord("A"), ord("Z") + 1)]
True
>>> len(drawn("O", letters["O"])) > 60
True
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

#: The letters' height, mm.
HEIGHT = 60.0
#: The hand: its slow wander and its jitter (mm), and the mean spacing of the points (mm).
WANDER, JITTER, SPACING = 0.4, 0.15, 2.2


def arc(cx, cy, r, a0, a1, ry=None):
    """Points of an arc (an ellipse's when ``ry`` is given) from angle ``a0`` to ``a1`` (degrees)."""
    t = np.radians(np.linspace(a0, a1, max(8, int(abs(a1 - a0) / 6))))
    return [(cx + r * math.cos(a), cy + (ry or r) * math.sin(a)) for a in t]


def strokes() -> dict[str, list[tuple[float, float]]]:
    """Each letter's stroke as the corners and arc points of its path, in a box one unit high."""
    return {
        "A": [(0, 0), (0.35, 1), (0.7, 0)],
        "B": [(0, 0), (0, 1), *arc(0.25, 0.75, 0.25, 90, -90)[1:], (0, 0.5), *arc(0.3, 0.25, 0.25, 90, -90, 0.25),
              (0, 0)],
        "C": arc(0.4, 0.5, 0.4, 45, 315, 0.5),
        "D": [(0, 0), (0, 1), *arc(0.2, 0.5, 0.45, 90, -90, 0.5)[1:-1], (0, 0)],
        "E": [*arc(0.35, 0.75, 0.3, 20, 270, 0.25), *arc(0.35, 0.25, 0.35, 90, 340, 0.25)[1:]],
        "F": [(0.6, 1), (0, 1), (0, 0)],
        "G": [*arc(0.4, 0.5, 0.4, 45, 340, 0.5), (0.76, 0.45), (0.45, 0.45)],
        "H": [(0, 1), (0, 0), (0, 0.45), *arc(0.3, 0.45, 0.3, 180, 0)[1:], (0.6, 0)],
        "I": [(0.3, 1), (0.3, 0)],
        "J": [(0.6, 1), (0.6, 0.3), *arc(0.3, 0.3, 0.3, 0, -180)[1:]],
        "K": [(0.6, 1), (0, 0.5), (0.6, 0)],
        "L": [(0, 1), (0, 0), (0.55, 0)],
        "M": [(0, 0), (0, 1), (0.4, 0.35), (0.8, 1), (0.8, 0)],
        "N": [(0, 0), (0, 1), (0.6, 0), (0.6, 1)],
        "O": arc(0.35, 0.5, 0.35, 90, 450, 0.5),
        "P": [(0, 0), (0, 1), *arc(0.2, 0.75, 0.3, 90, -90, 0.25)[1:], (0, 0.5)],
        "Q": [*arc(0.35, 0.5, 0.35, 90, 405, 0.5), (0.75, -0.05)],
        "R": [(0, 0), (0, 1), *arc(0.2, 0.75, 0.3, 90, -90, 0.25)[1:], (0, 0.5), (0.55, 0)],
        "S": [*arc(0.3, 0.75, 0.3, 10, 270, 0.25), *arc(0.3, 0.25, 0.3, 90, -190, 0.25)[1:]],
        "T": [(0, 1), (0.7, 1), (0.35, 1), (0.35, 0)],
        "U": [(0, 1), (0, 0.3), *arc(0.3, 0.3, 0.3, 180, 360)[1:], (0.6, 1)],
        "V": [(0, 1), (0.3, 0), (0.6, 1)],
        "W": [(0, 1), (0.2, 0), (0.4, 0.65), (0.6, 0), (0.8, 1)],
        "X": [(0, 1), (0.6, 0), (0.6, 1), (0, 0)],
        "Y": [(0, 1), (0.3, 0.5), (0.6, 1), (0.3, 0.5), (0.3, 0)],
        "Z": [(0, 1), (0.6, 1), (0, 0), (0.6, 0)],
    }


def drawn(letter: str, path) -> list[list[float]]:
    """The stroke through ``path`` as a hand draws it: points at the pen's varying speed, with its tremor (mm,
    rounded to 0.01)."""
    rng = np.random.default_rng(ord(letter))
    p = np.asarray(path, dtype=float) * HEIGHT
    closed = bool(np.allclose(p[0], p[-1]))
    seg = np.hypot(*np.diff(p, axis=0).T)
    s = np.r_[0.0, np.cumsum(seg)]
    dense = np.linspace(0.0, s[-1], 4000)
    line = np.c_[np.interp(dense, s, p[:, 0]), np.interp(dense, s, p[:, 1])]
    heading = np.unwrap(np.arctan2(*np.gradient(line, axis=0).T[::-1]))
    turning = np.abs(np.gradient(heading)) / max(dense[1], 1e-12)       # rad per mm
    speed = 1.0 / (1.0 + 4.0 * np.convolve(turning, np.ones(40) / 40, mode="same"))
    speed *= np.exp(rng.normal(0.0, 0.25, 1) + 0.2 * np.sin(dense / s[-1] * 2 * math.pi * rng.uniform(1, 3)))
    time = np.r_[0.0, np.cumsum(np.diff(dense) / speed[1:])]
    count = max(30, int(s[-1] / SPACING))
    ticks = np.sort(rng.uniform(0.0, time[-1], count - 2))
    at = np.interp(np.r_[0.0, ticks, time[-1]], time, dense)
    points = np.c_[np.interp(at, dense, line[:, 0]), np.interp(at, dense, line[:, 1])]
    phase = rng.uniform(0, 2 * math.pi, (3, 2))
    wander = sum(np.sin(at[:, None] / s[-1] * 2 * math.pi * (k + 1) + phase[k]) for k in range(3)) * WANDER / 3
    points = points + wander + rng.normal(0.0, JITTER, points.shape)
    if closed:
        points = points[:-1]
    return np.round(points, 2).tolist()


def letters() -> dict:
    """Every letter drawn, with what made them."""
    return {"source": "examples/curves/letters.py (one stroke per letter, drawn with a hand's varying speed and "
                      "tremor)", "units": "mm",
            "letters": {k: drawn(k, path) for k, path in strokes().items()}}


def letter_csv(points) -> str:
    """One letter's points as a path file (x, y per line) for ``domes curves match --drawn``."""
    return "# a letter drawn by hand (examples/curves/letters.py), mm\nx,y\n" + "".join(f"{x},{y}\n" for x, y in points)


if __name__ == "__main__":
    folder = Path(sys.argv[1]) if len(sys.argv) > 1 else Path(__file__).parent
    made = letters()
    (folder / "letters.json").write_text(json.dumps(made, separators=(",", ":")) + "\n", encoding="utf-8")
    (folder / "letter-O.csv").write_text(letter_csv(made["letters"]["O"]), encoding="utf-8")
    print(f"wrote {folder / 'letters.json'} and {folder / 'letter-O.csv'}")
