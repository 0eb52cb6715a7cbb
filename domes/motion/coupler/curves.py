"""Coupler curves of any planar mechanism of dyads: every circuit, traced with the backend.

A *circuit* is one connected piece of the mechanism's configuration space:
the coupler point traces a closed curve on it. A crank-rocker has two (the
open and the crossed assembly), a triple rocker one (its two assembly modes
join at the limits), a parallelogram two that cross at its change points.
:func:`trace` samples every assembly mode (each dyad's sign) over a full turn
of the input with the kernel, then walks each circuit with the sweep's walker
(:mod:`~domes.motion.planar.branches`): branch-continuous, limits located to
the accuracy's ``locate`` (the root of the dyad's assembly margin), branch
points passed on the smooth branch, gaps narrower than a step not stepped over. At a
limit the walk turns back in the assembly mode that meets it there, so a
circuit is followed to its end whatever its shape; it closes when it returns
to its start in its first mode.

>>> from domes.motion.coupler.fourbar import four_bar
>>> c = trace(four_bar(2, 2, 2.5, 3, 1, 0.5))            # seed 000 T9's triple rocker: one circuit
>>> len(c.circuits), c.circuits[0].full_turn, [str(d.kind) for d in c.circuits[0].limits]
(1, False, ['limit', 'limit'])
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from itertools import product

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.coupler.fourbar import joints_meet, lengths_of
from domes.motion.planar.arrays import Compiled, motion_many, outputs_many, positions_many
from domes.motion.planar.branches import Walker
from domes.motion.planar.continuation import Continuation, DeadPoint, Stuck, dead_point
from domes.motion.planar.kernel import SIGNED, vectorizable
from domes.motion.planar.query import Kinematics, sign_key
from domes.results import Result, Status

#: Samples of a full input turn used to find every assembly mode's assembled ranges.
SAMPLES = 720
#: Input turns a circuit may need before it closes (a change-point linkage may need two).
MAX_TURNS = 4


@dataclass(frozen=True, eq=False)
class Circuit:
    """One closed coupler curve: the point's positions and velocities along it, and what bounds it.

    ``inputs`` are the input values along the walk (not reduced modulo a
    turn), ``points`` the ``(n, 2)`` positions, ``velocities`` their rates
    (per unit input rate; NaN where refused), ``modes`` each dyad's sign at
    each point. ``limits`` are the located limit positions where the walk
    turned back; ``branch_points`` the bifurcations passed. ``full_turn`` is
    true when the input turns fully on this circuit (no limit).
    """

    inputs: np.ndarray
    points: np.ndarray
    velocities: np.ndarray
    modes: np.ndarray
    limits: tuple[DeadPoint, ...]
    branch_points: tuple[DeadPoint, ...]
    states: dict = field(default_factory=dict, repr=False)
    extra: dict = field(default_factory=dict, repr=False)

    def state(self, i: int) -> dict:
        """The mechanism's configuration (the query's variables) at point ``i``."""
        return {v: float(a[i]) for v, a in self.states.items()}

    @property
    def full_turn(self) -> bool:
        return not self.limits

    @property
    def turns(self) -> float:
        """Input turns walked to close the circuit (limits walk back and forth)."""
        closing = abs(math.remainder(self.inputs[0] - self.inputs[-1], 2 * math.pi))
        return (float(np.sum(np.abs(np.diff(self.inputs)))) + closing) / (2 * math.pi)

    @property
    def length(self) -> float:
        """The length of the closed curve (polyline through the points)."""
        closed = np.vstack([self.points, self.points[:1]])
        return float(np.sum(np.hypot(*np.diff(closed, axis=0).T)))


@dataclass(frozen=True, eq=False)
class CouplerCurve(Result):
    """The coupler curves of a point of a mechanism: one :class:`Circuit` each."""

    mechanism: str
    point: str
    circuits: tuple[Circuit, ...]
    status: Status = Status.COMPLETE
    notes: tuple[str, ...] = field(default=())
    compiled: object = field(default=None, repr=False)
    continuation: object = field(default=None, repr=False)

    def positions(self, circuit: Circuit, i: int, inputs) -> np.ndarray:
        """The point's positions ``(n, 2)`` at ``inputs`` reached from point ``i`` of ``circuit`` (its branch)."""
        run = positions_many(self.compiled, self.continuation.joint, np.asarray(inputs, dtype=float), circuit.state(i),
                             self.continuation.fixed)
        out = outputs_many(self.compiled.kin, run.values, {}, {}, 0)
        name = self.compiled.kin.outputs[0].name
        pts = np.c_[out[f"{name}.x"], out[f"{name}.y"]]
        if run.failure is not None:
            pts[run.failure[0]:] = np.nan
        return pts

    @property
    def message(self) -> str:
        parts = []
        for k, c in enumerate(self.circuits, 1):
            what = "full turn" if c.full_turn else f"{len(c.limits)} limits"
            if c.branch_points:
                what += f", {len(c.branch_points)} branch points"
            parts.append(f"circuit {k}: {c.points.shape[0]} points, {what}")
        return f"{self.status}: point {self.point} of {self.mechanism}: {len(self.circuits)} circuits (" + \
            "; ".join(parts) + ")"


