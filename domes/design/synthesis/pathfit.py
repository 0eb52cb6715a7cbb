"""Path generation with any free choices of Table 2-1, with prescribed input angles, or through more points
than an exact solution allows (least squares) (seed 002 §2-3, digest A.3.5).

The unknowns are the pivots ``a0, a1, b1, b0`` (position 1) and the
coupler rotations ``θ1j``; the equations (2-113) say that both cranks keep
their lengths: ``|D1j a1 − a0| = |a1 − a0|`` and the same for ``b``. With
the crank's rotations ``φ1j`` prescribed (timing), the crank pin's position
is known both ways, ``D1j a1 = Rot(a0, φ1j) a1``: two equations instead of
one. :mod:`~domes.design.synthesis.counts` counts them; the designer fixes
as many of the pivots' coordinates (``a0x``, ``a0y``, ... or whole pivots)
as the count leaves free. Fewer points than that is refused; more is a
least-squares problem, and each solution then reports its distance from
every point along its own coupler curve (the branch through point 1).

The roots come from many random starts polished together (a damped
Gauss-Newton, Levenberg-Marquardt, on arrays of starts with the analytic
Jacobian); a root that no start reaches is missed, so the
count is of roots *found*. (Example 5's form, five points with both fixed
pivots, is searched exhaustively by :func:`~domes.design.synthesis.path.five_points`.)

>>> P = [(1.0, 1.0), (2.0, 0.5), (3.0, 1.5), (2.0, 2.0)]
>>> sols = fit(P, {"a0x": 2.1, "a0y": 0.6, "b0x": 1.5, "a1x": 0.6, "a1y": -1.1}, starts=64)
>>> all(s.residual < 1e-9 for s in sols) and len(sols) > 0
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from domes.design.synthesis.counts import PROBLEMS
from domes.errors import InputError
from domes.results import Progress, Ticker

#: Least-squares minima with a pivot farther than this many times the points' size from their centre are left out
#: (exact roots are all kept: :mod:`~domes.design.synthesis.verify` groups the degenerate ones).
REACH = 10.0

#: Least-squares minima with a link shorter than this fraction of the points' size are degenerate, left out.
SHORTEST = 0.01

#: Points within this fraction of their size from one line are "nearly in line" (a note says so).
NEARLY = 1e-3

#: Evaluations of the polish of one least-squares minimum: the minima of a drawn path settle in about a hundred;
#: one still moving after this many runs off with its pivots (points nearly in line) and is left out by REACH.
POLISH = 400

#: A least-squares minimum this near every point (RMS, relative to the points' size) meets them exactly.
EXACT = 1e-12

#: The pivot coordinates, in the order of the unknowns.
PIVOTS = ("a0x", "a0y", "a1x", "a1y", "b1x", "b1y", "b0x", "b0y")


@dataclass(frozen=True)
class PathFit:
    """A four-bar for the points: pivots (position 1), coupler rotations ``θ1j`` (rad), the largest residual of
    the equations, and (least squares) the distance of every point from the coupler curve."""

    a0: tuple[float, float]
    a1: tuple[float, float]
    b1: tuple[float, float]
    b0: tuple[float, float]
    rotations: tuple[float, ...]
    residual: float
    distances: tuple[float, ...] = ()


def check_points(points) -> None:
    """An InputError naming the points when they cannot be a path (coincident, not finite)."""
    P = np.asarray(points, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or not np.all(np.isfinite(P)):
        raise InputError(f"path points must be finite pairs (x, y), got an array of shape {P.shape}")
    size = float(np.ptp(P, axis=0).max())
    for j in range(len(P)):
        for k in range(j):
            if math.dist(P[j], P[k]) <= 1e-9 * max(size, 1e-300):
                raise InputError(f"points {k + 1} and {j + 1} coincide")


#: A four-bar's coupler curve is a tricircular sextic: a line meets it in at most this many points.
ON_ONE_LINE = 6


def on_one_line(points) -> tuple[int, ...]:
    """The numbers (from 1) of the most points on one line, to 1e-9 of the points' size; () when no three are."""
    P = np.asarray(points, dtype=float)
    size = float(max(np.ptp(P, axis=0).max(), 1e-300))
    best: tuple[int, ...] = ()
    for i in range(len(P)):
        for j in range(i + 1, len(P)):
            d = P[j] - P[i]
            off = np.abs(d[0] * (P[:, 1] - P[i, 1]) - d[1] * (P[:, 0] - P[i, 0])) / max(float(np.hypot(*d)), 1e-300)
            on = tuple(int(k) + 1 for k in np.flatnonzero(off <= 1e-9 * size))
            if len(on) > len(best):
                best = on
    return best if len(best) >= 3 else ()


