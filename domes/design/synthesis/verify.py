"""Every synthesised linkage moved by the kinematics kernel, and its degenerate roots grouped (seed 002 §2-3).

A root of the synthesis equations is an answer only when the linkage it
describes does the task. :func:`replay` drives the linkage (its
``mechanism()``) with the compiled kernel (:func:`domes.motion.planar.batch.batch`)
through the crank angles it claims, on the assembly mode of its first
position (the drawn one), and over a dense grid between consecutive angles
(the loop must close all the way); :func:`errors` compares what the kernel
gives with what the task wants: the coupler point with the path points, the
coupler's pose with the guided positions, the rocker pin with the wanted
rocker angles. :func:`degenerate_kind` names the roots that are not
linkages worth listing: a link of zero length, pivots running off to
infinity (points in line are met in the limit of a translating coupler on
endless cranks), links longer than ``max_link_ratio`` times the task.

>>> from domes.design.synthesis.fourbars import FourBar
>>> fb = FourBar((0, 0), (1, 0), (3, 2), (3, 0), (1, 1))
>>> claim = Claim(angles=(0.0, 0.3), points=((1.0, 1.0), (1.1, 1.3)))
>>> [round(e, 4) for e in errors(fb, claim)]     # the kernel puts the coupler point at (1.0989, 1.2852) at 0.3 rad
[0.0, 0.0149]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.motion.coupler.freehand import polyline_distances
from domes.motion.planar.batch import batch

#: Default tolerance (relative to the task's size) within which every re-evaluated error of a usable linkage lies.
TOLERANCE = 1e-6

#: Default bound on the longest link over the task's extent (the spread of its points and given pivots).
MAX_LINK_RATIO = 20.0

#: A link shorter than this fraction of the task's extent is of zero length (coincident pivots).
ZERO_LINK = 1e-6

#: The kernel's step (rad) between consecutive positions, where it checks that the loop closes all the way.
STEP = math.radians(0.25)

#: Rounding of one floating-point operation: a linkage whose links are ``L`` long and whose task is ``size`` across
#: is re-evaluated to about ``16 × ROUNDING × L² / size`` (closing a dyad subtracts squares of lengths ``L``; two
#: independent evaluations of the runaway roots of five points in line differ by up to 3.6 × ROUNDING × L² / size).
ROUNDING = float(np.finfo(float).eps)

#: The names of the degenerate groups, in the order they are tested.
GROUPS = ("zero link", "runaway", "long links")


@dataclass(frozen=True)
class Claim:
    """What a solution claims to do: at the crank ``angles`` (rad, in the order of travel) the coupler point is at
    ``points``, the coupler has turned by ``turns`` (rad, from the first position), the rocker pin is at ``pins``.
    ``on_curve``: the points need only lie on the coupler curve (least squares, no timing)."""

    angles: tuple[float, ...]
    points: tuple | None = None
    turns: tuple | None = None
    pins: tuple | None = None
    on_curve: bool = False
    size: float = 1.0           # the length that relates a turn of the coupler to a distance (guidance)


@dataclass(frozen=True)
class Replay:
    """The kernel's outputs at the claimed angles (``values``: column -> ``(n,)``, NaN where the loop does not
    close), the first gap ``(j, angle °)`` between positions ``j`` and ``j + 1`` where it does not close, and
    the batch status of the drawn pose (``ambiguous``: drawn on a dead point)."""

    values: dict
    dead: tuple[int, float] | None
    kind: str


def replay(linkage, angles, outputs, between: bool = True) -> Replay:
    """Drive ``linkage`` (a FourBar or SliderCrank) by the kernel through ``angles`` (rad) on its drawn assembly
    mode; with ``between``, also over a grid of :data:`STEP` between consecutive angles."""
    angles = np.asarray(angles, dtype=float)
    gaps = []
    if between:
        for j in range(len(angles) - 1):
            k = max(2, int(math.ceil(abs(angles[j + 1] - angles[j]) / STEP)) + 1)
            gaps.append(np.linspace(angles[j], angles[j + 1], k)[1:-1])
    grid = np.concatenate([angles] + gaps)
    b = batch(linkage.mechanism(), inputs=grid, outputs=list(outputs))
    n = len(angles)
    values = {c: v[0, :n] for c, v in b.values.items()}
    dead = None
    start = n
    for j, gap in enumerate(gaps, 1):
        closed = b.assembled[0, start:start + gap.size]
        if not closed.all():
            dead = (j, float(math.degrees(gap[int(np.argmin(closed))])))
            break
        start += gap.size
    return Replay(values, dead, str(b.kinds[0]))


def errors(linkage, claim: Claim, replayed: Replay | None = None) -> tuple[float, ...]:
    """The distance (a length) between what the kernel gives at each claimed angle and what the claim says: the
    coupler point from its point, plus (guidance) the coupler's turn error times ``claim.size``, or the rocker
    pin from its pin; ``inf`` where the loop does not close."""
    if claim.on_curve:
        return curve_distances(linkage, claim.points)
    r = replayed or replay(linkage, claim.angles, _outputs(claim), between=False)
    n = len(claim.angles)
    out = np.zeros(n)
    if claim.points is not None:
        xy = np.c_[r.values["point:P.x"], r.values["point:P.y"]]
        out += np.linalg.norm(xy - np.asarray(claim.points, dtype=float), axis=1)
    if claim.turns is not None:
        turn = r.values["angle:coupler"] - r.values["angle:coupler"][0]
        wrong = np.remainder(turn - np.asarray(claim.turns) + math.pi, 2 * math.pi) - math.pi
        out += claim.size * np.abs(wrong)
    if claim.pins is not None:
        xy = np.c_[r.values["point:C.x"], r.values["point:C.y"]]
        out += np.linalg.norm(xy - np.asarray(claim.pins, dtype=float), axis=1)
    return tuple(float(e) if np.isfinite(e) else math.inf for e in out)


def curve_distances(fb, points) -> tuple[float, ...]:
    """The distance of each point from the coupler curve of ``fb`` on its drawn assembly mode (the one through the
    first point): the nearest of 2,880 crank angles, then 400 around it, evaluated by the kernel."""
    mech = fb.mechanism()
    grid = np.linspace(-math.pi, math.pi, 2881)
    b = batch(mech, inputs=grid, outputs=["point:P"])
    curve = np.c_[b.values["point:P.x"][0], b.values["point:P.y"][0]]
    pts = np.asarray(points, dtype=float)
    if not np.isfinite(curve).any():
        return tuple(math.inf for _ in pts)
    near = [int(np.nanargmin(np.linalg.norm(curve - p, axis=1))) for p in pts]
    h = grid[1] - grid[0]
    local = np.concatenate([np.linspace(grid[k] - 2 * h, grid[k] + 2 * h, 401) for k in near])
    fine = batch(mech, inputs=local, outputs=["point:P"])
    xy = np.c_[fine.values["point:P.x"][0], fine.values["point:P.y"][0]].reshape(len(pts), 401, 2)
    return tuple(float(min(polyline_distances(xy[j], p[None], closed=False)[0], polyline_distances(curve, p[None])[0]))
                 for j, p in enumerate(pts))


def _outputs(claim: Claim) -> list[str]:
    return ((["point:P"] if claim.points is not None else []) + (["angle:coupler"] if claim.turns is not None else [])
            + (["point:C"] if claim.pins is not None else []))


def check(linkage, claim: Claim, tolerance: float, size: float, what: str = "point",
          known: tuple[str, ...] = ()) -> tuple[tuple[float, ...], tuple[str, ...]]:
    """The re-evaluated errors of ``linkage`` and the defects they show: an error beyond ``tolerance × size``
    (saying by how much), a position where the loop does not close, a dead point between two positions (unless
    ``known``, the defects found already, has one or an order defect), a drawn pose on a dead point."""
    defects = []
    r = None
    if not claim.on_curve:
        r = replay(linkage, claim.angles, _outputs(claim))
        if r.kind == "ambiguous":
            defects.append("drawn on a dead point: the assembly mode of position 1 is not defined")
    errs = errors(linkage, claim, r)
    longest = longest_shortest(linkage)[0]
    blur = resolution(longest, size)
    if not blur < tolerance * size:
        defects.append(f"too long to check: with links {longest / size:.3g} times the task's size the re-evaluation "
                       f"is uncertain by {blur:.2g}, more than the tolerance {tolerance:g} of the size "
                       f"({tolerance * size:.2g})")
    off = [j for j, e in enumerate(errs) if not e <= tolerance * size]
    open_ = [j for j in off if math.isinf(errs[j])]
    if open_:
        where = (f"at the crank angle of {what} {open_[0] + 1} ({math.degrees(claim.angles[open_[0]]):.2f}°) on the "
                 "assembly mode of position 1" if r is not None else "anywhere on the assembly mode of position 1")
        defects.append(f"the loop does not close {where}")
    finite = [j for j in off if not math.isinf(errs[j])]
    if finite:
        j = max(finite, key=lambda k: errs[k])
        how = ("the nearest point of its coupler curve is that far" if claim.on_curve else
               f"the kernel, driving the crank to {math.degrees(claim.angles[j]):.2f}° on the assembly mode of "
               "position 1, puts it that far")
        others = f"; {len(finite) - 1} other {what}(s) miss too" if len(finite) > 1 else ""
        defects.append(f"misses {what} {j + 1} by {errs[j]:.3g} ({errs[j] / size:.2g} of the task's size {size:.3g}; "
                       f"tolerance {tolerance:g}): {how}{others}")
    if r is not None and r.dead is not None and not any(d.startswith(("dead point", "order defect")) for d in known):
        defects.append(f"dead point (kernel): the loop does not close between {what}s {r.dead[0]} and "
                       f"{r.dead[0] + 1}, near crank angle {r.dead[1]:.1f}°")
    return errs, tuple(defects)


def resolution(longest: float, size: float) -> float:
    """How far a re-evaluation of a linkage with links ``longest`` long may be off in floating point, for a task
    ``size`` across (see :data:`ROUNDING`)."""
    return 16 * ROUNDING * longest * longest / size


def longest_shortest(linkage) -> tuple[float, float]:
    """The longest link, the coupler's arm to its point included, and the shortest (a slider-crank's offset may be
    zero and is left out of the shortest, as is the arm: a coupler point on a pin is a circle's path)."""
    lengths = linkage.lengths
    moving = lengths[:2] if len(lengths) == 3 else lengths
    arms = (math.dist(linkage.point, linkage.a1), math.dist(linkage.point, linkage.b1)) if linkage.point else ()
    return max(lengths + arms), min(moving)


