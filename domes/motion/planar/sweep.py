"""Sweeps of one input with branch continuity, dead points, bifurcations and the reachable range.

The sweep starts from the drawn pose and walks (by the query's resolution)
to ``start``, then through the grid to ``stop``, each configuration
continuing the previous one, so the assembly mode is the drawn one. A
configuration that cannot be solved is refined by halving (seed 000, §4:
"by refining the step size one can determine the singular positions"), down
to the accuracy's ``locate``: the sweep then stops and reports the limit
(dead) position with the group and joints concerned. A dyad's limit is the
root of its assembly margin, found by Brent's method
(:meth:`~domes.motion.planar.branches.Walker.limit`); its ``within`` adds the
margin's rounding, so it is a bound, not a hope. ``solve`` (``--at``) walks
from the drawn pose as a sweep does, so the two agree.

A query of drivers and dyads runs on arrays (:mod:`~domes.motion.planar.branches`):
the whole grid at once, scalar code only where a decision is needed, and
every change or branch point located and passed on the branch whose
velocities are continuous (a ``bifurcation`` dead point). Larger groups
(Newton's method) walk step by step; there a peak of the condition number
(above 100, or a V of ``1/cond`` reaching towards zero) is refined (golden
section) and reported as a ``singular`` point. Wherever
the condition number cannot bound the error of a velocity or acceleration
(:func:`~domes.motion.planar.query.error_bounds` above the accuracy's
``derivatives``), the derivative is NaN and a ``singular`` dead point says why.

>>> from domes.motion.planar.examples import triple_rocker
>>> sw = sweep(triple_rocker(), 0.0, math.radians(130), math.radians(1), outputs=["angle:rocker"])
>>> str(sw.status), sw.success, round(math.degrees(sw.dead_points[0].input), 6)
('stopped', False, 127.1689)
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.mechanism import Mechanism
from domes.motion.planar import onepass
from domes.motion.planar.arrays import Compiled, fine_grid, motion_many, outputs_many
from domes.motion.planar.branches import Walker
from domes.motion.planar.compiled import choose
from domes.motion.planar.continuation import (
    MAX_STEPS,
    Continuation,
    DeadPoint,
    DeadPointKind,
    Stuck,
    dead_point,
    grid,
    grid_points,
    grid_size,
)
from domes.motion.planar.kernel import blocked, iterated
from domes.motion.planar.query import (
    PRESETS,
    SINGULAR_CONDITION,
    Accuracy,
    FailureKind,
    Kinematics,
    SolveFailure,
    Step,
    error_bounds,
)
from domes.results import Progress, Result, Status, Ticker

__all__ = ["Continuation", "DeadPoint", "DeadPointKind", "MAX_STEPS", "Steps", "Sweep", "grid", "grid_size",
           "run_sweep", "solve", "sweep"]

#: Condition numbers above this, at a local peak, are refined to look for a singular point (Newton groups).
WATCH_CONDITION = 1e2


@dataclass(frozen=True, eq=False)
class Sweep(Result):
    """The result of a sweep: a table of the outputs at every step, dead points, status and what was solved.

    ``status`` is COMPLETE when the whole range was swept, STOPPED when a
    dead point ended it (the table holds what was reached). ``inputs`` and
    each column of ``table`` are arrays over the steps; ``residuals`` and
    ``conditions`` show how good each step's numbers are; :attr:`steps`
    gives them as :class:`~domes.motion.planar.query.Step` objects.
    ``passed`` holds the branch points passed between the drawn pose and
    ``start``. ``turns`` is how many whole turns were taken off the inputs
    asked for (a revolute input more than a turn from its drawn value; its
    pose repeats every turn): the inputs are those asked less ``turns`` turns.
    """

    joint: str
    inputs: np.ndarray
    table: dict
    residuals: np.ndarray
    conditions: np.ndarray
    dead_points: tuple[DeadPoint, ...]
    status: Status
    reachable: tuple[float, float]
    groups_solved: int
    groups_total: int
    equations: int
    accuracy: Accuracy
    columns: tuple[str, ...]
    angular: bool
    fixed: dict = field(default_factory=dict)
    states: dict = field(default_factory=dict, repr=False)
    passed: tuple[DeadPoint, ...] = ()
    turns: int = 0

    @property
    def steps(self) -> "Steps":
        """The steps as :class:`~domes.motion.planar.query.Step` objects (made when read)."""
        return Steps(self)

    def column(self, name: str) -> np.ndarray:
        """One output column over the steps (e.g. ``"angle:rocker'"``)."""
        return self.table[name]

    @property
    def max_residual(self) -> float:
        return float(np.max(self.residuals)) if self.residuals.size else 0.0

    @property
    def max_condition(self) -> float:
        return float(np.max(self.conditions)) if self.conditions.size else 1.0

    @property
    def message(self) -> str:
        scale = math.degrees if self.angular else float
        unit = "°" if self.angular else ""
        lo, hi = (scale(x) for x in self.reachable)
        text = (f"{self.status}: input {self.joint} swept {lo:.6g}{unit} .. {hi:.6g}{unit} in {self.inputs.size} steps, "
                f"max residual {self.max_residual:.2g}, {len(self.dead_points)} dead points")
        branch = sum(d.kind is DeadPointKind.BIFURCATION for d in self.dead_points)
        if branch:
            text += f" ({branch} of them branch points)"
        if self.turns:
            text += f" ({self.turns:+,} whole turns taken off the inputs asked for)"
        stop = next((d for d in self.dead_points if d.stops), None)
        return text + (f"; stopped: {stop.message}" if self.status is Status.STOPPED and stop else "")

    def _repr_html_(self) -> str | None:
        """Each output column plotted over the input, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