#: Samples per input turn a trace accepts (a million resolves 6e-6 rad; more only costs memory).
MIN_SAMPLES, MAX_SAMPLES = 8, 1_000_000


def trace(mech: Mechanism, point: str | None = None, samples: int = SAMPLES, accuracy=None,
          extra: tuple[str, ...] = ()) -> CouplerCurve:
    """Every circuit of the curve of ``point`` (default: the first coupler point) as the input turns.

    ``samples`` points per input turn; the accuracy's ``locate`` bounds the
    limits' location. Mechanisms of drivers and dyads with one R input.
    ``extra`` names other joints or points whose positions each circuit
    keeps too (``Circuit.extra``).
    """
    if point is None:
        if not mech.points:
            raise InputError(f"{mech.name}: no coupler point to trace; name a joint or add a point")
        point = mech.points[0].name
    if not MIN_SAMPLES <= samples <= MAX_SAMPLES:
        raise InputError(f"samples must be between {MIN_SAMPLES} and {MAX_SAMPLES:,} per turn, got {samples}")
    _check_folding(mech)
    kin = Kinematics(mech, [f"point:{point}"] + [f"point:{x}" for x in extra], 1, "assur", accuracy)
    if not vectorizable(kin):
        raise InputError(f"{mech.name}: coupler curves are traced for mechanisms of drivers and dyads; its groups "
                         f"{[g.kind for g in kin.groups]} need Newton's method")
    cont = Continuation(kin)
    if not cont.angular:
        raise InputError(f"{mech.name}: the input {cont.joint} is a P joint; coupler curves follow a turning input")
    cont.h = 2 * math.pi / samples
    compiled = Compiled(kin)
    tracer = _Tracer(kin, cont, compiled, samples)
    circuits = tracer.all()
    notes = ()
    if not circuits:
        notes = ("the mechanism assembles at no sampled input",)
    return CouplerCurve(mech.name, point, tuple(circuits), Status.COMPLETE if circuits else Status.EMPTY, notes,
                        compiled, cont)


def _check_folding(mech: Mechanism) -> None:
    """An InputError for a four-bar whose joints can meet (a folding linkage): its motion branches there, so it has
    no coupler curve to follow, and a trace would run back and forth over itself."""
    lengths = lengths_of(mech)
    meet = joints_meet(*lengths) if lengths is not None else None
    if meet:
        a, b, c, d = lengths
        raise InputError(f"{mech.name}: a folding four-bar (a, b, c, d = {a:g}, {b:g}, {c:g}, {d:g}): {meet}; there "
                         "the loop's position is undetermined and the motion can switch branches (a change point), "
                         "so there is no single coupler curve to trace; change a length a little (e.g. the frame "
                         "by 1%) to trace the curves on either side")


