"""The compiled query on arrays of configurations of one mechanism: the sweep's vector path.

:func:`positions_many` places a mechanism of drivers and dyads at a whole
array of input values with the kernel (:mod:`domes.motion.planar.kernel`)
and turns the link placements into the query's variables (each rotation
kept continuous along the array); :func:`motion_many` assembles every
group's loop equations on the arrays and solves them as a stack of small
systems for velocities and accelerations, with every configuration's
loop-closure residual and condition number, as
:meth:`~domes.motion.planar.query.Kinematics.motion` does for one. Where a
configuration cannot be assembled, is undetermined, or would jump, the
first such index is returned; the sweep hands that one interval to the
scalar code, which locates the dead point.

>>> import math, numpy as np
>>> from domes.motion.planar.examples import four_bar
>>> from domes.motion.planar.query import Kinematics
>>> kin = Kinematics(four_bar(), outputs=["angle:rocker"], order=1)
>>> run = positions_many(Compiled(kin), "A", np.radians([0.0, 30.0, 60.0]), kin.structure.drawn)
>>> rates, accels, residual, condition = motion_many(kin, run.values, 1)
>>> angles = outputs_many(kin, run.values, rates, accels, 1)["angle:rocker"]
>>> run.failure is None, [round(math.degrees(float(x)), 6) for x in angles], bool(residual.max() < 1e-15)
(True, [78.463041, 70.546922, 75.228684], True)
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from domes.motion.planar.groups import Loops
from domes.motion.planar.kernel import Program, cam_rates
from domes.motion.planar.query import JUMP, sign_key
from domes.motion.planar.structure import CamTie, Rotation, evaluate


class Compiled:
    """A query with its kernel program and the mechanism's own geometry, compiled once per sweep."""

    def __init__(self, kin):
        self.kin = kin
        self.program = Program(kin)
        self.geometry = self.program.geometry()

    @classmethod
    def of(cls, kin) -> "Compiled":
        """The query's compiled form, made once and kept on the query (a sweep and its walks share it)."""
        done = kin.__dict__.get("_compiled")
        if done is None or done.kin is not kin:
            done = kin.__dict__["_compiled"] = cls(kin)
        return done


@dataclass
class Run:
    """Positions on an array of inputs: ``values`` (variable -> array), the dyads' ``roots``, the first failure.

    ``margins`` are the dyads' signed assembly margins (lengths; their roots
    are the limits, see :class:`~domes.motion.planar.kernel.Poses`).
    ``failure`` is ``(index, kind, group)`` with ``kind`` ``limit``,
    ``undetermined`` or ``jump``; values at and after it are not meaningful.
    """

    values: dict
    roots: dict
    failure: tuple | None
    margins: dict = field(default_factory=dict)

    def state(self, index: int) -> dict:
        """The scalar state (variable -> value) of one configuration."""
        return {v: (float(a[index]) if isinstance(a, np.ndarray) else a) for v, a in self.values.items()}


