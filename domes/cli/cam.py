"""``domes cam``: a disc cam's profile from a follower's motion law, checked for pressure angle and undercut.

>>> from domes.cli import main
>>> main(["cam", "--segment", "cycloidal", "120", "20", "--segment", "dwell", "60",
...       "--segment", "3-4-5", "120", "-20", "--segment", "dwell", "60",
...       "--face", "roller", "--roller", "10", "--offset", "5", "--base-radius", "40"])  # doctest: +ELLIPSIS
# complete: translating roller follower, base radius 40; largest pressure angle 21.28° at θ = ...
segments: cycloidal 120° rise 20; dwell 60°; 3-4-5 polynomial 120° rise -20; dwell 60°
...
0
"""

from __future__ import annotations

import argparse
import math

from domes.cli.common import write_document
from domes.errors import InputError
from domes.io.files import read_text

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "cam": "a disc cam's profile from a follower motion law (dwell, rise, return), checked for pressure angle "
    "and undercut",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "cam",
        help=COMMANDS["cam"],
        description="Design a disc cam (issue 26; seed 000 §2.10 motion laws): the follower's displacement over "
        "one turn is given as segments (--segment LAW DEGREES [RISE]; laws: dwell, constant velocity, simple "
        "harmonic (cosine acceleration), cycloidal (sine acceleration), 3-4-5 polynomial) or a table (--table "
        "FILE of degrees, displacement). The profile is found by kinematic inversion; the pressure angle and the "
        "radius of curvature are reported, an undercut cam is refused. See docs/cams.md.",
    )
    p.add_argument("--segment", nargs="+", action="append", metavar="ARG", default=[],
                   help="LAW DEGREES [RISE]: one segment of the motion (repeat, in order; the degrees add up to "
                   "360). RISE is a length, or degrees for an oscillating follower")
    p.add_argument("--table", metavar="FILE",
                   help="the motion as a table: rows of cam angle (degrees, 0 to 360) and displacement")
    p.add_argument("--follower", choices=("translating", "oscillating"), default="translating",
                   help="translating (default) or oscillating")
    p.add_argument("--face", choices=("knife", "roller", "flat"), default="roller", help="default: roller")
    p.add_argument("--roller", type=float, default=None, help="the roller's radius (a roller face)")
    p.add_argument("--offset", type=float, default=0.0,
                   help="translating: the follower axis's offset from the cam's centre (default 0)")
    p.add_argument("--pivot", type=float, default=0.0, help="oscillating: the pivot's distance from the cam's centre")
    p.add_argument("--arm", type=float, default=0.0, help="oscillating knife or roller: the arm's length")
    p.add_argument("--face-offset", type=float, default=0.0,
                   help="oscillating flat face: its distance from the pivot towards the cam (default 0)")
    p.add_argument("--base-radius", type=float, default=None,
                   help="the base circle's radius (required, unless the cam is found from a --mechanism)")
    p.add_argument("--mechanism", metavar="FILE",
                   help="a cam in parallel (seed 002 Fig. 3-28): a two-input mechanism file (a crank on the frame, "
                   "then a follower sliding on it) whose --point must follow --path; the cam on the crank, its "
                   "follower's axis, offset and base radius come from the mechanism")
    p.add_argument("--path", metavar="FILE", help="with --mechanism: the path's points, rows of x, y (closed when the "
                   "last row repeats the first)")
    p.add_argument("--point", help="with --mechanism: the joint or point that must follow the path")
    p.add_argument("--direction", choices=("ccw", "cw"), default="ccw", help="the cam's turning (default ccw)")
    p.add_argument("--points", type=int, default=360, help="profile points per turn (default 360)")
    p.add_argument("--max-pressure", type=float, metavar="DEG", default=None,
                   help="pressure angle limit (default 30° translating, 45° oscillating)")
    p.add_argument("--format", choices=("text", "csv", "json"), default="text",
                   help="text (default), csv (a row per profile point) or json")
    p.set_defaults(func=run)


def _motion(args, oscillating: bool):
    import numpy as np

    from domes.model.laws import Motion, from_table, law_name, read_table

    scale = math.radians if oscillating else float
    if args.table and args.segment:
        raise InputError("give the motion as --segment ... or as --table FILE, not both")
    if args.table:
        xs, ss = read_table(read_text(args.table), args.table)
        if not xs or abs(xs[0]) > 1e-9 or abs(xs[-1] - 360) > 1e-9:
            raise InputError(f"--table {args.table}: the cam angle must run from 0 to 360 degrees")
        return from_table(np.radians(xs), [scale(v) for v in ss], periodic=True)
    if not args.segment:
        raise InputError("give the motion: --segment LAW DEGREES [RISE] (repeated) or --table FILE")
    segs = []
    for k, words in enumerate(args.segment, start=1):
        numbers = []
        for w in reversed(words):
            try:
                numbers.insert(0, float(w))
            except ValueError:
                break
        law = " ".join(words[:len(words) - len(numbers)])
        if not law or len(numbers) not in (1, 2):
            raise InputError(f"--segment {' '.join(words)!r} (segment {k}): expected LAW DEGREES [RISE], e.g. "
                             "'cycloidal 120 20' or 'dwell 60'")
        segs.append((law_name(law), numbers[0], scale(numbers[1]) if len(numbers) == 2 else 0.0))
    return Motion.cam(segs)


