"""Path generation: four-bars whose coupler point passes through given points (seed 002 §2-3, digest A.3.5).

The coupler's rotations ``θ1j`` are unknowns. With both fixed pivots ``a0``
and ``b0`` given (Table 2-1: five points, four free choices), the crank
conditions ``|D1j a1 − a0| = |a1 − a0|`` and ``|D1j b1 − b0| = |b1 − b0|``
(2-113) are, for each ``j``, linear in the circle point and, for a fixed
circle point, affine in ``(cos θ1j, sin θ1j)`` (the bilinear form of
:mod:`~domes.design.synthesis.guidance`). So for given ``θ12, θ13`` the
moving pivots follow from two 2 × 2 linear solves, and each further point
``j`` gives one condition: the two lines in ``(cos θ1j, sin θ1j)`` of the
two cranks meet on the unit circle. Five points leave two such conditions
in ``(θ12, θ13)``; :func:`five_points` finds every common zero on the torus
by a dense grid (sign changes of both in a cell) and polishes each by
Newton, then checks all eight equations. The search is repeated with the
pivots taken from points 4 and 5 (grid over ``θ14, θ15``), so that a root
next to a singular line of one parametrisation is seen in the other.

>>> P = [(1.0, 1.0), (2.0, 0.5), (3.0, 1.5), (2.0, 2.0), (1.5, 1.9)]       # seed 002 §2-3, Example 5
>>> sols = five_points(P, (2.10, 0.60), (1.50, 4.20))
>>> book = min(sols, key=lambda s: math.dist(s.a1, (0.607, -1.127)))
>>> [round(v, 6) for v in book.a1 + book.b1]
[0.607375, -1.127103, -0.5864, 0.996999]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import fsolve

from domes.errors import InputError
from domes.results import Progress, Ticker

#: Grid cells per turn of each of θ12 and θ13.
GRID = 720


@dataclass(frozen=True)
class PathSolution:
    """Moving pivots ``a1``, ``b1`` (position 1), the coupler rotations ``θ1j`` (rad) and the largest residual."""

    a1: tuple[float, float]
    b1: tuple[float, float]
    rotations: tuple[float, ...]
    residual: float


def _rows(P, j, pivot, c, s):
    """``(n, r)`` of the crank condition ``n · q1 = r`` of point ``j`` for coupler rotation ``(c, s)``.

    Written affine in ``(c, s)`` (``Rᵀ t = Rᵀ P_j − P1``, ``|t|² = |P_j|² + |P1|² − 2 P_j · R P1``), so that
    it may be evaluated off the unit circle.
    """
    p1x, p1y = P[0]
    pjx, pjy = P[j]
    gx, gy = pivot
    # n = 2 (Rᵀ P_j − P1 − Rᵀ pivot + pivot)
    nx = 2 * (c * (pjx - gx) + s * (pjy - gy) - p1x + gx)
    ny = 2 * (-s * (pjx - gx) + c * (pjy - gy) - p1y + gy)
    # r = 2 pivot · (P_j − R P1) − |P_j|² − |P1|² + 2 P_j · R P1
    rp1x, rp1y = c * p1x - s * p1y, s * p1x + c * p1y
    r = (2 * (gx * (pjx - rp1x) + gy * (pjy - rp1y)) - (pjx * pjx + pjy * pjy) - (p1x * p1x + p1y * p1y)
         + 2 * (pjx * rp1x + pjy * rp1y))
    return nx, ny, r


def _pivot(P, pivot, c2, s2, c3, s3, pair=(1, 2)):
    """The circle point from the conditions of the points ``pair`` (Cramer; NaN where they are dependent)."""
    n2x, n2y, r2 = _rows(P, pair[0], pivot, c2, s2)
    n3x, n3y, r3 = _rows(P, pair[1], pivot, c3, s3)
    det = n2x * n3y - n2y * n3x
    with np.errstate(invalid="ignore", divide="ignore"):
        return (r2 * n3y - n2y * r3) / det, (n2x * r3 - r2 * n3x) / det


def _line(P, j, pivot, q):
    """``(α, β, γ)`` with ``α cos θ1j + β sin θ1j = γ`` the condition of point ``j`` for circle point ``q``."""
    qx, qy = q
    e0 = [v for v in _rows(P, j, pivot, 0.0, 0.0)]
    e1 = [v for v in _rows(P, j, pivot, 1.0, 0.0)]
    e2 = [v for v in _rows(P, j, pivot, 0.0, 1.0)]
    f = [n[0] * qx + n[1] * qy - n[2] for n in (e0, e1, e2)]
    return f[1] - f[0], f[2] - f[0], -f[0]


def _meet(P, j, a0, b0, a1, b1):
    """``(cos θ1j, sin θ1j)`` where the two cranks' lines of point ``j`` meet, and how far off the unit circle."""
    aa, ab, ag = _line(P, j, a0, a1)
    ba, bb, bg = _line(P, j, b0, b1)
    det = aa * bb - ab * ba
    with np.errstate(invalid="ignore", divide="ignore"):
        c = (ag * bb - ab * bg) / det
        s = (aa * bg - ag * ba) / det
    return c, s, c * c + s * s - 1.0


