"""``domes curves``: the four-bar design space, coupler curves, their descriptors, the atlas and matching.

>>> from domes.cli import main
>>> main(["curves", "classify", "0.4", "1.2", "1.0", "1.4"])
a, b, c, d = 0.4, 1.2, 1, 1.4 (L = 1): region 1: crank-rocker, input a shortest (the crank)
Grashof: yes
0
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from domes.cli.common import confirm, parallel_options, progress_printer, write_output
from domes.errors import InputError
from domes.execution import InProcess, executor
from domes.io.files import check_target, read_json

FORMATS = ("text", "json", "csv", "html")


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "curves": "coupler curves: classify a four-bar, trace and describe curves, build the atlas, match a wanted path",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.motion.coupler.atlas import SIZES
    from domes.motion.coupler.freehand import CANDIDATES as DRAWN_CANDIDATES
    from domes.motion.coupler.match import CANDIDATES

    p = sub.add_parser(
        "curves",
        help=COMMANDS["curves"],
        description="Backward reasoning from a wanted coupler curve (seed 002 chapter 6): the four-bar design "
        "space (Table 6-1), every circuit of a coupler curve traced by the kinematics backend with its cusps and "
        "crossings, Fourier and fuzzy shape descriptors, the atlas of four-bar curves, and the four-bars that "
        "trace a wanted path (atlas look-up, then least-squares refinement). See docs/curves.md.",
    )
    cv = p.add_subparsers(dest="curves_command", metavar="ACTION")
    cv.required = True

    q = cv.add_parser("classify", help="the design-space region and Grashof class of a four-bar's lengths",
                      description="Normalise crank a, coupler b, output c and frame d (6-1)-(6-4) and name the "
                      "sub-region of Table 6-1 (or the boundary, for a change-point mechanism).")
    for name in ("a", "b", "c", "d"):
        q.add_argument(name, type=float, help={"a": "crank (input)", "b": "coupler", "c": "output (follower)",
                                              "d": "frame"}[name])
    q.add_argument("--format", choices=("text", "json"), default="text")
    q.set_defaults(func=run_classify)

    for name, helptext in (("trace", "every circuit of a coupler curve, with its cusps and crossings"),
                           ("describe", "the Fourier descriptor and fuzzy parameters of a curve")):
        q = cv.add_parser(name, help=helptext, description=helptext[0].upper() + helptext[1:] + ". The curve is "
                          "a mechanism file's coupler point, a four-bar given by --four-bar, or (describe) a "
                          "file of points (CSV or JSON).")
        q.add_argument("file", nargs="?", metavar="FILE",
                       help="mechanism file (.json with links and joints), or for describe a points file")
        q.add_argument("--four-bar", nargs=6, type=float, metavar=("A", "B", "C", "D", "U", "V"),
                       help="a four-bar in the chapter's convention: lengths and coupler point (u, v)")
        q.add_argument("--point", help="the coupler point to trace (default: the file's first point)")
        q.add_argument("--samples", type=int, default=720, help="samples per input turn (default 720)")
        q.add_argument("--format", choices=FORMATS if name == "trace" else ("text", "json"), default="text")
        q.add_argument("--output", "-o", help="write to this file (atomically) instead of standard output")
        q.set_defaults(func=run_trace if name == "trace" else run_describe)

    q = cv.add_parser("atlas", help="build the atlas of four-bar coupler curves, or say what one holds",
                      description="Sample the four-bar design space and the coupler plane (-4 <= u, v <= 4), trace "
                      "every linkage, and store each curve's normalised Fourier descriptor (HDF5). The small atlas "
                      "is built in your data folder when first needed (about 10 s); the large one on request.")
    q.add_argument("action", choices=("build", "info"))
    q.add_argument("--size", choices=sorted(SIZES), default="small", help="which atlas (default: small)")
    q.add_argument("--open", action="store_true", help="the atlas's index of open paths (windows of its curves)")
    q.add_argument("--file", help="an atlas file instead of the one in your data folder")
    q.add_argument("--yes", "-y", action="store_true", help="build the large atlas without asking")
    parallel_options(q, "trace the linkages")
    _progress(q)
    q.set_defaults(func=run_atlas)

    q = cv.add_parser("match", help="the four-bars whose coupler curve passes through a wanted path",
                      description="Look the wanted closed path (points, CSV or JSON) up in the atlas and refine "
                      "the nearest linkages by least squares until they pass through every point; report the "
                      "fit error before and after, and the linkage placed in the path's frame.")
    q.add_argument("file", metavar="POINTS", help="the wanted path: x, y per line (CSV) or a JSON list of [x, y]")
    q.add_argument("--atlas", default="small", metavar="SIZE|FILE", help="atlas size (small, large) or file")
    q.add_argument("--open", action="store_true",
                   help="the path is an open stretch, not a closed curve (also: \"closed\": false in a JSON file)")
    q.add_argument("--drawn", action="store_true",
                   help="the path is drawn by hand (noisy, unevenly spaced, perhaps with corners): read as a sketch, "
                   "closed or open by its ends (unless --open), every candidate fitted, each fit's error the distance "
                   "of your points from its traced curve, and the tolerance four times the sketch's scatter unless "
                   "--tol says (docs/curves.md)")
    q.add_argument("--speed", type=float, default=None, metavar="DEG",
                   help="with --drawn and a path timed by times (a CSV column headed time, a JSON \"times\" list): "
                   "the crank's speed in degrees per unit of time, its sign the direction (default: found by the fit; "
                   "a column headed angle, or \"angles\", gives the crank's angle at each point instead)")
    q.add_argument("--results", type=int, default=3, help="fitting linkages to find (default 3)")
    q.add_argument("--candidates", type=int, default=None,
                   help=f"atlas candidates refined at most (default {CANDIDATES}; with --drawn, where each one is "
                   f"fitted, {DRAWN_CANDIDATES})")
    q.add_argument("--tol", type=float, default=None,
                   help="largest distance accepted, relative to the path's size (default 1e-6; open paths 1e-3; "
                   "six-bars 1e-4)")
    q.add_argument("--six-bars", choices=("no", "auto", "yes"), default="no", dest="six_bars",
                   help="also fit Watt and Stephenson six-bars to a closed path: auto when no four-bar fits within "
                   "the tolerance, yes always (default no; the six-bar atlas is built in your data folder the first "
                   "time, docs/curves.md)")
    q.add_argument("--format", choices=("text", "json", "html"), default="text")
    q.add_argument("--output", "-o", help="write to this file (atomically) instead of standard output")
    q.add_argument("--save", metavar="FILE.json", help="save the best linkage as a mechanism file")
    _progress(q)
    q.set_defaults(func=run_match)


def _progress(q):
    shown = q.add_mutually_exclusive_group()
    shown.add_argument("--progress", dest="progress", action="store_true", default=None, help="show progress on stderr")
    shown.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")


# -- classify ---------------------------------------------------------------------------------


def run_classify(args) -> int:
    from domes.motion.coupler.designspace import classify

    p = classify(args.a, args.b, args.c, args.d)
    if args.format == "json":
        json.dump({"a": p.a, "b": p.b, "c": p.c, "d": p.d, "scale": p.scale, "region": p.region,
                   "boundary": list(p.boundary), "regions": list(p.regions), "mechanism": p.mechanism,
                   "grashof": p.grashof}, sys.stdout, indent=1)
        print()
    else:
        print(p.message)
        print(f"Grashof: {'yes' if p.grashof else 'no'}" + (" (at its limit)" if p.region is None else ""))
    return 0


# -- trace and describe -------------------------------------------------------------------------


def _mechanism(args):
    from domes.io.mechanisms import load_mechanism
    from domes.motion.coupler.fourbar import four_bar

    if args.four_bar and args.file:
        raise InputError("give a mechanism file or --four-bar, not both")
    if args.four_bar:
        return four_bar(*args.four_bar)
    if not args.file:
        raise InputError("give a mechanism file (FILE.json) or --four-bar A B C D U V")
    return load_mechanism(args.file)


def run_trace(args) -> int:
    import numpy as np

    from domes.motion.coupler.curves import trace
    from domes.motion.coupler.special import crossings, cusps
    from domes.sketch.curves import Card, curves_html, joint_names, moving_svg

    if args.output:
        check_target(args.output)
    mech = _mechanism(args)
    curve = trace(mech, args.point, args.samples, extra=joint_names(mech))
    specials = [(cusps(curve, c), crossings(curve, c)) for c in curve.circuits]
    if args.format == "csv":
        lines = ["circuit,index,input_deg,x,y"]
        for k, c in enumerate(curve.circuits, 1):
            for i, (q, (x, y)) in enumerate(zip(c.inputs, c.points)):
                lines.append(f"{k},{i},{math.degrees(q)!r},{x!r},{y!r}")
        write_output("\n".join(lines) + "\n", args.output)
    elif args.format == "json":
        doc = {"mechanism": mech.name, "point": curve.point, "circuits": [
            {"full_turn": c.full_turn, "turns": c.turns, "length": c.length,
             "limits_deg": [math.degrees(d.input) for d in c.limits],
             "branch_points_deg": [math.degrees(d.input) for d in c.branch_points],
             "cusps": [_special(s) for s in cu], "crossings": [_special(s) for s in cr],
             "inputs_deg": np.degrees(c.inputs).tolist(), "points": c.points.tolist()}
            for c, (cu, cr) in zip(curve.circuits, specials)]}
        write_output(json.dumps(doc, indent=1) + "\n", args.output)
    elif args.format == "html":
        cards = [Card(str(k), f"circuit {k}", moving_svg(mech, c, point=curve.point), _card_props(c, cu, cr))
                 for k, (c, (cu, cr)) in enumerate(zip(curve.circuits, specials), 1)]
        write_output(curves_html(cards, f"Coupler curve of {curve.point}: {mech.name}", curve.message), args.output)
    else:
        out = [curve.message]
        for k, (c, (cu, cr)) in enumerate(zip(curve.circuits, specials), 1):
            out.append(f"circuit {k}: " + "; ".join(f"{name} {value}" for name, value in _card_props(c, cu, cr)))
        write_output("\n".join(out) + "\n", args.output)
    return 0


def _special(s):
    return {"at": list(s.at), "inputs_deg": [math.degrees(q) for q in s.inputs], "measure": s.measure}


def _card_props(c, cu, cr):
    props = [("turns", f"{c.turns:.3g}"), ("length", f"{c.length:.6g}")]
    if c.limits:
        props.append(("limits", ", ".join(f"{math.degrees(d.input) % 360:.6g}°" for d in c.limits)))
    if c.branch_points:
        props.append(("branch points", ", ".join(f"{math.degrees(d.input) % 360:.6g}°" for d in c.branch_points)))
    props.append(("cusps", ", ".join(f"({s.at[0]:.6g}, {s.at[1]:.6g})" for s in cu) or "none"))
    props.append(("crossings", ", ".join(f"({s.at[0]:.6g}, {s.at[1]:.6g})" for s in cr) or "none"))
    return tuple(props)


def run_describe(args) -> int:
    from domes.io.curves import read_points
    from domes.motion.coupler.curves import trace
    from domes.motion.coupler.fourier import describe
    from domes.motion.coupler.fuzzy import parameters

    if args.output:
        check_target(args.output)
    if args.file and not args.four_bar and not _is_mechanism_file(args.file):
        curves = [("points", read_points(args.file))]
    else:
        mech = _mechanism(args)
        curve = trace(mech, args.point, args.samples)
        curves = [(f"circuit {k}", c.points) for k, c in enumerate(curve.circuits, 1)]
    docs = []
    for name, pts in curves:
        d = describe(pts)
        f = parameters(pts)
        docs.append({"curve": name, "fourier": {str(m): [a.real, a.imag] for m, a in d.coefficients.items()},
                     "translation": [d.translation.real, d.translation.imag], "rotation_deg": math.degrees(d.rotation),
                     "scale": d.scale, "start_deg": math.degrees(d.start), "reversed": d.reversed,
                     "fuzzy": {"type": f.type, "S": list(f.values), "crossings": f.crossings}})
    if args.format == "json":
        write_output(json.dumps(docs, indent=1) + "\n", args.output)
        return 0
    out = []
    for doc in docs:
        out.append(f"{doc['curve']}: Fourier descriptor (normalised; rotation {doc['rotation_deg']:.6g}°, scale "
                   f"{doc['scale']:.6g}, start {doc['start_deg']:.6g}°{', traversed backwards' if doc['reversed'] else ''})")
        for m, (re, im) in doc["fourier"].items():
            out.append(f"  a[{int(m):+d}] = {re: .6f} {im:+.6f}i")
        S = ", ".join(f"S{k}={v:.4g}" for k, v in enumerate(doc["fuzzy"]["S"], 1))
        out.append(f"  fuzzy type {doc['fuzzy']['type']} ({doc['fuzzy']['crossings']} crossings): {S}")
    write_output("\n".join(out) + "\n", args.output)
    return 0


def _is_mechanism_file(path) -> bool:
    if not str(path).lower().endswith(".json"):
        return False
    try:
        doc = read_json(path)
    except InputError:
        return False  # read_points says what is wrong with it
    return isinstance(doc, dict) and "joints" in doc


# -- atlas and match --------------------------------------------------------------------------


def run_atlas(args) -> int:
    from domes.io.atlas import atlas_path, load_atlas, save_atlas
    from domes.motion.coupler.atlas import SIZES, build, build_windows

    progress = progress_printer(args.progress)
    kind = "open" if args.open else "closed"
    where = args.file or atlas_path(args.size, kind)
    if args.action == "info":
        table = load_atlas(where)
        meta = table.meta
        what = "windows of curves" if meta.get("kind") == "open" else "curves"
        print(f"{where}: atlas {meta.get('name')}: {table.count:,} {what} of {len(table.linkages):,} four-bars × "
              f"coupler points every {meta.get('step')} over ±{meta.get('plane')}; built in "
              f"{meta.get('seconds', float('nan')):.1f} s")
        return 0
    if args.file:
        check_target(where)
    if args.size == "large":
        confirm("curves atlas build", "the large atlas takes a few minutes and a few hundred MB", args.yes)
    make = build_windows if args.open else build
    with executor(args.workers, args.scheduler, progress=progress) as run:        # its tasks said as they finish
        table = make(SIZES[args.size], progress, None if isinstance(run, InProcess) else run)
        ran_on = run.where
    if not args.file:
        atlas_path(args.size, kind).parent.mkdir(parents=True, exist_ok=True)
    save_atlas(table, where)
    print(f"{where}: {table.count:,} {'windows' if args.open else 'curves'} of {len(table.linkages):,} four-bars, "
          f"built in {table.meta['seconds']:.1f} s {ran_on}")
    return 0


def run_match(args) -> int:
    from domes.io.atlas import default_atlas, load_atlas
    from domes.io.curves import read_path
    from domes.io.mechanisms import save_mechanism
    from domes.motion.coupler.atlas import SIZES, Atlas, OpenAtlas
    from domes.motion.coupler.curves import trace
    from domes.motion.coupler.fit import check_wanted
    from domes.motion.coupler.freehand import CANDIDATES as DRAWN_CANDIDATES
    from domes.motion.coupler.match import CANDIDATES, kind_of, match
    from domes.sketch.curves import Card, curves_html, joint_names, moving_svg

    for path in (args.output, args.save):
        if path:
            check_target(path)
    progress = progress_printer(args.progress)
    wanted, closed = read_path(args.file)
    try:
        check_wanted(wanted)                # before the atlas, which may have to be built first
    except InputError as exc:
        raise InputError(f"{args.file}: {exc}") from None
    if args.six_bars != "no" and (args.drawn or args.open):
        raise InputError("--six-bars: six-bars are fitted to exact closed paths, not yet to open paths or paths "
                         "drawn by hand")
    sketch, timing = None, _timing(args)
    if args.drawn:
        from domes.motion.coupler.freehand import drawn, match_drawn

        said = False if args.open or closed is False else closed
        try:
            sketch = drawn(wanted, said)
        except InputError as exc:
            raise InputError(f"{args.file}: {exc}") from None
        closed = sketch.closed
    kind = "open" if args.open or closed is False else "closed"
    if args.atlas in SIZES:
        table = default_atlas(args.atlas, progress, kind)
    else:
        table = load_atlas(args.atlas)
    if table.meta.get("kind", "closed") != kind:
        raise InputError(f"{args.atlas}: an atlas of {table.meta.get('kind')} paths, but the path is {kind}")
    atlas = OpenAtlas(table) if kind == "open" else Atlas(table)
    six = None
    if args.six_bars != "no":
        from domes.io.sixatlas import default_sixatlas

        six = default_sixatlas()
    if sketch is not None:
        try:
            result = match_drawn(wanted, atlas, args.results, DRAWN_CANDIDATES if args.candidates is None else
                                 args.candidates, args.tol, said, progress=progress, timing=timing)
        except InputError as exc:
            raise InputError(f"{args.file}: {exc}") from None
    else:
        result = match(wanted, atlas, args.results, CANDIDATES if args.candidates is None else args.candidates,
                       args.tol, progress=progress, sixbars=args.six_bars, sixatlas=six)
    if args.save and result.fits and result.fits[0].mechanism is not None:
        save_mechanism(result.fits[0].mechanism, args.save)
    if args.format == "json":
        doc = {"message": result.message, "tried": result.tried, "lookup_ms": result.lookup_seconds * 1e3,
               "refine_s": result.refine_seconds, "size": result.size, "fits": [
                   {"success": f.success, "type": kind_of(f), "lengths": list(f.lengths), "coupler": list(f.coupler),
                    "before": {"max": f.before[0], "rms": f.before[1]}, "after": {"max": f.after[0], "rms": f.after[1]},
                    "mechanism": f.mechanism.to_dict() if f.mechanism else None, **_timed_doc(f),
                    "merged": [{"relation": why, "lengths": list(g.lengths), "coupler": list(g.coupler),
                                "after": {"max": g.after[0], "rms": g.after[1]}, "pivots": _pivots(g)}
                               for g, why in _merged(result, k)]} for k, f in enumerate(result.fits)]}
        write_output(json.dumps(doc, indent=1) + "\n", args.output)
    elif args.format == "html":
        cards = []
        for k, f in enumerate(result.fits, 1):
            if f.mechanism is None:
                continue
            curve = trace(f.mechanism, "P", 360, extra=joint_names(f.mechanism))
            circuit = min(curve.circuits, key=lambda c: _nearest(c.points, wanted))
            cards.append(Card(str(k), f"match {k}: {'fits' if f.success else 'nearest'}",
                              moving_svg(f.mechanism, circuit, wanted),
                              _fit_props(f) + tuple(("merged", _merged_text(g, why))
                                                    for g, why in _merged(result, k - 1))))
        write_output(curves_html(cards, "Linkages for a wanted path", result.message), args.output)
    else:
        out = [result.message]
        for k, f in enumerate(result.fits, 1):
            out.append(f"{k}. " + "; ".join(f"{name} {value}" for name, value in _fit_props(f)))
            out += [f"   merged: {_merged_text(g, why)}" for g, why in _merged(result, k - 1)]
        write_output("\n".join(out) + "\n", args.output)
    return 0 if result.success else 1


def _timing(args):
    """The timing of a drawn path's file (:func:`domes.io.curves.read_timing`) with ``--speed``, or None."""
    from domes.io.curves import read_timing
    from domes.motion.coupler.timing import Timing

    found = read_timing(args.file)
    if found is None:
        if args.speed is not None:
            raise InputError(f"--speed: {args.file} gives no times (a CSV column headed time, or a JSON \"times\" "
                             "list)")
        return None
    kind, values, speed = found
    if not args.drawn:
        raise InputError(f"{args.file}: the path gives the crank's {'angles' if kind == 'angle' else 'times'}; a "
                         "timing is fitted to a path drawn by hand: give --drawn")
    if args.speed is not None and kind != "time":
        raise InputError(f"--speed: {args.file} gives crank angles, not times")
    return Timing(tuple(values), kind, args.speed if args.speed is not None else speed)


