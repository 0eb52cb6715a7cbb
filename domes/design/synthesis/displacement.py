"""Planar displacements of a rigid body between precision positions (seed 002 §2-2, (2-24); digest A.2.1).

A position ``j`` of a body is a reference point ``P_j`` and an angle; the
displacement from position 1 is ``D1j``: a rotation by ``θ1j`` about ``P1``
followed by the translation ``P1 → P_j``, as a 3 × 3 homogeneous matrix.

>>> D = displacement((1, 1), (3, 2), math.radians(60))     # digest E.1, K-01
>>> np.round(D, 7).tolist()
[[0.5, -0.8660254, 3.3660254], [0.8660254, 0.5, 0.6339746], [0.0, 0.0, 1.0]]
>>> np.round(moved(D, (3, 1)), 7).tolist()
[4.0, 3.7320508]
"""

from __future__ import annotations

import math

import numpy as np

from domes.errors import InputError


def displacement(p1, pj, theta: float) -> np.ndarray:
    """``D1j``: rotate by ``theta`` (rad) about ``p1``, then translate ``p1 → pj``."""
    c, s = math.cos(theta), math.sin(theta)
    x1, y1 = p1
    xj, yj = pj
    return np.array([[c, -s, xj - c * x1 + s * y1], [s, c, yj - s * x1 - c * y1], [0.0, 0.0, 1.0]])


def moved(D: np.ndarray, q) -> np.ndarray:
    """Where the body point at ``q`` in position 1 is after the displacement ``D``."""
    return D[:2, :2] @ np.asarray(q, dtype=float) + D[:2, 2]


def rotation_about(point, angle: float) -> np.ndarray:
    """The displacement that turns the plane by ``angle`` (rad) about ``point``."""
    return displacement(point, point, angle)


def pole(D: np.ndarray):
    """The fixed point of ``D`` (its pole), or None for a pure translation."""
    R, t = D[:2, :2], D[:2, 2]
    A = np.eye(2) - R
    if abs(np.linalg.det(A)) < 1e-14:
        return None
    return np.linalg.solve(A, t)


def circumcentre(p, q, r):
    """The centre of the circle through three points; an InputError when they are collinear."""
    p, q, r = (np.asarray(x, dtype=float) for x in (p, q, r))
    A = 2 * np.array([q - p, r - p])
    b = np.array([q @ q - p @ p, r @ r - p @ p])
    scale = max(np.ptp(np.array([p, q, r]), axis=0).max(), 1e-300)
    if abs(np.linalg.det(A)) <= 1e-13 * scale * scale:
        raise InputError("the three positions of the point are collinear or coincide: no circle through them")
    return np.linalg.solve(A, b)
