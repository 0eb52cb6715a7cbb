"""Synthesised four-bars as mechanisms, with the checks every solution gets (issue 13, item 6).

A solution is four pivots in the first precision position: frame pivots
``a0``, ``b0``, moving pivots ``a1`` (crank pin) and ``b1`` (rocker pin),
and the body's point. :func:`check` says whether the linkage can do the task
as a mechanism: assembled in one mode at every precision position (no
branch defect), positions reached in order as the crank turns one way (no
order defect), its Grashof class, no dead point between consecutive positions (the loop closes all
the way), its Grashof class, and the smallest transmission angle at the
precision positions.

>>> fb = FourBar((0, 0), (0, 1), (3, 1), (3, 0))
>>> fb.lengths
(1.0, 3.0, 1.0, 3.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism


def _cross(u, v) -> float:
    return float(u[0] * v[1] - u[1] * v[0])


@dataclass(frozen=True)
class FourBar:
    """Pivots ``a0, a1, b1, b0`` in the first precision position, and the coupler point ``point`` (or None)."""

    a0: tuple[float, float]
    a1: tuple[float, float]
    b1: tuple[float, float]
    b0: tuple[float, float]
    point: tuple[float, float] | None = None

    def __post_init__(self):
        for name in ("a0", "a1", "b1", "b0", "point"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _pt(value))

    @property
    def lengths(self) -> tuple[float, float, float, float]:
        """Crank ``|a1 − a0|``, coupler ``|b1 − a1|``, rocker ``|b1 − b0|``, frame ``|b0 − a0|``."""
        return (math.dist(self.a0, self.a1), math.dist(self.a1, self.b1), math.dist(self.b1, self.b0),
                math.dist(self.a0, self.b0))

    def named_lengths(self) -> dict[str, float]:
        return dict(zip(("crank", "coupler", "rocker", "frame"), self.lengths))

    def mechanism(self, name: str = "synthesised four-bar") -> Mechanism:
        """The linkage in the kinematics file format, drawn at the first precision position; input at ``A``."""
        points = [CouplerPoint("P", "coupler", tuple(self.point))] if self.point is not None else []
        return Mechanism.build(
            name, ["frame", "crank", "coupler", "rocker"], "frame",
            [Joint("A", "R", ("frame", "crank"), _pt(self.a0)), Joint("B", "R", ("crank", "coupler"), _pt(self.a1)),
             Joint("C", "R", ("coupler", "rocker"), _pt(self.b1)), Joint("D", "R", ("rocker", "frame"), _pt(self.b0))],
            [Input("A")], points=points)


@dataclass(frozen=True)
class SliderCrank:
    """A crank ``a0``-``a1`` and a slider pin ``b1`` on a slide of ``direction`` (rad), in the first position."""

    a0: tuple[float, float]
    a1: tuple[float, float]
    b1: tuple[float, float]
    direction: float
    point: tuple[float, float] | None = None

    def __post_init__(self):
        for name in ("a0", "a1", "b1", "point"):
            value = getattr(self, name)
            if value is not None:
                object.__setattr__(self, name, _pt(value))

    @property
    def offset(self) -> float:
        """The signed distance of the crank pivot from the slide (left of its direction positive)."""
        u = (math.cos(self.direction), math.sin(self.direction))
        return _cross(u, np.subtract(self.a0, self.b1))

    @property
    def lengths(self) -> tuple[float, float, float]:
        """Crank ``|a1 − a0|``, coupler ``|b1 − a1|`` and the offset's size."""
        return math.dist(self.a0, self.a1), math.dist(self.a1, self.b1), abs(self.offset)

    def named_lengths(self) -> dict[str, float]:
        return dict(zip(("crank", "coupler", "offset"), self.lengths))

    def mechanism(self, name: str = "synthesised slider-crank") -> Mechanism:
        """The linkage in the kinematics file format, drawn at the first precision position; input at ``A``."""
        points = [CouplerPoint("P", "coupler", tuple(self.point))] if self.point is not None else []
        return Mechanism.build(
            name, ["frame", "crank", "coupler", "slider"], "frame",
            [Joint("A", "R", ("frame", "crank"), self.a0), Joint("B", "R", ("crank", "coupler"), self.a1),
             Joint("C", "R", ("coupler", "slider"), self.b1),
             Joint("D", "P", ("frame", "slider"), self.b1, float(self.direction))],
            [Input("A")], points=points)


