"""Parameter homotopy tracked in batch: every path a row of one array, stepped together (Sommese & Wampler 2005).

:func:`track` follows the solutions of ``F(z; p) = 0`` (a system with ``residual``, ``solve``, ``param_rate``:
:class:`~domes.design.synthesis.isotropic.DyadSystem`) while ``p`` moves from ``p0`` to ``p1`` along
``p0 + s (p1 − p0)``, ``s = t / (t + γ (1 − t))``: for a random complex ``γ`` (the gamma trick) the arc misses,
with probability one, the parameters where two solutions meet. Each path has its own step in ``t``: a fourth-order
Runge-Kutta predictor on ``dz/dt = −J⁻¹ ∂F/∂p dp/dt``, two Newton corrections, the step accepted when the first
correction (the predictor's error) is within :data:`TRACK_TOL` of the size and the second contracts (or is
at round-off, :data:`ROUNDOFF`); the next
step aims the predictor's error (of order ``h⁵``) at half the tolerance, between half and twice the last step. A path whose coordinates pass :data:`DIVERGED` goes to infinity; one whose
step falls below ``hmin`` fails. :class:`Projective` puts a system on a random projective chart, where a path
passing near infinity stays bounded. :func:`refine` polishes the end points by Newton. :func:`monodromy` fills a
solution set from one solution by loops in parameter space.

>>> import numpy as np
>>> from domes.design.synthesis.isotropic import DyadSystem, plant
>>> sys = DyadSystem(4, pivots_given=True)
>>> z0, p0 = plant(sys, np.random.default_rng(0))
>>> p1 = p0 + 0.3 * np.random.default_rng(1).normal(size=p0.shape)
>>> end = track(sys, z0, p0, p1, gamma=0.6 + 0.8j)
>>> end.status.tolist(), float(np.abs(sys.residual(end.z, p1)).max()) < 1e-12
([1], True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Largest first Newton correction of an accepted step, relative to ``1 + |z|``.
TRACK_TOL = 1e-5
#: A second Newton correction within this of ``1 + |z|`` is at round-off: the step is accepted.
ROUNDOFF = 1e-8
#: A path whose coordinates grow beyond this goes to infinity.
DIVERGED = 1e8
#: Path status codes.
RUNNING, DONE, FAILED, INFINITE = 0, 1, 2, 3


@dataclass
class Tracked:
    """End points ``z`` (N, m), ``status`` (:data:`DONE`, :data:`FAILED`, :data:`INFINITE`), ``steps`` and
    the path variable ``t`` reached (1 when done)."""

    z: np.ndarray
    status: np.ndarray
    steps: np.ndarray
    t: np.ndarray


def norm(v):
    return np.sqrt((v.real ** 2 + v.imag ** 2).sum(axis=1))


def track(system, z0, p0, p1, gamma: complex = 1.0, h0: float = 0.02, hmax: float = 0.1, hmin: float = 1e-9,
          max_rounds: int = 20000, tol: float = TRACK_TOL) -> Tracked:
    """Track the rows of ``z0`` (solutions at ``p0``) to ``p1`` (``p0``, ``p1``: one row or one per path);
    ``tol``: the largest predictor error of an accepted step, relative to ``1 + |z|``."""
    z = np.array(z0, complex)
    N = len(z)
    p0 = np.broadcast_to(np.asarray(p0, complex), (N, system.q))
    dp = np.broadcast_to(np.asarray(p1, complex), (N, system.q)) - p0
    t = np.zeros(N)
    h = np.full(N, h0)
    steps = np.zeros(N, int)
    status = np.full(N, RUNNING)

    def params(i, tt):
        s = tt / (tt + gamma * (1 - tt))
        return p0[i] + s[:, None] * dp[i]

    def velocity(i, zz, tt):
        rate = gamma / (tt + gamma * (1 - tt)) ** 2
        pp = params(i, tt)
        return pp, -system.solve(zz, pp, system.param_rate(zz, pp, dp[i] * rate[:, None]))

    for _ in range(max_rounds):
        i = np.flatnonzero(status == RUNNING)
        if i.size == 0:
            break
        zi, ti = z[i], t[i]
        hh = np.minimum(h[i], 1 - ti)
        with np.errstate(all="ignore"):
            _, k1 = velocity(i, zi, ti)
            _, k2 = velocity(i, zi + 0.5 * hh[:, None] * k1, ti + 0.5 * hh)
            _, k3 = velocity(i, zi + 0.5 * hh[:, None] * k2, ti + 0.5 * hh)
            pn, k4 = velocity(i, zi + hh[:, None] * k3, ti + hh)
            zp = zi + hh[:, None] / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
            d1 = system.solve(zp, pn, system.residual(zp, pn))
            z1 = zp - d1
            d2 = system.solve(z1, pn, system.residual(z1, pn))
            z2 = z1 - d2
            scale = 1 + norm(zi)
            n1, n2 = norm(d1), norm(d2)
        # accepted: the predictor within the tolerance and Newton contracting, or already at round-off (of a
        # solution far out the Jacobian's round-off is large: the second correction within ROUNDOFF is enough)
        ok = (np.isfinite(n1) & np.isfinite(n2) & (n1 < tol * scale)
              & ((n2 < 0.1 * n1) | (n1 < 1e-10 * scale) | (n2 < ROUNDOFF * scale)))
        good, bad = i[ok], i[~ok]
        z[good] = z2[ok]
        t[good] = np.where(hh[ok] >= 1 - ti[ok], 1.0, ti[ok] + hh[ok])
        steps[i] += 1
        # the first correction is the predictor's error, of order h⁵: aim the next step at TRACK_TOL / 2
        with np.errstate(all="ignore"):
            factor = np.nan_to_num(0.8 * (0.5 * tol * scale / n1) ** 0.2, nan=0.5, posinf=2.0)
        h[good] = np.minimum(hh[ok] * np.clip(factor[ok], 0.5, 2.0), hmax)
        h[bad] = hh[~ok] * np.clip(factor[~ok], 0.1, 0.5)
        status[good[t[good] >= 1.0]] = DONE
        status[bad[h[bad] < hmin]] = FAILED
        status[i[(norm(z[i]) > DIVERGED) | ~np.isfinite(norm(z[i]))]] = INFINITE
    status[status == RUNNING] = FAILED
    return Tracked(z, status, steps, t)


class Projective:
    """``system`` on a random affine chart of projective space: unknowns ``W = (Z, w)``, ``z = Z / w``, the
    equations ``w^d F(z)`` (``d``: each one's degree, ``system.degrees``) and the chart ``c · W = 1``, ``c``
    random. A path that passes near infinity in ``z`` stays bounded in ``W`` (Sommese & Wampler 2005, §3.7); the
    Newton step is a dense ``(m + 1)``-square solve, for the few paths the affine tracker loses.

    >>> import numpy as np
    >>> from domes.design.synthesis.isotropic import DyadSystem, plant
    >>> sys = DyadSystem(4, pivots_given=True)
    >>> z, p = plant(sys, np.random.default_rng(0))
    >>> ps = Projective(sys, np.random.default_rng(1))
    >>> W = ps.lift(z)
    >>> float(np.abs(ps.residual(W, p)).max()) < 1e-12, bool(np.allclose(ps.drop(W), z))
    (True, True)
    """

    def __init__(self, system, rng):
        self.system = system
        self.q = system.q
        self.m = system.m + 1
        self.degrees = np.asarray(system.degrees, float)
        c = rng.normal(size=self.m) + 1j * rng.normal(size=self.m)
        self.c = c / np.linalg.norm(c)

    def lift(self, z):
        """The points ``z`` (N, m − 1) on the chart."""
        W = np.concatenate([z, np.ones((len(z), 1))], axis=1)
        return W / (W @ self.c)[:, None]

    def drop(self, W):
        """The affine points ``Z / w``."""
        with np.errstate(all="ignore"):
            return W[:, :-1] / W[:, -1:]

    def residual(self, W, p):
        w = W[:, -1:]
        F = self.system.residual(W[:, :-1] / w, p) * w ** self.degrees
        return np.concatenate([F, (W @ self.c)[:, None] - 1], axis=1)

    def jacobian(self, W, p):
        """``∂/∂Z = w^(d−1) ∂F/∂z``; ``∂/∂w = w^(d−1) (d F − ∂F/∂z · z)`` (Euler); the chart's row ``c``."""
        w = W[:, -1:]
        z = W[:, :-1] / w
        F, J = self.system.residual(z, p), self.system.jacobian(z, p)
        s = w ** (self.degrees - 1)
        H = np.empty((len(W), self.m, self.m), complex)
        H[:, :-1, :-1] = J * s[:, :, None]
        H[:, :-1, -1] = s * (self.degrees * F - np.einsum("nrk,nk->nr", J, z))
        H[:, -1, :] = self.c
        return H

    def solve(self, W, p, rhs):
        return np.linalg.solve(self.jacobian(W, p), rhs[..., None])[..., 0]

    def param_rate(self, W, p, dp):
        w = W[:, -1:]
        rate = self.system.param_rate(W[:, :-1] / w, p, dp) * w ** self.degrees
        return np.concatenate([rate, np.zeros((len(W), 1))], axis=1)


def refine(system, z, p, iterations: int = 8, extended: bool = False):
    """Newton's method at ``p`` from the rows of ``z``, until the correction is at round-off (``1e-14`` of
    ``1 + |z|``) or ``iterations``: ``(z, residual norm, last correction norm)``. ``extended``: the residual and
    the iterate in ``np.clongdouble`` (the step still solved in double: mixed-precision Newton, for a solution far
    out whose double residual is all round-off; no gain where ``longdouble`` is ``double``)."""
    kind = np.clongdouble if extended else complex
    z = np.array(z, kind)
    p = np.broadcast_to(np.asarray(p, complex), (len(z), system.q))
    pk = p.astype(kind)
    last = np.full(len(z), np.inf)
    todo = np.arange(len(z))
    with np.errstate(all="ignore"):
        for _ in range(iterations):
            r = system.residual(z[todo], pk[todo]).astype(complex)
            d = system.solve(z[todo].astype(complex), p[todo], r)
            d[~np.isfinite(d).all(axis=1)] = 0
            z[todo] -= d
            last[todo] = norm(d)
            todo = todo[last[todo] > 1e-14 * (1 + norm(z[todo].astype(complex)))]
            if not len(todo):
                break
        z = z.astype(complex)
        return z, norm(system.residual(z, p)), last


def refine_mp(system, z, p, dps: int = 40, iterations: int = 12):
    """Newton's method on the residual in ``mpmath`` at ``dps`` digits from the row ``z`` (double) at ``p``, the
    step solved in double with the dense Jacobian, made in ``mpmath`` and rounded (mixed precision: each step gains
    about ``16 − log10`` of its condition number digits; the bordered :meth:`solve` squares the condition of a
    block): the iterate
    (an object array of ``mpc``) and the last correction's norm, relative to ``1 + |z|``. For a solution far out
    (pivots 10⁶ sizes away), whose dyad equations cancel terms of order ``|z|²``, so that its double coordinates
    cannot carry it (a coordinate rounded to double moves an equation by ``10⁻¹⁶ |z|²``).

    >>> import numpy as np
    >>> from domes.design.synthesis.isotropic import DyadSystem, plant
    >>> sys = DyadSystem(8)
    >>> z, p = plant(sys, np.random.default_rng(1))
    >>> w, step = refine_mp(sys, z[0] * (1 + 1e-9), p[0])
    >>> step < 1e-30, w.dtype
    (True, dtype('O'))
    """
    import mpmath

    with mpmath.workdps(dps):
        w = mp_array(z)
        pp = mp_array(p)[None]
        last = np.inf
        for _ in range(iterations):
            F = np.array([complex(f) for f in system.residual(w[None], pp)[0]])[None]
            J = system.jacobian(w[None], pp)[0].astype(complex)  # its entries cancel too: made in mpmath
            scale = 1 / np.linalg.norm(J, axis=1)                 # rows equilibrated
            try:
                d = np.linalg.solve(J * scale[:, None], F[0] * scale)
            except np.linalg.LinAlgError:
                break
            w = w - mp_array(d)
            last = float(norm(d[None])[0] / (1 + norm(np.array([complex(c) for c in w])[None])[0]))
            if last < 10.0 ** (8 - dps):
                break
        return w, last


def mp_array(v):
    """A 1-d array of numbers as an object array of ``mpmath.mpc`` (the doubles exactly)."""
    import mpmath

    return np.array([mpmath.mpc(complex(c)) if not isinstance(c, mpmath.mpc) else c for c in np.ravel(v)], object)


def condition(system, z, p):
    """The 2-norm condition number of each row's Jacobian, its columns scaled by ``1 + |z_k|`` and its rows then
    to unit length (a linkage with pivots far out is not thereby ill-conditioned)."""
    p = np.broadcast_to(np.asarray(p, complex), (len(z), system.q))
    with np.errstate(all="ignore"):
        J = system.jacobian(z, p) * (1 + np.abs(z))[:, None, :]
        J /= np.linalg.norm(J, axis=2, keepdims=True)
        return np.linalg.cond(J)


def twins(keys, tol: float = 1e-6) -> list[tuple[int, int]]:
    """The pairs ``(i, j)``, ``i < j``, of rows of ``keys`` (N, k complex) within ``tol`` of each other (each row
    scaled by ``1 + `` its largest entry)."""
    from scipy.spatial import cKDTree

    K = np.asarray(keys)
    if not len(K):
        return []
    X = np.concatenate([K.real, K.imag], axis=1) / (1 + np.abs(K).max(axis=1, keepdims=True))
    return sorted(cKDTree(X).query_pairs(tol))


def distinct(keys, tol: float = 1e-6):
    """Indices of the rows of ``keys`` (N, k complex) that are not within ``tol`` (relative) of an earlier row."""
    keep = np.ones(len(keys), bool)
    for a, b in twins(keys, tol):
        if keep[a]:
            keep[b] = False
    return np.flatnonzero(keep)


def monodromy(system, z, p, key, target: int, rng, loops: int = 3, batch: int = 2000, max_rounds: int = 400,
              progress=None):
    """Solutions at ``p`` (one row) found from those in ``z`` by tracking them around loops ``p → p1 → p2 → p``
    (``p1``, ``p2`` random complex): a loop permutes the solutions, so new ones turn up until all ``target`` are
    known. ``key(z, p)`` names a solution's class (rows equal within 1e-6 are one); one solution per class is
    kept. Stops at ``target`` classes or when every class has been around every loop (then one more loop is
    drawn, up to ``max_rounds`` batches). Returns the class representatives (M, m)."""
    p = np.asarray(p, complex).reshape(1, -1)
    scale = np.abs(p).mean()

    def draw():
        return scale * (rng.normal(size=(2, system.q)) + 1j * rng.normal(size=(2, system.q))) / np.sqrt(2)

    legs = [draw() for _ in range(loops)]
    reps = np.array(z, complex)
    keys = key(reps, p)
    pending = [(r, k) for r in range(len(reps)) for k in range(len(legs))]
    for _ in range(max_rounds):
        if len(reps) >= target:
            break
        if not pending:
            legs.append(draw())
            pending = [(r, len(legs) - 1) for r in range(len(reps))]
        work, pending = pending[:batch], pending[batch:]
        r = np.array([w[0] for w in work])
        loop = np.array([legs[w[1]] for w in work])
        zz, alive = reps[r], np.ones(len(work), bool)
        for a, b in ((p.repeat(len(work), 0), loop[:, 0]), (loop[:, 0], loop[:, 1]), (loop[:, 1], p.repeat(len(work), 0))):
            end = track(system, zz, a, b)
            zz, alive = end.z, alive & (end.status == DONE)
        zz, res, _ = refine(system, zz[alive], p)
        zz = zz[res < 1e-9 * (1 + norm(zz))]
        if len(zz):
            both = np.concatenate([keys, key(zz, p)])
            new = [i - len(keys) for i in distinct(both) if i >= len(keys)]
            if new:
                first = len(reps)
                reps = np.concatenate([reps, zz[new]])
                keys = np.concatenate([keys, both[len(keys):][new]])
                pending += [(i, k) for i in range(first, len(reps)) for k in range(len(legs))]
        if progress:
            progress(len(reps), len(pending), len(legs))
    return reps
