"""Catalogue mechanisms measured and proposed: the property each is kept for, by a sweep or a closed form.

:func:`measure` measures an :class:`~domes.knowledge.catalogue.Entry`'s
properties on its model (the kinematics kernel's continuation sweep for a
mechanism file, the closed forms of :mod:`domes.motion.geneva` and
:mod:`domes.model.laws` otherwise); :func:`propose` looks entries up by the
motion they convert and keeps those whose measured properties meet the
requirements, each with the reason it was kept or left out, in the order of
the §6-1 heuristic for the function asked or implied (a dwell: an exact law).

>>> from domes.io.catalogue import load_catalogue, load_heuristics
>>> found = propose(load_catalogue(), "rotation -> intermittent rotation", ["dwell >= 250"])
>>> [(p.entry.name, p.kept) for p in found]
[('Geneva wheel, 4 slots', True), ('Geneva wheel, 6 slots', False), ('ratchet, 24 teeth', False)]
>>> found = propose(load_catalogue(), "rotation -> reciprocation", [], "exact", load_heuristics())
>>> [p.entry.family for p in found][:2], found[0].advice.split(":")[0]
(['cam', 'linkage'], 'exact')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.knowledge.catalogue import Entry, choose, motion_pair, requirement
from domes.model.laws import Motion
from domes.motion.geneva import Geneva
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import sweep
from domes.results import Listing, Status

#: Samples per degree where a property is read off a sampled motion (dwell, extremes).
PER_DEGREE = 100


@dataclass(frozen=True)
class Measured:
    """A property's ``value`` in ``unit`` and how it was measured."""

    value: float
    unit: str
    how: str

    def __str__(self) -> str:
        return f"{self.value:.6g}{self.unit}"


def measure(entry: Entry) -> dict[str, Measured]:
    """The properties of ``entry`` (see ``docs/catalogue.md`` for each kind).

    >>> from domes.io.catalogue import load_catalogue
    >>> yoke = next(e for e in load_catalogue() if e.name == "Scotch yoke")
    >>> m = measure(yoke)
    >>> round(m["stroke"].value, 9), m["harmonic deviation"].value < 1e-9
    (2.0, True)
    """
    kind = entry.measure.get("kind")
    handler = _KINDS.get(kind)
    if handler is None:
        raise InputError(f"{entry.name}: unknown measure kind {kind!r}; known: {', '.join(sorted(_KINDS))}")
    return handler(entry, entry.measure)


def _sweep(entry, outputs, range_deg=None, step_deg=0.1, order=0):
    mech = entry.mechanism
    if mech.joint(mech.inputs[0].joint).kind != "R":
        raise InputError(f"{entry.name}: the catalogue measures mechanisms with a turning input")
    if range_deg is None:
        q0 = Kinematics(mech).drawn_inputs()[mech.inputs[0].joint]
        lo, hi = q0, q0 + 2 * math.pi
    else:
        lo, hi = (math.radians(float(v)) for v in range_deg)
    sw = sweep(mech, lo, hi, math.radians(step_deg), outputs=outputs, order=order)
    if sw.status is not Status.COMPLETE:
        raise InputError(f"{entry.name}: the measure's range cannot be swept: {sw.message}")
    return sw


def _range(values, unit):
    scale = math.degrees(1.0) if unit == "°" else 1.0
    return float((np.max(values) - np.min(values)) * scale)


def _unit(output: str) -> str:
    return "°" if output.startswith("angle:") else ""


def _stroke(entry, spec):
    out = spec["output"]
    sw = _sweep(entry, [out])
    return {"stroke": Measured(_range(sw.column(out), _unit(out)), _unit(out), "range of the output over a turn")}


def _harmonic(entry, spec):
    out = spec["output"]
    sw = _sweep(entry, [out])
    th, x = sw.inputs, sw.column(out)
    basis = np.c_[np.ones_like(th), np.cos(th), np.sin(th)]
    coef, *_ = np.linalg.lstsq(basis, x, rcond=None)
    amp = math.hypot(coef[1], coef[2])
    dev = float(np.max(np.abs(basis @ coef - x)) / amp * 100)
    return {"stroke": Measured(_range(x, _unit(out)), _unit(out), "range of the output over a turn"),
            "harmonic deviation": Measured(dev, "%", "largest distance from the best c + A cos(θ − φ), of A")}