def check_slider(sc: SliderCrank, positions_a, positions_b) -> Checks:
    """Check a slider-crank whose pins are at ``positions_a[j]`` (crank) and ``positions_b[j]`` (slider)."""
    a0 = np.asarray(sc.a0, float)
    A, B = np.asarray(positions_a, float), np.asarray(positions_b, float)
    r, length, e = sc.lengths
    u = np.array([math.cos(sc.direction), math.sin(sc.direction)])
    turns = r + e <= length
    kind = "crank turns fully (r + |e| ≤ L)" if turns else "crank oscillates (r + |e| > L)"
    defects = []
    if min(r, length) <= 1e-9 * max(r, length):
        defects.append("a link of zero length")
    modes = [np.sign(np.dot(B[j] - A[j], u)) for j in range(len(A))]

    def dead(angles):
        n = np.array([-u[1], u[0]])
        for j in range(len(angles) - 1):
            th = np.linspace(angles[j], angles[j + 1], 721)
            pins = a0 + r * np.c_[np.cos(th), np.sin(th)]
            bad = np.abs((pins - B[0]) @ n) > length
            if bad.any():
                return j + 1, float(math.degrees(th[int(np.argmax(bad))]))
        return None

    angles = _motion_defects(A, a0, modes, dead, "the coupler does not reach the slide", defects)
    mu = [math.degrees(math.acos(min(1.0, abs(float(np.dot(B[j] - A[j], u))) / max(length, 1e-300))))
          for j in range(len(A))]                        # the coupler's angle with the slide: 0 best
    driver = ("driven by a crank: it turns fully (r + |e| ≤ L)" if turns else
              "driven by a rocker: the crank only rocks (r + |e| > L)")
    return Checks(kind, turns, 90.0 - max(mu) if mu else float("nan"),
                  tuple(float(math.degrees(x)) for x in angles), tuple(defects), driver)


def _pt(p) -> tuple[float, float]:
    return (float(p[0]), float(p[1]))


@dataclass(frozen=True)
class Checks:
    """What a solution is worth as a mechanism; ``defects`` lists the reasons to reject it (empty: usable)."""

    grashof: str
    crank_rotates: bool
    min_transmission_deg: float
    crank_angles_deg: tuple[float, ...]
    defects: tuple[str, ...] = field(default_factory=tuple)
    #: What drives the linkage at ``A``: a crank that turns fully, or a link that only rocks (and over what range).
    driver: str = ""
    #: The range ``(from, to)`` (°, counter-clockwise) the link at ``A`` rocks over on its drawn circuit; None when it
    #: turns fully.
    crank_range_deg: tuple[float, float] | None = None

    @property
    def usable(self) -> bool:
        return not self.defects


def grashof_class(a: float, b: float, c: float, d: float) -> tuple[str, bool]:
    """The Grashof class of crank ``a``, coupler ``b``, rocker ``c``, frame ``d`` and whether the crank turns fully."""
    s, l = min(a, b, c, d), max(a, b, c, d)
    p_q = a + b + c + d - s - l
    if s + l > p_q + 1e-12 * l:
        return "non-Grashof (triple rocker)", False
    kind = "change point" if abs(s + l - p_q) <= 1e-12 * l else "Grashof"
    if s == d:
        return f"{kind} double crank", True
    if s == a:
        return f"{kind} crank-rocker", True
    if s == b:
        return f"{kind} double rocker (coupler shortest)", False
    return f"{kind} rocker-crank (the rocker turns)", False


def driver_range(fb: FourBar) -> tuple[float, float] | None:
    """The range ``(from, to)`` (rad, counter-clockwise, ``from`` within ±π) of the link at ``a0`` where the loop
    closes, the one holding its drawn angle; None when it turns fully.

    >>> [round(math.degrees(x), 3) for x in driver_range(FourBar((0, 0), (2, 0), (3, 2), (3, 0)))]
    [-114.332, 114.332]
    >>> driver_range(FourBar((0, 0), (1, 0), (3, 2), (3, 0))) is None
    True
    """
    a, b, c, d = fb.lengths
    frame = math.atan2(fb.b0[1] - fb.a0[1], fb.b0[0] - fb.a0[0])
    drawn = math.remainder(math.atan2(fb.a1[1] - fb.a0[1], fb.a1[0] - fb.a0[0]) - frame, 2 * math.pi)
    lo = (a * a + d * d - (b + c) ** 2) / (2 * a * d)     # cos of the angle from the frame: within [lo, hi]
    hi = (a * a + d * d - (b - c) ** 2) / (2 * a * d)
    if lo <= -1 and hi >= 1:
        return None
    outer = math.acos(max(-1.0, min(1.0, lo))) if lo > -1 else math.pi
    inner = math.acos(min(1.0, max(-1.0, hi))) if hi < 1 else 0.0
    if inner == 0.0:
        span = (-outer, outer)
    elif outer == math.pi:
        span = (inner, 2 * math.pi - inner)
    else:
        span = (inner, outer) if drawn >= 0 else (-outer, -inner)
    start = math.remainder(frame + span[0], 2 * math.pi)
    return start, start + span[1] - span[0]


