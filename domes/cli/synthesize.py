"""``domes synthesize``: dimension a four-bar for a task file (guidance, function or path generation).

>>> from domes.cli import main
>>> main(["synthesize", "examples/synthesis/ch2-example-4.json"])         # doctest: +ELLIPSIS
# complete: ch2-example-4: 1 real root(s), 1 linkage(s), 1 usable; ... ms
1. usable; crank 0.63234, coupler 0.342974, rocker 0.652519, frame 1; non-Grashof (triple rocker); ...
   pivots A (0, 0), D (1, 0); moving pivots B (0.346046, 0.52925), C (0.375, 0.1875); largest error ...
   driven by a rocker: the link at A only rocks, from ...
   inversion (2-109) and Freudenstein's equation agree on the lengths to ...
0
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from domes.cli.common import finite_json, parallel_options, progress_printer, write_output
from domes.errors import InputError
from domes.execution import InProcess, executor
from domes.io.files import check_target

#: Seconds between progress lines when stderr is not a terminal (a log): at most one line per interval.
LOG_EVERY = 5.0


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "synthesize": "dimension a four-bar for a task file: rigid-body guidance, function or path generation, every "
    "solution",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "synthesize",
        help=COMMANDS["synthesize"],
        description="Dimensional synthesis (seed 002 §2-3): every real four-bar that meets the task's precision "
        "positions (guidance: 3 positions in closed form, 4 on the circle-point curve, 5 at the Burmester "
        "points; function generation: 3, 4 or 5 precision points, with the structural error over the range and "
        "optional re-spacing; path generation: five points with both fixed pivots given), each checked (branch, "
        "order and dead-point defects, Grashof class, transmission angle; every one moved by the kinematics kernel "
        "through the crank angles it claims, usable only within --tolerance; degenerate roots grouped) and "
        "written as a mechanism file for domes kinematics and domes draw. A 'curve' task dimensions the labelled "
        "candidates of a scene by least squares against a wanted curve (a motorcycle's leverage ratio). See "
        "docs/synthesis.md.",
    )
    p.add_argument("task", metavar="TASK.json", help="the task file (examples in examples/synthesis/)")
    p.add_argument("--method", choices=("exact", "fast"), default="exact",
                   help="exact: every real root (default); fast: Newton from random starts, may miss roots")
    p.add_argument("--seeds", type=int, default=64, help="random starts of the fast method (default 64)")
    p.add_argument("--format", choices=("text", "json", "html"), default="text",
                   help="text (default), json (each solution a mechanism file), or an html page of drawings")
    p.add_argument("--all", action="store_true", help="also list the rejected solutions (text)")
    p.add_argument("--output", "-o", help="write to this file (atomically) instead of standard output")
    p.add_argument("--min-transmission", type=float, metavar="DEG", default=None,
                   help="warn of a usable linkage whose smallest transmission angle is below DEG and rank it after "
                   "the others (default: the task's min_transmission_deg, else 20); for a curve task, the limit "
                   "its layouts are fitted to and verified against")
    p.add_argument("--tolerance", type=float, metavar="REL", default=None,
                   help="largest error of a usable linkage, re-evaluated by the kinematics kernel, relative to the "
                   "task's size (default: the task's tolerance, else 1e-6); for a curve task, its wanted.tolerance")
    p.add_argument("--max-link-ratio", type=float, metavar="R", default=None,
                   help="group roots whose longest link is more than R times the task's extent as degenerate "
                   "(default: the task's max_link_ratio, else 20)")
    p.add_argument("--quiet", "-q", action="store_true",
                   help="no progress lines on stderr (shown by default: on a terminal as the search goes, "
                   "elsewhere one every few seconds)")
    p.add_argument("--atlas", choices=("auto", "small", "quick", "none"), default="auto",
                   help="path tasks of nine points or more: the coupler-curve atlas whose look-up (as domes curves "
                   "match) seeds the least squares: small (the data folder's, built there first if need be), quick "
                   "(built in memory, about 2.5 s), none (random starts only); auto (default): small when it is "
                   "built, else quick")
    parallel_options(p, "dimension a curve task's candidates")
    p.set_defaults(func=run)


def run(args) -> int:
    from domes.design.synthesis import synthesize
    from domes.design.synthesis.candidate import CurveTask, Dimensioning
    from domes.design.synthesis.task import link_ratio, min_transmission, relative_tolerance
    from domes.io.tasks import load_spatial_task, load_task
    from domes.sketch.synthesis import synthesis_html

    if args.output:
        check_target(args.output)
    spatial = load_spatial_task(args.task)
    if spatial is not None:
        return _spatial(args, spatial)
    task = load_task(args.task)
    if args.min_transmission is not None:
        min_transmission(args.min_transmission, "--min-transmission")
    if args.tolerance is not None:
        relative_tolerance(args.tolerance, "--tolerance")
    if args.max_link_ratio is not None:
        if isinstance(task, CurveTask):
            raise InputError("--max-link-ratio is for guidance, function and path tasks; a curve task's lengths are "
                             "bounded by its box and limits")
        link_ratio(args.max_link_ratio, "--max-link-ratio")
    with executor(args.workers, args.scheduler) as run_on:
        result = synthesize(task, args.method, args.seeds, progress=_progress(args),
                            executor=None if isinstance(run_on, InProcess) else run_on,
                            min_transmission_deg=args.min_transmission, tolerance=args.tolerance,
                            max_link_ratio=args.max_link_ratio, atlas=_atlas(args.atlas))
    if args.format == "html":
        text = synthesis_html(result, task)
    elif isinstance(result, Dimensioning):
        text = _curve_json(result) if args.format == "json" else _curve_text(result, args.all)
    else:
        text = _json(result) if args.format == "json" else _text(result, args.all)
    write_output(text, args.output)
    return 0 if result.success else 1


def _atlas(choice: str):
    """The atlas whose look-up seeds a path task: ``small`` (from the data folder, built there first if need be),
    ``quick`` (built in memory), ``none``; ``auto``: the small one when it is built, else the quick one."""
    from domes.io.atlas import atlas_path, default_atlas
    from domes.motion.coupler.atlas import Atlas

    if choice == "none":
        return False
    if choice == "small" or (choice == "auto" and atlas_path("small").is_file()):
        return Atlas(default_atlas("small"))
    return None


def _progress(args):
    """Progress on stderr unless ``--quiet``: as it comes on a terminal, else a line every few seconds."""
    if args.quiet:
        return None
    return progress_printer(True, every=0.0 if sys.stderr.isatty() else LOG_EVERY)


def _solution_dict(s, name):
    out = {"mechanism": s.fourbar.mechanism(name).to_dict(), "usable": s.usable, "defects": list(s.defects),
           "warnings": list(s.warnings),
           "lengths": s.fourbar.named_lengths(),
           "residuals": list(s.residuals), "equation_residuals": list(s.equation_residuals),
           "grashof": s.checks.grashof, "crank_rotates": s.checks.crank_rotates, "driver": s.checks.driver,
           "crank_range_deg": list(s.checks.crank_range_deg) if s.checks.crank_range_deg else None,
           "min_transmission_deg": s.checks.min_transmission_deg,
           "crank_angles_deg": list(s.checks.crank_angles_deg), "notes": list(s.notes)}
    if s.structural is not None:
        out["structural_error_deg"] = {"largest": math.degrees(s.structural.largest),
                                       "extrema": [math.degrees(e) for e in s.structural.extrema]}
    if s.respaced is not None:
        out["respaced"] = {"points": list(s.respaced.points),
                           "largest_deg": math.degrees(s.respaced.after.largest),
                           "extrema_deg": [math.degrees(e) for e in s.respaced.after.extrema],
                           "mechanism": _generator_mechanism(s.respaced.generator, name)}
    return out


def _generator_mechanism(g, name):
    from domes.design.synthesis.solve import generator_fourbar

    return generator_fourbar(g, g.theta0, g.phi0).mechanism(name + " (re-spaced)").to_dict()


def _json(result) -> str:
    data = {"task": result.task_name, "kind": result.kind, "status": str(result.status), "message": result.message,
            "roots": result.roots, "seconds": result.seconds, "notes": list(result.notes),
            "min_transmission_deg": result.min_transmission_deg, "tolerance": result.tolerance,
            "max_link_ratio": result.max_link_ratio, "size": result.size,
            "degenerate": [{"group": g.name, "count": g.count, "text": g.text} for g in result.degenerate],
            "solutions": [_solution_dict(s, f"{result.task_name} solution {k}")
                          for k, s in enumerate(result.solutions, 1)]}
    return json.dumps(finite_json(data), indent=1) + "\n"


def _fmt(p) -> str:
    return f"({p[0]:.6g}, {p[1]:.6g})"


def _text(result, everything: bool) -> str:
    from domes.design.synthesis.fourbars import SliderCrank

    lines = [f"# {result.message}"] + [f"# {n}" for n in result.notes]
    shown = result.solutions if everything else result.usable
    for k, s in enumerate(shown, 1):
        fb = s.fourbar
        state = "usable" if s.usable else "rejected: " + "; ".join(s.defects)
        if s.usable and s.warnings:
            state = "usable, with a warning"
        sizes = ", ".join(f"{name} {v:.6g}" for name, v in fb.named_lengths().items())
        lines.append(f"{k}. {state}; {sizes}; {s.checks.grashof}; smallest transmission angle "
                     f"{s.checks.min_transmission_deg:.1f}°")
        fixed = (f"slide through C at {math.degrees(fb.direction):.6g}°" if isinstance(fb, SliderCrank)
                 else f"D {_fmt(fb.b0)}")
        lines.append(f"   pivots A {_fmt(fb.a0)}, {fixed}; moving pivots B {_fmt(fb.a1)}, C {_fmt(fb.b1)}; "
                     f"largest error {s.residual:.1e} ({_measure(result.kind, s)}; equations "
                     f"{max(s.equation_residuals, default=0.0):.1e})")
        if s.checks.driver:
            lines.append(f"   {s.checks.driver}")
        for warning in s.warnings:
            lines.append(f"   warning: {warning}")
        for note in s.notes:
            lines.append(f"   {note}")
        if s.respaced is not None:
            r = s.respaced
            lines.append(f"   re-spaced precision points {', '.join(f'{x:.6g}' for x in r.points)}: largest error "
                         f"{math.degrees(r.after.largest):.4g}° (extrema equal within {100 * r.after.spread:.2g}%, "
                         f"{r.iterations} steps)")
    if not everything and len(result.usable) < len(result.solutions):
        lines.append(f"# {len(result.solutions) - len(result.usable)} rejected solution(s) not shown (--all lists them)")
    return "\n".join(lines) + "\n"


def _measure(kind: str, s) -> str:
    """What a solution's errors are: the kinematics kernel's re-evaluation of the task."""
    if s.claim is not None and s.claim.on_curve:
        return "kernel: distance of the points from the coupler curve"
    return {"path": "kernel: distance of the coupler point from each point",
            "guidance": "kernel: pose error at each position",
            "function": "kernel: rocker pin from its wanted place"}[kind]


def _curve_dict(s) -> dict:
    return {"candidate": s.candidate, "mechanism": s.mechanism.to_dict(), "usable": s.usable,
            "defects": list(s.defects), "error": s.error, "rms": s.rms,
            "min_transmission_deg": s.min_transmission_deg, "length": list(s.length) if s.length else None,
            "x": list(s.x), "achieved": list(s.achieved), "wanted": list(s.wanted), "notes": list(s.notes)}


def _curve_json(result) -> str:
    data = {"task": result.task_name, "kind": result.kind, "status": str(result.status), "message": result.message,
            "candidates": list(result.candidates), "screened": result.screened, "polished": result.polished,
            "seconds": result.seconds, "notes": list(result.notes),
            "solutions": [_curve_dict(s) for s in result.solutions]}
    return json.dumps(data, indent=1) + "\n"


def _curve_text(result, everything: bool) -> str:
    lines = [f"# {result.message}", f"# {result.screened:,} random layouts screened per candidate, the best "
             f"{result.polished} polished by least squares"] + [f"# {n}" for n in result.notes]
    shown = result.solutions if everything else result.usable
    for k, s in enumerate(shown, 1):
        state = "verified" if s.usable else "rejected: " + "; ".join(s.defects)
        length = f"; length {s.length[0]:.4g} to {s.length[1]:.4g}" if s.length else ""
        lines.append(f"{k}. candidate {s.candidate}: {state}; curve error {100 * s.error:.3g}% largest, "
                     f"{100 * s.rms:.3g}% RMS; smallest transmission angle {s.min_transmission_deg:.1f}°{length}")
        lines.append("   joints " + ", ".join(f"{j.name} {_fmt(j.at)}" for j in s.mechanism.joints if j.kind == "R"))
        for note in s.notes:
            lines.append(f"   {note}")
    if not everything and len(result.usable) < len(result.solutions):
        lines.append(f"# {len(result.solutions) - len(result.usable)} rejected layout(s) not shown (--all lists them)")
    return "\n".join(lines) + "\n"


def _spatial(args, task) -> int:
    """A spatial task (spherical guidance, spherical function generation, the RCCC of seed 004)."""
    from domes.design.synthesis.spatialtask import solve_spatial

    if args.format == "html":
        raise InputError("--format html is for planar tasks; draw a spatial solution with domes draw (save it with "
                         "--format json)")
    result = solve_spatial(task, progress=_progress(args))
    if args.format == "json":
        text = json.dumps(finite_json(result.to_dict()), indent=1) + "\n"
    else:
        text = "\n".join([f"# {result.message}"] + list(result.lines[1:])) + "\n"
    write_output(text, args.output)
    return 0 if result.success else 1