def _conditions(P, a0, b0, t2, t3, pair=(1, 2)):
    """The pivots from the points ``pair`` at rotations ``t2, t3``, and the conditions of the other two points."""
    c2, s2, c3, s3 = np.cos(t2), np.sin(t2), np.cos(t3), np.sin(t3)
    a1 = _pivot(P, a0, c2, s2, c3, s3, pair)
    b1 = _pivot(P, b0, c2, s2, c3, s3, pair)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):       # NaN at the poles: left out by the callers
        g = [_meet(P, j, a0, b0, a1, b1)[2] for j in range(1, 5) if j not in pair]
    return a1, b1, g


#: The pairs of points whose rotations span the searched grids (a root near a singular line of one is clear in
#: the other).
PAIRS = ((1, 2), (3, 4))


def check_path(points, a0, b0) -> None:
    """An InputError naming the entry when the five-point task cannot be solved."""
    P = np.asarray(points, dtype=float)
    if P.shape != (5, 2) or not np.all(np.isfinite(P)):
        raise InputError(f"five-point path generation takes 5 finite points (x, y), got an array of shape {P.shape}")
    size = float(np.ptp(P, axis=0).max())
    for j in range(5):
        for k in range(j):
            if math.dist(P[j], P[k]) <= 1e-9 * max(size, 1e-300):
                raise InputError(f"points {k + 1} and {j + 1} coincide")
    for name, q in (("a0", a0), ("b0", b0)):
        if len(q) != 2 or not all(math.isfinite(v) for v in q):
            raise InputError(f"{name} must be two finite numbers")
    if math.dist(a0, b0) <= 1e-9 * max(size, 1e-300):
        raise InputError("a0 and b0 coincide: the frame has no length")


def five_points(points, a0, b0, grid: int = GRID, method: str = "exact", seeds: int = 64,
                seed: int = 0, progress: Progress | None = None) -> list[PathSolution]:
    """Every real four-bar through five path points with fixed pivots ``a0``, ``b0`` (all eight equations
    met to 1e-9 of the points' size).

    ``method="fast"`` polishes ``seeds`` random starts instead of searching
    the grids (the book's procedure, step 6): quicker, and it finds some of
    the roots, not all. Every root is returned, degenerate ones too: with the
    points (nearly) on one line the equations are met in the limit of a
    translating coupler on endless cranks, hundreds of roots with pivots far
    away (:mod:`~domes.design.synthesis.verify` groups them).
    """
    check_path(points, a0, b0)
    clock = Ticker(progress)
    P = [tuple(map(float, p)) for p in points]
    a0, b0 = tuple(map(float, a0)), tuple(map(float, b0))
    size = float(np.ptp(np.asarray(P), axis=0).max())
    if method == "fast":
        found: list[PathSolution] = []
        at = _Scalar(P, a0, b0, (1, 2))
        for k, guess in enumerate(np.random.default_rng(seed).uniform(-math.pi, math.pi, (seeds, 2))):
            clock.tick(lambda: f"path points: start {k + 1} of {seeds}, {len(found)} solution(s)")
            sol = _polish(P, a0, b0, guess, size, at=at)
            if sol is not None and not any(math.dist(sol.a1, f.a1) + math.dist(sol.b1, f.b1) <= 1e-7 * size
                                           for f in found):
                found.append(sol)
        return found
    if method != "exact":
        raise InputError(f"method must be 'exact' or 'fast', got {method!r}")
    t = np.linspace(-math.pi, math.pi, grid + 1)
    T2, T3 = np.meshgrid(t, t, indexing="ij")
    found: list[PathSolution] = []
    for pair in PAIRS:
        _, _, (g4, g5) = _conditions(P, a0, b0, T2, T3, pair)
        cells = _sign_cells(g4) & _sign_cells(g5) & _small(g4) & _small(g5)
        todo = list(zip(*np.nonzero(cells)))
        at = _Scalar(P, a0, b0, pair)
        for c, (i, k) in enumerate(todo):
            clock.tick(lambda: f"path points: grid {PAIRS.index(pair) + 1} of {len(PAIRS)}, cell {c + 1} of "
                       f"{len(todo)}, {len(found)} solution(s)")
            guess = np.array([0.5 * (t[i] + t[i + 1]), 0.5 * (t[k] + t[k + 1])])
            sol = _polish(P, a0, b0, guess, size, pair, at)
            if sol is not None and not any(math.dist(sol.a1, f.a1) + math.dist(sol.b1, f.b1) <= 1e-7 * size
                                           for f in found):
                found.append(sol)
    return found


