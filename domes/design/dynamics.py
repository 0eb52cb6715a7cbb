"""Inverse dynamics of a planar mechanism: driving forces, joint reactions and the power balance at every step.

The kinematics backend gives every moving link's angle, angular rate and
acceleration and the motion of one of its points, along a sweep of one
input (:func:`inverse_dynamics` with ``start``/``stop``) or along a
prescribed motion of the inputs (``motion=``). Newton–Euler equations of
every moving link (force and moment about its centre of mass) then give, at
each step, in one linear solve, the driving torque or force of every input
and the reaction of every joint. The mechanism file's mass model
(:mod:`domes.model.masses`) supplies masses, inertias, gravity, loads and
springs.

Gear pairs (:mod:`domes.model.gears`) and cam pairs (:mod:`domes.model.cams`)
add one unknown each. A gear pair's is the tooth force at the pitch point,
along the line of action (the common tangent of the pitch circles turned by
the pressure angle, 20° unless ``pressure_angle`` says otherwise; its
separating part, ``|F_t|·tan α`` along the line of centres, is carried by
the gears' pivots or the rack's slide). A cam pair's is the ideal
constraint force of its law ``s = L(θ)`` (virtual work): ``λ`` along the
follower's slide (a torque about its pivot, for an oscillating follower) and
the torque ``−λ·L'(θ)`` on the cam, each with its reaction on the carrier.
Neither does net work: the pitch point rolls without slip, and the power of
``λ``, ``λ·(ṡ − L'·Δθ̇)``, vanishes on the law.

Every step reports its **power balance**: the input power plus the power of
the loads, springs and gravity minus the rate of change of the kinetic
energy. The reactions do no work only when the velocities satisfy every
joint, and the equations hold only when the solve is exact, so the balance
measures both; it is reported relative to the peak power of the motion.

>>> from domes.motion.planar.examples import slider_crank
>>> from domes.model.masses import LinkMass, MassModel
>>> import dataclasses
>>> mech = dataclasses.replace(slider_crank(), masses=MassModel((LinkMass("slider", 2.0, (2.958, 0.0), 0.0),)))
>>> dyn = inverse_dynamics(mech, 0.0, math.pi, math.radians(10))
>>> dyn.success, dyn.max_imbalance < 1e-9
(True, True)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.mechanism import CouplerPoint, Mechanism
from domes.motion.planar.query import SINGULAR_CONDITION, Kinematics, error_bounds
from domes.motion.planar.query import accuracy as preset
from domes.motion.planar.sweep import sweep
from domes.results import Progress, Result, Status, Ticker

__all__ = ["Dynamics", "inverse_dynamics", "ANCHOR", "PRESSURE_ANGLE"]

#: Name of the point added to each moving link to follow its motion (never shown).
ANCHOR = "@anchor:{}"
#: The gears' pressure angle when none is given (rad): the standard involute 20° (ISO 53).
PRESSURE_ANGLE = math.radians(20.0)


@dataclass(frozen=True, eq=False)
class Dynamics(Result):
    """Driving forces, joint reactions and the power balance at every step of a motion.

    Arrays run over the ``N`` steps. ``inputs`` are the swept input's values
    (rad or length; for a prescribed motion, the step numbers) and ``time``
    the time of each step when it is known (a sweep at a non-zero constant
    speed, or a motion with its times). ``driving[joint]``: the torque (R) or
    force (P) the input must apply; ``reactions[joint]``: ``(N, 2)`` the force
    the joint's first link exerts on its second; ``moments[joint]``: the
    moment a P joint's guide exerts on its slider (about the joint's point).
    ``input_power``, ``load_power`` (loads, springs, dampers, gravity) and
    ``kinetic_rate`` (dE/dt) give ``balance = input_power + load_power −
    kinetic_rate``; :attr:`max_imbalance` is its largest size relative to the
    peak power. ``residuals`` and ``conditions`` are the kinematics' own.

    ``contacts[pair]`` (``(N,)``) for each higher pair: a gear pair's tooth
    force along the line of action (``|F_t|/cos α``), signed as its tangential
    part ``F_t``, which pushes the other gear along ``i·(P − O)`` (``P`` the
    pitch point, ``O`` the first gear's centre; for a rack, the pinion's, and
    the other is the rack): positive when the first gear drives the other
    while turning counter-clockwise on the carrier. A cam pair's ``λ``: the force along the
    P joint's direction on a translating follower, or the counter-clockwise
    torque on an oscillating one; the cam takes ``−λ·L'(θ)``.
    ``contact_forces[pair]`` (``(N, 2)``, gear pairs): the tooth force the
    first gear (the pinion, for a rack) exerts on the other at the pitch point.
    """

    mechanism: str
    joint: str | None
    inputs: np.ndarray
    time: np.ndarray | None
    driving: dict
    reactions: dict
    moments: dict
    kinetic: np.ndarray
    input_power: np.ndarray
    load_power: np.ndarray
    kinetic_rate: np.ndarray
    residuals: np.ndarray
    conditions: np.ndarray
    status: Status
    determinate: bool = True
    notes: tuple[str, ...] = ()
    dead_points: tuple = field(default=(), repr=False)
    angular: bool = True
    contacts: dict = field(default_factory=dict)
    contact_forces: dict = field(default_factory=dict)
    pressure_angle: float = PRESSURE_ANGLE

    @property
    def balance(self) -> np.ndarray:
        """Input power + load power − dE/dt at every step (0 for exact dynamics)."""
        return self.input_power + self.load_power - self.kinetic_rate

    @property
    def peak_power(self) -> float:
        """The largest power in the motion: of the inputs, the loads, or the kinetic energy's rate."""
        parts = [np.abs(self.input_power), np.abs(self.load_power), np.abs(self.kinetic_rate)]
        peak = max((float(np.nanmax(p)) for p in parts if p.size and np.any(np.isfinite(p))), default=0.0)
        return peak

    @property
    def relative_balance(self) -> np.ndarray:
        """``|balance|`` over the peak power (0 where nothing moves)."""
        peak = self.peak_power
        return np.abs(self.balance) / peak if peak > 0 else np.zeros_like(self.balance)

    @property
    def max_imbalance(self) -> float:
        """The worst step's power balance relative to the peak power."""
        rel = self.relative_balance
        rel = rel[np.isfinite(rel)]
        return float(rel.max()) if rel.size else 0.0

    def peak(self, joint: str) -> tuple[float, float]:
        """``(value, input)`` of the largest driving force or torque (by size) of ``joint`` (NaN when no step has
        one: every step refused near a singular point)."""
        values = self.driving[joint]
        if not np.any(np.isfinite(values)):
            return math.nan, math.nan
        k = int(np.nanargmax(np.abs(values)))
        return float(values[k]), float(self.inputs[k])

    @property
    def message(self) -> str:
        scale = math.degrees if self.angular and self.joint else float
        unit = "°" if self.angular and self.joint else ""
        span = (f"input {self.joint} {scale(self.inputs[0]):.6g}{unit} .. {scale(self.inputs[-1]):.6g}{unit}"
                if self.joint else "prescribed motion")
        drives = "; ".join(f"{j} peak {self.peak(j)[0]:.6g}" for j in self.driving if np.any(np.isfinite(self.driving[j])))
        drives += "".join(f"; contact {p} peak {_peak(v):.6g}" for p, v in self.contacts.items()
                          if np.any(np.isfinite(v)))
        text = (f"{self.status}: {self.mechanism}, {span} in {self.inputs.size} steps: {drives}; "
                f"power balance within {self.max_imbalance:.2g} of the peak power {self.peak_power:.4g}")
        return text + "".join(f"; {n}" for n in self.notes)

    def to_dict(self) -> dict:
        """The result as plain lists (JSON)."""
        out = {"mechanism": self.mechanism, "status": str(self.status), "message": self.message,
               "joint": self.joint, "inputs": self.inputs.tolist(),
               "time": None if self.time is None else self.time.tolist(),
               "driving": {j: v.tolist() for j, v in self.driving.items()},
               "reactions": {j: v.tolist() for j, v in self.reactions.items()},
               "moments": {j: v.tolist() for j, v in self.moments.items()},
               "contacts": {p: v.tolist() for p, v in self.contacts.items()},
               "contact_forces": {p: v.tolist() for p, v in self.contact_forces.items()},
               "pressure_angle": self.pressure_angle,
               "kinetic_energy": self.kinetic.tolist(), "input_power": self.input_power.tolist(),
               "load_power": self.load_power.tolist(), "kinetic_rate": self.kinetic_rate.tolist(),
               "balance": self.balance.tolist(), "peak_power": self.peak_power,
               "max_imbalance": self.max_imbalance, "residuals": self.residuals.tolist(),
               "conditions": self.conditions.tolist(), "determinate": self.determinate}
        return out


