"""The dyad equations of four-bar path synthesis in isotropic coordinates (Wampler, Morgan & Sommese 1992).

A point ``(u, v)`` of the plane is the pair ``z = u + iv``, ``z̄ = u − iv``; a rotation is ``θ`` with
``θ θ̄ = 1``. The coupler point is at ``δ_j`` in position ``j`` (``δ_0 = 0``: positions are measured from the
first point); the moving pivot of a dyad is at ``δ_j + θ_j x`` (``x``: the pivot seen from the coupler point in
position 0) and its fixed pivot at ``a``. The dyad keeps its length,
``(δ_j + θ_j x − a)(δ̄_j + θ̄_j x̄ − ā) = (x − a)(x̄ − ā)``, that is

    E = θ_j x (δ̄_j − ā) + θ̄_j x̄ (δ_j − a) + δ_j δ̄_j − δ_j ā − a δ̄_j + x ā + a x̄ = 0,

one equation for each dyad and position, and ``θ_j θ̄_j = 1``. With ``z̄`` an unknown of its own the
equations are polynomial (a real solution has ``z̄ = conj(z)``). :class:`DyadSystem` holds them for ``n``
displacements, the linkage's eight isotropic coordinates ``x, x̄, a, ā, y, ȳ, b, b̄`` unknown (nine points:
``n = 8``) or the fixed pivots given (five points and two pivots, Morgan & Wampler 1990: ``n = 4``). Its
Newton step eliminates each position's ``θ_j, θ̄_j`` from its three equations (a bordered solve), so a step
costs one ``nu × nu`` solve per path, batched over paths.

>>> import numpy as np
>>> sys = DyadSystem(8)
>>> z, p = plant(sys, np.random.default_rng(1))
>>> float(np.abs(sys.residual(z, p)).max()) < 1e-12
True
"""

from __future__ import annotations

import numpy as np

#: The linkage's isotropic coordinates, in the order they are unknowns of the nine-point system.
LINKAGE = ("x", "xb", "a", "ab", "y", "yb", "b", "bb")


def dyad(x, xb, a, ab, th, thb, d, db):
    """The dyad equation ``E`` (module docstring), broadcast over arrays."""
    return th * x * (db - ab) + thb * xb * (d - a) + d * db - d * ab - a * db + x * ab + a * xb


def dyad_partials(x, xb, a, ab, th, thb, d, db):
    """``∂E`` with respect to ``x, x̄, a, ā, θ, θ̄, δ, δ̄``."""
    return (th * (db - ab) + ab, thb * (d - a) + a, xb - thb * xb - db, x - th * x - d,
            x * (db - ab), xb * (d - a), thb * xb + db - ab, th * x + d - a)


