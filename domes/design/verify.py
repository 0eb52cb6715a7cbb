"""Dimensional verification of a candidate: the checks a design scene asks of the kinematics backend.

The designer gives a dimensioned mechanism (a file of ``examples/mechanisms/``)
for one of the candidates kept, and a :class:`Check`:

* ``rotatability``: does the input turn fully? (else the reachable range and
  the dead points);
* ``range OUTPUT FROM:TO``: the smallest and largest value of an output while
  the input goes from FROM to TO (degrees for a revolute input, lengths for a
  prismatic one), e.g. the shock absorber's stroke for a swing-arm travel;
* ``force-ratio OUTPUT FROM:TO [RATIO]``: the force an output point delivers
  along its path (or an output link's torque) per unit input force, the
  toggle where it grows without bound, and where RATIO is reached (the hinge
  clamp; :func:`~domes.design.forces.force_ratio`);
* ``wheel-rate POINT SPRING FROM:TO``: the leverage ratio and the wheel rate
  at POINT from the file's SPRING (the motorcycle suspension);
* ``drive FROM:TO``: the input's force or torque from the file's masses,
  loads and springs (the tyre drum's actuator).

The mechanism must be that candidate (:func:`matches`): same chain, same
joint types, and its ground on the candidate's ground link when the
candidate has one.

>>> from domes.motion.planar.examples import four_bar
>>> Check.parse(["range", "angle:rocker", "0:90"])
Check(kind='range', output='angle:rocker', start=0.0, stop=90.0, ratio=None, spring='')
>>> result = verify(four_bar(), Check.parse(["rotatability"]))
>>> result.success, result.message
(True, 'crank-rocker four-bar: the input turns fully')
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.design import forces
from domes.errors import InputError
from domes.model.labelled import LabelledChain
from domes.model.mechanism import Mechanism
from domes.motion.planar import checks
from domes.results import Result, Status

CHECKS = ("rotatability", "range", "force-ratio", "wheel-rate", "drive")

#: How each check is written.
USAGE = ("rotatability", "range OUTPUT FROM:TO", "force-ratio OUTPUT FROM:TO [RATIO]", "wheel-rate POINT SPRING FROM:TO",
         "drive FROM:TO")


@dataclass(frozen=True)
class Check:
    """A verification (see the module doc): its ``kind``, ``output``, input range, wanted ``ratio``, ``spring``."""

    kind: str
    output: str = ""
    start: float = 0.0
    stop: float = 0.0
    ratio: float | None = None
    spring: str = ""

    @classmethod
    def parse(cls, words: list[str]) -> "Check":
        """A check from the designer's words (one of :data:`USAGE`)."""
        kind, rest = (words[0], words[1:]) if words else ("", [])
        if kind == "rotatability" and not rest:
            return cls("rotatability")
        if kind == "range" and len(rest) == 2:
            return cls("range", rest[0], *_span(rest[1]))
        if kind == "force-ratio" and len(rest) in (2, 3):
            ratio = None
            if len(rest) == 3:
                try:
                    ratio = float(rest[2])
                except ValueError:
                    ratio = math.nan
                if not (math.isfinite(ratio) and ratio > 0):
                    raise InputError(f"force-ratio RATIO must be a number > 0, got {rest[2]!r}")
            return cls("force-ratio", rest[0], *_span(rest[1]), ratio=ratio)
        if kind == "wheel-rate" and len(rest) == 3:
            return cls("wheel-rate", rest[0], *_span(rest[2]), spring=rest[1])
        if kind == "drive" and len(rest) == 1:
            return cls("drive", "", *_span(rest[0]))
        raise InputError("the check is one of: " + "; ".join(f"'{u}'" for u in USAGE))


def _span(text: str) -> tuple[float, float]:
    if text.count(":") != 1:
        raise InputError(f"FROM:TO must be two numbers joined by ':', got {text!r}")
    try:
        start, stop = (float(x) for x in text.split(":"))
    except ValueError:
        raise InputError(f"FROM:TO must be two numbers, got {text!r}") from None
    if not (math.isfinite(start) and math.isfinite(stop)):
        raise InputError(f"FROM:TO must be finite numbers, got {text!r}")
    if start == stop:
        raise InputError(f"FROM:TO is an empty range: {text!r}")
    return start, stop


