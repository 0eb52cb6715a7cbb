"""Active pairs (Yan ch. 3, Fig. 3-19; issue 26, item 6): inputs that are not independent get an error naming the
loop they over-constrain, and no choice of inputs ends in a traceback."""

from itertools import combinations

import pytest

from domes.errors import DomesError, InputError
from domes.model.mechanism import Mechanism
from domes.motion.planar.structure import Structure
from domes.motion.planar.sweep import solve

AT = {"a": (0, 0), "b": (1, 0), "c": (3.5, 2.449489742783178), "d": (3, 0), "e": (4.5, 1), "f": (6, 2),
      "g": (7.5, 1), "h": (7, -1)}
PAIRS = {"a": ("frame", "crank"), "b": ("crank", "coupler"), "c": ("coupler", "rocker"), "d": ("rocker", "frame"),
         "e": ("rocker", "l5"), "f": ("l5", "l6"), "g": ("l6", "l7"), "h": ("l7", "frame")}


def seven_bar(inputs) -> Mechanism:
    """A 2-DOF seven-bar: a four-bar (a, b, c, d) and a five-bar loop on its rocker (d, e, f, g, h)."""
    return Mechanism.from_dict({
        "name": "seven-bar", "links": ["frame", "crank", "coupler", "rocker", "l5", "l6", "l7"], "ground": "frame",
        "joints": [{"name": n, "type": "R", "links": list(PAIRS[n]), "at": list(AT[n])} for n in PAIRS],
        "inputs": [{"joint": j} for j in inputs]})


def test_both_inputs_in_the_four_bar_loop_name_that_loop():
    with pytest.raises(InputError, match=r"inputs a, d are not independent: .* in the loop (frame–crank–coupler–rocker "
                       r"\(joints a, b, c, d\)|frame–rocker–coupler–crank \(joints d, c, b, a\)), and leave another "
                       r"loop free"):
        Structure.of(seven_bar(["a", "d"]))


@pytest.mark.parametrize("inputs", [list(c) for k in (1, 2, 3) for c in combinations(sorted(PAIRS), k)],
                         ids=lambda c: "-".join(c))
def test_no_choice_of_inputs_ends_in_a_traceback(inputs):
    """Every choice of one, two or three input joints: a solved pose or a DomesError that says why."""
    try:
        step = solve(seven_bar(inputs))
    except DomesError as exc:
        assert str(exc) and "Traceback" not in str(exc)
        return
    assert len(inputs) == 2 and step.residual < 1e-9      # only a 2-DOF choice of independent inputs solves
