"""Small mechanisms used in docstrings and as starting points (geometry only, no results).

>>> four_bar().dof, triple_rocker().loops
(1, 1)
"""

from __future__ import annotations

import math

from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism


def four_bar(speed: float = 10.0) -> Mechanism:
    """Grashof crank-rocker of seed 000 T6's first loop: a=(0,0), d=(3,0), crank 1, coupler 3.5, rocker 2.5, drawn at 0°."""
    return Mechanism.build(
        "crank-rocker four-bar", ["frame", "crank", "coupler", "rocker"], "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)),
         Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
         Joint("C", "R", ("coupler", "rocker"), (3.5, math.sqrt(6.0))),
         Joint("D", "R", ("rocker", "frame"), (3.0, 0.0))],
        [Input("A", speed)],
        link_angles={"rocker": math.atan2(math.sqrt(6.0), 0.5)},
    )


def triple_rocker() -> Mechanism:
    """Non-Grashof four-bar of seed 000 T9: a=(0,0), d=(3,0), l1=2, l2=2, l3=2.5, upper branch, drawn at 0°."""
    # c: |c − b| = 2 with b = (2, 0), |c − d| = 2.5.
    cx = 2.0 + (4.0 - 6.25 + 1.0) / 2.0
    cy = math.sqrt(4.0 - (cx - 2.0) ** 2)
    return Mechanism.build(
        "triple-rocker four-bar", ["frame", "crank", "coupler", "rocker"], "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)),
         Joint("B", "R", ("crank", "coupler"), (2.0, 0.0)),
         Joint("C", "R", ("coupler", "rocker"), (cx, cy)),
         Joint("D", "R", ("rocker", "frame"), (3.0, 0.0))],
        [Input("A")],
        link_angles={"rocker": math.atan2(cy, cx - 3.0)},
    )


def slider_crank(crank: float = 1.0, rod: float = 3.0, offset: float = 0.0) -> Mechanism:
    """In-line (or offset) slider-crank drawn at crank angle 90°; the slide coordinate is the pin's x."""
    x = math.sqrt(rod ** 2 - (crank - offset) ** 2)
    return Mechanism.build(
        "slider-crank", ["frame", "crank", "rod", "slider"], "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)),
         Joint("B", "R", ("crank", "rod"), (0.0, crank)),
         Joint("C", "R", ("rod", "slider"), (x, offset)),
         Joint("S", "P", ("frame", "slider"), (x, offset), 0.0, (0.0, offset))],
        [Input("A")],
    )


def parallelogram() -> Mechanism:
    """Parallelogram four-bar: crank 1, coupler 3, drawn at 1 rad; its change points are at 0 and 180°.

    There all four joints are collinear and the parallelogram and the
    crossed (antiparallelogram) assembly modes meet: a bifurcation.
    """
    bx, by = math.cos(1.0), math.sin(1.0)
    return Mechanism.build(
        "parallelogram four-bar", ["frame", "crank", "coupler", "rocker"], "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)),
         Joint("B", "R", ("crank", "coupler"), (bx, by)),
         Joint("C", "R", ("coupler", "rocker"), (bx + 3.0, by)),
         Joint("D", "R", ("rocker", "frame"), (3.0, 0.0))],
        [Input("A")],
    )


def stephenson_iii(crank: float = 0.6) -> Mechanism:
    """Stephenson III six-bar: a crank (pivot O) drives, through link3, the ternary coupler of a triad (class III),
    whose links 1 and 2 are pivoted on the frame at P1 and P2; the crank turns fully."""
    return Mechanism.build(
        "Stephenson III six-bar", ["frame", "crank", "coupler", "link1", "link2", "link3"], "frame",
        [Joint("O", "R", ("frame", "crank"), (-3.0, 3.8)),
         Joint("Q", "R", ("crank", "link3"), (-3.0 + crank, 3.8)),
         Joint("B3", "R", ("link3", "coupler"), (1.0, 3.8)),
         Joint("B1", "R", ("coupler", "link1"), (0.0, 3.0)),
         Joint("P1", "R", ("link1", "frame"), (0.0, 0.0)),
         Joint("B2", "R", ("coupler", "link2"), (2.0, 3.2)),
         Joint("P2", "R", ("link2", "frame"), (2.0, 0.0))],
        [Input("O", 360.0)],
        points=[CouplerPoint("T", "coupler", (1.5, 4.5))],
    )
