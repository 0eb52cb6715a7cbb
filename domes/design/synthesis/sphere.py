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
form (the circumcentre on the sphere, (2-92)-(2-96)).

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


__all__ = ["Crank", "Rigidity", "SphericalFourBar", "centre_point_curve", "crank_with", "function_rotation",
           "function_rotation_printed", "function_three", "rigidity", "rot", "rotations"]