class Steps(Sequence):
    """The steps of a :class:`Sweep`, each made into a :class:`~domes.motion.planar.query.Step` when read."""

    def __init__(self, sweep: Sweep):
        self._sweep = sweep

    def __len__(self) -> int:
        return int(self._sweep.inputs.size)

    def __getitem__(self, index):
        if isinstance(index, slice):
            return [self[i] for i in range(*index.indices(len(self)))]
        sw = self._sweep
        i = range(len(self))[index]
        return Step({**sw.fixed, sw.joint: float(sw.inputs[i])}, {c: float(sw.table[c][i]) for c in sw.columns},
                    float(sw.residuals[i]), float(sw.conditions[i]), {v: float(a[i]) for v, a in sw.states.items()})


def solve(mech: Mechanism, q: float | None = None, outputs=None, order: int = 0, method: str = "assur",
          accuracy=None, joint: str | None = None, others: dict | None = None) -> Step:
    """One configuration at input ``q`` (default: the drawn pose), reached from the drawn pose by continuation.

    An angle more than a turn from the drawn one is taken less its whole turns
    (the step's inputs show the angle solved); inputs floats cannot place, or
    lengths far outside the mechanism, are refused
    (:meth:`~domes.motion.planar.continuation.Continuation.placed`).

    Raises :class:`~domes.errors.NumericalError` naming the group, joints and
    input when the input cannot be reached or the derivatives are
    undetermined (or not determined to the accuracy's ``derivatives``).
    Branch points passed on the way are in the step's ``passed``.
    """
    kin = Kinematics(mech, outputs, order, method, accuracy)
    cont = Continuation(kin, joint, others)
    q = cont.q0 if q is None else cont.placed(q)
    state, passed = _reach(kin, cont, q)
    try:
        step = kin.at(cont.inputs(q), state)
    except SolveFailure as exc:
        raise NumericalError(f"{exc} (input {cont.fmt(q)})", kind=exc.kind, condition=exc.condition,
                             where={**exc.where, "input": q}) from None
    return replace(step, passed=tuple(passed)) if passed else step


