"""The atlas applications of seed 002 §6-4 (digest B.6), worked: six-bars built on four-bar coupler curves.

Run ``python examples/curves/applications.py -o applications.html``: it prints
what each output does over one crank turn (from the kinematics backend) and
writes a page with each six-bar drawn moving along its coupler curve.

1. the airfoil curves (Fig. 6-30), simple closed curves;
2. a dwell from the near-straight stretch of (A=1, B=3, C=3.5, D=3, P=4.75,
   θBP=120°): a guide bar pivoted on the stretch's line, and a yoke across it;
3. a dwell from the near-circular arc of (1, 5, 4, 4, 7.5, 90°): a link as
   long as the arc's radius to an output rocker pinned at its centre;
4. two equal oscillations per turn from the figure-eight (1, 3.5, 3, 2, 2, 270°);
5. two output turns per crank turn from the double loop (2.5, 2.5, 3.5, 1, 2, 270°).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from domes.design.sixbar import arc_stretch, output_motion, straight_stretch, with_guide_bar, with_rocker, with_yoke  # noqa: E402
from domes.io.files import write_atomic  # noqa: E402
from domes.motion.coupler.curves import trace  # noqa: E402
from domes.motion.coupler.fourbar import from_atlas  # noqa: E402
from domes.motion.coupler.special import crossings  # noqa: E402
from domes.sketch.curves import Card, curves_html, joint_names, moving_svg  # noqa: E402


def deg(x):
    return f"{math.degrees(x):.3g}°"


def card(key, title, mech, props):
    curve = trace(mech, "P", 360, extra=joint_names(mech))
    return Card(key, title, moving_svg(mech, curve.circuits[0]), tuple(props))


def applications():
    cards, lines = [], []
    for args in [(1, 5, 5, 4, 7.5, 240), (1, 5, 5, 3, 10.5, 210), (1, 3.5, 3.5, 3.5, 10.25, 240),
                 (1, 2.5, 3.5, 2.5, 10.25, 0)]:
        m = from_atlas(*args)
        curve = trace(m, "P")
        n = len(crossings(curve, curve.circuits[0]))
        lines.append(f"airfoil {args}: {n} crossings")
        cards.append(card(f"airfoil-{len(cards)}", f"airfoil curve {args}", m, [("crossings", str(n))]))

    m = from_atlas(1, 3, 3.5, 3, 4.75, 120)
    circuit = trace(m, "P").circuits[0]
    s = straight_stretch(circuit.points)
    e1, e2 = np.array(s.first), np.array(s.last)
    along = (e2 - e1) / np.linalg.norm(e2 - e1)
    crank = (circuit.inputs[s.start], circuit.inputs[s.stop])
    bar = with_guide_bar(m, "P", tuple(e2 + along * np.linalg.norm(e2 - e1)), "dwell six-bar (guide bar)")
    om = output_motion(bar, "angle:bar")
    lines.append(f"straight stretch: {s.length:.3g} long within {s.deviation:.2g}; guide bar swings {deg(om.swing)} and "
                 f"moves {deg(om.variation(*crank))} while P runs along the stretch ({deg(crank[1] - crank[0])} of crank)")
    cards.append(card("dwell-bar", "dwell from a straight stretch: guide bar", bar,
                      [("swing", deg(om.swing)), ("during the dwell", deg(om.variation(*crank)))]))
    yoke = with_yoke(m, "P", math.atan2(along[1], along[0]), "dwell six-bar (yoke)")
    oy = output_motion(yoke, "slide:Y")
    lines.append(f"  yoke travels {oy.swing:.3g} and {oy.variation(*crank):.2g} during the stretch")
    cards.append(card("dwell-yoke", "dwell from a straight stretch: yoke", yoke,
                      [("travel", f"{oy.swing:.3g}"), ("during the dwell", f"{oy.variation(*crank):.2g}")]))

    m = from_atlas(1, 5, 4, 4, 7.5, 90)
    circuit = trace(m, "P").circuits[0]
    a = arc_stretch(circuit.points)
    crank = (circuit.inputs[a.start], circuit.inputs[a.stop])
    centre = np.array(a.centre)
    pivot = centre + np.array([0.0, -1.0]) * a.radius * 0.8
    rocker = with_rocker(m, "P", tuple(centre), tuple(pivot), "dwell six-bar (arc)")
    orr = output_motion(rocker, "angle:output")
    lines.append(f"arc stretch: radius {a.radius:.3g}, {a.length:.3g} long within {a.deviation:.2g}; rocker swings "
                 f"{deg(orr.swing)} and moves {deg(orr.variation(*crank))} along the arc")
    cards.append(card("dwell-arc", "dwell from a circular arc: output rocker", rocker,
                      [("swing", deg(orr.swing)), ("during the dwell", deg(orr.variation(*crank)))]))

    m = from_atlas(1, 3.5, 3, 2, 2, 270)
    curve = trace(m, "P")
    k = np.array(crossings(curve, curve.circuits[0])[0].at)
    pts = curve.circuits[0].points
    axis = np.linalg.svd(pts - pts.mean(axis=0))[2][0]
    size = float(np.max(np.ptp(pts, axis=0)))
    eight = with_guide_bar(m, "P", tuple(k + axis * 1.5 * size), "double-oscillation six-bar")
    oe = output_motion(eight, "angle:bar")
    lines.append(f"figure-eight: crossing at ({k[0]:.4g}, {k[1]:.4g}); the guide bar makes {oe.oscillations} "
                 f"oscillations per crank turn, swing {deg(oe.swing)}")
    cards.append(card("eight", "two oscillations per turn: figure-eight", eight,
                      [("oscillations per turn", str(oe.oscillations)), ("swing", deg(oe.swing))]))

    m = from_atlas(2.5, 2.5, 3.5, 1, 2, 270)
    pts = trace(m, "P").circuits[0].points
    inside = _winding_two(pts)
    loop = with_guide_bar(m, "P", tuple(inside), "double-turn six-bar")
    ol = output_motion(loop, "angle:bar")
    lines.append(f"double loop: pivot at ({inside[0]:.4g}, {inside[1]:.4g}) inside the small loop; the guide bar "
                 f"turns {ol.turns:.4g} times per crank turn")
    cards.append(card("double-turn", "two output turns per crank turn: double loop", loop,
                      [("output turns per crank turn", f"{ol.turns:.4g}")]))
    return cards, lines


def _winding_two(pts):
    """A point the curve winds round twice (the middle of the small loop)."""
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    found = []
    for i in range(1, 40):
        for j in range(1, 40):
            p = lo + (hi - lo) * (i / 40, j / 40)
            d = pts - p
            ang = np.arctan2(d[:, 1], d[:, 0])
            w = np.sum(np.remainder(np.diff(np.append(ang, ang[0])) + np.pi, 2 * np.pi) - np.pi) / (2 * np.pi)
            if abs(round(w)) == 2:
                found.append(p)
    return np.mean(found, axis=0)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--output", "-o", help="write the page of drawings to this file")
    args = ap.parse_args(argv)
    cards, lines = applications()
    print("\n".join(lines))
    if args.output:
        write_atomic(args.output, curves_html(cards, "Coupler-curve applications (seed 002 §6-4)",
                                              "Six-bars built on four-bar coupler curves of the atlas"))


if __name__ == "__main__":
    main()
