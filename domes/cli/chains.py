"""``domes chains`` (the atlas) and ``domes chain`` (one chain's properties)."""

from __future__ import annotations

import argparse
import json
import os
import sys
import textwrap
from typing import TYPE_CHECKING

from domes.cli.common import available_memory, confirm, parallel_options, progress_printer
from domes.errors import InputError
from domes.execution import SCHEDULER_VARIABLE, InProcess, executor
from domes.io.jobs import JobFolder

if TYPE_CHECKING:  # the chain model and the atlas are loaded by the commands that use them
    from domes.model.active import ActiveSets
    from domes.model.chain import Chain

#: Atlases from this many links on are very large: ask before building them.
LARGE_ATLAS_LINKS = 14
#: Pages of more drawn chains than this are made only when the user agrees (--yes).
LARGE_PAGE = 1000

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "chains": "every non-isomorphic, non-degenerate chain with N links and DOF F",
    "chain": "structural properties of given chains (graph6), degenerate ones included",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.typesynth.atlas import AUGMENT_LINKS, GENERATION_METHODS, ISOMORPHISM_METHODS

    p = sub.add_parser(
        "chains",
        help=COMMANDS["chains"],
        description="The unlabelled graph generator: every non-isomorphic kinematic chain of planar motion "
        "with simple revolute joints, the given links and DOF, and no rigid or over-constrained proper "
        "sub-chain (--spatial: single-loop spatial chains instead). DOF 0 gives the basic chains of Table 3-4 (with K). A chain whose graph is not planar "
        "(it cannot be drawn without crossings; 11 of the 230 ten-bar chains) is marked 'non-planar graph'. "
        "--clamping lists the chains of clamps instead (seed 002, §3-3-I (4)): any DOF, W <= 0 included, immobile "
        "sub-chains admitted (each marked with its links).",
    )
    size = p.add_mutually_exclusive_group(required=True)
    size.add_argument("--links", "-n", type=int, help="number of links n")
    size.add_argument("--loops", "-L", type=int, help="number of independent loops (links = F + 2L + 1)")
    p.add_argument("--dof", "-F", type=int, required=True,
                   help="degrees of freedom F of the chain (0 for basic chains; below 0 with --clamping)")
    p.add_argument("--include-fractionated", action="store_true", help="keep chains with a cut link")
    p.add_argument("--clamping", action="store_true",
                   help="clamping chains (seed 002, §3-3-I (4), Fig. 3-23): admit immobile (rigid or over-constrained) "
                   "sub-chains and any DOF, W <= 0 included; every simple graph of the size, each link with 2+ joints")
    p.add_argument("--count", action="store_true", help="print only the number of chains")
    p.add_argument("--spatial", nargs="?", const="RPHCS", metavar="TYPES",
                   help="single-loop spatial chains (λ = 6) instead: joints from TYPES (default RPHCS: revolute, "
                   "prismatic, helical, cylindric, spherical), DOF by Kutzbach less the idle spins of links held by "
                   "two S joints, up to rotation and reflection of the loop (docs/spatial.md); text and json")
    p.add_argument("--active", action="store_true",
                   help="with each chain, its sets of F joints (up to symmetry) that can be active pairs together "
                   "and the DOF type each gives: full, partial or fractionated (seed 002, §3-2-I.5); text and json")
    p.add_argument("--format", choices=("text", "graph6", "json", "html"), default="text", help="html: an atlas page with a drawing of every chain")
    p.add_argument(
        "--isomorphism",
        choices=ISOMORPHISM_METHODS,
        default="nauty",
        help="duplicate removal: nauty (exact, default) or charpoly (the book's test; merges some chains)",
    )
    p.add_argument("--method", choices=GENERATION_METHODS, default="auto",
                   help="how chains without a cut link are generated: augment (canonical augmentation: independent "
                   "parts, bounded memory on each worker), merge (level by level, children merged by certificate in "
                   f"this process; every smaller atlas kept with --out) or auto (default: augment from {AUGMENT_LINKS} "
                   "links on); the same atlas either way")
    p.add_argument("--yes", "-y", action="store_true",
                   help=f"build atlases of {LARGE_ATLAS_LINKS}+ links, or draw pages of more than {LARGE_PAGE} chains, without asking")
    p.add_argument("--out", metavar="FOLDER",
                   help="write the atlas (graph6, one chain a line) to FOLDER, with every smaller atlas it is built "
                   "from as each is finished and the large levels' slices as they come; rerun with the same FOLDER "
                   "to resume a killed run")
    parallel_options(p, "build the atlas's large levels")
    progress = p.add_mutually_exclusive_group()
    progress.add_argument("--progress", dest="progress", action="store_true", default=None, help="show progress on stderr")
    progress.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")
    p.set_defaults(func=run_chains)

    q = sub.add_parser(
        "chain",
        help=COMMANDS["chain"],
        description="Properties of one or more chains given as graph6 strings: loops, DOF, link "
        "assortment, contracted graph, DOF type, automorphisms and link orbits, for a "
        "degenerate chain the rigid sub-chain that makes it so, and for a chain of DOF F >= 1 its sets of F "
        "joints that can be active pairs together, with the DOF type each gives (seed 002, §3-2-I.5).",
    )
    q.add_argument("graph6", nargs="+", help="chains in graph6 format ('-' reads them from stdin, one per line)")
    q.add_argument("--format", choices=("text", "json"), default="text")
    q.set_defaults(func=run_chain)


