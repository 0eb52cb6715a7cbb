"""Measured spherical motion: the sphere through the points and normalisation (seed 002 §2-3, (2-87)-(2-89);
digest A.3.3 (2)).

A body point of a spherical motion stays on a sphere about the motion's
centre. Four of its positions fix that sphere: the determinant (2-87)
expands to (2-88)

    x² + y² + z² + A x + B y + C z + D = 0,

linear in ``A, B, C, D``; the centre is ``c = −(A, B, C)/2`` and
``R² = |c|² − D`` (2-89). With more than four (measured, noisy) points
:func:`fit_sphere` solves (2-88) by linear least squares (the algebraic fit)
and refines it by geometric least squares (the sum of squared distances
``|p − c| − R``). Points on one plane (or one circle) fix no sphere and are
refused.

Several body points of one motion (the hip orthosis of Example 3 measures
two) lie on concentric spheres: :func:`fit_motion` fits their one centre and a
radius each. :func:`normalise` then maps by (2-89): shift by the centre and
divide by ``R`` (the first body point's), so the motion takes place about
the origin with that point on the unit sphere; the :class:`SphereFrame` it
returns maps results back.

>>> import numpy as np
>>> pts = np.array([[1.0, 2, 3], [3, 2, 3], [2, 3, 3], [2, 2, 4]])
>>> s = fit_sphere(pts)
>>> s.centre.round(12).tolist(), round(s.radius, 12), s.method
([2.0, 2.0, 3.0], 1.0, 'exact')
>>> unit, frame = normalise(pts, s)
>>> bool(np.allclose(np.linalg.norm(unit, axis=1), 1)), bool(np.allclose(frame.back(unit), pts))
(True, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import least_squares

from domes.errors import InputError
from domes.results import Result, Status

#: Points whose thickness (smallest over largest singular value of the centred set) is below this are on a plane.
FLAT = 1e-9


@dataclass(frozen=True)
class SphereFrame:
    """The map (2-89) to the unit sphere about the origin: ``x ↦ (x − centre)/radius`` and back."""

    centre: np.ndarray
    radius: float

    def forward(self, points) -> np.ndarray:
        """Measured points to the normalised frame."""
        return (np.asarray(points, dtype=float) - self.centre) / self.radius

    def back(self, points) -> np.ndarray:
        """Normalised points (pivots found by synthesis) back to the measured frame."""
        return self.centre + self.radius * np.asarray(points, dtype=float)


class _Residuals:
    """``rms`` and ``worst`` of a fit's ``residuals`` (distances of the points from their spheres)."""

    residuals: np.ndarray

    @property
    def rms(self) -> float:
        """Root mean square distance of the points from the sphere."""
        return float(np.sqrt(np.mean(self.residuals ** 2)))

    @property
    def worst(self) -> float:
        """The largest distance of a point from the sphere."""
        return float(np.max(np.abs(self.residuals)))


@dataclass(frozen=True)
class Sphere(_Residuals, Result):
    """A fitted sphere: ``centre``, ``radius``, ``residuals`` (each point's signed distance ``|p − c| − R``),
    ``method`` (``"exact"`` for four points, (2-87)/(2-88); ``"algebraic"``; or ``"geometric"``, the algebraic
    fit refined)."""

    centre: np.ndarray
    radius: float
    residuals: np.ndarray
    method: str
    status: Status = Status.COMPLETE
    message: str = ""

    @property
    def worst_point(self) -> int:
        """The (1-based) number of the point farthest from the sphere."""
        return int(np.argmax(np.abs(self.residuals))) + 1

    @property
    def frame(self) -> SphereFrame:
        return SphereFrame(self.centre, self.radius)


@dataclass(frozen=True)
class MotionFit(_Residuals, Result):
    """Concentric spheres of several body points of one motion (:func:`fit_motion`): the common ``centre``, a
    ``radii`` each, ``residuals[j, k]`` the distance of body point k in position j from its sphere."""

    centre: np.ndarray
    radii: np.ndarray
    residuals: np.ndarray
    method: str
    status: Status = Status.COMPLETE
    message: str = ""

    @property
    def worst_at(self) -> tuple[int, int]:
        """(position, body point), 1-based, of the largest residual."""
        j, k = np.unravel_index(int(np.argmax(np.abs(self.residuals))), self.residuals.shape)
        return int(j) + 1, int(k) + 1

    @property
    def frame(self) -> SphereFrame:
        """(2-89): the first body point's sphere becomes the unit sphere."""
        return SphereFrame(self.centre, float(self.radii[0]))