class DyadSystem:
    """The equations of ``n`` displacements; unknowns ``z = (linkage, θ_1..θ_n, θ̄_1..θ̄_n)``, parameters
    ``p = (δ_1..δ_n, δ̄_1..δ̄_n)`` followed, when ``pivots_given``, by ``a, ā, b, b̄``. Arrays carry one row
    per path. Equations: the first dyad at every position, the second, then ``θ_j θ̄_j − 1``."""

    def __init__(self, n: int, pivots_given: bool = False):
        self.n = n
        self.pivots_given = pivots_given
        self.nu = 4 if pivots_given else 8
        if self.nu != n:
            raise ValueError(f"{n} displacements with {'given' if pivots_given else 'free'} pivots is not square")
        self.m = self.nu + 2 * n
        self.q = 2 * n + (4 if pivots_given else 0)
        #: Each equation's degree in the unknowns (``θ x ā`` is of degree 3; 2 when the pivots are given).
        self.degrees = np.array([2 if pivots_given else 3] * (2 * n) + [2] * n)

    def linkage(self, z, p):
        """The eight isotropic coordinates ``x, x̄, a, ā, y, ȳ, b, b̄`` as columns ``(N, 1)``."""
        if self.pivots_given:
            x, xb, y, yb = (z[:, k:k + 1] for k in range(4))
            a, ab, b, bb = (p[:, 2 * self.n + k:2 * self.n + k + 1] for k in range(4))
            return x, xb, a, ab, y, yb, b, bb
        return tuple(z[:, k:k + 1] for k in range(8))

    def _split(self, z, p):
        n, nu = self.n, self.nu
        return (self.linkage(z, p), z[:, nu:nu + n], z[:, nu + n:], p[:, :n], p[:, n:2 * n])

    def residual(self, z, p):
        """``F(z; p)``, shape ``(N, m)``."""
        (x, xb, a, ab, y, yb, b, bb), th, thb, d, db = self._split(z, p)
        return np.concatenate([dyad(x, xb, a, ab, th, thb, d, db), dyad(y, yb, b, bb, th, thb, d, db),
                               th * thb - 1], axis=1)

    def point_error(self, z, p):
        """Each row's residual as a distance: a dyad equation's residual over twice the dyad's length (how far
        the length is off), and ``|θ θ̄ − 1|`` times the coupler's arms; the largest, in the points' units. Also
        on object arrays of ``mpmath.mpc`` (extended precision)."""
        (x, xb, a, ab, y, yb, b, bb), th, thb, d, db = self._split(z, p)
        with np.errstate(all="ignore"):
            left = np.abs(dyad(x, xb, a, ab, th, thb, d, db)) / (2 * np.abs((x - a) * (xb - ab)) ** 0.5)
            right = np.abs(dyad(y, yb, b, bb, th, thb, d, db)) / (2 * np.abs((y - b) * (yb - bb)) ** 0.5)
            turn = np.abs(th * thb - 1) * np.maximum(np.abs(x) + np.abs(xb), np.abs(y) + np.abs(yb)) / 2
        return np.max(np.concatenate([left, right, turn], axis=1), axis=1)

    def _blocks(self, z, p):
        """Per position ``j``: ``U`` (N, n, 3, nu), the rows' derivatives in the linkage unknowns, and ``V``
        (N, n, 3, 2) in ``θ_j, θ̄_j`` (object arrays for object ``z``: extended precision)."""
        (x, xb, a, ab, y, yb, b, bb), th, thb, d, db = self._split(z, p)
        N, n = th.shape
        kind = object if z.dtype == object else complex
        L = dyad_partials(x, xb, a, ab, th, thb, d, db)
        R = dyad_partials(y, yb, b, bb, th, thb, d, db)
        U = np.zeros((N, n, 3, self.nu), kind)
        k = 2 if self.pivots_given else 4
        for c in range(k):
            U[:, :, 0, c] = L[c]
            U[:, :, 1, k + c] = R[c]
        V = np.empty((N, n, 3, 2), kind)
        V[:, :, 0, 0], V[:, :, 0, 1] = L[4], L[5]
        V[:, :, 1, 0], V[:, :, 1, 1] = R[4], R[5]
        V[:, :, 2, 0], V[:, :, 2, 1] = thb, th
        return U, V, L, R

    def solve(self, z, p, rhs):
        """``Δ`` with ``J(z; p) Δ = rhs`` (N, m): each position's ``θ`` eliminated by the left null vector ``w``
        of its ``3 × 2`` block, the linkage step from the ``nu × nu`` system left, then ``θ`` by least squares."""
        n, k = self.n, self.nu // 2
        (x, xb, a, ab, y, yb, b, bb), th, thb, d, db = self._split(z, p)
        L = dyad_partials(x, xb, a, ab, th, thb, d, db)
        R = dyad_partials(y, yb, b, bb, th, thb, d, db)
        r0, r1, r2 = rhs[:, :n], rhs[:, n:2 * n], rhs[:, 2 * n:]
        v0, v1, v2 = (L[4], L[5]), (R[4], R[5]), (thb, th)       # the rows of the 3 × 2 block
        w0 = v1[0] * v2[1] - v1[1] * v2[0]
        w1 = v2[0] * v0[1] - v2[1] * v0[0]
        w2 = v0[0] * v1[1] - v0[1] * v1[0]
        size = np.sqrt(abs(w0) ** 2 + abs(w1) ** 2 + abs(w2) ** 2)
        w0, w1, w2 = w0 / size, w1 / size, w2 / size
        M = np.concatenate([w0[..., None] * np.stack(L[:k], axis=-1), w1[..., None] * np.stack(R[:k], axis=-1)],
                           axis=-1)
        du = np.linalg.solve(M, (w0 * r0 + w1 * r1 + w2 * r2)[..., None])[..., 0]
        s0 = r0 - sum(L[c] * du[:, c:c + 1] for c in range(k))
        s1 = r1 - sum(R[c] * du[:, k + c:k + c + 1] for c in range(k))
        # least squares of the 3 × 2 block: (VᴴV) dθ = Vᴴ s
        g00 = abs(v0[0]) ** 2 + abs(v1[0]) ** 2 + abs(v2[0]) ** 2
        g11 = abs(v0[1]) ** 2 + abs(v1[1]) ** 2 + abs(v2[1]) ** 2
        g01 = v0[0].conj() * v0[1] + v1[0].conj() * v1[1] + v2[0].conj() * v2[1]
        h0 = v0[0].conj() * s0 + v1[0].conj() * s1 + v2[0].conj() * r2
        h1 = v0[1].conj() * s0 + v1[1].conj() * s1 + v2[1].conj() * r2
        det = g00 * g11 - abs(g01) ** 2
        return np.concatenate([du, (g11 * h0 - g01 * h1) / det, (g00 * h1 - g01.conj() * h0) / det], axis=1)

    def jacobian(self, z, p):
        """The dense Jacobian ``∂F/∂z`` (N, m, m), for condition numbers and extended-precision Newton."""
        n, nu = self.n, self.nu
        U, V, _, _ = self._blocks(z, p)
        N = len(z)
        J = np.zeros((N, self.m, self.m), U.dtype)
        j = np.arange(n)
        for row in range(3):
            J[:, row * n + j, :nu] = U[:, :, row, :]
            J[:, row * n + j, nu + j] = V[:, :, row, 0]
            J[:, row * n + j, nu + n + j] = V[:, :, row, 1]
        return J

    def param_rate(self, z, p, dp):
        """``∂F/∂p · dp`` (N, m)."""
        (x, xb, a, ab, y, yb, b, bb), th, thb, d, db = self._split(z, p)
        n = self.n
        dd, ddb = dp[:, :n], dp[:, n:2 * n]
        # the partials of dyad_partials this needs (∂δ, ∂δ̄, and ∂a, ∂ā when the pivots are parameters), alone
        tx, tbx, ty, tby = th * x, thb * xb, th * y, thb * yb
        fl = (tbx + db - ab) * dd + (tx + d - a) * ddb
        fr = (tby + db - bb) * dd + (ty + d - b) * ddb
        if self.pivots_given:
            da, dab, dbp, dbb = (dp[:, 2 * n + k:2 * n + k + 1] for k in range(4))
            fl = fl + (xb - tbx - db) * da + (x - tx - d) * dab
            fr = fr + (yb - tby - db) * dbp + (y - ty - d) * dbb
        return np.concatenate([fl, fr, np.zeros_like(fl)], axis=1)