def _timed_doc(f) -> dict:
    """A timed fit's crank angles, speed and distances from its curve, for the JSON answer (else nothing)."""
    if not hasattr(f, "angles"):
        return {}
    return {"timing": {"angles_deg": list(f.angles), "speed_deg_per_unit": f.speed,
                       "curve": {"max": f.curve[0], "rms": f.curve[1]}}}


def _merged(result, k: int):
    """The fits merged into fit ``k`` (from 0): ``(fit, relation)``."""
    return result.merged[k] if k < len(result.merged) else ()


def _pivots(f):
    if f.mechanism is None:
        return None
    return [list(f.mechanism.joint("A").at), list(f.mechanism.joint("D").at)]


def _merged_text(g, why: str) -> str:
    if hasattr(g, "ternary"):
        return f"{why}: {g.kind}, links " + ", ".join(f"{x:.6g}" for x in g.lengths) + f"; largest distance " \
            f"{g.after[0]:.3g}"
    a, b, c, d = g.lengths
    where = "" if g.mechanism is None else (" frame pivots A, D " + ", ".join(f"({x:.6g}, {y:.6g})"
                                                                             for x, y in _pivots(g)) + ";")
    return (f"{why}:{where} crank, coupler, rocker, frame {a:.6g}, {b:.6g}, {c:.6g}, {d:.6g}; largest distance "
            f"{g.after[0]:.3g}")