def _duration(seconds: float) -> str:
    if seconds < 120:
        return f"{seconds:.0f} s"
    if seconds < 7200:
        return f"{seconds / 60:.0f} min"
    if seconds < 3 * 86400:
        return f"{seconds / 3600:.1f} h"
    return f"{seconds / 86400:.0f} days"


def _confirm_large(links: int, dof: int, include_fractionated: bool, yes: bool, workers: int = 1,
                   method: str = "merge", progress=None) -> None:
    """Say how large, long and memory-hungry the atlas will likely be, before it starts; go on if the user agrees."""
    from domes.typesynth.atlas import forecast

    f = (forecast(links, dof, include_fractionated) if method == "merge"
         else forecast(links, dof, include_fractionated, method, max(workers, 1), progress=progress))
    where = {0: "in one process (less on the cluster)", 1: "in this process"}.get(workers, f"on {workers} workers")
    text = (f"the atlas of {links}-link chains with DOF {dof} is very large: roughly {f.count:.1e} chains ({f.basis}), "
            f"likely {_duration(f.seconds_on(max(workers, 1)))} {where} and {f.memory / 2**30:.1f} GiB of memory")
    if f.work:
        text += f" ({f.worker_memory / 2**30:.2f} GiB a worker)"
    available = available_memory()
    cores = os.cpu_count() or 1
    if available is not None and f.memory > available:
        text += f"; this machine has {available / 2**30:.1f} GiB available, so it will not fit"
        if not f.work:
            text += " (more workers do not help: the merge holds every chain in this process)"
    elif workers == 1 and cores > 1:
        text += f"; with --workers {cores}, likely {_duration(f.seconds_on(cores))}"
    confirm("chains", text, yes)


def _text_line(index: int, chain: Chain) -> str:
    assortment = " ".join(f"{d}^{k}" for d, k in chain.assortment.items())
    joints = " ".join(f"{u}-{v}" for u, v in chain.edges)
    mark = "" if chain.graph_planar else "  non-planar graph"
    return f"{index:5d}  [{assortment}]  |Aut|={chain.automorphisms.order:<3d} {chain.dof_type:<12s} {joints}{mark}"


def _check_active(args: argparse.Namespace) -> None:
    """--active is for the text and json listings of mobile chains."""
    if not args.active:
        return
    clash = ("--clamping" if args.clamping else "--count" if args.count else "--out" if args.out is not None
             else f"--format {args.format}" if args.format in ("graph6", "html") else None)
    if clash:
        raise InputError(f"--active adds the active pairs to the text and json listings; {clash} has no room for "
                         "them: leave one of the two out")
    if args.dof < 1:
        raise InputError(f"--active needs chains of DOF 1 or more (active pairs drive a chain); got --dof {args.dof}")


