"""``domes tolerance``: how far a mechanism's output wanders when it is made to tolerances.

>>> import os, tempfile
>>> from domes.cli import main
>>> from domes.io.mechanisms import save_mechanism
>>> from domes.motion.planar.examples import four_bar
>>> path = os.path.join(tempfile.mkdtemp(), "four-bar.json")
>>> save_mechanism(four_bar(), path)
>>> main(["tolerance", path, "--output", "angle:rocker", "--sweep", "0:90:90", "--relative", "1e-4",
...       "--samples", "20000"])    # doctest: +ELLIPSIS
# crank-rocker four-bar: angle:rocker (deg) at 2 input values of A (deg); 7 dimensions, normal (σ = tolerance/3)
#   dimension                  unit      nominal  ± tolerance   share  max |dy/dd| (unit)
    coupler:B-C          file units          3.5      0.00035 ...
...
#   its σ over first order's: ...: the first-order estimate is enough (within 5% of Monte Carlo)
0

Joint clearances (:mod:`domes.design.clearance`), alone or with the tolerances:

>>> main(["tolerance", path, "--output", "angle:rocker", "--sweep", "0:90:90", "--clearance-all", "1e-3",
...       "--samples", "20000"])    # doctest: +ELLIPSIS
# crank-rocker four-bar: angle:rocker (deg) at 2 input values of A (deg); 7 dimensions, 4 clearances (contact ...
...
    clearance:B          file units            0        0.001 ...
...
#   its σ over first order's: ...: the first-order estimate is enough (within 5% of Monte Carlo)
0
"""

from __future__ import annotations

import argparse
import math

from domes.cli.common import parallel_options, progress_printer, write_document
from domes.cli.kinematics import parse_sweep
from domes.errors import InputError
from domes.execution import InProcess, executor

#: Monte Carlo and first order agree when their standard deviations are this close (the issue's 5%).
AGREE = 0.05
#: What the table says after a row where first order is not valid, by the reason's key.
SHORT = {"singular": "dead point (singular)", "reach": "the tolerances reach a dead point",
         "unmade": "a link cannot be made", "nonlinear": "not linear over the tolerances"}


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "tolerance": "output error of a mechanism made to tolerances: first order and Monte Carlo, dimensions ranked",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.design.tolerance import DISTRIBUTIONS

    p = sub.add_parser(
        "tolerance",
        help=COMMANDS["tolerance"],
        description="Tolerance sensitivity (the redesign step): the error of one output over the input's range "
        "caused by tolerances on the link lengths, pivot positions and slide lines; by first order (derivatives, "
        "worst case and standard deviation) and by Monte Carlo (seeded batches, on --workers), compared; the "
        "dimensions ranked by their share; with --allocate, tolerances that keep a wanted accuracy.",
    )
    p.add_argument("file", help="mechanism file (JSON; see docs/kinematics.md)")
    p.add_argument("--output", required=True, metavar="OUT", help="angle:LINK, slide:JOINT or point:NAME")
    p.add_argument("--sweep", default="0:360:10", metavar="START:STOP:STEP",
                   help="input values (degrees for an R input; default 0:360:10, the stop left out when it is a "
                   "full turn)")
    band = p.add_mutually_exclusive_group()
    band.add_argument("--tolerance", type=float, metavar="T",
                      help="± T on every length and position (file units); one of --tolerance, --relative or a "
                      "clearance is required")
    band.add_argument("--relative", type=float, metavar="R",
                      help="± R times each link length (positions: times the mechanism's size)")
    p.add_argument("--set", action="append", default=[], metavar="NAME=T",
                   help="the tolerance of one dimension (names as listed; angles in degrees), repeatable")
    p.add_argument("--clearance", action="append", default=[], metavar="JOINT=C",
                   help="the clearance of one joint (file units; over --clearance-all), repeatable: a revolute joint's "
                   "radial clearance, or a slide's lateral play (half the guide's width less the block's)")
    p.add_argument("--clearance-all", type=float, metavar="C",
                   help="the clearance of every revolute joint and slide on the frame (file units): the pin rests on "
                   "its hole's wall in a random direction, the block shifted and tilted in its guide with a corner on "
                   "a wall (contact mode); its effect is added to the tolerances'")
    p.add_argument("--block", action="append", default=[], metavar="JOINT=L",
                   help="the length of a slide's block (file units), repeatable: needed where its tilt moves its pin "
                   "(the pin away from the slide point) or the output")
    p.add_argument("--distribution", choices=DISTRIBUTIONS, default="normal",
                   help="normal: σ = T/3 (default); uniform: anywhere within ± T")
    p.add_argument("--samples", type=int, default=100_000, help="Monte Carlo samples (default 100000; 0: first order only)")
    p.add_argument("--seed", type=int, default=0, help="Monte Carlo seed (default 0): the same seed, the same numbers")
    p.add_argument("--spec", type=float, metavar="ERROR",
                   help="count the Monte Carlo samples whose output is off by more than ± ERROR at some input "
                   "(degrees for an angle; a point: by that distance) as out of spec")
    p.add_argument("--allocate", type=float, metavar="ACCURACY",
                   help="suggest tolerances that keep the output's 3σ (uniform: worst case) within ACCURACY "
                   "(degrees for an angle)")
    p.add_argument("--scan", action="store_true",
                   help="compare first order and Monte Carlo with the tolerances (and clearances) 1, 10, 100 and 1000 times "
                   "as large")
    p.add_argument("--format", choices=("text", "csv", "json", "html"), default="text",
                   help="text (default), csv (a row per input), json (everything), or an html page with plots")
    parallel_options(p, "run the Monte Carlo batches")
    shown = p.add_mutually_exclusive_group()
    shown.add_argument("--progress", dest="progress", action="store_true", default=None, help="show progress on stderr")
    shown.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")
    p.set_defaults(func=run)


