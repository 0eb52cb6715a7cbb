"""Feasibility, the last screening level: each quasi-feasible candidate dimensioned for the requirements and
verified (seed 002, §5-2, Fig. 5-4: a type is *feasible* when its dimensional synthesis meets the motion law,
the motion space and the other requirements; the dimensional solution is the final criterion).

For each candidate, :func:`feasibility` dimensions it for the brief's task (least squares over random
layouts, :func:`~domes.design.synthesis.candidate.dimension`), takes its best verified layout, and runs
every check: those each layout passes (assembly and branch through the stroke by the continuation sweep, no
dead point, the transmission angle, the wanted curve within its tolerance, a length within its range) and
the brief's (:mod:`domes.design.brief`: wheel rate, force ratio, drive torque, tolerances). Each check says
its value, its limit and whether it passed; a candidate that fails says which check and by how much.
Candidates run on an executor (``--workers``) and within a time budget: what was not finished is said.

>>> from domes.design.brief import brief_from
>>> from domes.model import LabelledChain
>>> c = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={0: {"ground"}, 1: {"crank"}, 3: {"rocker"}})
>>> b = brief_from("demo", {"kind": "curve", "input": {"role": "crank", "rotation_deg": 60}, "point": {"at": [1, 0]},
...                         "wanted": {"quantity": "angle", "of": "rocker", "function": "0.5*x"},
...                         "box": [[-1.0, 4.0], [-2.5, 2.5]]}, [], {})
>>> result = feasibility(b, [(1, c)], seeds=8)
>>> result.designs[0].status, [k.name for k in result.designs[0].checks][:3]
('feasible', ['assembly', 'dead points', 'transmission angle'])
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from domes.design import forces
from domes.design.brief import CheckSpec, DesignBrief
from domes.design.methods import METHODS
from domes.design.synthesis.candidate import Dimensioned, Model, dimension
from domes.design.tolerance import Tolerancing, sensitivity
from domes.errors import DomesError, InputError
from domes.model.masses import Load, MassModel, Spring
from domes.model.mechanism import Input, Mechanism
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import solve, sweep
from domes.results import Listing, Progress, Status, Ticker

FEASIBLE, INFEASIBLE, NOT_CARRIED, NOT_DONE = "feasible", "infeasible", "cannot carry the task", "not finished"


@dataclass(frozen=True)
class CheckResult:
    """One check of a dimensioned design: its ``value`` against its ``limit`` (``kind`` ``min``: the value must
    be at least the limit; ``max``: at most; ``pass``: a yes/no check), in ``unit``, and what it found."""

    name: str
    passed: bool
    value: float | None = None
    limit: float | None = None
    kind: str = "pass"
    unit: str = ""
    message: str = ""

    @property
    def by(self) -> str:
        """How far a failed check missed its limit, in words ('' when it passed or has no limit)."""
        if self.passed or self.value is None or self.limit is None or not math.isfinite(self.value):
            return ""
        miss = self.limit - self.value if self.kind == "min" else self.value - self.limit
        rel = f" ({100 * miss / abs(self.limit):.3g}% of the limit)" if self.limit else ""
        return f"missed by {miss:.4g}{(' ' + self.unit) if self.unit else ''}{rel}"

    def to_dict(self) -> dict:
        return {"name": self.name, "passed": self.passed, "value": _plain(self.value), "limit": _plain(self.limit),
                "kind": self.kind, "unit": self.unit, "message": self.message}


def _plain(x):
    return None if x is None or not math.isfinite(x) else float(x)


@dataclass(frozen=True)
class Design:
    """A candidate after the feasibility level: ``status`` (feasible, infeasible, cannot carry the task, not
    finished), its dimensioned ``mechanism`` and ``solution``, every check, the raw soft ``indices`` the
    ranking reads, and the ``reason`` it is not feasible."""

    candidate: int
    status: str
    mechanism: Mechanism | None = None
    solution: Dimensioned | None = None
    checks: tuple[CheckResult, ...] = ()
    indices: Mapping[str, float] = field(default_factory=dict)
    reason: str = ""
    seconds: float = 0.0
    #: The input's values at the start and the end of the stroke (rad, or a length), in the drawn pose's terms.
    stroke: tuple[float, float] | None = None
    #: What the curve is (the task's quantity) and what its x is.
    labels: tuple[str, str] = ("", "")

    @property
    def feasible(self) -> bool:
        return self.status == FEASIBLE

    def check(self, name: str) -> CheckResult | None:
        return next((c for c in self.checks if c.name == name), None)

    def to_dict(self) -> dict:
        s = self.solution
        out = {"candidate": self.candidate, "status": self.status, "reason": self.reason,
               "checks": [c.to_dict() for c in self.checks],
               "indices": {k: _plain(v) for k, v in self.indices.items()}}
        if self.mechanism is not None:
            out["mechanism"] = self.mechanism.to_dict()
        if self.stroke is not None:
            out["stroke"] = [float(self.stroke[0]), float(self.stroke[1])]
        if s is not None:
            out["curve"] = {"x": list(s.x), "achieved": [_plain(v) for v in s.achieved],
                            "wanted": [_plain(v) for v in s.wanted], "error": _plain(s.error), "rms": _plain(s.rms),
                            "quantity": self.labels[0], "x_label": self.labels[1]}
        return out


@dataclass(frozen=True, eq=False)
class Feasibility(Listing):
    """The feasibility level over the quasi-feasible candidates: a :class:`Design` each, in candidate order."""

    task_name: str
    designs: tuple[Design, ...]
    seconds: float
    time_budget: float | None = None
    items_field = "designs"

    @property
    def feasible(self) -> tuple[Design, ...]:
        return tuple(d for d in self.designs if d.feasible)

    @property
    def unfinished(self) -> tuple[int, ...]:
        return tuple(d.candidate for d in self.designs if d.status == NOT_DONE)

    @property
    def status(self) -> Status:
        if self.unfinished:
            return Status.STOPPED
        return Status.COMPLETE if self.feasible else Status.EMPTY

    @property
    def message(self) -> str:
        done = len(self.designs) - len(self.unfinished)
        text = (f"{len(self.feasible)} of {len(self.designs)} quasi-feasible candidate(s) feasible for "
                f"{self.task_name} ({done} dimensioned and verified in {self.seconds:.1f} s)")
        if self.unfinished:
            text += (f"; the time budget of {self.time_budget:g} s ran out before candidate(s) "
                     f"{', '.join(map(str, self.unfinished))}")
        return text


def feasibility(brief: DesignBrief, candidates, method: str = "fast", seeds: int = 16, seed: int = 0,
                executor=None, time_budget: float | None = None, progress: Progress | None = None) -> Feasibility:
    """Dimension and verify every ``(id, labelled chain)`` of ``candidates`` for ``brief`` (see the module doc).

    ``method`` and ``seeds`` are the dimensioning's knobs (``200 × seeds`` random layouts screened per
    candidate, the best 4 (``fast``) or 12 (``exact``) polished); each candidate draws from its own seed
    (``seed`` and its id), so an ``executor`` gives the same designs. ``time_budget`` (seconds) stops
    starting candidates once spent; those left are ``not finished``.
    """
    if method not in METHODS:
        raise InputError(f"feasibility: method must be one of {', '.join(METHODS)}, got {method!r}")
    if isinstance(seeds, bool) or not isinstance(seeds, int) or not 1 <= seeds <= 4096:
        raise InputError(f"feasibility: seeds must be a whole number from 1 to 4096, got {seeds!r}")
    if time_budget is not None and not (math.isfinite(time_budget) and time_budget > 0):
        raise InputError(f"feasibility: the time budget must be a positive number of seconds, got {time_budget!r}")
    started = time.perf_counter()
    candidates = list(candidates)
    items = [(brief, cid, chain, method, seeds, seed) for cid, chain in candidates]
    done: dict[int, Design] = {}
    clock = Ticker(progress)
    run = executor.completed if executor is not None else _in_order
    results = run(_design_one, items)
    try:
        for index, design in results:
            done[index] = design
            clock.tick(lambda: f"feasibility: {len(done)}/{len(items)} candidates dimensioned and verified, "
                               f"{sum(d.feasible for d in done.values())} feasible", force=True)
            if time_budget is not None and time.perf_counter() - started > time_budget and len(done) < len(items):
                break
    finally:
        close = getattr(results, "close", None)
        if close:
            close()
    designs = tuple(done.get(k, Design(cid, NOT_DONE, reason="the time budget ran out before it"))
                    for k, (cid, _) in enumerate(candidates))
    return Feasibility(brief.task.name, designs, time.perf_counter() - started, time_budget)


def _in_order(fn, items):
    for k, item in enumerate(items):
        yield k, fn(item)


def _design_one(item) -> Design:
    """One candidate: dimensioned, its best layout verified and checked (an executor's task)."""
    brief, cid, chain, method, seeds, seed = item
    started = time.perf_counter()
    task = brief.task
    try:
        model = Model(chain, task, f"{task.name}: candidate {cid}")
    except InputError as exc:
        return Design(cid, NOT_CARRIED, reason=str(exc), seconds=time.perf_counter() - started)
    result = dimension(task, [(cid, chain)], method=method, seeds=seeds, seed=seed + 7919 * cid)
    if not result.solutions:
        reason = "; ".join(result.notes) or "no layout of the box assembles over the stroke"
        return Design(cid, INFEASIBLE, reason=reason, seconds=time.perf_counter() - started,
                      checks=(CheckResult("assembly", False, message=reason),))
    best = min(result.solutions, key=lambda s: (not s.usable, s.error, -s.min_transmission_deg))
    checks = list(layout_checks(task, best))
    indices = {"accuracy": best.error / task.tolerance if math.isfinite(best.error) else math.inf,
               "transmission": best.min_transmission_deg, "complexity": complexity(chain)}
    if best.usable:
        for spec in brief.checks:
            try:
                check, index = CHECKS[spec.kind](spec, best.mechanism, model, chain)
            except DomesError as exc:
                check, index = CheckResult(spec.kind, False, message=f"could not be evaluated: {exc}"), None
            checks.append(check)
            if index is not None:
                indices[INDEX_OF[spec.kind]] = index
        indices["compactness"] = compactness(best.mechanism, model)
    failed = [c for c in checks if not c.passed]
    reason = "; ".join(f"{c.name}: {c.message}" + (f" ({c.by})" if c.by else "") for c in failed)
    q0, qs = _stroke(best.mechanism, model)
    labels = (f"{task.quantity} of {' and '.join(task.of) if isinstance(task.of, tuple) else task.of}".replace("_", " "),
              f"rise of {task.point_name} (m)" if task.quantity == "leverage" else "input rotation (°)")
    return Design(cid, FEASIBLE if not failed else INFEASIBLE, best.mechanism, best, tuple(checks), indices, reason,
                  time.perf_counter() - started, (q0, float(qs[-1])), labels)


def layout_checks(task, s: Dimensioned) -> list[CheckResult]:
    """The checks every dimensioned layout is verified by (the continuation sweep of its ``_verify``)."""
    text = " ".join(s.defects)
    out = [CheckResult("assembly", "does not assemble" not in text,
                       message="assembles in one branch over the stroke" if "does not assemble" not in text
                       else next(d for d in s.defects if "does not assemble" in d)),
           CheckResult("dead points", "dead point" not in text,
                       message="no dead point over the stroke" if "dead point" not in text
                       else next(d for d in s.defects if "dead point" in d))]
    mu = math.degrees(task.min_transmission)
    out.append(CheckResult("transmission angle", s.min_transmission_deg >= mu - 1e-6, s.min_transmission_deg, mu,
                           "min", "°", f"smallest {s.min_transmission_deg:.1f}° (at least {mu:.0f}°)"))
    what = "curve" if task.bound == "equal" else f"{task.quantity} {task.bound} the wanted value"
    out.append(CheckResult(what, s.error <= task.tolerance, s.error * 100, task.tolerance * 100, "max", "%",
                           f"largest relative error {100 * s.error:.3g}% (tolerance {100 * task.tolerance:.3g}%)"))
    if s.length is not None and task.length_range is not None:
        lo, hi = task.length_range
        inside = lo - 1e-9 <= s.length[0] and s.length[1] <= hi + 1e-9
        out.append(CheckResult("length range", inside, message=f"{s.length[0]:.4g} to {s.length[1]:.4g} "
                               f"(within {lo:.4g} to {hi:.4g})"))
    return out


def _stroke(mech: Mechanism, model: Model) -> tuple[float, np.ndarray]:
    """The drawn input angle and the input values of the stroke's samples (without the overtravel)."""
    q0 = Kinematics(mech).drawn_inputs()[model.fixed]
    return q0, q0 + model.ts[:model.task.stroke_count]


def _wheel_rate(spec: CheckSpec, mech: Mechanism, model: Model, chain):
    q0, qs = _stroke(mech, model)
    sprung = dataclasses.replace(mech, masses=MassModel(springs=(Spring("spring", tuple(model.ends),
                                                                        rate=spec["spring_rate"]),)))
    r = forces.wheel_rate(sprung, f"point:{model.task.point_name}", "spring", q0, float(qs[-1]),
                          abs(float(qs[-1]) - q0) / (qs.size - 1))
    rate = np.asarray(r.wheel_rate, float)
    if rate.size < 2 or not np.all(np.isfinite(rate)):
        return CheckResult("wheel rate", False, message="the wheel rate is not finite over the travel"), None
    start, end, low, high = float(rate[0]), float(rate[-1]), float(rate.min()), float(rate.max())
    text = (f"{start / 1000:.4g} to {end / 1000:.4g} N/mm over the travel ({'rising' if end > start else 'falling'}; "
            f"{low / 1000:.4g} .. {high / 1000:.4g} N/mm) from a spring of {spec['spring_rate'] / 1000:.4g} N/mm")
    progression = end / start if start > 0 else math.nan
    if spec.get("rising") and not end > start:
        return CheckResult("wheel rate", False, progression, 1.0, "min", "", text + "; a rising rate is wanted"), \
            progression
    if spec.get("range"):
        lo, hi = spec["range"]
        limits = f" (wanted {lo / 1000:.4g} .. {hi / 1000:.4g} N/mm)"
        if low < lo:
            return CheckResult("wheel rate", False, low / 1000, lo / 1000, "min", "N/mm", text + limits), progression
        if high > hi:
            return CheckResult("wheel rate", False, high / 1000, hi / 1000, "max", "N/mm", text + limits), progression
        text += limits
    return CheckResult("wheel rate", True, end / 1000, None, "pass", "N/mm", text), progression


def _force_ratio(spec: CheckSpec, mech: Mechanism, model: Model, chain):
    task = model.task
    q0, qs = _stroke(mech, model)
    q1 = float(qs[-1])
    count = 4 * (task.samples - 1) + 1
    sw = sweep(mech, q0, q1, abs(q1 - q0) / (count - 1), outputs=[f"slide:{model.slider}"], order=1)
    theta = np.asarray(sw.inputs, float)
    rate = np.asarray(sw.table[f"slide:{model.slider}'"], float)
    turns = np.flatnonzero(np.sign(rate[1:]) != np.sign(rate[:-1]))
    if turns.size:  # the actuator's length turns back: it cannot drive the mechanism through that point
        where = math.degrees(float(theta[turns[0]]) - q0)
        return CheckResult("force ratio", False, 0.0, spec.get("minimum", spec["ratio"]), "min", "",
                           f"the actuator's length turns back {where:.3g}° into the stroke: it cannot drive the "
                           "mechanism past that point (the force ratio falls to 0)"), 0.0
    s = np.asarray(sw.table[f"slide:{model.slider}"], float)
    driven = dataclasses.replace(mech, inputs=(Input(model.slider),))
    r = forces.force_ratio(driven, f"point:{task.point_name}", float(s[0]), float(s[-1]),
                           abs(float(s[-1]) - float(s[0])) / (count - 1))
    ratio = np.asarray(r.ratio, float)
    end, least = float(ratio[-1]), float(np.min(ratio))
    minimum = spec.get("minimum", 0.0)
    last = spec.get("over_last")
    held = end
    if last:  # the last stretch of the stroke, from the slide where it begins (found by the input's rotation)
        begin = q1 - math.copysign(math.radians(last), q1 - q0)
        s_begin = float(solve(mech, begin, outputs=[f"slide:{model.slider}"]).values[f"slide:{model.slider}"])
        window = forces.force_ratio(driven, f"point:{task.point_name}", s_begin, float(s[-1]),
                                    abs(float(s[-1]) - s_begin) / (count - 1))
        held = float(np.min(np.asarray(window.ratio, float)))
    where = f"over the last {last:g}° of the stroke" if last else "at the end of the stroke"
    text = (f"{held:.4g} or more {where} (at least {spec['ratio']:g}; {end:.4g} at the end), smallest {least:.3g} "
            "over the stroke" + (f" (at least {minimum:g})" if minimum else "") + "; the actuator driving, by statics")
    if least < minimum:
        return CheckResult("force ratio", False, least, minimum, "min", "", text), held / spec["ratio"]
    return CheckResult("force ratio", held >= spec["ratio"] * (1 - 1e-9), held, spec["ratio"], "min", "", text), \
        held / spec["ratio"]


def _drive(spec: CheckSpec, mech: Mechanism, model: Model, chain):
    task = model.task
    links = chain.links_with_role(spec["on"])
    if len(links) != 1:
        raise InputError(f"drive: the load acts on role {spec['on']!r}, carried by {len(links)} links")
    link = str(links[0])
    at = next(j.at for j in mech.joints if link in j.links)
    q0, qs = _stroke(mech, model)
    if "direction_deg" in spec.values:
        angle = math.radians(spec["direction_deg"])
    elif model.guided:  # against the travel along the slide
        sw = sweep(mech, q0, float(qs[-1]), abs(float(qs[-1]) - q0) / (qs.size - 1), outputs=[f"slide:{model.slider}"])
        s = np.asarray(sw.table[f"slide:{model.slider}"], float)
        angle = task.guide + (math.pi if s[-1] > s[0] else 0.0)
    else:
        angle = -math.pi / 2
    force = (spec["load"] * math.cos(angle), spec["load"] * math.sin(angle))
    speed = abs(task.rotation) / spec.get("time", 1.0)
    loaded = dataclasses.replace(mech, inputs=(Input(model.fixed, speed=math.copysign(speed, task.rotation)),),
                                 masses=MassModel(loads=(Load("load", link, force, at),)))
    r = forces.drive(loaded, q0, float(qs[-1]), abs(float(qs[-1]) - q0) / (qs.size - 1))
    torque = np.abs(np.asarray(r.dynamics.driving[model.fixed], float))
    peak = float(np.max(torque))
    ok = peak <= spec["torque"]
    return CheckResult("drive torque", ok, peak, spec["torque"], "max", "N·m",
                       f"peak {peak:.4g} N·m at the input (at most {spec['torque']:g} N·m) against {spec['load']:g} N "
                       f"over the stroke in {spec.get('time', 1.0):g} s"), spec["torque"] / max(peak, 1e-300)


def _tolerance(spec: CheckSpec, mech: Mechanism, model: Model, chain):
    output = f"slide:{model.slider}" if model.slider else f"angle:{model.of_link}"
    _, qs = _stroke(mech, model)
    tol = Tolerancing(mech, output, qs, tolerance=spec["tolerance"])
    s = sensitivity(tol, distribution="uniform")
    worst = np.asarray(s.worst, float)
    unit = "m" if model.slider else "°"
    factor = 1.0 if model.slider else math.degrees(1.0)
    budget = spec["budget"]  # in the output's unit: a length for a slide, degrees for an angle
    if not np.all(np.isfinite(worst)):
        return CheckResult("tolerance", False, message="first order is not valid: the output is singular somewhere "
                           "over the stroke"), None
    spread = float(np.max(worst)) * factor
    ok = spread <= budget
    task = model.task
    what = (f"the length of {' and '.join(task.of) if isinstance(task.of, tuple) else task.of}" if model.slider
            and not model.guided else f"the travel of {task.of}" if model.guided else f"the angle of {task.of}")
    return CheckResult("tolerance", ok, spread, budget, "max", unit,
                       f"worst case ±{spread:.3g} {unit} of {what.replace('_', ' ')} ({output}) over the stroke, "
                       f"from ±{spec['tolerance']:g} on every dimension (first order; budget ±{budget:g} {unit}); "
                       f"largest share {s.ranking[0]}"), spread / budget


CHECKS = {"wheel-rate": _wheel_rate, "force-ratio": _force_ratio, "drive": _drive, "tolerance": _tolerance}
#: The soft index each check gives the ranking.
INDEX_OF = {"wheel-rate": "force", "force-ratio": "force", "drive": "force", "tolerance": "sensitivity"}


def compactness(mech: Mechanism, model: Model) -> float:
    """The area of the box around every joint over the stroke, over the area of the task's box (smaller: more
    compact; above 1 the mechanism leaves its box as it moves)."""
    q0, qs = _stroke(mech, model)
    names = [f"point:{j.name}" for j in mech.joints]
    sw = sweep(mech, q0, float(qs[-1]), abs(float(qs[-1]) - q0) / (qs.size - 1), outputs=names)
    xs = np.concatenate([np.asarray(sw.table[f"{n}.x"], float) for n in names])
    ys = np.concatenate([np.asarray(sw.table[f"{n}.y"], float) for n in names])
    (x0, x1), (y0, y1) = model.task.box
    return float(np.ptp(xs) * np.ptp(ys) / ((x1 - x0) * (y1 - y0)))


def complexity(chain) -> float:
    """Links, plus the links with three or more joints, plus the prismatic pairs: what there is to make."""
    degrees = [sum(k in e for e in chain.edges) for k in range(chain.n)]
    return float(chain.n + sum(d >= 3 for d in degrees) + sum(t == "P" for t in chain.joint_types))
