"""RRSS spatial path generation: a coupler point through up to 8 given points (seed 002 §2-3, Fig. 2-25, Table 2-3).

The RRSS: a crank turns about the fixed axis ``u0`` through ``a0``; the
coupler turns on the crank about the moving axis ``u1`` through ``a1``; an
S-S link (fixed centre ``b0``, moving centre ``b1`` on the coupler) closes
the loop. The coupler frame is the world frame in position 1, so the traced
point is ``p_1`` itself, and the coupler's displacement to point ``j`` is
``x ↦ C_j (x − p_1) + p_j``.

**The book's system** (digest A.3.5, Table 2-3). Unknowns: ``u0, a0, u1,
a1, b0, b1`` (18) and the coupler's rotation ``C_j`` at each further point
(3 angles each): ``3n + 15``. Equations: the R-R link (2-63)–(2-66) — the
two unit axes, ``a_j`` in the plane through ``a0`` normal to ``u0`` and in
the plane through ``a_j`` normal to ``u_j`` (j = 1..n), the constant twist
and moment (j = 2..n) — and the S-S link (2-57): ``5n − 1``. So ``16 − 2n``
of the 18 first-position coordinates are given (``fixed``), none at ``n =
8``. The plane equations at ``j = 1`` fix the gauge: ``a0`` and ``a1`` are
the feet of the common normal of the two axes (any other point of an axis
is kinematically the same); the axes' signs are immaterial (solutions equal
up to them are one).

**How it is solved.** In the joint-angle form the R-R equations hold
identically: the coupler's pose at point ``j`` is its turn ``φ_j`` about
the moving axis followed by the crank's turn ``θ_j`` about the fixed axis
(``C_j = Rot(u0, θ_j) Rot(u1, φ_j)``, the book's three angles). The path
condition then splits: ``p_1`` turned by ``φ_j`` must have the height
``h = u0·(p − a0)`` and the squared distance ``y = |p − a0|²`` of ``p_j``
(two equations per point that do not involve the S-S link, nor ``θ_j``);
with the unit axes and the feet, ``2n + 2`` equations in the chain's 12
coordinates and the ``φ_j``: ``9 − n`` chain coordinates are given, and the
S-S link takes the other ``7 − n`` givens.

``method="conic"`` (n = 4..7, the chain's givens on the fixed axis: ``a0``
and ``5 − n`` of ``u0`` at n = 4, 5; ``a0`` at n = 6; two of ``a0`` at
n = 7). ``(h, y)`` of the coupler point are affine in ``(cos φ, sin φ)``:
its circle about the moving axis maps to an ellipse in the ``(h, y)``
plane, with axes parallel to ``h`` and ``y`` exactly when ``a0`` is the
foot of the common normal. So the fixed axis comes first, alone: the
points' ``(h_j, y_j)`` lie on a conic ``κ·(h², y², h, y, 1) = 0``, the
``n × 5`` matrix ``K(u0, a0)`` has rank 4 (:class:`_Axis`) — at n = 4 the
conic is unique, at n = 5 ``det K`` is a trigonometric cubic in ``u0``'s
one free turn (all real roots from a degree-6 polynomial), at n = 6, 7 the
``5 × 5`` minors are cubics in ``u0`` solved by batched Newton from a
Fibonacci lattice of directions (:func:`_directions`). For each axis the
moving axis follows in closed form (:func:`_circles`: a cubic in the
circle's squared radius, then the twist, the azimuth ``±β`` and the turn
that puts ``p_1`` on the circle), and Levenberg–Marquardt on the full chain
system only polishes. The per-point angles never enter a search.

``method="seeded"`` (any givens, n = 2..7): the chain's coordinates and the
``φ_j`` together by Levenberg–Marquardt from ``starts`` seeded starts at
once (numpy, vectorised; starts: random axes and feet in the points' box,
``φ_j`` from the 2 × 2 solve that puts ``p_1`` nearest ``p_j``), then
Gauss–Newton polish; it finds a given root only from some starts (about
8 in 10 planted cases at n = 4, rarely at n = 5). ``method="auto"`` (the
default) takes ``"conic"`` where its givens allow, else ``"seeded"``.

For each chain root the S-S link is exact: linear in ``b1`` when ``b0`` is
given, a 4 × 4 eigenvalue pencil in the third coordinate when two of
``b0``'s are (n = 5), batched Newton on the 4 × 4 minors of the linear
system in ``b1`` (:func:`_sphere_centres`, n = 6, 7, ``b0``'s coordinates
given), else :func:`~domes.design.synthesis.links.guiding_links`. Eight
points (nothing given) do not split — the chain would keep one free
choice and the S-S link meet seven conditions with six unknowns — and are
refused. Each solution is checked three ways: the book's 5n − 1 equations
(:func:`book_residuals`), the guiding links' own check
(:func:`~domes.design.synthesis.links.check`), and the spatial solver
driving the fixed R joint of its
:class:`~domes.model.spatial.SpatialMechanism` continuously from position 1
through every ``θ_j`` (:func:`path_errors`): a root of the equations whose
points lie on the other assembly branch shows there a large path error.

Measured (random planted RRSS, points from each one's own motion, the
givens from it, as in ``tests/design/test_rrss_path_generation.py``; found =
the planted RRSS among the solutions to 1e-6 of the size): ``"conic"``
199 of 200 at n = 5 (four seeds of 50), 60 of 60 at n = 4, 100 of 100 at
n = 6 (two seeds of 50), 25 of 30 at n = 7 (the minors' Newton misses
the axis where rows 1–4 are nearly dependent, or ``b0`` lies outside the
search cube); about 40 ms a case at n = 5, 0.2 s at n = 6, 1–3 s at n = 7.
``"seeded"`` on the same cases: 7 of 10 at n = 4, 5 of 10 at n = 5, about
3 s a case.

>>> table_2_3(5)
(24, 30, 6)
>>> rrss_path([[0, 0, 0], [1, 0, 0], [0, 1, 0]], fixed={"a0x": 0.0})
Traceback (most recent call last):
...
domes.errors.InputError: rrss_path: 3 points give 14 equations in 24 unknowns (Table 2-3): give exactly 10 coordinates in 'fixed', got 1
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.design.synthesis import links
from domes.design.synthesis.sphere import rot
from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism, SpatialPoint
from domes.results import Listing, Status

#: The most path points (Table 2-3: 39 equations in 39 unknowns at 8).
MOST = 8
#: The first-position coordinates, by name (the variables ``fixed`` may give).
NAMES = tuple(f"{v}{c}" for v in ("u0", "a0", "u1", "a1", "b0", "b1") for c in "xyz")
METHODS = ("auto", "conic", "seeded")
#: Iterations of Levenberg–Marquardt from each start.
ITERATIONS = 120


def table_2_3(n: int) -> tuple[int, int, int]:
    """``(equations, unknowns, given)`` of Table 2-3 for ``n`` points: ``(5n − 1, 3n + 15, 16 − 2n)``.

    >>> [table_2_3(n) for n in (2, 5, 8)]
    [(9, 21, 12), (24, 30, 6), (39, 39, 0)]
    """
    return 5 * n - 1, 3 * n + 15, 16 - 2 * n


# -- geometry (batched over starts: arrays (N, 3), angles (N,)) ------------------------------------------

def _rotate(x, u, t):
    """Rodrigues: ``x`` turned by ``t`` about the unit ``u`` (all batched)."""
    c, s = np.cos(t)[:, None], np.sin(t)[:, None]
    return x * c + np.cross(u, x) * s + u * np.sum(u * x, axis=1, keepdims=True) * (1 - c)


def _unit(u):
    return u / np.linalg.norm(u, axis=-1, keepdims=True)


def _move(x, u0, a0, u1, a1, theta, phi):
    """The coupler point ``x`` (position 1) after the coupler's turn ``φ`` about (u1, a1), then the crank's ``θ``."""
    q = a1 + _rotate(x - a1, u1, phi)
    return a0 + _rotate(q - a0, u0, theta)


def _cross(a, b):
    return np.stack([a[:, 1] * b[:, 2] - a[:, 2] * b[:, 1], a[:, 2] * b[:, 0] - a[:, 0] * b[:, 2],
                     a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]], 1)


def _dot(a, b):
    return np.einsum("ni,ni->n", a, b)


class _Chain:
    """The R-R chain with the coupler point alone: ``p_1`` turned by ``φ_j`` about the moving axis must have the
    height along ``u0`` and the distance from ``a0`` of ``p_j`` (the crank's turn ``θ_j`` then brings it there).
    Unknowns: the free coordinates of ``u0, a0, u1, a1`` and ``φ_j``; equations: unit axes, feet, two per point."""

    def __init__(self, P: np.ndarray, fixed: dict[str, float]):
        self.P, self.n = P, len(P)
        self.fixed = {k: v for k, v in fixed.items() if NAMES.index(k) < 12}
        self.free = [k for k in range(12) if NAMES[k] not in self.fixed]
        self.size = len(self.free) + self.n - 1
        self.base = np.zeros(12)
        for nm, v in self.fixed.items():
            self.base[NAMES.index(nm)] = v

    def full(self, z):
        x = np.repeat(self.base[None], z.shape[0], axis=0)
        x[:, self.free] = z[:, :len(self.free)]
        return x, z[:, len(self.free):]

    def residuals(self, z):
        x, phi = self.full(z)
        u0, a0, u1, a1 = x[:, 0:3], x[:, 3:6], x[:, 6:9], x[:, 9:12]
        d = a1 - a0
        out = [_dot(u0, u0) - 1, _dot(u1, u1) - 1, _dot(u0, d), _dot(u1, d)]
        n0, n1 = _unit(u0), _unit(u1)
        w = self.P[0] - a1
        along = n1 * _dot(n1, w)[:, None]
        e = w - along
        f = _cross(n1, e)
        g = a1 + along - a0                                   # centre of p_1's circle, from a0
        for j in range(1, self.n):
            c, s = np.cos(phi[:, j - 1])[:, None], np.sin(phi[:, j - 1])[:, None]
            q = g + e * c + f * s                             # p_1 turned, from a0
            r = self.P[j] - a0
            out.append(_dot(n0, q - r))
            out.append(0.5 * (_dot(q, q) - _dot(r, r)))
        return np.array(out).T

    def jacobian(self, z, f):
        N, m = z.shape
        h = 1e-7 * np.maximum(1.0, np.abs(z))
        zz = np.repeat(z[:, None, :], m, axis=1)
        idx = np.arange(m)
        zz[:, idx, idx] += h
        F = self.residuals(zz.reshape(N * m, m)).reshape(N, m, -1)
        return np.transpose((F - f[:, None, :]) / h[:, :, None], (0, 2, 1))

    def starts(self, N, rng):
        x = rng.uniform(-1.0, 1.0, (N, 12))
        for k in (0, 6):
            x[:, k:k + 3] = _unit(rng.normal(size=(N, 3)))
        for nm, v in self.fixed.items():
            x[:, NAMES.index(nm)] = v
        a1 = x[:, 3:6] + _unit(_cross(x[:, 0:3], x[:, 6:9])) * rng.uniform(-1.0, 1.0, (N, 1))
        for c in range(3):
            if NAMES[9 + c] not in self.fixed:
                x[:, 9 + c] = a1[:, c]
        phi = self.angles(x, rng)[1]
        return np.concatenate([x[:, self.free], phi], 1)

    def angles(self, x, rng=None):
        """``(θ_j, φ_j)`` that bring ``p_1`` nearest ``p_j`` (the two conditions are affine in ``(cos φ, sin φ)``:
        their 2 × 2 solve, put on the unit circle; then the crank's turn about ``u0``)."""
        N = x.shape[0]
        u0, a0, u1, a1 = _unit(x[:, 0:3]), x[:, 3:6], _unit(x[:, 6:9]), x[:, 9:12]
        w = self.P[0] - a1
        along = u1 * _dot(u1, w)[:, None]
        e = w - along
        f = _cross(u1, e)
        g = a1 + along - a0
        thetas, phis = [], []
        for j in range(1, self.n):
            r = self.P[j] - a0
            A = np.stack([np.stack([_dot(u0, e), _dot(u0, f)], 1), np.stack([2 * _dot(g, e), 2 * _dot(g, f)], 1)], 1)
            rhs = np.stack([_dot(u0, r - g), _dot(r, r) - _dot(g, g) - _dot(e, e)], 1)
            det = np.linalg.det(A)
            ok = np.abs(det) > 1e-12
            cs = np.ones((N, 2))
            cs[ok] = np.linalg.solve(A[ok], rhs[ok][..., None])[..., 0]
            phi = np.arctan2(cs[:, 1], cs[:, 0])
            if rng is not None:
                phi = np.where(ok, phi, rng.uniform(-np.pi, np.pi, N))
            q = g + e * np.cos(phi)[:, None] + f * np.sin(phi)[:, None]
            q = q - u0 * _dot(u0, q)[:, None]
            r = r - u0 * _dot(u0, r)[:, None]
            thetas.append(np.arctan2(_dot(u0, _cross(q, r)), _dot(q, r)))
            phis.append(phi)
        return np.array(thetas).T, np.array(phis).T

    def exact_angles(self, x, phi):
        """``θ_j`` for the solved ``φ_j``."""
        u0, a0, u1, a1 = _unit(x[:, 0:3]), x[:, 3:6], _unit(x[:, 6:9]), x[:, 9:12]
        out = []
        for j in range(1, self.n):
            q = a1 + _rotate(self.P[0] - a1, u1, phi[:, j - 1]) - a0
            r = self.P[j] - a0
            q = q - u0 * _dot(u0, q)[:, None]
            r = r - u0 * _dot(u0, r)[:, None]
            out.append(np.arctan2(_dot(u0, _cross(q, r)), _dot(q, r)))
        return np.array(out).T


def _complex_step(residuals, z):
    """The Jacobian ``(N, equations, unknowns)`` of batched analytic residuals by the complex step (exact to
    rounding: the residuals here are polynomials)."""
    N, m = z.shape
    h = 1e-30
    zz = np.repeat(z[:, None, :].astype(complex), m, axis=1)
    idx = np.arange(m)
    zz[:, idx, idx] += 1j * h
    F = residuals(zz.reshape(N * m, m)).reshape(N, m, -1)
    return np.transpose(F.imag / h, (0, 2, 1))


class _Axis:
    """The fixed axis alone. Seen from the axis ``(a0, u0)``, a path point has the height ``h = u0·(p − a0)``
    and the squared distance ``y = |p − a0|²``, unchanged by the crank's turn; the coupler point's circle about
    the moving axis maps to an ellipse in the ``(h, y)`` plane (``(h, y)`` are affine in ``cos φ, sin φ``),
    whose axes are parallel to ``h`` and ``y`` exactly when ``a0`` is the foot of the common normal. So the
    ``n`` points ``(h_j, y_j)`` lie on a conic ``κ·(h², y², h, y, 1) = 0``: the ``n × 5`` matrix ``K`` has
    rank ≤ 4. Unknowns: the free coordinates of ``u0, a0`` (``9 − n`` of the 6 given, ``|u0| = 1``) and the
    unit ``κ``; equations: ``|u0| = 1``, ``K κ = 0``, ``|κ| = 1``: ``n + 2`` each."""

    def __init__(self, P: np.ndarray, fixed: dict[str, float]):
        self.P, self.n = P, len(P)
        self.fixed = dict(fixed)
        self.free = [k for k in range(6) if NAMES[k] not in fixed]
        self.base = np.zeros(6)
        for nm, v in fixed.items():
            self.base[NAMES.index(nm)] = v

    def split(self, z):
        x = np.repeat(self.base[None].astype(z.dtype), z.shape[0], axis=0)
        x[:, self.free] = z[:, :len(self.free)]
        return x, z[:, len(self.free):]

    def matrix(self, x):
        u0, a0 = x[:, 0:3], x[:, 3:6]
        r = self.P[None, :, :] - a0[:, None, :]
        h = np.einsum("ni,nji->nj", u0, r)
        y = np.einsum("nji,nji->nj", r, r)
        return np.stack([h * h, y * y, h, y, np.ones_like(h)], -1)

    def residuals(self, z):
        x, kappa = self.split(z)
        u0 = x[:, 0:3]
        K = self.matrix(x)
        return np.concatenate([(_dot(u0, u0) - 1)[:, None], np.einsum("nji,ni->nj", K, kappa),
                               (_dot(kappa, kappa) - 1)[:, None]], 1)

    def jacobian(self, z, f):
        return _complex_step(self.residuals, z)


def _kappa(ax: _Axis, x: np.ndarray) -> np.ndarray:
    """The conic of each axis ``x`` (N, 6): the right singular vector of ``K`` with the least singular value."""
    return np.linalg.svd(ax.matrix(x))[2][:, -1, :]


def _turns(ax: _Axis, x0: np.ndarray, k: int, rows) -> np.ndarray:
    """Every turn ``ψ`` of ``u0`` about the coordinate axis ``k`` (its ``k``-th coordinate kept) at which the
    points ``rows`` give ``det K = 0`` (``x0`` (6,): the axis at ``ψ = 0``). ``K``'s columns are of degree
    2, 1, 0, 0, 0 in ``u0``, so the determinant is a trigonometric polynomial of degree 3 in ``ψ``: 16
    samples give its coefficients exactly (FFT), and its real roots are the unit-circle roots of a degree-6
    polynomial."""
    i, j = [c for c in range(3) if c != k]
    psi = 2 * np.pi * np.arange(16) / 16
    x = np.repeat(x0[None], 16, axis=0)
    x[:, i] = x0[i] * np.cos(psi) - x0[j] * np.sin(psi)
    x[:, j] = x0[i] * np.sin(psi) + x0[j] * np.cos(psi)
    sub = _Axis(ax.P[list(rows)], {})
    coef = np.fft.fft(np.linalg.det(sub.matrix(x))) / 16   # det(ψ) = Σ coef_m e^{imψ}, m = −3..3
    poly = np.array([coef[m % 16] for m in range(3, -4, -1)])
    if not np.any(np.abs(poly) > 1e-14 * max(1.0, float(np.max(np.abs(coef))))):
        return np.zeros(0)
    z = np.roots(poly)
    z = z[np.abs(np.abs(z) - 1) < 1e-5]
    return np.sort(np.angle(z))


def _rotated(x0: np.ndarray, k: int, psi: float) -> np.ndarray:
    i, j = [c for c in range(3) if c != k]
    x = x0.copy()
    x[i] = x0[i] * math.cos(psi) - x0[j] * math.sin(psi)
    x[j] = x0[i] * math.sin(psi) + x0[j] * math.cos(psi)
    return x


def _directions(ax: _Axis, starts: int = 200, heights: int = 8) -> list[np.ndarray]:
    """n = 6 (``a0`` given) or 7 (two of ``a0``'s coordinates given): every axis ``[u0, a0]`` where the
    ``n × 5`` matrix ``K`` has rank 4, as the common roots of its ``5 × 5`` minors of rows ``1, 2, 3, 4, k``
    (k = 5..n; homogeneous cubics in ``u0``) and ``|u0|² − 1``: batched Newton from ``starts`` directions
    spread over the sphere (a Fibonacci lattice), times ``heights`` values of ``a0``'s free coordinate in
    ``[−2, 2]`` (normalised units) at n = 7. Roots where rows 1–4 alone drop rank (every minor vanishes, ``K``
    of rank 3) are not roots of the problem and are left out."""
    subs = [_Axis(ax.P[[0, 1, 2, 3, k]], {}) for k in range(4, ax.n)]
    free = [k for k in range(3, 6) if k in ax.free]

    def full(v):
        x = np.repeat(ax.base[None].astype(v.dtype), len(v), axis=0)
        x[:, 0:3] = v[:, 0:3]
        x[:, free] = v[:, 3:]
        return x

    def residuals(v):
        x = full(v)
        dets = [np.linalg.det(sub.matrix(x)) for sub in subs]
        return np.stack(dets + [_dot(x[:, 0:3], x[:, 0:3]) - 1], 1)

    k = np.arange(starts) + 0.5
    z = 1 - 2 * k / starts
    lon = np.pi * (1 + 5 ** 0.5) * k
    v = np.stack([np.sqrt(1 - z * z) * np.cos(lon), np.sqrt(1 - z * z) * np.sin(lon), z], 1)
    if free:
        g = np.linspace(-2.0, 2.0, heights)
        v = np.concatenate([np.repeat(v, heights, axis=0), np.tile(g, starts)[:, None]], 1)
    v = _newton(residuals, v, most=0.3)
    v = v[np.all(np.isfinite(v), 1)]
    v[:, 0:3] /= np.linalg.norm(v[:, 0:3], axis=1, keepdims=True)
    x = full(v)
    K = ax.matrix(x)
    K = K / np.linalg.norm(K, axis=1, keepdims=True)           # columns to unit length
    sv, shared = np.linalg.svd(K, compute_uv=False), np.linalg.svd(K[:, :4], compute_uv=False)
    keep = (sv[:, 4] < 1e-9 * sv[:, 0]) & (shared[:, 3] > 1e-10 * shared[:, 0])
    return list(x[keep])


def _newton(residuals, x: np.ndarray, iterations: int = 40, most: float = 0.5, owner=None) -> np.ndarray:
    """Batched Newton on a square system from every row of ``x``, each step at most ``most`` long (complex-step
    Jacobian); a start stops once its step is below 1e-13. With ``owner`` (an array, one entry a row), the
    residuals are called as ``residuals(x, owner)`` on the rows still running."""
    x = x.copy()
    active = np.arange(len(x))
    m = x.shape[1]
    with np.errstate(all="ignore"):
        for _ in range(iterations):
            if active.size == 0:
                break
            xa = x[active]
            if owner is None:
                res = residuals
            else:
                def res(v, rows=active):
                    return residuals(v, owner[rows if len(v) == len(rows) else np.repeat(rows, m)])
            f = res(xa)
            J = _complex_step(res, xa)
            good = np.all(np.isfinite(J), (1, 2)) & np.all(np.isfinite(f), 1) & (np.abs(np.linalg.det(J)) > 1e-300)
            step = np.zeros_like(xa)
            if np.any(good):
                step[good] = np.linalg.solve(J[good], -f[good][..., None])[..., 0]
            big = np.linalg.norm(step, axis=1, keepdims=True)
            x[active] = xa + step * np.minimum(1.0, most / np.maximum(big, 1e-300))
            active = active[good & (big[:, 0] > 1e-13)]
    return x


def _axes(P: np.ndarray, fixed: dict[str, float]) -> list[np.ndarray] | None:
    """Every fixed axis ``[u0, a0]`` (6) whose points ``(h_j, y_j)`` lie on an axis-parallel conic (:class:`_Axis`),
    when the chain's givens are ``a0`` and ``5 − n`` coordinates of ``u0`` (n = 4, 5), ``a0`` alone (n = 6) or
    two of ``a0``'s coordinates (n = 7); ``None`` for other givens. n = 4: ``u0`` known up to the sign of its
    last coordinate, the conic through 4 points unique. n = 5: the turn of ``u0`` about its given coordinate's
    axis, the real roots of :func:`_turns` (all of them). n = 6, 7: :func:`_directions`."""
    if any(NAMES.index(k) >= 6 for k in fixed):
        return None
    n = len(P)
    if n == 7 and len(fixed) == 2 and all(k.startswith("a0") for k in fixed):
        out = _directions(_Axis(P, fixed))
        return _distinct(out, [])
    if not all(f"a0{c}" in fixed for c in "xyz") or len(fixed) != 9 - n:
        return None
    a0 = np.array([fixed[f"a0{c}"] for c in "xyz"])
    given = [k for k in range(3) if NAMES[k] in fixed]
    ax = _Axis(P, fixed)
    out = []
    if n == 4:
        k = next(c for c in range(3) if c not in given)
        rest = 1 - sum(fixed[NAMES[c]] ** 2 for c in given)
        if rest < 0:
            return []
        for sign in (1.0, -1.0):
            u0 = np.array([fixed.get(NAMES[c], 0.0) for c in range(3)])
            u0[k] = sign * math.sqrt(rest)
            out.append(np.concatenate([u0, a0]))
    elif n == 5:
        k = given[0]
        rest = 1 - fixed[NAMES[k]] ** 2
        if rest < 0:
            return []
        u0 = np.zeros(3)
        u0[k] = fixed[NAMES[k]]
        u0[(k + 1) % 3] = math.sqrt(rest)
        x0 = np.concatenate([u0, a0])
        out = [_rotated(x0, k, psi) for psi in _turns(ax, x0, k, range(5))]
    elif n in (6, 7):
        out = _directions(ax)
    else:
        return None
    return _distinct(out, given)


def _distinct(out, given) -> list[np.ndarray]:
    found: list[np.ndarray] = []
    for x in out:
        x = np.asarray(x, float)
        if not given and x[int(np.argmax(np.abs(x[:3])))] < 0:
            x = np.concatenate([-x[:3], x[3:]])                # the axis's sign is immaterial
        if not any(np.max(np.abs(x - y)) < 1e-8 for y in found):
            found.append(x)
    return found


def _circles(P: np.ndarray, u0: np.ndarray, a0: np.ndarray, kappa: np.ndarray) -> list[np.ndarray]:
    """Every R-R chain ``[u0, a0, u1, a1]`` (12) on the fixed axis ``(a0, u0)`` (``a0`` the foot) whose coupler
    point ``p_1`` meets each ``p_j``'s circle about the axis, from the conic ``κ`` of :class:`_Axis`, in closed
    form. The ellipse ``a (h − H)² + c (y − Y)² = k`` is the image of the circle (centre ``a0 + H u0 + δ w``,
    radius ``R``, axis ``u1`` at the angle ``α`` from ``u0``) when ``S00 = k/a = R² sin²α``,
    ``S11 = k/c = 4 R² (H² + δ² − m²)``, ``H = m cos α`` and ``Y = H² + δ² + R²`` (``m = u1·(centre − a0)``):
    a cubic in ``t = R²``, ``−t³ + (Y + S00 − H²) t² − (S11/4 + S00 Y) t + S00 S11 / 4 = 0``; then ``α``,
    ``δ``, ``m`` and the azimuth ``±β`` of ``u1``, and the turn about ``u0`` that puts ``p_1`` on the circle."""
    u0 = u0 / np.linalg.norm(u0)
    a, c, d, e, f = kappa
    if not a * c > 0:
        return []                                           # not an ellipse
    H, Y = -d / (2 * a), -e / (2 * c)
    k = a * H * H + c * Y * Y - f
    S00, S11 = k / a, k / c
    if not (S00 > 0 and S11 > 0):
        return []
    w = np.cross(u0, [1.0, 0, 0] if abs(u0[0]) < 0.9 else [0, 1.0, 0])
    w /= np.linalg.norm(w)
    w2 = np.cross(u0, w)
    r1 = P[0] - a0
    out = []
    for t in np.roots([-1.0, Y + S00 - H * H, -(S11 / 4 + S00 * Y), S00 * S11 / 4]):
        if abs(t.imag) > 1e-9 * max(1.0, abs(t)) or not t.real > S00:
            continue
        t = t.real
        sa, ca = math.sqrt(S00 / t), math.sqrt(1 - S00 / t)
        dd = Y - H * H - t
        if ca < 1e-9 or dd < 0 or sa < 1e-9:
            continue
        delta, m = math.sqrt(dd), H / ca
        cb = (m - H * ca) / (delta * sa) if delta > 1e-12 else 1.0
        if abs(cb) > 1 + 1e-6:
            continue
        cb = min(1.0, max(-1.0, cb))
        for sb in {math.sqrt(1 - cb * cb), -math.sqrt(1 - cb * cb)}:
            u1 = ca * u0 + sa * (cb * w + sb * w2)
            g = H * u0 + delta * w                           # the circle's centre, from a0
            ce = np.cross(u1, u0)
            ce *= math.sqrt(t) / np.linalg.norm(ce)
            cf = np.cross(u1, ce)
            A = np.array([[u0 @ ce, u0 @ cf], [2 * g @ ce, 2 * g @ cf]])
            if abs(np.linalg.det(A)) < 1e-12:
                continue
            cs = np.linalg.solve(A, [u0 @ (r1 - g), r1 @ r1 - g @ g - t])
            q = g + ce * cs[0] + cf * cs[1]                  # the circle's point at p_1's height and distance
            qp, rp = q - u0 * (u0 @ q), r1 - u0 * (u0 @ r1)
            turn = math.atan2(u0 @ np.cross(qp, rp), qp @ rp)
            R = rot(u0, turn)
            u1, g = R @ u1, R @ g
            out.append(np.concatenate([u0, a0, u1, a0 + g - u1 * (u1 @ g)]))
    return out


def _poses(P, x, theta, phi):
    """The coupler's displacements ``x ↦ C_j x + d_j`` (j = 1..n, the first the identity) of one chain."""
    u0, a0, u1, a1 = (np.asarray(x[3 * k:3 * k + 3], float) for k in range(4))
    u0, u1 = u0 / np.linalg.norm(u0), u1 / np.linalg.norm(u1)
    out = [(np.eye(3), np.zeros(3))]
    for t, f in zip(theta, phi):
        C = rot(u0, float(t)) @ rot(u1, float(f))
        out.append((C, a0 + rot(u0, float(t)) @ (a1 - rot(u1, float(f)) @ a1 - a0)))
    return out


def _sphere_pairs(moves, b0xy: dict[str, float]) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every S-S link ``(b0, b1)`` for the displacements ``moves`` (five positions) with two coordinates of ``b0``
    given: (2-57) reads ``2 (C_jᵀ(d_j − b0) + b0) · b1 = 2 d_j · b0 − |d_j|²``, linear in ``b1`` with
    coefficients affine in the third coordinate ``z`` of ``b0``: the 4 × 4 pencil ``(M0 + z M1) [b1; −1] = 0``,
    whose finite real eigenvalues are all the solutions."""
    from scipy.linalg import eig

    known = {"xyz".index(k[-1]): v for k, v in b0xy.items()}
    k = next(c for c in range(3) if c not in known)

    def matrix(zval):
        b0 = np.zeros(3)
        for c, v in known.items():
            b0[c] = v
        b0[k] = zval
        rows = []
        for C, d in moves[1:]:
            rows.append(np.concatenate([2 * (C.T @ (d - b0) + b0), [2 * d @ b0 - d @ d]]))
        return np.array(rows), b0

    M0, _ = matrix(0.0)
    M1 = matrix(1.0)[0] - M0
    vals, vecs = eig(M0, -M1)
    out = []
    for lam, v in zip(vals, vecs.T):
        if not np.isfinite(lam) or abs(lam.imag) > 1e-7 * max(1.0, abs(lam)) or abs(v[3]) < 1e-12:
            continue
        v = np.real(v / v[3])
        M, b0 = matrix(float(lam.real))
        out.append((b0, -v[:3]))
    return out


def _sphere_centres(moves_list, given: dict[str, float], box: float = 4.0) -> list[list[tuple[np.ndarray, np.ndarray]]]:
    """Every S-S link ``(b0, b1)`` for each set of six or seven positions in ``moves_list`` (one batch) with
    ``7 − n`` coordinates of ``b0`` given (n = 6: one, n = 7: none). For a fixed ``b0``, (2-57) is linear in
    ``b1``: ``M(b0) [b1; 1] = 0`` with ``M`` ``(n − 1) × 4``, affine in ``b0``; it has rank 3 at a solution.
    Its 4 × 4 minors of rows ``1, 2, 3, k`` (k = 4..n−1) give as many equations as ``b0`` has free
    coordinates: batched Newton from a grid of starts in the cube ``[−box, box]`` (normalised units); then
    ``b1`` from ``M``'s null vector. Where ``M`` has rank 2 (``b0`` on the fixed axis: ``b1`` anywhere on the
    moving axis, a link that only repeats the R-R chain) the root is left out."""
    known = {"xyz".index(k[-1]): v for k, v in given.items()}
    free = [c for c in range(3) if c not in known]
    Cs = np.array([[C for C, _ in mv[1:]] for mv in moves_list])      # (G, rows, 3, 3)
    ds = np.array([[d for _, d in mv[1:]] for mv in moves_list])      # (G, rows, 3)
    rows = Cs.shape[1]

    def matrix(b, owner):
        b0 = np.zeros((len(b), 3), dtype=b.dtype)
        for c, v in known.items():
            b0[:, c] = v
        b0[:, free] = b
        C, d = Cs[owner], ds[owner]
        a = 2 * (np.einsum("nrji,nrj->nri", C, d - b0[:, None, :]) + b0[:, None, :])
        last = np.einsum("nri,nri->nr", d, d) - 2 * np.einsum("ni,nri->nr", b0, d)
        return np.concatenate([a, last[..., None]], 2)

    minors = [[0, 1, 2, k] for k in range(3, rows)]

    def residuals(b, owner):
        M = matrix(b, owner)
        return np.stack([np.linalg.det(M[:, r, :]) for r in minors], 1)

    g = np.linspace(-box, box, 9 if len(free) == 2 else 5)
    grid = np.stack(np.meshgrid(*[g] * len(free), indexing="ij"), -1).reshape(-1, len(free))
    owner = np.repeat(np.arange(len(moves_list)), len(grid))
    b = _newton(residuals, np.tile(grid, (len(moves_list), 1)), owner=owner)
    fine = np.all(np.isfinite(b), 1)
    b, owner = b[fine], owner[fine]
    M = matrix(b, owner)
    _, sv, Vt = np.linalg.svd(M)
    ok = (sv[:, 3] < 1e-10 * sv[:, 0]) & (sv[:, 2] > 1e-7 * sv[:, 0]) & (np.abs(Vt[:, 3, 3]) > 1e-12)
    out: list[list[tuple[np.ndarray, np.ndarray]]] = [[] for _ in moves_list]
    for k in np.flatnonzero(ok):
        b0 = np.zeros(3)
        for c, v in known.items():
            b0[c] = v
        b0[free] = b[k]
        b1 = Vt[k, 3, :3] / Vt[k, 3, 3]
        mine = out[owner[k]]
        if not any(np.max(np.abs(b0 - p)) + np.max(np.abs(b1 - q)) < 1e-8 for p, q in mine):
            mine.append((b0, b1))
    return out


def _lm(system, z: np.ndarray, tol: float, iterations: int = ITERATIONS):
    """Levenberg–Marquardt on every start at once; ``(z, worst residual)`` per start."""
    N, m = z.shape
    f = system.residuals(z)
    cost = np.sum(f * f, 1)
    lam = np.full(N, 1e-3)
    active = np.ones(N, bool)
    for _ in range(iterations):
        idx = np.flatnonzero(active)
        if idx.size == 0:
            break
        za, fa = z[idx], f[idx]
        J = system.jacobian(za, fa)
        A = np.einsum("nei,nej->nij", J, J)
        g = np.einsum("nei,ne->ni", J, fa)
        D = np.einsum("nii->ni", A) + 1e-12
        A = A + (lam[idx, None] * D)[:, :, None] * np.eye(m)
        try:
            step = np.linalg.solve(A, -g[..., None])[..., 0]
        except np.linalg.LinAlgError:
            step = np.array([np.linalg.lstsq(a, -b, rcond=None)[0] for a, b in zip(A, g)])
        zn = za + step
        fn = system.residuals(zn)
        cn = np.sum(fn * fn, 1)
        better = np.isfinite(cn) & (cn < cost[idx])
        z[idx[better]], f[idx[better]], cost[idx[better]] = zn[better], fn[better], cn[better]
        lam[idx] = np.where(better, np.maximum(lam[idx] / 5, 1e-12), lam[idx] * 8)
        worst = np.max(np.abs(f[idx]), 1)
        done = (worst < tol) | (lam[idx] > 1e12) | ~np.isfinite(worst)
        active[idx[done]] = False
    near = np.flatnonzero(np.isfinite(cost) & (np.max(np.abs(f), 1) < 1e-3))
    for _ in range(12):                                       # Gauss–Newton polish of the near ones
        if near.size == 0:
            break
        J = system.jacobian(z[near], f[near])
        step = np.array([np.linalg.lstsq(a, -b, rcond=None)[0] for a, b in zip(J, f[near])])
        zn = z[near] + step
        fn = system.residuals(zn)
        better = np.max(np.abs(fn), 1) < np.max(np.abs(f[near]), 1)
        z[near[better]], f[near[better]] = zn[better], fn[better]
        near = near[better]
    return z, np.max(np.abs(f), 1)


# -- the solver ------------------------------------------------------------------------------------------

@dataclass(frozen=True)
class RRSSSolution:
    """One RRSS through the points: first-position axes and points (world units), the crank's turns ``thetas``
    and the coupler's turns on the crank ``phis`` at each point (rad, the first 0), the coupler's rotations
    ``rotations`` (3 × 3, the first the identity; the book's three angles per point), the largest residual of the
    book's 5n − 1 equations (``residual``, relative to the path's size), the guiding links' own check
    (``link_check``), and the spatial solver's worst distance of the coupler point from a ``p_j``
    (``path_error``, relative to the size; NaN where the walk does not reach every point on one branch,
    ``reach`` says why)."""

    u0: np.ndarray
    a0: np.ndarray
    u1: np.ndarray
    a1: np.ndarray
    b0: np.ndarray
    b1: np.ndarray
    p1: np.ndarray
    thetas: tuple[float, ...]
    phis: tuple[float, ...]
    rotations: tuple[np.ndarray, ...] = field(repr=False)
    residual: float = math.nan
    link_check: float = math.nan
    path_error: float = math.nan
    reach: str = ""

    def values(self) -> dict[str, float]:
        """The 18 first-position coordinates by name (:data:`NAMES`)."""
        v = np.concatenate([self.u0, self.a0, self.u1, self.a1, self.b0, self.b1])
        return {nm: float(x) for nm, x in zip(NAMES, v)}

    def distance(self, other: dict[str, float]) -> float:
        """The largest coordinate difference from ``other`` (names as :data:`NAMES`), the axes up to their sign."""
        a = np.array([self.values()[k] for k in NAMES])
        b = np.array([other[k] for k in NAMES])
        for k in (0, 6):
            if a[k:k + 3] @ b[k:k + 3] < 0:
                a[k:k + 3] = -a[k:k + 3]
        return float(np.max(np.abs(a - b)))

    def mechanism(self) -> SpatialMechanism:
        """The RRSS as a spatial mechanism in position 1 (:func:`rrss_mechanism`)."""
        return rrss_mechanism(self.u0, self.a0, self.u1, self.a1, self.b0, self.b1, self.p1)


@dataclass(frozen=True)
class RRSSPath(Listing):
    """The result of :func:`rrss_path`: every distinct solution found (``solutions``, also the sequence), the
    status (``empty`` when none), the method that ran (``"conic"`` or ``"seeded"``), the starts (``"seeded"``)
    or closed-form chains (``"conic"``) tried and how many converged, the worst residual."""

    items_field = "solutions"
    solutions: tuple[RRSSSolution, ...]
    status: Status
    message: str
    method: str
    starts: int
    converged: int
    worst: float


def book_residuals(values: dict[str, float], rotations, points) -> np.ndarray:
    """The book's equations for a solution (Table 2-3: ``5n − 1`` of them), each relative to the size: unit
    axes (2-64), the plane equations (2-63) for j = 1..n, twist (2-65) and moment (2-66) for j = 2..n, and the
    S-S (2-57) for j = 2..n; the coupler's displacement ``D1j x = C_j (x − p_1) + p_j``."""
    P = np.asarray(points, float)
    size = max(1.0, float(np.max(np.linalg.norm(P - P.mean(0), axis=1))))
    u0, a0, u1, a1, b0, b1 = (np.array([values[f"{v}{c}"] for c in "xyz"]) for v in ("u0", "a0", "u1", "a1", "b0", "b1"))
    out = [u0 @ u0 - 1, u1 @ u1 - 1]
    twist, moment, length = u0 @ u1, u0 @ np.cross(a1 - a0, u1), (b1 - b0) @ (b1 - b0)
    for j, C in enumerate(rotations):
        aj, uj, bj = C @ (a1 - P[0]) + P[j], C @ u1, C @ (b1 - P[0]) + P[j]
        out += [u0 @ (aj - a0) / size, uj @ (aj - a0) / size]
        if j:
            out += [uj @ u0 - twist, (u0 @ np.cross(aj - a0, uj) - moment) / size, (bj - b0) @ (bj - b0) / size ** 2
                    - length / size ** 2]
    return np.array(out)


def path_errors(sol: RRSSSolution, points) -> tuple[float, str]:
    """Drive the fixed R joint of the solution's mechanism continuously from position 1 (the spatial solver's
    Newton in turns of at most :data:`STEP`, one branch: :func:`trace`) to each ``θ_j`` and measure the coupler
    point against ``p_j``: ``(worst distance / size, "")``, or ``(NaN, why)`` where the walk stops (no pose)
    before a point."""
    P = np.asarray(points, float)
    size = max(1.0, float(np.max(np.linalg.norm(P - P.mean(0), axis=1))))
    try:
        got, _ = trace(sol.mechanism(), sol.thetas)
    except (NumericalError, InputError) as exc:
        return math.nan, str(exc)
    return float(np.max(np.linalg.norm(got - P, axis=1))) / size, ""


def _split(n: int, fixed: dict[str, float]) -> tuple[dict, dict]:
    chain = {k: v for k, v in fixed.items() if NAMES.index(k) < 12}
    link = {k: v for k, v in fixed.items() if NAMES.index(k) >= 12}
    if len(chain) != 9 - n:
        raise InputError(f"rrss_path: the seeded method solves the R-R chain first, so {9 - n} of the given "
                         f"coordinates must be of u0, a0, u1, a1 (and {7 - n} of b0, b1); got {len(chain)} "
                         f"({', '.join(chain) or 'none'}) and {len(link)} ({', '.join(link) or 'none'})")
    return chain, link


def rrss_path(points, fixed: dict | None = None, method: str = "auto", starts: int = 512, seed: int = 0,
              tol: float = 1e-10, check: bool = True) -> RRSSPath:
    """Every distinct RRSS whose coupler point passes through ``points`` (n from 2 to 7 here; Table 2-3 allows 8)
    that the method reaches, with ``16 − 2n`` of the first-position coordinates given by name in ``fixed``
    (:data:`NAMES`: ``u0x`` .. ``b1z``).

    The problem splits (the R-R chain's conditions do not involve the S-S link), so ``9 − n`` of the given
    coordinates must be the chain's and ``7 − n`` the S-S link's. ``method="conic"``: the fixed axis first
    (the points' heights and squared distances from it on an axis-parallel conic), then the moving axis in
    closed form — needs the chain's givens on the fixed axis (``a0`` and ``5 − n`` of ``u0`` at n = 4, 5,
    ``a0`` at n = 6, two of ``a0`` at n = 7). ``method="seeded"``: the chain's coordinates and the coupler's
    turns ``φ_j`` by Levenberg–Marquardt from ``starts`` seeded starts at once (any givens; finds a given root
    only from some starts). ``method="auto"``: ``"conic"`` where the givens allow, else ``"seeded"``; the
    result's ``method`` says which ran. For each chain root the S-S link is found exactly where ``b0`` is given
    (linear in ``b1``) or two of its coordinates are (a 4 × 4 eigenvalue pencil, n = 5), by batched Newton on
    its minors at n = 6, 7, else by :func:`~domes.design.synthesis.links.guiding_links`. ``tol``: the residual
    a root must reach (relative to the size). With ``check``, each solution is driven by the spatial solver
    (:func:`path_errors`)."""
    if method not in METHODS:
        raise InputError(f"rrss_path: method is one of {', '.join(METHODS)}, got {method!r}")
    try:
        P = np.array(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError("rrss_path: points must be a list of [x, y, z]") from None
    if P.ndim != 2 or P.shape[1] != 3 or not np.all(np.isfinite(P)):
        raise InputError(f"rrss_path: points must be n × 3 finite numbers, got shape {P.shape}")
    n = len(P)
    if not 2 <= n <= MOST:
        raise InputError(f"rrss_path: an RRSS path has 2 to {MOST} points (Table 2-3), got {n}")
    for i in range(n):
        for k in range(i):
            if np.linalg.norm(P[i] - P[k]) < 1e-9 * max(1.0, float(np.max(np.abs(P)))):
                raise InputError(f"rrss_path: points {k + 1} and {i + 1} coincide")
    fixed = dict(fixed or {})
    for k, v in fixed.items():
        if k not in NAMES:
            raise InputError(f"rrss_path: fixed: {k!r} is not a first-position coordinate ({', '.join(NAMES)})")
        if not isinstance(v, (int, float)) or not math.isfinite(v):
            raise InputError(f"rrss_path: fixed: {k} must be a finite number, got {v!r}")
    eqs, unknowns, given = table_2_3(n)
    if len(fixed) != given:
        raise InputError(f"rrss_path: {n} points give {eqs} equations in {unknowns} unknowns (Table 2-3): give "
                         f"exactly {given} coordinates in 'fixed', got {len(fixed)}")
    if n == MOST:
        raise InputError("rrss_path: 8 points (nothing given) do not split into chain and link (the chain keeps one "
                         "free choice, the S-S link meets 7 conditions with 6 unknowns); the methods here solve 2 "
                         "to 7 points")
    if not starts >= 1:
        raise InputError(f"rrss_path: starts must be a positive integer, got {starts!r}")
    chain_fixed, link_fixed = _split(n, fixed)
    # normalised coordinates: centred on the points' mean, scaled by their spread
    centre = P.mean(0)
    size = max(1e-300, float(np.max(np.linalg.norm(P - centre, axis=1))))
    Q = (P - centre) / size

    def inward(k, v):
        return v if k[0] == "u" else (v - centre["xyz".index(k[-1])]) / size

    inner = {k: inward(k, v) for k, v in chain_fixed.items()}
    chain = _Chain(Q, inner)
    rng = np.random.default_rng(seed)
    axes = _axes(Q, inner) if method in ("auto", "conic") else None
    if axes is None and method == "conic":
        raise InputError("rrss_path: method 'conic' needs the chain's givens on the fixed axis: a0x, a0y, a0z and "
                         "2 of u0x, u0y, u0z (n = 4), a0 and 1 of u0 (n = 5), a0 (n = 6), or 2 of a0 (n = 7); got "
                         f"{', '.join(chain_fixed) or 'none'} at n = {n}")
    if axes is not None:
        method = "conic"
        z0 = _conic_chains(Q, inner, axes, chain)
        tried = len(z0)
        z, worst = _lm(chain, z0, tol, 30) if tried else (z0, np.zeros(0))
    else:
        method = "seeded"
        tried = int(starts)
        z, worst = _lm(chain, chain.starts(tried, rng), tol)
    ok = np.flatnonzero(worst < tol)
    given_link = {k: inward(k, v) for k, v in link_fixed.items()}
    chains, seen = [], []
    for k in ok:
        x, phi = chain.full(z[k:k + 1])
        u0, u1 = x[0, 0:3], x[0, 6:9]
        if abs(abs(float(u0 @ u1)) / (np.linalg.norm(u0) * np.linalg.norm(u1)) - 1) < 1e-6:
            continue                                       # parallel axes: no common normal
        key = x[0].copy()
        for c in (0, 6):                                   # the axes' signs are immaterial
            key[c:c + 3] *= np.sign(key[c + int(np.argmax(np.abs(key[c:c + 3])))])
        if any(np.max(np.abs(key - other)) < 1e-9 for other in seen):
            continue
        seen.append(key)
        theta = chain.exact_angles(x, phi)
        chains.append((x[0], theta[0], phi[0], _poses(Q, x[0], theta[0], phi[0])))
    if n >= 6 and all(k.startswith("b0") for k in given_link):
        pairs = _sphere_centres([c[3] for c in chains], given_link) if chains else []
    else:
        pairs = [_links(c[3], given_link, seed) for c in chains]
    found: list[RRSSSolution] = []
    for (x, theta, phi, moves), got in zip(chains, pairs):
        for b0, b1 in got:
            sol = _solution(x, b0, b1, theta, phi, moves, Q, centre, size)
            if sol is None or any(sol.distance(o.values()) < 1e-6 * max(1.0, size) for o in found):
                continue
            found.append(sol)
    if check:
        found = [_checked(s, P) for s in found]
    worst_res = max((s.residual for s in found), default=math.nan)
    status = Status.COMPLETE if found else Status.EMPTY
    what = "starts" if method == "seeded" else "closed-form chains"
    message = (f"{len(found)} distinct RRSS through {n} points ({len(ok)} of {tried} {what} converged; worst "
               f"residual {worst_res:.2g})" if found else
               f"no RRSS found through {n} points ({len(ok)} of {tried} {what} converged)"
               + (": try more starts" if method == "seeded" else ""))
    return RRSSPath(tuple(found), status, message, method, tried, int(len(ok)), worst_res)


def _conic_chains(Q: np.ndarray, inner: dict[str, float], axes, chain: _Chain) -> np.ndarray:
    """Starts ``[free chain coordinates, φ_j]`` for the full chain system from the fixed axes of :func:`_axes`:
    each axis polished on :class:`_Axis`, then its closed-form chains (:func:`_circles`)."""
    ax = _Axis(Q, inner)
    if not axes:
        return np.zeros((0, chain.size))
    X = np.array(axes)
    z, _ = _lm(ax, np.concatenate([X[:, ax.free], _kappa(ax, X)], 1), 1e-15, 20)
    chains = []
    for i in range(len(z)):
        x, kappa = ax.split(z[i:i + 1])
        if np.all(np.isfinite(x)):
            chains += _circles(Q, x[0, :3], x[0, 3:6], kappa[0])
    if not chains:
        return np.zeros((0, chain.size))
    C = np.array(chains)
    return np.concatenate([C[:, chain.free], chain.angles(C)[1]], 1)


def _links(moves, given: dict[str, float], seed: int):
    if all(f"b0{c}" in given for c in "xyz") and len(given) == 3:
        b0 = np.array([given[f"b0{c}"] for c in "xyz"])
        A = np.array([2 * (C.T @ (d - b0) + b0) for C, d in moves[1:]])
        r = np.array([2 * d @ b0 - d @ d for _, d in moves[1:]])
        if np.linalg.matrix_rank(A, 1e-10) < 3:
            return []
        return [(b0, np.linalg.lstsq(A, r, rcond=None)[0])]
    if len(moves) == 5 and len(given) == 2 and all(k.startswith("b0") for k in given):
        return _sphere_pairs(moves, given)
    if len(moves) >= 6 and all(k.startswith("b0") for k in given):
        return _sphere_centres([moves], given)[0]
    names = {f"b0{c}": f"a0{c}" for c in "xyz"} | {f"b1{c}": f"a1{c}" for c in "xyz"}
    got = links.guiding_links("S-S", moves, fixed={names[k]: v for k, v in given.items()}, seed=seed)
    return [(g.a0, g.a1) for g in got]


def _solution(x, b0, b1, theta, phi, moves, Q, centre, size):
    u0, a0, u1, a1 = x[0:3] / np.linalg.norm(x[0:3]), x[3:6], x[6:9] / np.linalg.norm(x[6:9]), x[9:12]
    if np.linalg.norm(b1 - b0) < 1e-9:
        return None
    out = lambda v: v * size + centre  # noqa: E731
    rotations = tuple(C for C, _ in moves)
    sol = RRSSSolution(u0, out(a0), u1, out(a1), out(b0), out(b1), out(Q[0]), (0.0,) + tuple(map(float, theta)),
                       (0.0,) + tuple(map(float, phi)), rotations)
    P = Q * size + centre
    res = float(np.max(np.abs(book_residuals(sol.values(), rotations, P))))
    world = [(C, d * size + centre - C @ centre) for C, d in moves]
    lc = max(links.check(links.Link("R-R", sol.a0, sol.a1, u0, u1, 0.0), world),
             links.check(links.Link("S-S", sol.b0, sol.b1, None, None, 0.0), world)) / size
    return RRSSSolution(**{**sol.__dict__, "residual": res, "link_check": lc})


def _checked(sol: RRSSSolution, P) -> RRSSSolution:
    err, why = path_errors(sol, P)
    return RRSSSolution(**{**sol.__dict__, "path_error": err, "reach": why})


# -- mechanisms ----------------------------------------------------------------------------------------

def _foot(a, v, b, u):
    """The foot on line ``(a, v)`` of its common normal with line ``(b, u)`` (unit directions)."""
    c = float(u @ v)
    w = a - b
    return a + ((c * float(u @ w) - float(v @ w)) / (1 - c * c)) * v


def rrss_mechanism(u0, a0, u1, a1, b0, b1, p1, name: str = "RRSS (seed 002 §2-3 path generation)") -> SpatialMechanism:
    """The RRSS in position 1: R joint ``A0`` (frame–crank, axis ``u0`` at ``a0``, the input), R joint ``A``
    (crank–coupler, ``u1`` at ``a1``), S joints ``B`` (coupler–rod at ``b1``) and ``B0`` (rod–frame at ``b0``),
    coupler point ``P`` at ``p1``.

    >>> m = planted_example()
    >>> [j.kind for j in m.joints], m.dof - m.idle
    (['R', 'R', 'S', 'S'], 1)
    """
    f = lambda v: tuple(float(c) for c in v)  # noqa: E731
    joints = (SpatialJoint("A0", "R", ("frame", "crank"), f(a0), f(u0)),
              SpatialJoint("A", "R", ("crank", "coupler"), f(a1), f(u1)),
              SpatialJoint("B", "S", ("coupler", "rod"), f(b1)),
              SpatialJoint("B0", "S", ("rod", "frame"), f(b0)))
    return SpatialMechanism.build(name, ("frame", "crank", "coupler", "rod"), "frame", joints, (SpatialInput("A0"),),
                                  (SpatialPoint("P", "coupler", f(p1)),))


def first_position(mech: SpatialMechanism) -> dict[str, float]:
    """The 18 first-position coordinates (:data:`NAMES`) of an RRSS built by :func:`rrss_mechanism`, with ``a0``
    and ``a1`` moved to the feet of the axes' common normal (the book's gauge).

    >>> sorted(first_position(planted_example()))[:3]
    ['a0x', 'a0y', 'a0z']
    """
    j = {x.name: x for x in mech.joints}
    u0, u1 = np.array(j["A0"].axis), np.array(j["A"].axis)
    if abs(abs(float(u0 @ u1)) - 1) < 1e-12:
        raise InputError("the two R axes are parallel: their common normal, and the feet a0, a1, are not defined")
    a0 = _foot(np.array(j["A0"].at), u0, np.array(j["A"].at), u1)
    a1 = _foot(np.array(j["A"].at), u1, np.array(j["A0"].at), u0)
    values = np.concatenate([u0, a0, u1, a1, j["B0"].at, j["B"].at])
    return {nm: float(v) for nm, v in zip(NAMES, values)}


#: The largest turn of the input between two Newton solves of the spatial solver when walking a branch (rad).
STEP = math.radians(5.0)


def _walk(mech: SpatialMechanism, thetas, step: float = STEP):
    """States of ``mech`` at the inputs ``thetas`` (rad, the drawn pose 0) on the branch of the drawn pose: on
    each side of 0 the spatial solver's Newton (:meth:`~domes.motion.spatial.loops.Loops.positions`) walks out
    in turns of at most ``step`` (halved where Newton fails, down to ``step / 64``), each from the last pose,
    through the points in order. Raises NumericalError where Newton finds no pose (a limit of the input) before
    a point."""
    from domes.motion.spatial.loops import Loops

    kin = Loops(mech)
    thetas = [float(t) for t in thetas]
    out: dict[int, object] = {}
    for side in (1.0, -1.0):
        mine = sorted((k for k, t in enumerate(thetas) if t * side > 0), key=lambda k: abs(thetas[k]))
        state, at = kin.drawn(), 0.0
        for k in mine:
            h = step
            while at != thetas[k]:
                t = thetas[k] if abs(thetas[k] - at) <= h else at + math.copysign(h, thetas[k] - at)
                try:
                    state, at, h = kin.positions({"A0": t}, state)[0], t, min(step, 2 * h)
                except NumericalError as exc:
                    if h < step / 64:
                        raise NumericalError(f"{mech.name}: the input A0 does not reach {math.degrees(thetas[k]):.6g}"
                                             f"° from position 1 (no pose at {math.degrees(t):.6g}°)",
                                             kind="limit") from exc
                    h /= 2
            out[k] = state
    for k, t in enumerate(thetas):
        if k not in out:
            out[k] = kin.positions({"A0": t}, kin.drawn())[0]
    return kin, [out[k] for k in range(len(thetas))]


def trace(mech: SpatialMechanism, thetas) -> tuple[np.ndarray, list[float]]:
    """The coupler point ``P`` at the inputs ``thetas`` (rad) by the spatial solver, on the branch of position 1:
    ``(points, inputs)``.

    >>> pts, _ = trace(planted_example(), [0.0, 0.2])
    >>> pts.shape
    (2, 3)
    """
    kin, states = _walk(mech, thetas)
    return np.array([kin.places(s)["P"] for s in states]), [float(t) for t in thetas]


def planted_example() -> SpatialMechanism:
    """A fixed, non-degenerate RRSS (the doctests' and docs' example)."""
    return rrss_mechanism((-0.25, -0.95, -0.17), (-0.13, -0.59, -0.35), (-1.0, 0.02, -0.03), (-0.16, -0.77, 0.70),
                          (0.65, -3.76, -0.26), (0.78, -0.2, -0.9), (-1.24, -0.59, -0.19))


__all__ = ["METHODS", "MOST", "NAMES", "RRSSPath", "RRSSSolution", "book_residuals", "first_position", "path_errors",
           "planted_example", "rrss_mechanism", "rrss_path", "table_2_3", "trace"]
