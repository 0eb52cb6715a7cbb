"""Dimensional verification of a candidate: the checks a design scene asks of the kinematics backend.

The designer gives a dimensioned mechanism (a file of ``examples/mechanisms/``)
for one of the candidates kept, and a :class:`Check`:

* ``rotatability``: does the input turn fully? (else the reachable range and
  the dead points);
* ``range OUTPUT FROM:TO``: the smallest and largest value of an output while
  the input goes from FROM to TO (degrees for a revolute input, lengths for a
  prismatic one), e.g. the shock absorber's stroke for a swing-arm travel.

The mechanism must be that candidate (:func:`matches`): same chain, same
joint types, and its ground on the candidate's ground link when the
candidate has one.

>>> from domes.motion.planar.examples import four_bar
>>> Check.parse(["range", "angle:rocker", "0:90"])
Check(kind='range', output='angle:rocker', start=0.0, stop=90.0)
>>> result = verify(four_bar(), Check.parse(["rotatability"]))
>>> result.success, result.message
(True, 'crank-rocker four-bar: the input turns fully')
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from domes.errors import InputError
from domes.model.labelled import LabelledChain
from domes.model.mechanism import Mechanism
from domes.motion.planar import checks
from domes.results import Result, Status

CHECKS = ("rotatability", "range")


@dataclass(frozen=True)
class Check:
    """A verification: ``rotatability``, or the ``range`` of ``output`` over the input from ``start`` to ``stop``."""

    kind: str
    output: str = ""
    start: float = 0.0
    stop: float = 0.0

    @classmethod
    def parse(cls, words: list[str]) -> "Check":
        """A check from the designer's words: ``rotatability`` or ``range OUTPUT FROM:TO``."""
        if words == ["rotatability"]:
            return cls("rotatability")
        if len(words) == 3 and words[0] == "range" and words[2].count(":") == 1:
            try:
                start, stop = (float(x) for x in words[2].split(":"))
            except ValueError:
                raise InputError(f"range FROM:TO must be two numbers, got {words[2]!r}") from None
            if not (math.isfinite(start) and math.isfinite(stop)):
                raise InputError(f"range FROM:TO must be finite numbers, got {words[2]!r}")
            return cls("range", words[1], start, stop)
        raise InputError("the check is 'rotatability' or 'range OUTPUT FROM:TO'")


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
    if check.kind != "range":
        raise InputError(f"unknown check {check.kind!r}; the checks are {', '.join(CHECKS)}")
    angular = next(j for j in mech.joints if j.name == mech.inputs[0].joint).kind == "R"
    scale = math.radians(1) if angular else 1.0
    r = checks.output_range(mech, check.output, check.start * scale, check.stop * scale, accuracy=accuracy)
    unit, factor = ("°", math.degrees(1)) if r.column.startswith("angle:") else ("", 1.0)
    where = "" if r.stopped_at is None else f"; stopped at a limit: {r.stopped_at.message}"
    values = {"minimum": r.minimum * factor, "maximum": r.maximum * factor, "travel": r.travel * factor}
    message = (
        f"{mech.name}: {r.column} from {values['minimum']:.6g}{unit} to {values['maximum']:.6g}{unit} "
        f"(travel {values['travel']:.6g}{unit}) while the input goes from {check.start:g} to {check.stop:g}{where}"
    )
    return Verification(check, Status.COMPLETE if r.stopped_at is None else Status.STOPPED, message, values)
