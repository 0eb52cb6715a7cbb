"""``domes dynamics``: driving forces, joint reactions and the power balance of a mechanism, or of the scriber.

>>> from domes.cli import main
>>> main(["dynamics", "examples/dynamics/slider-crank-engine.json", "--sweep", "0:180:90"])  # doctest: +ELLIPSIS
# single-cylinder engine (slider-crank with masses): inverse dynamics over input A (deg), 3 steps; ...
#   input (deg)           time        drive:A    input power          |F A|          |F B| ...
              0              0        0.09156       28.76442       2997.481       2997.449 ...
             90          0.005       -58.6791      -18434.58       1855.098       1862.327 ...
            180           0.01       -0.09156      -28.76442       3319.129         3319.1 ...
# A: peak torque -58.6791 at 90
# complete: ...; power balance within ... of the peak power 1.843e+04
0
"""

from __future__ import annotations

import argparse
import math
import sys

from domes.cli.common import progress_printer, write_document
from domes.cli.kinematics import parse_sweep
from domes.errors import InputError

#: The most steps of one sweep.
MAX_STEPS = 1_000_000


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "dynamics": "driving forces, joint reactions and the power balance of a mechanism with masses (or the scriber)",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.design.dynamics import PRESSURE_ANGLE
    from domes.design.scriber import EQUATIONS, KINETIC, MAX_POINTS
    from domes.motion.planar.query import PRESETS

    p = sub.add_parser(
        "dynamics",
        help=COMMANDS["dynamics"],
        description="Inverse dynamics. A mechanism file (with masses, loads, springs, gravity: docs/dynamics.md) "
        "is swept over its input at the input's speed: the driving force or torque of every input and the "
        "reaction of every joint at each step, with the power balance (input power + load power - dE/dt) as "
        "the measure of accuracy. A scriber task file (a 2-RPR of seed 003 and a contour of lines and arcs) "
        "gives the two actuator forces along the contour at constant speed, with the jumps at the junctions.",
    )
    p.add_argument("file", help="mechanism file or scriber task file (JSON)")
    p.add_argument("--sweep", metavar="START:STOP:STEP",
                   help="mechanism: the input's range (degrees for an R input; default 0:360:5, or the P input's "
                   "drawn value plus one tenth of the mechanism's size)")
    p.add_argument("--input", dest="joint", metavar="JOINT", help="mechanism: the input to sweep (default: the first)")
    p.add_argument("--speed", type=float,
                   help="mechanism: the input's speed (deg/s or length/s; default: the file's); scriber: the head's "
                   "speed (default: the file's)")
    p.add_argument("--acceleration", type=float, help="mechanism: the input's acceleration (default: the file's)")
    p.add_argument("--accuracy", choices=sorted(PRESETS), default="default", help="mechanism: the kinematics' preset")
    p.add_argument("--pressure-angle", type=float, default=math.degrees(PRESSURE_ANGLE), metavar="DEG",
                   help="mechanism: the gear pairs' pressure angle in degrees (default 20): the tooth force's "
                   "direction, from the common tangent of the pitch circles")
    p.add_argument("--points", type=int, help=f"scriber: sample points along the contour (default: the file's; at most "
                   f"{MAX_POINTS:,})")
    p.add_argument("--kinetic", choices=KINETIC, default="corrected",
                   help="scriber: corrected (rigid-body) kinetic energy, or the paper's eq. (11)+(13), which counts the "
                   "links' turning twice")
    p.add_argument("--equations", choices=EQUATIONS, default="corrected",
                   help="scriber: the Lagrange equations corrected, or as printed (they break the power balance)")
    p.add_argument("--format", choices=("text", "csv", "json", "html"), default="text",
                   help="text (default), csv (a row per step), json (everything), html (a page with the force curves)")
    shown = p.add_mutually_exclusive_group()
    shown.add_argument("--progress", dest="progress", action="store_true", default=None, help="show progress on stderr")
    shown.add_argument("--no-progress", dest="progress", action="store_false", help="never show progress")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from domes.io.mechanisms import is_scriber_task

    for name in ("speed", "acceleration"):
        value = getattr(args, name)
        if value is not None and not math.isfinite(value):
            raise InputError(f"--{name}: must be a finite number, got {value}")
    if is_scriber_task(args.file):
        doc = _scriber(args)
    else:
        doc = _mechanism(args)
    write_document(doc, args.format, html=_html, rows=_rows, text=_text)
    if doc["kind"] == "scriber" and doc["status"] == "stopped":   # the contour leaves the scriber's reach
        print(f"domes dynamics: stopped: {'; '.join(doc['problems'])}", file=sys.stderr)
        return 1
    return 0


