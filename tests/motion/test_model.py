"""The mechanism file format, its validation, and building from a labelled candidate."""

import json
import math

import pytest
from kinematics_cases import EXAMPLES, example

from domes.errors import DomesError
from domes.io.mechanisms import load_mechanism
from domes.model import LabelledChain
from domes.motion import Mechanism, from_labelled, solve

BASE = {"links": ["g", "a", "b", "c"], "ground": "g",
        "joints": [{"name": "A", "type": "R", "links": ["g", "a"], "at": [0, 0]},
                   {"name": "B", "type": "R", "links": ["a", "b"], "at": [1, 0]},
                   {"name": "C", "type": "R", "links": ["b", "c"], "at": [2, 2]},
                   {"name": "D", "type": "R", "links": ["c", "g"], "at": [3, 0]}],
        "inputs": [{"joint": "A"}]}


def _with(**changes):
    d = json.loads(json.dumps(BASE))
    d.update(changes)
    return d


@pytest.mark.parametrize("data,message", [
    (_with(joints=BASE["joints"][:3] + [{"name": "D", "type": "R", "links": ["c", "x"], "at": [3, 0]}]),
     r"joints\[3\]|joint 'D': link 'x'"),
    (_with(inputs=[{"joint": "Z"}]), "inputs: joint 'Z'"),
    (_with(inputs=[]), "1 degree\\(s\\) of freedom .* but 0 input"),
    (_with(ground="q"), "ground: 'q'"),
    (_with(joints=BASE["joints"][:3] + [{"name": "D", "type": "R", "links": ["c", "g"], "at": [3, "x"]}]),
     r"joints\[3\]\.at\[1\]: expected a finite number"),
    (_with(joints=BASE["joints"][:3] + [{"name": "D", "type": "Q", "links": ["c", "g"], "at": [3, 0]}]),
     "type 'Q' is not supported"),
    (_with(joints=BASE["joints"][:3] + [{"name": "D", "type": "G", "links": ["c", "g"], "at": [3, 0]}]),
     r"gear pair 'D': gears \['c', 'g'\] need a common carrier"),
    (_with(extra=1), r"unknown field\(s\) \['extra'\]"),
    (_with(angle_unit="grad"), "angle_unit"),
    (_with(joints=BASE["joints"] + [{"name": "E", "type": "P", "links": ["a", "c"], "at": [1, 1], "origin": [0, 0],
                                     "direction": 0}]), "origin .* off the slide line"),
])
def test_bad_input_names_the_field(data, message):
    with pytest.raises(DomesError, match=message):
        Mechanism.from_dict(data, "m.json")


def test_a_misspelt_field_is_named_as_written_with_the_closest_known_one():
    # issue 25, item 5: "joins" for "joints"
    data = {("joins" if k == "joints" else k): v for k, v in BASE.items()}
    with pytest.raises(DomesError, match=r"m.json: unknown field\(s\) \['joins'\] \(did you mean 'joints'\?\)"):
        Mechanism.from_dict(data, "m.json")
    data = {("joins" if k == "joints" else "lnks" if k == "links" else k): v for k, v in BASE.items()}
    with pytest.raises(DomesError, match=r"\['joins', 'lnks'\] \(did you mean 'joints' for 'joins', 'links' for 'lnks'\?\)"):
        Mechanism.from_dict(data, "m.json")


def test_a_wrong_space_is_called_a_wrong_value_with_the_spaces_there_are():
    # issue 25, item 5: it was called an unknown field
    with pytest.raises(DomesError, match=r"m.json: space: 'plane' is not a space \(did you mean 'planar'\?\); the "
                                         "spaces are 'planar' and 'spatial'"):
        Mechanism.from_dict(_with(space="plane"), "m.json")
    assert Mechanism.from_dict(_with(space="planar"), "m.json").name == Mechanism.from_dict(BASE, "m.json").name


