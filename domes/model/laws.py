"""Motion laws: a displacement and its derivatives over time or a cam's angle (seed 000 §2.10, issue 26).

MCAD's motion class drives a link by a law: constant velocity, sine
acceleration, cosine acceleration, the 3-4-5 polynomial, or one read from a
file (seed 000, §2.10). In cam nomenclature the sine-acceleration law is the
cycloidal one and the cosine-acceleration law is simple harmonic motion. A
:class:`Motion` joins segments of these laws end to end (dwell, rise, dwell,
return) and evaluates the displacement ``s`` and its first three
derivatives ``s'``, ``s''``, ``s'''`` with respect to the independent
variable ``x`` (a time, or the angle of a cam turning at constant speed),
in closed form on arrays.

Each law is a normalised rise ``S(u)`` on ``u ∈ [0, 1]`` from 0 to 1; a
segment of length ``L`` and rise ``h`` gives ``s = h S(u)``,
``s' = h S'(u) / L``, ``s'' = h S''(u) / L²``, ``s''' = h S'''(u) / L³``.

>>> m = Motion.cam([("dwell", 90), ("cycloidal", 90, 20), ("dwell", 90), ("cycloidal", 90, -20)])
>>> [round(float(v), 9) for v in m.evaluate([0.0, 3 * 3.141592653589793 / 4])[0]]
[0.0, 10.0]
>>> round(m.peak(1) * m.segments[1].length / 20, 9)         # cycloidal: C_v = 2
2.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from domes.errors import InputError

#: The names of the laws and their other names (seed 000 calls two of them by their acceleration).
ALIASES = {
    "dwell": "dwell",
    "constant velocity": "constant velocity", "uniform": "constant velocity", "linear": "constant velocity",
    "simple harmonic": "simple harmonic", "harmonic": "simple harmonic", "cosine acceleration": "simple harmonic",
    "cycloidal": "cycloidal", "sine acceleration": "cycloidal",
    "3-4-5 polynomial": "3-4-5 polynomial", "3-4-5": "3-4-5 polynomial", "polynomial": "3-4-5 polynomial",
}
LAWS = ("dwell", "constant velocity", "simple harmonic", "cycloidal", "3-4-5 polynomial")


def normalised(law: str, u, order: int = 0) -> np.ndarray:
    """The ``order``-th derivative (0 to 3) of the normalised rise ``S(u)`` of ``law`` at ``u`` (in [0, 1]).

    >>> [round(float(normalised("3-4-5 polynomial", 0.5, k)), 6) for k in range(3)]
    [0.5, 1.875, 0.0]
    """
    u = np.asarray(u, dtype=float)
    name = law_name(law)
    pi = math.pi
    if name == "dwell":
        return np.zeros_like(u)
    if name == "constant velocity":
        return (u, np.ones_like(u), np.zeros_like(u), np.zeros_like(u))[order]
    if name == "simple harmonic":
        return ((1 - np.cos(pi * u)) / 2, pi / 2 * np.sin(pi * u), pi ** 2 / 2 * np.cos(pi * u),
                -pi ** 3 / 2 * np.sin(pi * u))[order]
    if name == "cycloidal":
        w = 2 * pi
        return (u - np.sin(w * u) / w, 1 - np.cos(w * u), w * np.sin(w * u), w * w * np.cos(w * u))[order]
    u2, u3 = u * u, u * u * u
    return (10 * u3 - 15 * u2 * u2 + 6 * u3 * u2, 30 * u2 - 60 * u3 + 30 * u2 * u2,
            60 * u - 180 * u2 + 120 * u3, 60 - 360 * u + 360 * u2)[order]


def law_name(law: str) -> str:
    """The law's canonical name, or an InputError listing the laws."""
    key = " ".join(str(law).lower().replace("_", " ").split())
    if key not in ALIASES:
        raise InputError(f"unknown motion law {law!r}: use one of {', '.join(LAWS)} (or a table read from a file)")
    return ALIASES[key]


@dataclass(frozen=True)
class Segment:
    """``law`` over a length ``length`` of ``x``, changing ``s`` by ``rise`` (0 for a dwell)."""

    law: str
    length: float
    rise: float = 0.0

    def __post_init__(self):
        object.__setattr__(self, "law", law_name(self.law))
        if not (isinstance(self.length, (int, float)) and math.isfinite(self.length) and self.length > 0):
            raise InputError(f"a {self.law} segment needs a length > 0, got {self.length!r}")
        if not (isinstance(self.rise, (int, float)) and math.isfinite(self.rise)):
            raise InputError(f"a {self.law} segment needs a finite rise, got {self.rise!r}")
        if self.law == "dwell" and self.rise != 0:
            raise InputError(f"a dwell has no rise, got {self.rise!r}")


