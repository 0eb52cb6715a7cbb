"""Skeleton layout: time against drawing quality, one row per setting of the knobs.

Run ``python benchmarks/bench_sketch.py``. For each one-DOF atlas and each
``(equalize, refine)`` setting of :func:`domes.sketch.skeleton_layout` it
prints the time per chain and, over the planar chains, the worst closest-
joint distance (fraction of the median link size; higher is better) and the
worst and median ratio of the largest to the smallest link (lower is better).
The last rows time the whole HTML atlas page.
"""

from __future__ import annotations

import os
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from domes.chains import chains  # noqa: E402
from domes.sketch import chain_atlas_html, layout_quality, skeleton_layout  # noqa: E402

SETTINGS = [(0, 0), (8, 0), (8, 30), (8, 100), (16, 300)]


def main() -> None:
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


if __name__ == "__main__":
    main()
