"""``domes regenerate SCENE`` and ``domes generalize FILE``."""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING

from domes.cli.common import progress_printer
from domes.errors import InputError

if TYPE_CHECKING:  # the stages are loaded by the commands that use them
    from domes.typesynth.regenerate import Regeneration

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "regenerate": "regenerate chains into mechanisms under a design scene's rules",
    "generalize": "the generalized chain of a mechanism file (Table 3-5)",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "regenerate",
        help=COMMANDS["regenerate"],
        description="Yan's chain regeneration: assign the scene's roles stage by stage on every "
        "chain, remove duplicates exactly, screen, particularize, and flag existing designs. "
        "SCENE is a scene name (knowledge/scenes/NAME.toml) or a scene file.",
    )
    p.add_argument("scene", metavar="SCENE", help="scene name or file")
    p.add_argument("--format", choices=("text", "json", "html"), default="text",
                   help="text (default), json, or an HTML atlas page with a sketch of every candidate")
    p.add_argument("--new-only", action="store_true", help="leave out candidates equal to an existing design")
    p.set_defaults(func=run_regenerate)

    g = sub.add_parser(
        "generalize",
        help=COMMANDS["generalize"],
        description="Generalize a mechanism (TOML file, see docs/regeneration.md) into its chain of "
        "revolute joints with the marks of Table 3-5, and find the chain in the atlas.",
    )
    g.add_argument("file", metavar="FILE", help="mechanism file (.toml)")
    g.add_argument("--format", choices=("text", "json", "mtm", "type"), default="text",
                   help="text (default), json, or the mechanism's own MTM / TYPE matrix")
    g.set_defaults(func=run_generalize)


def _roles_text(candidate) -> str:
    m = candidate.labelled
    by_role: dict[str, list[int]] = {}
    for v, roles in enumerate(m.roles):
        for r in roles:
            by_role.setdefault(r, []).append(v)
    return "  ".join(f"{r}={','.join(map(str, vs))}" for r, vs in sorted(by_role.items(), key=lambda x: x[1]))


def _mode_text(candidate, dof: int) -> str:
    """The candidate's combination mode(s) (seed 002 §3-3-III.2), when it has one ground and one input."""
    from domes.model.combination_modes import combination_phrase

    try:
        phrase = combination_phrase(candidate.labelled, dof)
    except InputError:  # no driver (or no single one): no combination mode to read
        return ""
    return f"  {phrase}" if phrase else ""


def print_regeneration(result: Regeneration, new_only: bool, out=None) -> None:
    out = out or sys.stdout  # looked up now: the stdout of the moment (a test's capture), not of the import
    scene = result.scene
    out.write(f"{scene.title}  [{scene.name}]\n")
    if scene.source:
        out.write(f"source: {scene.source}\n")
    out.write(f"chains: {scene.links} links, DOF {scene.dof}\n\n")
    out.write(f"  {'stage':<34s} {'count':>6s} {'book':>6s} {'raw S_i':>8s} {'n_i':>6s}\n")
    for s, n in zip(result.stages, result.divergence_numbers()):
        book = "-" if s.book is None else str(s.book)
        name = f"{s.name} [{s.change}]" if s.change else s.name
        out.write(f"  {name:<34s} {s.count:>6d} {book:>6s} {s.raw:>8d} {n:>6.2f}\n")
    if scene.book_note:
        out.write(f"  book: {scene.book_note}\n")

    def named(i: int) -> str:
        name = result.chain_name(i)
        return f" ({name})" if name else ""

    existing = [c for c in result.candidates if c.existing]
    split = ", ".join(f"chain {i}{named(i)}: {k}" for i, k in result.per_chain().items())
    out.write(f"\n{len(result.candidates)} candidates ({split}), {len(existing)} existing, {len(result.candidates) - len(existing)} new\n")
    for c in result.candidates:
        if new_only and c.existing:
            continue
        m = c.labelled
        special = " ".join(f"{u}-{v}:{t}" for (u, v), t in zip(m.edges, m.joint_types) if t != "R")
        flag = f"  EXISTING ({'; '.join(c.existing)})" if c.existing else ""
        joints = " ".join(f"{u}-{v}" for u, v in m.edges)
        mode = _mode_text(c, scene.dof)
        out.write(f"  {c.id:3d}  chain {c.chain_index}{named(c.chain_index)}  {_roles_text(c)}  [{special}]  "
                  f"joints {joints}{mode}{flag}\n")


def run_regenerate(args: argparse.Namespace) -> int:
    from domes.io.scenes import load_scene
    from domes.typesynth.regenerate import regenerate

    result = regenerate(load_scene(args.scene), progress_printer())
    if args.format == "json":
        json.dump(result.to_dict(new_only=args.new_only), sys.stdout, indent=1)
        sys.stdout.write("\n")
    elif args.format == "html":
        from domes.sketch.atlas import regeneration_html  # the drawing stage, loaded only when asked

        sys.stdout.write(regeneration_html(result, new_only=args.new_only))
    else:
        print_regeneration(result, args.new_only)
    return 0


def run_generalize(args: argparse.Namespace) -> int:
    from domes.io.topology import read_topology, to_mtm, type_matrix
    from domes.typesynth.generalize import generalize

    mechanism = read_topology(args.file)
    if args.format == "mtm":
        print(to_mtm(mechanism))
        return 0
    if args.format == "type":
        print(type_matrix(mechanism))
        return 0
    g = generalize(mechanism)
    record = g.to_dict()
    if args.format == "json":
        json.dump(record, sys.stdout, indent=1)
        sys.stdout.write("\n")
        return 0
    chain, position = g.unlabelled, record["atlas_position"]
    print(f"{mechanism.name}: generalized chain of {chain.n} links, {chain.joints} joints, DOF {chain.dof}, {chain.loops} loops")
    if record["chain"]:
        print(f"  the {record['chain']} chain")
    if position:
        kind = "with or without cut links" if chain.cut_links else "without cut links"
        print(f"  chain #{position} of `domes chains --links {chain.n} --dof {chain.dof}{' --include-fractionated' if chain.cut_links else ''}` ({kind})")
    if chain.is_degenerate:
        print(f"  degenerate: links {[g.link_names[v] for v in chain.rigid_subchain]} form a rigid sub-chain")
    for (u, v), t in zip(g.chain.edges, g.chain.joint_types):
        mark = f"  mark {t}" if t != "R" else ""
        print(f"  joint {g.link_names[u]}-{g.link_names[v]}{mark}")
    for v, roles in enumerate(g.chain.roles):
        if roles:
            print(f"  link {g.link_names[v]}: {', '.join(sorted(roles))}")
    print(f"  graph6 {chain.graph6}")
    return 0
