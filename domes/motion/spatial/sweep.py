"""Sweeps of a spatial mechanism's input with continuity: each pose continues the last, limits located.

The walk starts at the drawn pose (every joint variable 0) and goes by at
most ``step`` to ``start`` (an angle more than a turn away less its whole
turns: the pose repeats every turn), then through the grid to ``stop``. A step that
Newton's method cannot take, or that jumps (a link turning by more than
:data:`JUMP` rad, or moving by more than ``JUMP`` times the size: another
assembly mode), is halved down to ``locate``; there the sweep stops and
reports the limit (the linkage does not assemble beyond it, or is singular
there) with its input value.

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
from domes.model.spatial import SpatialMechanism
from domes.motion.spatial.loops import SINGULAR, Loops, State
from domes.results import Progress, Result, Status, Ticker

#: The largest turn (rad) or move (fraction of the size) of a link accepted in one step.
JUMP = 0.75
#: How closely a limit is located (rad, or fraction of the size).
LOCATE = 1e-10
#: The most steps of one sweep.
MAX_STEPS = 1_000_000
#: A length input is refused beyond this many times the mechanism's size from its drawn value (0).
FARTHEST = 100.0


@dataclass(frozen=True)
class Limit:
    """Where a sweep stopped: the last input reached, the kind (``limit`` or ``singular``) and why."""

    input: float
    kind: str
    message: str


@dataclass(frozen=True, eq=False)
class SpatialSweep(Result):
    """Outputs over the steps (columns of ``table``), with residuals, condition numbers and the limit met;
    ``turns``: the whole turns taken off the inputs asked for (an angle more than a turn from the drawn pose)."""

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

    @property
    def message(self) -> str:
        f = math.degrees if self.angular else float
        u = "°" if self.angular else ""
        text = (f"{self.status}: input {self.joint} swept {f(self.inputs[0]):.6g}{u} .. {f(self.inputs[-1]):.6g}{u} "
                f"in {self.inputs.size} steps, max residual {np.max(self.residuals):.2g}, max condition "
                f"{np.max(self.conditions):.3g}")
        if self.turns:
            text += f" ({self.turns:+,} whole turns taken off the inputs asked for)"
        return text + (f"; stopped: {self.limit.message}" if self.limit else "")


def _distance(a: State, b: State) -> float:
    """The largest move (fraction of the size) or turn (rad) of a link between two states."""
    out = float(np.max(np.abs(a.o - b.o))) if a.o.size else 0.0
    for Ra, Rb in zip(a.R, b.R):
        D = Ra.T @ Rb
        sine = 0.5 * math.sqrt((D[2, 1] - D[1, 2]) ** 2 + (D[0, 2] - D[2, 0]) ** 2 + (D[1, 0] - D[0, 1]) ** 2)
        out = max(out, math.atan2(sine, (np.trace(D) - 1) / 2))
    return out


#: How closely a limit is located where the mechanism has a closed form (rad): the root of its discriminant.
EXACT = 1e-13
#: How far beyond the walk's last pose the closed form looks for the limit (rad).
BEYOND = 0.05


def _closed_form(mech: SpatialMechanism):
    """The RSSR closed form of ``mech`` (seed 001) when it is one, else None."""
    from domes.motion.spatial.rssr import RSSR

    try:
        return RSSR.of(mech)
    except (InputError, StopIteration, ValueError):
        return None


def _limit(closed, q: float, dq: float, why: str, joint: str, angular: bool, locate: float) -> Limit:
    """The limit met by a walk that cannot go from ``q`` by ``dq``: located by the walk to ``locate``, or, for a
    mechanism with a closed form, the root of its discriminant beyond ``q`` (bracketed, then Brent's method),
    and where the closed form says the linkage assembles on, a walk that stopped at a near-singular pose."""
    if closed is None or not angular:
        return Limit(q, "limit", f"{joint} cannot go beyond {_fmt(q, angular)} ({why}; located to "
                                 f"{_fmt(locate, angular)})")
    from scipy.optimize import brentq

    direction = math.copysign(1.0, dq)
    d = closed.discriminant
    near, far = 0.0, 1e-12
    while far <= BEYOND and float(d(q + direction * far)) >= 0:
        near, far = far, 2 * far
    if far > BEYOND:
        return Limit(q, "stuck", f"{joint}: the walk stops at {_fmt(q, angular)} ({why}) though the linkage "
                                 f"assembles beyond it (its closed form, seed 001): a near-singular pose, where the "
                                 f"two assembly modes nearly meet; try a smaller --step")
    root = brentq(lambda x: float(d(q + direction * x)), near, far, xtol=EXACT, rtol=4 * np.finfo(float).eps)
    return Limit(q + direction * root, "limit",
                 f"{joint} cannot go beyond {_fmt(q + direction * root, angular)} (no assembly; the root of the RSSR's "
                 f"closed form, located to {_fmt(EXACT, angular)})")


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
    resolution = min(h, math.radians(1.0) if angular else 0.01 * mech.size)
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
    closed = _closed_form(mech)

    def take(q_from, q_to, s):
        """Walk from ``q_from`` (state ``s``) to ``q_to``; the state there, or the Limit met."""
        q = q_from
        size = h
        while q != q_to:
            dq = q_to - q
            dq = math.copysign(min(abs(dq), size), dq)
            while True:
                target = q + dq
                if abs(q_to - target) <= 1e-12 * max(1.0, abs(q_to)):
                    target, dq = q_to, q_to - q
                try:
                    guess, ahead = _predict(kin, s, joint, dq)
                    nxt, _ = kin.positions({**others, joint: target}, guess)
                    if _distance(guess, nxt) <= 0.25 * ahead + 1e-9 and _distance(s, nxt) <= JUMP:
                        break
                    why = "a jump to another assembly mode"
                except NumericalError:
                    why = "no assembly"
                if abs(dq) <= locate:
                    return None, _limit(closed, q, dq, why, joint, angular, locate)
                dq /= 2
            q, s = target, nxt
            size = min(h, 2 * abs(dq))  # after a halved step, grow back gradually
        return s, None

    state, limit = take(0.0, float(grid[0]), state)
    if limit is not None:
        raise NumericalError(f"{mech.name}: the start {_fmt(grid[0], angular)} is not reachable from the drawn pose: "
                             f"{limit.message}", kind="limit", where={"input": float(grid[0])})
    rows, residuals, conditions, reached, states = [], [], [], [], []
    clock = Ticker(progress)
    for k, q in enumerate(grid):
        clock.tick(lambda: f"step {k:,}/{grid.size:,}")
        if k:
            state, limit = take(float(grid[k - 1]), float(q), state)
            if limit is not None:
                break
        values = {**others, joint: float(q)}
        s, residual = kin.positions(values, state)
        cond = kin.condition(s)
        if order and not cond < SINGULAR:
            limit = Limit(float(q), "singular", f"singular at {_fmt(q, angular)} (condition {cond:.3g})")
            break
        xd, xdd = kin.motion(s, order)
        rows.append(kin.output_values(s, xd, xdd))
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
                        Status.STOPPED if limit else Status.COMPLETE, limit, angular, states, turns)


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


__all__ = ["Limit", "SpatialSweep", "spatial_sweep"]
