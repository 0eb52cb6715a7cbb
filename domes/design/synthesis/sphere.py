"""Spherical synthesis (seed 002 §2-3, digest A.3.3 and A.3.4): guidance by cranks, function generation.

**Input data checked.** A spherical motion measured as two body points
``p, p'`` per position (Example 3, the hip orthosis) is rigid only if every
point stays on the unit sphere and ``p·p'`` keeps its value; the rotations
``D1j = [p_j, p'_j, p_j × p'_j][p_1, p'_1, p_1 × p'_1]⁻¹`` (2-86, with the third
point ``p × p'``) are then orthogonal. :func:`rotations` measures all three
and refuses data that is not rigid, with its size (Example 3 as printed,
``p1y = 0.483820``, is off by 4.8e-4; the digest's correction 0.482820 is
rigid to 2e-6).

**Guidance by a spherical crank** (fixed pivot ``a0``, moving pivot ``a1``
on the unit sphere, (2-90)-(2-91)). Since each ``D1j`` is a rotation,
``|D1j a1 − a0| = |a1 − a0|`` is ``a1 · (D1jᵀ a0 − a0) = 0``: for four
positions ``a1`` is orthogonal to three vectors, which needs
``det[D1jᵀ a0 − a0]_{j=2..4} = 0``: the centre-point curve, a cone through
the sphere's centre, closed on the sphere. :func:`crank_with` fixes one
coordinate of ``a0`` (as the book did: ``a0x = −0.25``) and returns every
crank on that circle; :func:`centre_point_curve` traces the whole family.

**Function generation** (Fig. 2-20): input axis x, output axis
``u = (cos α, sin α, 0)``; by inversion the input crank's motion relative to
the output is ``D_R = Rot(u, −φ) Rot(x, θ)`` (2-110, with the digest's four
corrected elements); three precision points give the moving pivot in closed
form (the circumcentre on the sphere, (2-92)-(2-96)). For unit pivots the
constant coupler (2-109) is ``a1ᵀ(D_Rᵀ − I) b1 = 0``, bilinear:
:func:`function_generator` eliminates ``a1`` and solves 3 to 5 precision
points (α given) exhaustively, 6 (α found) by a seeded sweep over α, and
checks every solution with the closed-form analysis of
:mod:`domes.motion.spatial.spherical`. Measured data is first fitted and
normalised by :mod:`domes.design.synthesis.spherefit` ((2-87)-(2-89)).

>>> import numpy as np
>>> D = function_rotation(0.7, 0.3, 0.2)
>>> bool(np.allclose(D @ D.T, np.eye(3))), round(float(np.linalg.det(D)), 12)
(True, 1.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq, least_squares

from domes.design.synthesis.spherical import centre_points_three
from domes.errors import InputError
from domes.results import Listing, Status

#: Measured data is rigid enough when every check is below this.
RIGID = 1e-4


@dataclass(frozen=True)
class Rigidity:
    """How far measured positions are from a rigid spherical motion: the largest ``|p| − 1``, the largest
    change of ``p·p'``, and the largest ``|D Dᵀ − I|`` of the rebuilt rotations (at which position, and
    ``by_position``: each ``D1j``'s, the first 0)."""

    norm: float
    angle: float
    orthogonality: float
    worst: int
    by_position: tuple[float, ...] = ()

    @property
    def rigid(self) -> bool:
        return max(self.norm, self.angle, self.orthogonality) <= RIGID

    @property
    def message(self) -> str:
        return (f"|p| − 1 up to {self.norm:.2g}, p·p' changes by up to {self.angle:.2g}, the rotations are "
                f"orthogonal to {self.orthogonality:.2g} (worst at position {self.worst})")


def check_frames(p, q) -> None:
    """An InputError naming the first position whose points ``p``, ``q`` do not fix the body: one of them at the
    sphere's centre, or both on one line through it (``q = p``, ``q = −p``), so that ``[p, q, p × q]`` is singular."""
    for j, (pj, qj) in enumerate(zip(p, q), 1):
        if not (np.all(np.isfinite(pj)) and np.all(np.isfinite(qj))):
            raise InputError(f"position {j}: p and q must be finite numbers")
        for name, v in (("p", pj), ("q", qj)):
            if np.linalg.norm(v) <= 1e-9:
                raise InputError(f"position {j}: {name} is at the sphere's centre; give a point on the unit sphere")
        sine = np.linalg.norm(np.cross(pj, qj)) / (np.linalg.norm(pj) * np.linalg.norm(qj))
        if sine <= 1e-6:
            same = np.linalg.norm(pj - qj) <= 1e-6 * np.linalg.norm(pj)
            what = "one point" if same else "on one line through the sphere's centre"
            raise InputError(f"position {j}: p and q are {what}, so they do not fix the body's rotation; measure q "
                             "at another point of the body")


def rigidity(p, q) -> Rigidity:
    """Check positions ``p[j], q[j]`` (two body points per position) for a rigid motion about the origin."""
    p, q = (np.asarray(x, dtype=float) for x in (p, q))
    if p.shape != q.shape or p.ndim != 2 or p.shape[1] != 3 or p.shape[0] < 2:
        raise InputError("two body points per position, each (x, y, z), for two or more positions")
    check_frames(p, q)
    norms = np.abs(np.concatenate([np.linalg.norm(p, axis=1), np.linalg.norm(q, axis=1)]) - 1.0)
    dots = np.einsum("ij,ij->i", p, q)
    first = np.column_stack([p[0], q[0], np.cross(p[0], q[0])])
    orth = [0.0]
    for j in range(1, len(p)):
        D = np.column_stack([p[j], q[j], np.cross(p[j], q[j])]) @ np.linalg.inv(first)
        orth.append(float(np.max(np.abs(D @ D.T - np.eye(3)))))
    worst = int(np.argmax(np.maximum(orth, np.abs(dots - dots[0]))))
    return Rigidity(float(norms.max()), float(np.max(np.abs(dots - dots[0]))), float(max(orth)), worst + 1,
                    tuple(orth))


