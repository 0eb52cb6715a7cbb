"""Skeleton layout: time against drawing quality, one row per setting of the knobs.

Run ``python benchmarks/bench_sketch.py``. For each one-DOF atlas and each
``(equalize, refine)`` setting of :func:`domes.sketch.skeleton_layout` it
prints the time per chain and, over the planar chains, the worst closest-
joint distance (fraction of the median link size; higher is better) and the
worst and median ratio of the largest to the smallest link (lower is better).
The next rows time the whole HTML atlas page, and the candidates' page of
three regeneration scenes (the regeneration itself not counted). The last table times the
dimensioned drawing with coupler curves (:func:`domes.sketch.dimensioned_svg`)
for each accuracy preset of the kinematics backend (its sweep resolution is
the knob) and gives the chordal error of the drawn polyline: the largest
distance from the curve (a 0.05° reference sweep at accuracy "exact") to the
polyline, relative to the mechanism's size and in pixels of a 400-px drawing.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from domes.io.mechanisms import load_mechanism
from domes.io.scenes import load_scene
from domes.motion import sweep  # noqa: E402
from domes.sketch import (  # noqa: E402
    chain_atlas_html,
    coupler_curves,
    dimensioned_svg,
    layout_quality,
    regeneration_html,
    skeleton_layout,
)
from domes.typesynth import chains, regenerate  # noqa: E402

EXAMPLES = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "examples", "mechanisms")
CURVES = [("four-bar.json", "P"), ("eight-bar-class-iv.json", "K"), ("swing-arm-shock.json", "axle")]

SETTINGS = [(0, 0), (8, 0), (8, 30), (8, 100), (16, 300)]


def main(argv=None) -> None:
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    print(f"{'atlas':>16} {'equalize':>8} {'refine':>6} {'ms/chain':>9} {'min gap':>8} {'worst ratio':>11} {'median ratio':>12}")
    atlases = [("8-bar", chains(links=8, dof=1), SETTINGS), ("10-bar", chains(links=10, dof=1), SETTINGS)]
    atlases.append(("12-bar/20", chains(links=12, dof=1)[::20], [(8, 0), (8, 100)]))  # every 20th chain
    for name, atlas, settings in atlases:
        for equalize, refine in settings:
            start = time.perf_counter()
            layouts = [skeleton_layout(c, equalize=equalize, refine=refine) for c in atlas]
            elapsed = time.perf_counter() - start
            quality = [layout_quality(layout) for layout in layouts if layout.planar]
            print(
                f"{f'{name} ({len(atlas)})':>16} {equalize:>8} {refine:>6} {1000 * elapsed / len(atlas):>9.1f} "
                f"{min(q[0] for q in quality):>8.3f} {max(q[1] for q in quality):>11.2f} {statistics.median(q[1] for q in quality):>12.2f}"
            )
    for links in (8, 10):
        atlas = chains(links=links, dof=1)
        start = time.perf_counter()
        page = chain_atlas_html(atlas)
        print(f"atlas page, {links}-bar: {time.perf_counter() - start:.2f} s, {len(page) / 1e6:.2f} MB")
    for scene in ("motorcycle", "motorcycle-8bar", "tyre-drum"):
        result = regenerate(load_scene(scene))
        start = time.perf_counter()
        page = regeneration_html(result)
        print(f"candidates page, {scene} ({len(result.candidates)}): {time.perf_counter() - start:.2f} s, {len(page) / 1e6:.2f} MB")
    coupler_table()


def _chord_error(reference: np.ndarray, path: np.ndarray, closed: bool) -> float:
    """Largest distance from a reference point to the polyline ``path``."""
    a = path if not closed else np.vstack([path, path[:1]])
    p, q = a[:-1], a[1:]
    d = q - p
    best = np.full(len(reference), np.inf)
    for k in range(len(p)):
        t = np.clip(((reference - p[k]) @ d[k]) / max(d[k] @ d[k], 1e-300), 0.0, 1.0)
        best = np.minimum(best, np.hypot(*(reference - (p[k] + t[:, None] * d[k])).T))
    return float(best.max())


def coupler_table() -> None:
    print(f"\n{'mechanism, point':>28} {'accuracy':>8} {'ms':>8} {'vertices':>8} {'chord err/size':>14} {'px @400 <=':>10}")
    for name, point in CURVES:
        mech = load_mechanism(os.path.join(EXAMPLES, name))
        (exact,) = coupler_curves(mech, [point], accuracy="exact")
        lo, hi = (exact.first.input if exact.first else None), (exact.last.input if exact.last else None)
        angular = mech.joint(mech.inputs[0].joint).kind == "R"
        fine = math.radians(0.05) if angular else 0.0005 * mech.size
        span = (0.0, 2 * math.pi) if exact.closed else (lo, hi)
        ref = sweep(mech, span[0] + 1e-9, span[1] - 1e-9, fine, outputs=[f"point:{point}"], accuracy="exact")
        reference = np.array([(s.values[f"point:{point}.x"], s.values[f"point:{point}.y"]) for s in ref.steps])
        extent = np.ptp(reference, axis=0).max()
        for preset in ("fast", "default", "exact"):
            start = time.perf_counter()
            dimensioned_svg(mech, coupler=[point], accuracy=preset)
            elapsed = time.perf_counter() - start
            (curve,) = coupler_curves(mech, [point], accuracy=preset)
            error = _chord_error(reference, np.array(curve.path), curve.closed)
            print(f"{f'{name[:-5]}, {point}':>28} {preset:>8} {1000 * elapsed:>8.0f} {len(curve.path):>8} {error / mech.size:>14.2e} {error / extent * 304:>10.3f}")


if __name__ == "__main__":
    main()
