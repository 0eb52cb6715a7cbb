"""The path task's last steps, shared by ``domes synthesize`` and the published-targets benchmark (issue 27).

After the least squares of a path task, :func:`polished_path` lowers the
best linkage's worst point (:func:`domes.motion.coupler.minimax.polish`)
and keeps it only when it does; with prescribed timing,
:func:`bounded_timing` is the bounded least squares of
:func:`domes.motion.coupler.minimax.timed_fit`, kept only when the kernel
drives its crank through every prescribed angle in one motion.

>>> from domes.design.synthesis.fourbars import FourBar
>>> fb = FourBar((0, 0), (1, 0), (3, 1), (3, 0), (1, 1))
>>> fourbar_of(fb.mechanism()) == fb
True
"""

from __future__ import annotations

import numpy as np

from domes.design.synthesis.fourbars import FourBar
from domes.design.synthesis.verify import replay
from domes.motion.coupler.minimax import TIMED_STARTS, polish, timed_fit

__all__ = ["TIMED_STARTS", "bounded_timing", "carried", "coupler_turns", "fourbar_of", "polished_path"]

#: The path task's pivot coordinates as the dimensions of :func:`~domes.motion.coupler.minimax.timed_fit`.
TIMED_GIVEN = {"a0x": "ax", "a0y": "ay", "b0x": "dx", "b0y": "dy"}


def fourbar_of(mech) -> FourBar:
    """The four-bar of a mechanism with joints ``A B C D`` and coupler point ``P``, drawn as it is."""
    return FourBar(*(tuple(mech.joint(n).at) for n in "ABCD"), tuple(mech.point("P")[1]))


def carried(fb: FourBar, a1, b1) -> tuple[float, float]:
    """The coupler point of ``fb`` carried with its coupler to the pose whose moving pivots are ``a1`` and ``b1``.

    >>> carried(FourBar((0, 0), (1, 0), (3, 0), (3, -1), (2, 1)), (0, 1), (0, 3))
    (-1.0, 2.0)
    """
    p, q = complex(*fb.a1), complex(*fb.b1)
    u, v = complex(*a1), complex(*b1)
    z = u + (complex(*fb.point) - p) * (v - u) / (q - p)
    return (float(z.real), float(z.imag))


def coupler_turns(fb: FourBar, angles) -> tuple[float, ...]:
    """The coupler's rotation (rad) from the first of the crank ``angles`` to each later one, as the kernel drives
    ``fb`` on its drawn assembly mode.

    >>> [round(t, 6) for t in coupler_turns(FourBar((0, 0), (1, 0), (3, 1), (3, 0), (1, 1)), [0.0, 0.0])]
    [0.0]
    """
    r = replay(fb, angles, ["point:B", "point:C"], between=False)
    e = (r.values["point:C.x"] - r.values["point:B.x"]) + 1j * (r.values["point:C.y"] - r.values["point:B.y"])
    turn = np.angle(e / e[0])
    return tuple(float(t) for t in turn[1:])


def polished_path(fb: FourBar, points) -> tuple[FourBar, float, float] | None:
    """``(polished, worst before, worst after)``: ``fb`` moved towards the smallest largest distance from
    ``points`` (every dimension free, pivots too), or None when the polish does not lower the worst point.
    Distances are measured by the polish on each linkage's own curve."""
    mech = fb.mechanism()
    _, (before, _) = polish(mech, points, rounds=0)
    moved, (after, _) = polish(mech, points)
    return (fourbar_of(moved), before, after) if after < before else None


def bounded_timing(points, rotations, given: dict, starts: int = TIMED_STARTS):
    """``(FourBar, crank angles, worst)``: the bounded least squares of the prescribed timing (the crank turning by
    ``rotations``, rad, from the first point to each later one; ``given`` pivot coordinates ``a0x a0y b0x b0y``
    held), its crank angles (world, rad) at the points and its largest distance there as the kernel drives it;
    None when no start closes, a coordinate other than those is given, or the kernel cannot drive the crank
    through every prescribed angle in one motion."""
    if set(given) - set(TIMED_GIVEN):
        return None
    pts = np.asarray(points, dtype=float)
    found = timed_fit(pts, np.asarray(rotations, dtype=float), {TIMED_GIVEN[k]: v for k, v in given.items()}, starts)
    if found is None:
        return None
    fb, first = fourbar_of(found[0]), found[1]
    angles = (first,) + tuple(first + r for r in rotations)
    r = replay(fb, angles, ["point:P"])
    if r.dead is not None:
        return None
    xy = np.c_[r.values["point:P.x"], r.values["point:P.y"]]
    worst = float(np.max(np.linalg.norm(xy - pts, axis=1)))
    return (fb, angles, worst) if np.isfinite(worst) else None
