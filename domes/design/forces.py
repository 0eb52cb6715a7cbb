"""Design checks that need forces: force amplification near a toggle, wheel rate, the actuator's load.

* :func:`force_ratio`: the force an output point delivers along its path
  (or the torque of an output link) per unit force or torque at the input,
  over the input's range; at a toggle the output stands still and the ratio
  grows without bound (the hinge clamp, a drum held near dead centre). The
  toggle is located, and the distance from it at which a requested ratio is
  reached, in the input's and the output's units.
* :func:`wheel_rate`: a suspension's leverage ratio (wheel travel per spring
  compression) and wheel rate (vertical wheel force per travel) over the
  travel, from the spring of the mechanism file (the motorcycle).
* :func:`drive`: the input's force or torque over a range from the file's
  masses, loads and springs, with its peak (the tyre drum's actuator).

All three run the inverse dynamics (:mod:`domes.design.dynamics`) on the
mechanism: static for the first two (loads only), at the file's speed for the last.

>>> from domes.motion.planar.examples import four_bar
>>> r = force_ratio(four_bar(), "angle:rocker", 0.0, math.radians(30), math.radians(5))
>>> r.success, round(float(r.ratio[0]), 6)        # rocker torque per crank torque: the rocker turns half as fast
(True, 2.0)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from domes.design.dynamics import inverse_dynamics
from domes.errors import InputError
from domes.model.masses import Load, MassModel
from domes.model.mechanism import Mechanism
from domes.motion.planar.checks import toggle_near
from domes.motion.planar.query import parse_outputs
from domes.results import Result, Status

__all__ = ["Drive", "ForceRatio", "WheelRate", "drive", "force_ratio", "wheel_rate"]


def _statics(mech: Mechanism, loads=(), springs=()) -> Mechanism:
    """The mechanism without masses and gravity, with only the given loads and springs; inputs at unit speed
    (so that velocities are derivatives with respect to the input)."""
    inputs = tuple(dataclasses.replace(i, speed=1.0, acceleration=0.0) for i in mech.inputs)
    return dataclasses.replace(mech, inputs=inputs, masses=MassModel(loads=tuple(loads), springs=tuple(springs)))


def _joint(mech: Mechanism, joint: str | None) -> str:
    if not mech.inputs:
        raise InputError(f"{mech.name}: the mechanism has no input")
    return joint or mech.inputs[0].joint


@dataclass(frozen=True, eq=False)
class ForceRatio(Result):
    """Output force (along the output point's path) or torque per unit input force or torque, over the inputs.

    ``ratio`` is ``inf`` where the output stands still (a toggle). ``toggles``
    are the inputs where it does (located); ``reached`` is, when a ``wanted``
    ratio is given, ``(input, distance from the toggle in input units,
    distance in output units)`` for the nearest toggle at which it is reached.
    """

    mechanism: str
    output: str
    joint: str
    angular: bool
    inputs: np.ndarray
    ratio: np.ndarray
    output_values: np.ndarray
    toggles: tuple[float, ...]
    wanted: float | None
    reached: tuple[float, float, float] | None
    status: Status

    @property
    def message(self) -> str:
        f = math.degrees if self.angular else float
        u = "°" if self.angular else ""
        finite = self.ratio[np.isfinite(self.ratio)]
        text = (f"{self.mechanism}: force ratio {self.output} / input {self.joint} from {finite.min():.4g} to "
                f"{finite.max():.4g} over {f(self.inputs[0]):.6g}{u} .. {f(self.inputs[-1]):.6g}{u}")
        if self.toggles:
            text += "; toggle (ratio without bound) at " + ", ".join(f"{f(q):.6g}{u}" for q in self.toggles)
        else:
            text += "; no toggle in the range"
        if self.wanted is not None:
            if self.reached is None:
                text += f"; the ratio {self.wanted:g} is not reached"
            else:
                q, d_in, d_out = self.reached
                ou = "°" if self.output.startswith("angle:") else ""
                text += (f"; the ratio {self.wanted:g} is reached at {f(q):.6g}{u}, {f(d_in):.4g}{u} of input "
                         f"(and {d_out:.4g}{ou} of {self.output}) from the toggle")
        return text


def _output_column(mech: Mechanism, output: str) -> tuple[str, str, str]:
    """The output's kind, target and full name (``point:NAME``, also for a bare name as the kinematics take)."""
    out = parse_outputs(mech, [output])[0]
    if out.kind == "slide":
        raise InputError(f"force ratio: the output is a point (point:NAME) or a link (angle:LINK), not {output!r}")
    return out.kind, out.target, out.name


def force_ratio(mech: Mechanism, output: str, start: float, stop: float, step: float | None = None,
                wanted: float | None = None, joint: str | None = None, accuracy=None) -> ForceRatio:
    """The force amplification from the input to ``output`` (``point:NAME`` or ``angle:LINK``) over the range.

    For a point, unit loads in x and in y at the point give the input
    forces ``f_x``, ``f_y`` that hold them (statics); a load along the
    point's path is held by ``|f|``, so the ratio is ``1/|f|``. For a link, a
    unit torque. ``wanted``: also say where this ratio is reached before the
    nearest toggle.
    """
    joint = _joint(mech, joint)
    kind, target, output = _output_column(mech, output)
    if wanted is not None and not (math.isfinite(wanted) and wanted > 0):
        raise InputError(f"wanted force ratio must be a number > 0, got {wanted!r}")
    angular = mech.joint(joint).kind == "R"

    def held(q0, q1, h):
        """Input force or torque holding each unit load (arrays over the steps)."""
        if kind == "angle":
            loads = [(Load("unit", target, torque=1.0),)]
        else:
            link, at = mech.point(target)
            loads = [(Load("x", link, (1.0, 0.0), at),), (Load("y", link, (0.0, 1.0), at),)]
        forces, dyn = [], None
        for ld in loads:
            dyn = inverse_dynamics(_statics(mech, ld), q0, q1, h, joint=joint, speed=0.0, acceleration=0.0,
                                   accuracy=accuracy)
            forces.append(dyn.driving[joint])
        return np.hypot(*forces) if len(forces) == 2 else np.abs(forces[0]), dyn

    f, dyn = held(start, stop, step)
    with np.errstate(divide="ignore"):
        ratio = np.where(f > 0, 1.0 / f, np.inf)
    values = _outputs(mech, output, dyn.inputs, joint, accuracy)
    lo, hi = min(start, stop), max(start, stop)
    toggles = []
    for d in toggle_near(mech, 0.5 * (lo + hi), 0.5 * (hi - lo), output, accuracy):
        if d.kind == "toggle" and lo <= d.input <= hi:
            toggles.append(d.input)
    toggles = sorted(set(toggles))
    reached = None
    if wanted is not None and toggles:
        reached = _reached(lambda q: held(q, q, 1.0)[0][0], toggles, dyn.inputs, ratio, wanted, mech, output, joint,
                           accuracy)
    status = dyn.status
    return ForceRatio(mech.name, output, joint, angular, dyn.inputs, ratio, values, tuple(toggles), wanted, reached,
                      status)


def _outputs(mech, output, inputs, joint, accuracy) -> np.ndarray:
    """The output's value (angle, or the point's path length from the first input) at the inputs."""
    from domes.motion.planar.sweep import sweep

    step = abs(float(inputs[1] - inputs[0])) if inputs.size > 1 else 1.0  # a sweep may run down: its step is > 0
    sw = sweep(mech, float(inputs[0]), float(inputs[-1]), step, outputs=[output], joint=joint, accuracy=accuracy)
    if output.startswith("angle:"):
        return np.degrees(np.asarray(sw.table[output], float))
    x, y = (np.asarray(sw.table[f"{output}.{c}"], float) for c in "xy")
    return np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(y)))])


