"""The two path-synthesis routes on planted four-bars: ``domes synthesize`` (a path task) and ``domes curves match``.

Run ``python benchmarks/bench_path_routes.py`` (``--arcs`` adds the open
arcs; ``--atlas small|quick|none`` chooses the path task's atlas look-up;
``--method``, ``--seeds``, ``--count``, ``--points``). Random four-bars
drawn from seeded numbers give twelve points of their own coupler curve on
one assembly mode: *closed*, crank-rockers, double cranks and rocker-cranks
(the points spread over a full turn of the link that turns: at a0, or at b0
for the rocker-crank); *arcs*, double rockers and triple rockers (the
points over the swing of the link at a0). A four-bar traces each exactly.
Each path goes to the path task with nothing given, with the crank pivot
``a0`` given, and with ``a0`` and ``"driver": "crank"``, and (closed ones)
to ``curves match`` with the small atlas. Per route the script counts runs
that raise (a traceback), runs with no answer, runs whose first answer's
coupler curve, traced by the kinematics kernel, passes every point within
1e-8 of the size (recovered), first answers driven by a link that only
rocks, and those of them that do not say so.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from domes.design.synthesis import synthesize, task_from_dict  # noqa: E402
from domes.design.synthesis.fourbars import FourBar, grashof_class  # noqa: E402
from domes.design.synthesis.verify import curve_distances  # noqa: E402
from domes.io.atlas import default_atlas  # noqa: E402
from domes.motion.coupler.atlas import Atlas  # noqa: E402
from domes.motion.coupler.match import match  # noqa: E402

#: Kinds of planted four-bar whose points go round a closed curve (the driving link turns fully: the one at a0,
#: or for a rocker-crank the one at b0), cycled through.
CLOSED = ("crank-rocker", "double crank", "rocker-crank")
#: Kinds whose points lie on an arc: the link at a0 swings between its limits on one assembly mode.
ARCS = ("double rocker", "triple rocker")

#: An answer recovers the planted path when every point is this near its coupler curve (relative to the size).
EXACT = 1e-8


def _lengths(rng, kind):
    """Crank ``a``, coupler ``b``, rocker ``c``, frame ``d`` of a four-bar of ``kind`` (rejection sampling)."""
    while True:
        a, b, c, d = rng.uniform(0.4, 3.0, 4)
        name, turns = grashof_class(a, b, c, d)
        s, l = min(a, b, c, d), max(a, b, c, d)
        if s + l > 0.97 * (a + b + c + d - s - l) and s + l < 1.03 * (a + b + c + d - s - l):
            continue                                    # keep off the change point
        if {"crank-rocker": "crank-rocker" in name, "double crank": "double crank" in name,
                "rocker-crank": "rocker-crank" in name, "double rocker": "double rocker" in name,
                "triple rocker": "triple rocker" in name}[kind] and max(a, b, c, d) < 4 * min(a, b, c, d):
            return a, b, c, d


def _driver_range(a, b, c, d):
    """The angles of the link at a0 (from the frame's direction) where the loop closes: ``(lo, hi)``."""
    lo = (a * a + d * d - (b + c) ** 2) / (2 * a * d)
    hi = (a * a + d * d - (b - c) ** 2) / (2 * a * d)
    if lo <= -1 and hi >= 1:
        return 0.0, 2 * math.pi
    if hi >= 1:                                         # |φ| <= acos(lo): around the frame's direction
        w = math.acos(lo)
        return -w, w
    if lo <= -1:                                        # |φ| >= acos(hi): around the opposite direction
        w = math.acos(hi)
        return w, 2 * math.pi - w
    return math.acos(hi), math.acos(lo)                 # two ranges: the one above the frame


def planted(rng, kind, n):
    """A four-bar of ``kind`` placed at random and ``n`` points of its coupler curve on one assembly mode:
    ``(points, FourBar)``, the linkage drawn at the first point."""
    a, b, c, d = _lengths(rng, kind)
    a0 = rng.uniform(-1, 1, 2)
    frame = rng.uniform(-math.pi, math.pi)
    b0 = a0 + d * np.array([math.cos(frame), math.sin(frame)])
    u, v = rng.uniform(-1.5, 1.5, 2) * (a + b + c + d) / 4
    sign = rng.choice([-1.0, 1.0])
    start = rng.uniform(0, 2 * math.pi)
    pts, first = [], None
    if kind == "rocker-crank":                          # the link at b0 turns fully: the points go round with it
        for phi in start + np.linspace(0, 2 * math.pi, n, endpoint=False):
            B = b0 + c * np.array([math.cos(phi), math.sin(phi)])
            A = _third(B, a0, b, a, sign)
            pts.append(_coupler(A, B, b, u, v))
            first = first or FourBar(a0, A, B, b0, pts[0])
        return np.array(pts), first, kind
    lo, hi = _driver_range(a, b, c, d)
    full = hi - lo >= 2 * math.pi - 1e-12
    phis = (start + np.linspace(0, 2 * math.pi, n, endpoint=False) if full else
            np.linspace(lo, hi, n + 2)[1:-1] if rng.uniform() < 0.5 else np.linspace(hi, lo, n + 2)[1:-1])
    for phi in phis:
        A = a0 + a * np.array([math.cos(frame + phi), math.sin(frame + phi)])
        B = _third(A, b0, b, c, sign)
        pts.append(_coupler(A, B, b, u, v))
        first = first or FourBar(a0, A, B, b0, pts[0])
    return np.array(pts), first, kind


def _third(A, D, b, c, sign):
    """The point ``|B − A| = b``, ``|B − D| = c`` on the side ``sign`` of ``A → D``."""
    e = D - A
    r = float(np.hypot(*e))
    along = (b * b + r * r - c * c) / (2 * r)
    across = sign * math.sqrt(max(b * b - along * along, 0.0))
    ux, uy = e / r
    return A + np.array([along * ux - across * uy, along * uy + across * ux])


def _coupler(A, B, b, u, v):
    """The coupler point ``(u, v)`` (along ``A → B`` and across) when the coupler is at ``A → B``."""
    ex, ey = (B - A) / b
    return A + np.array([u * ex - v * ey, u * ey + v * ex])


def size_of(points) -> float:
    return float(np.ptp(np.asarray(points), axis=0).max())


def path_route(points, a0=None, method="exact", seeds=64, atlas=None, driver="any"):
    """``(seconds, outcome, result)``: the path task's result, or the exception's name and text (a traceback)."""
    data = {"kind": "path", "points": np.asarray(points).tolist(), "driver": driver}
    if a0 is not None:
        data["a0"] = list(map(float, a0))
    t0 = time.perf_counter()
    try:
        result = synthesize(task_from_dict(data), method, seeds, atlas=atlas)
    except Exception as exc:                      # noqa: BLE001 - counted: a traceback is what is measured
        return time.perf_counter() - t0, f"{type(exc).__name__}: {exc}", None
    return time.perf_counter() - t0, "ok" if result.solutions else "nothing", result


def match_route(points, atlas):
    """``(seconds, outcome, worst relative distance of the best fit)`` of ``curves match``."""
    t0 = time.perf_counter()
    try:
        result = match(points, atlas, results=1)
    except Exception as exc:                      # noqa: BLE001
        return time.perf_counter() - t0, f"{type(exc).__name__}: {exc}", None
    dt = time.perf_counter() - t0
    if not result.fits:
        return dt, "nothing", None
    return dt, "ok", result.fits[0].after[0] / result.size


def answer_error(result, points) -> float:
    """The worst distance of the points from the first answer's coupler curve, by the kernel, over the size."""
    return max(curve_distances(result.solutions[0].fourbar, points)) / size_of(points)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--count", type=int, default=12, help="planted four-bars of each set (default 12)")
    ap.add_argument("--points", type=int, default=12, help="points per path (default 12)")
    ap.add_argument("--seed", type=int, default=27)
    ap.add_argument("--method", choices=("exact", "fast"), default="exact")
    ap.add_argument("--seeds", type=int, default=64, help="the path task's seeds (random starts: 64 x seeds "
                    "exact, 8 x seeds fast)")
    ap.add_argument("--atlas", choices=("quick", "small", "none"), default="quick",
                    help="the path task's atlas look-up: the quick one built in memory (the Python default), the "
                    "small one of the data folder (the command's, when built), or none (random starts only)")
    ap.add_argument("--arcs", action="store_true", help="also the paths on arcs (a rocker's swing)")
    ap.add_argument("--verbose", "-v", action="store_true")
    args = ap.parse_args(argv)
    small = Atlas(default_atlas("small"))
    atlas = {"quick": None, "small": small, "none": False}[args.atlas]
    sets = [("closed", CLOSED)] + ([("arcs", ARCS)] if args.arcs else [])
    print(f"{args.count} planted four-bars per set, {args.points} points each; path task: method {args.method}, "
          f"seeds {args.seeds}, atlas {args.atlas}; recovered = every point within {EXACT:g} of the size of the "
          "first answer's coupler curve (the kernel's)")
    print(f"{'set':7} {'route':22} {'traceback':>9} {'nothing':>7} {'recovered':>9} {'rocking 1st':>11} "
          f"{'unsaid':>6} {'median s':>8}")
    for label, kinds in sets:
        rng = np.random.default_rng(args.seed)
        cases = [planted(rng, kinds[k % len(kinds)], args.points) for k in range(args.count)]
        routes = {"path, nothing given": lambda P, fb: path_route(P, None, args.method, args.seeds, atlas),
                  "path, a0 given": lambda P, fb: path_route(P, fb.a0, args.method, args.seeds, atlas),
                  "path, a0, crank": lambda P, fb: path_route(P, fb.a0, args.method, args.seeds, atlas, "crank")}
        for name, run in routes.items():
            crashed = nothing = recovered = rocking = unsaid = 0
            times = []
            for k, (P, fb, kind) in enumerate(cases, 1):
                dt, outcome, result = run(P, fb)
                times.append(dt)
                if outcome != "ok":
                    crashed += outcome != "nothing"
                    nothing += outcome == "nothing"
                    if args.verbose:
                        print(f"  {name} #{k} ({kind}): {outcome}")
                    continue
                err = answer_error(result, P)
                first = result.solutions[0]
                recovered += err <= EXACT
                rocking += not first.checks.crank_rotates
                unsaid += not first.checks.crank_rotates and "rocks" not in first.checks.driver
                if args.verbose:
                    print(f"  {name} #{k} ({kind}): worst {err:.2g} of the size, usable {first.usable}; "
                          f"{first.checks.grashof}; {first.checks.driver or 'driver not said'}; {dt:.2f} s")
            print(f"{label:7} {name:22} {crashed:9d} {nothing:7d} {recovered:6d}/{args.count:<2d} {rocking:11d} "
                  f"{unsaid:6d} {float(np.median(times)):8.2f}")
        if label == "closed":
            ok, times = 0, []
            for P, fb, kind in cases:
                dt, outcome, err = match_route(P, small)
                times.append(dt)
                ok += outcome == "ok" and err <= EXACT
                if args.verbose:
                    print(f"  curves match ({kind}): {outcome}, worst {err if err is None else f'{err:.2g}'}; "
                          f"{dt:.2f} s")
            print(f"{label:7} {'curves match (small)':22} {0:9d} {0:7d} {ok:6d}/{args.count:<2d} {'':11} {'':6} "
                  f"{float(np.median(times)):8.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
