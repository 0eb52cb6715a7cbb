"""``domes draw``: one chain (graph6) as a skeleton drawing, or with labels as a mechanism sketch."""

from __future__ import annotations

import argparse
import math
import os
from typing import TYPE_CHECKING

from domes.cli.common import write_output
from domes.cli.kinematics import parse_sweep
from domes.errors import InputError

if TYPE_CHECKING:  # loaded by the commands that use them
    from domes.model import LabelledChain
    from domes.model.chain import Chain


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "draw": "draw a chain (graph6) as a mechanism skeleton or sketch, or a mechanism file (JSON) to scale",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.model import JOINT_TYPES
    from domes.motion import PRESETS

    p = sub.add_parser(
        "draw",
        help=COMMANDS["draw"],
        description="Draw one chain, given as a graph6 string (as printed by `domes chains --format graph6`), "
        "as a mechanism skeleton: bars, plates, joints. With --ground, --input, --joint or --role the "
        "chain is labelled and drawn as a mechanism sketch with the symbols of Table 3-5. "
        "A mechanism file (FILE.json, see docs/kinematics.md) is drawn to scale at an input (--at), "
        "joint positions from the kinematics backend, with the coupler curves of --coupler points.",
    )
    p.add_argument("graph6", metavar="GRAPH6|FILE.json", help="the chain in graph6 format (links are numbered 0..n-1 in graph6 order), or a mechanism file ending in .json")
    p.add_argument("--format", choices=("svg", "html"), default="svg", help="an SVG drawing (default) or a one-card HTML page")
    p.add_argument("--output", "-o", help="write to this file (atomically) instead of standard output")
    p.add_argument("--graph", action="store_true", help="draw the abstract graph (links as vertices) beside the skeleton")
    p.add_argument("--size", type=float, help="drawing size in pixels (default 220, 400 for a mechanism file)")
    p.add_argument("--ground", type=int, action="append", default=[], metavar="LINK", help="the ground (frame) link")
    p.add_argument("--input", type=int, action="append", default=[], metavar="LINK", help="the input (driving) link")
    p.add_argument("--role", action="append", default=[], metavar="LINK=NAME", help="give link LINK the role NAME (e.g. 3=swing_arm); repeatable")
    p.add_argument("--joint", action="append", default=[], metavar="U-V=T", help=f"joint between links U and V has type T ({', '.join(JOINT_TYPES)}); repeatable")
    m = p.add_argument_group("mechanism files (FILE.json)")
    m.add_argument("--at", type=float, metavar="INPUT", help="the first input's value: degrees for an R input, a length for a P input (default: the drawn pose)")
    m.add_argument("--coupler", nargs="+", action="extend", default=[], metavar="POINT", help="trace these coupler points (or joints) over a sweep of the first input")
    m.add_argument("--sweep", metavar="START:STOP[:STEP]", help="the sweep for --coupler (degrees or lengths; default: a full turn each way from the drawn pose, or the mechanism's size each way for a P input)")
    m.add_argument("--accuracy", choices=sorted(PRESETS), default="default", help="kinematics accuracy preset; sets the sweep's resolution (fast 5°, default 1°, exact 0.25°)")
    m.add_argument("--no-dimensions", dest="dimensions", action="store_false", help="leave out the link lengths")
    p.set_defaults(func=run_draw)


def _parse_role(text: str) -> tuple[int, str]:
    link, sep, name = text.partition("=")
    if not sep or not name.strip() or not link.strip().isdigit():
        raise InputError(f"--role {text!r}: expected LINK=NAME, e.g. 3=swing_arm")
    return int(link), name.strip()


def _parse_joint(text: str) -> tuple[tuple[int, int], str]:
    pair, sep, kind = text.partition("=")
    ends = pair.split("-")
    if not sep or len(ends) != 2 or not all(e.strip().isdigit() for e in ends):
        raise InputError(f"--joint {text!r}: expected U-V=T, e.g. 4-5=P")
    return (int(ends[0]), int(ends[1])), kind.strip()


def labelled_from_args(chain: Chain, args: argparse.Namespace) -> LabelledChain | None:
    """The labelled chain the options describe, or ``None`` when none is given."""
    from domes.model import LabelledChain

    if not (args.ground or args.input or args.role or args.joint):
        return None
    roles: dict[int, set[str]] = {}
    for link in args.ground:
        roles.setdefault(link, set()).add("ground")
    for link in args.input:
        roles.setdefault(link, set()).add("input")
    for text in args.role:
        link, name = _parse_role(text)
        roles.setdefault(link, set()).add(name)
    types = {}
    joints = set(chain.edges)
    for text in args.joint:
        (u, v), kind = _parse_joint(text)
        if (min(u, v), max(u, v)) not in joints:
            raise InputError(f"--joint {text!r}: links {u} and {v} are not jointed in this chain (joints: {' '.join(f'{a}-{b}' for a, b in chain.edges)})")
        types[(u, v)] = kind
    return LabelledChain.build(chain.n, chain.edges, types, roles)


