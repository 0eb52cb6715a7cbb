"""Spherical guidance, three positions in closed form (seed 002 §2-3, (2-92)-(2-96); digest A.3.3 (3)).

On the unit sphere, the fixed pivot ``a0`` of a crank whose moving pivot
takes the positions ``a1, a2, a3`` is equidistant from them: it is where the
normal of their plane (2-92) pierces the sphere. With the 3 × 3 minors
``A = |a_iy a_iz 1|``, ``B = |a_ix a_iz 1|``, ``C = |a_ix a_iy 1|`` (2-94),

    a0 = ±(A, −B, C) / D,   D = √(A² + B² + C²)        (2-96)

(the minus sign on ``B`` is the one (2-93) lost in print).

>>> import numpy as np
>>> a = [np.array(p) / np.linalg.norm(p) for p in ((1.0, 0.2, 0.1), (0.8, 0.6, 0.0), (0.7, 0.1, 0.7))]
>>> [round(float(np.linalg.norm(q - a0)), 12) == round(float(np.linalg.norm(a[0] - a0)), 12)
...  for a0 in centre_points_three(*a)[:1] for q in a]
[True, True, True]
"""

from __future__ import annotations

import numpy as np

from domes.errors import InputError


def centre_points_three(a1, a2, a3) -> tuple[np.ndarray, np.ndarray]:
    """The two fixed pivots ``±(A, −B, C)/D`` (2-96) of three positions ``a1, a2, a3`` on the unit sphere."""
    pts = np.array([a1, a2, a3], dtype=float)
    if pts.shape != (3, 3) or not np.all(np.isfinite(pts)):
        raise InputError("three positions on the unit sphere, each (x, y, z)")
    if np.max(np.abs(np.linalg.norm(pts, axis=1) - 1.0)) > 1e-9:
        raise InputError("the positions must lie on the unit sphere (normalise them first, (2-87)-(2-89))")
    ones = np.ones((3, 1))
    A = np.linalg.det(np.hstack([pts[:, [1, 2]], ones]))
    B = np.linalg.det(np.hstack([pts[:, [0, 2]], ones]))
    C = np.linalg.det(np.hstack([pts[:, [0, 1]], ones]))
    D = float(np.sqrt(A * A + B * B + C * C))
    if D <= 1e-12:
        raise InputError("two of the three positions coincide: their plane, and the pivot, are not defined")
    a0 = np.array([A, -B, C]) / D
    return a0, -a0