def rotations(p, q) -> list[np.ndarray]:
    """The rotations ``D1j`` (j = 1..n, the first the identity) of measured positions, (2-86) with ``r = p × p'``.

    Raises :class:`~domes.errors.InputError` when the data is not a rigid motion, saying by how much."""
    check = rigidity(p, q)
    if not check.rigid:
        raise InputError(f"the positions are not a rigid spherical motion: {check.message}; check the data "
                         f"(a digit misread?) before synthesis")
    p, q = (np.asarray(x, dtype=float) for x in (p, q))
    first = np.column_stack([p[0], q[0], np.cross(p[0], q[0])])
    return [np.column_stack([p[j], q[j], np.cross(p[j], q[j])]) @ np.linalg.inv(first) for j in range(len(p))]


@dataclass(frozen=True)
class Crank:
    """A spherical crank: fixed pivot ``a0`` and moving pivot ``a1`` (first position), unit vectors; ``spread``:
    the largest difference of ``|a_j − a0|`` over the positions (0 for an exact solution)."""

    a0: np.ndarray
    a1: np.ndarray
    spread: float

    @property
    def arc(self) -> float:
        """The crank's angle ``∠(a0, a1)`` (rad)."""
        return float(math.acos(max(-1.0, min(1.0, float(self.a0 @ self.a1)))))


def _condition(Ds, a0) -> np.ndarray:
    return np.array([D.T @ a0 - a0 for D in Ds[1:]])


def _determinant(Ds, a0) -> float:
    return float(np.linalg.det(_condition(Ds, a0)))


def _moving(Ds, a0, toward) -> np.ndarray:
    rows = _condition(Ds, a0)
    _, _, vt = np.linalg.svd(rows)
    a1 = vt[-1]
    return a1 if a1 @ toward >= 0 else -a1


def _polish(Ds, a0, a1, fixed: int) -> Crank:
    """Solve (2-90), (2-91) exactly (least squares: the rotations may be rigid only to the data's digits)."""
    value = a0[fixed]
    free = [k for k in range(3) if k != fixed]

    def residual(x):
        b0 = np.empty(3)
        b0[fixed] = value
        b0[free] = x[:2]
        b1 = x[2:]
        r = [np.linalg.norm(D @ b1 - b0) - np.linalg.norm(b1 - b0) for D in Ds[1:]]
        return np.array(r + [b1 @ b1 - 1.0, b0 @ b0 - 1.0])

    fit = least_squares(residual, np.concatenate([a0[free], a1]), xtol=1e-15, ftol=1e-15, gtol=1e-15)
    b0 = np.empty(3)
    b0[fixed] = value
    b0[free] = fit.x[:2]
    b1 = fit.x[2:]
    lengths = [np.linalg.norm(D @ b1 - b0) for D in Ds]
    return Crank(b0, b1, float(np.ptp(lengths)))


def crank_with(Ds, coordinate: str, value: float, toward=None, samples: int = 3600) -> list[Crank]:
    """Every crank for four positions (rotations ``Ds``, the first the identity) whose fixed pivot has the given
    coordinate (``"x"``, ``"y"`` or ``"z"``): the roots of the centre-point condition on that circle of the
    sphere, polished on (2-90)-(2-91). ``toward``: the moving pivot is taken on this side (default: the first
    position's mean body direction is not known here, so ``+z``)."""
    if len(Ds) != 4:
        raise InputError(f"a spherical crank meets four positions with one free choice; got {len(Ds)} positions")
    k = "xyz".index(coordinate)
    if not -1.0 < value < 1.0:
        raise InputError(f"a0{coordinate} = {value} does not cut the unit sphere in a circle")
    toward = np.array([0.0, 0.0, 1.0]) if toward is None else np.asarray(toward, dtype=float)
    r = math.sqrt(1 - value * value)
    i, j = [m for m in range(3) if m != k]

    def point(t):
        a = np.empty(3)
        a[k], a[i], a[j] = value, r * math.cos(t), r * math.sin(t)
        return a

    ts = np.linspace(0.0, 2 * math.pi, samples + 1)
    f = np.array([_determinant(Ds, point(t)) for t in ts])
    out = []
    for n in np.flatnonzero(np.sign(f[1:]) != np.sign(f[:-1])):
        t = brentq(lambda x: _determinant(Ds, point(x)), ts[n], ts[n + 1], xtol=1e-15)
        a0 = point(t)
        out.append(_polish(Ds, a0, _moving(Ds, a0, toward), k))
    return out


def centre_point_curve(Ds, samples: int = 181) -> np.ndarray:
    """Points of the centre-point curve on the unit sphere (the fixed pivots of all cranks for four positions):
    the roots on ``samples`` circles ``a0x = c``, ``c`` from −1 to 1 (ends left out). Shape (m, 3)."""
    pts = []
    for c in np.linspace(-1.0, 1.0, samples + 2)[1:-1]:
        r = math.sqrt(1 - c * c)
        ts = np.linspace(0.0, 2 * math.pi, 721)
        a = np.column_stack([np.full(ts.size, c), r * np.cos(ts), r * np.sin(ts)])
        f = np.array([_determinant(Ds, x) for x in a])
        for n in np.flatnonzero(np.sign(f[1:]) != np.sign(f[:-1])):
            t = brentq(lambda x: _determinant(Ds, np.array([c, r * math.cos(x), r * math.sin(x)])), ts[n], ts[n + 1])
            pts.append((c, r * math.cos(t), r * math.sin(t)))
    return np.array(pts).reshape(-1, 3)