def _peak(values: np.ndarray) -> float:
    """The value of largest size (NaN steps skipped)."""
    return float(values[int(np.nanargmax(np.abs(values)))])


# -- kinematics of every link ------------------------------------------------------------------

@dataclass
class _Frames:
    """Per moving link over the steps: rotation from the drawn pose, its rates, and an anchor point's motion."""

    rot: dict
    w: dict
    al: dict
    a: dict
    va: dict
    aa: dict
    slide_rate: dict
    inputs: np.ndarray
    residuals: np.ndarray
    conditions: np.ndarray


def _augmented(mech: Mechanism) -> tuple[Mechanism, dict]:
    """The mechanism with an anchor point on every moving link; anchors' drawn positions by link."""
    anchors = {}
    for link in mech.links:
        if link == mech.ground:
            continue
        anchors[link] = complex(*mech.joints_of(link)[0].at)
    extra = tuple(CouplerPoint(ANCHOR.format(k), k, (z.real, z.imag)) for k, z in anchors.items())
    return dataclasses.replace(mech, points=mech.points + extra), anchors


def _outputs(mech: Mechanism, anchors: dict) -> list[str]:
    names = [f"angle:{k}" for k in anchors] + [f"point:{ANCHOR.format(k)}" for k in anchors]
    names += [f"slide:{i.joint}" for i in mech.inputs if mech.joint(i.joint).kind == "P"]
    return names


