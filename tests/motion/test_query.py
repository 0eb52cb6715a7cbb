"""Only as much as asked: a query solves only the groups its outputs depend on (issue 5, item 2)."""

import math

import pytest
from kinematics_cases import example

from domes.errors import InputError
from domes.motion import Kinematics, Mechanism, sweep
from domes.motion.planar.structure import Structure
from domes.motion.planar.sweep import Continuation


def test_one_output_of_the_eight_bar_solves_fewer_groups():
    # Seed 000 §3.2 eight-bar: a point on Y needs the crank and the RRR dyad, not the class-IV group.
    m = example("eight-bar-class-iv.json")
    one = Kinematics(m, ["point:K"], order=2)
    full = Kinematics(m, None, order=2)
    model = Kinematics(m, None, order=2, method="newton")
    assert [g.kind for g in one.groups] == ["driver", "RRR"]
    assert [g.kind for g in full.groups] == ["driver", "RRR", "class-IV"]
    assert (one.equations, full.equations, model.equations) == (2, 6, 6)
    # Count the groups actually solved along the same sweep.
    for kin in (one, full):
        cont = Continuation(kin)
        state = cont.start(cont.q0)
        kin.groups_solved = 0
        for k in range(1, 11):
            state = kin.positions(cont.inputs(cont.q0 + 0.05 * k), state)
    assert (one.groups_solved, full.groups_solved) == (10, 20)
    sw = sweep(m, 0.0, math.pi, outputs=["point:K"])
    assert (sw.groups_solved, sw.groups_total, sw.equations) == (2, 3, 2)


@pytest.mark.parametrize("deg", [10.0, 95.0, 222.0])
def test_partial_query_agrees_with_the_full_model(deg):
    m = example("eight-bar-class-iv.json")
    q = math.radians(deg)
    from domes.motion import solve
    part = solve(m, q, outputs=["point:K", "angle:Q"], order=2).values
    whole = solve(m, q, order=2, method="newton").values
    whole_k = solve(m, q, outputs=["point:K"], order=2, method="newton").values
    for k, v in part.items():
        ref = whole.get(k, whole_k.get(k))
        assert v == pytest.approx(ref, abs=1e-9 * max(1, abs(ref))), k


def test_order_zero_builds_no_derivatives():
    m = example("watt-six-bar.json")
    from domes.motion import solve
    v = solve(m, 0.3, outputs=["slide:g"], order=0).values
    assert list(v) == ["slide:g"]


def _seven_bar(inputs):
    """A 2-DOF seven-bar: a four-bar (a, b, c, d) and a five-bar loop on its rocker (d, e, f, g, h)."""
    at = {"a": (0, 0), "b": (1, 0), "c": (3.5, 2.449489742783178), "d": (3, 0), "e": (4.5, 1), "f": (6, 2),
          "g": (7.5, 1), "h": (7, -1)}
    pairs = {"a": ("frame", "crank"), "b": ("crank", "coupler"), "c": ("coupler", "rocker"), "d": ("rocker", "frame"),
             "e": ("rocker", "l5"), "f": ("l5", "l6"), "g": ("l6", "l7"), "h": ("l7", "frame")}
    return Mechanism.from_dict({
        "name": "seven-bar", "links": ["frame", "crank", "coupler", "rocker", "l5", "l6", "l7"], "ground": "frame",
        "joints": [{"name": n, "type": "R", "links": list(pairs[n]), "at": list(at[n])} for n in pairs],
        "inputs": [{"joint": j} for j in inputs]})


def test_two_inputs_in_one_four_bar_loop_are_not_independent():
    # issue 25, item 4 (Yan ch. 3, the active-pair criterion of Fig. 3-19): both inputs of a 2-DOF seven-bar in its
    # four-bar loop over-constrain that loop and leave the five-bar loop free; this crashed with StopIteration.
    with pytest.raises(InputError, match=r"inputs a, d are not independent.*'coupler'"):
        Structure.of(_seven_bar(["a", "d"]))
    kinds = [g.kind for g in Structure.of(_seven_bar(["a", "h"])).groups]
    assert kinds == ["driver", "driver", "RRR", "RRR"]                 # a and h are independent: two dyads