def _overrides(items: list[str], option: str = "--set", example: str = "NAME=TOLERANCE (e.g. crank:A-B=0.001)") -> dict:
    out = {}
    for item in items:
        name, sep, value = item.rpartition("=")
        try:
            out[name] = float(value)
        except ValueError:
            name = ""
        if not sep or not name:
            raise InputError(f"{option}: expected {example}, got {item!r}")
    return out


def run(args: argparse.Namespace) -> int:
    import numpy as np

    from domes.design import clearance as play
    from domes.design.tolerance import MAX_INPUTS, Tolerancing, compare, monte_carlo, sensitivity
    from domes.io.mechanisms import load_mechanism

    mech = load_mechanism(args.file)
    if args.samples < 0:
        raise InputError(f"--samples must be >= 0, got {args.samples}")
    if args.seed < 0:
        raise InputError(f"--seed must be >= 0, got {args.seed}")
    joint = mech.inputs[0].joint if mech.inputs else None
    if joint is None:
        raise InputError(f"{args.file}: the mechanism has no input")
    angular = mech.joint(joint).kind == "R"
    start, stop, step = parse_sweep(args.sweep, math.radians if angular else float)
    if step is None:
        raise InputError("--sweep: give START:STOP:STEP")
    count = int(math.floor((stop - start) / step + 1e-9)) + 1 if stop >= start else 0
    if not 1 <= count <= MAX_INPUTS:
        raise InputError(f"--sweep {args.sweep}: gives {count:,} input values; give START <= STOP and at most "
                         f"{MAX_INPUTS:,} values")
    inputs = start + step * np.arange(count)
    if angular and math.isclose(stop - start, 2 * math.pi) and count > 1:
        inputs = inputs[:-1]                                   # a full turn: 360 is 0 again
    overrides = _overrides(args.set)
    played = _overrides(args.clearance, "--clearance", "JOINT=CLEARANCE (e.g. B=0.001)")
    if args.tolerance is None and args.relative is None:
        if not played and args.clearance_all is None:
            raise InputError("give the tolerances (--tolerance T or --relative R), the clearances (--clearance JOINT=C "
                             "or --clearance-all C), or both")
        args.tolerance = 0.0                                   # clearances only
    tol = Tolerancing(mech, args.output, inputs, tolerance=args.tolerance, relative=args.relative)
    if overrides:                                              # angles are given in degrees, as shown
        kinds = {d.name: d.kind for d in tol.dimensions}
        overrides = {k: math.radians(v) if kinds.get(k) == "angle" else v for k, v in overrides.items()}
        tol = Tolerancing(mech, args.output, inputs, tolerance=args.tolerance, relative=args.relative,
                          tolerances=overrides)
    blocks = _overrides(args.block, "--block", "JOINT=LENGTH (e.g. S=0.4)")
    cl = (play.Clearances(tol, played, args.clearance_all, blocks=blocks) if played or args.clearance_all is not None
          else None)
    if blocks and cl is None:
        raise InputError("--block: give the slide a clearance too (--clearance JOINT=C or --clearance-all C)")
    if cl is not None and not len(cl):
        cl = None                                              # every clearance 0: tolerances only
    if cl is None and not np.any(tol.bands > 0):
        raise InputError("nothing varies: every tolerance is 0 and no joint has a clearance; give --tolerance T, "
                         "--relative R, --clearance JOINT=C or --clearance-all C")
    first = sensitivity(tol, args.distribution)
    total = play.budget(cl, args.distribution, first) if cl is not None else None
    scale = math.degrees(1.0) if args.output.startswith("angle:") else 1.0
    allocated = None
    if args.allocate is not None:
        accuracy = args.allocate / scale
        if total is not None and math.isfinite(accuracy) and accuracy > 0:   # the clearances' part first (worst input)
            taken = (np.nanmax(total.clearance_worst) if args.distribution == "uniform"
                     else 3 * np.nanmax(total.clearance_std))
            if not accuracy > taken:
                raise InputError(f"--allocate {args.allocate:g}: the clearances alone take {taken * scale:.4g} "
                                 f"({'worst case' if args.distribution == 'uniform' else '3σ'}); ask for more or give "
                                 "smaller clearances")
            accuracy = accuracy - taken if args.distribution == "uniform" else math.sqrt(accuracy ** 2 - taken ** 2)
        allocated = first.allocate(accuracy)
    if args.spec is not None and not (math.isfinite(args.spec) and args.spec > 0):
        raise InputError(f"--spec must be a positive number (the largest error accepted), got {args.spec}")
    mc = scan = None
    with executor(args.workers, args.scheduler) as run_on:
        where = None if isinstance(run_on, InProcess) else run_on
        if args.samples >= 2:
            sample = play.monte_carlo if cl is not None else monte_carlo      # with the clearances, or without
            mc = sample(tol if cl is None else cl, args.samples, args.seed, args.distribution, executor=where,
                        progress=progress_printer(args.progress), spec=None if args.spec is None else args.spec / scale)
        if args.scan:
            scales = play.compare if cl is not None else compare
            scan = scales(tol if cl is None else cl, (1.0, 10.0, 100.0, 1000.0), min(args.samples, 20_000) or 20_000,
                          args.seed, args.distribution, executor=where)
    doc = _document(args, tol, first, mc, scan, allocated, scale, joint, angular, total)
    write_document(doc, args.format, html=_html, rows=_rows, text=_text)
    return 0