@dataclass(frozen=True)
class NormalisedMotion:
    """A measured motion mapped by (2-89): ``points[j, k]`` (positions × body points × 3) about the origin,
    ``directions`` the same scaled to unit length (each body point's ray, what :func:`~domes.design.synthesis.
    sphere.rotations` takes), ``radii`` each body point's sphere radius in the normalised frame (the first 1),
    ``frame`` to map back and ``fit`` the sphere fit with its residuals."""

    points: np.ndarray
    directions: np.ndarray
    radii: np.ndarray
    frame: SphereFrame
    fit: MotionFit = field(repr=False)


def _points(points, name: str = "points") -> np.ndarray:
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 3:
        raise InputError(f"{name}: give a list of (x, y, z) points, got shape {p.shape}")
    if not np.all(np.isfinite(p)):
        bad = int(np.flatnonzero(~np.all(np.isfinite(p), axis=1))[0]) + 1
        raise InputError(f"{name}: point {bad} is not a finite (x, y, z)")
    return p


def _check_spread(p: np.ndarray, what: str) -> tuple[np.ndarray, float]:
    """The centroid and size of the points; an InputError when they lie on one line or one plane."""
    mid = p.mean(axis=0)
    s = np.linalg.svd(p - mid, compute_uv=False)
    if s[0] == 0.0:
        raise InputError(f"{what}: all points coincide; a sphere needs four points not on one plane")
    if s[1] <= FLAT * s[0]:
        raise InputError(f"{what}: the points lie on one line; a sphere needs four points not on one plane")
    if s[2] <= FLAT * s[0]:
        raise InputError(f"{what}: the points lie on one plane (thickness {s[2] / s[0]:.2g} of their spread), so "
                         "they fix no sphere; measure a point off that plane")
    return mid, float(s[0] / math.sqrt(len(p)))


def _fit(groups: list[np.ndarray], method: str, what: str):
    """Concentric spheres through point groups: centre ``c`` and one radius per group. Algebraic least squares on
    (2-88), ``|p|² − 2 c·p + d_k = 0`` with ``d_k = |c|² − R_k²`` (linear in ``c, d``), in a centred, scaled frame;
    then, unless ``method == "algebraic"``, geometric least squares. Returns ``c, R, residuals per group, method``."""
    allp = np.vstack(groups)
    mid, size = _check_spread(allp, what)
    g = [(q - mid) / size for q in groups]
    K = len(g)
    rows, rhs = [], []
    for k, q in enumerate(g):
        block = np.zeros((len(q), 3 + K))
        block[:, :3] = -2.0 * q
        block[:, 3 + k] = 1.0
        rows.append(block)
        rhs.append(-np.einsum("ij,ij->i", q, q))
    A, b = np.vstack(rows), np.concatenate(rhs)
    if A.shape[0] < A.shape[1]:
        raise InputError(f"{what}: {A.shape[0]} points cannot fix {A.shape[1]} unknowns (a centre and "
                         f"{K} radius{'es' if K > 1 else ''}); give more positions")
    s = np.linalg.svd(A, compute_uv=False)
    if s[-1] <= 1e-10 * s[0]:
        raise InputError(f"{what}: the points do not fix the sphere's centre (each body point's track lies on one "
                         "plane and the planes do not cross); measure more positions")
    x, *_ = np.linalg.lstsq(A, b, rcond=None)
    c, d = x[:3], x[3:]
    r2 = c @ c - d
    if np.any(r2 <= 0):
        raise InputError(f"{what}: the points fix no real sphere")
    R = np.sqrt(r2)
    exact = A.shape[0] == A.shape[1]
    used = "exact" if exact else "algebraic"
    if not exact and method == "geometric":
        sizes = [len(q) for q in g]
        owner = np.repeat(np.arange(K), sizes)
        stacked = np.vstack(g)

        def residual(z):
            return np.linalg.norm(stacked - z[:3], axis=1) - z[3:][owner]

        def jac(z):
            diff = stacked - z[:3]
            dist = np.linalg.norm(diff, axis=1)
            J = np.zeros((len(stacked), 3 + K))
            J[:, :3] = -diff / dist[:, None]
            J[np.arange(len(stacked)), 3 + owner] = -1.0
            return J

        fit = least_squares(residual, np.concatenate([c, R]), jac=jac, method="lm", xtol=1e-15, ftol=1e-15,
                            gtol=1e-15)
        c, R = fit.x[:3], np.abs(fit.x[3:])
        used = "geometric"
    elif method not in ("geometric", "algebraic"):
        raise InputError(f"method must be 'geometric' or 'algebraic', got {method!r}")
    centre = mid + size * c
    radii = size * R
    residuals = [np.linalg.norm(q - centre, axis=1) - radii[k] for k, q in enumerate(groups)]
    return centre, radii, residuals, used