def line_deviation(points) -> float:
    """The largest distance of the points from their best line (total least squares)."""
    P = np.asarray(points, dtype=float)
    Q = P - P.mean(axis=0)
    normal = np.linalg.svd(Q, full_matrices=True)[2][-1]
    return float(np.max(np.abs(Q @ normal)))


def on_one_circle(points, within: float = NEARLY):
    """``(centre, radius, largest distance from it)`` when the points lie within ``within`` of their size from one
    circle (of radius up to 100 sizes: flatter is a line), else None."""
    P = np.asarray(points, dtype=float)
    size = float(max(np.ptp(P, axis=0).max(), 1e-300))
    M = np.c_[2 * P, np.ones(len(P))]
    sol, *_ = np.linalg.lstsq(M, np.sum(P * P, axis=1), rcond=None)
    centre = sol[:2]
    radius2 = sol[2] + centre @ centre
    if not radius2 > 0 or radius2 > (100 * size) ** 2:
        return None
    radius = math.sqrt(radius2)
    off = float(np.max(np.abs(np.linalg.norm(P - centre, axis=1) - radius)))
    if off > within * size:
        return None
    return (float(centre[0]), float(centre[1])), radius, off


def problem_counts(n: int, crank=None) -> tuple[int, int, int]:
    """``(equations, unknowns, free choices)`` of ``n`` path points (Table 2-1; with prescribed input angles)."""
    name = "planar path, input angles prescribed" if crank is not None else "planar path"
    return PROBLEMS[name].counts(n)


def check_given(n: int, given: dict, crank=None) -> str:
    """``"exact"`` or ``"least squares"``; an InputError when the points leave choices unmade."""
    unknown = sorted(set(given) - set(PIVOTS))
    if unknown:
        raise InputError(f"given: {unknown} are not pivot coordinates; use {', '.join(PIVOTS)} (or a0, a1, b0, b1)")
    eqs, unknowns, free = problem_counts(n, crank)
    if len(given) < free:
        raise InputError(f"{n} path points{' with input angles' if crank is not None else ''} leave {free} free "
                         f"choices ({eqs} equations in {unknowns} unknowns, Table 2-1); {len(given)} given: fix "
                         f"{free - len(given)} more pivot coordinate(s)")
    return "exact" if len(given) == free else "least squares"