def positions_many(compiled: Compiled, joint: str, qs, start: dict, others: dict | None = None,
                   jumps: bool = True) -> Run:
    """Every variable of the needed groups at inputs ``qs`` of ``joint``, continuing from the state ``start``.

    ``start`` is the configuration the array continues from (rotations stay
    within half a turn of it and of each other); its ``sign:`` entries are
    the dyads' assembly modes. ``others`` holds the other inputs' values.
    With ``jumps=False`` the first configuration is not required to be near
    ``start`` (a configuration placed anew, e.g. in another assembly mode).
    """
    kin = compiled.kin
    qs = np.asarray(qs, dtype=float)
    n = qs.size
    s = kin.structure
    groups = [g for g in kin.groups if g.unknowns]
    signs = {g.index: start[sign_key(g)] for g in groups if sign_key(g) in start}
    fixed = {j: (others or {}).get(j, start[v]) for j, v in s.input_vars.items() if j != joint}
    pose = compiled.program.poses(compiled.geometry, qs, joint, fixed, signs, start)
    values: dict = dict(start)
    for j, v in s.input_vars.items():
        values[v] = qs if j == joint else float(fixed[j])
    first: tuple | None = None

    def fail(mask, kind, group):
        nonlocal first
        mask = np.broadcast_to(mask, (n,))
        if np.any(mask):
            k = int(np.argmax(mask))
            if first is None or k < first[0]:
                first = (k, kind, group)

    for g in groups:
        fail(pose.unassembled[g.index], "limit", g)
        fail(pose.undetermined[g.index], "undetermined", g)
        for link in g.links:
            expr = s.rotations[link]
            var, coeff = next(((v, c) for v, c in expr.terms if v in g.unknowns), (None, 0.0))
            if var is None:
                continue
            rest = sum(c * values[v] for v, c in expr.terms if v != var) + expr.const
            new = (np.angle(pose.links[link][0]) - rest) / coeff
            values[var] = np.unwrap(np.concatenate(([start[var]], np.broadcast_to(new, (n,)))))[1:]
        for v in g.unknowns:
            if v.startswith("s:"):
                values[v] = np.broadcast_to(pose.slides[v[2:]], (n,)).astype(float)
        for v in g.unknowns:
            path = np.concatenate(([start[v]], values[v]))[0 if jumps else 1:]
            change = np.abs(np.diff(path)) / (1.0 if v.startswith("rot:") else kin.size)
            fail(np.concatenate(([False] if not jumps else [], ~(change <= JUMP))), "jump", g)
    for g in kin.groups:  # racks' slides and cams' followers, as the kernel placed them
        for v in s.derived_of(g):
            value = pose.values[v] if v in pose.values else s.derived[v].value(values)
            values[v] = np.broadcast_to(value, (n,)).astype(float)
    roots = {i: np.broadcast_to(r, (n,)) for i, r in pose.root.items()}
    margins = {i: np.broadcast_to(r, (n,)) for i, r in pose.margin.items()}
    return Run(values, roots, first, margins)


def _stack(kin, g, values, rates=None):
    """The group's residuals ``(n, m)``, Jacobian ``(n, m, u)`` and the loop columns of every variable."""
    col = {v: k for k, v in enumerate(g.unknowns)}
    parts, J, loops = [], None, []
    for i, loop in enumerate(g.loops):
        a, cols, dcols = evaluate(loop, values, rates, lib=np)
        parts += [a[0], a[1]]
        loops.append((cols, dcols))
    n = max(np.size(p) for p in parts)
    A = np.stack([np.broadcast_to(p, (n,)) for p in parts], axis=-1)
    J = np.zeros((n, g.equations, len(g.unknowns)))
    for i, (cols, _) in enumerate(loops):
        for v, c in cols.items():
            if v in col:
                J[:, 2 * i, col[v]] = c[0]
                J[:, 2 * i + 1, col[v]] = c[1]
    return A, J, loops


#: Condition numbers up to this are taken from ``JᵀJ`` (their relative error is about ``ε·cond²``).
SQUARED = 1e3


def _condition(J):
    """2-norm condition numbers of a stack of matrices (``inf`` where singular); 2 × 2 in closed form.

    For 2 × 2, ``σ₁² = (F + √(F² − 4D²))/2`` with ``F`` the squared Frobenius
    norm and ``D`` the determinant, and ``cond = σ₁/σ₂ = σ₁²/|D|``; larger
    ones from the extreme eigenvalues of ``JᵀJ`` (by SVD above :data:`SQUARED`).

    >>> float(_condition(np.array([[[3.0, 0.0], [0.0, 1e-3]]]))[0])
    3000.0
    """
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        if J.shape[-2:] == (2, 2):
            F = np.sum(J * J, axis=(-2, -1))
            D = np.abs(J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0])
            s1 = 0.5 * (F + np.sqrt(np.maximum(F * F - 4 * D * D, 0.0)))
            cond = np.maximum(s1 / D, 1.0)
        else:  # from the eigenvalues of JᵀJ (squared singular values); by SVD where that squares away digits
            w = np.linalg.eigvalsh(np.matmul(np.swapaxes(J, -1, -2), J))
            cond = np.sqrt(w[..., -1] / w[..., 0])
            redo = ~(cond <= SQUARED)
            if np.any(redo):
                cond[redo] = np.linalg.cond(J[redo])
    return np.where(np.isfinite(cond), cond, np.inf)