def _reached(held_at, toggles, inputs, ratio, wanted, mech, output, joint, accuracy):
    """Bisection for ``ratio == wanted`` between a sampled input below it and the nearest toggle."""
    from domes.motion.planar.sweep import solve

    best = None
    for t in toggles:
        below = [q for q, r in zip(inputs, ratio) if np.isfinite(r) and r < wanted]
        if not below:
            continue
        a = min(below, key=lambda q: abs(q - t))
        b = t
        fa = 1.0 / held_at(a) - wanted
        for _ in range(200):
            m = 0.5 * (a + b)
            if abs(b - a) <= 1e-12 * max(1.0, abs(t)):
                break
            fm = 1.0 / held_at(m) - wanted if held_at(m) > 0 else math.inf
            if (fm < 0) == (fa < 0):
                a, fa = m, fm
            else:
                b = m
        q = 0.5 * (a + b)
        here = solve(mech, q, outputs=[output], joint=joint, accuracy=accuracy).values
        there = solve(mech, t, outputs=[output], joint=joint, accuracy=accuracy).values
        if output.startswith("angle:"):
            d_out = abs(math.degrees(here[output] - there[output]))
        else:
            d_out = math.hypot(here[f"{output}.x"] - there[f"{output}.x"], here[f"{output}.y"] - there[f"{output}.y"])
        candidate = (q, abs(t - q), d_out)
        if best is None or candidate[1] < best[1]:
            best = candidate
    return best


@dataclass(frozen=True, eq=False)
class WheelRate(Result):
    """Leverage ratio and wheel rate of a suspension over its travel.

    Arrays over the inputs: ``travel`` (the wheel point's vertical travel from
    the first input), ``spring_length``, ``leverage`` (wheel travel per spring
    compression, ``−dy/dL``), ``wheel_force`` (the vertical force at the wheel
    point that holds the spring, from the inverse dynamics), ``wheel_rate``
    (its derivative along the travel) and ``simple_rate`` (``k / leverage²``,
    the rate when the leverage does not change).
    """

    mechanism: str
    point: str
    spring: str
    rate: float
    inputs: np.ndarray
    travel: np.ndarray
    spring_length: np.ndarray
    leverage: np.ndarray
    wheel_force: np.ndarray
    wheel_rate: np.ndarray
    simple_rate: np.ndarray
    status: Status

    @property
    def message(self) -> str:
        rising = self.wheel_rate[-1] > self.wheel_rate[0]
        return (f"{self.mechanism}: wheel travel {np.ptp(self.travel):.4g}, spring {self.spring} compressed "
                f"{np.ptp(self.spring_length):.4g}; leverage ratio {self.leverage.min():.4g} .. {self.leverage.max():.4g}; "
                f"wheel rate {self.wheel_rate[0]:.4g} at the start to {self.wheel_rate[-1]:.4g} at the end "
                f"({'rising' if rising else 'falling'}; spring rate {self.rate:g})")