def _frames(mech: Mechanism, anchors: dict, table: dict, inputs, residuals, conditions) -> _Frames:
    rot, w, al, a, va, aa = {}, {}, {}, {}, {}, {}
    for k in anchors:
        col = f"angle:{k}"
        rot[k] = np.asarray(table[col], float) - mech.reference_angle(k)
        w[k] = np.asarray(table[col + "'"], float)
        al[k] = np.asarray(table[col + "''"], float)
        p = f"point:{ANCHOR.format(k)}"
        a[k], va[k], aa[k] = (np.asarray(table[f"{p}.x{d}"], float) + 1j * np.asarray(table[f"{p}.y{d}"], float)
                              for d in ("", "'", "''"))
    slide_rate = {i.joint: np.asarray(table[f"slide:{i.joint}'"], float) for i in mech.inputs
                  if mech.joint(i.joint).kind == "P"}
    return _Frames(rot, w, al, a, va, aa, slide_rate, np.asarray(inputs, float), np.asarray(residuals, float),
                   np.asarray(conditions, float))


class _Body:
    """World position, velocity and acceleration of drawn points of the links, over the steps."""

    def __init__(self, mech: Mechanism, frames: _Frames, anchors: dict):
        self.mech, self.f, self.anchors = mech, frames, anchors
        self.n = frames.inputs.size

    def angular(self, link):
        if link == self.mech.ground:
            z = np.zeros(self.n)
            return z, z
        return self.f.w[link], self.f.al[link]

    def point(self, link: str, drawn) -> tuple:
        d = complex(*drawn)
        if link == self.mech.ground:
            z = np.zeros(self.n, complex)
            return d + z, z, z
        f = self.f
        r = np.exp(1j * f.rot[link]) * (d - self.anchors[link])
        w, al = f.w[link], f.al[link]
        return f.a[link] + r, f.va[link] + 1j * w * r, f.aa[link] + (1j * al - w * w) * r

    def rotation(self, link):
        """The link's rotation from its drawn pose (rad)."""
        return np.zeros(self.n) if link == self.mech.ground else self.f.rot[link]

    def turn(self, link):
        """``e^{iφ}`` of the link's rotation from its drawn pose."""
        if link == self.mech.ground:
            return np.ones(self.n, complex)
        return np.exp(1j * self.f.rot[link])