def _tangent(entry, spec):
    out = spec["output"]
    sw = _sweep(entry, [out], spec.get("range_deg"))
    th, s = sw.inputs, sw.column(out)
    basis = np.c_[np.tan(th), np.ones_like(th)]
    coef, *_ = np.linalg.lstsq(basis, s, rcond=None)
    dev = float(np.max(np.abs(basis @ coef - s)) / np.max(np.abs(s - coef[1])) * 100)
    return {"tangent deviation": Measured(dev, "%", "largest distance from the best d tan θ + c, of the stroke"),
            "stroke": Measured(_range(s, _unit(out)), _unit(out), "range of the output over the measured range")}


def _time_ratio(entry, spec):
    out = spec["output"]
    sw = _sweep(entry, [out], step_deg=1.0 / PER_DEGREE)
    th, y = sw.inputs, np.unwrap(sw.column(out)) if out.startswith("angle:") else sw.column(out)
    hi, lo = _peak(th, y), _peak(th, -y)
    turn = 2 * math.pi
    forward = (hi - lo) % turn
    ratio = max(forward, turn - forward) / min(forward, turn - forward)
    return {"time ratio": Measured(ratio, "", "crank angle of the slow stroke over the quick one (output extremes, "
                                   "located by a parabola through the sampled peak)"),
            "stroke": Measured(_range(y, _unit(out)), _unit(out), "range of the output over a turn")}


def _peak(th, y) -> float:
    return _vertex(th, y)[0]


def _straight(entry, spec):
    point = spec["point"]
    sw = _sweep(entry, [f"point:{point}"], spec.get("range_deg"), step_deg=0.05)
    xy = np.c_[sw.column(f"point:{point}.x"), sw.column(f"point:{point}.y")]
    centre = xy.mean(axis=0)
    _, _, vt = np.linalg.svd(xy - centre)
    normal = vt[1]
    dist = (xy - centre) @ normal
    along = (xy - centre) @ vt[0]
    length = float(np.max(along) - np.min(along))
    return {"straight-line deviation": Measured(float(np.max(np.abs(dist)) / length * 100), "%",
                                                "largest distance from the best-fitting line, of the length"),
            "straight length": Measured(length, "", "length of the path's straight part along the line")}


def _ratio(entry, spec):
    out = spec["output"]
    sw = _sweep(entry, [out], spec.get("range_deg"), step_deg=1.0, order=1)
    ratio = sw.column(out + "'") / entry.mechanism.inputs[0].speed
    mean = float(np.mean(ratio))
    unit = "" if out.startswith("angle:") else " per rad"
    return {"ratio": Measured(mean, unit, "output rate per input rate (mean over the sweep)"),
            "ratio variation": Measured(float(np.max(np.abs(ratio - mean)) / abs(mean) * 100), "%",
                                        "largest change of the ratio over the sweep, of the ratio")}


def _rest(rate, lo: float, hi: float) -> float:
    """The measure (rad) of ``[lo, hi)`` where ``rate`` is zero (below 1e-9 of its peak): sampled every
    1/:data:`PER_DEGREE` °, each change from moving to resting located by bisection to 1e-13 rad."""
    x = np.linspace(lo, hi, int(round(math.degrees(hi - lo))) * PER_DEGREE + 1)
    r = np.abs(rate(x))
    tiny = 1e-9 * float(np.max(r))
    still = r <= tiny
    total = 0.0
    edges = [lo] + [_edge(rate, x[k], x[k + 1], tiny, bool(still[k])) for k in np.flatnonzero(still[1:] != still[:-1])]
    edges.append(hi)
    state = bool(still[0])
    for a, b in zip(edges[:-1], edges[1:]):
        total += (b - a) if state else 0.0
        state = not state
    return total


def _edge(rate, a, b, tiny, resting_at_a):
    for _ in range(60):
        m = 0.5 * (a + b)
        if (abs(float(rate(np.array([m]))[0])) <= tiny) == resting_at_a:
            a = m
        else:
            b = m
        if b - a < 1e-13:
            break
    return 0.5 * (a + b)


