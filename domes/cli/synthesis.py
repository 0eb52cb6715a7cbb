"""``domes synthesis``: links, joints and link assortments of a problem."""

from __future__ import annotations

import argparse
import json

from domes.cli.common import confirm
from domes.errors import InputError

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {"synthesis": "number synthesis: links and joints from DOF, loops, λ and gear pairs"}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "synthesis",
        help=COMMANDS["synthesis"],
        description="Number synthesis (DOMES §7-2): i = W + (λ−1)L − j_G + 1, j = W + λL − j_G, "
        "and the link assortments of Table 3-1.",
    )
    p.add_argument("--dof", "-W", type=int, required=True, help="degrees of freedom W")
    p.add_argument("--loops", "-L", type=int, required=True, help="independent loops L_ind")
    p.add_argument("--space", type=int, default=3, choices=(3, 6), help="λ: 3 planar (default), 6 spatial")
    p.add_argument("--gear-pairs", type=int, default=0, help="gear pairs j_G (default 0)")
    p.add_argument("--format", choices=("text", "json"), default="text")
    p.add_argument("--no-assortments", action="store_true", help="only the numbers of links and joints")
    p.add_argument("--yes", "-y", action="store_true", help=f"list more than {LARGE:,} link assortments without asking")
    p.set_defaults(func=run)


#: More link assortments than this are listed only when the user agrees (--yes).
LARGE = 10_000
#: More than this cannot be listed at all (the list would not finish).
HUGE = 10_000_000
#: Assortments are counted exactly up to this many loops (a second); beyond, the count is bounded below.
COUNTED_LOOPS = 1000


def run(args: argparse.Namespace) -> int:
    from domes.typesynth.number import count_link_assortments, link_assortments, number_synthesis

    result = number_synthesis(args.dof, args.loops, args.space, args.gear_pairs)
    assortments = []
    if result.loops >= 1 and not args.no_assortments:
        if result.loops > COUNTED_LOOPS:  # the count grows with the loops: the one at COUNTED_LOOPS is a lower bound
            bound = number_synthesis(args.dof, COUNTED_LOOPS, args.space, args.gear_pairs)
            raise InputError(f"{result.links} links and {result.joints} joints have more than "
                             f"{count_link_assortments(bound.links, bound.joints):.3g} link assortments, too many to "
                             "list; give --no-assortments for the numbers of links and joints")
        count = count_link_assortments(result.links, result.joints)
        if count > HUGE:
            raise InputError(f"{result.links} links and {result.joints} joints have {count:.3g} link assortments, "
                             "too many to list; give --no-assortments for the numbers of links and joints")
        if count > LARGE:
            confirm("synthesis", f"{result.links} links and {result.joints} joints have {count:,} link assortments",
                    args.yes)
        assortments = link_assortments(result.links, result.joints)
    if args.format == "json":
        record = dict(vars(result))
        record["assortments"] = [{str(d): k for d, k in a.counts.items()} for a in assortments]
        print(json.dumps(record, indent=2))
        return 0
    print(f"W={result.dof}  L={result.loops}  λ={result.space}  j_G={result.gear_pairs}")
    print(f"links i = {result.links}   joints j = {result.joints}")
    if assortments:
        print("link assortments (n_2, n_3, ...):")
        for a in assortments:
            print("  " + "  ".join(f"n_{d}={k}" for d, k in a.counts.items()))
    return 0
