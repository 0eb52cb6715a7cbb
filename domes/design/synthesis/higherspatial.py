"""The S-S link through infinitesimally and mixed separated spatial positions (seed 002 §2-3, (2-57)–(2-59)).

The spatial twin of :mod:`~domes.design.synthesis.higher`: a sphere centre
``a`` of the moving body keeps its distance from a fixed centre ``a0``, so
between positions ``|a_j − a0|² = |a_1 − a0|²`` (2-57) and at a state with
rates ``ȧ·(a − a0) = 0`` (2-58) and ``ä·(a − a0) + |ȧ|² = 0`` (2-59), with
``ȧ = V a`` and ``ä = A a`` as the digest corrects the OCR. Each condition is
bilinear in ``a0`` and ``a1``; six of them (seven positions, or PPP-PPP-P,
PP-PP-PP-P, ...) leave finitely many links (:func:`ss_links`), three or more
give the fixed centre of a moving one (:func:`ss_centre`).

>>> import numpy as np
>>> from domes.design.synthesis.sphere import rot
>>> a0, a1 = np.array([0.2, -0.1, 0.3]), np.array([1.0, 0.5, 0.2])
>>> turns = [np.eye(3), rot((0, 0, 1), 0.3), rot((1, 0, 0), 0.5), rot((0, 0.6, 0.8), 0.4)]
>>> moves = [SpatialState(C, a0 - C @ a0) for C in turns]          # a spherical motion about a0
>>> [round(float(v), 9) + 0.0 for v in ss_centre(moves, a1)]
[0.2, -0.1, 0.3]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from domes.design.synthesis.links import Link
from domes.errors import InputError


@dataclass(frozen=True)
class SpatialState:
    """A spatial precision position: the move ``x ↦ C x + d`` from position 1 (``rotation`` C, ``translation``
    d), and optionally its velocity state, ``omega`` and the ``velocity`` of the body point at the origin
    (``ȧ = ω × a + v``: ``ȧ = V a`` of (2-58)), and acceleration state, ``alpha`` and the ``acceleration`` of
    the body point at the origin (``ä = α × a + ω × (ω × a) + a_O``: ``ä = A a`` of (2-59))."""

    rotation: tuple
    translation: tuple
    omega: tuple | None = None
    velocity: tuple | None = None
    alpha: tuple | None = None
    acceleration: tuple | None = None

    @property
    def order(self) -> int:
        return (self.omega is not None) + (self.alpha is not None)


def _spatial_states(task) -> list[SpatialState]:
    if isinstance(task, SpatialState) or not hasattr(task, "__len__") or len(task) == 0:
        raise InputError("a spatial task is a non-empty list of SpatialState")
    for j, s in enumerate(task, 1):
        if not isinstance(s, SpatialState):
            raise InputError(f"position {j}: expected a SpatialState, got {type(s).__name__}")
        C = np.asarray(s.rotation, dtype=float)
        if C.shape != (3, 3) or np.max(np.abs(C @ C.T - np.eye(3))) > 1e-9 or np.linalg.det(C) < 0:
            raise InputError(f"position {j}: 'rotation' must be a 3 × 3 rotation matrix")
        for name, other in (("omega", "velocity"), ("velocity", "omega"), ("alpha", "acceleration"),
                            ("acceleration", "alpha")):
            v = getattr(s, name)
            if (v is None) != (getattr(s, other) is None):
                raise InputError(f"position {j}: '{name}' needs '{other}' too")
            if v is not None and (np.shape(v) != (3,) or not np.all(np.isfinite(v))):
                raise InputError(f"position {j}: '{name}' must be three finite numbers")
        if s.alpha is not None and s.omega is None:
            raise InputError(f"position {j}: 'alpha' and 'acceleration' need 'omega' and 'velocity' (2-59 uses ȧ)")
        if np.shape(s.translation) != (3,) or not np.all(np.isfinite(s.translation)):
            raise InputError(f"position {j}: 'translation' must be three finite numbers")
    return list(task)


def _spatial_forms(task) -> np.ndarray:
    """One 4 × 4 bilinear form per S-S condition: ``c = [a1; 1]ᵀ K [a0; 1]`` (positions, (2-57); velocities,
    (2-58); accelerations, (2-59))."""
    ss = _spatial_states(task)
    C1, d1 = np.asarray(ss[0].rotation, float), np.asarray(ss[0].translation, float)
    moves = []
    for s in ss:
        M = np.asarray(s.rotation, float) @ C1.T
        moves.append((M, np.asarray(s.translation, float) - M @ d1))
    funcs = []
    for j in range(1, len(ss)):
        M, t = moves[j]
        funcs.append(lambda a1, M=M, t=t: (M @ a1 + t - a1, ((M @ a1 + t) @ (M @ a1 + t) - a1 @ a1) / 2))
    for s, (M, t) in zip(ss, moves):
        if s.order >= 1:
            w, v = np.asarray(s.omega, float), np.asarray(s.velocity, float)
            funcs.append(lambda a1, M=M, t=t, w=w, v=v: _ss_rate(M @ a1 + t, w, v, None, None, 1))
        if s.order >= 2:
            al, ac = np.asarray(s.alpha, float), np.asarray(s.acceleration, float)
            funcs.append(lambda a1, M=M, t=t, w=w, v=v, al=al, ac=ac: _ss_rate(M @ a1 + t, w, v, al, ac, 2))
    K = np.zeros((len(funcs), 4, 4))
    basis = np.vstack([np.zeros(3), np.eye(3)])
    for i, f in enumerate(funcs):
        vals = [f(b) for b in basis]
        w0, h0 = vals[0]
        for r in range(3):
            K[i, r, :3] = -(vals[r + 1][0] - w0)
            K[i, r, 3] = vals[r + 1][1] - h0
        K[i, 3, :3], K[i, 3, 3] = -w0, h0
    return K


def _ss_rate(a, w, v, al, ac, k):
    da = np.cross(w, a) + v
    if k == 1:
        return da, da @ a
    dda = np.cross(al, a) + np.cross(w, np.cross(w, a)) + ac
    return dda, dda @ a + da @ da


def ss_centre(task, a1) -> np.ndarray:
    """The fixed centre of the S-S link whose moving centre is ``a1`` (position 1), from three or more
    conditions (P-P-P-P, PPP-P, PP-PP, ...; least squares when more: ``a1`` should then be a solution)."""
    K = _spatial_forms(task)
    if len(K) < 3:
        raise InputError(f"an S-S centre needs three or more conditions, got {len(K)}")
    q = np.einsum("i,kij->kj", np.r_[np.asarray(a1, float), 1.0], K)
    q = q / np.maximum(np.linalg.norm(q, axis=1), 1e-300)[:, None]
    s = np.linalg.svd(q[:, :3], compute_uv=False)
    if s[-1] <= 1e-10 * s[0]:
        raise InputError(f"no finite S-S centre for {tuple(a1)}: the conditions leave it free or at infinity")
    return np.linalg.lstsq(q[:, :3], -q[:, 3], rcond=None)[0]


def ss_links(task, starts: int = 48, seed: int = 0, tol: float = 1e-10) -> list:
    """Every distinct S-S link of six conditions (seven finitely separated positions, or fewer with velocities
    and accelerations: PPP-PPP-P, PP-PP-PP-P, ...) that Newton reaches from ``starts`` seeded random pairs
    ``(a0, a1)`` in the positions' box; each a :class:`~domes.design.synthesis.links.Link` with its residual (the
    largest condition error divided by the link's length)."""
    K = _spatial_forms(task)
    if len(K) != 6:
        raise InputError(f"S-S links take 6 conditions (a position after the first, a velocity and an "
                         f"acceleration count one each), got {len(K)}")
    pts = np.array([s.translation for s in task], dtype=float)
    scale = max(1.0, float(np.abs(pts).max()))
    norms = np.linalg.norm(K, axis=(1, 2))
    rng = np.random.default_rng(seed)
    x0 = np.c_[rng.uniform(-2, 2, (starts, 3)) * scale, np.ones(starts)]
    x1 = np.c_[rng.uniform(-2, 2, (starts, 3)) * scale, np.ones(starts)]
    with np.errstate(all="ignore"):                 # every start at once; diverging ones end non-finite
        for _ in range(40):
            q = np.einsum("si,kij->skj", x1, K)
            J = np.concatenate([q[:, :, :3], np.einsum("kij,sj->ski", K, x0)[:, :, :3]], axis=2)
            ok = np.abs(np.linalg.det(J)) > 1e-300
            J[~ok] = np.eye(6)
            step = np.linalg.solve(J, -np.einsum("skj,sj->sk", q, x0)[:, :, None])[:, :, 0]
            step[~ok] = np.nan
            x0[:, :3] += step[:, :3]
            x1[:, :3] += step[:, 3:]
    found = []
    for a, b in zip(x0, x1):
        if not (np.all(np.isfinite(a)) and np.all(np.isfinite(b))):
            continue
        r = max(float(np.linalg.norm(b[:3] - a[:3])), 1e-300)
        worst = float(np.max(np.abs(np.einsum("i,kij,j->k", b, K, a)) / norms)) / r
        if worst > tol * scale or r <= 1e-9 * scale:
            continue
        if not any(np.linalg.norm(f.a0 - a[:3]) + np.linalg.norm(f.a1 - b[:3]) <= 1e-6 * scale for f in found):
            found.append(Link("S-S", a[:3].copy(), b[:3].copy(), None, None, worst))
    return found


__all__ = ["SpatialState", "ss_centre", "ss_links"]