class _Tracer:
    """Finds every circuit: assembly modes sampled on a grid, each unvisited sample walked to a closed circuit."""

    def __init__(self, kin, cont, compiled, samples):
        self.kin, self.cont, self.compiled, self.n = kin, cont, compiled, samples
        self.signed = [g for g in kin.groups if g.index in kin.plans and kin.plans[g.index].kind in SIGNED]
        self.modes = [tuple(m) for m in product((1.0, -1.0), repeat=len(self.signed))]
        self.q0 = cont.q0
        self.grid = self.q0 + np.arange(samples) * cont.h
        self.columns = None

    def assembled(self) -> np.ndarray:
        """``(modes, samples)``: where each assembly mode closes every dyad."""
        prog, geom = self.compiled.program, self.compiled.program.geometry()
        count = len(self.modes)
        geom.count = count
        for k, g in enumerate(self.signed):
            geom.sign[g.index] = np.array([m[k] for m in self.modes])[:, None]
        with np.errstate(invalid="ignore", divide="ignore"):
            pose = prog.poses(geom, self.grid[None, :])
        failed = np.broadcast_to(pose.failed, (count, self.n)) if np.ndim(pose.failed) else np.zeros((count, self.n), bool)
        return ~failed

    def state(self, q, mode) -> dict | None:
        start = dict(self.kin.structure.drawn)
        start.update({sign_key(g): s for g, s in zip(self.signed, mode)})
        run = positions_many(self.compiled, self.cont.joint, np.array([q]), start, self.cont.fixed, jumps=False)
        return None if run.failure is not None else run.state(0)

    def all(self) -> list[Circuit]:
        ok = self.assembled()
        visited = np.zeros_like(ok)
        circuits = []
        while True:
            free = np.argwhere(ok & ~visited)
            if not free.size:
                return circuits
            m, i = free[0]
            state = self.state(self.grid[i], self.modes[m])
            if state is None:
                visited[m, i] = True
                continue
            circuit = self.walk(state, self.grid[i], self.modes[m])
            marked = self.mark(circuit, visited)
            visited[m, i] = True
            if marked or not circuits:
                circuits.append(circuit)

    def mark(self, circuit, visited) -> int:
        """Mark the grid samples the circuit passes (in the mode it passes them in); how many were new."""
        k = (circuit.inputs - self.q0) / self.cont.h
        near = np.abs(k - np.round(k)) <= 1e-6
        index = np.round(k[near]).astype(int) % self.n
        modes = circuit.modes[near]
        new = 0
        lookup = {m: j for j, m in enumerate(self.modes)}
        for i, mode in zip(index, map(tuple, modes)):
            j = lookup.get(mode)
            if j is not None and not visited[j, i]:
                visited[j, i] = True
                new += 1
        return new

    def walk(self, state0, q0, mode0) -> Circuit:
        """Walk from ``(q0, mode0)`` forward, turning back at every limit, until the start comes round again."""
        walker = Walker(self.cont, self.compiled)
        h = self.cont.h
        legs = [(np.array([q0]), {v: np.array([x]) for v, x in state0.items()})]
        limits, branch = [], []
        state, q, direction = state0, q0, 1.0
        budget = MAX_TURNS * self.n + 4
        first = True
        while budget > 0:
            steps = self.n if first else min(self.n, budget)
            base = math.floor((q - self.q0) / h + 1e-9) if direction > 0 else math.ceil((q - self.q0) / h - 1e-9)
            pts = self.q0 + (base + direction * np.arange(1, steps + 1)) * h
            w = walker.walk(state, q, pts)
            xs = pts[:w.count]
            values = {v: a[:w.count] for v, a in w.values.items()}
            branch += w.branch_points
            closing = None if first else self._closing(xs, values, direction, q0, mode0)
            if closing is not None:
                legs.append((xs[:closing], {v: a[:closing] for v, a in values.items()}))
                break
            legs.append((xs, values))
            budget -= max(w.count, 1)
            first = False
            if w.stuck is None:  # a whole turn without a limit: closed if back in the first mode
                if direction > 0 and self._mode(w.state) == mode0:
                    legs[-1] = (xs[:-1], {v: a[:-1] for v, a in values.items()})  # its last point is the first
                    break
                state, q = w.state, xs[-1]
                continue
            stuck = w.stuck
            limits.append(walker.limit(stuck) or dead_point(self.cont, stuck))
            last = (xs[-1], {v: a[-1] for v, a in values.items()}) if w.count else (q, state)
            legs.append(self._approach(last[1], last[0], stuck.good))
            state, q = self._turn(stuck)
            legs.append(self._approach(state, stuck.good, pts[w.count - 1] if w.count else q, reverse=True))
            direction = -direction
        return self._circuit(legs, limits, branch)

    def _approach(self, state, x_from, x_to, count=8, reverse=False):
        """Inputs from ``x_from`` to ``x_to`` crowded towards the limit (where the input barely moves the point).

        Forward the last one is ``x_to`` (the limit); with ``reverse`` the walk
        leaves the limit ``x_from`` and stops short of ``x_to``.
        """
        t = np.arange(1, count + 1) / count if not reverse else np.arange(0, count) / count
        xs = x_from + (x_to - x_from) * (1 - (1 - t) ** 2) if not reverse else x_from + (x_to - x_from) * t ** 2
        run = positions_many(self.compiled, self.cont.joint, xs, state, self.cont.fixed)
        keep = run.failure[0] if run.failure is not None else xs.size
        return xs[:keep], {v: (a[:keep] if isinstance(a, np.ndarray) and a.ndim else np.full(keep, float(a)))
                           for v, a in run.values.items()}

    def _mode(self, state) -> tuple:
        return tuple(float(state.get(sign_key(g), self.kin.plans[g.index].sign)) for g in self.signed)

    def _closing(self, xs, values, direction, q0, mode0):
        """Index where the walk passes ``q0`` (mod a turn) forward in the first mode, or None."""
        if direction < 0 or not xs.size:
            return None
        turns = (xs - q0) / (2 * math.pi)
        k = np.abs(turns - np.round(turns)) * 2 * math.pi <= 1e-9 + 1e-12 * abs(q0)
        for i in np.flatnonzero(k):
            if self._mode({v: a[i] for v, a in values.items() if v.startswith("sign:")}) == mode0:
                return int(i)
        return None

    def _turn(self, stuck: Stuck):
        """At a limit: the configuration of the other assembly mode of the dyad that meets it, and its input."""
        g = stuck.failure.group
        state = dict(stuck.state)
        key = sign_key(g)
        if g.index in self.kin.plans and self.kin.plans[g.index].kind in SIGNED:
            state[key] = -state.get(key, self.kin.plans[g.index].sign)
        run = positions_many(self.compiled, self.cont.joint, np.array([stuck.good]), state, self.cont.fixed, jumps=False)
        if run.failure is not None:
            raise InputError(f"the coupler curve cannot be followed past the limit at input {self.cont.fmt(stuck.good)} "
                             f"({stuck.failure})")
        return run.state(0), stuck.good

    def _circuit(self, legs, limits, branch) -> Circuit:
        xs = np.concatenate([x for x, _ in legs])
        keys = set().union(*(v.keys() for _, v in legs))
        values = {k: np.concatenate([np.broadcast_to(v.get(k, np.nan), x.shape) for x, v in legs]) for k in keys}
        rates, accels, _, _ = motion_many(self.kin, values, 1)
        out = outputs_many(self.kin, values, rates, accels, 1)
        name = self.kin.outputs[0].name
        pts = np.c_[out[f"{name}.x"], out[f"{name}.y"]]
        vel = np.c_[out[f"{name}.x'"], out[f"{name}.y'"]]
        extra = {o.target: np.c_[out[f"{o.name}.x"], out[f"{o.name}.y"]] for o in self.kin.outputs[1:]}
        columns = [values.get(sign_key(g), np.full(xs.shape, self.kin.plans[g.index].sign)) for g in self.signed]
        modes = np.stack(columns, axis=1) if columns else np.empty((xs.size, 0))
        return Circuit(xs, pts, vel, modes, tuple(limits), tuple(branch), values, extra)