def coupler_turns(poses) -> np.ndarray:
    """The coupler's turn (rad) from the first position at every position, from its moving pivots."""
    A = np.array([p[0] for p in poses], dtype=float)
    B = np.array([p[1] for p in poses], dtype=float)
    ang = np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])
    return np.remainder(ang - ang[0] + math.pi, 2 * math.pi) - math.pi


def degenerate_kind(linkage, poses, extent: float, size: float, max_link_ratio: float) -> str | None:
    """The degenerate group of a root (one of :data:`GROUPS`), or None for a linkage worth listing.

    ``zero link``: a link shorter than :data:`ZERO_LINK` × ``extent``;
    ``runaway``: the longest link (:func:`longest_shortest`) beyond ``max_link_ratio`` × ``extent`` with
    the coupler turning by less than ``size`` over that link at every
    position (it nearly translates: pivots running off to infinity);
    ``long links``: any other root whose longest link is beyond the ratio.
    """
    longest, shortest = longest_shortest(linkage)
    if not shortest > ZERO_LINK * extent:
        return "zero link"
    if longest > max_link_ratio * extent:
        turn = float(np.max(np.abs(coupler_turns(poses)))) if len(poses) > 1 else 0.0
        return "runaway" if turn * longest <= size else "long links"
    return None