# -- function generation ---------------------------------------------------------------------------

def rot(axis, angle: float) -> np.ndarray:
    """The rotation by ``angle`` about the unit ``axis`` (digest F.4)."""
    u = np.asarray(axis, dtype=float)
    k = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return math.cos(angle) * np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * np.outer(u, u)


def function_rotation(alpha: float, theta: float, phi: float) -> np.ndarray:
    """``D_R`` of (2-110) with the digest's corrected elements: the input's turn ``θ`` about x seen from the
    output, which turned ``φ`` about ``u = (cos α, sin α, 0)``."""
    ca, sa, ct, st, cp, sp = (math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta), math.cos(phi),
                              math.sin(phi))
    return np.array([
        [ca * ca + sa * sa * cp, sa * ca * ct * (1 - cp) - sa * st * sp, -sa * ca * st * (1 - cp) - sa * ct * sp],
        [sa * ca * (1 - cp), sa * sa * ct + ca * ca * cp * ct + ca * st * sp, -sa * sa * st - ca * ca * st * cp + ca * ct * sp],
        [sa * sp, st * cp - ca * ct * sp, ct * cp + ca * st * sp]])


def function_rotation_printed(alpha: float, theta: float, phi: float) -> np.ndarray:
    """``D_R`` as the book prints it (four elements wrong: d12, d13, d21, d23); kept to show it is not a
    rotation."""
    D = function_rotation(alpha, theta, phi)
    ca, sa, ct, st, cp, sp = (math.cos(alpha), math.sin(alpha), math.cos(theta), math.sin(theta), math.cos(phi),
                              math.sin(phi))
    D[0, 1] = sa * ca * ct * (1 - cp) - sa * ct * sp
    D[0, 2] = -sa * ca * ct * (1 - cp) - sa * ct * sp
    D[1, 0] = sa * sa * ca * (1 - cp)
    D[1, 2] = -sa * st - ca * ca * st * cp + ca * ct * sp
    return D


@dataclass(frozen=True)
class SphericalFourBar:
    """A spherical function generator: input axis x, output axis ``u(α)``, the input crank's moving pivot ``a1``
    and the output crank's ``b1`` (first position, unit vectors); the coupler is the arc ``a1 b1``."""

    alpha: float
    a1: np.ndarray
    b1: np.ndarray

    @property
    def coupler(self) -> float:
        return float(math.acos(max(-1.0, min(1.0, float(self.a1 @ self.b1)))))


def function_three(alpha: float, thetas, phis, b1) -> list[SphericalFourBar]:
    """Three precision points ``(θ1j, φ1j)`` (j = 1, 2, 3; the first 0, 0) and a chosen output pivot ``b1``: the
    input pivot ``a1`` is the circumcentre on the sphere of ``b1`` and ``D_R,j⁻¹ b1`` (by inversion, (2-109)).
    Both antipodal solutions are returned."""
    thetas, phis = list(thetas), list(phis)
    if len(thetas) != 3 or len(phis) != 3:
        raise InputError("three precision points (θ1j, φ1j), the first (0, 0)")
    b1 = np.asarray(b1, dtype=float)
    if abs(np.linalg.norm(b1) - 1.0) > 1e-9:
        raise InputError("b1 must lie on the unit sphere")
    pts = [function_rotation(alpha, t, f).T @ b1 for t, f in zip(thetas, phis)]
    return [SphericalFourBar(alpha, a, b1) for a in centre_points_three(*pts)]


# -- function generation, three to six precision points ((2-109)-(2-112)) ------------------------------

_X = np.array([1.0, 0.0, 0.0])
_EPS = np.zeros((3, 3, 3))
_EPS[0, 1, 2] = _EPS[1, 2, 0] = _EPS[2, 0, 1] = 1.0
_EPS[0, 2, 1] = _EPS[2, 1, 0] = _EPS[1, 0, 2] = -1.0
#: Monomials of a ternary cubic: index triple (i, j, k) of ``b_i b_j b_k`` → exponents (of x, of y) with z = 1.
_MONO = np.zeros((27, 4, 4))
_MONO[np.arange(27), [e.count(0) for e in np.ndindex(3, 3, 3)], [e.count(1) for e in np.ndindex(3, 3, 3)]] = 1.0
#: Generic rotations of the pivot's coordinates before elimination, so no solution lies at z = 0 or shares its
#: x with another, and generic weights of the four 3 × 3 minors in the two cubics eliminated (fixed, so the
#: solver is deterministic; the second and third set are tried when the first's count fails the parity check).
_GENERIC = [(rot(np.array(axis) / np.linalg.norm(axis), angle), np.array(c), np.array(d)) for axis, angle, c, d in (
    ((0.37, -0.52, 0.77), 1.13, (1.0, 0.61, -0.83, 0.29), (-0.47, 1.0, 0.38, -0.91)),
    ((-0.81, 0.24, 0.53), 2.07, (0.72, -1.0, 0.35, 0.88), (0.93, 0.17, -1.0, 0.41)),
    ((0.12, 0.95, -0.29), 0.71, (-0.66, 0.44, 1.0, -0.23), (0.31, -0.78, 0.52, 1.0)))]
#: Samples of the resultant on the unit circle (its degree is 9; the 6 × 6 determinant's formal degree 18).
_SAMPLES = 32
#: Newton's iterations at most, and the residual it stops at.
_ITERATIONS, _STOP = 40, 1e-15
#: A solution with a pivot this close (rad) to its own axis, or the two axes this close, is degenerate (a crank
#: of 0.06°: the solver finds such near the trivial solutions, which are a whole curve when α is free).
_DEGENERATE = 1e-3
#: Coordinates a user may fix (``fixed=``), by name.
_COORDS = {f"{p}1{c}": (p, k) for p in "ab" for k, c in enumerate("xyz")}


