"""Sweeps of a spatial mechanism's input with continuity: each pose continues the last, limits located.

The walk starts at the drawn pose (every joint variable 0) and goes by at
most the resolution (``step``, and no more than 1° or 1% of the size
unless a closed form keeps the walk on its branch) to ``start`` (an angle more than a turn away less its whole turns: the pose
repeats every turn), then through the grid to ``stop``. A step that
Newton's method cannot take, or that jumps (a link turning by more than
:data:`JUMP` rad, or moving by more than ``JUMP`` times the size: another
assembly mode; for a mechanism with a closed form, a pose nearer the other
branch of it than its own, or a step across a range where it does not
assemble, however narrow), is halved down to ``locate``; there the sweep
stops and reports the limit with its input value, located to a precision it
states (:mod:`~domes.motion.spatial.limits`). A grid point where the
velocities are not determined (condition above :data:`~domes.motion.spatial.loops.SINGULAR`)
has NaN derivatives and is listed in ``singular``; the sweep goes on.

>>> import math
>>> from domes.motion.spatial.examples import rssr
>>> sw = spatial_sweep(rssr(), 0.0, 2 * math.pi, math.radians(30), outputs=["angle:B0"], order=1)
>>> sw.success, len(sw.inputs), round(float(max(sw.table["angle:B0"])), 6)
(True, 13, 1.164814)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialInput, SpatialMechanism
from domes.motion.spatial.limits import EXACT, closed_form, closed_limit, fold_limit
from domes.motion.spatial.loops import SINGULAR, Loops, State
from domes.results import Progress, Result, Status, Ticker

#: The largest turn (rad) or move (fraction of the size) of a link accepted in one step.
JUMP = 0.75
#: How short the walk's halved steps get before it stops (rad, or fraction of the size).
LOCATE = 1e-10
#: The longest step the walk takes without a closed form (rad; a slide: 0.01 of the size), as ``--at`` does.
RESOLUTION = math.radians(1.0)
#: Where a closed form's two branches are closer than this (rad) a pose cannot be told to lie on one of them.
ON_BRANCH = 1e-6
#: The most steps of one sweep.
MAX_STEPS = 1_000_000
#: A length input is refused beyond this many times the mechanism's size from its drawn value (0).
FARTHEST = 100.0


@dataclass(frozen=True)
class Limit:
    """Where a sweep stopped: the input, the kind (``limit``, or ``stuck`` where a closed form says the linkage
    assembles on) and why; ``within``: how closely a limit is located (NaN where it is not)."""

    input: float
    kind: str
    message: str
    within: float = math.nan


@dataclass(frozen=True, eq=False)
class SpatialSweep(Result):
    """Outputs over the steps (columns of ``table``), with residuals, condition numbers and the limit met;
    ``turns``: the whole turns taken off the inputs asked for (an angle more than a turn from the drawn pose);
    ``singular``: the inputs where the velocities are not determined (NaN there); ``branch_points``: the inputs
    where the closed form's two modes meet and the walk passed on the smooth branch."""

    mechanism: str
    joint: str
    inputs: np.ndarray
    table: dict
    residuals: np.ndarray
    conditions: np.ndarray
    status: Status
    limit: Limit | None = None
    angular: bool = True
    states: list = field(default_factory=list, repr=False)
    turns: int = 0
    singular: tuple = ()
    branch_points: tuple = ()

    @property
    def message(self) -> str:
        f = math.degrees if self.angular else float
        u = "°" if self.angular else ""
        text = (f"{self.status}: input {self.joint} swept {f(self.inputs[0]):.6g}{u} .. {f(self.inputs[-1]):.6g}{u} "
                f"in {self.inputs.size} steps, max residual {np.max(self.residuals):.2g}, max condition "
                f"{np.max(self.conditions):.3g}")
        if self.turns:
            text += f" ({self.turns:+,} whole turns taken off the inputs asked for)"
        if self.branch_points:
            text += (f"; passed branch points (the two assembly modes meet) at "
                     f"{', '.join(_fmt(q, self.angular) for q in self.branch_points)} on the smooth branch")
        if self.singular:
            text += (f"; velocities not determined (NaN) at {', '.join(_fmt(q, self.angular) for q in self.singular)} "
                     f"(condition above {SINGULAR:.0e})")
        return text + (f"; stopped: {self.limit.message}" if self.limit else "")

    def _repr_html_(self) -> str | None:
        """Each output column plotted over the input, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


def _distance(a: State, b: State) -> float:
    """The largest move (fraction of the size) or turn (rad) of a link between two states."""
    out = float(np.max(np.abs(a.o - b.o))) if a.o.size else 0.0
    for Ra, Rb in zip(a.R, b.R):
        D = Ra.T @ Rb
        sine = 0.5 * math.sqrt((D[2, 1] - D[1, 2]) ** 2 + (D[0, 2] - D[2, 0]) ** 2 + (D[1, 0] - D[0, 1]) ** 2)
        out = max(out, math.atan2(sine, (np.trace(D) - 1) / 2))
    return out


def _limit(kin, closed, state, q: float, dq: float, why: str, joint: str, angular: bool, values: dict) -> Limit:
    """The limit met by a walk that cannot go from ``q`` (pose ``state``) by ``dq``.

    With a closed form: the root of its discriminant next to ``q``
    (:func:`~domes.motion.spatial.limits.closed_limit`); where it says the
    linkage assembles on, the walk stopped at a near-singular pose (kind
    ``stuck``). Without: the fold located by driving the fastest joint
    variable instead (:func:`~domes.motion.spatial.limits.fold_limit`), or, if
    that fails, the walk's last pose, said to be no more than that.
    """
    direction = math.copysign(1.0, dq)
    if closed is not None and angular:
        found = closed_limit(closed, q, direction)
        if found is None:
            return Limit(q, "stuck", f"{joint}: the walk stops at {_fmt(q, angular)} ({why}) though the linkage "
                                     f"assembles beyond it (its closed form, the {closed.kind}): a near-singular "
                                     "pose, where the two assembly modes nearly meet; try a smaller --step")
        x, within = found
        return Limit(x, "limit", f"{joint} cannot go beyond {_fmt(x, angular)} (no assembly; the root of the "
                                 f"{closed.kind}'s closed form, located to {_fmt(within, angular)})", within)
    found = fold_limit(kin, state, joint, q, direction, values)
    if found is None:
        return Limit(q, "limit", f"{joint} cannot go beyond {_fmt(q, angular)} ({why}); the walk's last pose: the "
                                 "limit itself could not be located beyond it")
    x, within, driver = found
    return Limit(x, "limit", f"{joint} cannot go beyond {_fmt(x, angular)} (no assembly; the fold of the loop, "
                             f"where {joint}'s rate changes sign as {driver} turns on, located to "
                             f"{_fmt(within, angular)})", within)


#: How far past a branch point of a closed form the walk hops (rad).
HOP = 1e-5
#: A walk this close (rad) to a branch point of its closed form is on it.
BRANCH_POINT = 1e-9


def _hop(kin, closed, s, q: float, q_to: float, joint: str, others: dict, branch: int, came: float):
    """Past a branch point of a closed form (its two modes meet at ``q``, where the walk stuck): the pose
    :data:`HOP` further on (or at ``q_to``, if nearer), on the branch that continues the line through the
    walk's output at ``q`` and the output :data:`HOP` back on the side the walk ``came`` from (±1), on the
    ``branch`` it came along: the smooth branch, as the planar sweep follows (back along the same one where
    the walk turns back). Placed by Newton's method with both the input and the output angle given.
    ``(input, pose, branch)``, or None."""
    direction = math.copysign(1.0, q_to - q)
    target = q_to if abs(q_to - q) <= HOP else q + direction * HOP
    if target == q:
        return None
    here = float(kin._variable(closed.output, "angle", s)[0])
    q_back = q + came * HOP
    ahead = here + math.remainder(here - closed.angle(q_back, branch), 2 * math.pi) * (target - q) / (q - q_back)
    mode = min((1, -1), key=lambda b: abs(math.remainder(closed.angle(target, b) - ahead, 2 * math.pi)))
    drive = next(i for i in kin.inputs if i.joint == joint)
    both = kin.driven_by([drive, SpatialInput(closed.output, "angle", 0.0)])
    values = {**others, joint: target}
    try:
        nxt, _ = both.positions({**values, closed.output: closed.angle(target, mode)}, s)
    except NumericalError:
        return None
    if float(np.max(np.abs(kin._jacobian(nxt, values)[1]))) > 1e-12:
        return None
    return target, nxt, mode


def _predict(kin: Loops, s: State, joint: str, dq: float) -> tuple[State, float]:
    """The state one step ``dq`` ahead along the tangent (the twists at unit input rate), and the step's size."""
    speeds = {i.joint: (1.0 if i.joint == joint else 0.0) for i in kin.inputs}
    xd, _ = kin.motion(s, 1, speeds)
    ahead = s.copy()
    kin._update(ahead, xd * dq)
    return ahead, float(np.max(np.abs(xd * dq)))