@dataclass(frozen=True)
class Degenerate:
    """A group of degenerate roots: its name (one of :data:`GROUPS`), how many, the line that describes it, and
    the roots (``members``, each a :class:`~domes.design.synthesis.solve.Solution`)."""

    name: str
    count: int
    text: str
    members: tuple = ()


def group(name: str, members, extent: float, max_link_ratio: float) -> Degenerate:
    """The :class:`Degenerate` group ``name`` of ``members`` (solutions), with its describing line."""
    longest = [longest_shortest(s.fourbar)[0] / extent for s in members]
    span = (f"{min(longest):.3g}" if len(longest) == 1 or min(longest) == max(longest)
            else f"{min(longest):.3g} to {max(longest):.3g}")
    n = len(members)
    if name == "zero link":
        text = (f"degenerate: {n} root(s) with a link of zero length (coincident pivots, shorter than {ZERO_LINK:g} "
                "of the task's extent): not a four-bar")
    elif name == "runaway":
        text = (f"degenerate: {n} root(s) with pivots running off to infinity (a translating coupler in the limit): "
                f"longest link {span} times the task's extent, the coupler nearly not turning")
    else:
        text = (f"degenerate: {n} root(s) with links beyond max_link_ratio {max_link_ratio:g}: longest link {span} "
                "times the task's extent (raise max_link_ratio, --max-link-ratio, to list them)")
    return Degenerate(name, n, text, tuple(members))


__all__ = ["GROUPS", "MAX_LINK_RATIO", "TOLERANCE", "ZERO_LINK", "Claim", "Degenerate", "Replay", "check",
           "curve_distances", "degenerate_kind", "errors", "group", "replay",
           "resolution"]