@dataclass(frozen=True)
class Motion:
    """Segments of motion laws end to end from ``start`` (``x``) and ``s0`` (``s``); periodic when ``periodic``.

    A periodic motion (a cam's) covers one period: its segments' lengths add
    up to the period and their rises to zero; ``x`` outside is wrapped.
    """

    segments: tuple[Segment, ...]
    s0: float = 0.0
    start: float = 0.0
    periodic: bool = False

    def __post_init__(self):
        segs = tuple(s if isinstance(s, Segment) else Segment(*s) for s in self.segments)
        if not segs:
            raise InputError("a motion needs at least one segment")
        object.__setattr__(self, "segments", segs)
        if self.periodic and abs(sum(s.rise for s in segs)) > 1e-12 * max(1.0, max(abs(s.rise) for s in segs)):
            raise InputError(f"a periodic motion (a cam's) must return to its start: the rises add up to "
                             f"{sum(s.rise for s in segs):g}, not 0")

    @classmethod
    def cam(cls, segments, s0: float = 0.0) -> Motion:
        """A cam's motion over one turn from segments ``(law, degrees[, rise])`` whose degrees add up to 360.

        >>> Motion.cam([("3-4-5", 180, 1), ("3-4-5", 180, -1)]).period
        6.283185307179586
        """
        segs = []
        for k, item in enumerate(segments, start=1):
            if not isinstance(item, (list, tuple)) or len(item) not in (2, 3):
                raise InputError(f"segment {k}: give (law, degrees) or (law, degrees, rise), got {item!r}")
            law, deg, *rise = item
            if not (isinstance(deg, (int, float)) and math.isfinite(deg) and deg > 0):
                raise InputError(f"segment {k} ({law}): its angle must be a number of degrees > 0, got {deg!r}")
            segs.append(Segment(law, math.radians(deg), float(rise[0]) if rise else 0.0))
        total = math.degrees(sum(s.length for s in segs))
        if abs(total - 360) > 1e-9:
            raise InputError(f"a cam's segments must cover one turn: their angles add up to {total:g}°, not 360°")
        return cls(tuple(segs), s0, 0.0, True)

    @property
    def period(self) -> float:
        return float(sum(s.length for s in self.segments))

    @property
    def stops(self) -> np.ndarray:
        """The values of ``x`` where the segments begin, and the end of the last."""
        return self.start + np.concatenate(([0.0], np.cumsum([s.length for s in self.segments])))

    def evaluate(self, x, order: int = 2) -> tuple[np.ndarray, ...]:
        """``(s, s', ..., s^(order))`` at ``x`` (``order`` 0 to 3), closed form on arrays.

        Outside a non-periodic motion's span ``s`` holds its end values and the derivatives are 0.
        """
        if order not in (0, 1, 2, 3):
            raise InputError(f"order must be 0, 1, 2 or 3, got {order!r}")
        x = np.asarray(x, dtype=float)
        if not np.all(np.isfinite(x)):
            raise InputError("a motion is evaluated at finite values of x only")
        rel = x - self.start
        if self.periodic:
            rel = np.mod(rel, self.period)
        stops = self.stops - self.start
        k = np.clip(np.searchsorted(stops, rel, side="right") - 1, 0, len(self.segments) - 1)
        out = [np.zeros_like(rel) for _ in range(order + 1)]
        base = self.s0 + np.concatenate(([0.0], np.cumsum([s.rise for s in self.segments])))
        for i, seg in enumerate(self.segments):
            here = k == i
            if not here.any():
                continue
            u = np.clip((rel[here] - stops[i]) / seg.length, 0.0, 1.0)
            inside = ((rel[here] >= stops[i]) & (rel[here] <= stops[i + 1])) if not self.periodic else True
            out[0][here] = base[i] + seg.rise * normalised(seg.law, u, 0)
            for d in range(1, order + 1):
                out[d][here] = np.where(inside, seg.rise * normalised(seg.law, u, d) / seg.length ** d, 0.0)
        return tuple(out)

    def peak(self, order: int) -> float:
        """The largest ``|s^(order)|`` over the motion, from a fine sample (each segment's own peak included)."""
        xs = np.concatenate([np.linspace(a, b, 2001) for a, b in zip(self.stops[:-1], self.stops[1:])])
        return float(np.max(np.abs(self.evaluate(xs, order)[order])))

    def jumps(self, order: int = 1) -> list[tuple[float, float]]:
        """Where ``s^(order)`` jumps between segments: ``(x, jump)`` for every join (and the wrap of a cam).

        >>> Motion.cam([("constant velocity", 180, 1), ("constant velocity", 180, -1)]).jumps(1)[0][1]
        -0.6366197723675814
        """
        out = []
        joins = list(self.stops[1:-1]) + ([self.stops[-1]] if self.periodic else [])
        for xj in joins:
            left = self._side(xj, -1, order)
            right = self._side(xj, +1, order)
            if abs(right - left) > 1e-9 * max(1.0, abs(left), abs(right)):
                out.append((float(xj), float(right - left)))
        return out

    def _side(self, xj, side, order) -> float:
        """``s^(order)`` at a join from one side, evaluated at the segment's own end."""
        rel = xj - self.start
        stops = self.stops - self.start
        i = int(np.argmin(np.abs(stops - rel)))
        if side < 0:
            seg, u = self.segments[i - 1], 1.0
        else:
            seg, u = self.segments[i % len(self.segments)], 0.0
        return float(seg.rise * normalised(seg.law, u, order) / seg.length ** order) if order else 0.0