def _axis(alpha):
    alpha = np.asarray(alpha, dtype=float)
    return np.stack([np.cos(alpha), np.sin(alpha), np.zeros_like(alpha)], axis=-1)


def _d_r(alpha, theta, phi):
    """``D_R`` of (2-110) (corrected elements, as :func:`function_rotation`) and its derivative in α, for arrays
    of angles (broadcast): shapes (..., 3, 3)."""
    alpha, theta, phi = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (alpha, theta, phi)))
    ca, sa, ct, st, cp, sp = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta), np.cos(phi), np.sin(phi)
    D = np.stack([
        np.stack([ca * ca + sa * sa * cp, sa * ca * ct * (1 - cp) - sa * st * sp,
                  -sa * ca * st * (1 - cp) - sa * ct * sp], -1),
        np.stack([sa * ca * (1 - cp), sa * sa * ct + ca * ca * cp * ct + ca * st * sp,
                  -sa * sa * st - ca * ca * st * cp + ca * ct * sp], -1),
        np.stack([sa * sp, st * cp - ca * ct * sp, ct * cp + ca * st * sp], -1)], -2)
    # D = Rot(u, −φ) Rot(x, θ); Rot(u, −φ) = cos φ I − sin φ [u]× + (1 − cos φ) u uᵀ, differentiated in α
    u = _axis(alpha)
    du = np.stack([-sa, ca, np.zeros_like(sa)], -1)
    cross = np.zeros(du.shape + (3,))
    cross[..., 0, 1], cross[..., 0, 2], cross[..., 1, 2] = -du[..., 2], du[..., 1], -du[..., 0]
    cross[..., 1, 0], cross[..., 2, 0], cross[..., 2, 1] = du[..., 2], -du[..., 1], du[..., 0]
    dR = (-sp[..., None, None] * cross
          + (1 - cp)[..., None, None] * (du[..., :, None] * u[..., None, :] + u[..., :, None] * du[..., None, :]))
    Rx = np.zeros(theta.shape + (3, 3))
    Rx[..., 0, 0] = 1.0
    Rx[..., 1, 1], Rx[..., 1, 2], Rx[..., 2, 1], Rx[..., 2, 2] = ct, -st, st, ct
    return D, dR @ Rx


def _conditions(alpha, theta, phi):
    """``M_j = D_R,jᵀ − I`` (the conditions ``a1ᵀ M_j b1 = 0``, (2-109) for unit vectors) and ``dM_j/dα``."""
    D, dD = _d_r(alpha, theta, phi)
    return np.swapaxes(D, -1, -2) - np.eye(3), np.swapaxes(dD, -1, -2)


def _null(rows):
    """The unit vector most nearly orthogonal to the rows (..., m, 3)."""
    return np.linalg.svd(rows)[2][..., -1, :]


def _five_seeds(M, variant: int = 0):
    """Every pair ``(a1, b1)`` (up to sign) with ``a1ᵀ M_j b1 = 0`` for four conditions ``M`` (..., 4, 3, 3).

    ``b1`` makes the 4 × 3 matrix of rows ``(M_j b1)ᵀ`` rank-deficient: its four 3 × 3 minors, cubics in
    ``b1``, vanish (at 6 points, Bézout for a 4 × 3 determinantal set; one is the trivial ``b1 = u``). Two
    generic combinations of the minors are eliminated: with ``b1 = G (x, y, 1)`` (``G`` a generic rotation)
    their resultant in ``y`` (6 × 6 Sylvester determinant) is a polynomial of degree 9 in ``x``, found from
    samples on the unit circle by FFT. Its 9 roots are the 6 solutions and 3 extra where only the two
    combinations vanish; all are returned (unrefined, real parts), the caller's Newton step and residual check
    sort them. ``variant`` picks one of the constant sets :data:`_GENERIC`. Returns ``a, b`` of shape
    (..., 9, 3) (NaN where a root is complex)."""
    batch = M.shape[:-3]
    rotation, c, d = _GENERIC[variant]
    K = M @ rotation
    minors = np.stack([np.einsum("ijk,...ia,...jb,...kc->...abc", _EPS, K[..., p, :, :], K[..., q, :, :],
                                 K[..., r, :, :]) for p, q, r in ((1, 2, 3), (0, 2, 3), (0, 1, 3), (0, 1, 2))], -4)
    TF = np.einsum("k,...kabc->...abc", c, minors)
    TG = np.einsum("k,...kabc->...abc", d, minors)
    f = np.einsum("...t,tpq->...pq", TF.reshape(batch + (27,)), _MONO)
    g = np.einsum("...t,tpq->...pq", TG.reshape(batch + (27,)), _MONO)

    def sylvester(x):
        powers = x[..., None] ** np.arange(4)
        fq = np.einsum("...p,...pq->...q", powers, f[..., None, :, :])
        gq = np.einsum("...p,...pq->...q", powers, g[..., None, :, :])
        S = np.zeros(x.shape + (6, 6), dtype=np.result_type(x, float))
        for s in range(3):
            S[..., s, s:s + 4] = fq
            S[..., 3 + s, s:s + 4] = gq
        return S

    z = np.exp(2j * np.pi * np.arange(_SAMPLES) / _SAMPLES)
    zs = np.broadcast_to(z, batch + (_SAMPLES,))
    coef = np.fft.fft(np.linalg.det(sylvester(zs)), axis=-1) / _SAMPLES
    coef = coef[..., :10].real
    flat = coef.reshape(-1, 10)
    roots = np.full((len(flat), 9), np.nan + 0j)
    for n, c in enumerate(flat):
        r = np.roots(c[::-1]) if np.any(c) else np.array([])
        roots[n, :len(r)] = r
    roots = roots.reshape(batch + (9,))
    real = np.abs(roots.imag) <= 1e-3 * (1.0 + np.abs(roots))
    x = np.where(real, roots.real, 0.0)
    S = sylvester(x)
    w = np.linalg.svd(S)[2][..., -1, :]
    y = np.einsum("...i,...i->...", w[..., :-1], w[..., 1:]) / np.einsum("...i,...i->...", w[..., :-1], w[..., :-1])
    point = np.stack([x, y, np.ones_like(x)], -1)
    b = point @ rotation.T
    b /= np.linalg.norm(b, axis=-1, keepdims=True)
    rows = np.einsum("...jmn,...rn->...rjm", M, b)
    a = _null(rows)
    bad = ~real | ~np.isfinite(b).all(-1) | ~np.isfinite(a).all(-1)
    a[bad], b[bad] = np.nan, np.nan
    return a, b


