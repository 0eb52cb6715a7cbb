"""``domes catalogue``: standard mechanisms by the motion they convert, their properties measured.

>>> from domes.cli import main
>>> main(["catalogue", "--motion", "rotation -> intermittent rotation", "--require", "dwell >= 250"])  # doctest: +ELLIPSIS
# complete: rotation → intermittent rotation: 3 catalogue mechanism(s), 1 meeting dwell >= 250; ordered for ...
1. Geneva wheel, 4 slots (geneva): kept
   the wheel turns a quarter turn while the crank turns 90 degrees and is locked for the other 270
   index 90°; dwell 270°; peak speed ratio 2.41421
   dwell >= 250: has 270°
   why here: exact: intermittent is choice 2 of cam, intermittent, linkage, gears, gear-linkage; a precise ...
2. Geneva wheel, 6 slots (geneva): left out
...
0
"""

from __future__ import annotations

import argparse
import json
import sys

from domes.cli.common import finite_json

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "catalogue": "standard mechanisms by the motion they convert (rotation -> straight line, ...), properties measured",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.knowledge.catalogue import FUNCTIONS, MOTIONS

    p = sub.add_parser(
        "catalogue",
        help=COMMANDS["catalogue"],
        description="The catalogue of standard mechanisms (seed 002 ch. 1 system search, §5-1 functional "
        "combination): slider-crank, Scotch yoke, tangent, quick return, toggle press, straight-line linkages, "
        f"Geneva wheels, ratchet, cams, gears. Motions: {', '.join(MOTIONS)}. Each property is measured on the "
        "mechanism's model (the kinematics kernel or a closed form); the mechanisms kept are ordered by the §6-1 "
        "heuristic for the function (--function, or implied by a requirement). See docs/catalogue.md.",
    )
    p.add_argument("--motion", metavar="'IN -> OUT'", help="e.g. 'rotation -> straight line' (default: every entry)")
    p.add_argument("--require", action="append", default=[], metavar="'NAME OP NUMBER'",
                   help="a property the mechanism must have, e.g. 'dwell >= 90' or 'straight-line deviation <= 0.5' "
                   "(repeat for more)")
    p.add_argument("--function", choices=FUNCTIONS,
                   help="seed 002 §6-1: order the mechanisms by the families that suit this function best (default: "
                   "the function a requirement implies, e.g. a dwell: exact)")
    p.add_argument("--knowledge", metavar="FOLDER", help="a knowledge folder with its own catalogue.toml "
                   "(and heuristics.toml)")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from domes.design.catalogue import propose
    from domes.io.catalogue import load_catalogue, load_heuristics

    found = propose(load_catalogue(args.knowledge), args.motion, args.require, args.function,
                    load_heuristics(args.knowledge))
    if args.format == "json":
        rule = found.heuristic
        doc = {"message": found.message, "motion": list(found.motion),
               "requirements": [str(r) for r in found.requirements],
               "heuristic": None if rule is None else {"function": rule.function, "prefer": list(rule.prefer),
                                                       "reason": rule.reason, "source": rule.source},
               "mechanisms": [{"name": p.entry.name, "motion": list(p.entry.motion), "model": p.entry.model,
                               "family": p.entry.family, "kept": p.kept, "reasons": list(p.reasons),
                               "advice": p.advice, "source": p.entry.source,
                               "description": p.entry.description,
                               "properties": {k: {"value": v.value, "unit": v.unit, "how": v.how}
                                              for k, v in p.properties.items()}}
                              for p in found]}
        json.dump(finite_json(doc), sys.stdout, indent=1)
        sys.stdout.write("\n")
        return 0
    print(f"# {found.message}")
    for k, p in enumerate(found, start=1):
        e = p.entry
        where = f"{e.motion[0]} → {e.motion[1]}, " if args.motion is None else ""
        print(f"{k}. {e.name} ({where}{e.model}): {'kept' if p.kept else 'left out'}")
        if e.description:
            print(f"   {e.description}")
        print("   " + "; ".join(f"{name} {value}" for name, value in p.properties.items()))
        for r in p.reasons:
            print(f"   {r}")
        if p.advice:
            print(f"   why here: {p.advice}")
    return 0 if found.success or not found.requirements else 1