def _active_text(found: ActiveSets) -> str:
    return "  " + found.summary()


def run_chains(args: argparse.Namespace) -> int:
    from domes.model.chain import Chain
    from domes.model.mobility import chain_joints
    from domes.typesynth.atlas import ChainGenerator, check_links

    if args.spatial is not None:
        return _run_spatial(args)
    _check_active(args)
    if args.dof < 0 and not args.clamping:
        raise InputError(f"--dof must be >= 0 for chains without immobile sub-chains, got {args.dof}; chains of "
                         "DOF below 0 always hold one: add --clamping to list them (the chains of clamps, W <= 0)")
    if args.loops is not None:
        if args.loops < 1:
            raise InputError(f"--loops must be >= 1, got {args.loops}")
        links = args.dof + 2 * args.loops + 1
    else:
        links = args.links
    if args.clamping:
        return _run_clamping(args, links)
    joints = chain_joints(links, args.dof)
    loops = joints - links + 1
    if loops < 1:
        raise InputError(f"{links} links with DOF {args.dof} have {joints} joints and no closed loop; use more links")
    check_links(links)
    job = None
    if args.out is not None:
        if args.format != "text":
            raise InputError(f"--out writes the atlas as graph6 files to {args.out}; --format {args.format} is for "
                             "standard output, leave one of them out")
        job = JobFolder(args.out, {"kind": "chain atlas", "isomorphism": args.isomorphism},
                        say=lambda text: print(f"domes chains: {text}", file=sys.stderr, flush=True))
    if args.method == "augment" and args.isomorphism != "nauty":
        raise InputError(f"--method augment keeps chains by nauty's canonical labelling (exact); --isomorphism "
                         f"{args.isomorphism} is for --method merge: leave one of them out")
    method = "merge" if args.isomorphism != "nauty" and args.method == "auto" else args.method
    if links >= LARGE_ATLAS_LINKS:
        _confirm_large(links, args.dof, args.include_fractionated, args.yes,
                       0 if args.scheduler or os.environ.get(SCHEDULER_VARIABLE) else args.workers or 1, method,
                       progress_printer(args.progress))
    rerun = None if job is None else f"run the same command again ({args.out} keeps every finished slice)"
    streamed = not args.include_fractionated and (args.count or job is not None or args.format == "graph6")
    with executor(args.workers, args.scheduler, rerun) as run:
        generator = ChainGenerator(isomorphism=args.isomorphism, progress=progress_printer(args.progress),
                                   executor=None if isinstance(run, InProcess) else run, checkpoints=job,
                                   method=method)
        if streamed:                                  # never held as graphs (see ChainGenerator.stream)
            count, lines = generator.stream(links, args.dof)
            if not args.count and job is None:
                for line in lines:
                    sys.stdout.write(line + "\n")
                return 0
        else:
            graphs = generator.chains(links, args.dof, args.include_fractionated)
            count = len(graphs)
    if args.count:
        print(count)
        return 0
    if job is not None:
        kind = "-with-cut-links" if args.include_fractionated else ""
        print(f"{count} chains of {links} links, DOF {args.dof}: {job.path / f'chains-n{links}-F{args.dof}{kind}.g6'}")
        return 0
    return _write_atlas(args, [Chain(n, edges) for n, edges in graphs], links, joints, loops)