def _newton(a, b, alpha, theta, phi, free_alpha: bool, fixed: list[tuple[str, int, float]]):
    """Newton's method on (2-109), (2-111), (2-112) (and fixed coordinates) from many starts at once: ``a, b``
    (S, 3), ``alpha`` (S,). Returns ``a, b, alpha`` refined and each start's largest residual."""
    S = len(a)
    if S == 0:
        return a, b, np.asarray(alpha, dtype=float), np.zeros(0)
    z = np.concatenate([a, b] + ([alpha[:, None]] if free_alpha else []), axis=1)
    n_eq = len(theta) + 2 + len(fixed)
    n_var = z.shape[1]
    M0 = None if free_alpha else _conditions(alpha[:1, None], theta, phi)[0][0]
    active = np.arange(S)
    for _ in range(_ITERATIONS):
        if not active.size:
            break
        S = active.size
        a, b = z[active, :3], z[active, 3:6]
        if free_alpha:
            M, dM = _conditions(z[active, 6:7], theta, phi)
        else:
            M = np.broadcast_to(M0, (S,) + M0.shape)
        r = np.empty((S, n_eq))
        J = np.zeros((S, n_eq, n_var))
        m = len(theta)
        r[:, :m] = np.einsum("si,sjik,sk->sj", a, M, b)
        J[:, :m, :3] = np.einsum("sjik,sk->sji", M, b)
        J[:, :m, 3:6] = np.einsum("si,sjik->sjk", a, M)
        if free_alpha:
            J[:, :m, 6] = np.einsum("si,sjik,sk->sj", a, dM, b)
        r[:, m] = 0.5 * (np.einsum("si,si->s", a, a) - 1)
        r[:, m + 1] = 0.5 * (np.einsum("si,si->s", b, b) - 1)
        J[:, m, :3], J[:, m + 1, 3:6] = a, b
        for e, (pivot, k, value) in enumerate(fixed, m + 2):
            col = k if pivot == "a" else 3 + k
            r[:, e] = z[active, col] - value
            J[:, e, col] = 1.0
        worst = np.max(np.abs(r), axis=1)
        go = (worst > _STOP) & np.isfinite(worst) & (np.max(np.abs(z[active]), axis=1) < 1e3)
        if free_alpha:  # a start heading for the degenerate set (the axes together, a pivot on its axis) is dropped
            go &= ~_degenerate(a, b, z[active, 6])
        active, r, J = active[go], r[go], J[go]
        if not active.size:
            break
        with np.errstate(all="ignore"):
            try:
                step = np.linalg.solve(J, r[..., None])[..., 0]
            except np.linalg.LinAlgError:
                step = np.einsum("svk,sk->sv", np.linalg.pinv(J, rcond=1e-13), r)
        z[active] = np.where(np.isfinite(step), z[active] - step, np.nan)
        active = active[~(np.max(np.abs(step), axis=1) <= 1e-15)]  # converged to rounding
    al = np.asarray(z[:, 6] if free_alpha else alpha, dtype=float)
    with np.errstate(all="ignore"):
        a = z[:, :3] / np.linalg.norm(z[:, :3], axis=1, keepdims=True)
        b = z[:, 3:6] / np.linalg.norm(z[:, 3:6], axis=1, keepdims=True)
    return a, b, al, _residual(a, b, al, theta, phi)


def _degenerate(a, b, alpha):
    """Which (a1, b1, α) are degenerate: a pivot within :data:`_DEGENERATE` of its own axis, or the axes that
    close together (the frame itself, ``a1 = x, b1 = u``, is one)."""
    with np.errstate(all="ignore"):
        a = a / np.linalg.norm(a, axis=-1, keepdims=True)
        b = b / np.linalg.norm(b, axis=-1, keepdims=True)
        return ((np.linalg.norm(np.cross(a, _X), axis=-1) < _DEGENERATE)
                | (np.linalg.norm(np.cross(b, _axis(alpha)), axis=-1) < _DEGENERATE)
                | (np.abs(np.sin(alpha)) < _DEGENERATE))


def _distinct(a, b, alpha, res, tol, flip_a: bool, flip_b: bool) -> list[tuple[np.ndarray, np.ndarray, float, float]]:
    """The distinct solutions ``(a1, b1, α, residual)`` among refined starts with residual ≤ ``tol``, best first;
    ``a1`` (``b1``) turned to within 90° of its axis when ``flip_a`` (``flip_b``): ``±a1`` is one joint axis."""
    out, keys = [], []
    for s in np.argsort(res):
        if not res[s] <= tol:
            break
        x, y, t = a[s].copy(), b[s].copy(), float(alpha[s])
        if flip_a and x[0] < 0:
            x = -x
        if flip_b and y @ _axis(t) < 0:
            y = -y
        key = np.concatenate([x, y, [t]])
        if any(np.max(np.abs(key - other)) < 1e-7 for other in keys):
            continue
        keys.append(key)
        out.append((x, y, t, float(res[s])))
    return out


