"""Dimensional verification of a candidate inside a design session (the kinematics backend).

The designer gives a dimensioned mechanism file (``examples/mechanisms/``)
for one of the candidates kept, and a check:

* ``rotatability``: does the input turn fully? (else the reachable range and
  the dead points);
* ``range OUTPUT FROM:TO``: the smallest and largest value of an output while
  the input goes from FROM to TO (degrees for a revolute input, lengths for a
  prismatic one), e.g. the shock absorber's stroke for a swing-arm travel.

The file must be that candidate: same chain, same joint types, and its
ground on the candidate's ground link when the candidate has one.

>>> parse_check(["range", "slide:g", "-10:10"])
('range', 'slide:g', -10.0, 10.0)
"""

from __future__ import annotations

import math
from pathlib import Path

from domes.errors import InputError
from domes.motion.planar import checks
from domes.model.mechanism import Mechanism, load_mechanism
from domes.model.labelled import LabelledChain
from domes.io.resources import repo_root


def parse_check(words: list[str]) -> tuple:
    if words == ["rotatability"]:
        return ("rotatability",)
    if len(words) == 3 and words[0] == "range" and words[2].count(":") == 1:
        try:
            start, stop = (float(x) for x in words[2].split(":"))
        except ValueError:
            raise InputError(f"range FROM:TO must be two numbers, got {words[2]!r}") from None
        return ("range", words[1], start, stop)
    raise InputError("the check is 'rotatability' or 'range OUTPUT FROM:TO'")


def as_labelled(mech: Mechanism) -> LabelledChain:
    """The mechanism's chain with joint types and its ground."""
    index = {name: i for i, name in enumerate(mech.links)}
    return LabelledChain.build(
        len(mech.links),
        [(index[j.links[0]], index[j.links[1]]) for j in mech.joints],
        [j.kind for j in mech.joints],
        {index[mech.ground]: {"ground"}},
    )


def matches(candidate: LabelledChain, mech: Mechanism) -> bool:
    """Whether the dimensioned mechanism is this candidate (chain, joint types, ground)."""
    grounded = any("ground" in r for r in candidate.roles)
    mine = as_labelled(mech)
    if not grounded:
        mine = mine.with_roles({})
    keep = candidate.with_roles({v: r & {"ground"} for v, r in enumerate(candidate.roles)})
    return keep == mine


def load_for(candidate: LabelledChain, path: str) -> Mechanism:
    """The mechanism file (relative paths: to the working folder, else to the checkout), checked to be the candidate."""
    found = Path(path)
    if not found.is_file() and not found.is_absolute() and (repo_root() / found).is_file():
        found = repo_root() / found
    if not found.is_file():
        raise InputError(f"no mechanism file {path!r}")
    mech = load_mechanism(str(found))
    if not matches(candidate, mech):
        raise InputError(f"{path} is not this candidate: its chain, joint types or ground differ")
    return mech


def run_check(mech: Mechanism, check: tuple) -> str:
    """The check's result in words, with the numbers that show how good it is."""
    if check[0] == "rotatability":
        r = checks.rotatability(mech)
        if r.full:
            return f"{mech.name}: the input turns fully"
        lo, hi = (math.degrees(x) for x in r.reachable)
        dead = "; ".join(d.message for d in r.dead_points[:2])
        return f"{mech.name}: the input does not turn fully; it reaches {lo:.4f}° .. {hi:.4f}° ({dead})"
    _, output, start, stop = check
    angular = next(j for j in mech.joints if j.name == mech.inputs[0].joint).kind == "R"
    scale = math.radians(1) if angular else 1.0
    r = checks.output_range(mech, output, start * scale, stop * scale)
    unit, factor = ("°", math.degrees(1)) if r.column.startswith("angle:") else ("", 1.0)
    where = "" if r.stopped_at is None else f"; stopped at a limit: {r.stopped_at.message}"
    return (
        f"{mech.name}: {r.column} from {r.minimum * factor:.6g}{unit} to {r.maximum * factor:.6g}{unit} "
        f"(travel {r.travel * factor:.6g}{unit}) while the input goes from {start:g} to {stop:g}{where}"
    )