def _run_spatial(args: argparse.Namespace) -> int:
    """``domes chains --spatial``: the single-loop spatial chains of ``domes.typesynth.spatial``."""
    from domes.typesynth.spatial import spatial_loops

    clash = ("--loops" if args.loops is not None else "--clamping" if args.clamping else "--active" if args.active
             else "--include-fractionated" if args.include_fractionated else "--out" if args.out is not None
             else f"--format {args.format}" if args.format in ("graph6", "html")
             else f"--isomorphism {args.isomorphism}" if args.isomorphism != "nauty" else None)
    if clash:
        raise InputError(f"--spatial lists single loops, given by --links, as text or json; {clash} is for the "
                         "planar atlas: leave it out")
    found = spatial_loops(args.links, args.dof, args.spatial)
    if args.count:
        print(len(found))
        return 0
    if args.format == "json":
        json.dump({"space": "spatial", "links": args.links, "joints": args.links, "loops": 1, "dof": args.dof,
                   "joint_types": found.joint_types, "count": len(found),
                   "proper": sum(loop.proper for loop in found),
                   "chains": [{"id": i, **loop.to_dict(), "note": loop.note()} for i, loop in enumerate(found, 1)]},
                  sys.stdout, indent=1)
        sys.stdout.write("\n")
        return 0
    print(f"# {found.message}")
    print("# DOF = Kutzbach (Σf − 6) less the idle spins (links held by two S joints); generic: the screw rank with "
          "the joints in general position")
    print("# joints: the loop's least reading (R < P < H < C < S) from any link either way round; the RSSR is RRSS")
    print("#   id  joints     Σf  Kutzbach  idle  DOF  generic  |sym|  note")
    for i, loop in enumerate(found, 1):
        print(f"{i:5d}  {loop.joints:<9s}  {loop.freedom:2d}  {loop.kutzbach:8d}  {loop.idle:4d}  {loop.dof:3d}  "
              f"{loop.generic_dof:7d}  {loop.symmetry:5d}  {loop.note()}".rstrip())
    return 0


def _run_clamping(args: argparse.Namespace, links: int) -> int:
    """``domes chains --clamping``: the small clamping atlases, built here (no --out, no workers needed)."""
    from domes.model.chain import Chain
    from domes.typesynth.atlas import MAX_CLAMPING_JOINTS, SMALL_CLAMPING_LINKS, ChainGenerator, clamping_joints

    if args.out is not None:
        raise InputError(f"--out is for the large atlases of mobile chains; a clamping atlas is small (at most "
                         f"{MAX_CLAMPING_JOINTS} joints beyond {SMALL_CLAMPING_LINKS} links): leave --out out and use "
                         "--format graph6 to save it")
    if links < 3:
        given = f" (links = F + 2L + 1 with --loops {args.loops} and --dof {args.dof})" if args.loops is not None else ""
        raise InputError(f"a clamping chain needs at least 3 links (a closed loop), got {links}{given}")
    joints = clamping_joints(links, args.dof)
    generator = ChainGenerator(isomorphism=args.isomorphism, progress=progress_printer(args.progress))
    graphs = generator.chains(links, args.dof, args.include_fractionated, clamping=True)
    if args.count:
        print(len(graphs))
        return 0
    return _write_atlas(args, [Chain(n, edges) for n, edges in graphs], links, joints, joints - links + 1)