def plant(system: DyadSystem, rng, size: float = 1.0):
    """A random complex linkage and the parameters that make it a solution: ``(z (1, m), p (1, q))``.

    Each position's ``θ_j`` is drawn and ``δ_j, δ̄_j`` solved from the two dyad equations (their difference is
    linear in ``δ_j, δ̄_j``; substituted in the first it leaves a quadratic)."""
    def c(*shape):
        return size * (rng.normal(size=shape) + 1j * rng.normal(size=shape)) / np.sqrt(2)

    x, xb, a, ab, y, yb, b, bb = c(8)
    n = system.n
    th = np.exp(1j * rng.uniform(-np.pi, np.pi, n)) * np.exp(0.3 * c(n) / size)
    thb = 1 / th

    def coefficients(x, xb, a, ab):
        return thb * xb - ab, th * x - a, x * ab + a * xb - th * x * ab - thb * xb * a

    a1, b1, c1 = coefficients(x, xb, a, ab)
    a2, b2, c2 = coefficients(y, yb, b, bb)
    al, be, ga = a1 - a2, b1 - b2, c1 - c2                 # al δ + be δ̄ + ga = 0
    qa, qb, qc = -al, a1 * be - ga - b1 * al, c1 * be - b1 * ga
    d = (-qb + np.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
    db = -(ga + al * d) / be
    link = np.array([x, xb, y, yb]) if system.pivots_given else np.array([x, xb, a, ab, y, yb, b, bb])
    z = np.concatenate([link, th, thb])[None]
    p = np.concatenate([d, db] + ([np.array([a, ab, b, bb])] if system.pivots_given else []))[None]
    return z, p
