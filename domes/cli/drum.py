"""``domes drum``: the tyre-building drum checks of a mechanism file with tiles (seed 002, §5-3; docs/drum.md).

>>> from domes.cli import main
>>> main(["drum", "knowledge/mechanisms/tyre-drum-fig5-1.json"])    # doctest: +ELLIPSIS
tyre-building drum, ...: N = 12, D1 = 0.80309, D2 = 0.84309; folded 0.638643 (D1/Df = 1.2575); Δ_min = ...
0
"""

from __future__ import annotations

import argparse
import json
import math

from domes.errors import InputError

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "drum": "tyre-building drum checks: deployed cylinder, folded space, interference Δ_min, D0/D1, α1/β1, "
            "anti-retraction",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "drum",
        help=COMMANDS["drum"],
        description="Read a mechanism file with tiles (polygons 'tile ...') and a frame point 'drum axis' as one "
        "of N tile pairs of a tyre-building drum and run every drum check: the tiles deployed form a gap-free "
        "cylinder, folded they fit inside D1, the least signed clearance Δ_min of the tiles (own and "
        "neighbouring pairs) from folded to deployed, D0/D1, the tile angles α1/β1 and the main shaft's holding "
        "torque (anti-retraction). Exit status 1 when a check fails. Readings of the book's undefined terms: "
        "docs/drum.md.",
    )
    p.add_argument("file", help="mechanism file (JSON) with tiles and the drum axis")
    p.add_argument("--lengthen", type=float, default=None, metavar="FACTOR",
                   help="check the same drum with every tile FACTOR times as long round the axis (0 < FACTOR ≤ 2)")
    p.add_argument("--layout", action="store_true",
                   help="also the tile layout (N, tile I's share) with the least folded perimeter, interference-free "
                   "folded, for the file's drum")
    p.add_argument("--link-width", type=float, default=None, metavar="W",
                   help="also check the tiles against the links, each a bar of half-width W about its joints "
                   "(the file has no link widths), from folded to deployed")
    p.add_argument("--format", choices=("text", "json"), default="text", help="output format")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from domes.design import drum as dm
    from domes.io.mechanisms import load_mechanism

    drum = dm.Drum.of(load_mechanism(args.file))
    if args.lengthen is not None:
        if not (math.isfinite(args.lengthen) and 0 < args.lengthen <= 2):
            raise InputError(f"--lengthen must be a number in (0, 2], got {args.lengthen!r}")
        drum = dm.lengthen(drum, args.lengthen)
    c = dm.check(drum, link_width=args.link_width)
    layout = None
    if args.layout:
        layout = dm.layout_optimum(_design_of(drum))
    if args.format == "json":
        out = {"name": c.name, "success": c.success, "count": c.count, "D1": 2 * c.inner, "D2": 2 * c.outer,
               "folded_diameter": c.folded_diameter, "folding_ratio": c.folding_ratio, "D0_D1": c.d0_d1,
               "delta_min": c.delta.minimum, "pair": c.delta.pair.label, "input_deg": math.degrees(c.delta.input),
               "angles_deg": {k: math.degrees(v) for k, v in c.angles.items()}, "holding_torque": c.holding,
               "holding_share": c.holding_share, "failures": c.failures}
        if c.links is not None:
            out["links"] = {"half_width": c.link_width, "least_clearance": c.links.minimum, "pair": c.links.pair.label,
                            "input_deg": math.degrees(c.links.input)}
        if layout is not None:
            out["layout"] = {"count": layout.count, "share": layout.share, "perimeter": layout.perimeter}
        print(json.dumps(out, indent=1))
    else:
        print(c.message)
        if layout is not None:
            print(f"layout: {layout.message}")
    return 0 if c.success else 1


def _design_of(drum):
    """The file's drum as a :class:`~domes.design.drum.Design` whose count and share the layout search varies: its
    tiles read back as a layout (radii, where the pair starts and ends, the face slants)."""
    from domes.design import drum as dm

    w = drum.world(drum.deployed)
    r = [drum.radii(v) for v in w.values()]
    inner = float(min(x.min() for x in r))
    outer = float(max(x.max() for x in r))
    spans = drum.spans(drum.deployed)
    order = tuple(sorted(spans, key=lambda k: spans[k][0]))
    if set(order) != {"tile I", "tile II"}:
        raise InputError(f"{drum.mech.name}: --layout needs the two tiles 'tile I' and 'tile II'")
    start = spans[order[0]][0]
    pitch = 2 * math.pi / drum.count
    share = (spans["tile I"][1] - spans["tile I"][0]) / pitch
    slants = []
    for name, edge in ((order[0], 0), (order[1], 0)):
        ends = [f for n, f in drum.ends(drum.deployed) if n == name]
        ang = [(math.atan2(f[1][1] - drum.centre[1], f[1][0] - drum.centre[0]),
                math.atan2(f[0][1] - drum.centre[1], f[0][0] - drum.centre[0])) for f in ends]
        first = min(ang, key=lambda a: abs(math.remainder(a[0] - spans[name][0], 2 * math.pi)))
        slants.append(math.remainder(first[1] - first[0], 2 * math.pi))
    mid = start + pitch / 2
    reach = (drum.centre[0] + outer * math.cos(mid), drum.centre[1] + outer * math.sin(mid))
    carriers = {n: drum.shapes[n].link for n in ("tile I", "tile II")}
    bare = drum.mech
    return dm.Design(bare, carriers, drum.deployed, drum.folded, reach, mid, outer, outer - inner, drum.count, share,
                     tuple(slants), order, 4)
