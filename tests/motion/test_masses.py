"""Mass properties, loads, springs and gravity in the mechanism file (issue 16, item 1).

A file without them is what it was; a file with them reads, writes back the
same, and every mistake is named with its place.
"""

import json

import pytest

from domes.errors import InputError
from domes.io.mechanisms import load_mechanism, save_mechanism
from domes.model.mechanism import Mechanism

BASE = json.loads(open("examples/mechanisms/slider-crank.json").read())


def with_masses(**extra):
    data = json.loads(json.dumps(BASE))
    data["links"] = ["frame", {"name": "crank", "mass": 0.4, "centre": [0.0, 0.5], "inertia": 2e-3},
                     {"name": "rod", "mass": 1.2, "centre": [1.479, 0.75], "inertia": 0.9}, {"name": "slider", "mass": 0.8,
                                                                                          "centre": [2.958, 0.5]}]
    data["gravity"] = [0.0, -9.81]
    data["loads"] = [{"name": "cut", "link": "slider", "force": [-50.0, 0.0], "at": [2.958, 0.5]},
                     {"name": "brake", "link": "crank", "torque": -1.5}]
    data["springs"] = [{"name": "return", "between": ["A", "C"], "rate": 400.0, "free_length": 2.5, "damping": 3.0}]
    data.update(extra)
    return data


def test_files_without_masses_are_unchanged():
    mech = load_mechanism("examples/mechanisms/slider-crank.json")
    assert mech.masses.empty and mech.masses.mass_of("rod").mass == 0.0
    assert "gravity" not in mech.to_dict() and all(isinstance(x, str) for x in mech.to_dict()["links"])


def test_masses_loads_and_springs_round_trip(tmp_path):
    mech = Mechanism.from_dict(with_masses(), "test")
    m = mech.masses
    assert m.mass_of("rod").mass == 1.2 and m.mass_of("rod").centre == (1.479, 0.75) and m.mass_of("frame").mass == 0
    assert m.gravity == (0.0, -9.81) and [x.name for x in m.loads] == ["cut", "brake"]
    assert m.springs[0].between == ("A", "C") and m.springs[0].damping == 3.0
    path = tmp_path / "massive.json"
    save_mechanism(mech, path)
    again = load_mechanism(path)
    assert again == mech and again.masses == mech.masses


@pytest.mark.parametrize("change, message", [
    ({"gravity": [0, "down"]}, r"gravity\[1\]: expected a finite number"),
    ({"loads": [{"name": "x", "link": "wheel", "torque": 1.0}]}, r"load 'x': link 'wheel' is not one of the links"),
    ({"loads": [{"name": "x", "link": "rod", "force": [1, 0]}]}, r"load 'x': a force needs the point it acts at"),
    ({"loads": [{"name": "x", "link": "rod"}]}, r"loads\[0\]: give a force \(with 'at'\) or a torque"),
    ({"springs": [{"name": "s", "between": ["A", "Q"], "rate": 1.0}]}, r"spring 's': 'Q' is not a joint or point"),
    ({"springs": [{"name": "s", "between": ["A", "A"], "rate": 1.0}]}, r"its two ends are the same place"),
    ({"springs": [{"name": "s", "between": ["A", "C"], "rate": -1.0}]}, r"springs\[0\].rate: must be >= 0"),
    ({"springs": [{"name": "s", "between": ["A", "C"], "free_length": 0}]}, r"free_length: must be > 0"),
    ({"loads": [{"name": "s", "link": "rod", "torque": 1.0}],
      "springs": [{"name": "s", "between": ["A", "C"]}]}, r"names \['s'\] are used twice"),
])
def test_mistakes_are_named(change, message):
    with pytest.raises(InputError, match=message):
        Mechanism.from_dict(with_masses(**change), "test")


def test_a_mass_needs_its_centre_and_no_negative_inertia():
    data = with_masses()
    data["links"][1] = {"name": "crank", "mass": 0.4}
    with pytest.raises(InputError, match=r"link 'crank': a link with a mass needs its centre of mass"):
        Mechanism.from_dict(data, "test")
    data["links"][1] = {"name": "crank", "mass": 0.4, "centre": [0, 0.5], "inertia": -1}
    with pytest.raises(InputError, match=r"link 'crank'.inertia: must be >= 0"):
        Mechanism.from_dict(data, "test")