def _residual(a, b, alpha, theta, phi):
    """Each start's largest ``|a1ᵀ M_j b1|`` (inf where not finite)."""
    with np.errstate(all="ignore"):
        M = _conditions(np.asarray(alpha)[:, None], theta, phi)[0]
        res = np.max(np.abs(np.einsum("si,sjik,sk->sj", a, M, b)), axis=1)
    return np.where(np.isfinite(res), res, np.inf)


def _circle_seeds(M, pivot: str, k: int, value: float, samples: int = 16):
    """Four precision points with one coordinate of one pivot fixed: on that circle of the sphere the 3 × 3
    determinant of the rows ``(M_j b1)ᵀ`` (or ``(M_jᵀ a1)ᵀ``) is a trigonometric cubic, found from samples by
    FFT; its (up to 6) roots are the solutions. Returns ``a, b`` seeds (m, 3)."""
    i, j = [m for m in range(3) if m != k]
    r = math.sqrt(1.0 - value * value)
    Ms = M if pivot == "b" else np.swapaxes(M, -1, -2)

    def on_circle(t):
        p = np.zeros(np.shape(t) + (3,))
        p[..., k], p[..., i], p[..., j] = value, r * np.cos(t), r * np.sin(t)
        return p

    ts = 2 * np.pi * np.arange(samples) / samples
    p = on_circle(ts)
    h = np.linalg.det(np.einsum("jmn,sn->sjm", Ms, p))
    H = np.fft.fft(h) / samples
    poly = np.array([H[m % samples] for m in range(-3, 4)])  # coefficient of z^(m+3)
    if np.max(np.abs(poly)) <= 1e-14 * max(1.0, float(np.max(np.abs(Ms)))):
        raise InputError(f"every point of the circle {pivot}1{'xyz'[k]} = {value:g} meets the four precision "
                         "points: fix a different coordinate")
    roots = np.roots(poly[::-1])
    roots = roots[np.abs(np.abs(roots) - 1.0) <= 1e-3]
    p = on_circle(np.angle(roots))
    other = _null(np.einsum("jmn,sn->sjm", Ms, p))
    return (other, p) if pivot == "b" else (p, other)


@dataclass(frozen=True)
class GeneratorSolution:
    """One spherical function generator and its checks: ``residual`` the largest ``|a1ᵀ(D_R,jᵀ − I) b1|``
    ((2-109), unit vectors); ``error`` the worst ``|ψ(θ_j) − φ_j|`` (rad) when the closed-form analysis
    (:class:`~domes.motion.spatial.spherical.SphericalFourBar`) moves it on its drawn assembly mode;
    ``error_any`` the same with each precision point on its nearer mode (small while ``error`` is not: the
    linkage meets the points only if taken apart, a branch defect)."""

    generator: SphericalFourBar
    residual: float
    error: float
    error_any: float

    @property
    def one_branch(self) -> bool:
        """Whether the drawn assembly mode meets every precision point (to 1e-6 rad)."""
        return self.error <= 1e-6

    def closed_form(self):
        """The linkage as :class:`~domes.motion.spatial.spherical.SphericalFourBar` (input axis x)."""
        from domes.motion.spatial.spherical import SphericalFourBar as ClosedForm

        g = self.generator
        return ClosedForm.make(_X, g.a1, g.b1, _axis(g.alpha))


@dataclass(frozen=True)
class FunctionSynthesis(Listing):
    """The spherical function generators for the precision points (``solutions``, each
    :class:`GeneratorSolution`), ``method`` (how they were found: ``"exhaustive ..."`` or ``"seeded ..."``),
    ``seeds`` (starts refined), ``status`` (``EMPTY`` when no real generator exists), ``degenerate`` (roots
    left out: a pivot on its own axis, as the frame itself ``a1 = x, b1 = u``)."""

    items_field = "solutions"
    solutions: tuple[GeneratorSolution, ...]
    method: str
    seeds: int
    status: Status
    message: str
    degenerate: int = 0

    @property
    def residuals(self) -> tuple[float, ...]:
        return tuple(s.residual for s in self.solutions)

    @property
    def worst_error(self) -> float:
        """The largest output-angle error over the solutions, each on its drawn mode (0 when none)."""
        return max((s.error for s in self.solutions), default=0.0)


def _check_output(alpha: float, a1, b1, theta, phi) -> tuple[float, float]:
    from domes.motion.spatial.spherical import SphericalFourBar as ClosedForm

    mech = ClosedForm.make(_X, a1, b1, _axis(alpha))
    theta = np.concatenate([[0.0], theta])
    phi = np.concatenate([[0.0], phi])
    branch = mech.drawn_branch()
    errs = [np.abs(np.remainder(mech.psi(theta, s) - phi + np.pi, 2 * np.pi) - np.pi) for s in (branch, -branch)]
    errs = [np.where(np.isfinite(e), e, np.inf) for e in errs]
    return float(np.max(errs[0])), float(np.max(np.minimum(*errs)))