def _solve(J, rhs):
    """Solve a stack of small systems; 2 × 2 by Cramer's rule (no exception where one is singular: NaN there)."""
    if J.shape[-2:] == (2, 2):
        det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
        with np.errstate(invalid="ignore", divide="ignore"):
            x0 = (rhs[:, 0] * J[:, 1, 1] - J[:, 0, 1] * rhs[:, 1]) / det
            x1 = (J[:, 0, 0] * rhs[:, 1] - J[:, 1, 0] * rhs[:, 0]) / det
        return np.stack([x0, x1], axis=1)
    return np.linalg.solve(J, rhs[..., None])[..., 0]


def _rhs(n, g, loops, col, given, rates=None):
    """``−B·given`` (and ``− Ḃ·rates − J̇·rates`` when ``rates`` are given) of every configuration: ``(n, m)``."""
    rhs = np.zeros((n, g.equations))
    for i, (cols, dcols) in enumerate(loops):
        terms = [(c, given[v]) for v, c in cols.items() if v not in col]
        if rates is not None:
            terms += [(c, rates[v]) for v, c in dcols.items()]
        for c, x in terms:
            rhs[:, 2 * i] -= c[0] * x
            rhs[:, 2 * i + 1] -= c[1] * x
    return rhs


def motion_many(kin, values: dict, order: int):
    """Rates and accelerations (variable -> array), residuals and condition numbers of every configuration.

    Rates and accelerations are NaN where a group's Jacobian is singular;
    ``residual`` and ``condition`` are the worst over the groups, as in
    :meth:`~domes.motion.planar.query.Kinematics.motion`.
    """
    n = max((np.size(a) for a in values.values()), default=1)
    ins = kin.structure.input_vars
    rates = {v: kin.inputs[j].speed for j, v in ins.items()}
    accels = {v: kin.inputs[j].acceleration for j, v in ins.items()}
    residual = np.zeros(n)
    condition = np.ones(n)
    for g in kin.groups:
        _derive(kin, values, rates, accels, order)
        if not g.unknowns:
            continue
        got = None if g.index in kin.plans else _compiled(kin, g, values, rates, accels, order, n)
        if got is not None:
            residual, condition = np.maximum(residual, got[0]), np.maximum(condition, got[1])
            continue
        A, J, loops = _stack(kin, g, values)
        residual = np.maximum(residual, np.max(np.abs(A), axis=-1) / kin.size)
        scale = np.array([1.0 / kin.size if v.startswith("rot:") else 1.0 for v in g.unknowns])
        cond = _condition(J * scale)
        condition = np.maximum(condition, cond)
        if order == 0:
            continue
        ok = np.isfinite(cond)
        safe = np.where(ok[:, None, None], J, np.eye(len(g.unknowns)))
        col = {v: k for k, v in enumerate(g.unknowns)}
        sol = _solve(safe, _rhs(n, g, loops, col, rates))
        sol[~ok] = np.nan
        rates.update({v: sol[:, k] for k, v in enumerate(g.unknowns)})
        if order == 1:
            continue
        _, _, loops = _stack(kin, g, values, rates)
        sol = _solve(safe, _rhs(n, g, loops, col, accels, rates))
        sol[~ok] = np.nan
        accels.update({v: sol[:, k] for k, v in enumerate(g.unknowns)})
    _derive(kin, values, rates, accels, order)
    return rates, accels, residual, condition