def _combination(args) -> int:
    import numpy as np

    from domes.design.combination import cam_for_path
    from domes.io.mechanisms import load_mechanism
    from domes.model.laws import read_table

    if args.segment or args.table or args.base_radius is not None:
        raise InputError("with --mechanism the motion and the base radius come from the path: leave out --segment, "
                         "--table and --base-radius")
    if not args.path or not args.point:
        raise InputError("--mechanism needs --path FILE (rows of x, y) and --point NAME")
    if args.face == "flat" or args.follower != "translating":
        raise InputError("a cam in parallel drives a translating knife or roller follower (the mechanism's slider)")
    xs, ys = read_table(read_text(args.path), args.path)
    combo = cam_for_path(load_mechanism(args.mechanism), np.c_[xs, ys], args.point,
                         roller=args.roller or 0.0 if args.face == "roller" else 0.0, samples=args.points,
                         max_pressure_deg=args.max_pressure)
    cam = combo.cam
    s = cam.motion.evaluate(cam.theta)
    doc = {
        "message": combo.message,
        "warnings": list(combo.warnings),
        "follower": {"kind": "translating", "face": cam.follower.face, "roller": cam.follower.roller,
                     "offset": cam.follower.offset},
        "base_radius": cam.base_radius,
        "stroke": float(np.ptp(combo.drive)),
        "path_error": combo.path_error,
        "turns": combo.turns,
        "covered": combo.covered,
        "max_pressure_deg": cam.max_pressure_angle_deg,
        "min_radius": cam.min_radius,
        "segments": [],
        "profile": _rows(cam, s, combo.profile, 1.0),
    }
    _write(doc, args.format)
    return 0


def run(args: argparse.Namespace) -> int:
    from domes.design.cam import Follower, design_cam

    if args.face == "roller" and args.roller is None:
        raise InputError("a roller follower needs --roller RADIUS (or choose --face knife or flat)")
    if args.mechanism:
        return _combination(args)
    if args.base_radius is None:
        raise InputError("give the cam's --base-radius (or a --mechanism, --path and --point to find it)")
    oscillating = args.follower == "oscillating"
    motion = _motion(args, oscillating)
    follower = Follower(args.follower, args.face, roller=args.roller or 0.0, offset=args.offset, pivot=args.pivot,
                        arm=args.arm, face_offset=args.face_offset)
    cam = design_cam(motion, follower, args.base_radius, 1 if args.direction == "ccw" else -1, args.points,
                     args.max_pressure)
    s = motion.evaluate(cam.theta)
    unit = math.degrees(1.0) if oscillating else 1.0
    doc = {
        "message": cam.message,
        "warnings": list(cam.warnings),
        "follower": {"kind": follower.kind, "face": follower.face, "roller": follower.roller,
                     "offset": follower.offset, "pivot": follower.pivot, "arm": follower.arm,
                     "face_offset": follower.face_offset},
        "base_radius": cam.base_radius,
        "direction": args.direction,
        "max_pressure_deg": cam.max_pressure_angle_deg,
        "min_radius": cam.min_radius,
        "segments": [{"law": g.law, "degrees": math.degrees(g.length), "rise": g.rise * unit}
                     for g in getattr(motion, "segments", ())],
        "profile": _rows(cam, s, cam.profile, unit),
    }
    _write(doc, args.format)
    return 0


KEYS = ["theta_deg", "s", "ds", "dds", "x", "y", "pressure_deg", "radius"]


def _rows(cam, s, profile, unit: float) -> list[dict]:
    """A row per profile point: the angle, the law (``s`` and its derivatives, times ``unit``), the point, the
    pressure angle and the radius of curvature."""
    return [{"theta_deg": float(math.degrees(t)), "s": float(v * unit), "ds": float(d1 * unit),
             "dds": float(d2 * unit), "x": float(p[0]), "y": float(p[1]), "pressure_deg": float(a), "radius": float(r)}
            for t, v, d1, d2, p, a, r in zip(cam.theta, s[0], s[1], s[2], profile, cam.pressure_deg, cam.radius)]


def _write(doc: dict, fmt: str) -> None:
    write_document(doc, fmt, html=None, rows=lambda d: [KEYS] + [[r[k] for k in KEYS] for r in d["profile"]],
                   text=_text)


def _text(out, doc) -> None:
    print(f"# {doc['message']}", file=out)
    if doc["segments"]:
        print("segments: " + "; ".join(f"{g['law']} {g['degrees']:g}°" + (f" rise {g['rise']:g}" if g["rise"] else "")
                                     for g in doc["segments"]), file=out)
    for w in doc["warnings"]:
        print(f"warning: {w}", file=out)
    rows = doc["profile"]
    step = max(1, len(rows) // 24)
    print(f"{'θ (°)':>8} {'s':>10} {'x':>10} {'y':>10} {'pressure°':>10} {'radius':>10}", file=out)
    for r in rows[::step]:
        print(f"{r['theta_deg']:8.1f} {r['s']:10.4f} {r['x']:10.4f} {r['y']:10.4f} {r['pressure_deg']:10.2f} "
              f"{r['radius']:10.4g}", file=out)
    print(f"({len(rows)} profile points; --format csv or json for all)", file=out)
