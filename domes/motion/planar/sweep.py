"""Sweeps of one input with branch continuity, dead points and the reachable range.

The sweep starts from the drawn pose and walks (by the query's resolution)
to ``start``, then through the grid to ``stop``. Each step is solved from
the previous one, so the assembly mode is the drawn one. A step that
cannot be solved is refined by halving (seed 000, §4: "by refining the step
size one can determine the singular positions"), down to the accuracy's
``locate``: the sweep then stops and reports the limit (dead) position
with the group and joints concerned. Between steps the condition number of
the Jacobian is watched; a peak is refined (golden section) and reported as
a singular (branch) point when the Jacobian is singular there.

>>> from domes.motion.planar.examples import triple_rocker
>>> sw = sweep(triple_rocker(), 0.0, math.radians(130), math.radians(1), outputs=["angle:rocker"])
>>> str(sw.status), sw.success, round(math.degrees(sw.dead_points[0].input), 6)
('stopped', False, 127.1689)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.mechanism import Mechanism
from domes.motion.planar.query import PRESETS, SINGULAR_CONDITION, Accuracy, Kinematics, SolveFailure, Step
from domes.results import Progress, Result, Status, Ticker

#: Condition numbers above this, at a local peak, are refined to look for a singular point.
WATCH_CONDITION = 1e2


class DeadPointKind(StrEnum):
    """What happens to the mechanism at a dead point."""

    #: It cannot be assembled beyond this input.
    LIMIT = "limit"
    #: Its Jacobian is singular here; the sweep went on in the same assembly mode.
    SINGULAR = "singular"
    #: Its pose is not determined here (coincident joints, parallel slides).
    UNDETERMINED = "undetermined"
    #: Its pose would jump here (a bifurcation).
    DISCONTINUITY = "discontinuity"


@dataclass(frozen=True)
class DeadPoint:
    """A limit or singular position of the input.

    ``kind``: ``limit`` (the mechanism cannot be assembled beyond it),
    ``singular`` (the Jacobian is singular there; the sweep went on in the same
    assembly mode), ``undetermined`` (coincident joints or parallel slides),
    ``discontinuity`` (the solution would jump: a bifurcation).
    ``input`` is located within ``within``.
    """

    input: float
    within: float
    kind: DeadPointKind
    group: str
    joints: tuple[str, ...]
    message: str


@dataclass(frozen=True)
class Sweep(Result):
    """The result of a sweep: steps, dead points, status and what was solved.

    ``status`` is COMPLETE when the whole range was swept, STOPPED when a
    dead point ended it (the steps hold what was reached); ``max_residual``
    and each step's residual and condition number show how good the numbers are.
    """

    joint: str
    steps: tuple[Step, ...]
    dead_points: tuple[DeadPoint, ...]
    status: Status
    reachable: tuple[float, float]
    groups_solved: int
    groups_total: int
    equations: int
    accuracy: Accuracy
    columns: tuple[str, ...]
    angular: bool

    @property
    def max_residual(self) -> float:
        return max((s.residual for s in self.steps), default=0.0)

    @property
    def max_condition(self) -> float:
        return max((s.condition for s in self.steps), default=1.0)

    @property
    def message(self) -> str:
        scale = math.degrees if self.angular else float
        unit = "°" if self.angular else ""
        lo, hi = (scale(x) for x in self.reachable)
        text = (f"{self.status}: input {self.joint} swept {lo:.6g}{unit} .. {hi:.6g}{unit} in {len(self.steps)} steps, "
                f"max residual {self.max_residual:.2g}, {len(self.dead_points)} dead points")
        stop = next((d for d in self.dead_points if d.kind != DeadPointKind.SINGULAR), None)
        return text + (f"; stopped: {stop.message}" if self.status is Status.STOPPED and stop else "")


class _Stuck(Exception):
    def __init__(self, good, bad, state, failure):
        super().__init__(str(failure))
        self.good, self.bad, self.state, self.failure = good, bad, state, failure


class Continuation:
    """Walks one input of a compiled query from configuration to configuration."""

    def __init__(self, kin: Kinematics, joint: str | None = None, others: dict | None = None):
        self.kin = kin
        drawn = kin.drawn_inputs()
        self.joint = joint or kin.mech.inputs[0].joint
        if self.joint not in drawn:
            raise InputError(f"{self.joint!r} is not a driven joint; driven joints are {sorted(drawn)}")
        self.fixed = {**drawn, **(others or {})}
        self.angular = kin.mech.joint(self.joint).kind == "R"
        scale = 1.0 if self.angular else kin.size
        self.h = kin.accuracy.step * scale
        self.locate = kin.accuracy.locate * scale
        self.q0 = drawn[self.joint]

    def inputs(self, q):
        return {**self.fixed, self.joint: q}

    def reach(self, state, qa, qb):
        """State at ``qb`` from the state at ``qa``, halving the step on failure (raises :class:`_Stuck`)."""
        try:
            return self.kin.positions(self.inputs(qb), state)
        except SolveFailure as failure:
            if abs(qb - qa) <= self.locate:
                raise _Stuck(qa, qb, state, failure) from None
            mid = 0.5 * (qa + qb)
            return self.reach(self.reach(state, qa, mid), mid, qb)

    def walk(self, state, qa, qb, h=None):
        """Walk from ``qa`` to ``qb`` in pieces no longer than the resolution."""
        h = h or self.h
        n = max(1, math.ceil(abs(qb - qa) / h - 1e-9))
        for k in range(1, n + 1):
            state = self.reach(state, qa + (qb - qa) * (k - 1) / n, qa + (qb - qa) * k / n)
        return state

    def start(self, q):
        """State at ``q`` reached from the drawn pose."""
        try:
            return self.walk(dict(self.kin.structure.drawn), self.q0, q)
        except _Stuck as st:
            f = st.failure
            raise NumericalError(f"input {self.fmt(q)} is not reachable from the drawn pose ({self.fmt(self.q0)}): "
                                 f"{f} near input {self.fmt(st.good)}", kind=f.kind, condition=f.condition,
                                 where={**f.where, "input": st.good}) from None

    def fmt(self, q) -> str:
        return f"{math.degrees(q):.12g}°" if self.angular else f"{q:.12g}"


#: The most steps a sweep takes (a grid of more would not fit in memory, nor finish).
MAX_STEPS = 10_000_000


def grid_size(start: float, stop: float, step: float) -> int:
    """How many input values :func:`grid` makes; an InputError for values that are not finite or too many.

    >>> grid_size(0.0, 1.0, 0.25)
    5
    """
    for name, value in (("start", start), ("stop", stop), ("step", step)):
        if not math.isfinite(value):
            raise InputError(f"sweep {name} must be a finite number, got {value}")
    if step <= 0:
        raise InputError(f"sweep step must be > 0, got {step}")
    count = int(math.floor(abs(stop - start) / step + 1e-9)) + 1
    if count > MAX_STEPS:
        raise InputError(f"a sweep from {start:g} to {stop:g} by {step:g} has {count:.3g} steps, more than "
                         f"{MAX_STEPS:,}: use a larger step or a shorter range")
    return count


def grid(start: float, stop: float, step: float) -> list[float]:
    """``start, start ± step, ..., stop`` (the last point is ``stop`` when within 1e-9 of a step)."""
    grid_size(start, stop, step)
    n = (stop - start) / step
    count = int(math.floor(abs(n) + 1e-9))
    sign = 1.0 if stop >= start else -1.0
    pts = [start + sign * k * step for k in range(count + 1)]
    if abs(pts[-1] - stop) > 1e-9 * max(1.0, abs(stop)):
        pts.append(stop)
    return pts


def solve(mech: Mechanism, q: float | None = None, outputs=None, order: int = 0, method: str = "assur",
          accuracy=None, joint: str | None = None, others: dict | None = None) -> Step:
    """One configuration at input ``q`` (default: the drawn pose), reached from the drawn pose by continuation.

    Raises :class:`~domes.errors.NumericalError` naming the group, joints and
    input when the input cannot be reached or the derivatives are undetermined.
    """
    kin = Kinematics(mech, outputs, order, method, accuracy)
    cont = Continuation(kin, joint, others)
    q = cont.q0 if q is None else q
    state = cont.start(q)
    try:
        return kin.at(cont.inputs(q), state)
    except SolveFailure as exc:
        raise NumericalError(f"{exc} (input {cont.fmt(q)})", kind=exc.kind, condition=exc.condition,
                             where={**exc.where, "input": q}) from None


def sweep(mech: Mechanism, start: float, stop: float, step: float | None = None, outputs=None, order: int = 0,
          method: str = "assur", accuracy=None, joint: str | None = None, others: dict | None = None,
          progress: Progress | None = None) -> Sweep:
    """Sweep the driven ``joint`` (default: the first input) from ``start`` to ``stop``.

    Angles in rad, lengths in the file's unit; ``step`` defaults to the
    accuracy's resolution (the ``accuracy`` knob: a preset name or an
    :class:`~domes.motion.planar.query.Accuracy`). Other inputs stay at their
    drawn values (or ``others``).
    """
    kin = Kinematics(mech, outputs, order, method, accuracy)
    return run_sweep(kin, start, stop, step, joint, others, progress)


def run_sweep(kin: Kinematics, start, stop, step=None, joint=None, others=None, progress: Progress | None = None) -> Sweep:
    """:func:`sweep` with a compiled query."""
    cont = Continuation(kin, joint, others)
    qs = grid(start, stop, step or cont.h)
    state = cont.start(qs[0])
    steps: list[Step] = []
    dead: list[DeadPoint] = []
    status = Status.COMPLETE
    qa = qs[0]
    clock = Ticker(progress)
    for number, q in enumerate(qs, 1):
        clock.tick(lambda: f"step {number}/{len(qs)}: input {cont.fmt(q)}")
        try:
            state = cont.walk(state, qa, q)
        except _Stuck as st:
            dead.append(_dead_point(kin, cont, st))
            status = Status.STOPPED
            break
        qa = q
        steps.append(_step(kin, cont, q, state, dead))
    _refine_peaks(kin, cont, steps, dead)
    dead.sort(key=lambda d: (d.input - qs[0]) * (1 if stop >= start else -1))
    reached = [s.inputs[cont.joint] for s in steps]
    reach = (min(reached), max(reached)) if reached else (qs[0], qs[0])
    columns = tuple(steps[0].values) if steps else ()
    return Sweep(cont.joint, tuple(steps), tuple(dead), status, reach, len(kin.groups), len(kin.structure.groups),
                 kin.equations, kin.accuracy, columns, cont.angular)


def _step(kin, cont, q, state, dead) -> Step:
    try:
        return kin.at(cont.inputs(q), state)
    except SolveFailure as f:  # singular Jacobian exactly at a grid point: positions only
        dead.append(DeadPoint(q, 4 * math.sqrt(2.2e-16) * (1.0 if cont.angular else kin.size), DeadPointKind.SINGULAR,
                              f.group.label, f.group.joints,
                              f"{f} (input {cont.fmt(q)}); derivatives set to NaN"))
        step = kin.at(cont.inputs(q), state, order=0)
        values = dict(step.values)
        full = kin.output_values(state, _nan(state), _nan(state), kin.order)
        for k, v in full.items():
            values.setdefault(k, v)
        return Step(step.inputs, {k: values[k] for k in full}, step.residual, math.inf, state)


def _nan(state):
    return {k: math.nan for k in state}


def _dead_point(kin, cont, st: _Stuck) -> DeadPoint:
    f = st.failure
    kind = {"undetermined": DeadPointKind.UNDETERMINED, "jump": DeadPointKind.DISCONTINUITY}.get(f.kind, DeadPointKind.LIMIT)
    q = 0.5 * (st.good + st.bad)
    what = {"limit": "a limit (dead) position", "undetermined": "the pose is undetermined there",
            "discontinuity": "the pose would jump there (a bifurcation)"}[kind]
    msg = f"{f}; the input cannot pass {cont.fmt(q)} (last solved {cont.fmt(st.good)}): {what}"
    return DeadPoint(q, abs(st.bad - st.good) / 2, kind, f.group.label, f.group.joints, msg)


def _inverse_condition(cont, q, near):
    """``1/cond`` at input ``q``, walking there in small steps from the nearest solved step."""
    step = min(near, key=lambda st: abs(st.inputs[cont.joint] - q))
    values = cont.walk(step.state, step.inputs[cont.joint], q, cont.h / 16)
    return 1.0 / cont.kin.motion(values, 0)[3]


def _refine_peaks(kin, cont, steps, dead):
    """Golden-section search for the singular point under each peak of the condition number.

    Near a simple singularity ``1/cond`` falls linearly to zero; the peak is
    reported when the refined minimum is consistent with a zero inside the
    final bracket (``1/cond ≤ 10·slope·bracket``, the slope read at the
    neighbouring steps) or ``cond`` exceeds :data:`SINGULAR_CONDITION`.
    """
    conds = [s.condition for s in steps]
    known = [d.input for d in dead]
    # Positions to rounding: Newton's tolerance would blur the peak.
    fine = Continuation(kin.with_accuracy(PRESETS["exact"]), cont.joint, cont.fixed)
    fine.h, fine.locate = cont.h, cont.locate
    eps_q = 4 * math.sqrt(2.2e-16) * (1.0 if cont.angular else kin.size)

    def report(q, within, group, text):
        if not any(abs(q - d) <= max(2 * cont.locate, within) for d in known):
            dead.append(DeadPoint(q, within, DeadPointKind.SINGULAR, group.label, group.joints, text))
            known.append(q)

    for k in range(1, len(steps) - 1):
        c = conds[k]
        if not (c >= conds[k - 1] and c >= conds[k + 1] and c > WATCH_CONDITION):
            continue
        q = steps[k].inputs[cont.joint]
        group = _worst_group(kin, steps[k].state)
        if not c < SINGULAR_CONDITION:  # the grid hit the singular point itself
            report(q, eps_q, group, f"{group.label}: Jacobian singular at input {cont.fmt(q)} (joints "
                   f"{', '.join(group.joints)}); a branch or change point")
            continue
        near = steps[k - 1:k + 2]
        a, b = steps[k - 1].inputs[cont.joint], steps[k + 1].inputs[cont.joint]
        slope = max(1 / conds[k - 1], 1 / conds[k + 1]) / abs(b - a) * 2
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
        except (_Stuck, SolveFailure) as exc:
            report(q, abs(near[2].inputs[cont.joint] - near[0].inputs[cont.joint]) / 2, group, f"{group.label}: condition number {c:.3g} peaks near input "
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
