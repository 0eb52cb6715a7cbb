"""Position, velocity and acceleration of the groups a query needs.

A :class:`Kinematics` is compiled once per query: the outputs it names and
the derivative order. It keeps only the Assur groups those outputs depend on
(with ``method="assur"``; ``method="newton"`` keeps the whole mechanism as
one group, the loop-closure model of seed 000). Dyads are solved in closed
form (:mod:`domes.motion.planar.dyads`), larger groups by Newton's method with
the analytic Jacobian; velocities and accelerations of every group come
from its loop equations (seed 000, eqs. 4–5 with the corrected ``J̇φ̇``):
``J φ̇ = −B q̇``, ``J φ̈ = −B q̈ − Ḃ q̇ − J̇ φ̇``.

>>> from domes.motion.planar.examples import four_bar
>>> kin = Kinematics(four_bar(), outputs=["angle:rocker"], order=1)
>>> step = kin.at({"A": 0.0})
>>> round(step.values["angle:rocker"], 9), step.residual < 1e-12
(1.369438406, True)
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from enum import StrEnum

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.mechanism import Mechanism
from domes.motion.planar.dyads import DyadPlan, Unassembled, Undetermined
from domes.motion.planar.structure import Rotation, Structure, evaluate
from domes.results import Result, Status


@dataclass(frozen=True)
class Accuracy:
    """The accuracy knob of a query.

    ``tol``: Newton stops when its last correction is below ``tol`` (rad;
    slides relative to the size), leaving an error of order ``tol²``·cond
    (closed-form dyads are exact to rounding whatever ``tol``); ``step``: sweep resolution (rad for an R input; for a P input
    ``step·size``); ``locate``: how closely dead points and extremes are
    located (rad, or ``locate·size``); ``refine``: locate output extremes
    and singular points between steps; ``derivatives``: the largest error
    bound accepted for a velocity or acceleration (relative;
    :func:`error_bounds`): beyond it, near a singular point, derivatives are
    refused rather than returned.
    """

    name: str
    tol: float
    step: float
    locate: float
    refine: bool = True
    derivatives: float = 1e-6


#: Named presets: the trade of time for accuracy measured in ``docs/kinematics.md``.
PRESETS = {
    "fast": Accuracy("fast", 1e-4, math.radians(5.0), 1e-4, False, 1e-3),
    "default": Accuracy("default", 1e-9, math.radians(1.0), 1e-10, True, 1e-6),
    "exact": Accuracy("exact", 1e-15, math.radians(0.25), 1e-13, True, 1e-9),
}


def accuracy(spec=None, tol=None, step=None, derivatives=None) -> Accuracy:
    """An :class:`Accuracy` from a preset name (or an Accuracy), optionally overriding ``tol``, ``step``, ``derivatives``.

    >>> accuracy("fast", tol=1e-9).tol
    1e-09
    """
    if spec is None:
        spec = "default"
    if isinstance(spec, str):
        if spec not in PRESETS:
            raise InputError(f"accuracy preset must be one of {sorted(PRESETS)}, got {spec!r}")
        spec = PRESETS[spec]
    if tol is None and step is None and derivatives is None:
        return spec
    if tol is not None and not 0 < tol < 1:
        raise InputError(f"tol must be in (0, 1), got {tol}")
    if step is not None and not step > 0:
        raise InputError(f"step must be > 0, got {step}")
    if derivatives is not None and not derivatives > 0:
        raise InputError(f"derivatives (the largest accepted error bound) must be > 0, got {derivatives}")
    return Accuracy(f"{spec.name}*", tol if tol is not None else spec.tol, step if step is not None else spec.step,
                    min(spec.locate, tol) if tol is not None else spec.locate, spec.refine,
                    derivatives if derivatives is not None else spec.derivatives)


#: Beyond this condition number of a group's scaled Jacobian its pose is known only to about
#: √eps and its velocities not at all: derivatives are refused (the pose is a singular point).
SINGULAR_CONDITION = 1e7

EPS = 2.220446049250313e-16


def error_bounds(condition, order: int) -> list:
    """Relative error bounds of positions, velocities and accelerations from the condition number.

    Near a singular point the pose is known to about ``cond·ε`` (relative to
    the size); each derivative solves the same near-singular system once
    more with a Jacobian that carries that error, so the bound of order
    ``k`` is ``cond^(k+1)·ε``. Works on numbers and on numpy arrays.

    >>> [f"{e:.1e}" for e in error_bounds(3.3e6, 2)]
    ['7.3e-10', '2.4e-03', '8.0e+03']
    """
    with np.errstate(over="ignore", invalid="ignore"):
        out = [np.asarray(condition, dtype=float) ** (k + 1) * EPS for k in range(order + 1)]
    return [float(e) if e.ndim == 0 else e for e in out]


def refused(condition, order: int, tolerance: float) -> bool:
    """Whether derivatives up to ``order`` must be refused at this condition number (singular, or bound too large)."""
    if order == 0:
        return False
    return not (condition <= SINGULAR_CONDITION and error_bounds(condition, order)[order] <= tolerance)

#: The largest change of a rotation (rad) or of a slide (fraction of the size) accepted in one continuation step.
JUMP = 0.75


def sign_key(group) -> str:
    """The state entry that holds a dyad's assembly mode once a bifurcation has changed it."""
    return f"sign:{group.index}"