def _driver(fb: FourBar, turns: bool) -> tuple[str, tuple[float, float] | None]:
    """The sentence that says what drives the linkage at ``A`` and the range (°) it rocks over."""
    if turns:
        return "driven by a crank: the link at A turns fully", None
    lo, hi = (math.degrees(x) for x in driver_range(fb))
    other = grashof_class(*reversed(fb.lengths[:3]), fb.lengths[3])[1]
    hint = "; the link at D turns fully: driven there it is a crank" if other else ""
    return f"driven by a rocker: the link at A only rocks, from {lo:.1f}° to {hi:.1f}° ({hi - lo:.1f}°){hint}", (lo, hi)


def check(fb: FourBar, positions_a, positions_b) -> Checks:
    """Check a four-bar whose moving pivots are at ``positions_a[j]`` and ``positions_b[j]`` in position ``j``."""
    a0, b0 = np.asarray(fb.a0, float), np.asarray(fb.b0, float)
    A, B = np.asarray(positions_a, float), np.asarray(positions_b, float)
    a, b, c, d = fb.lengths
    kind, turns = grashof_class(a, b, c, d)
    defects = []
    if min(a, b, c, d) <= 1e-9 * max(a, b, c, d):
        defects.append("a link of zero length")
    modes = [np.sign(_cross(B[j] - A[j], b0 - B[j])) for j in range(len(A))]
    angles = _motion_defects(A, a0, modes, lambda th: _dead_between(fb, th), "the loop does not close", defects)
    mu = []
    for j in range(len(A)):
        u, v = A[j] - B[j], b0 - B[j]
        cos = float(np.dot(u, v) / (np.linalg.norm(u) * np.linalg.norm(v))) if np.linalg.norm(u) * np.linalg.norm(v) else 1
        ang = math.degrees(math.acos(max(-1.0, min(1.0, cos))))
        mu.append(min(ang, 180 - ang))
    driver, span = _driver(fb, turns) if min(a, b, c, d) > 0 else ("", None)
    return Checks(kind, turns, min(mu) if mu else float("nan"), tuple(float(math.degrees(x)) for x in angles),
                  tuple(defects), driver, span)


def _motion_defects(A, a0, modes, dead, why: str, defects: list) -> np.ndarray:
    """Branch, order and dead-point defects (appended to ``defects``); the crank's angles at the positions."""
    if len({m for m in modes if m != 0}) > 1:
        defects.append("branch defect: the precision positions lie on both assembly modes")
    angles, stuck = _crank_order(A, a0, dead)
    if angles is None:
        defects.append("order defect: the crank does not reach the positions in order within one turn either way")
        return np.array([math.atan2(*(A[j] - a0)[::-1]) for j in range(len(A))])
    if stuck is not None:
        defects.append(f"dead point: the crank cannot turn from position {stuck[0]} to {stuck[0] + 1} ({why} near "
                       f"crank angle {stuck[1]:.1f}°)")
    return angles


def _crank_order(A, a0, dead):
    """The crank's angles at the positions ``A`` turning one way, within one turn (the shorter way when both
    do), and where it first gets stuck between two (``dead(angles)``); ``(None, None)`` on an order defect."""
    raw = np.array([math.atan2(*(A[j] - a0)[::-1]) for j in range(len(A))])
    angles = None
    for direction in (1.0, -1.0):
        steps = np.mod(direction * np.diff(raw), 2 * math.pi)
        if steps.sum() < 2 * math.pi:
            path = raw[0] + direction * np.concatenate(([0.0], np.cumsum(steps)))
            if angles is None or abs(path[-1] - path[0]) < abs(angles[-1] - angles[0]):
                angles = path
    return (None, None) if angles is None else (angles, dead(angles))


def _dead_between(fb: FourBar, angles) -> tuple[int, float] | None:
    """The first pair of consecutive positions the crank cannot turn between, and where, or None."""
    a, b, c, _ = fb.lengths
    a0, b0 = np.asarray(fb.a0, float), np.asarray(fb.b0, float)
    for j in range(len(angles) - 1):
        th = np.linspace(angles[j], angles[j + 1], 721)
        B = a0 + a * np.c_[np.cos(th), np.sin(th)]
        r = np.linalg.norm(B - b0, axis=1)
        bad = (r >= b + c) | (r <= abs(b - c))
        if bad.any():
            return j + 1, float(math.degrees(th[int(np.argmax(bad))]))
    return None
