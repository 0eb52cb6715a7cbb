"""``domes kinematics`` on a spatial mechanism file: the sweep of the loop-closure solver, with its limits.

>>> from domes.cli import main
>>> main(["kinematics", "examples/spatial/rssr-seed001.json", "--sweep", "0:180:90", "--outputs", "angle:B0",
...       "--order", "2"])                                          # doctest: +ELLIPSIS
# RSSR of seed 001 ...: spatial, 4 links, joints R S S R, 1 idle spin; loop closure on rigid transforms
           input          angle:B0         angle:B0'        angle:B0''          residual         condition
               0                 0       -204.627784       2604.353614 ...
              90       5.690967298       271.3841085       2730.640769 ...
             180       65.38002267        204.627784      -7846.247895 ...
# status: complete; input A0 (deg) swept 0 .. 180; max residual ...
0
"""

from __future__ import annotations

import argparse
import json
import math
import sys

from domes.cli.common import finite_json, progress_printer
from domes.cli.kinematics import parse_sweep
from domes.errors import InputError


def run_spatial(args: argparse.Namespace) -> int:
    """The spatial branch of ``domes kinematics`` (same options; --method and --accuracy do not apply)."""
    from domes.io.mechanisms import load_spatial
    from domes.motion.spatial.sweep import spatial_sweep

    mech = load_spatial(args.file)
    if not mech.inputs:
        raise InputError(f"{args.file}: the mechanism has no input")
    joint = args.joint or mech.inputs[0].joint
    variable = next((i.variable for i in mech.inputs if i.joint == joint), None)
    if variable is None:
        raise InputError(f"--input: {joint!r} is not a driven joint of {mech.name}; inputs are "
                         f"{[i.joint for i in mech.inputs]}")
    angular = variable == "angle"
    deg = args.angles == "deg"
    to_in = math.radians if angular and deg else float
    from_in = math.degrees if angular and deg else float
    if args.sweep:
        start, stop, step = parse_sweep(args.sweep, to_in)
    else:
        if args.at is not None and not math.isfinite(args.at):
            raise InputError(f"--at must be a finite number, got {args.at}")
        start = stop = to_in(args.at) if args.at is not None else 0.0
        step = None
    sw = spatial_sweep(mech, start, stop, step, args.outputs, args.order, joint, progress_printer(args.progress))
    turned = (f"# input {joint}: {sw.turns:+,} whole turns taken off the values asked for (a revolute joint's pose "
              f"repeats every turn)\n" if sw.turns else "")
    columns = list(sw.table)

    def shown(col, value):
        return math.degrees(value) if deg and col.startswith("angle:") else value

    rows = [{"input": from_in(float(q)), **{c: shown(c, float(sw.table[c][k])) for c in columns},
             "residual": float(sw.residuals[k]), "condition": float(sw.conditions[k])} for k, q in enumerate(sw.inputs)]
    limit = None if sw.limit is None else {"input": from_in(sw.limit.input), "within": from_in(sw.limit.within),
                                           "kind": sw.limit.kind, "message": sw.limit.message}
    singular = [from_in(q) for q in sw.singular]
    out = sys.stdout
    if args.format == "json":
        doc = {"mechanism": mech.name, "file": args.file, "space": "spatial", "input": joint, "variable": variable,
               "angle_unit": args.angles, "order": args.order, "idle": mech.idle, "status": str(sw.status),
               "turns": sw.turns, "max_residual": float(max(sw.residuals)), "limit": limit, "singular": singular,
               "steps": rows}
        json.dump(finite_json(doc), out, indent=1)
        out.write("\n")
        return 0
    header = ["input", *columns, "residual", "condition"]
    if args.format == "csv":
        import csv

        writer = csv.writer(out)
        writer.writerow(header)
        for r in rows:
            writer.writerow([repr(r[h]) for h in header])
        if limit:
            print(f"# {limit['kind']} at input {limit['input']:.12g}: {limit['message']}", file=sys.stderr)
        for q in singular:
            print(f"# singular at input {q:.12g}: velocities not determined (NaN)", file=sys.stderr)
        sys.stderr.write(turned)
        return 0
    unit = ("deg" if deg else "rad") if angular else "length"
    out.write(f"# {mech.name}: spatial, {len(mech.links)} links, joints {' '.join(j.kind for j in mech.joints)}, "
              f"{mech.idle} idle spin{'s' if mech.idle != 1 else ''}; loop closure on rigid transforms\n")
    out.write(turned)
    out.write("  ".join(f"{h:>16s}" for h in header) + "\n")
    for r in rows:
        out.write("  ".join(f"{r[h]:16.10g}" for h in header) + "\n")
    out.write(f"# status: {sw.status}; input {joint} ({unit}) swept {from_in(sw.inputs[0]):.10g} .. "
              f"{from_in(sw.inputs[-1]):.10g}; max residual {max(sw.residuals):.2g}\n")
    for q in singular:
        out.write(f"# singular at input {q:.12g}: velocities not determined (NaN)\n")
    if limit:
        out.write(f"# {limit['kind']} at input {limit['input']:.12g}: {limit['message']}\n")
    return 0
