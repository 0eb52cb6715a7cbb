"""Special points of coupler curves: cusps, crunodes (double points), and the focal curve (digest B.4).

A *cusp* is where the coupler point stands still: it is then the coupler's
instant centre, so every point of the moving centrode traces a cusped curve.
A *crunode* is where a circuit crosses itself. :func:`cusps` and
:func:`crossings` find them on a traced :class:`~domes.motion.coupler.curves.Circuit`
and locate them on dense samples of the backend. For a four-bar, the
*focal curve* of seed 002 (6-13)–(6-20) holds every point that can be a
crunode for a given position: the points ``R`` from which the coupler ``BC``
and the frame ``AD`` subtend the same directed angle ``α``. (6-17) and (6-18)
are two circles; this module intersects them through their radical axis,
written with ``sin α`` and ``cos α`` so that ``α = 90°`` needs no ``tan α``,
and with the digest's correction of ``A2`` (``−x_B y_C``).

>>> from domes.motion.coupler.fourbar import closure
>>> B, C = closure(0.4, 1.2, 1.0, 1.4, math.radians(45))
>>> [[round(x, 5) for x in R] for R in focal_points(B, C, 1.4, math.radians(90))]
[[0.18898, 0.47839], [1.30051, 0.3597]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

#: A local minimum of the point's speed below this fraction of the circuit's median speed is a cusp.
CUSP_RATIO = 1e-3
#: Rounds of dense re-sampling that locate a cusp or a crossing (each shrinks the bracket 16-fold).
ROUNDS = 6


@dataclass(frozen=True)
class SpecialPoint:
    """A cusp or a crossing of one circuit: where it is, at which input(s), and how sure.

    ``inputs`` holds one input for a cusp and the two passes for a
    crossing; ``measure`` is the cusp's speed relative to the circuit's
    median speed, or the distance between the two passes at the located
    crossing.
    """

    kind: str
    at: tuple[float, float]
    inputs: tuple[float, ...]
    measure: float


def cusps(curve, circuit, ratio: float = CUSP_RATIO) -> list[SpecialPoint]:
    """The cusps of ``circuit``: local minima of the point's speed (per unit input rate) that reach ~0."""
    speed = np.hypot(*circuit.velocities.T)
    ok = np.isfinite(speed)
    if ok.sum() < 3:
        return []
    median = float(np.median(speed[ok]))
    out = []
    n = speed.size
    for i in range(n):
        a, b = speed[i - 1], speed[(i + 1) % n]
        s = speed[i]
        if not (np.isfinite(s) and s <= a and s <= b and s < 0.25 * median):  # a dip worth locating
            continue
        q, at, smin = _refine_cusp(curve, circuit, i)
        if smin <= ratio * median:
            out.append(SpecialPoint("cusp", at, (q,), smin / median))
    return _unique(out)


def _refine_cusp(curve, circuit, i):
    """Minimise the speed near point ``i`` on dense samples of the backend (finite differences of positions)."""
    xs = circuit.inputs
    lo = xs[i] - math.remainder(xs[i] - xs[i - 1], 2 * math.pi) if i else xs[0] - (_next_input(xs, 0) - xs[0])
    hi = _next_input(xs, i)
    best = (xs[i], tuple(circuit.points[i]), float(np.hypot(*circuit.velocities[i])))
    for _ in range(ROUNDS):
        ts = np.linspace(lo, hi, 17)
        pts = curve.positions(circuit, i, ts)
        if np.any(~np.isfinite(pts)):
            break
        step = np.hypot(*np.diff(pts, axis=0).T) / np.abs(np.diff(ts))
        j = int(np.argmin(step))
        mid = 0.5 * (ts[j] + ts[j + 1])
        best = (float(mid), tuple(0.5 * (pts[j] + pts[j + 1])), float(step[j]))
        lo, hi = ts[max(j - 1, 0)], ts[min(j + 2, 16)]
    return best


def crossings(curve, circuit) -> list[SpecialPoint]:
    """Where ``circuit`` crosses itself (its crunodes), each located by re-sampling both passes."""
    return _unique([_refine_crossing(curve, circuit, i, j, (t, u))
                    for i, j, t, u in polyline_crossings(circuit.points)])


def polyline_crossings(P) -> list[tuple[int, int, float, float]]:
    """Where the closed polyline ``P`` crosses itself: ``(i, j, t, u)`` with ``i < j``, segment ``i`` at its
    fraction ``t`` meeting segment ``j`` at ``u`` (a sweep over the segments sorted by ``x``).

    >>> polyline_crossings(np.array([[0, 0], [1, 1], [1, 0], [0, 1]], dtype=float))
    [(0, 2, 0.5, 0.5)]
    """
    n = P.shape[0]
    seg_a, seg_b = P, np.roll(P, -1, axis=0)
    lo = np.minimum(seg_a, seg_b)
    hi = np.maximum(seg_a, seg_b)
    out = []
    order = np.argsort(lo[:, 0])
    for idx, i in enumerate(order):
        for j in order[idx + 1:]:
            if lo[j, 0] > hi[i, 0]:
                break
            if abs(i - j) <= 1 or {i, j} == {0, n - 1}:
                continue
            if lo[j, 1] > hi[i, 1] or lo[i, 1] > hi[j, 1]:
                continue
            first, second = (i, j) if i < j else (j, i)
            hit = _intersect(seg_a[first], seg_b[first], seg_a[second], seg_b[second])
            if hit is not None:
                out.append((int(first), int(second), float(hit[0]), float(hit[1])))
    return out