def fit_sphere(points, method: str = "geometric") -> Sphere:
    """The sphere through four points (exactly, (2-87)/(2-88)) or nearest to more (algebraic least squares on
    (2-88), refined by geometric least squares unless ``method="algebraic"``).

    Raises :class:`~domes.errors.InputError` for fewer than four points or points on one plane (or line)."""
    p = _points(points)
    if len(p) < 4:
        raise InputError(f"points: a sphere needs four points not on one plane, got {len(p)}")
    centre, radii, residuals, used = _fit([p], method, "points")
    res = residuals[0]
    out = Sphere(centre, float(radii[0]), res, used)
    msg = (f"sphere through {len(p)} points ({used}): centre ({', '.join(f'{v:.6g}' for v in centre)}), "
           f"radius {out.radius:.6g}; rms distance {out.rms:.2g}, worst {out.worst:.2g} at point {out.worst_point}")
    return Sphere(centre, float(radii[0]), res, used, Status.COMPLETE, msg)


def fit_motion(positions, method: str = "geometric") -> MotionFit:
    """Concentric spheres of a measured spherical motion: ``positions[j][k]`` is body point k in position j. One
    centre for all, a radius per body point; exact when the count fits, else least squares as in
    :func:`fit_sphere`."""
    P = np.asarray(positions, dtype=float)
    if P.ndim != 3 or P.shape[2] != 3 or P.shape[0] < 2 or P.shape[1] < 1:
        raise InputError(f"positions: give positions × body points × (x, y, z), got shape {P.shape}")
    if not np.all(np.isfinite(P)):
        j, k = np.argwhere(~np.all(np.isfinite(P), axis=2))[0]
        raise InputError(f"positions: point {k + 1} of position {j + 1} is not a finite (x, y, z)")
    groups = [P[:, k, :] for k in range(P.shape[1])]
    centre, radii, residuals, used = _fit(groups, method, "positions")
    res = np.column_stack(residuals)
    out = MotionFit(centre, radii, res, used)
    j, k = out.worst_at
    msg = (f"{P.shape[0]} positions of {P.shape[1]} body points ({used}): centre "
           f"({', '.join(f'{v:.6g}' for v in centre)}), radii {', '.join(f'{r:.6g}' for r in radii)}; rms distance "
           f"{out.rms:.2g}, worst {out.worst:.2g} (position {j}, point {k})")
    return MotionFit(centre, radii, res, used, Status.COMPLETE, msg)


def normalise(points, sphere: Sphere | SphereFrame) -> tuple[np.ndarray, SphereFrame]:
    """Map points by (2-89): subtract the sphere's centre and divide by its radius. Returns the mapped points and
    the :class:`SphereFrame` (its ``back`` maps results to the measured frame)."""
    frame = sphere if isinstance(sphere, SphereFrame) else sphere.frame
    if not (np.all(np.isfinite(frame.centre)) and math.isfinite(frame.radius) and frame.radius > 0):
        raise InputError("sphere: a finite centre and a positive radius are needed")
    p = np.asarray(points, dtype=float)
    if p.shape[-1] != 3:
        raise InputError(f"points: give (x, y, z) points, got shape {p.shape}")
    return frame.forward(p), frame


def normalise_motion(positions, method: str = "geometric") -> NormalisedMotion:
    """A measured spherical motion (positions × body points × 3) fitted (:func:`fit_motion`) and mapped by (2-89)
    so the first body point moves on the unit sphere about the origin.

    >>> import numpy as np
    >>> from domes.design.synthesis.sphere import rot
    >>> body = np.array([[0.6, 0.0, 0.8], [0.0, 1.2, 1.6]])
    >>> turns = [rot((0, 0, 1), t) @ rot((1, 0, 0), t / 2) for t in (0.0, 0.3, 0.6, 0.9)]
    >>> measured = np.array([[5.0 + 2.0 * (D @ b) for b in body] for D in turns])
    >>> m = normalise_motion(measured)
    >>> m.frame.centre.round(9).tolist(), round(m.frame.radius, 9), m.radii.round(9).tolist()
    ([5.0, 5.0, 5.0], 2.0, [1.0, 2.0])
    """
    fit = fit_motion(positions, method)
    frame = fit.frame
    pts = frame.forward(np.asarray(positions, dtype=float))
    dirs = pts / np.linalg.norm(pts, axis=2, keepdims=True)
    return NormalisedMotion(pts, dirs, fit.radii / fit.radii[0], frame, fit)


__all__ = ["MotionFit", "NormalisedMotion", "Sphere", "SphereFrame", "fit_motion", "fit_sphere", "normalise",
           "normalise_motion"]