def _size(given: float | None, default: float) -> float:
    size = default if given is None else given
    if not 40 <= size <= 4000:
        raise InputError(f"--size must be between 40 and 4000 pixels, got {size}")
    return size


def run_draw(args: argparse.Namespace) -> int:
    from domes.model.chain import Chain
    from domes.sketch.atlas import atlas_html, chain_card, mechanism_card
    from domes.sketch.layout import skeleton_layout

    if args.graph6.lower().endswith(".json"):
        return draw_mechanism_file(args)
    args.size = _size(args.size, 220.0)
    given = [name for name, value in (("--at", args.at), ("--coupler", args.coupler), ("--sweep", args.sweep)) if value not in (None, [])]
    if given:
        raise InputError(f"{', '.join(given)}: only for a mechanism file (FILE.json), not for a chain")
    chain = Chain.from_graph6(args.graph6)
    labelled = labelled_from_args(chain, args)
    if labelled is None:
        card = chain_card(args.graph6, chain, layout=skeleton_layout(chain), graph=args.graph, size=args.size)
    else:
        card = mechanism_card(args.graph6, labelled, title=f"mechanism on chain {args.graph6}", size=args.size)
    if args.format == "html":
        write_output(atlas_html([card], card.title), args.output)
    else:
        write_output(card.svg + "\n", args.output)
    return 0


def draw_mechanism_file(args: argparse.Namespace) -> int:
    """``domes draw FILE.json``: the mechanism to scale at ``--at``, with its coupler curves."""
    from domes.io.mechanisms import is_spatial, load_mechanism
    from domes.sketch.atlas import Card, atlas_html
    from domes.sketch.dimensioned import dimensioned_svg

    given = [name for name, value in (("--ground", args.ground), ("--input", args.input), ("--role", args.role), ("--joint", args.joint), ("--graph", args.graph)) if value]
    if given:
        raise InputError(f"{', '.join(given)}: only for a chain (graph6); a mechanism file has its own ground, inputs and joints")
    size = _size(args.size, 400.0)
    if is_spatial(args.graph6):
        return _draw_spatial(args, size)
    mech = load_mechanism(args.graph6)
    scale = math.radians if mech.joint(mech.inputs[0].joint).kind == "R" else float
    q = None if args.at is None else scale(args.at)
    span = parse_sweep(args.sweep, scale) if args.sweep else None
    svg = dimensioned_svg(mech, q, coupler=args.coupler, span=span, accuracy=args.accuracy, size=size, dimensions=args.dimensions)
    if args.format == "html":
        card = Card(os.path.basename(args.graph6), mech.name, svg, (("file", args.graph6), ("traced", " ".join(args.coupler) or "none")))
        write_output(atlas_html([card], mech.name), args.output)
    else:
        write_output(svg + "\n", args.output)
    return 0


def _draw_spatial(args: argparse.Namespace, size: float) -> int:
    """A spatial mechanism file: an axonometric SVG at ``--at``, or (html) a page that turns and plays a sweep."""
    from domes.io.mechanisms import load_spatial
    from domes.motion.spatial.loops import Loops
    from domes.motion.spatial.sweep import spatial_sweep
    from domes.sketch.spatial import spatial_html, spatial_svg

    mech = load_spatial(args.graph6)
    if not mech.inputs:
        raise InputError(f"{args.graph6}: the mechanism has no input")
    first = mech.inputs[0]
    angular = first.variable == "angle"
    scale = math.radians if angular else float
    names = {j.name for j in mech.joints} | {p.name for p in mech.points}
    unknown = [c for c in args.coupler if c not in names]
    if unknown:
        raise InputError(f"--coupler {unknown}: not joints or points of {mech.name} ({sorted(names)})")
    kin = Loops(mech)
    if args.sweep:
        start, stop, step = parse_sweep(args.sweep, scale)
    else:
        start, stop, step = (0.0, 2 * math.pi, math.radians(5)) if angular else (0.0, 0.1 * mech.size, 0.005 * mech.size)
    if args.format == "html" or args.coupler:
        sw = spatial_sweep(mech, start, stop, step)
        frames = [kin.places(s) for s in sw.states]
    if args.format == "html":
        unit = "°" if angular else ""
        shown = [math.degrees(q) for q in sw.inputs] if angular else list(sw.inputs)
        summary = (f"{sw.message}. Drag the drawing or use the sliders to turn it; play moves it through the sweep.")
        write_output(spatial_html(mech, frames, shown, first.joint, unit, args.coupler, size=max(size, 520.0),
                                  summary=summary), args.output)
        return 0
    q = 0.0 if args.at is None else scale(args.at)
    state = spatial_sweep(mech, q, q, None).states[-1] if q else kin.drawn()
    traces = {c: [f[c] for f in frames] for c in args.coupler} if args.coupler else None
    write_output(spatial_svg(mech, kin.places(state), traces, size) + "\n", args.output)
    return 0
