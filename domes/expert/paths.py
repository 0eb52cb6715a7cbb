"""A wanted coupler path as a design question: "which mechanism traces this?" (docs/curves.md).

At the design dialogue's verification step, ``path FILE`` looks the path up
in the atlas of four-bar coupler curves (the small one, built in the user's
data folder when first needed), refines the nearest linkages until they
pass through every point, checks them with the kinematics kernel, and draws
them over the path.
"""

from __future__ import annotations

from pathlib import Path

from domes.io.atlas import default_atlas
from domes.io.curves import read_path
from domes.io.files import write_atomic
from domes.motion.coupler.atlas import Atlas, OpenAtlas
from domes.motion.coupler.curves import trace
from domes.motion.coupler.match import match
from domes.results import Progress
from domes.sketch.curves import Card, curves_html, joint_names, moving_svg


def coupler_path_text(path: str, progress: Progress | None = None, results: int = 3) -> str:
    """The four-bars through the wanted path in ``path`` as text; their drawing is written to ``PATH.matches.html``."""
    points, closed = read_path(path)
    kind = "open" if closed is False else "closed"
    table = default_atlas("small", progress, kind)
    atlas = OpenAtlas(table) if kind == "open" else Atlas(table)
    result = match(points, atlas, results=results, progress=progress)
    lines = [f"the wanted path {path} ({len(points)} points, {kind}): {result.message}"]
    cards = []
    for k, f in enumerate(result.fits, 1):
        a, b, c, d = f.lengths
        lines.append(f"  {k}. crank {a:.6g}, coupler {b:.6g}, rocker {c:.6g}, frame {d:.6g}, coupler point "
                     f"({f.coupler[0]:.6g}, {f.coupler[1]:.6g}); largest distance {f.after[0]:.3g}"
                     + ("" if f.success else " (does not fit)"))
        if f.mechanism is not None:
            curve = trace(f.mechanism, "P", 360, extra=joint_names(f.mechanism))
            cards.append(Card(str(k), f"match {k}", moving_svg(f.mechanism, curve.circuits[0], points),
                              (("largest distance", f"{f.after[0]:.3g}"),)))
    if cards:
        page = Path(str(path) + ".matches.html")
        write_atomic(page, curves_html(cards, f"Four-bars for {Path(path).name}", result.message))
        lines.append(f"  drawn in {page}")
    return "\n".join(lines)
