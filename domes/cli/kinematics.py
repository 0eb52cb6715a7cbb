"""``domes kinematics``: positions, velocities and accelerations of a mechanism file, with dead points.

>>> import os, tempfile
>>> from domes.cli import main
>>> from domes.io.mechanisms import save_mechanism
>>> from domes.motion.planar.examples import four_bar
>>> path = os.path.join(tempfile.mkdtemp(), "four-bar.json")
>>> save_mechanism(four_bar(), path)
>>> main(["kinematics", path, "--sweep", "0:90:45", "--outputs", "angle:rocker"])
# crank-rocker four-bar: 2 of 2 groups, 2 loop equations (driver, RRR); accuracy default; method assur
           input      angle:rocker          residual         condition
               0       78.46304097   ...
              45       71.70185915   ...
              90       86.21910579   ...
# status: complete; input A (deg) reached 0 .. 90; max residual ...
0
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys

from domes.cli.common import confirm, finite_json, progress_printer
from domes.errors import InputError

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "kinematics": "position, velocity and acceleration of a dimensioned mechanism (JSON file), with dead points",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.motion.planar.query import PRESETS

    p = sub.add_parser(
        "kinematics",
        help=COMMANDS["kinematics"],
        description="The kinematics backend: solves only the Assur groups the requested outputs depend on, "
        "sweeps the input with assembly-mode continuity, and reports every step's loop-closure residual and "
        "condition number and every dead (limit) or singular point. Angles in degrees unless --angles rad.",
    )
    p.add_argument("file", help="mechanism file (JSON; planar: docs/kinematics.md, spatial: docs/spatial.md)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--sweep", metavar="START:STOP[:STEP]",
                       help="sweep the input (degrees for an R input, length for a P input); STEP defaults to the "
                       "accuracy preset's resolution")
    where.add_argument("--at", type=float, metavar="VALUE", help="one input value (default: the drawn pose)")
    p.add_argument("--outputs", nargs="+", metavar="OUT",
                   help="angle:LINK, slide:JOINT, point:NAME (default: every link angle, slide and coupler point)")
    p.add_argument("--order", type=int, choices=(0, 1, 2), default=0, help="derivative order (0 positions, 1 velocities, 2 accelerations)")
    p.add_argument("--format", choices=("text", "csv", "json"), default="text")
    p.add_argument("--accuracy", choices=sorted(PRESETS), default="default", help="accuracy preset (default: default)")
    p.add_argument("--tol", type=float, help="override the preset's Newton tolerance")
    p.add_argument("--derivatives", type=float, metavar="BOUND",
                   help="override the largest error bound accepted for a velocity or acceleration (relative; "
                   "near a singular point derivatives beyond it are refused)")
    p.add_argument("--method", choices=("assur", "newton"), default="assur",
                   help="assur: closed-form dyads and per-group Newton (default); newton: the whole loop-closure model")
    p.add_argument("--input", dest="joint", metavar="JOINT", help="driven joint to sweep (default: the first input)")
    p.add_argument("--angles", choices=("deg", "rad"), default="deg", help="unit of angles in input and output")
    p.add_argument("--yes", "-y", action="store_true", help=f"sweep more than {LARGE_SWEEP:,} steps without asking")
    shown = p.add_mutually_exclusive_group()
    shown.add_argument("--progress", dest="progress", action="store_true", default=None, help="show progress on stderr")
    shown.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")
    p.set_defaults(func=run)


#: Sweeps of more steps than this run only when the user agrees (--yes).
LARGE_SWEEP = 100_000
#: Measured time of one step of a sweep (positions to accelerations, the examples; docs/benchmarks.md), for the
#: estimate: on arrays (drivers and dyads) and step by step (groups solved by Newton's method).
SECONDS_PER_STEP = {True: 3e-6, False: 2e-3}
#: Measured time to write one row of the table (text), for the estimate.
SECONDS_PER_ROW = 2e-5


def parse_sweep(text: str, scale) -> tuple[float, float, float | None]:
    parts = text.split(":")
    if len(parts) not in (2, 3):
        raise InputError(f"--sweep: expected START:STOP or START:STOP:STEP, got {text!r}")
    try:
        nums = [float(x) for x in parts]
    except ValueError:
        raise InputError(f"--sweep: {text!r} has a part that is not a number") from None
    if not all(math.isfinite(x) for x in nums):
        raise InputError(f"--sweep: {text!r}: START, STOP and STEP must be finite numbers")
    if len(nums) == 3 and nums[2] <= 0:
        raise InputError(f"--sweep: STEP must be > 0, got {parts[2]}")
    return scale(nums[0]), scale(nums[1]), scale(nums[2]) if len(nums) == 3 else None


def run(args: argparse.Namespace) -> int:
    from domes.io.mechanisms import is_spatial, load_mechanism
    from domes.motion.planar.kernel import vectorizable
    from domes.motion.planar.query import Kinematics, accuracy
    from domes.motion.planar.sweep import grid_size, run_sweep

    if is_spatial(args.file):
        from domes.cli.spatial import run_spatial

        return run_spatial(args)
    mech = load_mechanism(args.file)
    acc = accuracy(args.accuracy, tol=args.tol, derivatives=args.derivatives)
    kin = Kinematics(mech, args.outputs, args.order, args.method, acc)
    joint = args.joint or mech.inputs[0].joint
    angular = mech.joint(joint).kind == "R"
    deg = args.angles == "deg"
    to_in = math.radians if angular and deg else float
    from_in = math.degrees if angular and deg else float
    if args.sweep:
        start, stop, step = parse_sweep(args.sweep, to_in)
        unit = to_in(1.0)  # the file's units and degrees, as the user wrote them
        steps = grid_size(start / unit, stop / unit, (step or (acc.step if angular else acc.step * mech.size)) / unit)
        if steps > LARGE_SWEEP:
            each = SECONDS_PER_STEP[vectorizable(kin)] + SECONDS_PER_ROW
            confirm("kinematics", f"a sweep of {steps:,} steps takes about {max(steps * each / 60, 1):.0f} min "
                    f"(about {each * 1e6:.0f} µs a step, most of it writing the table)", args.yes)
    else:
        if args.at is not None and not math.isfinite(args.at):
            raise InputError(f"--at must be a finite number, got {args.at}")
        q = kin.drawn_inputs()[joint] if joint in kin.drawn_inputs() else None
        if q is None:
            raise InputError(f"--input: {joint!r} is not a driven joint of {mech.name}")
        start = stop = to_in(args.at) if args.at is not None else q
        step = 1.0
    sw = run_sweep(kin, start, stop, step, joint, progress=progress_printer(args.progress))
    turned = (f"# input {joint}: {sw.turns:+,} whole turns taken off the values asked for (a revolute joint's pose "
              f"repeats every turn)\n" if sw.turns else "")
    angle_cols = {c for c in sw.columns if c.startswith("angle:")}

    def shown(col, value):
        base = col.rstrip("'")
        return math.degrees(value) if deg and base in angle_cols else value

    table = {c: [shown(c, float(v)) for v in sw.column(c)] for c in sw.columns}
    rows = [{"input": from_in(float(q)), **{c: table[c][k] for c in sw.columns}, "residual": float(sw.residuals[k]),
             "condition": float(sw.conditions[k])} for k, q in enumerate(sw.inputs)]
    dead = [{"input": from_in(float(d.input)), "within": from_in(float(d.within)), "kind": d.kind,
             "group": d.group, "joints": list(d.joints), "message": d.message} for d in sw.dead_points + sw.passed]
    out = sys.stdout
    if args.format == "json":
        doc = {"mechanism": mech.name, "file": args.file, "input": joint, "angle_unit": args.angles,
               "order": args.order, "method": args.method,
               "accuracy": {"preset": acc.name, "tol": acc.tol, "step": acc.step, "locate": acc.locate,
                            "derivatives": acc.derivatives},
               "groups": [{"kind": g.kind, "links": list(g.links), "joints": list(g.joints), "equations": g.equations}
                          for g in kin.groups],
               "groups_solved": sw.groups_solved, "groups_total": sw.groups_total, "equations": sw.equations,
               "status": sw.status, "turns": sw.turns, "reachable": [from_in(x) for x in sw.reachable],
               "max_residual": sw.max_residual, "dead_points": dead, "steps": rows}
        json.dump(finite_json(doc), out, indent=1)
        out.write("\n")
    elif args.format == "csv":
        writer = csv.writer(out)
        header = ["input", *sw.columns, "residual", "condition"]
        writer.writerow(header)
        for r in rows:
            writer.writerow([repr(r[h]) for h in header])
        for d in dead:
            print(f"# {d['kind']} at input {d['input']:.12g}: {d['message']}", file=sys.stderr)
        sys.stderr.write(turned)
    else:
        unit = ("deg" if deg else "rad") if angular else "length"
        out.write(f"# {mech.name}: {len(kin.groups)} of {len(kin.structure.groups)} groups, {kin.equations} loop "
                  f"equations ({', '.join(g.kind for g in kin.groups)}); accuracy {acc.name}; method {args.method}\n")
        out.write(turned)
        header = ["input"] + list(sw.columns) + ["residual", "condition"]
        out.write("  ".join(f"{h:>16s}" for h in header) + "\n")
        for r in rows:
            out.write("  ".join(f"{r[h]:16.10g}" for h in header) + "\n")
        out.write(f"# status: {sw.status}; input {joint} ({unit}) reached {from_in(sw.reachable[0]):.10g} .. "
                  f"{from_in(sw.reachable[1]):.10g}; max residual {sw.max_residual:.2g}\n")
        for d in dead:
            out.write(f"# {d['kind']} at input {d['input']:.12g} (± {d['within']:.2g}): {d['message']}\n")
    return 0