def _parse_fixed(fixed, n: int, free_alpha: bool):
    fixed = dict(fixed or {})
    need = 4 + free_alpha - (n - 1)
    coords, vectors = [], {}
    for name, value in fixed.items():
        if name in ("a1", "b1"):
            v = np.asarray(value, dtype=float)
            if v.shape != (3,) or not np.all(np.isfinite(v)) or abs(np.linalg.norm(v) - 1.0) > 1e-9:
                raise InputError(f"fixed {name}: give a unit vector (x, y, z) on the unit sphere")
            vectors[name[0]] = v
        elif name in _COORDS:
            try:
                value = float(value)
            except (TypeError, ValueError):
                value = math.nan
            if not (math.isfinite(value) and -1.0 < value < 1.0):
                raise InputError(f"fixed {name} = {value!r}: a coordinate on the unit sphere, strictly between −1 "
                                 "and 1")
            coords.append((*_COORDS[name], float(value)))
        else:
            raise InputError(f"fixed: unknown name {name!r}; use a1, b1 (unit vectors) or one of "
                             f"{', '.join(_COORDS)}")
    given = len(coords) + 2 * len(vectors)
    if given != need:
        hint = {0: "fix nothing", 1: "fix one coordinate of a pivot, e.g. fixed={'b1x': 0.3}",
                2: "fix one pivot, e.g. fixed={'b1': (0.6, 0.0, 0.8)}"}.get(need, "")
        raise InputError(f"{n} precision points{' with α free' if free_alpha else ''} leave {need} of the "
                         f"pivots' {4 + free_alpha} unknowns to choose, {given} fixed: {hint}")
    if n == 3 and coords:
        raise InputError("three precision points: fix a whole pivot (fixed={'b1': ...} or {'a1': ...}), not "
                         "coordinates")
    return coords, vectors