def _sweep_frames(mech, start, stop, step, joint, speed, acceleration, accuracy, progress):
    joint = joint or mech.inputs[0].joint
    if joint not in {i.joint for i in mech.inputs}:
        raise InputError(f"{joint!r} is not a driven joint of {mech.name}; inputs are {[i.joint for i in mech.inputs]}")
    inputs = []
    for i in mech.inputs:
        if i.joint == joint:
            inputs.append(dataclasses.replace(i, speed=i.speed if speed is None else float(speed),
                                              acceleration=i.acceleration if acceleration is None else float(acceleration)))
        else:  # the other inputs hold their drawn values
            inputs.append(dataclasses.replace(i, speed=0.0, acceleration=0.0))
    mech = dataclasses.replace(mech, inputs=tuple(inputs))
    aug, anchors = _augmented(mech)
    sw = sweep(aug, start, stop, step, outputs=_outputs(mech, anchors), order=2, accuracy=accuracy, joint=joint,
               progress=progress)
    rate = next(i for i in inputs if i.joint == joint)
    return mech, anchors, _frames(mech, anchors, sw.table, sw.inputs, sw.residuals, sw.conditions), sw, rate


def _motion_frames(mech, motion, accuracy, progress):
    if not isinstance(motion, dict) or not motion:
        raise InputError("motion: give {input joint: (values, rates, accelerations)} with arrays of one length")
    names = {i.joint for i in mech.inputs}
    arrays = {}
    n = None
    for j, triple in motion.items():
        if j not in names:
            raise InputError(f"motion: {j!r} is not a driven joint of {mech.name}; inputs are {sorted(names)}")
        try:
            q, qd, qdd = (np.atleast_1d(np.asarray(x, dtype=float)) for x in triple)
        except (TypeError, ValueError):
            raise InputError(f"motion[{j!r}]: expected (values, rates, accelerations), three arrays of numbers") from None
        if not (q.shape == qd.shape == qdd.shape) or q.ndim != 1:
            raise InputError(f"motion[{j!r}]: values, rates and accelerations must be 1-D arrays of one length")
        if not all(np.all(np.isfinite(x)) for x in (q, qd, qdd)):
            raise InputError(f"motion[{j!r}]: every value must be a finite number")
        if n is not None and q.size != n:
            raise InputError(f"motion[{j!r}] has {q.size} steps, the other inputs {n}")
        n = q.size
        arrays[j] = (q, qd, qdd)
    aug, anchors = _augmented(mech)
    kin = Kinematics(aug, _outputs(mech, anchors), order=2, accuracy=accuracy)
    drawn = kin.drawn_inputs
    table: dict = {}
    residuals, conditions = np.zeros(n), np.ones(n)
    guess = None
    clock = Ticker(progress)
    for k in range(n):
        clock.tick(lambda: f"step {k:,}/{n:,}")
        values = {j: float(arrays[j][0][k]) if j in arrays else drawn[j] for j in names}
        speeds = {j: float(arrays[j][1][k]) if j in arrays else 0.0 for j in names}
        accels = {j: float(arrays[j][2][k]) if j in arrays else 0.0 for j in names}
        try:
            st = kin.at(values, guess, speeds=speeds, accelerations=accels)
        except NumericalError as exc:
            raise NumericalError(f"motion step {k} ({', '.join(f'{j} = {v:.6g}' for j, v in values.items())}): {exc}; "
                                 "a motion must move by small steps, each continuing the last",
                                 kind=exc.kind, residual=exc.residual, condition=exc.condition,
                                 where={**exc.where, "step": k}) from None
        guess = st.state
        for c, v in st.values.items():
            table.setdefault(c, np.empty(n))[k] = v
        residuals[k], conditions[k] = st.residual, st.condition
    return anchors, _frames(mech, anchors, table, np.arange(n, dtype=float), residuals, conditions)


# -- Newton–Euler --------------------------------------------------------------------------------