_as_accuracy = accuracy  # Kinematics takes an ``accuracy`` argument of the same name


class FailureKind(StrEnum):
    """Why a group could not be solved."""

    #: The group cannot be assembled at this input (beyond a limit position).
    LIMIT = "limit"
    #: The pose is not determined (coincident joints, parallel slides).
    UNDETERMINED = "undetermined"
    #: Newton's method failed (singular Jacobian during the iteration, or no convergence).
    NEWTON = "newton"
    #: Continuation would jump to another assembly mode (a bifurcation or discontinuity).
    JUMP = "jump"
    #: The Jacobian is singular: positions are known, their rates are not.
    SINGULAR = "singular"


class SolveFailure(NumericalError):
    """A group could not be solved at this input; ``kind`` is a :class:`FailureKind`, ``group`` the group."""

    def __init__(self, message, kind, group, condition=math.nan):
        super().__init__(message, kind=FailureKind(kind), condition=condition,
                         where={"group": group.label, "joints": tuple(group.joints)})
        self.group = group


@dataclass(frozen=True)
class Step(Result):
    """One solved configuration: output values by column name, loop closure and conditioning.

    ``residual`` is the largest loop-closure error relative to the
    mechanism's size, ``condition`` the largest condition number of a
    solved group's scaled Jacobian (1 when no group has unknowns).
    Derivative columns end in ``'`` (velocity) and ``''`` (acceleration).
    A configuration that cannot be solved raises a
    :class:`~domes.errors.NumericalError` instead, so a step is always COMPLETE.
    ``passed`` lists the branch points (bifurcation dead points) passed on
    the way from the drawn pose.
    """

    inputs: dict
    values: dict
    residual: float
    condition: float
    state: dict = field(repr=False, compare=False, default_factory=dict)
    passed: tuple = field(repr=False, compare=False, default=())

    status = Status.COMPLETE

    @property
    def bounds(self) -> list[float]:
        """Estimated relative error bounds of the positions, velocities and accelerations (:func:`error_bounds`)."""
        return error_bounds(self.condition, 2)

    @property
    def message(self) -> str:
        text = f"solved: residual {self.residual:.2g}, condition {self.condition:.3g}"
        if self.passed:
            text += f"; passed {len(self.passed)} branch points on the way: " + "; ".join(d.message for d in self.passed)
        return text