def _small(g, bound: float = 0.5):
    """Cells whose corners all have ``|g| < bound``: a sign change across a pole of ``g`` (where the pivots' 2 × 2
    solve is singular) is not a root; a root next to a pole is found in the other parametrisation."""
    ok = np.where(np.isfinite(g), np.abs(g) < bound, False)
    return ok[:-1, :-1] & ok[1:, :-1] & ok[:-1, 1:] & ok[1:, 1:]


def _sign_cells(g):
    """Cells of the grid where ``g`` takes both signs at its corners (NaN corners excluded)."""
    pos = np.where(np.isfinite(g), g > 0, False)
    neg = np.where(np.isfinite(g), g < 0, False)
    any_pos = pos[:-1, :-1] | pos[1:, :-1] | pos[:-1, 1:] | pos[1:, 1:]
    any_neg = neg[:-1, :-1] | neg[1:, :-1] | neg[:-1, 1:] | neg[1:, 1:]
    return any_pos & any_neg


def _div(a: float, b: float) -> float:
    """``a / b`` as numpy divides (±inf or NaN where ``b`` is zero)."""
    if b:
        return a / b
    with np.errstate(all="ignore"):
        return float(np.divide(a, b))


class _Scalar:
    """:func:`_conditions` and :func:`_meet` at one point ``(θ, θ')`` in Python floats, for the polish, which
    evaluates them thousands of times: numpy's scalars cost ten times as much for the same numbers. The same
    operations in the same order (the sines and cosines are numpy's, as on the grid); the parts that do not
    depend on the rotations are worked out once."""

    def __init__(self, P, a0, b0, pair):
        self.P, self.a0, self.b0, self.pair = P, a0, b0, pair
        self.others = [j for j in range(1, 5) if j not in pair]
        # the lines of :func:`_line`: the rows at (c, s) = (0, 0), (1, 0) and (0, 1), for each point and pivot
        self.rows = {(j, k): tuple(self.row(j, pivot, c, s) for c, s in ((0.0, 0.0), (1.0, 0.0), (0.0, 1.0)))
                     for j in range(1, 5) for k, pivot in enumerate((a0, b0))}
        p1x, p1y = P[0]
        self.first = p1x, p1y, p1x * p1x + p1y * p1y
        self.fixed = {(j, k): (*P[j], *pivot, P[j][0] - pivot[0], P[j][1] - pivot[1], P[j][0] * P[j][0] + P[j][1] * P[j][1])
                      for j in pair for k, pivot in enumerate((a0, b0))}

    def row(self, j, pivot, c, s):
        """:func:`_rows` on this task's points (Python floats)."""
        return _rows(self.P, j, pivot, c, s)

    def pivot(self, pivot: int, c2, s2, c3, s3):
        """:func:`_pivot` (the two rows of :meth:`row` written out, with the sums that do not depend on the rotation
        taken from :attr:`fixed`)."""
        p1x, p1y, p11 = self.first
        j, k = self.pair
        pjx, pjy, gx, gy, dx, dy, pjj = self.fixed[j, pivot]
        n2x = 2 * (c2 * dx + s2 * dy - p1x + gx)
        n2y = 2 * (-s2 * dx + c2 * dy - p1y + gy)
        rp1x, rp1y = c2 * p1x - s2 * p1y, s2 * p1x + c2 * p1y
        r2 = 2 * (gx * (pjx - rp1x) + gy * (pjy - rp1y)) - pjj - p11 + 2 * (pjx * rp1x + pjy * rp1y)
        pjx, pjy, gx, gy, dx, dy, pjj = self.fixed[k, pivot]
        n3x = 2 * (c3 * dx + s3 * dy - p1x + gx)
        n3y = 2 * (-s3 * dx + c3 * dy - p1y + gy)
        rp1x, rp1y = c3 * p1x - s3 * p1y, s3 * p1x + c3 * p1y
        r3 = 2 * (gx * (pjx - rp1x) + gy * (pjy - rp1y)) - pjj - p11 + 2 * (pjx * rp1x + pjy * rp1y)
        det = n2x * n3y - n2y * n3x
        return _div(r2 * n3y - n2y * r3, det), _div(n2x * r3 - r2 * n3x, det)

    def meet(self, j, a1, b1):
        """:func:`_meet`."""
        (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = self.rows[j, 0]
        (b00, b01, b02), (b10, b11, b12), (b20, b21, b22) = self.rows[j, 1]
        qx, qy = a1
        f0 = a00 * qx + a01 * qy - a02
        aa, ab, ag = (a10 * qx + a11 * qy - a12) - f0, (a20 * qx + a21 * qy - a22) - f0, -f0
        qx, qy = b1
        f0 = b00 * qx + b01 * qy - b02
        ba, bb, bg = (b10 * qx + b11 * qy - b12) - f0, (b20 * qx + b21 * qy - b22) - f0, -f0
        det = aa * bb - ab * ba
        c = _div(ag * bb - ab * bg, det)
        s = _div(aa * bg - ag * ba, det)
        return c, s, c * c + s * s - 1.0

    def conditions(self, t2, t3):
        """:func:`_conditions`."""
        c2, s2, c3, s3 = float(np.cos(t2)), float(np.sin(t2)), float(np.cos(t3)), float(np.sin(t3))
        a1 = self.pivot(0, c2, s2, c3, s3)
        b1 = self.pivot(1, c2, s2, c3, s3)
        j, k = self.others
        return a1, b1, [self.meet(j, a1, b1)[2], self.meet(k, a1, b1)[2]]


def _polish(P, a0, b0, guess, size, pair=(1, 2), at: _Scalar | None = None):
    at = at or _Scalar(P, a0, b0, pair)

    def fn(x):
        return at.conditions(x[0], x[1])[2]

    with np.errstate(all="ignore"):
        x, info, ok, _ = fsolve(fn, guess, full_output=True, xtol=1e-14)
    if not np.all(np.isfinite(info["fvec"])) or np.max(np.abs(info["fvec"])) > 1e-10:
        return None
    a1, b1, _ = at.conditions(x[0], x[1])
    if not all(map(math.isfinite, a1 + b1)):
        return None
    rot = []
    for j in range(1, 5):
        if j in pair:
            rot.append(float(x[pair.index(j)]))
        else:
            c, s, _ = at.meet(j, a1, b1)
            rot.append(math.atan2(s, c))
    res = residuals(P, a0, b0, a1, b1, rot)
    if not res <= 1e-9 * max(size, 1.0):
        return None
    wrap = [(r + math.pi) % (2 * math.pi) - math.pi for r in rot]
    return PathSolution(a1, b1, tuple(wrap), float(res))


def residuals(P, a0, b0, a1, b1, rotations) -> float:
    """The largest error of the eight crank equations (2-113), as a difference of lengths."""
    worst = 0.0
    p1 = np.asarray(P[0])
    for j, th in enumerate(rotations, start=1):
        R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        for pivot, q in ((a0, a1), (b0, b1)):
            qj = R @ (np.asarray(q) - p1) + np.asarray(P[j])
            worst = max(worst, abs(np.linalg.norm(qj - pivot) - np.linalg.norm(np.asarray(q) - pivot)))
    return worst


def coupler_positions(P, solution: PathSolution):
    """The moving pivots at every point: ``(A_j, B_j)`` lists, for the checks."""
    p1 = np.asarray(P[0])
    A, B = [np.asarray(solution.a1)], [np.asarray(solution.b1)]
    for j, th in enumerate(solution.rotations, start=1):
        R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        A.append(R @ (np.asarray(solution.a1) - p1) + np.asarray(P[j]))
        B.append(R @ (np.asarray(solution.b1) - p1) + np.asarray(P[j]))
    return A, B