def _compiled(kin, g, values, rates, accels, order, n):
    """A group solved by Newton's method, from its compiled loop equations (:class:`~domes.motion.planar.groups.Loops`:
    the same equations, a few array operations): rates and accelerations as :func:`motion_many`, and ``(residuals,
    condition numbers)``; None (nothing done) when a variable it reads has no rate here."""
    loops = Loops(kin, g)
    if order and not all(v in rates and (order < 2 or v in accels) for v in loops.external):
        return None
    U = len(loops.unknowns)
    names = loops.unknowns + loops.external
    X = np.stack([np.broadcast_to(np.asarray(values[v], dtype=float), (n,)) for v in names], axis=1)
    A, J = loops.system(X)
    scale = np.array([1.0 / kin.size if v.startswith("rot:") else 1.0 for v in g.unknowns])
    cond = _condition(J[:, :, :U] * scale)
    out = (np.max(np.abs(A), axis=-1) / kin.size, cond)
    if order == 0:
        return out
    ok = np.isfinite(cond)
    safe = np.where(ok[:, None, None], J[:, :, :U], np.eye(U))

    def given(store):
        return np.stack([np.broadcast_to(np.asarray(store[v], dtype=float), (n,)) for v in loops.external], axis=1)

    sol = _solve(safe, -np.einsum("nrv,nv->nr", J[:, :, U:], given(rates)))
    sol[~ok] = np.nan
    rates.update({v: sol[:, k] for k, v in enumerate(loops.unknowns)})
    if order == 1:
        return out
    Xd = np.concatenate((sol, given(rates)), axis=1)
    sol = _solve(safe, -np.einsum("nrv,nv->nr", J[:, :, U:], given(accels)) - loops.second(X, Xd))
    sol[~ok] = np.nan
    accels.update({v: sol[:, k] for k, v in enumerate(loops.unknowns)})
    return out


def _derive(kin, values, rates, accels, order):
    """Rates and accelerations of the derived variables whose terms' are known (on arrays), as
    :meth:`~domes.motion.planar.query.Kinematics._derive_rates`: racks' slides (linear) and cams' followers."""
    for v, expr in kin.structure.derived.items():
        if isinstance(expr, Rotation):
            for store in (rates, accels):
                if v not in store and all(t in store for t, _ in expr.terms):
                    store[v] = expr.rate(store)
        elif isinstance(expr, CamTie) and order and v not in rates and all(t in rates for t, _ in expr.terms):
            rate, accel = cam_rates(expr, values, rates, accels if all(t in accels for t, _ in expr.terms) else None)
            rates[v] = rate
            if accel is not None:
                accels[v] = accel


def outputs_many(kin, values, rates, accels, order: int) -> dict:
    """The query's output columns (name -> array), as :meth:`~domes.motion.planar.query.Kinematics.output_values`."""
    n = max((np.size(a) for a in values.values()), default=1)
    out = kin.output_values(values, rates, accels, order, lib=np)
    return {k: np.broadcast_to(np.asarray(v, dtype=float), (n,)) for k, v in out.items()}


def fine_grid(qs, q_from: float, h: float) -> tuple[np.ndarray, np.ndarray]:
    """The grid a sweep walks: from ``q_from`` through every point of ``qs`` in pieces no longer than ``h``.

    Returns the walked points and the index in them of each point of
    ``qs`` (``q_from`` is walked only when it is the first point of ``qs``).

    >>> pts, at = fine_grid([0.0, 1.0], 0.0, 0.4)
    >>> [round(float(x), 6) for x in pts], [int(i) for i in at]
    ([0.0, 0.333333, 0.666667, 1.0], [0, 3])
    """
    qs = np.asarray(qs, dtype=float)
    if qs.size == 0:
        return qs, np.zeros(0, dtype=int)
    prev = np.concatenate(([q_from], qs[:-1]))
    span = qs - prev
    pieces = np.ceil(np.abs(span) / h - 1e-9).astype(np.int64)
    pieces = np.where(span == 0, 0, np.maximum(pieces, 1))
    pieces[0] = max(pieces[0], 1)
    owner = np.repeat(np.arange(qs.size), pieces)
    offset = np.arange(owner.size) - np.repeat(np.cumsum(pieces) - pieces, pieces) + 1
    pts = prev[owner] + span[owner] * offset / pieces[owner]
    return pts, np.cumsum(pieces) - 1