def _html(doc: dict) -> str:
    from domes.sketch.tolerance import tolerance_html

    return tolerance_html(doc)


def _rows(doc: dict):
    header = list(doc["inputs"][0])
    yield header
    for row in doc["inputs"]:
        yield [row[h] for h in header]


def _document(args, tol, first, mc, scan, allocated, scale, joint, angular, total=None) -> dict:
    import numpy as np

    from domes.design import clearance as play
    from domes.design.tolerance import REASONS, largest

    unit = "deg" if scale != 1.0 else "length"
    dims = []
    slope = largest(np.abs(first.gradient), axis=(0, 1))
    share = first.share if total is None else total.share
    for k, d in enumerate(tol.dimensions):
        row = {"name": d.name, "kind": d.kind, "nominal": d.nominal if d.kind != "angle" else math.degrees(d.nominal),
               "tolerance": d.tolerance if d.kind != "angle" else math.degrees(d.tolerance),
               "share": float(share[k]),
               "largest_derivative": float(slope[k] * scale * (math.radians(1.0) if d.kind == "angle" else 1.0))}
        if allocated is not None:
            row["allocated"] = float(allocated[k]) if d.kind != "angle" else math.degrees(allocated[k])
        dims.append(row)
    if total is not None:                                      # each clearance beside the dimensions
        for k, c in enumerate(total.clearances):
            row = {"name": play.PREFIX + c.joint, "kind": "clearance", "nominal": 0.0, "tolerance": c.clearance,
                   "share": float(share[len(tol.dimensions) + k]),
                   "largest_derivative": float(total.largest[k] * scale), "carrier": c.carrier}
            if allocated is not None:
                row["allocated"] = None
            dims.append(row)
    dims.sort(key=lambda r: -r["share"])
    worst, std = (first.worst, first.std) if total is None else (total.worst, total.std)
    rows = []
    for c, col in enumerate(tol.columns):
        for n, q in enumerate(tol.inputs):
            row = {"column": col, "input": math.degrees(q) if angular else float(q),
                   "nominal": float(first.nominal[c, n] * scale), "worst_case": float(worst[c, n] * scale),
                   "three_sigma_first_order": float(3 * std[c, n] * scale),
                   "three_sigma_second_order": float(3 * first.second[c, n] * scale),
                   "first_order_valid": not first.notes[n], "first_order_note": first.notes[n]}
            if total is not None:                              # the budget's parts; second order: tolerances only
                row.update({"worst_case_tolerances": float(first.worst[c, n] * scale),
                            "worst_case_clearances": float(total.clearance_worst[c, n] * scale),
                            "three_sigma_tolerances": float(3 * first.std[c, n] * scale),
                            "three_sigma_clearances": float(3 * total.clearance_std[c, n] * scale),
                            "three_sigma_second_order": float(3 * math.hypot(first.second[c, n],
                                                                             total.clearance_std[c, n]) * scale)})
            if mc is not None:
                row.update({"three_sigma_monte_carlo": float(3 * mc.std[c, n] * scale),
                            "three_sigma_monte_carlo_error": float(3 * mc.std_error[c, n] * scale),
                            "largest_monte_carlo": float(mc.largest[c, n] * scale),
                            "mean_monte_carlo": float(mc.mean[c, n] * scale)})
            rows.append(row)
    doc = {"mechanism": tol.mech.name, "file": args.file, "output": tol.output, "unit": unit, "input": joint,
           "input_unit": "deg" if angular else "length", "distribution": args.distribution,
           "dimensions": dims, "inputs": rows, "first_order": first.message if total is None else total.message,
           "first_order_valid": bool(first.valid.all()), "first_order_not_valid": first.not_valid,
           "ignored": list(tol.ignored)}
    if total is not None:
        doc["clearances"] = {"model": play.MODEL, "joints": [{"joint": c.joint, "kind": c.kind, "clearance": c.clearance,
                                                             "carrier": c.carrier, "block": c.block}
                                                            for c in total.clearances]}
    if mc is not None:
        with np.errstate(invalid="ignore", divide="ignore"):    # no spread at all: no ratio
            ratio = mc.std / std
        ok = np.isfinite(ratio)
        within = bool(ok.any() and np.all(np.abs(ratio[ok] - 1) <= AGREE))
        doc["monte_carlo"] = {"samples": mc.samples, "seed": mc.seed, "batches": mc.batches, "failed": mc.failed,
                              "failures": {k: mc.failures[k] for k in REASONS},
                              "spec": None if mc.spec is None else mc.spec * scale,
                              "failure_fraction": mc.fraction, "failure_fraction_error": mc.fraction_error,
                              "std_relative_error": mc.relative_error, "trusted": mc.trusted, "trust": mc.trust,
                              "ratio_min": float(np.min(ratio[ok])) if ok.any() else None,
                              "ratio_max": float(np.max(ratio[ok])) if ok.any() else None,
                              "agree": bool(within and mc.trusted and first.valid.all()),
                              "verdict": _verdict(first, mc, within), "message": mc.message}
    if scan is not None:
        doc["scan"] = [{"scale": s.scale, "first_order_std": s.first_order * scale, "monte_carlo_std": s.monte_carlo * scale,
                        "ratio": s.ratio, "failed": s.failed, "first_order_valid": s.valid,
                        "monte_carlo_trusted": s.trusted, "agree": s.agree} for s in scan]
    if allocated is not None:
        doc["allocate"] = {"accuracy": args.allocate,
                           "meaning": "3 sigma" if args.distribution == "normal" else "worst case"}
    return doc


