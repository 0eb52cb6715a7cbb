"""A mechanism driven by a motion law over time (seed 000 §2.10's motion class; issue 26, item 3).

A sweep walks the input's value; a designer's input moves in time, by a
law (:mod:`domes.model.laws`): ``q(t) = q0 + s(t)``, ``q̇ = s'(t)``,
``q̈ = s''(t)``. :func:`timed` solves the mechanism at every time on the
drawn assembly mode (the states of a continuation sweep over the range the
law covers set the branch) and carries the law's velocity and acceleration
through the loop equations: every output's rate and acceleration are in
time, ``ẏ = y_q q̇`` and ``ÿ = y_qq q̇² + y_q q̈``, as the query computes them
from the actual input rates.

>>> import math
>>> from domes.model.laws import Motion
>>> from domes.motion.planar.examples import four_bar
>>> law = Motion([("cycloidal", 0.5, math.pi / 2), ("dwell", 0.25), ("cycloidal", 0.5, -math.pi / 2)])
>>> run = timed(four_bar(), law, [0.0, 0.25, 0.6], outputs=["angle:rocker"])
>>> [round(math.degrees(v), 3) for v in run.table["angle:rocker"]]
[78.463, 71.702, 86.219]
>>> float(run.table["angle:rocker'"][2])                     # in a dwell the rocker rests
0.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.mechanism import Input, Mechanism
from domes.motion.planar.batch import batch
from domes.motion.planar.kernel import vectorizable
from domes.motion.planar.query import Kinematics, SolveFailure
from domes.motion.planar.sweep import sweep
from domes.results import Progress, Result, Status, Ticker


@dataclass(frozen=True, eq=False)
class TimedMotion(Result):
    """Outputs over time: ``times``, the input's ``inputs``, ``speeds``, ``accelerations``, and a ``table`` of
    output columns (``name``, ``name'``, ``name''``: rates in time); ``residuals`` and ``conditions`` per time."""

    joint: str
    times: np.ndarray
    inputs: np.ndarray
    speeds: np.ndarray
    accelerations: np.ndarray
    table: dict
    residuals: np.ndarray
    conditions: np.ndarray
    status = Status.COMPLETE

    @property
    def message(self) -> str:
        cond = f", max condition {np.max(self.conditions):.3g}" if np.all(np.isfinite(self.conditions)) else ""
        return (f"{self.status}: input {self.joint} driven by its law at {self.times.size} times "
                f"({self.times[0]:g} .. {self.times[-1]:g}), max residual {float(np.max(self.residuals)):.2g}{cond}")


def timed(mech: Mechanism, law, times, outputs=None, order: int = 2, joint: str | None = None,
          start: float | None = None, accuracy=None, progress: Progress | None = None) -> TimedMotion:
    """Drive ``joint`` (default the first input) by ``law`` from ``start`` (default its drawn value) at ``times``.

    ``law`` is a :class:`~domes.model.laws.Motion` or
    :class:`~domes.model.laws.TableMotion` whose ``s`` is the input's
    displacement (rad for an R joint). Raises a NumericalError naming the
    time when the law asks for a value the linkage cannot reach.
    """
    if order not in (0, 1, 2):
        raise InputError(f"order must be 0, 1 or 2, got {order!r}")
    times = np.asarray(times, dtype=float)
    if times.ndim != 1 or times.size == 0 or not np.all(np.isfinite(times)):
        raise InputError("times must be a non-empty list of finite numbers")
    kin = Kinematics(mech, outputs, order, "assur", accuracy)
    joint = joint or (mech.inputs[0].joint if mech.inputs else None)
    if joint not in kin.structure.input_vars:
        raise InputError(f"{joint!r} is not a driven joint; inputs are {sorted(kin.structure.input_vars)}")
    drawn = kin.drawn_inputs()[joint]
    q0 = drawn if start is None else float(start)
    s, ds, dds = law.evaluate(times, 2)
    qs = q0 + s
    lo, hi = float(np.min(qs)), float(np.max(qs))
    span = sweep(mech, min(lo, drawn), max(hi, drawn), outputs=outputs, accuracy=accuracy, joint=joint)
    if span.status is not Status.COMPLETE:
        reach = span.reachable
        bad = int(np.flatnonzero((qs < reach[0] - 1e-12) | (qs > reach[1] + 1e-12))[0]) if span.inputs.size else 0
        raise NumericalError(f"the law drives {joint} to {_fmt(kin, joint, qs[bad])} at t = {times[bad]:g}, beyond "
                             f"what the linkage reaches from its drawn pose ({_fmt(kin, joint, reach[0])} .. "
                             f"{_fmt(kin, joint, reach[1])}): {span.message}", kind="limit",
                             where={"time": float(times[bad]), "input": float(qs[bad])})
    others = {j: v for j, v in kin.drawn_inputs().items() if j != joint}
    if vectorizable(kin) and not span.dead_points and not span.passed and order:
        return _on_arrays(mech, kin, joint, law, times, qs, ds, dds, outputs, order)
    states = span.states
    grid = span.inputs
    table: dict[str, list] = {}
    residuals, conditions = np.zeros(times.size), np.zeros(times.size)
    still = dict.fromkeys(others, 0.0)                           # the other inputs stay where they are drawn
    clock = Ticker(progress)
    for k, (t, q) in enumerate(zip(times, qs)):
        clock.tick(lambda: f"timed motion: {k + 1} of {times.size} times")
        near = int(np.argmin(np.abs(grid - q)))
        guess = {v: float(a[near]) for v, a in states.items()}
        try:
            step = kin.at({**others, joint: float(q)}, guess, order, speeds={**still, joint: float(ds[k])},
                          accelerations={**still, joint: float(dds[k])})
        except SolveFailure as exc:
            raise NumericalError(f"{exc} (t = {t:g}, input {_fmt(kin, joint, q)})", kind=exc.kind,
                                 condition=exc.condition, where={**exc.where, "time": float(t)}) from None
        for name, value in step.values.items():
            table.setdefault(name, []).append(value)
        residuals[k], conditions[k] = step.residual, step.condition
    return TimedMotion(joint, times, qs, ds, dds, {c: np.asarray(v) for c, v in table.items()}, residuals,
                       conditions)


def _on_arrays(mech, kin, joint, law, times, qs, ds, dds, outputs, order) -> TimedMotion:
    """The kernel on arrays (:func:`~domes.motion.planar.batch.batch`): a linkage of drivers and dyads that passes
    no dead or branch point over the law's range stays on its drawn mode, so the batch's values are the sweep's.
    Its rates at unit input speed are ``y_q`` and ``y_qq``; the law's carry them: ``ẏ = y_q ṡ``,
    ``ÿ = y_qq ṡ² + y_q s̈``."""
    unit = replace(mech, inputs=tuple(Input(i.joint, 1.0 if i.joint == joint else 0.0, 0.0) for i in mech.inputs))
    b = batch(unit, inputs=qs, outputs=outputs, order=order, joint=joint)
    if b.kinds[0] != "complete":
        raise NumericalError(f"the law drives {joint} where the linkage does not assemble ({b.kinds[0]})", kind="limit")
    table = {}
    for name, values in b.values.items():
        v = values[0]
        if name.endswith("''"):
            continue
        if name.endswith("'"):
            yq, yqq = v, b.values[name + "'"][0] if order >= 2 else None
            table[name] = yq * ds
            if order >= 2:
                table[name + "'"] = yqq * ds * ds + yq * dds
        else:
            table[name] = v
    residuals = np.full(times.size, float(b.residual[0]))
    return TimedMotion(joint, times, qs, ds, dds, table, residuals, np.full(times.size, np.nan))


def _fmt(kin, joint, q) -> str:
    return f"{math.degrees(q):.6g}°" if kin.mech.joint(joint).kind == "R" else f"{q:.6g}"