def _write_atlas(args: argparse.Namespace, atlas: list[Chain], links: int, joints: int, loops: int) -> int:
    """Write the atlas to standard output in ``args.format``."""
    from domes.model.active import active_sets

    out = sys.stdout
    if args.format == "html":
        from domes.sketch.atlas import chain_atlas_html

        if len(atlas) > LARGE_PAGE:
            confirm("chains", f"a page of {len(atlas)} drawn chains is large: about {len(atlas) * 6 / 1000:.0f} MB, "
                    f"drawn in about {len(atlas) * 0.06 / 60:.0f} min", args.yes)

        out.write(chain_atlas_html(atlas, f"{len(atlas)} chains: {links} links, {joints} joints, DOF {args.dof}",
                                   progress=progress_printer(args.progress)))
    elif args.format == "graph6":
        for chain in atlas:
            out.write(chain.graph6 + "\n")
    elif args.format == "json":
        records = []
        for index, chain in enumerate(atlas, 1):
            record = {"id": index, **chain.to_dict()}
            if args.active:
                found = active_sets(chain)
                record["active_sets"] = {"classes": found.counts(), "labelled": found.counts(labelled=True)}
            records.append(record)
        json.dump(
            {
                "links": links,
                "joints": joints,
                "loops": loops,
                "dof": args.dof,
                "include_fractionated": args.include_fractionated,
                "clamping": args.clamping,
                "isomorphism": args.isomorphism,
                "count": len(atlas),
                "chains": records,
            },
            out,
            indent=1,
        )
        out.write("\n")
    else:
        kind = "with or without a cut link" if args.include_fractionated else "without a cut link"
        what = "chains"
        if args.clamping:
            kind += ", immobile sub-chains admitted"
            what = f"clamping chains ({sum(c.is_degenerate for c in atlas)} with an immobile sub-chain)"
        out.write(f"# {len(atlas)} {what}: {links} links, {joints} joints, {loops} loops, DOF {args.dof} ({kind})\n")
        out.write("#   id  [link assortment d^n_d]  |Aut|  DOF type   joints\n")
        if args.active:
            out.write(f"#   active a/s: of the s sets of {args.dof} joints (up to symmetry), a can be active pairs "
                      "together: full, partial, fractionated DOF (seed 002, §3-2-I.5)\n")
        for index, chain in enumerate(atlas, 1):
            line = _text_line(index, chain)
            if args.active:
                line += _active_text(active_sets(chain))
            if args.clamping and chain.is_degenerate:
                line += f"  immobile sub-chain {{{', '.join(map(str, chain.rigid_subchain))}}}"
            elif args.dof == 0:
                line += f"  K={chain.structural_number}"
            out.write(line + "\n")
    return 0


def run_chain(args: argparse.Namespace) -> int:
    from domes.model.chain import Chain

    texts = [line for g in args.graph6 for line in (sys.stdin.read().split() if g == "-" else [g])]
    chains = [Chain.from_graph6(t) for t in texts]
    if args.format == "json":
        records = []
        for chain in chains:
            found, _ = _active_or_why(chain)
            records.append({**chain.to_dict(), "active_sets": found.to_dict() if found else None})
        json.dump(records, sys.stdout, indent=1)
        sys.stdout.write("\n")
        return 0
    for text, chain in zip(texts, chains):
        d = chain.to_dict()
        print(f"{text}: {d['links']} links, {d['joints']} joints, {d['loops']} loops, DOF {d['dof']}")
        print(f"  assortment {d['assortment']}   DOF type {d['dof_type']}   |Aut| = {d['automorphism_group_order']}")
        print(f"  link orbits {d['link_orbits']}   cut links {d['cut_links'] or 'none'}")
        if d["degenerate"]:
            print(f"  DEGENERATE: links {d['rigid_subchain']} form a rigid or over-constrained sub-chain")
        if "structural_number" in d:
            print(f"  structural characteristic number K = {d['structural_number']}")
        found, why = _active_or_why(chain)
        if found is not None:
            _print_active(found)
        elif chain.dof >= 1:
            print(f"  active pairs: not tabulated ({why})")
    return 0


def _active_or_why(chain: Chain) -> tuple[ActiveSets | None, str]:
    """The chain's active sets, or None and why there are none."""
    from domes.model.active import active_sets

    if chain.dof < 1:
        return None, f"DOF {chain.dof}"
    try:
        return active_sets(chain), ""
    except InputError as exc:
        return None, str(exc)


def _print_active(found: ActiveSets) -> None:
    """The counts, then the classes of joint sets by DOF type (each with how many sets it holds)."""
    from domes.model.active import DOF_TYPES

    c, labelled = found.counts(), found.counts(labelled=True)
    print(f"  active pairs ({found.dof} joints, classes up to symmetry): {c['active']} of {c['sets']} can be active "
          f"together (full {c['full']}, partial {c['partial']}, fractionated {c['fractionated']}); "
          f"{labelled['active']} of {labelled['sets']} sets")
    for kind in (*DOF_TYPES, None):
        items = [" ".join(f"{u}-{v}" for u, v in s.edges) + (f" (x{s.size})" if s.size > 1 else "")
                 for s in found.classes if s.dof_type == kind]
        if items:
            print(textwrap.fill("; ".join(items), 116, initial_indent=f"    {kind or 'not active':<13s}",
                                subsequent_indent=" " * 17))