def _html(doc: dict) -> str:
    from domes.sketch.dynamics import dynamics_html

    return dynamics_html(doc)


def _rows(doc: dict):
    names = list(doc["columns"])
    yield names
    yield from zip(*(doc["columns"][n] for n in names))


def _mechanism(args) -> dict:
    import numpy as np

    from domes.design.dynamics import inverse_dynamics
    from domes.io.mechanisms import load_mechanism

    for name in ("points",):
        if getattr(args, name) is not None:
            raise InputError(f"--{name} is for a scriber task file; {args.file} is a mechanism")
    if not 0.0 <= args.pressure_angle < 90.0:
        raise InputError(f"--pressure-angle: must be at least 0 and below 90 (degrees), got {args.pressure_angle}")
    mech = load_mechanism(args.file)
    if not mech.inputs:
        raise InputError(f"{args.file}: the mechanism has no input")
    joint = args.joint or mech.inputs[0].joint
    kind = mech.joint(joint).kind
    angular = kind == "R"
    scale = math.radians if angular else float
    if args.sweep:
        start, stop, step = parse_sweep(args.sweep, scale)
        if step is None:
            raise InputError("--sweep: give START:STOP:STEP")
    elif angular:
        start, stop, step = 0.0, 2 * math.pi, math.radians(5)
    else:
        s0 = mech.joint(joint).s0
        start, stop, step = s0, s0 + 0.1 * mech.size, 0.005 * mech.size
    count = abs(stop - start) / step + 1 if step > 0 else math.inf
    if not count <= MAX_STEPS:
        raise InputError(f"--sweep {args.sweep}: gives {count:.3g} steps; at most {MAX_STEPS:,}")
    dyn = inverse_dynamics(mech, start, stop, step, joint=joint,
                           speed=None if args.speed is None else scale(args.speed),
                           acceleration=None if args.acceleration is None else scale(args.acceleration),
                           accuracy=args.accuracy, progress=progress_printer(args.progress),
                           pressure_angle=math.radians(args.pressure_angle))
    x = np.degrees(dyn.inputs) if angular else dyn.inputs
    unit = "deg" if angular else "length"
    columns = {f"input ({unit})": x}
    if dyn.time is not None:
        columns["time"] = dyn.time
    for j, v in dyn.driving.items():
        columns[f"drive:{j}"] = v
    for j, v in dyn.reactions.items():
        columns[f"reaction:{j}.x"] = v[:, 0]
        columns[f"reaction:{j}.y"] = v[:, 1]
    for j, v in dyn.moments.items():
        columns[f"moment:{j}"] = v
    contacts = {}
    for p, v in dyn.contacts.items():
        columns[f"contact:{p}"] = v
        if p in dyn.contact_forces:
            columns[f"contact:{p}.x"] = dyn.contact_forces[p][:, 0]
            columns[f"contact:{p}.y"] = dyn.contact_forces[p][:, 1]
        gear = p in dyn.contact_forces
        follower = "" if gear else next(c for c in mech.cams if c.name == p).contact(mech).kind
        finite = np.isfinite(v)
        k = int(np.nanargmax(np.abs(v))) if finite.any() else None
        contacts[p] = {"kind": "tooth force" if gear else "torque" if follower == "oscillating" else "force",
                       "pair": "gear" if gear else f"cam ({follower} follower)",
                       "peak": math.nan if k is None else float(v[k]),
                       "at": math.nan if k is None else float(x[k])}
    columns.update({"kinetic energy": dyn.kinetic, "input power": dyn.input_power, "load power": dyn.load_power,
                    "dE/dt": dyn.kinetic_rate, "balance": dyn.balance, "balance/peak": dyn.relative_balance})
    drives = {}
    for j in dyn.driving:
        value, where = dyn.peak(j)
        drives[j] = {"kind": "torque" if mech.joint(j).kind == "R" else "force", "peak": value,
                     "at": math.degrees(where) if angular else where}
    return {"kind": "mechanism", "file": args.file, "name": mech.name, "message": dyn.message,
            "status": str(dyn.status), "x": f"input {joint} ({unit})", "drives": drives, "contacts": contacts,
            "pressure_angle_deg": args.pressure_angle if dyn.contact_forces else None,
            "max_imbalance": dyn.max_imbalance, "peak_power": dyn.peak_power,
            "columns": {k: np.asarray(v, float).tolist() for k, v in columns.items()},
            "reaction_sizes": {j: np.hypot(v[:, 0], v[:, 1]).tolist() for j, v in dyn.reactions.items()}}