def inverse_dynamics(mech: Mechanism, start: float | None = None, stop: float | None = None,
                     step: float | None = None, *, joint: str | None = None, speed: float | None = None,
                     acceleration: float | None = None, motion: dict | None = None, time=None,
                     accuracy=None, progress: Progress | None = None,
                     pressure_angle: float = PRESSURE_ANGLE) -> Dynamics:
    """Driving forces, joint reactions and the power balance along a sweep or a prescribed motion.

    Sweep: the input ``joint`` (default: the first) from ``start`` to
    ``stop`` by ``step`` (rad or length), at its file speed and acceleration
    or ``speed``/``acceleration``; other inputs hold their drawn values.
    Motion: ``motion={joint: (values, rates, accelerations)}`` (arrays of one
    length; inputs not given hold their drawn values), optionally with the
    ``time`` of each step. ``accuracy`` is the kinematics' knob;
    ``pressure_angle`` (rad, 0 to below π/2) the gear pairs' (for every pair).

    >>> from domes.io.mechanisms import load_mechanism
    >>> dyn = inverse_dynamics(load_mechanism("examples/mechanisms/planetary.json"), 0.0, 1.0, 0.5)
    >>> sorted(dyn.contacts), dyn.contact_forces["SP"].shape
    (['PR', 'SP'], (3, 2))
    """
    try:
        alpha = float(pressure_angle)
    except (TypeError, ValueError):
        raise InputError(f"pressure_angle: expected an angle in radians, got {pressure_angle!r}") from None
    if not 0.0 <= alpha < math.pi / 2:
        raise InputError(f"pressure_angle: must be at least 0 and below 90° (π/2), got {alpha!r} rad "
                         f"({math.degrees(alpha):.6g}°)" if math.isfinite(alpha) else
                         f"pressure_angle: must be a finite angle, got {alpha!r}")
    with np.errstate(over="ignore", invalid="ignore"):  # an overflow is found in the numbers and reported below
        if motion is not None:
            if start is not None or stop is not None:
                raise InputError("give either a sweep (start, stop) or a motion, not both")
            anchors, frames = _motion_frames(mech, motion, accuracy, progress)
            t = None
            if time is not None:
                t = np.asarray(time, dtype=float)
                if t.shape != frames.inputs.shape or not np.all(np.isfinite(t)):
                    raise InputError(f"time: expected {frames.inputs.size} finite numbers, one per step")
            sw, swept, rate = None, None, None
        else:
            if start is None or stop is None:
                raise InputError("give the sweep's start and stop (rad or length), or a motion")
            mech, anchors, frames, sw, rate = _sweep_frames(mech, start, stop, step, joint, speed, acceleration,
                                                            accuracy, progress)
            swept = sw.joint
            t = None
            if rate.speed and rate.acceleration == 0:
                t = (frames.inputs - frames.inputs[0]) / rate.speed
        body = _Body(mech, frames, anchors)
        solved = _solve(mech, body, alpha)
    _overflow(mech, frames, solved, swept, accuracy)
    status = sw.status if sw is not None else Status.COMPLETE
    notes = list(solved.pop("notes"))
    if sw is not None and sw.status is Status.STOPPED:
        stop_at = next((d for d in sw.dead_points if d.stops), None)
        if stop_at is not None:
            notes.append(f"stopped: {stop_at.message}")
    bad = ~np.isfinite(solved["input_power"])
    if np.any(bad):
        notes.append(f"{int(bad.sum())} steps without forces (velocities or accelerations refused near a singular point)")
    angular = swept is None or mech.joint(swept).kind == "R"
    return Dynamics(mech.name, swept, frames.inputs, t, residuals=frames.residuals, conditions=frames.conditions,
                    status=status, notes=tuple(notes), dead_points=tuple(sw.dead_points) if sw is not None else (),
                    angular=angular, pressure_angle=alpha, **solved)