def sweep(mech: Mechanism, start: float, stop: float, step: float | None = None, outputs=None, order: int = 0,
          method: str = "assur", accuracy=None, joint: str | None = None, others: dict | None = None,
          progress: Progress | None = None) -> Sweep:
    """Sweep the driven ``joint`` (default: the first input) from ``start`` to ``stop``.

    Angles in rad, lengths in the file's unit; ``step`` defaults to the
    accuracy's resolution (the ``accuracy`` knob: a preset name or an
    :class:`~domes.motion.planar.query.Accuracy`). Other inputs stay at their
    drawn values (or ``others``). A ``start`` more than a turn from the drawn
    angle is taken less its whole turns (``Sweep.turns``), and so is ``stop``.
    """
    kin = Kinematics(mech, outputs, order, method, accuracy)
    return run_sweep(kin, start, stop, step, joint, others, progress)


def run_sweep(kin: Kinematics, start, stop, step=None, joint=None, others=None, progress: Progress | None = None) -> Sweep:
    """:func:`sweep` with a compiled query."""
    cont = Continuation(kin, joint, others)
    placed = cont.placed(start)
    turns = round((start - placed) / (2 * math.pi)) if placed != start else 0
    start, stop = placed, placed + (stop - start)
    cont.placed(stop)
    walked = (abs(start - cont.q0) + abs(stop - start)) / cont.h
    if walked > MAX_STEPS:
        raise InputError(f"a sweep from {cont.fmt(start)} to {cont.fmt(stop)} walks from the drawn pose "
                         f"({cont.fmt(cont.q0)}) in {walked:.3g} steps of the resolution {cont.fmt(cont.h)}, more than "
                         f"{MAX_STEPS:,}: sweep a shorter range, nearer the drawn pose")
    qs = _grid(kin, start, stop, step or cont.h)
    if blocked(kin):
        sw = _scalar_sweep(kin, cont, qs.tolist(), progress)
    else:  # the compiled route tries the sweep in one pass first; where a decision is due, the numpy walk makes it
        sw = onepass.sweep(kin, cont, qs, progress) if choose(qs.size) else None
        sw = sw or _vector_sweep(kin, cont, qs.tolist(), progress)
    return replace(sw, turns=turns) if turns else sw


def _grid(kin, start, stop, step):
    """:func:`~domes.motion.planar.continuation.grid_points`, read-only and kept on the query for its next sweeps
    of the same grid (the last few)."""
    cache = kin.__dict__.setdefault("_grids", {})
    qs = cache.get((start, stop, step))
    if qs is None:
        qs = grid_points(start, stop, step)
        qs.flags.writeable = False
        if len(cache) >= 4:
            cache.pop(next(iter(cache)), None)
        cache[(start, stop, step)] = qs
    return qs


def _reach(kin, cont, q):
    """The state at ``q`` reached from the drawn pose, and the branch points passed on the way."""
    if blocked(kin):
        return cont.start(q), []
    walker = Walker(cont, Compiled.of(kin))
    pts, _ = fine_grid([q], cont.q0, cont.h)
    w = walker.walk(dict(kin.structure.drawn), cont.q0, pts)
    if w.stuck is not None:
        raise cont.unreachable(q, w.stuck)
    return w.state, w.branch_points


# -- the vector path -------------------------------------------------------------------------