def _residuals(X, P, given, crank, scale):
    """Residuals ``(S, m)`` and their Jacobian ``(S, m, k)`` of ``S`` unknown vectors ``X`` (``(S, k)``) at once."""
    S, n = X.shape[0], len(P)
    cols, k = {}, 0
    full = np.empty((S, 8))
    for i, name in enumerate(PIVOTS):
        if name in given:
            full[:, i] = given[name]
        else:
            full[:, i] = X[:, k]
            cols[i] = k
            k += 1
    th = X[:, k:]
    a0, a1, b1, b0 = (full[:, 2 * i:2 * i + 2] for i in range(4))
    rows, jac = [], []
    da1, db1 = a1 - a0, b1 - b0
    ra, rb = np.linalg.norm(da1, axis=1), np.linalg.norm(db1, axis=1)
    q_a, q_b = a1 - P[0], b1 - P[0]

    def row(grad_pivots, grad_theta, j):
        """One Jacobian row from gradients by pivot (name -> (S, 2)) and by θ1j (S,)."""
        J = np.zeros((S, X.shape[1]))
        for p, g in grad_pivots.items():
            base = 2 * ("a0", "a1", "b1", "b0").index(p)
            for c in (0, 1):
                if base + c in cols:
                    J[:, cols[base + c]] += g[:, c]
        J[:, k + j - 1] += grad_theta
        return J

    for j in range(1, n):
        c, s = np.cos(th[:, j - 1]), np.sin(th[:, j - 1])
        rot = lambda v: np.c_[c * v[:, 0] - s * v[:, 1], s * v[:, 0] + c * v[:, 1]]           # noqa: E731
        drot = lambda v: np.c_[-s * v[:, 0] - c * v[:, 1], c * v[:, 0] - s * v[:, 1]]         # noqa: E731
        rotT = lambda v: np.c_[c * v[:, 0] + s * v[:, 1], -s * v[:, 0] + c * v[:, 1]]         # noqa: E731
        aj, bj = rot(q_a) + P[j], rot(q_b) + P[j]
        if crank is None:
            ea = aj - a0
            la = np.linalg.norm(ea, axis=1)
            ua, u1 = ea / la[:, None], da1 / ra[:, None]
            rows.append(la - ra)
            jac.append(row({"a1": rotT(ua) - u1, "a0": -ua + u1}, (ua * drot(q_a)).sum(axis=1), j))
        else:
            cf, sf = math.cos(crank[j - 1]), math.sin(crank[j - 1])
            Rf = np.array([[cf, -sf], [sf, cf]])
            e = aj - (da1 @ Rf.T + a0)
            for comp in (0, 1):
                rows.append(e[:, comp])
                Rj = np.stack([np.c_[c, -s], np.c_[s, c]], axis=1)           # (S, 2, 2)
                g_a1 = Rj[:, comp, :] - Rf[comp]
                g_a0 = Rf[comp] - np.eye(2)[comp]
                jac.append(row({"a1": g_a1, "a0": np.broadcast_to(g_a0, (S, 2))}, drot(q_a)[:, comp], j))
        eb = bj - b0
        lb = np.linalg.norm(eb, axis=1)
        ub, v1 = eb / lb[:, None], db1 / rb[:, None]
        rows.append(lb - rb)
        jac.append(row({"b1": rotT(ub) - v1, "b0": -ub + v1}, (ub * drot(q_b)).sum(axis=1), j))
    return np.stack(rows, axis=1) / scale, np.stack(jac, axis=1) / scale


def _levenberg_marquardt(X, P, given, crank, scale, iterations: int = 200, clock: Ticker | None = None):
    """Damped Gauss-Newton from every row of ``X`` at once; the polished rows and their residuals. Rows that
    have converged or stalled (the damping grown past 1e10, or a singular step) drop out of the batch."""
    X = X.copy()
    clock = clock or Ticker(None)
    with np.errstate(all="ignore"):
        r, J = _residuals(X, P, given, crank, scale)
        cost = np.sum(r * r, axis=1)
        lam = np.full(X.shape[0], 1e-3)
        active = np.flatnonzero(np.isfinite(cost))
        eye = np.eye(X.shape[1])
        for it in range(iterations):
            if not active.size:
                break
            clock.tick(lambda: f"path points: Gauss-Newton step {it + 1} (at most {iterations}), {active.size} of "
                       f"{X.shape[0]} starts still moving")
            Ja, ra = J[active], r[active]
            JT = np.transpose(Ja, (0, 2, 1))
            A = JT @ Ja
            g = (JT @ ra[:, :, None])[:, :, 0]
            D = np.einsum("sii->si", A) + 1e-30
            step = _damped_steps(A + lam[active, None, None] * np.einsum("si,ij->sij", D, eye), g)
            singular = ~np.all(np.isfinite(step), axis=1)
            if singular.any():                 # a singular normal matrix: the start has stalled, it drops out
                active, step = active[~singular], step[~singular]
            Xt = X[active] + step
            rt, Jt = _residuals(Xt, P, given, crank, scale)
            ct = np.sum(rt * rt, axis=1)
            better = np.isfinite(ct) & (ct < cost[active])
            rows = active[better]
            X[rows], r[rows], J[rows], cost[rows] = Xt[better], rt[better], Jt[better], ct[better]
            lam[active] = np.clip(np.where(better, lam[active] / 3, lam[active] * 4), 1e-12, 1e12)
            active = active[(lam[active] < 1e10) & (cost[active] > 1e-30)]
    return X, r


