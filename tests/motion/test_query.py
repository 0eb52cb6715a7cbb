"""Only as much as asked: a query solves only the groups its outputs depend on (issue 5, item 2)."""

import math

import pytest
from kinematics_cases import example

from domes.motion import Kinematics, sweep
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
