"""Requirements with units, the design brief a scene builds from them, and the fuzzy ranking of designs."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from domes.design.brief import brief_from
from domes.design.ranking import GRADES, SCORES, goodness, memberships, rank
from domes.errors import DomesError
from domes.expert.replay import design_differences
from domes.io.scenes import load_scene, parse_scene
from domes.io.tomlsource import TomlSource
from domes.model.requirements import Requirement, RequirementSpec, convert, fill


@pytest.mark.parametrize("text, value", [("0.3 m", 0.3), ("300 mm", 0.3), ("30 cm", 0.3), ("11.811023622 in", 0.3),
                                         ("0.3", 0.3)])
def test_a_length_in_any_unit(text, value):
    assert RequirementSpec("l", "length", "quantity", "m").parse(text).value == pytest.approx(value, rel=1e-9)


@pytest.mark.parametrize("spec, text, why", [
    (("a", "rotation", "quantity", "deg"), "2 kN", "expected an angle"),
    (("a", "rotation", "quantity", "deg"), "3 %", "expected an angle"),
    (("r", "ratio", "quantity", "1"), "30 deg", "plain number"),
    (("k", "rate", "quantity", "N/m"), "5 N", "stiffness"),
    (("k", "rate", "quantity", "N/m"), "1e999 N/m", "finite"),
    (("k", "rate", "quantity", "N/m"), "9**9**9 N/m", "is not a unit"),
    (("l", "length", "range", "m"), "0.45 .. 0.25 m", "lower to a higher"),
    (("l", "length", "range", "m"), "0.25 m", "expected LOW .. HIGH"),
    (("b", "box", "box", "m"), "0 .. 1, 1 .. 0 m", "X0 < X1 and Y0 < Y1"),
    (("p", "point", "point", "m"), "1, 2, 3 m", "expected X, Y"),
    (("f", "function", "function", ""), "", "function of x"),
])
def test_a_bad_answer_says_what_was_expected(spec, text, why):
    with pytest.raises(DomesError, match=why):
        RequirementSpec(*spec).parse(text)


def test_units_convert_both_ways_and_write_out_inside_text():
    assert convert(60, "N/mm", "N/m") == 60000.0 and convert(1500, "rpm", "rad/s") == pytest.approx(50 * math.pi)
    travel = RequirementSpec("travel", "window travel", "quantity", "m").parse("400 mm")
    box = RequirementSpec("box", "envelope", "box", "m").parse("-300 .. 300, -300 .. 500 mm")
    filled = fill({"function": "{travel:m} * x / 150", "box": "{box}", "deg": ["{travel:mm}"]},
                  {"travel": travel, "box": box})
    assert filled == {"function": "(0.4) * x / 150", "box": [[-0.3, 0.3], [-0.3, 0.5]], "deg": [400.0]}
    with pytest.raises(DomesError, match="'nope', which was not answered"):
        fill("{nope}", {})
    # a requirement survives the case base (plain data) unchanged
    assert Requirement.from_dict(box.to_dict()) == box


@pytest.mark.parametrize("scene", ["motorcycle", "hinge-clamp", "window-lifter"])
def test_every_shipped_design_task_builds_from_its_defaults(scene):
    found = load_scene(scene)
    answers = {s.id: s.parse(s.default) for s in found.requirements}
    brief = brief_from(scene, found.design["task"], found.design["checks"], answers, found.design["weights"])
    assert brief.task.candidates == () and brief.checks


def test_a_scene_naming_an_undeclared_requirement_is_refused_with_its_line(tmp_path):
    text = load_scene("window-lifter").path
    source = open(text).read().replace('torque = "{torque:N*m}"', 'torque = "{motor:N*m}"')
    path = tmp_path / "bad.toml"
    path.write_text(source)
    with pytest.raises(DomesError, match=r"bad.toml:\d+: \[design\] names requirement 'motor'"):
        parse_scene(TomlSource.read(path))
    path.write_text(source.replace('"{motor:N*m}"', '"{torque:m}"'))
    with pytest.raises(DomesError, match="cannot be expressed in m"):
        parse_scene(TomlSource.read(path))


@settings(max_examples=200, deadline=None)
@given(st.floats(-1.0, 2.0))
def test_memberships_are_a_partition_of_one(g):
    row = memberships(min(1.0, max(0.0, g)))
    assert len(row) == len(GRADES) and sum(row) == pytest.approx(1.0) and min(row) >= 0


@settings(max_examples=100, deadline=None)
@given(st.lists(st.floats(0.0, 1.0), min_size=6, max_size=6), st.lists(st.floats(0.0, 1.0), min_size=6, max_size=6))
def test_a_design_no_worse_in_every_factor_ranks_no_lower(a, b):
    better = {"accuracy": min(a[0], b[0]), "transmission": 20 + 50 * max(a[1], b[1]),
              "compactness": min(a[2], b[2]), "force": 3 ** max(a[3], b[3]), "sensitivity": min(a[4], b[4]),
              "complexity": 14 - 10 * max(a[5], b[5])}
    worse = {"accuracy": a[0], "transmission": 20 + 50 * a[1], "compactness": a[2], "force": 3 ** a[3],
             "sensitivity": a[4], "complexity": 14 - 10 * a[5]}
    ranked = rank([{"candidate": 2, "indices": worse}, {"candidate": 1, "indices": better}])
    assert ranked[0].candidate == 1 or ranked[0].score == pytest.approx(ranked[1].score)
    for r in ranked:
        assert sum(r.contributions.values()) == pytest.approx(r.score)
        assert r.score == pytest.approx(np.dot(r.distribution, SCORES))


def test_weights_decide_between_a_smooth_and_a_compact_design():
    smooth = {"candidate": 1, "indices": {"transmission": 80.0, "compactness": 0.9}}
    compact = {"candidate": 2, "indices": {"transmission": 35.0, "compactness": 0.1}}
    assert [r.candidate for r in rank([smooth, compact], {"transmission": 3})] == [1, 2]
    assert [r.candidate for r in rank([smooth, compact], {"compactness": 3})] == [2, 1]
    assert goodness("transmission", float("nan")) == 0.0
    with pytest.raises(DomesError, match="unknown factor 'beauty'"):
        rank([smooth], {"beauty": 1})


def test_replays_compare_designs_by_status_rank_and_numbers():
    old = [{"candidate": 3, "status": "feasible", "rank": 1, "score": 0.5,
            "checks": [{"name": "curve", "passed": True, "value": 1.0}]}]
    assert design_differences(old, old) == []
    moved = [{**old[0], "score": 0.5 * (1 + 1e-3)}]
    assert "score recorded 0.5" in design_differences(old, moved)[0]
    failed = [{**old[0], "status": "infeasible", "rank": None,
               "checks": [{"name": "curve", "passed": False, "value": 9.0}]}]
    assert "designs: recorded [(3, 'feasible', 1)], now [(3, 'infeasible', None)]" in design_differences(old, failed)