def _overflow(mech: Mechanism, frames: _Frames, solved: dict, swept: str | None, accuracy) -> None:
    """A NumericalError when numbers overflowed: a step whose derivatives the kinematics gave (not refused near a
    singular point) but whose forces, energies or powers are not finite numbers."""
    derivatives = preset(accuracy).derivatives
    given = (frames.conditions <= SINGULAR_CONDITION) & (error_bounds(frames.conditions, 2)[2] <= derivatives)
    numbers = [solved["input_power"], solved["load_power"], solved["kinetic_rate"], solved["kinetic"],
               *solved["driving"].values(), *solved["moments"].values(), *solved["contacts"].values(),
               *(v[:, i] for v in solved["reactions"].values() for i in (0, 1))]
    lost = given & ~np.all(np.isfinite(np.stack(numbers)), axis=0)
    if not np.any(lost):
        return
    k = int(np.flatnonzero(lost)[0])
    q = float(frames.inputs[k])
    where = (f"input {swept} = {math.degrees(q) if mech.joint(swept).kind == 'R' else q:.6g}"
             f"{'°' if mech.joint(swept).kind == 'R' else ''}" if swept else f"motion step {k}")
    raise NumericalError(f"{mech.name}: the forces overflow the floating-point range (about 1.8e308) at "
                         f"{int(lost.sum()):,} of {lost.size:,} steps, the first at {where}: the speed, the "
                         "acceleration or the loads are too large to compute with", kind="overflow",
                         where={"input": q, "step": k})