def _intermittent(entry, spec):
    g = Geneva(int(entry.parameters.get("slots", 0)))
    rest = _rest(lambda t: g.wheel(t)[1], -math.pi, math.pi)
    peak = np.max(np.abs(g.wheel(np.linspace(-math.pi, math.pi, 360 * PER_DEGREE + 1))[1]))
    return {"index": Measured(math.degrees(float(g.wheel(math.pi)[0] - g.wheel(-math.pi)[0])), "°",
                              "output turn per input turn"),
            "dwell": Measured(math.degrees(rest), "°", "input angle with the output at rest (speed below 1e-9 of its peak; edges by bisection)"),
            "peak speed ratio": Measured(float(peak), "", "largest output speed per input speed (sampled)")}


def _advantage(entry, spec):
    out, rng = spec["output"], spec.get("range_deg")
    if rng is None:
        raise InputError(f"{entry.name}: a mechanical advantage is read at the end of range_deg = [START, END]")
    sw = _sweep(entry, [out], rng, step_deg=0.1, order=1)
    rate = np.abs(sw.column(out + "'")) / entry.mechanism.inputs[0].speed
    if not rate[-1] > 1e-9 * np.max(rate):
        raise InputError(f"{entry.name}: the output is at rest at {math.degrees(sw.inputs[-1]):g}°, the dead centre "
                         "itself (an unbounded advantage): end range_deg before it")
    unit = "" if out.startswith("angle:") else " per length"
    return {"mechanical advantage": Measured(float(1 / rate[-1]), unit, "input rate over output rate at the range's "
                                             "end: by virtual work, the output's force per input torque"),
            "advantage growth": Measured(float(rate[0] / rate[-1]), "", "the advantage at the range's end over that "
                                         "at its start"),
            "stroke": Measured(_range(sw.column(out), _unit(out)), _unit(out), "range of the output over the range")}


def _ratchet(entry, spec):
    """A pawl on the rocker (``output``) drives a wheel of ``teeth`` one way (the model: docs/catalogue.md)."""
    teeth, out = entry.parameters.get("teeth"), spec["output"]
    if isinstance(teeth, bool) or not isinstance(teeth, int) or teeth < 1:
        raise InputError(f"{entry.name}: a ratchet needs parameters.teeth, a whole number >= 1, got {teeth!r}")
    if not out.startswith("angle:"):
        raise InputError(f"{entry.name}: a ratchet's output is the pawl carrier's angle (angle:LINK), got {out!r}")
    sw = _sweep(entry, [out], step_deg=1.0 / PER_DEGREE)
    th, psi = sw.inputs, sw.column(out)
    (t_hi, hi), (t_lo, lo) = _vertex(th, psi), _vertex(th, -psi)
    swing, pitch = hi + lo, 2 * math.pi / teeth
    k = math.floor(swing / pitch * (1 + 1e-12))
    if k < 1:
        raise InputError(f"{entry.name}: the rocker swings {math.degrees(swing):.6g}°, less than a tooth's pitch "
                         f"{math.degrees(pitch):.6g}°: the pawl never moves the wheel")
    t_hi += 2 * math.pi * math.ceil((t_lo - t_hi) / (2 * math.pi))         # the forward stroke runs t_lo -> t_hi
    fwd = _sweep(entry, [out], [math.degrees(t_lo), math.degrees(t_hi)], step_deg=1.0 / PER_DEGREE, order=1)
    t, y, dy = fwd.inputs, fwd.column(out), fwd.column(out + "'") / entry.mechanism.inputs[0].speed
    target = hi - k * pitch
    j = int(np.argmin(np.abs(y - target)))
    t_on = float(t[j] + (target - y[j]) / dy[j])                            # a Newton step from the nearest sample
    return {"index": Measured(math.degrees(k * pitch), "°", f"whole teeth per input turn: floor(swing / pitch) = {k}"
                              f" of {teeth}"),
            "dwell": Measured(360.0 - math.degrees(t_hi - t_on), "°", "input angle with the wheel at rest: all but "
                              "the end of the forward stroke, the pawl engaged (k pitches before its extreme)"),
            "swing": Measured(math.degrees(swing), "°", "the rocker's range (extremes by a parabola through the "
                              "sampled peak, 0.01° steps)"),
            "lost motion": Measured(math.degrees(swing - k * pitch), "°", "the rocker's turn before the pawl engages"),
            "peak speed ratio": Measured(float(np.max(np.where(t >= t_on, np.abs(dy), 0.0))), "",
                                         "largest wheel speed per input speed while engaged (sampled)")}