def _damped_steps(M, g):
    """``-M⁻¹ g`` for a stack of matrices; a row whose matrix is singular gets NaN (one singular matrix does not
    stop the batch)."""
    try:
        return -np.linalg.solve(M, g[:, :, None])[:, :, 0]
    except np.linalg.LinAlgError:
        step = np.full(g.shape, np.nan)
        for i in range(len(M)):
            try:
                step[i] = -np.linalg.solve(M[i], g[i])
            except np.linalg.LinAlgError:
                pass
        return step


def fit(points, given: dict, crank=None, starts: int = 256, seed: int = 0, keep: int = 10,
        least_squares_only: bool = False, progress: Progress | None = None, left_out: dict | None = None,
        seeded: list[PathFit] | None = None, info: dict | None = None) -> list[PathFit]:
    """Four-bars through ``points`` with the pivot coordinates ``given``: every distinct root found (exact, the
    degenerate ones too), or the ``keep`` best distinct local minima (least squares), from ``starts`` random starts.

    ``crank``: the crank's rotations ``φ1j`` (rad) from point 1 to each later point (prescribed input angles).
    ``least_squares_only``: the best minima even when the count makes the problem exact (no root was found).
    ``left_out``: a dictionary that counts the least-squares minima left out as degenerate, by reason.
    ``seeded``: linkages to start from besides the random starts (:func:`seed_from`; their given coordinates are
    replaced by the task's); by least squares, when one of them meets every point (RMS within :data:`EXACT` of the
    size) the random starts are left out, and ``info["random starts"]`` says how many were used.
    """
    check_points(points)
    P = np.asarray(points, dtype=float)
    n = len(P)
    if crank is not None and len(crank) != n - 1:
        raise InputError(f"prescribed input angles: one crank rotation per point after the first ({n - 1}), got "
                         f"{len(crank)}")
    kind = "least squares" if least_squares_only else check_given(n, given, crank)
    clock = Ticker(progress)
    size = float(max(np.ptp(P, axis=0).max(), 1e-300))
    centre = P.mean(axis=0)
    free = [p for p in PIVOTS if p not in given]
    if info is not None:
        info["random starts"] = starts
    rng = np.random.default_rng(seed)
    X0 = np.hstack([centre[[0 if p.endswith("x") else 1 for p in free]] + 2 * size * rng.uniform(-1, 1, (starts, len(free))),
                    rng.uniform(-math.pi, math.pi, (starts, n - 1))])
    if seeded:
        rows = [[getattr(f, p[:2])[p[2] == "y"] for p in free] + list(f.rotations) for f in seeded
                if len(f.rotations) == n - 1]
        if rows and kind == "least squares":
            # seeds that reach the points exactly make the random starts pointless: no minimum is lower
            Xs, rs = _levenberg_marquardt(np.asarray(rows, dtype=float), P, given, crank, size, clock=clock)
            if any(f.residual <= EXACT * size for _, f in _collect(Xs, rs, P, given, kind, size, keep)):
                X0 = Xs
                if info is not None:
                    info["random starts"] = 0
            else:
                X0 = np.vstack([Xs, X0])
        elif rows:
            X0 = np.vstack([np.asarray(rows, dtype=float), X0])
    X, r = _levenberg_marquardt(X0, P, given, crank, size, clock=clock)
    found = _collect(X, r, P, given, kind, size, keep)
    if kind == "least squares":          # the minima polished (the batch stops at a cap), ranked again
        idx = [i for i, _ in found]
        last: dict = {"x": None, "calls": 0}

        def both(x):
            """Residuals and Jacobian at ``x``, kept for the next call (least_squares asks both at one point)."""
            if last["x"] is None or not np.array_equal(last["x"], x):
                last["calls"] += 1
                clock.tick(lambda: f"path points: polishing least-squares minimum {k + 1} of {len(idx)}, "
                           f"{last['calls']} evaluations")
                rr, jj = _residuals(x[None], P, given, crank, size)
                last.update(x=np.array(x), value=(rr[0], jj[0]))
            return last["value"]

        fun = lambda x: both(x)[0]            # noqa: E731
        jac = lambda x: both(x)[1]            # noqa: E731
        for k, i in enumerate(idx):
            last["calls"] = 0
            with np.errstate(all="ignore"):
                # Levenberg-Marquardt needs as many residuals as unknowns; fewer given than Table 2-1's count
                # (least_squares_only on an underdetermined task) takes the trust region instead
                X[i] = least_squares(fun, X[i], jac=jac, method="lm" if len(fun(X[i])) >= X.shape[1] else "trf",
                                     xtol=1e-15, ftol=1e-15, gtol=1e-15,
                                     max_nfev=POLISH).x
            r[i] = fun(X[i])
        found = _collect(X[idx], r[idx], P, given, kind, size, keep, left_out)
    return [f for _, f in found]