def spatial_sweep(mech: SpatialMechanism, start: float, stop: float, step: float | None = None, outputs=None,
                  order: int = 0, joint: str | None = None, progress: Progress | None = None) -> SpatialSweep:
    """Sweep the driven ``joint`` (default: the first input; rad or length) from ``start`` to ``stop``."""
    kin = Loops(mech, outputs, order)
    inputs = {i.joint: i for i in mech.inputs}
    joint = joint or mech.inputs[0].joint
    if joint not in inputs:
        raise InputError(f"{joint!r} is not a driven joint of {mech.name}; inputs are {sorted(inputs)}")
    angular = inputs[joint].variable == "angle"
    h = abs(step) if step else (math.radians(1.0) if angular else 0.01 * mech.size)
    if not (math.isfinite(start) and math.isfinite(stop) and h > 0):
        raise InputError("sweep: start, stop and step must be finite numbers, step > 0")
    locate = LOCATE if angular else LOCATE * mech.size
    placed = _placed(start, angular, locate, mech, joint)
    turns = round((start - placed) / (2 * math.pi)) if placed != start else 0
    start, stop = placed, placed + (stop - start)
    _placed(stop, angular, locate, mech, joint)
    resolution = min(h, RESOLUTION if angular else 0.01 * mech.size)
    walked = (abs(start) + abs(stop - start)) / resolution
    if walked > MAX_STEPS:
        raise InputError(f"sweep: from the drawn pose to {_fmt(start, angular)} and on to {_fmt(stop, angular)} is "
                         f"{walked:.3g} steps of {_fmt(resolution, angular)}, more than {MAX_STEPS:,}: sweep a "
                         "shorter range, nearer the drawn pose")
    n = int(math.floor(abs(stop - start) / h + 1e-9)) + 1
    if n > MAX_STEPS:
        raise InputError(f"sweep: {n:,} steps; at most {MAX_STEPS:,}")
    grid = start + math.copysign(h, stop - start) * np.arange(n)
    if abs(grid[-1] - stop) > 1e-9 * max(1.0, abs(stop)):
        grid = np.append(grid, stop)
    others = {j: 0.0 for j in inputs if j != joint}
    state = kin.drawn()
    closed = closed_form(mech) if angular else None
    if closed is not None:  # its branch and gaps keep the walk honest at any step
        resolution = h
    branch = [closed.drawn_branch] if closed is not None else [0]
    gaps = closed.form.gaps() if closed is not None else ()
    meetings = closed.meetings() if closed is not None else ()
    crossed: list[float] = []
    trail: list[float] = [0.0]  # the inputs of the walk's last poses

    def on_branch(target, nxt) -> bool:
        """Whether the pose ``nxt`` at ``target`` lies on the closed form's branch the walk is on, not nearer the
        other (a jump: the walk passes from one to the other only at a branch point, by :func:`_hop`). Where
        the two are closer than :data:`ON_BRANCH` they cannot be told apart and the pose is on its own."""
        a = float(kin._variable(closed.output, "angle", nxt)[0])
        plus, minus = closed.branches(target)
        gap = {1: abs(math.remainder(a - plus, 2 * math.pi)), -1: abs(math.remainder(a - minus, 2 * math.pi))}
        apart = abs(math.remainder(plus - minus, 2 * math.pi))
        return not (gap[-branch[0]] < gap[branch[0]] and apart > ON_BRANCH)  # NaN: a hair past a limit (rounding)

    def note(q):
        trail.append(q)
        del trail[:-8]

    def hop(q, q_to, s, dq):
        """Past the branch point at ``q`` (:func:`_hop`): ``(input, pose)``, or None."""
        came = next((math.copysign(1.0, x - q) for x in reversed(trail) if x != q), -math.copysign(1.0, dq))
        found = _hop(kin, closed, s, q, q_to, joint, others, branch[0], came)
        if found is None:
            return None
        target, nxt, branch[0] = found
        crossed.append(q)
        return target, nxt

    def take(q_from, q_to, s):
        """Walk from ``q_from`` (state ``s``) to ``q_to``; the state there, or the Limit met."""
        q = q_from
        size = resolution
        while q != q_to:
            dq = q_to - q
            dq = math.copysign(min(abs(dq), size), dq)
            if closed is not None:  # land on a branch point of the closed form, then hop past it
                meet = closed.next_meeting(q, q + dq, meetings)
                passed = hop(q, q_to, s, dq) if meet is not None and abs(meet - q) <= BRANCH_POINT else None
                if passed is not None:
                    q, s = passed
                    note(q)
                    size = min(resolution, HOP)
                    continue
                if meet is not None and abs(meet - q) > BRANCH_POINT:
                    dq = meet - q
            while True:
                target = q + dq
                if abs(q_to - target) <= 1e-12 * max(1.0, abs(q_to)):
                    target, dq = q_to, q_to - q
                try:
                    if closed is not None and closed.crosses_gap(q, target, gaps):
                        raise NumericalError(f"{mech.name}: no assembly between {_fmt(q, True)} and "
                                             f"{_fmt(target, True)} (its closed form)", kind="limit")
                    guess, ahead = _predict(kin, s, joint, dq)
                    nxt, _ = kin.positions({**others, joint: target}, guess)
                    if _distance(guess, nxt) <= 0.25 * ahead + 1e-9 and _distance(s, nxt) <= JUMP:
                        if closed is None or on_branch(target, nxt):
                            break
                    why = "a jump to another assembly mode"
                except NumericalError:
                    why = "no assembly"
                if abs(dq) <= locate:
                    passed = None
                    if closed is not None and closed_limit(closed, q, math.copysign(1.0, dq)) is None:
                        passed = hop(q, q_to, s, dq)  # a branch point the walk could not land on
                    if passed is None:
                        return None, _limit(kin, closed, s, q, dq, why, joint, angular, others)
                    target, nxt = passed
                    break
                dq /= 2
            q, s = target, nxt
            note(q)
            size = min(resolution, 2 * abs(dq))  # after a halved step, grow back gradually
        return s, None

    state, limit = take(0.0, float(grid[0]), state)
    if limit is not None:
        raise NumericalError(f"{mech.name}: the start {_fmt(grid[0], angular)} is not reachable from the drawn pose: "
                             f"{limit.message}", kind="limit", where={"input": float(grid[0])})
    rows, residuals, conditions, reached, states, singular = [], [], [], [], [], []
    clock = Ticker(progress)
    for k, q in enumerate(grid):
        clock.tick(lambda: f"step {k:,}/{grid.size:,}")
        if k:
            state, limit = take(float(grid[k - 1]), float(q), state)
            if limit is not None:
                break
        values = {**others, joint: float(q)}
        try:
            s, residual = kin.positions(values, state)
        except NumericalError:  # the walk's own pose there, closed to its tolerance
            s, residual = state, float(np.max(np.abs(kin._jacobian(state, values)[1])))
        cond = kin.condition(s)
        if order and not cond < SINGULAR:  # positions only: the rates are not determined here
            singular.append(float(q))
            row = kin.output_values(s, *kin.motion(s, order))
            rows.append({c: (v if not c.endswith("'") else math.nan) for c, v in row.items()})
        else:
            rows.append(kin.output_values(s, *kin.motion(s, order)))
        residuals.append(residual)
        conditions.append(cond)
        reached.append(float(q))
        states.append(s)
        state = s
    if not rows:
        raise NumericalError(f"{mech.name}: no configuration reached ({limit.message if limit else ''})", kind="limit")
    table = {c: np.array([r[c] for r in rows]) for c in rows[0]}
    for c in table:  # angles continuous along the sweep
        if c.startswith("angle:") and not c.endswith("'"):
            table[c] = np.unwrap(table[c])
    return SpatialSweep(mech.name, joint, np.array(reached), table, np.array(residuals), np.array(conditions),
                        Status.STOPPED if limit else Status.COMPLETE, limit, angular, states, turns, tuple(singular),
                        tuple(crossed))


def _placed(q: float, angular: bool, locate: float, mech: SpatialMechanism, joint: str) -> float:
    """``q`` as the walk from the drawn pose (0) takes it: an angle more than a turn away less its whole turns, refused
    where floats are farther apart than ``locate``; a length refused beyond :data:`FARTHEST` sizes."""
    if not angular:
        if abs(q) > FARTHEST * mech.size:
            raise InputError(f"input {joint} = {q:.6g} is far outside {mech.name} (size {mech.size:.4g}): give a "
                             f"length within {FARTHEST:g} sizes of the drawn pose")
        return q
    if math.ulp(q) > locate:
        raise InputError(f"input {joint} = {math.degrees(q):.6g}° is too large to mean an angle: floats there are "
                         f"{math.degrees(math.ulp(q)):.3g}° apart, coarser than the accuracy "
                         f"({math.degrees(locate):.3g}°); give an angle within a few turns")
    return q if abs(q) < 2 * math.pi else math.fmod(q, 2 * math.pi)


def _fmt(q: float, angular: bool) -> str:
    return f"{math.degrees(q):.10g}°" if angular else f"{q:.10g}"


__all__ = ["EXACT", "Limit", "SpatialSweep", "spatial_sweep"]