def _solve(mech: Mechanism, body: _Body, alpha: float = PRESSURE_ANGLE) -> dict:
    """Assemble and solve the Newton–Euler equations of every moving link at every step (``alpha``: the gears'
    pressure angle)."""
    n = body.n
    moving = [k for k in mech.links if k != mech.ground]
    row = {k: 3 * i for i, k in enumerate(moving)}
    model = mech.masses
    centre = {}
    for k in moving:
        m = model.mass_of(k)
        drawn = m.centre if m.centre is not None else (body.anchors[k].real, body.anchors[k].imag)
        centre[k] = body.point(k, drawn)

    columns: list[tuple] = []  # (kind, joint)
    for j in mech.joints:
        columns += [("Fx", j.name), ("Fy", j.name)] if j.kind == "R" else [("N", j.name), ("M", j.name)]
    for i in mech.inputs:
        columns.append(("drive", i.joint))
    columns += [("mesh", g.name) for g in mech.gears] + [("cam", c.name) for c in mech.cams]
    A = np.zeros((n, 3 * len(moving), len(columns)))
    b = np.zeros((n, 3 * len(moving)))

    def force(link, col, F, X):
        """Unit-coefficient force ``F`` (complex, over steps) at ``X`` on ``link`` into column ``col``."""
        if link == mech.ground:
            return
        r = row[link]
        c = centre[link][0]
        A[:, r, col] += F.real
        A[:, r + 1, col] += F.imag
        A[:, r + 2, col] += ((X - c).real * F.imag - (X - c).imag * F.real)

    def moment(link, col, sign):
        """Unit-coefficient torque ``sign`` (a number or one per step) on ``link`` into column ``col``."""
        if link != mech.ground:
            A[:, row[link] + 2, col] += sign

    # gear pairs: the pitch point P and the first gear's centre O ride on the carrier; the tangential unit t =
    # i·(P − O)/|P − O| pushes the second gear; ``apart`` is the separating direction on the second gear
    meshes = {g.name: g.mesh(mech) for g in mech.gears}
    pitch = {}
    for name, m in meshes.items():
        P = body.point(m.carrier, m.pair.at)[0]
        r = P - body.point(m.carrier, m.centres[0])[0]
        r = r / np.abs(r)
        ring_first = m.kind == "internal" and m.radii[0] > m.radii[1]
        pitch[name] = (P, 1j * r, -r if ring_first else r)
    # cam pairs: L'(θ) of the law at the cam's turn on its carrier; a translating follower's slide direction
    cams = {c.name: c.contact(mech) for c in mech.cams}
    law_rate, slide_of = {}, {}
    for name, ct in cams.items():
        turn = ct.pair.phase + body.rotation(ct.cam) - body.rotation(ct.carrier)
        law_rate[name] = np.asarray(ct.pair.law.evaluate(turn, 1)[1], float)
        if ct.kind == "translating":
            sj = mech.joint(ct.joint)
            slide_of[name] = (body.turn(sj.links[0]) * complex(math.cos(sj.direction), math.sin(sj.direction)),
                              body.point(ct.follower, ct.pair.at)[0])

    joint_at, slide_dir = {}, {}
    for j in mech.joints:
        first, second = j.links
        X = body.point(second, j.at)[0]
        joint_at[j.name] = X
        if j.kind == "P":
            slide_dir[j.name] = body.turn(first) * complex(math.cos(j.direction), math.sin(j.direction))
    for c, (kind, name) in enumerate(columns):
        if kind == "mesh":  # the tooth force's tangential part F_t: +t on the second gear, −t on the first
            m = meshes[name]
            P, t, _ = pitch[name]
            force(m.b, c, t, P)
            force(m.a, c, -t, P)
            continue
        if kind == "cam":  # λ on the follower and −λ·L' on the cam; their reactions on the carrier
            ct = cams[name]
            if ct.kind == "translating":
                u, X = slide_of[name]
                force(ct.follower, c, u, X)
                force(ct.carrier, c, -u, X)
            else:
                moment(ct.follower, c, 1.0)
                moment(ct.carrier, c, -1.0)
            moment(ct.cam, c, -law_rate[name])
            moment(ct.carrier, c, law_rate[name])
            continue
        j = mech.joint(name)
        first, second = j.links
        X = joint_at[name]
        if kind in ("Fx", "Fy"):
            F = np.full(n, 1.0 + 0j) if kind == "Fx" else np.full(n, 1j)
            force(second, c, F, X)
            force(first, c, -F, X)
        elif kind == "N":
            F = 1j * slide_dir[name]
            force(second, c, F, X)
            force(first, c, -F, X)
        elif kind == "M":
            moment(second, c, 1.0)
            moment(first, c, -1.0)
        elif j.kind == "P":  # a driven slide: force along the slide on the slider
            F = slide_dir[name]
            force(second, c, F, X)
            force(first, c, -F, X)
        else:  # a driven R joint: torque on its driven side
            a, bb = _driven_sides(mech, j)
            moment(bb, c, 1.0)
            moment(a, c, -1.0)

    # inertia (right-hand side) and kinetic energy
    kinetic = np.zeros(n)
    kinetic_rate = np.zeros(n)
    for k in moving:
        m = model.mass_of(k)
        _, v, acc = centre[k]
        w, al = body.angular(k)
        r = row[k]
        b[:, r] += m.mass * acc.real
        b[:, r + 1] += m.mass * acc.imag
        b[:, r + 2] += m.inertia * al
        kinetic += 0.5 * (m.mass * np.abs(v) ** 2 + m.inertia * w * w)
        kinetic_rate += m.mass * (v.real * acc.real + v.imag * acc.imag) + m.inertia * w * al

    # external loads: gravity, loads, springs (moved to the right-hand side), and their power
    load_power = np.zeros(n)
    g = complex(*model.gravity)

    def applied(rhs, link, F, X):
        """A known force ``F`` at ``X`` on ``link``, moved to the right-hand side ``rhs``."""
        if link == mech.ground:
            return
        r = row[link]
        c = centre[link][0]
        rhs[:, r] -= F.real
        rhs[:, r + 1] -= F.imag
        rhs[:, r + 2] -= (X - c).real * F.imag - (X - c).imag * F.real

    def external(link, F, X, V):
        nonlocal load_power
        load_power = load_power + (F.real * V.real + F.imag * V.imag)
        applied(b, link, F, X)

    if g:
        for k in moving:
            m = model.mass_of(k)
            if m.mass:
                X, V, _ = centre[k]
                external(k, np.full(n, m.mass * g), X, V)
    for load in model.loads:
        if load.at is not None and any(load.force):
            X, V, _ = body.point(load.link, load.at)
            external(load.link, np.full(n, complex(*load.force)), X, V)
        if load.torque:
            w, _ = body.angular(load.link)
            load_power = load_power + load.torque * w
            if load.link != mech.ground:
                b[:, row[load.link] + 2] -= load.torque
    for spring in model.springs:
        ends = []
        for name in spring.between:
            link, drawn = mech.point(name)
            ends.append((link, *body.point(link, drawn)[:2], complex(*drawn)))
        (l1, X1, V1, d1), (l2, X2, V2, d2) = ends
        D = X2 - X1
        length = np.abs(D)
        if np.any(length == 0):
            raise InputError(f"spring {spring.name!r}: its ends {spring.between} meet; its direction is undefined")
        u = D / length
        rate = (u.real * (V2 - V1).real + u.imag * (V2 - V1).imag)
        free = abs(d2 - d1) if spring.free_length is None else spring.free_length
        tension = spring.rate * (length - free) + spring.damping * rate - spring.preload
        external(l1, tension * u, X1, V1)
        external(l2, -tension * u, X2, V2)

    # a unit separating pair at each gear pair's pitch point: solved with the same matrix, then scaled by
    # |F_t|·tan α (it works on the pivots only: no drive and no tooth force changes with it)
    rhs = [b]
    for name, m in meshes.items():
        P, _, apart = pitch[name]
        sep = np.zeros_like(b)
        applied(sep, m.b, apart, P)
        applied(sep, m.a, -apart, P)
        rhs.append(sep)
    xs, determinate = _linear_solve(A, np.stack(rhs, axis=2))
    x = xs[..., 0]
    tan = math.tan(alpha)
    tangential = {name: x[:, c].copy() for c, (kind, name) in enumerate(columns) if kind == "mesh"}
    for k, name in enumerate(meshes, start=1):
        x = x + (tan * np.abs(tangential[name]))[:, None] * xs[..., k]
    contacts, contact_forces = {}, {}
    for name in meshes:
        _, t, apart = pitch[name]
        Ft = tangential[name]
        F = Ft * t + tan * np.abs(Ft) * apart
        contacts[name] = Ft / math.cos(alpha)
        contact_forces[name] = np.stack([F.real, F.imag], axis=1)
    for c, (kind, name) in enumerate(columns):
        if kind == "cam":
            contacts[name] = x[:, c]
    driving, reactions, moments = {}, {}, {}
    for c, (kind, name) in enumerate(columns):
        if kind == "Fx":
            reactions[name] = np.stack([x[:, c], x[:, c + 1]], axis=1)
        elif kind == "N":
            N = x[:, c] * (1j * slide_dir[name])
            reactions[name] = np.stack([N.real, N.imag], axis=1)
            moments[name] = x[:, c + 1]
        elif kind == "drive":
            driving[name] = x[:, c]
    input_power = np.zeros(n)
    for i in mech.inputs:
        j = mech.joint(i.joint)
        if j.kind == "P":
            rate = body.f.slide_rate[i.joint]
        else:
            a, bb = _driven_sides(mech, j)
            rate = body.angular(bb)[0] - body.angular(a)[0]
        input_power = input_power + driving[i.joint] * rate
    notes = [] if determinate else ["statically indeterminate: the reactions shown are the least-norm ones"]
    return {"driving": driving, "reactions": reactions, "moments": moments, "contacts": contacts,
            "contact_forces": contact_forces, "kinetic": kinetic,
            "input_power": input_power, "load_power": load_power, "kinetic_rate": kinetic_rate,
            "determinate": determinate, "notes": notes}


def _driven_sides(mech: Mechanism, j) -> tuple[str, str]:
    """``(a, b)`` of a driven R joint: its rate is b's rotation over a's (b the side away from the ground)."""
    a, b = j.links
    if mech.ground in (a, b):
        a, b = mech.ground, (b if a == mech.ground else a)
    return a, b


def _linear_solve(A: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, bool]:
    """Solve every step's system for each right-hand side ``b[:, :, i]``; least squares (least norm) when it is not
    square or is rank deficient."""
    n, rows, cols = A.shape
    out = np.full((n, cols, b.shape[2]), np.nan)
    good = np.all(np.isfinite(A), axis=(1, 2)) & np.all(np.isfinite(b), axis=(1, 2))
    if rows == cols:
        try:
            out[good] = np.linalg.solve(A[good], b[good])
            return out, True
        except np.linalg.LinAlgError:
            pass
    determinate = True
    for k in np.flatnonzero(good):
        sol, _, rank, _ = np.linalg.lstsq(A[k], b[k], rcond=None)
        determinate &= rank == cols
        out[k] = sol
    return out, bool(determinate)