@dataclass(frozen=True)
class Output:
    """A requested output: ``kind`` in angle / slide / point."""

    kind: str
    target: str

    @property
    def name(self) -> str:
        return f"{self.kind}:{self.target}"

    def columns(self) -> list[str]:
        return [f"{self.name}.x", f"{self.name}.y"] if self.kind == "point" else [self.name]


def parse_outputs(mech: Mechanism, names) -> list[Output]:
    """Outputs from names ``angle:LINK``, ``slide:JOINT``, ``point:NAME`` (or a bare link, joint or point name).

    No names: every moving link's angle, every slide and every coupler point.
    """
    if not names:
        outs = [Output("angle", x) for x in mech.links if x != mech.ground]
        outs += [Output("slide", j.name) for j in mech.joints if j.kind == "P"]
        outs += [Output("point", p.name) for p in mech.points]
        return outs
    joints = {j.name: j for j in mech.joints}
    points = {p.name for p in mech.points}
    outs = []
    for name in names:
        kind, _, target = name.partition(":") if ":" in name else ("", "", name)
        if not kind:
            kind = "angle" if target in mech.links else "slide" if joints.get(target) and joints[target].kind == "P" \
                else "point" if target in joints or target in points else ""
        ok = (kind == "angle" and target in mech.links) or (kind == "slide" and target in joints and joints[target].kind == "P") \
            or (kind == "point" and (target in joints or target in points))
        if not ok:
            raise InputError(f"output {name!r}: use angle:LINK (links {list(mech.links)}), slide:JOINT (P joints "
                             f"{[j for j in joints if joints[j].kind == 'P']}) or point:NAME (joints and points "
                             f"{sorted(set(joints) | points)})")
        outs.append(Output(kind, target))
    return outs


