"""Planar rigid-body guidance: the crank dyads that guide a body through precision positions (digest A.3.1).

A crank with fixed pivot ``a0`` and moving pivot ``a1`` (in position 1)
guides the body when ``|D1j a1 − a0| = |a1 − a0|`` for every position ``j``
(2-49), (2-56). Expanded, each equation is *bilinear* in ``a0`` and ``a1``:

    2 (R_jᵀ (t_j − a0) + a0) · a1 = 2 a0 · t_j − |t_j|²,   D1j = [R_j | t_j]

so with ``a1`` given, ``a0`` follows from a linear solve, and the other
way round. Two positions leave a family, three give one centre point per
circle point (:func:`centre_point`) and one circle point per centre point
(:func:`circle_point`); four give the circle-point curve, a cubic
(:func:`circle_points_at` gives its points on a vertical line, every
branch: the three roots of a cubic in ``y``); five give the Burmester
points (:func:`burmester_points`), the real intersections of two such
cubics, found as the real roots of their resultant (degree 9) and
polished.

>>> pos = [Position((1.0, 1.0), 0.0), Position((2.0, 0.5), 0.0), Position((3.0, 1.5), math.radians(45)),
...        Position((2.0, 2.0), math.radians(90))]                              # seed 002 §2-3, Example 2
>>> sorted(round(float(y), 6) for y in circle_points_at(pos, 0.0))              # digest S-08
[-1.915055, 1.488794, 2.736921]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import chebyshev as C
from scipy.optimize import fsolve

from domes.design.synthesis.displacement import circumcentre, displacement, moved
from domes.errors import InputError


@dataclass(frozen=True)
class Position:
    """A precision position of the guided body: its reference point and angle (rad)."""

    point: tuple[float, float]
    angle: float


def displacements(positions: list[Position]) -> list[np.ndarray]:
    """``D1j`` of every position (``D11`` is the identity)."""
    p1, t1 = positions[0].point, positions[0].angle
    return [displacement(p1, p.point, p.angle - t1) for p in positions]


def size(positions: list[Position]) -> float:
    """The spread of the reference points (the scale of tolerances)."""
    pts = np.array([p.point for p in positions], dtype=float)
    return float(max(np.ptp(pts, axis=0).max(), 1e-300))


def check_positions(positions: list[Position], most: int = 5) -> None:
    """An InputError naming the entry when the positions cannot be synthesised."""
    if not 2 <= len(positions) <= most:
        raise InputError(f"planar guidance by crank dyads takes 2 to {most} positions, got {len(positions)}")
    for j, p in enumerate(positions, 1):
        if not (np.all(np.isfinite(p.point)) and math.isfinite(p.angle)):
            raise InputError(f"position {j}: the point and angle must be finite numbers")
    for j in range(len(positions)):
        for k in range(j):
            same_point = math.dist(positions[j].point, positions[k].point) <= 1e-12 * size(positions)
            same_angle = abs(math.remainder(positions[j].angle - positions[k].angle, 2 * math.pi)) <= 1e-12
            if same_point and same_angle:
                raise InputError(f"positions {k + 1} and {j + 1} coincide: the body does not move between them")


def _rows(Ds, a0, which):
    """The linear equations ``n · a1 = r`` of the positions ``which`` for the centre point ``a0``."""
    a0 = np.asarray(a0, dtype=float)
    N, r = [], []
    for j in which:
        R, t = Ds[j][:2, :2], Ds[j][:2, 2]
        N.append(2 * (R.T @ (t - a0) + a0))
        r.append(2 * a0 @ t - t @ t)
    return np.array(N), np.array(r)


def circle_point(positions: list[Position], a0) -> np.ndarray:
    """The moving pivot (in position 1) of the crank pivoted at ``a0`` that guides through three positions."""
    Ds = displacements(positions)
    N, r = _rows(Ds, a0, range(1, len(positions)))
    if len(positions) != 3:
        raise InputError("a circle point from a centre point is unique for three positions")
    if abs(np.linalg.det(N)) <= 1e-13 * max(np.abs(N).max() ** 2, 1e-300):
        raise InputError(f"no circle point for the centre point {tuple(a0)}: it is a pole or the positions are "
                         "degenerate")
    return np.linalg.solve(N, r)


def centre_point(positions: list[Position], a1) -> np.ndarray:
    """The fixed pivot of the crank whose moving pivot is ``a1`` in position 1 (three or more positions:
    the circumcentre of its first three positions)."""
    Ds = displacements(positions)
    pts = [moved(D, a1) for D in Ds[:3]]
    return circumcentre(*pts)


def _cubic_in_y(Ds, which, x, scale, centre):
    """Coefficients (highest first) of ``det[|a_j|², a_jx, a_jy, 1]`` over positions ``which``, as a cubic in ``y``."""
    ys = centre + scale * np.array([-1.0, -1 / 3, 1 / 3, 1.0])
    vals = [_concyclic(Ds, which, (x, y)) for y in ys]
    return np.polyfit((ys - centre) / scale, vals, 3), centre, scale


def _concyclic(Ds, which, a1) -> float:
    M = np.empty((4, 4))
    for row, j in enumerate(which):
        p = moved(Ds[j], a1)
        M[row] = (p @ p, p[0], p[1], 1.0)
    return float(np.linalg.det(M))


def circle_points_at(positions: list[Position], x: float) -> list[float]:
    """Every ``y`` with ``(x, y)`` on the circle-point curve of four positions (the real roots of a cubic)."""
    check_positions(positions)
    if len(positions) != 4:
        raise InputError(f"the circle-point curve is of four positions, got {len(positions)}")
    Ds = displacements(positions)
    s = size(positions)
    centre = float(np.mean([p.point[1] for p in positions]))
    coef, c0, sc = _cubic_in_y(Ds, range(4), x, s, centre)
    roots = np.roots(coef)
    top = max(np.abs(coef).max(), 1e-300)
    ys = [c0 + sc * r.real for r in roots if abs(r.imag) <= 1e-9 * max(1.0, abs(r))]
    if abs(coef[0]) <= 1e-13 * top:     # the curve's asymptote direction: fewer finite roots
        ys = [c0 + sc * r.real for r in np.roots(coef[1:]) if abs(r.imag) <= 1e-9 * max(1.0, abs(r))]
    return [_polish_y(Ds, x, y, s) for y in ys]


def _polish_y(Ds, x, y, s):
    f = lambda yy: _concyclic(Ds, range(4), (x, yy))   # noqa: E731
    for _ in range(6):
        h = 1e-7 * s
        d = (f(y + h) - f(y - h)) / (2 * h)
        if d == 0:
            break
        step = f(y) / d
        y -= step
        if abs(step) <= 1e-15 * max(s, abs(y)):
            break
    return float(y)


@dataclass(frozen=True)
class Dyad:
    """A guiding crank: fixed pivot ``a0`` (centre point) and moving pivot ``a1`` (circle point, position 1)."""

    a0: tuple[float, float]
    a1: tuple[float, float]
    radius: float
    residual: float


def dyad(positions: list[Position], a1) -> Dyad:
    """The crank through circle point ``a1`` with its residual: the spread of ``|a_j − a0|`` over the positions."""
    a0 = centre_point(positions, a1)
    Ds = displacements(positions)
    radii = [float(np.linalg.norm(moved(D, a1) - a0)) for D in Ds]
    return Dyad(tuple(float(v) for v in a0), tuple(float(v) for v in a1), radii[0], max(radii) - min(radii))


def circle_point_curve(positions: list[Position], xs) -> list[Dyad]:
    """Points of the circle-point curve of four positions at every abscissa in ``xs``, every branch, with their
    centre points (the centre-point curve); poles and points whose centre is undefined are left out."""
    out = []
    Ds, s = displacements(positions), size(positions)
    for x in xs:
        for y in circle_points_at(positions, float(x)):
            if _is_pole(Ds, (float(x), y), 1e-9 * s):
                continue
            try:
                out.append(dyad(positions, (float(x), y)))
            except InputError:
                continue
    return out


#: The frames (turned by these angles, rad) in which the Burmester points are searched.
TURNS = (0.0, 1.0, 2.1)
#: The half-widths (× the positions' size) of the windows the resultant is fitted over: a degree-9 polynomial
#: fitted over a wide window loses the relative accuracy of its small values near the middle.
WINDOWS = (2.0, 10.0)


def burmester_points(positions: list[Position], reach: float = 10.0, method: str = "exact", seeds: int = 64,
                     seed: int = 0) -> list[Dyad]:
    """Every real Burmester point pair of five positions within ``reach`` × their size of their centre.

    The circle points lie on the circle-point curves of positions 1234 and
    1235; in ``x`` their intersections are the real roots of the
    resultant in ``y`` of the two cubics (degree 9), fitted in a Chebyshev
    basis over the reach and polished by Newton in ``(x, y)`` (a root of the
    fit near the real axis seeds the polishing too). Two intersections with
    nearly the same ``x`` (a Burmester point and a pole, or two Burmester
    points) can merge in the fit, so the search is repeated in frames turned
    by :data:`TURNS` and the answers merged. Poles (where two
    positions of the point coincide) are not guiding cranks and are left
    out; every pair returned has all five distances equal to 1e-9.
    ``method="fast"`` polishes ``seeds`` random starts around the positions
    instead: quicker, and it finds some of the points, not all.
    """
    check_positions(positions)
    if len(positions) != 5:
        raise InputError(f"Burmester points are of five positions, got {len(positions)}")
    s = size(positions)
    found: list[Dyad] = []
    if method == "fast":
        Ds = displacements(positions)
        centre = np.mean([p.point for p in positions], axis=0)
        for guess in centre + 2 * s * np.random.default_rng(seed).standard_normal((seeds, 2)):
            sol = _polish_xy(Ds, (0, 1, 2, 3), (0, 1, 2, 4), guess, s)
            if sol is not None and not _is_pole(Ds, sol, 1e-6 * s):
                _keep(positions, sol, found, s)
        return found
    if method != "exact":
        raise InputError(f"method must be 'exact' or 'fast', got {method!r}")
    for turn in TURNS:
        c, si = math.cos(turn), math.sin(turn)
        turned = [Position((c * p.point[0] - si * p.point[1], si * p.point[0] + c * p.point[1]), p.angle + turn)
                  for p in positions]
        for window in WINDOWS:
            for a1 in _burmester_once(turned, min(window, reach)):
                _keep(positions, (c * a1[0] + si * a1[1], -si * a1[0] + c * a1[1]), found, s)
    return found


def _is_pole(Ds, a1, tol: float) -> bool:
    """Whether two positions of the point ``a1`` coincide (within ``tol``): a pole, not a guiding crank."""
    images = [moved(D, a1) for D in Ds]
    return min(math.dist(p, q) for i, p in enumerate(images) for q in images[:i]) <= tol


def _keep(positions, a1, found: list[Dyad], s: float) -> None:
    """Add the crank through circle point ``a1`` to ``found`` when it guides through every position (to 1e-9)
    and is not there yet."""
    try:
        d = dyad(positions, a1)
    except InputError:
        return
    if d.residual <= 1e-9 * max(s, d.radius) and not any(math.dist(d.a1, e.a1) <= 1e-7 * s for e in found):
        found.append(d)


def _burmester_once(positions: list[Position], reach: float) -> list[np.ndarray]:
    """Candidate circle points of five positions from the resultant in ``x`` (see :func:`burmester_points`)."""
    Ds = displacements(positions)
    s = size(positions)
    pts = np.array([p.point for p in positions], dtype=float)
    cx, cy = pts.mean(axis=0)
    half = reach * s
    first, second = (0, 1, 2, 3), (0, 1, 2, 4)

    def resultant(x):
        f, _, _ = _cubic_in_y(Ds, first, x, s, cy)
        g, _, _ = _cubic_in_y(Ds, second, x, s, cy)
        S = np.zeros((6, 6))
        for i in range(3):
            S[i, i:i + 4] = f
            S[3 + i, i:i + 4] = g
        return np.linalg.det(S)

    nodes = cx + half * np.cos(np.pi * (np.arange(60) + 0.5) / 60)
    vals = np.array([resultant(x) for x in nodes])
    series = C.chebfit((nodes - cx) / half, vals / max(np.abs(vals).max(), 1e-300), 9)
    xs = []
    for r in C.chebroots(series):
        if abs(r.imag) <= 0.02 and abs(r.real) <= 1.0 + 1e-9:
            xs += [cx + half * (r.real + k * abs(r.imag)) for k in ((0,) if abs(r.imag) <= 1e-9 else (-1, 0, 1))]
    out = []
    for x in xs:
        coef, c0, sc = _cubic_in_y(Ds, first, x, s, cy)
        for r in np.roots(coef):
            if abs(r.imag) > 1e-5 * max(1.0, abs(r)):
                continue
            sol = _polish_xy(Ds, first, second, np.array([x, c0 + sc * r.real]), s)
            if sol is not None and not _is_pole(Ds, sol, 1e-6 * s):
                out.append(sol)
    return out


def _polish_xy(Ds, first, second, guess, s):
    scale = max(abs(_concyclic(Ds, first, guess + [s, 0])), 1e-300)
    fn = lambda p: [_concyclic(Ds, first, p) / scale, _concyclic(Ds, second, p) / scale]   # noqa: E731
    with np.errstate(all="ignore"):      # steps to non-finite points (degenerate positions) fail the test below
        sol, info, ok, _ = fsolve(fn, guess, full_output=True, xtol=1e-14)
    if not np.all(np.isfinite(sol)):
        return None
    return sol if ok == 1 or np.max(np.abs(info["fvec"])) < 1e-12 else None