def test_damaged_values_are_named_never_a_traceback():
    # issue 25, item 18 (the file fuzz): an integer too large for a float, null for a list, a coordinate that
    # overflows the kinematics, duplicates by the thousand, and a name of 200,000 characters
    joints = BASE["joints"]
    cases = [
        (_with(joints=joints[:3] + [{**joints[3], "at": [10 ** 400, 0]}]),
         r"joints\[3\]\.at\[0\]: expected a finite number, got an integer of 401 digits \(too large\)"),
        (_with(inputs=None), "m.json: inputs: expected a list, got None"),
        (_with(points=None), "m.json: points: expected a list, got None"),
        (_with(joints=joints[:3] + [{**joints[3], "at": [1e300, 0]}]), r"at\[0\]: 1e\+300 is too large"),
        (_with(points=[{"name": "P", "link": "b", "at": [1, 1]}] * 50_000), r"points: names \['P'\] are used twice"),
        (_with(links=["g", "a", "b", "c" * 200_000]), "link 'c' is not one of the links"),
    ]
    for data, message in cases:
        with pytest.raises(DomesError, match=message) as caught:
            Mechanism.from_dict(data, "m.json")
        assert len(str(caught.value)) <= 400


def test_bad_json_names_the_line(tmp_path):
    path = tmp_path / "bad.json"
    path.write_text('{\n "links": ["g",\n}\n')
    with pytest.raises(DomesError, match=r"bad.json: line 3"):
        load_mechanism(str(path))


@pytest.mark.parametrize("name", sorted(p.name for p in EXAMPLES.glob("*.json")))
def test_round_trip(name):
    m = example(name)
    again = Mechanism.from_dict(json.loads(json.dumps(m.to_dict())), name)
    assert [(j.name, j.kind, j.links, j.at, j.origin) for j in again.joints] == \
        [(j.name, j.kind, j.links, j.at, j.origin) for j in m.joints]
    assert [j.direction for j in again.joints] == pytest.approx([j.direction for j in m.joints], abs=1e-15)
    # pytest.approx compares flat sequences only (pytest >= 9.2 refuses nested ones)
    rates = lambda mech: [x for i in mech.inputs for x in (i.speed, i.acceleration)]  # noqa: E731
    assert rates(again) == pytest.approx(rates(m))
    assert dict(again.link_angles) == pytest.approx(dict(m.link_angles), abs=1e-15)
    assert (again.points, again.polygons) == (m.points, m.polygons)


def test_from_labelled_candidate_matches_the_file():
    # A LabelledChain (links 0..3, 0 = ground, 1 = input) plus joint coordinates gives the four-bar of four-bar.json.
    chain = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={0: {"ground"}, 1: {"input"}})
    at = {(0, 1): (0, 0), (1, 2): (1, 0), (2, 3): (3.5, math.sqrt(6)), (0, 3): (3, 0)}
    m = from_labelled(chain, at)
    ref = example("four-bar.json")
    a = solve(m, 1.0, outputs=["point:J2-3"], order=0).values
    b = solve(ref, 1.0, outputs=["point:C"], order=0).values
    assert (a["point:J2-3.x"], a["point:J2-3.y"]) == pytest.approx((b["point:C.x"], b["point:C.y"]), abs=1e-12)


def test_from_labelled_with_a_slider():
    chain = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(0, 3): "P"},
                                roles={0: {"ground"}, 1: {"input"}})
    x = math.sqrt(9 - 1)
    m = from_labelled(chain, {(0, 1): (0, 0), (1, 2): (0, 1), (2, 3): (x, 0), (0, 3): (x, 0)}, {(0, 3): 0.0})
    v = solve(m, 0.0, outputs=["slide:J0-3"], order=0).values
    assert v["slide:J0-3"] == pytest.approx(4.0 - x, abs=1e-12)  # crank along x: pin at 1 + 3 = 4, s from the drawn x


def test_from_labelled_refuses_other_joint_types():
    chain = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(2, 3): "H"}, roles={0: {"ground"}, 1: {"input"}})
    with pytest.raises(DomesError, match="joint 2-3 has type 'H'"):
        from_labelled(chain, {(0, 1): (0, 0), (1, 2): (0, 1), (2, 3): (3, 0), (0, 3): (3, 0)})
