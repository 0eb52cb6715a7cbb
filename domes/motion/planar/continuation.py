"""Continuation: walking one input of a compiled query from configuration to configuration.

A :class:`Continuation` solves each configuration from the previous one, so
the assembly mode stays the drawn one (or the one a bifurcation led to). A
step that cannot be solved is refined by halving (seed 000, §4: "by
refining the step size one can determine the singular positions"), down to
the accuracy's ``locate``; the interval where it stuck is a dead point.

>>> from domes.motion.planar.examples import triple_rocker
>>> from domes.motion.planar.query import Kinematics
>>> cont = Continuation(Kinematics(triple_rocker()))
>>> try:
...     cont.walk(dict(cont.kin.structure.drawn), 0.0, math.radians(130))
... except Stuck as st:
...     print(round(math.degrees(st.good), 6), dead_point(cont, st).kind)
127.1689 limit
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import StrEnum

import numpy as np

from domes.errors import InputError, NumericalError
from domes.motion.planar.query import PRESETS, FailureKind, Kinematics, SolveFailure


class DeadPointKind(StrEnum):
    """What happens to the mechanism at a dead point."""

    #: It cannot be assembled beyond this input.
    LIMIT = "limit"
    #: Its Jacobian is singular here; the sweep went on in the same assembly mode.
    SINGULAR = "singular"
    #: Its pose is not determined here (coincident joints, parallel slides).
    UNDETERMINED = "undetermined"
    #: Its pose would jump here (a discontinuity the sweep cannot pass).
    DISCONTINUITY = "discontinuity"
    #: Two assembly modes meet here (a change or branch point); the sweep went on along the smooth branch.
    BIFURCATION = "bifurcation"


@dataclass(frozen=True)
class DeadPoint:
    """A limit or singular position of the input.

    ``kind``: ``limit`` (the mechanism cannot be assembled beyond it),
    ``singular`` (the Jacobian is singular there; the sweep went on in the same
    assembly mode), ``undetermined`` (coincident joints or parallel slides),
    ``discontinuity`` (the solution would jump), ``bifurcation`` (two
    assembly modes meet; the sweep followed the one whose velocities are
    continuous). ``input`` is located within ``within``.
    """

    input: float
    within: float
    kind: DeadPointKind
    group: str
    joints: tuple[str, ...]
    message: str

    @property
    def stops(self) -> bool:
        """Whether the sweep cannot go past this point (a limit, an undetermined pose or a jump)."""
        return self.kind not in (DeadPointKind.SINGULAR, DeadPointKind.BIFURCATION)


class Stuck(Exception):
    """Continuation could not pass from ``good`` to ``bad`` (closer than the accuracy's ``locate``)."""

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

    def placed(self, q: float) -> float:
        """``q`` as the walk from the drawn pose takes it. An angle more than a turn from the drawn one loses its
        whole turns (a revolute joint's pose repeats every turn) and is refused where floats are farther apart
        than the accuracy's ``locate``; a length more than :data:`FARTHEST` sizes from the drawn one is refused."""
        if not math.isfinite(q):
            raise InputError(f"input {self.joint} must be a finite number, got {q}")
        if not self.angular:
            if abs(q - self.q0) > FARTHEST * self.kin.size:
                raise InputError(f"input {self.joint} = {q:.6g} is far outside {self.kin.mech.name} (size "
                                 f"{self.kin.size:.4g}, drawn at {self.q0:.6g}): give a length within {FARTHEST:g} "
                                 "sizes of the drawn one")
            return q
        if math.ulp(q) > self.locate:
            raise InputError(f"input {self.joint} = {math.degrees(q):.6g}° is too large to mean an angle: floats there "
                             f"are {math.degrees(math.ulp(q)):.3g}° apart, coarser than the accuracy "
                             f"({math.degrees(self.locate):.3g}°); give an angle within a few turns")
        if abs(q - self.q0) < 2 * math.pi:
            return q
        return self.q0 + math.fmod(q - self.q0, 2 * math.pi)

    def reach(self, state, qa, qb):
        """State at ``qb`` from the state at ``qa``, halving the step on failure (raises :class:`Stuck`)."""
        try:
            return self.kin.positions(self.inputs(qb), state)
        except SolveFailure as failure:
            if abs(qb - qa) <= self.locate:
                raise Stuck(qa, qb, state, failure) from None
            mid = 0.5 * (qa + qb)
            return self.reach(self.reach(state, qa, mid), mid, qb)

    def walk(self, state, qa, qb, h=None):
        """Walk from ``qa`` to ``qb`` in pieces no longer than the resolution."""
        h = h or self.h
        n = max(1, math.ceil(abs(qb - qa) / h - 1e-9))
        for k in range(1, n + 1):
            state = self.reach(state, qa + (qb - qa) * (k - 1) / n, qa + (qb - qa) * k / n)
        return state

    def walk_far(self, state, qa, qb):
        """:meth:`walk`, and where it sticks for Newton's method, again from ``qa`` with positions to rounding.

        With a loose ``tol`` Newton's method accepts a pose a little off, and
        near a limit one a little beyond it, where none closes (0.01° beyond
        with ``tol`` 1e-2): the walk is taken again with positions to rounding,
        which stop only at the limit itself, so a limit and its ``within`` are
        those of the mechanism, not of the tolerance.
        """
        try:
            return self.walk(state, qa, qb)
        except Stuck as st:
            exact = PRESETS["exact"]
            if self.kin.accuracy.tol <= exact.tol or st.failure.kind not in (FailureKind.NEWTON, FailureKind.LIMIT):
                raise
            fine = Continuation(self.kin.with_accuracy(exact), self.joint, self.fixed)
            fine.h, fine.locate = self.h, self.locate
            return fine.walk(state, qa, qb)

    def start(self, q):
        """State at ``q`` reached from the drawn pose."""
        try:
            return self.walk_far(dict(self.kin.structure.drawn), self.q0, q)
        except Stuck as st:
            raise self.unreachable(q, st) from None

    def unreachable(self, q, st: Stuck) -> NumericalError:
        """The error for an input ``q`` that the walk from the drawn pose could not reach."""
        f = st.failure
        return NumericalError(f"input {self.fmt(q)} is not reachable from the drawn pose ({self.fmt(self.q0)}): "
                              f"{f} near input {self.fmt(st.good)}", kind=f.kind, condition=f.condition,
                              where={**f.where, "input": st.good})

    def fmt(self, q) -> str:
        return f"{math.degrees(q):.12g}°" if self.angular else f"{q:.12g}"


#: The most steps a sweep takes (a grid of more would not fit in memory, nor finish).
MAX_STEPS = 10_000_000
#: A length input is refused beyond this many times the mechanism's size from its drawn value.
FARTHEST = 100.0
#: A limit bisected on whether a group solves is known to no better than this many units in the last place of
#: the input.
PREDICATE_ULPS = 256
EPS = 2.0 ** -52


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
    return grid_points(start, stop, step).tolist()


def grid_points(start: float, stop: float, step: float) -> np.ndarray:
    """:func:`grid` as an array.

    >>> grid_points(0.0, 1.0, 0.4).tolist()
    [0.0, 0.4, 0.8, 1.0]
    """
    grid_size(start, stop, step)
    n = (stop - start) / step
    count = int(math.floor(abs(n) + 1e-9))
    sign = 1.0 if stop >= start else -1.0
    pts = start + sign * np.arange(count + 1) * step  # as start + sign·k·step, in one pass
    if abs(float(pts[-1]) - stop) > 1e-9 * max(1.0, abs(stop)):
        pts = np.append(pts, stop)
    return pts


def dead_point(cont: "Continuation", st: Stuck) -> DeadPoint:
    """The dead point where continuation stuck: its kind, input, group and joints."""
    f = st.failure
    kind = {"undetermined": DeadPointKind.UNDETERMINED, "jump": DeadPointKind.DISCONTINUITY}.get(f.kind, DeadPointKind.LIMIT)
    q = 0.5 * (st.good + st.bad)
    what = {"limit": "a limit (dead) position", "undetermined": "the pose is undetermined there",
            "discontinuity": "the pose would jump there (a discontinuity)"}[kind]
    msg = f"{f}; the input cannot pass {cont.fmt(q)} (last solved {cont.fmt(st.good)}): {what}"
    # bisected on whether the group solves, a test made in floating point: known to no better than some hundred
    # units in the last place of the input, however narrow the bracket
    within = max(abs(st.bad - st.good) / 2, PREDICATE_ULPS * EPS * max(1.0, abs(q)))
    return DeadPoint(q, within, kind, f.group.label, f.group.joints, msg)