@dataclass(frozen=True)
class Verification(Result):
    """The outcome of a check: ``status`` COMPLETE when the check passed over its whole range.

    ``values`` holds the numbers found (``reachable`` range, ``minimum``,
    ``maximum`` and ``travel`` of an output, in the file's units and degrees).
    """

    check: Check
    status: Status
    message: str
    values: dict = field(default_factory=dict)


def matches(candidate: LabelledChain, mech: Mechanism) -> bool:
    """Whether the dimensioned mechanism is this candidate (chain, joint types, ground)."""
    grounded = any("ground" in r for r in candidate.roles)
    mine = mech.labelled()
    if not grounded:
        mine = mine.with_roles({})
    keep = candidate.with_roles({v: r & {"ground"} for v, r in enumerate(candidate.roles)})
    return keep == mine


def verify(mech: Mechanism, check: Check, accuracy=None) -> Verification:
    """Run one check on a dimensioned mechanism; the message says the result with its numbers."""
    if check.kind == "rotatability":
        r = checks.rotatability(mech, accuracy)
        lo, hi = (math.degrees(x) for x in r.reachable)
        if r.full:
            return Verification(check, Status.COMPLETE, f"{mech.name}: the input turns fully", {"reachable": (lo, hi)})
        dead = "; ".join(d.message for d in r.dead_points[:2])
        return Verification(check, Status.STOPPED, f"{mech.name}: the input does not turn fully; it reaches "
                            f"{lo:.4f}° .. {hi:.4f}° ({dead})", {"reachable": (lo, hi)})
    if check.kind not in CHECKS:
        raise InputError(f"unknown check {check.kind!r}; the checks are {', '.join(CHECKS)}")
    angular = next(j for j in mech.joints if j.name == mech.inputs[0].joint).kind == "R"
    scale = math.radians(1) if angular else 1.0
    if check.kind in ("force-ratio", "wheel-rate", "drive"):
        return _force_check(mech, check, angular, scale, accuracy)
    r = checks.output_range(mech, check.output, check.start * scale, check.stop * scale, accuracy=accuracy)
    unit, factor = ("°", math.degrees(1)) if r.column.startswith("angle:") else ("", 1.0)
    where = "" if r.stopped_at is None else f"; stopped at a limit: {r.stopped_at.message}"
    values = {"minimum": r.minimum * factor, "maximum": r.maximum * factor, "travel": r.travel * factor}
    message = (
        f"{mech.name}: {r.column} from {values['minimum']:.6g}{unit} to {values['maximum']:.6g}{unit} "
        f"(travel {values['travel']:.6g}{unit}) while the input goes from {check.start:g} to {check.stop:g}{where}"
    )
    return Verification(check, Status.COMPLETE if r.stopped_at is None else Status.STOPPED, message, values)


#: Steps of a force check over its range.
FORCE_STEPS = 60


def _force_check(mech: Mechanism, check: Check, angular: bool, scale: float, accuracy) -> Verification:
    start, stop = check.start * scale, check.stop * scale
    step = abs(stop - start) / FORCE_STEPS
    unit = (lambda q: math.degrees(q)) if angular else float
    if check.kind == "force-ratio":
        r = forces.force_ratio(mech, check.output, start, stop, step, check.ratio, accuracy=accuracy)
        values = {"minimum": float(np.min(r.ratio)), "maximum": float(np.max(r.ratio[np.isfinite(r.ratio)])),
                  "toggles": [unit(q) for q in r.toggles]}
        if r.reached is not None:
            q, d_in, d_out = r.reached
            values.update({"reached_at": unit(q), "distance_input": unit(d_in), "distance_output": d_out})
        ok = check.ratio is None or r.reached is not None or values["maximum"] >= check.ratio
        return Verification(check, Status.COMPLETE if ok and r.success else Status.STOPPED, r.message, values)
    if check.kind == "wheel-rate":
        r = forces.wheel_rate(mech, check.output, check.spring, start, stop, step, accuracy=accuracy)
        values = {"leverage": (float(r.leverage.min()), float(r.leverage.max())),
                  "wheel_rate": (float(r.wheel_rate[0]), float(r.wheel_rate[-1])), "travel": float(np.ptp(r.travel))}
        return Verification(check, r.status, r.message, values)
    r = forces.drive(mech, start, stop, step, accuracy=accuracy)
    d = r.dynamics
    value, where = d.peak(r.joint)
    values = {"peak": value, "at": unit(where), "start": float(d.driving[r.joint][0]),
              "end": float(d.driving[r.joint][-1]), "max_imbalance": d.max_imbalance}
    return Verification(check, r.status, r.message, values)