def _vector_sweep(kin, cont, qs, progress) -> Sweep:
    state, passed = _reach(kin, cont, qs[0])
    walker = Walker(cont, Compiled.of(kin))
    pts, marks = fine_grid(qs, qs[0], cont.h)
    clock = Ticker(progress)
    w = walker.walk(state, qs[0], pts, lambda i, n: clock.tick(lambda: f"step {i}/{n}: input {cont.fmt(pts[i - 1])}"))
    reached = marks[marks < w.count]
    values = {v: a[reached] for v, a in w.values.items()}
    dead = list(w.branch_points)
    status = Status.COMPLETE
    if w.stuck is not None:
        dead.append(walker.limit(w.stuck) or dead_point(cont, w.stuck))
        status = Status.STOPPED
    inputs = pts[reached]
    if inputs.size:
        ends = {0: "starts"} if w.stuck is not None else {0: "starts", inputs.size - 1: "ends"}
        for k, end in ends.items() if walker.signed else ():  # only dyads with two assembly modes branch there
            dead += walker.on_branch_point({v: float(a[k]) for v, a in values.items()}, float(inputs[k]), end, dead)
        rates, accels, residuals, conditions = motion_many(kin, values, kin.order)
        table = {c: np.array(a, dtype=float) for c, a in outputs_many(kin, values, rates, accels, kin.order).items()}
        if iterated(kin):  # groups solved by Newton's method: their singular points, as the scalar path finds them
            _refine_peaks(kin, cont, inputs, conditions, lambda k: {v: float(a[k]) for v, a in values.items()}, dead)
        dead += _refuse(kin, cont, inputs, table, conditions, values, dead)
    else:
        table = {c: np.zeros(0) for c in kin.output_values(state, _nan(state), _nan(state), kin.order)}
        residuals = conditions = np.zeros(0)
    return _result(kin, cont, qs, inputs, table, residuals, conditions, values, dead, status, passed)


def _refuse(kin, cont, inputs, table, conditions, values, known) -> list[DeadPoint]:
    """Set to NaN the derivatives the condition number cannot bound; a singular dead point for each stretch."""
    order, tol = kin.order, kin.accuracy.derivatives
    if order == 0:
        return []
    bounds = error_bounds(conditions, order)
    bad_any = np.zeros(inputs.size, dtype=bool)
    for k in range(1, order + 1):
        bad = ~((conditions <= SINGULAR_CONDITION) & (bounds[k] <= tol))
        bad_any |= bad
        for c in table:
            if len(c) - len(c.rstrip("'")) >= k:
                table[c][bad] = np.nan
    out = []
    spacing = float(np.max(np.abs(np.diff(inputs)))) if inputs.size > 1 else cont.h
    edges = np.flatnonzero(np.diff(np.concatenate(([0], bad_any.astype(np.int8), [0]))))
    for lo, hi in zip(edges[::2], edges[1::2]):
        k = lo + int(np.argmax(conditions[lo:hi]))
        q = float(inputs[k])
        if any(abs(d.input - q) <= spacing * (hi - lo + 1) + d.within for d in known):
            continue
        state = {v: float(a[k]) for v, a in values.items()}
        group = _worst_group(kin, state)
        cond = float(conditions[k])
        what = "velocities" if not cond <= SINGULAR_CONDITION or error_bounds(cond, 1)[1] > tol else "accelerations"
        out.append(DeadPoint(q, spacing / 2, DeadPointKind.SINGULAR, group.label, group.joints,
                             f"{group.label}: near input {cont.fmt(q)} (joints {', '.join(group.joints)}) the condition "
                             f"number reaches {cond:.3g}, so the {what} are known only to "
                             f"{error_bounds(cond, order)[order]:.2g}, more than the accuracy's {tol:g}: they are "
                             f"refused (NaN) at {hi - lo} steps; a singular point is near"))
    return out


def _result(kin, cont, qs, inputs, table, residuals, conditions, states, dead, status, passed, reach=None) -> Sweep:
    dead.sort(key=lambda d: (d.input - qs[0]) * (1 if qs[-1] >= qs[0] else -1))
    if reach is None:
        reach = (float(np.min(inputs)), float(np.max(inputs))) if inputs.size else (float(qs[0]), float(qs[0]))
    fixed = {j: v for j, v in cont.fixed.items() if j != cont.joint}
    return Sweep(cont.joint, inputs, table, residuals, conditions, tuple(dead), status, reach, len(kin.groups),
                 len(kin.structure.groups), kin.equations, kin.accuracy, tuple(table), cont.angular, fixed, states,
                 tuple(passed))


# -- the scalar path (groups solved by Newton's method) ----------------------------------------------