def _vertex(th, y) -> tuple[float, float]:
    """The input and value of the peak of sampled ``y``, by a parabola through the largest sample and its neighbours."""
    k = min(max(int(np.argmax(y)), 1), len(y) - 2)
    y0, y1, y2 = y[k - 1], y[k], y[k + 1]
    d = (y0 - y2) / (y0 - 2 * y1 + y2)
    return float(th[k] + 0.5 * (th[1] - th[0]) * d), float(y1 - 0.125 * (y0 - y2) * d)


def _follower(entry, spec):
    segs = entry.parameters.get("segments")
    if not isinstance(segs, list):
        raise InputError(f"{entry.name}: a cam needs parameters.segments ([law, degrees, rise] lists)")
    motion = Motion.cam([tuple(s) for s in segs])
    rest = _rest(lambda t: motion.evaluate(t, 1)[1], 0.0, 2 * math.pi)
    s = motion.evaluate(np.linspace(0, 2 * math.pi, 360 * PER_DEGREE + 1), 0)[0]
    return {"dwell": Measured(math.degrees(rest), "°", "input angle with the follower at rest (speed below 1e-9 of its peak; edges by bisection)"),
            "stroke": Measured(float(np.max(s) - np.min(s)), "", "the follower's travel")}


_KINDS = {"ratio": _ratio, "stroke": _stroke, "harmonic": _harmonic, "tangent": _tangent, "time ratio": _time_ratio,
          "straight line": _straight, "intermittent": _intermittent, "follower": _follower,
          "mechanical advantage": _advantage, "ratchet": _ratchet}


@dataclass(frozen=True)
class Proposal:
    """A catalogue entry for a motion: its measured properties, whether it meets the requirements, and why."""

    entry: Entry
    properties: dict
    kept: bool
    reasons: tuple[str, ...]
    advice: str = ""


@dataclass(frozen=True, eq=False)
class Proposals(Listing):
    """The entries for a motion conversion, those meeting every requirement first."""

    motion: tuple[str, str]
    requirements: tuple
    proposals: tuple[Proposal, ...]
    heuristic: object = None
    items_field = "proposals"

    @property
    def status(self) -> Status:
        return Status.COMPLETE if any(p.kept for p in self.proposals) else Status.EMPTY

    @property
    def message(self) -> str:
        kept = sum(p.kept for p in self.proposals)
        need = "; ".join(map(str, self.requirements)) or "no requirement"
        what = "every motion" if self.motion == ("any", "any") else f"{self.motion[0]} → {self.motion[1]}"
        order = f"; ordered for the function {self.heuristic.function!r} ({self.heuristic.source})" \
            if self.heuristic is not None else ""
        return f"{self.status}: {what}: {len(self.proposals)} catalogue mechanism(s), {kept} meeting {need}{order}"


def propose(entries, motion=None, requirements=(), function=None, heuristics=()) -> Proposals:
    """The entries converting ``motion`` (``"rotation -> straight line"``; None: all), measured and checked
    against ``requirements`` (texts or :class:`~domes.knowledge.catalogue.Requirement`); those kept first, in the
    order of the heuristic of ``heuristics`` for ``function`` (None: the one a requirement implies), each with
    its advice."""
    pair = motion_pair(motion) if isinstance(motion, str) else (tuple(motion) if motion else ("any", "any"))
    reqs = tuple(requirement(r) if isinstance(r, str) else r for r in requirements)
    rule = choose(heuristics, function, pair, reqs)
    if function is not None and rule is None:
        raise InputError(f"no heuristic for the function {function!r} with output {pair[1]!r} in the knowledge's "
                         "heuristics.toml")
    out = []
    for e in entries:
        if motion is not None and e.motion != pair:
            continue
        props = measure(e)
        reasons = []
        kept = True
        for r in reqs:
            if r.name not in props:
                kept = False
                reasons.append(f"{r}: not a property it has ({', '.join(props)})")
            elif not r.met(props[r.name].value):
                kept = False
                reasons.append(f"{r}: has {props[r.name]}")
            else:
                reasons.append(f"{r}: has {props[r.name]}")
        out.append(Proposal(e, props, kept, tuple(reasons), rule.advice(e.family) if rule else ""))
    out.sort(key=lambda p: (not p.kept, rule.rank(p.entry.family) if rule else 0))
    return Proposals(pair, reqs, tuple(out), rule)
