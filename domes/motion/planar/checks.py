"""Verification checks for the design process.

- :func:`grashof`: the Grashof class of a four-bar (exact, from its lengths);
- :func:`rotatability`: can the input turn fully (numerically, for any mechanism);
- :func:`transmission_angle`: the minimum transmission angle of the RRR and RRP dyads;
- :func:`toggle_near`: dead (toggle) positions near a given input;
- :func:`output_range`: the range of an output over an input range (e.g. swing-arm travel against
  shock-absorber length);
- :func:`interference`: do two polygons carried by links collide along the motion.

>>> from domes.motion.planar.examples import four_bar, triple_rocker
>>> grashof(four_bar()).kind, grashof(triple_rocker()).kind
('crank-rocker', 'triple-rocker')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.planar.matrices import apply, displacement_matrix
from domes.motion.planar.query import Kinematics, SolveFailure
from domes.motion.planar.structure import Structure
from domes.motion.planar.sweep import Continuation, DeadPoint, DeadPointKind, run_sweep
from domes.results import Status

#: Relative tolerance of the Grashof equality s + l = p + q (the change-point boundary).
GRASHOF_TOL = 1e-12


@dataclass(frozen=True)
class GrashofResult:
    """Grashof class of a four-bar: ``margin = (p + q) − (s + l)`` (> 0 Grashof, 0 change point)."""

    kind: str
    lengths: dict
    margin: float
    input_rotates: bool


def grashof(mech: Mechanism) -> GrashofResult:
    """Grashof class of a four-bar with revolute joints and a grounded input.

    ``kind``: ``crank-rocker`` (the input is the shortest link), ``double-crank``
    (the ground is), ``double-rocker`` (the coupler is), ``rocker-crank`` (the
    output is), ``change point`` (s + l = p + q within :data:`GRASHOF_TOL`; the
    input turns fully but passes branch points) or ``triple-rocker``.
    """
    if len(mech.links) != 4 or len(mech.joints) != 4 or any(j.kind != "R" for j in mech.joints):
        raise InputError(f"{mech.name}: Grashof's criterion applies to four-bars with four R joints")
    inp = mech.joint(mech.inputs[0].joint)
    if mech.ground not in inp.links:
        raise InputError(f"{mech.name}: the input joint {inp.name} is not on the ground")
    crank = next(x for x in inp.links if x != mech.ground)
    lengths = {}
    for x in mech.links:
        a, b = [j.at for j in mech.joints_of(x)]
        lengths[x] = math.dist(a, b)
    ordered = sorted(lengths.values())
    s, p, q, l = ordered
    margin = (p + q) - (s + l)
    shortest = min(lengths, key=lengths.get)
    if abs(margin) <= GRASHOF_TOL * l:
        return GrashofResult("change point", lengths, margin, True)
    if margin < 0:
        return GrashofResult("triple-rocker", lengths, margin, False)
    if shortest == crank:
        kind = "crank-rocker"
    elif shortest == mech.ground:
        kind = "double-crank"
    elif any(shortest in j.links for j in mech.joints_of(mech.ground)):
        kind = "rocker-crank"
    else:
        kind = "double-rocker"
    return GrashofResult(kind, lengths, margin, kind in ("crank-rocker", "double-crank"))


@dataclass(frozen=True)
class Rotatability:
    """Numeric rotatability: ``full`` when a whole turn from the drawn pose meets no limit."""

    full: bool
    reachable: tuple[float, float]
    dead_points: tuple[DeadPoint, ...]
    grashof: GrashofResult | None


def rotatability(mech: Mechanism, accuracy=None) -> Rotatability:
    """Can the (first) input turn fully? Sweeps a turn each way from the drawn pose.

    For a four-bar the Grashof class is attached as an independent check.
    """
    kin = Kinematics(mech, None, 0, "assur", accuracy)  # every group: a limit anywhere stops the input
    cont = Continuation(kin)
    if not cont.angular:
        raise InputError(f"{mech.name}: the input {cont.joint} is a P joint; rotatability concerns R inputs")
    q0 = cont.q0
    up = run_sweep(kin, q0, q0 + 2 * math.pi)
    dead = list(up.dead_points)
    lo, hi = up.reachable
    if up.status is not Status.COMPLETE:
        down = run_sweep(kin, q0, q0 - 2 * math.pi)
        dead += down.dead_points
        lo = down.reachable[0]
    for d in dead:  # the reachable range ends at the located limits, not at the last grid step
        if d.kind is DeadPointKind.LIMIT:
            lo, hi = (min(lo, d.input), hi) if d.input < q0 else (lo, max(hi, d.input))
    g = None
    if len(mech.links) == 4 and all(j.kind == "R" for j in mech.joints):
        g = grashof(mech)
    full = up.status is Status.COMPLETE and not any(d.stops for d in dead)
    return Rotatability(full, (lo, hi), tuple(dead), g)


@dataclass(frozen=True)
class TransmissionAngle:
    """The smallest transmission angle μ (rad, folded into [0, 90°]) met along a sweep."""

    minimum: float
    input: float
    group: str


def transmission_angle(mech: Mechanism, start: float, stop: float, step=None, accuracy=None) -> TransmissionAngle:
    """Minimum transmission angle of the RRR and RRP dyads over an input range.

    RRR: the angle between the two links at the middle joint; RRP: the angle
    between the link and the normal of the slide. Folded so that 90° is best.
    """
    s = Structure.of(mech)
    dyads = [g for g in s.groups if g.kind in ("RRR", "RRP")]
    if not dyads:
        raise InputError(f"{mech.name}: no RRR or RRP dyad, so no transmission angle")
    from domes.motion.planar.dyads import DyadPlan
    plans = [(g, DyadPlan.of(mech, g)) for g in dyads]
    outputs = set()
    for g, p in plans:
        outputs |= {f"point:{p.a.name}", f"point:{p.b.name}"}
        outputs.add(f"point:{p.c.name}" if p.kind == "RRR" else f"angle:{p.l2}")
    kin = Kinematics(mech, sorted(outputs), 0, "assur", accuracy)
    sw = run_sweep(kin, start, stop, step)
    best = TransmissionAngle(math.inf, math.nan, "")
    for st in sw.steps:
        v = st.values
        for g, p in plans:
            a = (v[f"point:{p.a.name}.x"], v[f"point:{p.a.name}.y"])
            b = (v[f"point:{p.b.name}.x"], v[f"point:{p.b.name}.y"])
            u = (a[0] - b[0], a[1] - b[1])
            if p.kind == "RRR":
                w = (v[f"point:{p.c.name}.x"] - b[0], v[f"point:{p.c.name}.y"] - b[1])
            else:
                d = p.c.direction + v[f"angle:{p.l2}"] - mech.reference_angle(p.l2)
                w = (-math.sin(d), math.cos(d))
            mu = abs(math.atan2(u[0] * w[1] - u[1] * w[0], u[0] * w[0] + u[1] * w[1]))
            mu = min(mu, math.pi - mu)
            if mu < best.minimum:
                best = TransmissionAngle(mu, st.inputs[sw.joint], g.label)
    return best


def toggle_near(mech: Mechanism, q: float, window: float = math.radians(30), output: str | None = None,
                accuracy=None) -> list[DeadPoint]:
    """Dead (toggle) positions within ``window`` of input ``q``, nearest first.

    Limits and singular points of the mechanism are found by sweeping from
    ``q`` both ways; with ``output``, the inputs where that output stands
    still (its toggle, infinite mechanical advantage) are added as kind ``toggle``.
    """
    outs = [output] if output else None
    kin = Kinematics(mech, outs, 1 if output else 0, "assur", accuracy)
    found: list[DeadPoint] = []
    for end in (q + window, q - window):
        sw = run_sweep(kin, q, end)
        found += sw.dead_points
        if output:
            found += _stationary(kin, sw, output)
    found.sort(key=lambda d: abs(d.input - q))
    unique: list[DeadPoint] = []
    for d in found:
        if not any(abs(d.input - u.input) <= max(d.within, u.within, 1e-12) and d.kind == u.kind for u in unique):
            unique.append(d)
    return unique


def _stationary(kin, sw, output) -> list[DeadPoint]:
    col = kin.outputs[0].columns()[0]
    cont = Continuation(kin, sw.joint)
    out = []
    steps = sw.steps
    for a, b in zip(steps, steps[1:]):
        va, vb = a.values[col + "'"], b.values[col + "'"]
        if va == 0 or va * vb < 0:
            q = _root(kin, cont, col + "'", a, b)
            out.append(DeadPoint(q, cont.locate, "toggle", output, (), f"{output} stands still at input {cont.fmt(q)} "
                                 "(toggle: its velocity ratio is zero)"))
    return out


def _root(kin, cont, col, a, b):
    """Bisection on the sign of column ``col`` between steps ``a`` and ``b``."""
    qa, qb = a.inputs[cont.joint], b.inputs[cont.joint]
    fa = a.values[col]
    state = a.state
    while abs(qb - qa) > cont.locate:
        qm = 0.5 * (qa + qb)
        state = kin.positions(cont.inputs(qm), state)
        fm = kin.at(cont.inputs(qm), state).values[col]
        if fm == 0:
            return qm
        if (fm < 0) == (fa < 0):
            qa, fa = qm, fm
        else:
            qb = qm
    return 0.5 * (qa + qb)


@dataclass(frozen=True)
class OutputRange:
    """Smallest and largest value of an output column over an input range, with their inputs."""

    column: str
    minimum: float
    maximum: float
    at_minimum: float
    at_maximum: float
    stopped_at: DeadPoint | None

    @property
    def travel(self) -> float:
        return self.maximum - self.minimum


def output_range(mech: Mechanism, output: str, start: float, stop: float, step=None, accuracy=None,
                 joint: str | None = None) -> OutputRange:
    """Range of ``output`` (its first column) while the input goes from ``start`` to ``stop``.

    Interior extremes are located where the output's velocity changes sign
    (when the accuracy refines), so the answer does not depend on the step.
    A sweep stopped by a limit reports it in ``stopped_at``.
    """
    kin = Kinematics(mech, [output], 1, "assur", accuracy)
    sw = run_sweep(kin, start, stop, step, joint)
    if not sw.steps:
        raise InputError(f"{mech.name}: no configuration reached between the given inputs")
    col = kin.outputs[0].columns()[0]
    cont = Continuation(kin, sw.joint)
    cands = [(s.values[col], s.inputs[sw.joint]) for s in sw.steps]
    if kin.accuracy.refine:
        for a, b in zip(sw.steps, sw.steps[1:]):
            if a.values[col + "'"] * b.values[col + "'"] < 0:
                q = _root(kin, cont, col + "'", a, b)
                v = kin.at(cont.inputs(q), kin.positions(cont.inputs(q), a.state)).values[col]
                cands.append((v, q))
    lo = min(cands)
    hi = max(cands)
    stopped = next((d for d in sw.dead_points if d.stops), None)
    return OutputRange(col, lo[0], hi[0], lo[1], hi[1], stopped)


@dataclass(frozen=True)
class Interference:
    """Whether two link-carried polygons collide along a sweep; first contact and least clearance."""

    collides: bool
    first_contact: float | None
    min_clearance: float
    at_min_clearance: float


def interference(mech: Mechanism, first: str, second: str, start: float, stop: float, step=None,
                 accuracy=None) -> Interference:
    """Do polygons ``first`` and ``second`` overlap anywhere between inputs ``start`` and ``stop``?

    The first contact is located by bisection to the accuracy's ``locate``.
    """
    polys = {p.name: p for p in mech.polygons}
    for name in (first, second):
        if name not in polys:
            raise InputError(f"{mech.name}: no polygon {name!r}; polygons are {sorted(polys)}")
    outputs = []
    anchors = {}
    for name in (first, second):
        link = polys[name].link
        pins = [j for j in mech.joints_of(link) if j.kind == "R"]
        if not pins:
            raise InputError(f"{mech.name}: polygon {name!r} is on link {link!r}, which has no R joint to place it by")
        joint = pins[0]
        anchors[name] = (link, joint)
        outputs += [f"point:{joint.name}", f"angle:{link}"]
    kin = Kinematics(mech, sorted(set(outputs)), 0, "assur", accuracy)
    sw = run_sweep(kin, start, stop, step)
    cont = Continuation(kin, sw.joint)

    def placed(values, name):
        link, joint = anchors[name]
        d = values[f"angle:{link}"] - (0.0 if link == mech.ground else mech.reference_angle(link))
        D = displacement_matrix(d, joint.at, (values[f"point:{joint.name}.x"], values[f"point:{joint.name}.y"]))
        return [apply(D, v) for v in polys[name].vertices]

    def gap(values):
        return polygon_gap(placed(values, first), placed(values, second))

    best = (math.inf, math.nan)
    prev = None
    for st in sw.steps:
        g = gap(st.values)
        q = st.inputs[sw.joint]
        if g <= 0:
            contact = q
            if prev is not None:
                qa, qb, state = prev.inputs[sw.joint], q, prev.state
                while abs(qb - qa) > cont.locate:
                    qm = 0.5 * (qa + qb)
                    try:
                        state_m = kin.positions(cont.inputs(qm), state)
                    except SolveFailure:
                        break
                    if gap(kin.output_values(state_m, {}, {}, 0)) <= 0:
                        qb = qm
                    else:
                        qa, state = qm, state_m
                contact = qb
            return Interference(True, contact, 0.0, contact)
        if g < best[0]:
            best = (g, q)
        prev = st
    return Interference(False, None, best[0], best[1])


def polygon_gap(a, b) -> float:
    """Distance between two simple polygons; 0 when they touch or overlap.

    >>> polygon_gap([(0, 0), (1, 0), (1, 1), (0, 1)], [(2, 0), (3, 0), (3, 1), (2, 1)])
    1.0
    """
    ea = list(zip(a, a[1:] + a[:1]))
    eb = list(zip(b, b[1:] + b[:1]))
    for p, q in ea:
        for r, s in eb:
            if _segments_cross(p, q, r, s):
                return 0.0
    if _inside(a[0], b) or _inside(b[0], a):
        return 0.0
    return min(min(_point_segment(p, r, s) for p in a for r, s in eb),
               min(_point_segment(p, r, s) for p in b for r, s in ea))


def _orient(p, q, r):
    return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])


def _segments_cross(p, q, r, s) -> bool:
    d1, d2, d3, d4 = _orient(r, s, p), _orient(r, s, q), _orient(p, q, r), _orient(p, q, s)
    if ((d1 > 0) != (d2 > 0) or d1 == 0 or d2 == 0) and ((d3 > 0) != (d4 > 0) or d3 == 0 or d4 == 0):
        return _point_segment(p, r, s) == 0 or _point_segment(q, r, s) == 0 or _point_segment(r, p, q) == 0 \
            or _point_segment(s, p, q) == 0 or (d1 * d2 < 0 and d3 * d4 < 0)
    return False


def _inside(p, poly) -> bool:
    inside = False
    for (x1, y1), (x2, y2) in zip(poly, poly[1:] + poly[:1]):
        if (y1 > p[1]) != (y2 > p[1]) and p[0] < x1 + (p[1] - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def _point_segment(p, a, b) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    n = dx * dx + dy * dy
    t = 0.0 if n == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / n))
    return math.hypot(p[0] - a[0] - t * dx, p[1] - a[1] - t * dy)