def from_table(xs, ss, periodic: bool = False) -> TableMotion:
    """A motion read from a table of ``(x, s)`` (a file's): a cubic spline through the points, periodic when asked.

    >>> m = from_table([0, 1, 2, 3], [0, 1, 4, 9])
    >>> round(float(m.evaluate(1.5, 1)[1]), 9)
    3.0
    """
    return TableMotion(tuple(map(float, xs)), tuple(map(float, ss)), periodic)


@dataclass(frozen=True)
class TableMotion:
    """A motion through tabulated points (a cubic spline: exact for cubics, C² everywhere)."""

    xs: tuple[float, ...]
    ss: tuple[float, ...]
    periodic: bool = False

    def __post_init__(self):
        x, s = np.asarray(self.xs), np.asarray(self.ss)
        if x.ndim != 1 or x.shape != s.shape or x.size < 4:
            raise InputError(f"a motion table needs at least 4 rows of (x, s), got {x.size}")
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(s))):
            bad = int(np.flatnonzero(~(np.isfinite(x) & np.isfinite(s)))[0])
            raise InputError(f"motion table row {bad + 1}: x and s must be finite numbers")
        if np.any(np.diff(x) <= 0):
            bad = int(np.flatnonzero(np.diff(x) <= 0)[0])
            raise InputError(f"motion table rows {bad + 1} and {bad + 2}: x must increase ({x[bad]:g}, {x[bad + 1]:g})")
        if self.periodic and abs(s[-1] - s[0]) > 1e-12 * max(1.0, float(np.max(np.abs(s)))):
            raise InputError(f"a periodic motion table must end where it starts (s = {s[0]:g} and {s[-1]:g})")

    @property
    def period(self) -> float:
        return self.xs[-1] - self.xs[0]

    @cached_property
    def _spline(self):
        """The spline through the rows, made once (evaluate is called on hot paths: a cam's contact search)."""
        from scipy.interpolate import CubicSpline
        return CubicSpline(self.xs, self.ss, bc_type="periodic" if self.periodic else "not-a-knot")

    def evaluate(self, x, order: int = 2) -> tuple[np.ndarray, ...]:
        if order not in (0, 1, 2, 3):
            raise InputError(f"order must be 0, 1, 2 or 3, got {order!r}")
        x = np.asarray(x, dtype=float)
        if self.periodic:
            x = self.xs[0] + np.mod(x - self.xs[0], self.period)
        elif np.any((x < self.xs[0]) | (x > self.xs[-1])):
            raise InputError(f"the motion table covers x from {self.xs[0]:g} to {self.xs[-1]:g} only")
        sp = self._spline
        return tuple(np.asarray(sp(x, d), dtype=float) for d in range(order + 1))


def read_table(text: str, where: str = "motion table") -> tuple[list[float], list[float]]:
    """Rows ``x, s`` (commas or spaces; ``#`` comments) from a file's text; an InputError names the line."""
    xs, ss = [], []
    for n, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        parts = line.replace(",", " ").split()
        try:
            x, s = (float(p) for p in parts)
        except ValueError:
            raise InputError(f"{where}, line {n}: expected two numbers x, s, got {line!r}") from None
        xs.append(x)
        ss.append(s)
    return xs, ss