def _scalar_sweep(kin, cont, qs, progress) -> Sweep:
    state = cont.start(qs[0])
    steps: list[Step] = []
    dead: list[DeadPoint] = []
    status = Status.COMPLETE
    qa = qs[0]
    clock = Ticker(progress)
    for number, q in enumerate(qs, 1):
        clock.tick(lambda: f"step {number}/{len(qs)}: input {cont.fmt(q)}")
        try:
            state = cont.walk_far(state, qa, q)
        except Stuck as st:
            dead.append(dead_point(cont, st))
            status = Status.STOPPED
            break
        qa = q
        steps.append(_step(kin, cont, q, state, dead))
    _refine_peaks(kin, cont, [s.inputs[cont.joint] for s in steps], [s.condition for s in steps],
                  lambda k: steps[k].state, dead)
    columns = tuple(steps[0].values) if steps else tuple(kin.output_values(state, _nan(state), _nan(state), kin.order))
    inputs = np.array([s.inputs[cont.joint] for s in steps], dtype=float)
    table = {c: np.array([s.values[c] for s in steps], dtype=float) for c in columns}
    states = {v: np.array([s.state[v] for s in steps], dtype=float) for v in (steps[0].state if steps else {})}
    residuals = np.array([s.residual for s in steps], dtype=float)
    conditions = np.array([s.condition for s in steps], dtype=float)
    return _result(kin, cont, qs, inputs, table, residuals, conditions, states, dead, status, ())


def _step(kin, cont, q, state, dead) -> Step:
    try:
        return kin.at(cont.inputs(q), state)
    except SolveFailure as f:  # singular (or too ill-conditioned) at a grid point: the derivatives it can give
        if f.kind is not FailureKind.SINGULAR:
            raise
        full = kin.output_values(state, _nan(state), _nan(state), kin.order)
        for order in range(kin.order - 1, -1, -1):
            try:
                step = kin.at(cont.inputs(q), state, order=order)
                break
            except SolveFailure:
                continue
        dead.append(DeadPoint(q, 4 * math.sqrt(2.2e-16) * (1.0 if cont.angular else kin.size), DeadPointKind.SINGULAR,
                              f.group.label, f.group.joints, f"{f} (input {cont.fmt(q)}); derivatives set to NaN"))
        values = {k: step.values.get(k, v) for k, v in full.items()}
        return Step(step.inputs, values, step.residual, math.inf if order == 0 else step.condition, state)


def _nan(state):
    return {k: math.nan for k in state}


def _inverse_condition(cont, q, near):
    """``1/cond`` at input ``q``, walking there in small steps from the nearest solved step (``(input, state)``)."""
    qa, state = min(near, key=lambda st: abs(st[0] - q))
    values = cont.walk(state, qa, q, cont.h / 16)
    return 1.0 / cont.kin.motion(values, 0)[3]


