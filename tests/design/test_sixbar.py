"""Seed 002 §6-4 (digest B.6): six-bars built on atlas coupler curves do what the book says, by the backend."""

import math
import sys
from pathlib import Path

import pytest

from domes.design.sixbar import arc_stretch, output_motion, straight_stretch, with_guide_bar
from domes.errors import InputError
from domes.motion.coupler.curves import trace
from domes.motion.coupler.fourbar import from_atlas

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "examples" / "curves"))
import applications  # noqa: E402


@pytest.fixture(scope="module")
def worked():
    cards, lines = applications.applications()
    return {c.id: dict(c.properties) for c in cards}, lines


def _deg(text):
    return float(text.rstrip("°"))


def test_dwells_from_a_straight_stretch(worked):
    # Fig. 6-31: while P runs along the near-straight stretch the guide bar (and the yoke) hardly move: under 3% of
    # their swing (travel) over that part of the crank turn.
    props, _ = worked
    bar, yoke = props["dwell-bar"], props["dwell-yoke"]
    assert _deg(bar["during the dwell"]) < 0.03 * _deg(bar["swing"])
    assert float(yoke["during the dwell"]) < 0.03 * float(yoke["travel"])


def test_dwell_from_a_circular_arc(worked):
    # Fig. 6-32: the rocker pinned at the arc's centre hardly moves while P runs along the arc.
    props, _ = worked
    arc = props["dwell-arc"]
    assert _deg(arc["during the dwell"]) < 0.05 * _deg(arc["swing"])


def test_two_oscillations_and_two_turns(worked):
    # Fig. 6-33: the figure-eight gives two oscillations per crank turn; Fig. 6-34: the double loop two turns.
    props, _ = worked
    assert props["eight"]["oscillations per turn"] == "2"
    assert float(props["double-turn"]["output turns per crank turn"]) == pytest.approx(2.0, abs=1e-9)
    assert all(props[f"airfoil-{k}"]["crossings"] == "0" for k in range(4))


def test_a_pivot_outside_the_small_loop_turns_once():
    # The independent check of the double-turn claim: with the pivot outside both loops the bar only rocks.
    m = from_atlas(2.5, 2.5, 3.5, 1, 2, 270)
    pts = trace(m, "P").circuits[0].points
    far = tuple(pts.mean(axis=0) + [0.0, 3 * float(pts[:, 1].max() - pts[:, 1].min())])
    motion = output_motion(with_guide_bar(m, "P", far), "angle:bar")
    assert motion.turns == pytest.approx(0.0, abs=1e-9) and motion.swing < math.pi


def test_stretches_are_found_or_refused():
    pts = trace(from_atlas(1, 5, 4, 4, 7.5, 90), "P").circuits[0].points
    arc = arc_stretch(pts)
    assert arc.deviation <= 0.005 * max(pts.max(axis=0) - pts.min(axis=0)) and arc.radius > 0
    assert straight_stretch(pts, tolerance=1e-9).length < 0.1 * arc.length   # only a sliver is that straight
    with pytest.raises(InputError, match="no stretch"):
        arc_stretch(pts, min_turn=2 * math.pi)