def _nearest(points, wanted):
    import numpy as np

    d = np.min(np.hypot(*(points[:, None, :] - wanted[None, :, :]).transpose(2, 0, 1)), axis=0)
    return float(np.max(d))


def _fit_props(f):
    if hasattr(f, "ternary"):
        return _six_props(f)
    a, b, c, d = f.lengths
    props = [("fits", "yes" if f.success else "no"), ("crank, coupler, rocker, frame", f"{a:.6g}, {b:.6g}, {c:.6g}, {d:.6g}"),
             ("coupler point (u, v)", f"{f.coupler[0]:.6g}, {f.coupler[1]:.6g}"),
             ("largest distance", f"{f.after[0]:.3g} (before refinement {f.before[0]:.3g})"),
             ("RMS distance", f"{f.after[1]:.3g}")]
    if f.mechanism is not None:
        A, D = f.mechanism.joint("A").at, f.mechanism.joint("D").at
        props.append(("frame pivots A, D", f"({A[0]:.6g}, {A[1]:.6g}), ({D[0]:.6g}, {D[1]:.6g})"))
    if hasattr(f, "angles"):
        props[3:5] = [("largest distance at the timing", f"{f.after[0]:.3g} (the start: {f.before[0]:.3g})"),
                      ("RMS distance at the timing", f"{f.after[1]:.3g}"),
                      ("crank angle at the first point", f"{f.angles[0]:.6g}°")]
        if f.speed is not None:
            props.append(("crank speed", f"{f.speed:.6g}° per unit of time"))
        props.append(("from the curve (anywhere on it)", f"largest {f.curve[0]:.3g}, RMS {f.curve[1]:.3g}"))
    return tuple(props)


def _six_props(f):
    """A fitted six-bar's lines: its type, links, joint E's and point P's places, errors and frame pivots."""
    props = [("fits", "yes" if f.success else "no"), ("type", f.kind),
             ("crank, coupler, rocker, frame, tracer, link", ", ".join(f"{x:.6g}" for x in f.lengths)),
             ("joint E on its link (p, q)", f"{f.ternary[0]:.6g}, {f.ternary[1]:.6g}"),
             ("point P on link E F (u, v)", f"{f.coupler[0]:.6g}, {f.coupler[1]:.6g}"),
             ("largest distance", f"{f.after[0]:.3g} (before refinement {f.before[0]:.3g})"),
             ("RMS distance", f"{f.after[1]:.3g}")]
    if f.mechanism is not None:
        props.append(("frame pivots A, D, G", ", ".join(f"({x:.6g}, {y:.6g})" for x, y in
                                                        (f.mechanism.joint(n).at for n in "ADG"))))
    return tuple(props)
