"""Six-bars built on a four-bar's coupler curve: the atlas applications of seed 002 §6-4 (digest B.6).

A feature of a coupler curve becomes a motion of an output link when a dyad
is hung on the coupler point ``P``:

- a near-straight stretch: a guide bar pivoted on the stretch's line (an
  RPR dyad) stands still while ``P`` runs along the stretch (a *dwell*), and
  so does a yoke sliding across the stretch with a slot along it (RPP);
- a near-circular arc: a link as long as the arc's radius from ``P`` to an
  output rocker whose pin sits at the arc's centre (RRR): the rocker dwells
  while ``P`` runs along the arc;
- a figure-eight: a guide bar pivoted outside the curve swings twice per
  crank turn;
- a double loop: a guide bar pivoted inside the small loop turns twice per
  crank turn.

:func:`straight_stretch` and :func:`arc_stretch` find the features on a
traced circuit; :func:`with_guide_bar`, :func:`with_yoke` and
:func:`with_rocker` add the dyad in the drawn pose; :func:`output_motion`
sweeps the six-bar with the kinematics backend and measures what the
output does.

>>> from domes.motion.coupler.fourbar import from_atlas
>>> from domes.motion.coupler.curves import trace
>>> m = from_atlas(1, 3, 3.5, 3, 4.75, 120)               # Fig. 6-31: a near-straight stretch
>>> s = straight_stretch(trace(m, "P").circuits[0].points)
>>> s.length > 2.0 and s.deviation < 0.01 * s.length
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import Joint, Mechanism
from domes.motion.planar.sweep import sweep


@dataclass(frozen=True)
class Stretch:
    """A stretch of a closed curve: the indices ``start .. stop`` (cyclic), its chord or circle, how close.

    For a straight stretch ``centre`` is None and ``deviation`` the largest
    distance from the chord's line; for an arc, ``centre`` and ``radius`` are
    the fitted circle's and ``deviation`` the largest distance from it.
    """

    start: int
    stop: int
    first: tuple[float, float]
    last: tuple[float, float]
    length: float
    deviation: float
    centre: tuple[float, float] | None = None
    radius: float | None = None


def straight_stretch(points, tolerance: float = 0.005) -> Stretch:
    """The longest stretch of the closed curve that stays within ``tolerance`` (of the curve's size) of a line."""
    p = np.asarray(points, dtype=float)
    size = float(np.max(np.ptp(p, axis=0)))
    return _longest(p, lambda seg: _line_deviation(seg), tolerance * size)


def arc_stretch(points, tolerance: float = 0.005, min_turn: float = math.radians(30)) -> Stretch:
    """The longest stretch within ``tolerance`` (of the curve's size) of a circle, turning at least ``min_turn``."""
    p = np.asarray(points, dtype=float)
    size = float(np.max(np.ptp(p, axis=0)))

    def deviation(seg):
        centre, radius, dev = _circle(seg)
        if radius is None or radius > 3 * size:
            return math.inf
        turn = abs(_turned(seg, centre))
        return dev if turn >= min_turn else math.inf

    return _longest(p, deviation, tolerance * size, arc=True)


def _longest(p, deviation, tol, arc=False) -> Stretch:
    n = len(p)
    best = None
    for start in range(0, n, max(1, n // 180)):
        lo, hi = 2, n // 2
        while lo < hi:  # the longest window from ``start`` within the tolerance (deviation grows with length)
            mid = (lo + hi + 1) // 2
            seg = p[np.arange(start, start + mid) % n]
            if deviation(seg) <= tol:
                lo = mid
            else:
                hi = mid - 1
        seg = p[np.arange(start, start + lo) % n]
        length = float(np.sum(np.hypot(*np.diff(seg, axis=0).T)))
        if deviation(seg) <= tol and (best is None or length > best[0]):
            best = (length, start, lo)
    if best is None:
        raise InputError("no stretch of the curve is that close to a " + ("circle" if arc else "line"))
    length, start, count = best
    seg = p[np.arange(start, start + count) % n]
    if arc:
        centre, radius, dev = _circle(seg)
        return Stretch(start, (start + count - 1) % n, tuple(seg[0]), tuple(seg[-1]), length, dev, tuple(centre),
                       radius)
    return Stretch(start, (start + count - 1) % n, tuple(seg[0]), tuple(seg[-1]), length, _line_deviation(seg))


def _line_deviation(seg) -> float:
    a, b = seg[0], seg[-1]
    d = b - a
    norm = math.hypot(*d)
    if norm == 0:
        return math.inf
    return float(np.max(np.abs((seg[:, 0] - a[0]) * d[1] - (seg[:, 1] - a[1]) * d[0])) / norm)


def _circle(seg):
    """Least-squares circle (Kåsa) through the points: ``(centre, radius, largest deviation)``."""
    x, y = seg[:, 0], seg[:, 1]
    A = np.c_[2 * x, 2 * y, np.ones_like(x)]
    sol, *_ = np.linalg.lstsq(A, x * x + y * y, rcond=None)
    cx, cy, c = sol
    r2 = c + cx * cx + cy * cy
    if not r2 > 0:
        return None, None, math.inf
    r = math.sqrt(r2)
    return np.array([cx, cy]), r, float(np.max(np.abs(np.hypot(x - cx, y - cy) - r)))


def _turned(seg, centre) -> float:
    ang = np.unwrap(np.arctan2(seg[:, 1] - centre[1], seg[:, 0] - centre[0]))
    return float(ang[-1] - ang[0])


def _added(mech: Mechanism, links: list[str], joints: list[Joint], name: str) -> Mechanism:
    return Mechanism.build(name, list(mech.links) + links, mech.ground, list(mech.joints) + joints, list(mech.inputs),
                           points=list(mech.points), link_angles=dict(mech.link_angles))


def with_guide_bar(mech: Mechanism, point: str, pivot, name: str | None = None) -> Mechanism:
    """An RPR dyad on ``point``: a block pinned there slides on a bar pivoted on the frame at ``pivot``.

    The bar's angle (``angle:bar``) is the output.
    """
    link, at = mech.point(point)
    direction = math.atan2(at[1] - pivot[1], at[0] - pivot[0])
    joints = [Joint("E", "R", (link, "block"), at), Joint("S", "P", ("bar", "block"), at, direction, tuple(pivot)),
              Joint("G", "R", ("bar", mech.ground), tuple(pivot))]
    return _added(mech, ["block", "bar"], joints, name or f"{mech.name} with a guide bar at {tuple(pivot)}")


def with_yoke(mech: Mechanism, point: str, along: float, name: str | None = None) -> Mechanism:
    """An RPP dyad on ``point``: a block pinned there slides in a yoke's slot along ``along`` (rad); the yoke
    slides on the frame across it. The yoke's slide (``slide:Y``) is the output."""
    link, at = mech.point(point)
    across = along + math.pi / 2
    joints = [Joint("E", "R", (link, "block"), at), Joint("S", "P", ("yoke", "block"), at, along),
              Joint("Y", "P", (mech.ground, "yoke"), at, across)]
    return _added(mech, ["block", "yoke"], joints, name or f"{mech.name} with a yoke")


def with_rocker(mech: Mechanism, point: str, pin, pivot, name: str | None = None) -> Mechanism:
    """An RRR dyad on ``point``: a link from it to ``pin`` on an output rocker pivoted on the frame at ``pivot``.

    The rocker's angle (``angle:output``) is the output.
    """
    link, at = mech.point(point)
    joints = [Joint("E", "R", (link, "connector"), at), Joint("F", "R", ("connector", "output"), tuple(pin)),
              Joint("G", "R", ("output", mech.ground), tuple(pivot))]
    return _added(mech, ["connector", "output"], joints, name or f"{mech.name} with an output rocker")


@dataclass(frozen=True)
class OutputMotion:
    """What the output does over one crank turn: its values, swing, turns and oscillations."""

    inputs: np.ndarray
    values: np.ndarray
    swing: float
    turns: float
    oscillations: int

    def variation(self, start: float, stop: float) -> float:
        """How far the output moves while the crank goes from ``start`` to ``stop`` (rad, modulo a turn)."""
        span = (stop - start) % (2 * math.pi)
        inside = ((self.inputs - start) % (2 * math.pi)) <= span
        return float(np.ptp(self.values[inside])) if inside.any() else 0.0


def output_motion(mech: Mechanism, output: str, steps: int = 720) -> OutputMotion:
    """Sweep the crank one turn from the drawn pose (the backend) and measure the output."""
    joint = mech.inputs[0].joint
    from domes.motion.planar.query import Kinematics
    q0 = Kinematics(mech).drawn_inputs()[joint]
    sw = sweep(mech, q0, q0 + 2 * math.pi, 2 * math.pi / steps, outputs=[output])
    if sw.status != "complete":
        raise InputError(f"{mech.name}: the crank does not turn fully: {sw.message}")
    values = sw.column(output)
    change = np.diff(values)
    signs = np.sign(change[np.abs(change) > 1e-12])
    flips = int(np.sum(signs[1:] != signs[:-1]))
    turns = (values[-1] - values[0]) / (2 * math.pi) if output.startswith("angle") else 0.0
    return OutputMotion(sw.inputs, values, float(np.ptp(values)), float(turns), (flips + 1) // 2)


__all__ = ["OutputMotion", "Stretch", "arc_stretch", "output_motion", "straight_stretch", "with_guide_bar",
           "with_rocker", "with_yoke"]