def seed_from(points, linkage) -> PathFit | None:
    """A start for :func:`fit` from a four-bar ``(a0, a1, b1, b0, point)`` drawn in any pose (points in the
    plane): its moving pivots where its coupler point is nearest point 1, and the coupler's rotation from there to
    where it is nearest each later point (either assembly mode; 2,880 crank angles, then twice 400 around the
    nearest); None when its loop never closes. ``residual`` is the largest of those distances.

    >>> P = [(1.0, 1.0), (1.2, 1.6), (0.5, 2.0)]
    >>> s = seed_from(P, ((0, 0), (1, 0), (3, 1), (3, 0), (1, 1)))
    >>> s.a0, s.a1
    ((0.0, 0.0), (1.0, 0.0))
    """
    a0, a1, b1, b0, p = (np.asarray(v, dtype=float) for v in linkage)
    pts = np.asarray(points, dtype=float)
    a, b, c = np.linalg.norm(a1 - a0), np.linalg.norm(b1 - a1), np.linalg.norm(b1 - b0)
    if not min(a, b, c) > 0:
        return None
    ex = (b1 - a1) / b
    rel = p - a1
    pu, pv = rel @ ex, ex[0] * rel[1] - ex[1] * rel[0]          # the coupler point along a1 -> b1 and across

    def pose(th, sign):
        """Crank pins, rocker pins, coupler points and coupler angles at crank angles ``th`` on mode ``sign``."""
        A = a0 + a * np.stack([np.cos(th), np.sin(th)], axis=-1)
        e = b0 - A
        r = np.linalg.norm(e, axis=-1)[..., None]
        with np.errstate(all="ignore"):
            along = (b * b + r * r - c * c) / (2 * r)
            u = e / r
            B = A + along * u + sign * np.sqrt(b * b - along * along) * np.stack([-u[..., 1], u[..., 0]], axis=-1)
        f = (B - A) / b
        Q = A + pu * f + pv * np.stack([-f[..., 1], f[..., 0]], axis=-1)
        return A, B, Q, np.arctan2(f[..., 1], f[..., 0])

    step = 2 * math.pi / 2880
    grid = np.arange(2880) * step - math.pi
    best = []
    for sign in (1.0, -1.0):
        th = np.broadcast_to(grid, (len(pts), grid.size))
        for width in (step, step / 100):                   # the nearest sample, then twice 400 around it
            Q = pose(th, sign)[2]
            d = np.linalg.norm(Q - pts[:, None, :], axis=2)
            d = np.where(np.isfinite(d), d, np.inf)
            k = np.argmin(d, axis=1)
            centre = th[np.arange(len(pts)), k]
            th = centre[:, None] + np.linspace(-2 * width, 2 * width, 401)[None, :]
        Q = pose(th, sign)[2]
        d = np.linalg.norm(Q - pts[:, None, :], axis=2)
        d = np.where(np.isfinite(d), d, np.inf)
        k = np.argmin(d, axis=1)
        best.append((d[np.arange(len(pts)), k], th[np.arange(len(pts)), k]))
    mode = np.where(best[0][0] <= best[1][0], 1.0, -1.0)     # each point on the mode it is nearest (the equations
    dist = np.minimum(best[0][0], best[1][0])               # do not fix one)
    angle = np.where(mode > 0, best[0][1], best[1][1])
    worst = float(np.max(dist))
    if not math.isfinite(worst):
        return None
    A, B, _, psi = pose(angle, mode[:, None])
    turns = tuple(float(math.remainder(psi[j] - psi[0], 2 * math.pi)) for j in range(1, len(pts)))
    return PathFit(tuple(map(float, a0)), tuple(map(float, A[0])), tuple(map(float, B[0])), tuple(map(float, b0)),
                   turns, worst)