def _refine_peaks(kin, cont, qs, conds, state, dead):
    """Golden-section search for the singular point under each peak of the condition number.

    ``qs`` and ``conds`` are the steps' inputs and condition numbers,
    ``state(k)`` the configuration of step ``k``. Near a simple singularity
    ``1/cond`` falls linearly to zero; the peak is reported when the refined
    minimum is consistent with a zero inside the final bracket
    (``1/cond ≤ 10·slope·bracket``, the slope read at the neighbouring
    steps) or ``cond`` exceeds :data:`SINGULAR_CONDITION`.
    """
    known = [d.input for d in dead]
    # Positions to rounding: Newton's tolerance would blur the peak.
    fine = Continuation(kin.with_accuracy(PRESETS["exact"]), cont.joint, cont.fixed)
    fine.h, fine.locate = cont.h, cont.locate
    eps_q = 4 * math.sqrt(2.2e-16) * (1.0 if cont.angular else kin.size)

    def report(q, within, group, text):
        if not any(abs(q - d) <= max(2 * cont.locate, within) for d in known):
            dead.append(DeadPoint(q, within, DeadPointKind.SINGULAR, group.label, group.joints, text))
            known.append(q)

    qs, conds = np.asarray(qs, dtype=float), np.asarray(conds, dtype=float)
    for k in _peaks(qs, conds):
        c = float(conds[k])
        q = float(qs[k])
        group = _worst_group(kin, state(k))
        if not c < SINGULAR_CONDITION:  # the grid hit the singular point itself
            report(q, eps_q, group, f"{group.label}: Jacobian singular at input {cont.fmt(q)} (joints "
                   f"{', '.join(group.joints)}); a branch or change point")
            continue
        near = [(float(qs[i]), state(i)) for i in (k - 1, k, k + 1)]
        a, b = float(qs[k - 1]), float(qs[k + 1])
        slope = max(1 / float(conds[k - 1]), 1 / float(conds[k + 1])) / abs(b - a) * 2
        g = (math.sqrt(5) - 1) / 2
        x1, x2 = b - g * (b - a), a + g * (b - a)
        try:
            f1, f2 = _inverse_condition(fine, x1, near), _inverse_condition(fine, x2, near)
            while abs(b - a) > cont.locate:
                if f1 < f2:
                    b, x2, f2 = x2, x1, f1
                    x1 = b - g * (b - a)
                    f1 = _inverse_condition(fine, x1, near)
                else:
                    a, x1, f1 = x1, x2, f2
                    x2 = a + g * (b - a)
                    f2 = _inverse_condition(fine, x2, near)
        except (Stuck, SolveFailure) as exc:
            report(q, abs(near[2][0] - near[0][0]) / 2, group, f"{group.label}: condition number {c:.3g} peaks near input "
                   f"{cont.fmt(q)} (joints {', '.join(group.joints)}); a singular point is likely there but "
                   f"could not be located ({exc})")
            continue
        q = 0.5 * (a + b)
        fmin = min(f1, f2)
        if fmin * SINGULAR_CONDITION < 1 or fmin <= 10 * slope * abs(b - a):
            # A singular point is located no better than √eps (the pose there is a double root).
            within = max(abs(b - a) / 2, fmin / slope, eps_q)
            report(q, within, group, f"{group.label}: Jacobian singular at input {cont.fmt(q)} (joints "
                   f"{', '.join(group.joints)}, condition {1 / fmin if fmin else math.inf:.3g}); a branch or change point: "
                   "the sweep stays in the drawn assembly mode")


def _peaks(qs, conds) -> list[int]:
    """The interior steps where the condition number peaks above :data:`WATCH_CONDITION` or ``1/cond`` dips in a V
    towards zero (:func:`_v_shaped`), in order."""
    if conds.size < 3:
        return []
    c, before, after = conds[1:-1], conds[:-2], conds[2:]
    top = (c >= before) & (c >= after)
    candidates = np.flatnonzero(top) + 1
    return [int(k) for k in candidates if conds[k] > WATCH_CONDITION or _v_shaped(qs, conds, k)]


def _v_shaped(qs, conds, k) -> bool:
    """Whether ``1/cond`` at step ``k`` is low enough to be a V reaching zero between its neighbours.

    Near a branch point ``1/cond`` falls linearly to zero from both sides, so
    at the step nearest it ``1/cond`` is at most the steeper chord's slope
    times the spacing; a smooth minimum away from zero is far above that.
    """
    f = [1.0 / c if c > 0 else math.inf for c in conds[k - 1:k + 2]]
    dx = (abs(qs[k] - qs[k - 1]), abs(qs[k + 1] - qs[k]))
    if not min(dx) > 0:
        return False
    slope = max(abs(f[1] - f[0]) / dx[0], abs(f[2] - f[1]) / dx[1])
    return f[1] <= slope * max(dx)


def _worst_group(kin, values):
    worst, best = None, -1.0
    for g in kin.groups:
        if not g.unknowns:
            continue
        _, J = kin._assemble(g, values)
        scale = np.array([1.0 / kin.size if v.startswith("rot:") else 1.0 for v in g.unknowns])
        c = float(np.linalg.cond(J * scale))
        if c > best:
            worst, best = g, c
    return worst