def function_generator(thetas, phis, alpha: float | None = None, fixed=None, tol: float = 1e-12,
                       grid: int = 60) -> FunctionSynthesis:
    """Spherical four-bar function generators (Fig. 2-20) for 3 to 5 precision pairs ``(θ_j, φ_j)`` with the
    output axis angle ``alpha`` given, or 6 with ``alpha=None`` (found too). Angles in radians; only their
    changes from the first pair count (θ1j, φ1j of (2-104), (2-105)).

    Unknowns ``a1, b1`` on the unit sphere ((2-111), (2-112)), one condition (2-109) per precision point after
    the first, with ``D_R`` of (2-110) (the digest's corrected elements). For unit vectors (2-109) is
    ``a1ᵀ(D_Rᵀ − I) b1 = 0``: bilinear, so with ``b1`` fixed the conditions are linear in ``a1``, which is
    eliminated:

    * 5 points: the 4 × 3 matrix of rows ``(M_j b1)ᵀ`` must be rank-deficient; a resultant of degree 9 gives
      every solution (up to 5 real ones besides the trivial ``a1 = x, b1 = u``, the frame) -- exhaustive;
    * 6 points, α free: α swept over ``grid`` values in (0, π), the 5-point solutions at each as starts of
      Newton's method on all six (α included) -- seeded. Turning the whole linkage by π about the input axis
      maps ``u(α)`` to ``u(−α)`` and gives the same generator, so α is reported in (0, π);
    * 4 points: ``fixed`` one coordinate of ``a1`` or ``b1`` (``{"b1x": 0.2}``, as the book fixed ``a0x``); a
      trigonometric cubic on that circle -- exhaustive;
    * 3 points: ``fixed`` a whole pivot (``{"b1": (x, y, z)}``); the other in closed form, as
      :func:`function_three`.

    ``(±a1, ±b1)`` are the same joint axes and so one linkage; each is returned once, each pivot within 90° of
    its axis unless fixed. Every solution is moved by the closed-form analysis
    (:class:`~domes.motion.spatial.spherical.SphericalFourBar`) to the precision inputs: its ``error``.

    >>> import numpy as np
    >>> a1, b1, alpha = np.array([0.8, 0.6, 0.0]), np.array([0.36, 0.48, 0.8]), 1.2
    >>> from domes.motion.spatial.spherical import SphericalFourBar as Moved
    >>> m = Moved.make((1, 0, 0), a1, b1, (np.cos(alpha), np.sin(alpha), 0))
    >>> th = np.radians([0, 10, 20, 30, 40]); ph = m.psi(th)
    >>> found = function_generator(th, ph, alpha)
    >>> found.method.split(":")[0], any(np.allclose(s.generator.a1, a1) and np.allclose(s.generator.b1, b1)
    ...                                  for s in found)
    ('exhaustive', True)
    """
    th, ph = (np.asarray(x, dtype=float).ravel() for x in (thetas, phis))
    if th.shape != ph.shape:
        raise InputError(f"thetas and phis: one output angle per input angle, got {th.size} and {ph.size}")
    n = th.size
    if not np.all(np.isfinite(th)) or not np.all(np.isfinite(ph)):
        raise InputError("thetas and phis must be finite numbers (radians)")
    free_alpha = alpha is None
    if free_alpha and n != 6:
        raise InputError(f"alpha=None (the output axis angle found too) needs exactly 6 precision points, got {n}")
    if not free_alpha and not 3 <= n <= 5:
        raise InputError(f"with the output axis angle alpha given, 3 to 5 precision points fix the generator "
                         f"(6 with alpha=None); got {n}")
    if not free_alpha:
        try:
            alpha = float(alpha)
        except (TypeError, ValueError):
            raise InputError(f"alpha must be a finite angle (radians), got {alpha!r}") from None
        if not math.isfinite(alpha):
            raise InputError(f"alpha must be a finite angle (radians), got {alpha!r}")
        if abs(math.sin(alpha)) < 1e-6:
            raise InputError(f"alpha = {alpha:g}: the output axis is on the input axis (x); no four-bar")
    if free_alpha and not (isinstance(grid, int) and grid >= 8):
        raise InputError(f"grid: the number of α values swept, an integer ≥ 8, got {grid!r}")
    if not (isinstance(tol, (int, float)) and tol > 0):
        raise InputError(f"tol: the largest residual of (2-109) accepted, a positive number, got {tol!r}")
    theta, phi = th[1:] - th[0], ph[1:] - ph[0]
    for j in range(n):
        for k in range(j):
            if abs(math.remainder(th[j] - th[k], 2 * math.pi)) < 1e-9 and \
                    abs(math.remainder(ph[j] - ph[k], 2 * math.pi)) < 1e-9:
                raise InputError(f"precision points {k + 1} and {j + 1} are the same pair (θ, φ)")
    coords, vectors = _parse_fixed(fixed, n, free_alpha)
    fixed_rows = [(p, k, v) for p, k, v in coords]

    if n == 3:
        pivot, v = next(iter(vectors.items()))
        M = _conditions(alpha, theta, phi)[0]
        rows = M @ v if pivot == "b" else np.einsum("i,jik->jk", v, M)
        other = np.cross(rows[0], rows[1])
        if np.linalg.norm(other) <= 1e-12:
            raise InputError(f"fixed {pivot}1: the two conditions are parallel there; every point of a great "
                             "circle solves them; fix another pivot")
        other /= np.linalg.norm(other)
        a, b = (other, v) if pivot == "b" else (v, other)
        a, b, al = a[None], b[None], np.array([alpha], dtype=float)
        method, seeds = "closed form: the other pivot orthogonal to both conditions (the circumcentre)", 1
        res = _residual(a, b, al, theta, phi)
    elif n == 4:
        pivot, k, value = coords[0]
        M = _conditions(alpha, theta, phi)[0]
        a, b = _circle_seeds(M, pivot, k, value)
        method = f"exhaustive: trigonometric cubic on the circle {pivot}1{'xyz'[k]} = {value:g}, roots refined"
        seeds = len(a)
        a, b, al, res = _newton(a, b, np.full(len(a), float(alpha)), theta, phi, False, fixed_rows)
    elif n == 5:
        # the 5 roots besides the frame's are real or complex pairs: an even count of real ones means a root
        # was lost (two close together); the elimination is then repeated with other generic constants
        M = _conditions(alpha, theta, phi)[0]
        parts, seeds = [], 0
        for variant in range(len(_GENERIC)):
            a, b = _five_seeds(M, variant)
            keep = np.isfinite(a).all(1)
            seeds += int(np.count_nonzero(keep))
            parts.append(_newton(a[keep], b[keep], np.full(int(np.count_nonzero(keep)), float(alpha)), theta, phi,
                                 False, []))
            a, b, al, res = (np.concatenate(x) for x in zip(*parts))
            trivial = ((np.linalg.norm(np.cross(a, _X), axis=-1) < 1e-8)
                       & (np.linalg.norm(np.cross(b, _axis(al)), axis=-1) < 1e-8))
            if len(_distinct(a[~trivial], b[~trivial], al[~trivial], res[~trivial], tol, True, True)) % 2:
                break
        method = (f"exhaustive: resultant of degree 9 of two cubics in b1, roots refined by Newton (parity check: "
                  f"{variant + 1} elimination{'s' if variant else ''})")
    else:
        grid_alpha = (np.arange(grid) + 0.5) * np.pi / grid
        M = _conditions(grid_alpha[:, None], theta[:4], phi[:4])[0]
        a, b = _five_seeds(M)
        al = np.broadcast_to(grid_alpha[:, None], a.shape[:2])
        a, b, al = a.reshape(-1, 3), b.reshape(-1, 3), al.reshape(-1)
        u = _axis(al)
        keep = np.isfinite(a).all(1) & ~((np.abs(a[:, 0]) > 1 - 1e-6) & (np.abs(np.einsum("si,si->s", b, u)) >
                                                                           1 - 1e-6))
        a, b, al = a[keep], b[keep], al[keep]
        method = (f"seeded: α swept over {grid} values in (0, π), the exhaustive 5-point solutions at each "
                  "refined by Newton on all six")
        seeds = len(a)
        a, b, al, res = _newton(a, b, al, theta, phi, True, [])
        al = np.remainder(al + np.pi, 2 * np.pi) - np.pi
        # turning the whole linkage by π about the input axis maps u(α) to u(−α): the same generator
        flip = al < 0
        a[flip] *= [1.0, -1.0, -1.0]
        b[flip] *= [1.0, -1.0, -1.0]
        al[flip] = -al[flip]

    flat = _degenerate(a, b, al) if len(al) else np.zeros(0, dtype=bool)
    degenerate = len(_distinct(a[flat], b[flat], al[flat], res[flat], tol, True, True))
    flip_a = "a" not in vectors and not any(p == "a" for p, _, _ in coords)
    flip_b = "b" not in vectors and not any(p == "b" for p, _, _ in coords)
    solutions: list[GeneratorSolution] = []
    for x, y, t, r in _distinct(a[~flat], b[~flat], al[~flat], res[~flat], tol, flip_a, flip_b):
        error, error_any = _check_output(t, x, y, theta, phi)
        solutions.append(GeneratorSolution(SphericalFourBar(t, x, y), r, error, error_any))
    count = len(solutions)
    status = Status.COMPLETE if count else Status.EMPTY
    worst = max((s.error for s in solutions), default=0.0)
    defects = sum(not s.one_branch for s in solutions)
    message = (f"{n} precision points{', α found' if free_alpha else ''}: {count} generator"
               f"{'' if count == 1 else 's'} ({method.split(':')[0]}, {seeds} start{'' if seeds == 1 else 's'})"
               + (f"; worst output error {worst:.2g} rad" if count else "; no real solution")
               + (f"; {defects} meet the points only on the other assembly mode" if defects else "")
               + (f"; {degenerate} degenerate root{'' if degenerate == 1 else 's'} (a pivot on its own axis) left "
                  "out" if degenerate else ""))
    return FunctionSynthesis(tuple(solutions), method, seeds, status, message, degenerate)


__all__ = ["Crank", "FunctionSynthesis", "GeneratorSolution", "Rigidity", "SphericalFourBar", "centre_point_curve",
           "crank_with", "function_generator", "function_rotation", "function_rotation_printed", "function_three",
           "rigidity", "rot", "rotations"]