def _scriber(args) -> dict:
    import numpy as np

    from domes.design.scriber import follow
    from domes.io.mechanisms import load_scriber_task

    for name in ("sweep", "joint", "acceleration"):
        if getattr(args, name) is not None:
            raise InputError(f"--{name if name != 'joint' else 'input'} is for a mechanism file; {args.file} is a "
                             "scriber task")
    task = load_scriber_task(args.file)
    speed = task.speed if args.speed is None else args.speed
    points = task.points if args.points is None else args.points
    run = follow(task.scriber, task.contour, speed, points, args.kinetic, args.equations)
    columns = {"s": run.s, "time": run.time, "segment": run.segment.astype(float), "x": run.P.real, "y": run.P.imag,
               "q1": run.q[0], "q2": run.q[1], "q1'": run.qd[0], "q2'": run.qd[1], "q1''": run.qdd[0],
               "q2''": run.qdd[1], "Q1": run.Q[:, 0], "Q2": run.Q[:, 1], "kinetic energy": run.energy,
               "input power": run.power, "dE/dt": run.energy_rate, "balance": run.balance}
    return {"kind": "scriber", "file": args.file, "name": task.name, "message": run.message, "status": str(run.status),
            "problems": list(run.problems),
            "x": "arc length s", "speed": speed, "kinetic": args.kinetic, "equations": args.equations,
            "max_imbalance": run.max_imbalance, "peak_power": run.peak_power, "work": run.work,
            "spreads": {k: list(v) for k, v in run.spreads().items()},
            "junctions": [{"index": j.index, "s": j.s, "corner_deg": math.degrees(j.corner), "jump_qdd": list(j.jump_qdd),
                           "jump_Q": list(j.jump_Q)} for j in run.junctions],
            "contour": task.contour.to_dict(), "scriber": task.scriber.to_dict(),
            "columns": {k: np.asarray(v, float).tolist() for k, v in columns.items()}}


def _text(out, doc) -> None:
    cols = doc["columns"]
    if doc["kind"] == "mechanism":
        names = [n for n in cols if n.startswith(("input", "time", "drive:"))]
        names += [f"contact:{p}" for p in doc["contacts"]]
        sizes = doc["reaction_sizes"]
        out.write(f"# {doc['name']}: inverse dynamics over {doc['x']}, "
                  f"{len(cols[names[0]])} steps; forces and torques in the file's units (SI: N, N·m)\n")
        header = names + [f"|F {j}|" for j in sizes] + ["balance/peak"]
        out.write("#" + " ".join(f"{h:>14s}" for h in header) + "\n")
        for k in range(len(cols[names[0]])):
            row = [cols[n][k] for n in names] + [sizes[j][k] for j in sizes] + [cols["balance/peak"][k]]
            out.write(" " + " ".join(f"{v:14.7g}" for v in row) + "\n")
        for j, d in doc["drives"].items():
            out.write(f"# {j}: peak {d['kind']} {d['peak']:.6g} at {d['at']:.6g}\n")
        for p, d in doc["contacts"].items():
            extra = f" (pressure angle {doc['pressure_angle_deg']:g}°)" if d["pair"] == "gear" else ""
            out.write(f"# {p}: {d['pair']} pair, peak {d['kind']} {d['peak']:.6g} at {d['at']:.6g}{extra}\n")
    else:
        names = ["s", "x", "y", "q1", "q2", "Q1", "Q2", "balance"]
        out.write(f"# {doc['name']}: 2-RPR scriber along its contour at {doc['speed']:g}/s, "
                  f"{len(cols['s'])} points ({doc['kinetic']} kinetic energy, {doc['equations']} equations)\n")
        out.write("#" + " ".join(f"{h:>14s}" for h in names) + "\n")
        for k in range(len(cols["s"])):
            out.write(" " + " ".join(f"{cols[n][k]:14.7g}" for n in names) + "\n")
        for j in doc["junctions"]:
            out.write(f"# junction {j['index']} at s = {j['s']:.6g}: corner {j['corner_deg']:.4g}°, "
                      f"jump of q'' ({j['jump_qdd'][0]:.6g}, {j['jump_qdd'][1]:.6g}), "
                      f"of Q ({j['jump_Q'][0]:.6g}, {j['jump_Q'][1]:.6g})\n")
        out.write(f"# work over the {'points done' if doc['status'] == 'stopped' else 'contour'} {doc['work']:.4g}\n")
    out.write(f"# {doc['message']}\n")