def wheel_rate(mech: Mechanism, point: str, spring: str, start: float, stop: float, step: float | None = None,
               joint: str | None = None, accuracy=None) -> WheelRate:
    """The leverage ratio and wheel rate at ``point`` (the axle) from the file's ``spring``, over the input range."""
    joint = _joint(mech, joint)
    springs = {s.name: s for s in mech.masses.springs}
    if spring not in springs:
        raise InputError(f"{mech.name}: no spring {spring!r} in the file (springs: {sorted(springs) or 'none'})")
    kind, target, point = _output_column(mech, point)
    if kind != "point":
        raise InputError(f"wheel rate: the wheel is a point (point:NAME), got {point!r}")
    s = springs[spring]
    if s.rate <= 0:
        raise InputError(f"spring {spring!r} has no rate")
    dyn = inverse_dynamics(_statics(mech, springs=(dataclasses.replace(s, damping=0.0),)), start, stop, step,
                           joint=joint, speed=1.0, acceleration=0.0, accuracy=accuracy)
    from domes.motion.planar.sweep import sweep

    names = [point] + [f"point:{e}" for e in s.between]
    sw = sweep(_statics(mech), float(dyn.inputs[0]), float(dyn.inputs[-1]),
               float(dyn.inputs[1] - dyn.inputs[0]) if dyn.inputs.size > 1 else 1.0,
               outputs=names, order=1, joint=joint, accuracy=accuracy)
    y = np.asarray(sw.table[f"{point}.y"], float)
    dy = np.asarray(sw.table[f"{point}.y'"], float)  # per unit input (speed 1)
    ends = [np.asarray(sw.table[f"point:{e}.x"], float) + 1j * np.asarray(sw.table[f"point:{e}.y"], float)
            for e in s.between]
    rates = [np.asarray(sw.table[f"point:{e}.x'"], float) + 1j * np.asarray(sw.table[f"point:{e}.y'"], float)
             for e in s.between]
    D = ends[1] - ends[0]
    length = np.abs(D)
    dL = (D.real * (rates[1] - rates[0]).real + D.imag * (rates[1] - rates[0]).imag) / length
    with np.errstate(divide="ignore", invalid="ignore"):
        leverage = -dy / dL
        force = dyn.driving[joint] / dy          # virtual work: a vertical force F at the point replaces τ
    travel = y - y[0]
    k = np.gradient(force, travel, edge_order=2) if travel.size > 2 else np.full(travel.size, np.nan)  # 2nd order ends
    return WheelRate(mech.name, point, spring, s.rate, dyn.inputs, travel, length, leverage, force, k,
                     s.rate / leverage ** 2, dyn.status)


@dataclass(frozen=True, eq=False)
class Drive(Result):
    """The input's force or torque over a range (from the file's masses, loads, springs), with its peak."""

    dynamics: object
    joint: str
    angular: bool

    @property
    def status(self) -> Status:
        return self.dynamics.status

    @property
    def message(self) -> str:
        d = self.dynamics
        f = math.degrees if self.angular else float
        u = "°" if self.angular else ""
        value, where = d.peak(self.joint)
        kind = "torque" if self.angular else "force"
        held = np.abs(d.driving[self.joint])
        return (f"{d.mechanism}: the {kind} at {self.joint} from {d.driving[self.joint][0]:.6g} to "
                f"{d.driving[self.joint][-1]:.6g} over {f(d.inputs[0]):.6g}{u} .. {f(d.inputs[-1]):.6g}{u}; peak "
                f"{value:.6g} at {f(where):.6g}{u}, least {held.min():.4g} at {f(d.inputs[int(np.argmin(held))]):.6g}{u}; "
                f"power balance within {d.max_imbalance:.2g}")


def drive(mech: Mechanism, start: float, stop: float, step: float | None = None, joint: str | None = None,
          accuracy=None) -> Drive:
    """The input's driving force or torque over the range at the file's speed, from its masses, loads and springs."""
    joint = _joint(mech, joint)
    if mech.masses.empty:
        raise InputError(f"{mech.name}: the file gives no masses, loads, springs or gravity: nothing to drive")
    dyn = inverse_dynamics(mech, start, stop, step, joint=joint, accuracy=accuracy)
    return Drive(dyn, joint, mech.joint(joint).kind == "R")