def _collect(X, r, P, given, kind, size, keep, left_out=None):
    """``(row, PathFit)`` of the distinct rows of ``X``, best first: every root (exact), or the distinct minima
    that are four-bars (least squares; the others counted in ``left_out`` by reason)."""
    centre = P.mean(axis=0)
    res = np.max(np.abs(r), axis=1) * size
    if kind == "least squares":
        res = np.sqrt(np.mean(r * r, axis=1)) * size
    order = np.argsort(np.where(np.isfinite(res), res, np.inf))
    found: list[tuple[int, PathFit]] = []
    pivots = np.empty((0, 8))                 # the pivots of the rows kept, to find a repeat at once
    skipped: dict = {}
    for i in order:
        if not np.isfinite(res[i]) or (kind == "exact" and res[i] > 1e-9 * size):
            continue
        full = [given[name] if name in given else None for name in PIVOTS]
        it = iter(X[i])
        full = [v if v is not None else float(next(it)) for v in full]
        th = list(it)
        cand = PathFit(*(tuple(full[2 * k:2 * k + 2]) for k in range(4)),
                       tuple(float(math.remainder(t, 2 * math.pi)) for t in th), float(res[i]))
        if kind == "least squares":
            shortest = min(math.dist(cand.a0, cand.a1), math.dist(cand.b0, cand.b1), math.dist(cand.a1, cand.b1),
                           math.dist(cand.a0, cand.b0))
            why = ("with a link shorter than 1% of the points' size" if shortest <= SHORTEST * size else
                   "with pivots running off (beyond 10 times the points' size)"
                   if max(math.dist(q, centre) for q in (cand.a0, cand.a1, cand.b1, cand.b0)) > REACH * size else
                   "meeting the points on both assembly modes" if _mixed_modes(cand, P) else None)
            if why is not None:
                skipped[why] = skipped.get(why, 0) + 1
                continue
        flat = np.concatenate([cand.a0, cand.a1, cand.b1, cand.b0])
        if not np.any(np.sum(np.linalg.norm((pivots - flat).reshape(-1, 4, 2), axis=2), axis=1) <= 1e-6 * size):
            found.append((int(i), cand))
            pivots = np.vstack([pivots, flat])
        if kind == "least squares" and len(found) >= keep:
            break
    if left_out is not None:
        left_out.clear()
        left_out.update(skipped)
    return found


def _mixed_modes(f: PathFit, P) -> bool:
    """Whether the linkage meets the points on both assembly modes (the side of ``b_j`` from the line ``a_j b0``)."""
    signs = set()
    for j, th in enumerate((0.0,) + f.rotations):
        c, s = math.cos(th), math.sin(th)
        R = np.array([[c, -s], [s, c]])
        aj, bj = R @ np.subtract(f.a1, P[0]) + P[j], R @ np.subtract(f.b1, P[0]) + P[j]
        u, v = bj - aj, np.subtract(f.b0, bj)
        signs.add(np.sign(u[0] * v[1] - u[1] * v[0]))
    return len(signs - {0.0}) > 1


def crank_rocker_path(rng, n: int):
    """``n`` points of the coupler curve of a random crank-rocker (crank 1, frame about 3), evenly spaced in
    crank angle, with the linkage that makes them: ``(points, a0, b0, crank pins, rocker pins, crank angles)``;
    test and benchmark data for path generation (the generating linkage is a known root)."""
    a0 = rng.uniform(-1, 1, 2)
    b0 = a0 + np.array([3.0, 0.0]) + rng.uniform(-0.5, 0.5, 2)
    b, c = rng.uniform(2.8, 3.5), rng.uniform(2.5, 3.2)
    body = rng.uniform(-1.5, 1.5, 2)
    ths = np.linspace(0, 2 * np.pi, n, endpoint=False) + rng.uniform(0, 0.3)
    P, A, B = [], [], []
    for t in ths:
        a = a0 + np.array([np.cos(t), np.sin(t)])
        d = np.linalg.norm(b0 - a)
        ang = math.atan2(*(b0 - a)[::-1]) + math.acos((d * d + b * b - c * c) / (2 * d * b))
        P.append(a + np.array([[math.cos(ang), -math.sin(ang)], [math.sin(ang), math.cos(ang)]]) @ body)
        A.append(a)
        B.append(a + b * np.array([math.cos(ang), math.sin(ang)]))
    return np.array(P), a0, b0, A, B, ths
