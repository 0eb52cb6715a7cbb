"""The coupler-curve atlas: build time and size, look-up time, and the fit reached, per setting (issue 14, item 7).

Run ``python benchmarks/bench_curves.py``. For each atlas density (linkages
sampled in the design space, coupler-plane step) it builds the atlas,
writes it (HDF5) to measure its size, and matches a fixed set of target
paths (64 points on the curve of a random four-bar, not an atlas point,
Grashof or not, placed at another scale and position) with each setting of
the refinement (candidates refined at most, evaluations per refinement).
Per row: the median look-up time, the share of targets fitted within 1e-6
of their size, the median time to the first fit, and the median and worst
largest distance reached (relative to the size). Two rows vary the number
of harmonics of the descriptor (3 and 8 against the default 5). A second
table matches open stretches (40 points over a quarter to a half of a random
four-bar's curve) in the small atlas's index of windows, per tolerance.
``--large`` adds the large atlas (a few minutes). A third table puts the
small atlas beside Pyslvs's metaheuristic path synthesis (differential
evolution, ``benchmarks/peer_synthesis.py``) on the same closed paths; it is
skipped, with a note, when Pyslvs is not installed.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from domes.errors import InputError  # noqa: E402
from domes.io.atlas import save_atlas  # noqa: E402
from domes.motion.coupler.atlas import SIZES, Atlas, AtlasSpec, OpenAtlas, build, build_windows  # noqa: E402
from domes.motion.coupler.curves import trace  # noqa: E402
from domes.motion.coupler.designspace import classify  # noqa: E402
from domes.motion.coupler.fourbar import four_bar  # noqa: E402
from domes.motion.coupler.match import match  # noqa: E402

sys.path.insert(0, str(ROOT / "benchmarks"))
from peer_synthesis import pyslvs_path_synthesis  # noqa: E402


def _curves(seed):
    """Curves (the first circuit, 720 samples) of random four-bars: not atlas points, Grashof or not."""
    rng = np.random.default_rng(seed)
    while True:
        lengths, uv = rng.uniform(0.3, 1.7, 4), rng.uniform(-3, 3, 2)
        try:
            classify(*lengths)
            yield rng, trace(four_bar(*lengths, *uv), "P", 720).circuits[0].points
        except InputError:
            continue


def targets(count, seed=7):
    """Closed paths: 64 points on the curve of a random four-bar, placed at another scale and position."""
    out = []
    for _, points in _curves(seed):
        if len(out) == count:
            return out
        idx = np.linspace(0, len(points) - 1, 64).astype(int)
        out.append(points[idx] * 2.0 + [3.0, -1.0])


def stretches(count, seed=3):
    """Open paths: 40 points over 25-50% of the curve of a random four-bar, placed at another scale and position."""
    out = []
    for rng, points in _curves(seed):
        if len(out) == count:
            return out
        k = len(points)
        start, span = rng.integers(0, k), int(k * rng.uniform(0.25, 0.5))
        idx = (start + np.linspace(0, span, 40).astype(int)) % k
        out.append(points[idx] * 2.0 + [3.0, -1.0])


def built(make, spec):
    """The table ``make(spec)`` builds, the seconds it took, and its size in MB as an HDF5 file."""
    t = time.perf_counter()
    table = make(spec)
    seconds = time.perf_counter() - t
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "atlas.h5"
        save_atlas(table, path)
        return table, seconds, path.stat().st_size / 1e6


def run_open(spec, tols, paths, candidates=30, nfev=150):
    table, seconds, megabytes = built(build_windows, spec)
    atlas = OpenAtlas(table)
    rows = []
    for tol in tols:
        looks, times, errors = [], [], []
        for target in paths:
            t = time.perf_counter()
            m = match(target, atlas, results=1, candidates=candidates, tol=tol, max_nfev=nfev)
            times.append(time.perf_counter() - t)
            looks.append(m.lookup_seconds)
            errors.append(m.fits[0].after[0] / m.size if m.fits else float("inf"))
        ok = sum(e <= tol for e in errors)
        rows.append((spec.name, table.count, seconds, megabytes, tol, statistics.median(looks) * 1e3,
                     ok / len(paths), statistics.median(times), statistics.median(errors), max(errors)))
    return rows


def run_peer(paths, generations):
    """Pyslvs DE on each path: (median seconds, share within 1e-6, median and worst largest distance / size)."""
    times, errors = [], []
    for target in paths:
        size = float(np.max(np.ptp(target, axis=0)))
        found = pyslvs_path_synthesis(target, "DE", generations, seed=0)
        if found is None:
            return None
        times.append(found["seconds"])
        errors.append(found["max_error"] / size)
    return (statistics.median(times), sum(e <= 1e-6 for e in errors) / len(errors), statistics.median(errors),
            max(errors))


def run(spec, settings, paths):
    table, seconds, megabytes = built(build, spec)
    atlas = Atlas(table)
    rows = []
    for candidates, nfev in settings:
        looks, times, errors, ok = [], [], [], 0
        for target in paths:
            t = time.perf_counter()
            atlas.lookup(target, k=candidates)
            looks.append(time.perf_counter() - t)
            t = time.perf_counter()
            m = match(target, atlas, results=1, candidates=candidates, max_nfev=nfev)
            times.append(time.perf_counter() - t)
            best = m.fits[0].after[0] / m.size if m.fits else float("inf")
            errors.append(best)
            ok += bool(m.fits) and m.fits[0].success
        rows.append((spec.name, spec.linkages, spec.step, table.count, seconds, megabytes, candidates, nfev,
                     statistics.median(looks) * 1e3, ok / len(paths), statistics.median(times),
                     statistics.median(errors), max(errors)))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--targets", type=int, default=20, help="target paths (default 20)")
    ap.add_argument("--large", action="store_true", help="also the large atlas (a few minutes)")
    ap.add_argument("--generations", type=int, default=300, help="Pyslvs DE generations (default 300)")
    args = ap.parse_args(argv)
    paths = targets(args.targets)
    both = [(10, 150), (30, 150)]
    plan = [(AtlasSpec("coarse", 150, 1.0), both), (AtlasSpec("medium", 300, 0.5), both),
            (AtlasSpec("medium-h3", 300, 0.5, harmonics=3), [(10, 150)]),
            (AtlasSpec("medium-h8", 300, 0.5, harmonics=8), [(10, 150)]), (SIZES["small"], both)]
    if args.large:
        plan.append((SIZES["large"], both))
    head = ("atlas", "linkages", "step", "harmonics", "curves", "build s", "MB", "candidates", "evaluations",
            "look-up ms", "fitted", "time to fit s", "median error", "worst error")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    ours = None
    for spec, settings in plan:
        for r in run(spec, settings, paths):
            if spec.name == "small" and r[6] == 30:
                ours = r
            print(f"| {r[0]} | {r[1]} | {r[2]} | {spec.harmonics} | {r[3]:,} | {r[4]:.1f} | {r[5]:.1f} | {r[6]} | "
                  f"{r[7]} | {r[8]:.2f} | {r[9]:.0%} | {r[10]:.2f} | {r[11]:.1e} | {r[12]:.1e} |", flush=True)
    print()
    print("| path synthesis | time s | fitted within 1e-6 | median error | worst error |")
    print("|---|---|---|---|---|")
    if ours:
        print(f"| domes: small atlas, 30 candidates | {ours[10]:.2f} | {ours[9]:.0%} | {ours[11]:.1e} | {ours[12]:.1e} |")
    peer = run_peer(paths, args.generations)
    if peer is None:
        print("| Pyslvs | skipped: not installed | | | |")
    else:
        print(f"| Pyslvs 22.07: DE, {args.generations} generations | {peer[0]:.2f} | {peer[1]:.0%} | {peer[2]:.1e} | "
              f"{peer[3]:.1e} |", flush=True)
    print()
    head = ("open-path index", "windows", "build s", "MB", "tol", "look-up ms", "fitted within tol", "time s",
            "median error", "worst error")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in run_open(SIZES["small"], (1e-3, 1e-4), stretches(args.targets)):
        print(f"| {r[0]} | {r[1]:,} | {r[2]:.1f} | {r[3]:.1f} | {r[4]:g} | {r[5]:.2f} | {r[6]:.0%} | {r[7]:.2f} | "
              f"{r[8]:.1e} | {r[9]:.1e} |", flush=True)


if __name__ == "__main__":
    main()