def _verdict(first, mc, within: bool) -> str:
    """Which estimate to trust: a recommendation only when Monte Carlo can carry one."""
    if not mc.trusted:
        return (f"no recommendation: Monte Carlo cannot say ({mc.trust})"
                + (f"; {first.not_valid}" if first.not_valid else ""))
    if first.not_valid:
        return f"{first.not_valid}: trust Monte Carlo"
    if within:
        return f"the first-order estimate is enough (within {100 * AGREE:g}% of Monte Carlo)"
    return f"first order and Monte Carlo differ by more than {100 * AGREE:g}%: trust Monte Carlo"


#: The unit of a number as the text shows it: angles in degrees, lengths in the mechanism file's unit.
LABEL = {"deg": "deg", "length": "file units"}


def _short(value) -> str:
    """A number of four digits, or ``n/a`` where there is none (no derivative at any input)."""
    return f"{value:12.4g}" if value is not None and math.isfinite(value) else f"{'n/a':>12s}"


def _cell(value, word: str) -> str:
    """A number of the table, or a word where there is none (a singular first order, no sample assembled)."""
    return f"{value:12.6g}" if value is not None and math.isfinite(value) else f"{word:>12s}"


def _text(out, doc) -> None:
    unit, of_input = LABEL[doc["unit"]], LABEL[doc["input_unit"]]
    rows = doc["inputs"]
    played = sum(d["kind"] == "clearance" for d in doc["dimensions"])
    out.write(f"# {doc['mechanism']}: {doc['output']} ({unit}) at {len({r['input'] for r in rows})} input values of "
              f"{doc['input']} ({of_input}); {len(doc['dimensions']) - played} dimensions, "
              + (f"{played} clearances (contact mode: |e| = clearance, any direction; a block: |u| + |w| = "
                 "clearance), " if played else "")
              + f"{doc['distribution']} ({'σ = tolerance/3' if doc['distribution'] == 'normal' else 'within ± tolerance'})\n")
    alloc = "allocate" in doc
    out.write((f"#   {'dimension':<20s} {'unit':>10s} {'nominal':>12s} {'± tolerance':>12s} {'share':>7s} "
               f"{'max |dy/dd|':>12s} {'(unit)':<9s}" + (f" {'suggested ±':>12s}" if alloc else "")).rstrip() + "\n")
    for d in doc["dimensions"]:
        own = LABEL["deg" if d["kind"] == "angle" else "length"]
        slope = "/".join("deg" if u == "deg" else "unit" for u in (unit, own))   # unit: the file's length unit
        out.write((f"    {d['name']:<20s} {own:>10s} {d['nominal']:12.6g} {d['tolerance']:12.4g} "
                   f"{100 * d['share']:6.1f}% {_short(d['largest_derivative'])} {slope:<9s}"
                   + (f" {_short(d['allocated'])}" if alloc else "")).rstrip() + "\n")
    mc = "monte_carlo" in doc
    header = ["input", "nominal", "worst case", "3σ first", *(["3σ Monte C.", "largest MC"] if mc else [])]
    columns = len({r['column'] for r in rows}) > 1
    out.write("#" + " ".join(f"{h:>12s}" for h in header) + ("   column" if columns else "") + "\n")
    out.write("#" + " ".join(f"{u:>12s}" for u in [of_input] + [unit] * (len(header) - 1)) + "\n")
    for r in rows:
        word = "singular" if r["first_order_note"] == "singular" else "n/a"
        cells = [_cell(r["input"], ""), _cell(r["nominal"], ""), _cell(r["worst_case"], word),
                 _cell(r["three_sigma_first_order"], word)]
        if mc:
            cells += [_cell(r["three_sigma_monte_carlo"], "none"), _cell(r["largest_monte_carlo"], "none")]
        note = f"   <- first order not valid: {SHORT[r['first_order_note']]}" if r["first_order_note"] else ""
        out.write(" " + " ".join(cells) + (f"   {r['column']}" if columns else "") + note + "\n")
    out.write(f"# first order: {doc['first_order']}\n")
    if "clearances" in doc:
        carried = ", ".join(f"{c['joint']} on {c['carrier']}" if c.get("kind", "R") == "R" else
                            f"{c['joint']} the block {c['carrier']}"
                            + (f" ({c['block']:g} long)" if c.get("block") is not None else " (centred on its pin)")
                            for c in doc["clearances"]["joints"])
        out.write(f"#   clearances (each offset carried by a link: {carried}) add to the tolerances: worst cases "
                  "sum, σ root-sum-square; worst case and 3σ first above are the two together\n")
    if doc["ignored"]:
        out.write(f"#   {', '.join(doc['ignored'])}: not needed for {doc['output']}, not solved (cannot make a sample "
                  "fail)\n")
    if mc:
        m = doc["monte_carlo"]
        out.write(f"# Monte Carlo: {m['message']}\n")
        if m["ratio_min"] is None:
            out.write("#   its σ over first order's: not defined (no input where both are finite and first order's is "
                      f"not zero){'' if m['trusted'] and doc['first_order_valid'] else '; ' + m['verdict']}\n")
        else:
            out.write(f"#   its σ over first order's: {m['ratio_min']:.4f} .. {m['ratio_max']:.4f}: {m['verdict']}\n")
    if "scan" in doc:
        if "clearances" in doc:
            out.write("# tolerances and clearances scaled together:\n")
        out.write(f"# tolerances scaled: {'scale':>6s} {'σ first':>12s} {'σ Monte C.':>12s} {'ratio':>8s} {'failed':>7s}\n")
        out.write(f"#                    {'×':>6s} {unit:>12s} {unit:>12s} {'×':>8s} {'samples':>7s}\n")
        for s in doc["scan"]:
            ratio = f"{s['ratio']:8.4f}" if s["ratio"] is not None and math.isfinite(s["ratio"]) else f"{'-':>8s}"
            why = ([] if s["first_order_valid"] else ["first order not valid"]) + \
                  ([] if s["monte_carlo_trusted"] else ["Monte Carlo not trusted"])
            spreads = " ".join(f"{v:12.4g}" if v is not None and math.isfinite(v) else f"{'n/a':>12s}"
                               for v in (s["first_order_std"], s["monte_carlo_std"]))
            parted = not (s["ratio"] is not None and abs(s["ratio"] - 1) <= AGREE)
            mark = "" if s["agree"] else "  <- they part" if parted else "  <- no verdict"
            out.write(f"#                    {s['scale']:6g} {spreads} {ratio} {s['failed']:7d}{mark}"
                      + (f" ({', '.join(why)})" if why else "") + "\n")
    if alloc:
        out.write(f"# suggested tolerances keep the {doc['allocate']['meaning']} within {doc['allocate']['accuracy']:g} "
                  f"{unit}, each dimension taking an equal part at its worst input"
                  + (" of what the clearances leave" if "clearances" in doc else "") + "\n")