class Kinematics:
    """A compiled query: outputs, derivative order, method and accuracy of one mechanism."""

    def __init__(self, mech: Mechanism, outputs=None, order: int = 0, method: str = "assur", accuracy=None):
        if order not in (0, 1, 2):
            raise InputError(f"order must be 0, 1 or 2, got {order}")
        self.mech = mech
        self.order = order
        self.accuracy = _as_accuracy(accuracy)
        self.structure = s = Structure.of(mech, method)
        self.outputs = parse_outputs(mech, outputs)
        links = set()
        for o in self.outputs:
            if o.kind == "angle":
                links.add(o.target)
            elif o.kind == "slide":
                links |= set(mech.joint(o.target).links)
            else:
                links.add(mech.point(o.target)[0])
        self.groups = [s.groups[i] for i in s.needed(links)]
        self.size = mech.size
        self.plans = {}
        self._outer_paths = {}
        solved = {mech.ground} | {x for g in self.groups for x in g.links}
        for g in self.groups:
            if method == "assur" and g.kind in ("RRR", "RRP", "RPR", "PRP", "RPP"):
                self.plans[g.index] = DyadPlan.of(mech, g)
                allowed = {mech.ground} | {x for i in s.needed(g.links) if i != g.index for x in s.groups[i].links}
                for jn in g.joints:
                    j = mech.joint(jn)
                    known = [x for x in j.links if x not in g.links]
                    if known:
                        self._outer_paths[jn] = s.point_path(known[0], j.at, allowed)
        self._output_paths = {}
        for o in self.outputs:
            if o.kind == "point":
                link, at = mech.point(o.target)
                self._output_paths[o.target] = s.point_path(link, at, solved)
        self.inputs = {i.joint: i for i in mech.inputs}
        #: Groups solved so far (for showing that a query solves only what it needs).
        self.groups_solved = 0

    # -- bookkeeping ---------------------------------------------------------------------

    def with_accuracy(self, spec) -> "Kinematics":
        """The same query with another accuracy."""
        other = copy.copy(self)
        other.accuracy = _as_accuracy(spec)
        return other

    @property
    def equations(self) -> int:
        """Scalar loop equations of the groups this query solves."""
        return sum(g.equations for g in self.groups)

    def drawn_inputs(self) -> dict:
        """Input values in the drawn pose, by driven joint."""
        return {j: self.structure.drawn[v] for j, v in self.structure.input_vars.items()}

    def _input_values(self, inputs: dict) -> dict:
        out = {}
        for j, v in self.structure.input_vars.items():
            if j not in inputs:
                raise InputError(f"input joint {j!r} needs a value")
            out[v] = float(inputs[j])
            if not math.isfinite(out[v]):
                raise InputError(f"input joint {j!r}: the value must be a finite number, got {inputs[j]!r}")
        unknown = set(inputs) - set(self.structure.input_vars)
        if unknown:
            raise InputError(f"{sorted(unknown)} are not driven joints; inputs are {sorted(self.structure.input_vars)}")
        return out

    # -- positions -------------------------------------------------------------------------

    def positions(self, inputs: dict, guess: dict | None = None) -> dict:
        """Values of all variables of the needed groups at ``inputs``, continuing from ``guess``."""
        values = dict(self.structure.drawn if guess is None else guess)
        values.update(self._input_values(inputs))
        derived = self.structure.derived
        for g in self.groups:
            # derived variables of the group that depend on known ones only (all of them, but in a single Newton
            # group of every link) are set before its loops are solved
            values.update({v: derived[v].value(values) for v in self.structure.derived_of(g)})
            if not g.unknowns:
                continue
            before = [values[v] for v in g.unknowns]
            try:
                if g.index in self.plans:
                    self._dyad(g, values)
                else:
                    self._newton(g, values)
            except Unassembled as exc:
                raise SolveFailure(str(exc), FailureKind.LIMIT, g) from None
            except Undetermined as exc:
                raise SolveFailure(str(exc), FailureKind.UNDETERMINED, g) from None
            if guess is not None:
                self._check_jump(g, before, values)
        self.groups_solved += sum(1 for g in self.groups if g.unknowns)
        return values

    def _check_jump(self, g, before, values):
        """Continuation may not jump: a rotation changing by more than :data:`JUMP` rad (or a slide by
        ``JUMP·size``) in one step means a change of assembly mode or a discontinuity."""
        for v, old in zip(g.unknowns, before):
            change = abs(values[v] - old) / (1.0 if v.startswith("rot:") else self.size)
            if change > JUMP:
                what = f"{math.degrees(change):.1f}°" if v.startswith("rot:") else f"{change:.3g} of the size"
                raise SolveFailure(f"{g.label}: {v} jumped by {what} in one step at joints {', '.join(g.joints)} "
                                   "(a discontinuity or change of assembly mode)", FailureKind.JUMP, g)

    def _dyad(self, g, values):
        plan = self.plans[g.index]
        rot = self.structure.rotations

        def world(joint):
            return tuple(evaluate(self._outer_paths[joint.name], values)[0])

        rotations, slides = plan.solve(world, lambda link: rot[link].value(values), values.get(sign_key(g)))
        for link, delta in rotations.items():
            expr = rot[link]
            var, coeff = next((v, c) for v, c in expr.terms if v in g.unknowns)
            rest = sum(c * values[v] for v, c in expr.terms if v != var) + expr.const
            new = (delta - rest) / coeff
            old = values[var]
            values[var] = old + math.remainder(new - old, 2 * math.pi)
        for jn, s in slides.items():
            values[self.structure.input_vars.get(jn, f"s:{jn}")] = s

    def _newton(self, g, values, maxit=60):
        """Newton's method on the group's loop equations (seed 000, eqs. 2–3) with the analytic Jacobian.

        Stops when the last correction (rotations in rad, slides over the
        size) is below ``tol``: the error left is then of order ``tol²``·cond.
        """
        tol = self.accuracy.tol
        x = np.array([values[v] for v in g.unknowns], float)
        scale = np.array([1.0 if v.startswith("rot:") else 1.0 / self.size for v in g.unknowns])
        last = math.inf
        for it in range(maxit):
            A, J = self._assemble(g, values)
            if not np.any(A):
                return
            try:
                dx = np.linalg.solve(J, -A)
            except np.linalg.LinAlgError:
                raise SolveFailure(f"{g.label}: Jacobian singular during Newton iteration", FailureKind.NEWTON, g) from None
            rot = [i for i, v in enumerate(g.unknowns) if v.startswith("rot:")]
            cap = max((abs(dx[i]) for i in rot), default=0.0)
            if cap > 0.5:
                dx *= 0.5 / cap
            x = x + dx
            for v, val in zip(g.unknowns, x):
                values[v] = float(val)
            size = float(np.max(np.abs(dx * scale)))
            if size <= tol or (size <= 1e-9 and size >= 0.9 * last):  # converged, or stalled at rounding
                return
            last = size
        raise SolveFailure(f"{g.label}: Newton's method did not converge (last correction {size:.3g})", FailureKind.NEWTON, g)

    def _assemble(self, g, values, rates=None):
        """``A`` (2L), ``J`` (2L×U) and, with ``rates``, the right-hand sides' parts."""
        A = np.zeros(g.equations)
        J = np.zeros((g.equations, len(g.unknowns)))
        col = {v: k for k, v in enumerate(g.unknowns)}
        for i, loop in enumerate(g.loops):
            a, cols, _ = evaluate(loop, values)
            A[2 * i:2 * i + 2] = a
            for v, c in cols.items():
                if v in col:
                    J[2 * i:2 * i + 2, col[v]] = c
        return A, J

    # -- derivatives -------------------------------------------------------------------

    def motion(self, values: dict, order: int, speeds: dict | None = None, accelerations: dict | None = None):
        """Rates and accelerations of all needed variables, the worst residual and condition number.

        Input rates are the mechanism's (``Input.speed``, ``Input.acceleration``) unless given by joint.
        """
        speeds, accelerations = speeds or {}, accelerations or {}
        rates = {v: speeds.get(j, self.inputs[j].speed) for j, v in self.structure.input_vars.items()}
        accels = {v: accelerations.get(j, self.inputs[j].acceleration) for j, v in self.structure.input_vars.items()}
        residual, condition = 0.0, 1.0
        for g in self.groups:
            self._derive_rates(rates, accels, values)
            if not g.unknowns:
                continue
            col = {v: k for k, v in enumerate(g.unknowns)}
            n = g.equations
            A = np.zeros(n)
            J = np.zeros((n, len(g.unknowns)))
            loops = []
            for i, loop in enumerate(g.loops):
                a, cols, _ = evaluate(loop, values)
                A[2 * i:2 * i + 2] = a
                loops.append(cols)
                for v, c in cols.items():
                    if v in col:
                        J[2 * i:2 * i + 2, col[v]] = c
            residual = max(residual, float(np.max(np.abs(A))) / self.size)
            scale = np.array([1.0 / self.size if v.startswith("rot:") else 1.0 for v in g.unknowns])
            cond = float(np.linalg.cond(J * scale)) if len(g.unknowns) else 1.0
            condition = max(condition, cond if math.isfinite(cond) else math.inf)
            if order == 0:
                continue
            if not math.isfinite(cond) or cond > SINGULAR_CONDITION:
                raise SolveFailure(f"{g.label}: Jacobian singular (condition {cond:.3g}); velocities are undetermined "
                                   f"at joints {', '.join(g.joints)}", FailureKind.SINGULAR, g, cond)
            if refused(cond, order, self.accuracy.derivatives):
                what = "velocities" if order == 1 else "accelerations"
                raise SolveFailure(f"{g.label}: near a singular point at joints {', '.join(g.joints)} (condition "
                                   f"{cond:.3g}) the {what} are known only to {error_bounds(cond, order)[order]:.2g} "
                                   f"(relative), more than the accuracy's {self.accuracy.derivatives:g}; they are "
                                   "refused (ask a lower order, or another input)", FailureKind.SINGULAR, g, cond)
            rhs = np.zeros(n)
            for i, cols in enumerate(loops):
                for v, c in cols.items():
                    if v not in col:
                        rhs[2 * i:2 * i + 2] -= np.asarray(c) * rates[v]
            sol = np.linalg.solve(J, rhs)
            rates.update(zip(g.unknowns, map(float, sol)))
            if order == 1:
                continue
            rhs = np.zeros(n)
            for i, loop in enumerate(g.loops):
                _, cols, dcols = evaluate(loop, values, rates)
                for v, c in cols.items():
                    if v not in col:
                        rhs[2 * i:2 * i + 2] -= np.asarray(c) * accels[v]
                for v, c in dcols.items():
                    rhs[2 * i:2 * i + 2] -= np.asarray(c) * rates[v]
            sol = np.linalg.solve(J, rhs)
            accels.update(zip(g.unknowns, map(float, sol)))
        self._derive_rates(rates, accels, values)
        return rates, accels, residual, condition

    def _derive_rates(self, rates, accels, values=None):
        """Rates and accelerations of the derived variables whose terms' are known: racks' slides (linear) and,
        given the ``values``, cams' followers (:class:`~domes.motion.planar.structure.CamTie`)."""
        for v, expr in self.structure.derived.items():
            if isinstance(expr, Rotation):
                for store in (rates, accels):
                    if v not in store and all(t in store for t, _ in expr.terms):
                        store[v] = expr.rate(store)
            elif values is not None and v not in rates and all(t in rates for t, _ in expr.terms):
                rate, accel = expr.motion(values, rates, accels if all(t in accels for t, _ in expr.terms) else None)
                rates[v] = rate
                if accel is not None:
                    accels[v] = accel

    # -- outputs -----------------------------------------------------------------------

    def output_values(self, values, rates, accels, order, lib=math) -> dict:
        """The output columns from the variables, their rates and accelerations (numbers, or arrays with ``lib=np``)."""
        out = {}
        s = self.structure
        mech = self.mech
        for o in self.outputs:
            if o.kind == "angle":
                expr = s.rotations[o.target]
                ref = 0.0 if o.target == mech.ground else mech.reference_angle(o.target)
                comps = [[ref + expr.value(values)]]
                if order >= 1:
                    comps.append([expr.rate(rates)])
                if order >= 2:
                    comps.append([expr.rate(accels)])
            elif o.kind == "slide":
                v = s.input_vars.get(o.target, f"s:{o.target}")
                comps = [[values[v]], [rates.get(v, 0.0)], [accels.get(v, 0.0)]][: order + 1]
            else:
                segs = self._output_paths[o.target]
                a, cols, dcols = evaluate(segs, values, rates if order >= 2 else None, lib=lib)
                comps = [list(a)]
                if order >= 1:
                    comps.append([sum(c[k] * rates[v] for v, c in cols.items()) for k in (0, 1)])
                if order >= 2:
                    comps.append([sum(c[k] * accels[v] for v, c in cols.items())
                                  + sum(c[k] * rates[v] for v, c in dcols.items()) for k in (0, 1)])
            for k, comp in enumerate(comps):
                for name, val in zip(o.columns(), comp):
                    out[name + "'" * k] = float(val) if lib is math else val
        return out

    def at(self, inputs: dict, guess: dict | None = None, order: int | None = None, speeds: dict | None = None,
           accelerations: dict | None = None) -> Step:
        """Solve one configuration (no continuation: ``guess`` sets the branch for Newton groups).

        ``speeds`` and ``accelerations`` (by input joint) replace the mechanism's input rates.
        """
        order = self.order if order is None else order
        values = self.positions(inputs, guess)
        rates, accels, residual, condition = self.motion(values, order, speeds, accelerations)
        return Step(dict(inputs), self.output_values(values, rates, accels, order), residual, condition, values)