def _intersect(p1, p2, p3, p4):
    d1, d2 = p2 - p1, p4 - p3
    den = d1[0] * d2[1] - d1[1] * d2[0]
    if den == 0:
        return None
    r = p3 - p1
    t = (r[0] * d2[1] - r[1] * d2[0]) / den
    u = (r[0] * d1[1] - r[1] * d1[0]) / den
    if 0 <= t < 1 and 0 <= u < 1:
        return t, u
    return None


def _refine_crossing(curve, circuit, i, j, hit):
    """Re-sample the two crossing passes densely and intersect again, a few times."""
    xs = circuit.inputs
    n = xs.size
    spans = [(i, xs[i], _next_input(xs, i)), (j, xs[j], _next_input(xs, j))]
    t, u = hit
    at = tuple(circuit.points[i] + t * (circuit.points[(i + 1) % n] - circuit.points[i]))
    qs = (xs[i] + t * (spans[0][2] - xs[i]), xs[j] + u * (spans[1][2] - xs[j]))
    for _ in range(ROUNDS):
        samples = []
        for k, lo, hi in spans:
            ts = np.linspace(lo, hi, 17)
            samples.append((ts, curve.positions(circuit, k, ts)))
        found = None
        (ta, pa), (tb, pb) = samples
        if np.any(~np.isfinite(pa)) or np.any(~np.isfinite(pb)):
            break
        for a in range(16):
            for b in range(16):
                hit = _intersect(pa[a], pa[a + 1], pb[b], pb[b + 1])
                if hit is not None:
                    found = (a, b, hit)
                    break
            if found:
                break
        if found is None:
            break
        a, b, (t, u) = found
        at = tuple(pa[a] + t * (pa[a + 1] - pa[a]))
        qs = (ta[a] + t * (ta[a + 1] - ta[a]), tb[b] + u * (tb[b + 1] - tb[b]))
        spans = [(spans[0][0], ta[a], ta[a + 1]), (spans[1][0], tb[b], tb[b + 1])]
    gap = float(np.hypot(*(curve.positions(circuit, i, [qs[0]])[0] - curve.positions(circuit, j, [qs[1]])[0])))
    return SpecialPoint("crossing", at, qs, gap)


def _next_input(xs, i):
    """The input at the end of segment ``i`` (the closing segment ends at the first point, a turn on or back)."""
    if i + 1 < xs.size:
        return xs[i + 1]
    return xs[i] + math.remainder(xs[0] - xs[i], 2 * math.pi)


def _unique(points, tol=1e-6):
    out = []
    for p in points:
        if not any(p.kind == o.kind and math.dist(p.at, o.at) <= tol * max(1.0, math.hypot(*o.at)) for o in out):
            out.append(p)
    return out


def focal_points(B, C, d: float, alpha: float):
    """The points ``R`` that see the coupler ``BC`` and the frame ``AD`` under the directed angle ``alpha``.

    (6-17) and (6-18) multiplied by ``cos α``: the circles
    ``sin α (x² + y²) + P1 y + P3 x + P2 = 0`` and
    ``sin α (x² + y²) − d cos α · y − d sin α · x = 0``, intersected with their
    radical axis. Returns 0, 1 or 2 points (none for ``α`` a multiple of 180°).
    """
    s, c = math.sin(alpha), math.cos(alpha)
    if abs(s) < 1e-12:
        return []
    xB, yB = B
    xC, yC = C
    P1 = c * (xB - xC) - s * (yB + yC)
    P2 = c * (xC * yB - xB * yC) + s * (yB * yC + xB * xC)   # A2 with the digest's correction: −x_B y_C
    P3 = c * (yC - yB) - s * (xB + xC)
    # Radical axis: (P1 + c d) y + (P3 + s d) x + P2 = 0; circle (6-18): x² + y² − d x − (d c / s) y = 0.
    ka, kb, kc = P3 + s * d, P1 + c * d, P2
    cx, cy = d / 2, d * c / (2 * s)
    r2 = cx * cx + cy * cy
    norm = math.hypot(ka, kb)
    if norm == 0:
        return []
    dist = (ka * cx + kb * cy + kc) / norm
    if dist * dist > r2:
        return []
    foot = (cx - ka * dist / norm, cy - kb * dist / norm)
    half = math.sqrt(max(r2 - dist * dist, 0.0))
    tx, ty = -kb / norm, ka / norm
    pts = [(foot[0] - half * tx, foot[1] - half * ty), (foot[0] + half * tx, foot[1] + half * ty)]
    return sorted(pts) if half > 0 else pts[:1]


def focal_curve(B, C, d: float, samples: int = 360):
    """The focal curve for one position: the focal points for ``α`` over (0°, 180°), as ``(α, x, y)`` rows."""
    rows = []
    for k in range(1, samples):
        alpha = math.pi * k / samples
        for R in focal_points(B, C, d, alpha):
            rows.append((alpha, R[0], R[1]))
    return np.array(rows)
