"""Spatial mechanism files (issue 15, item 1): read, written, validated; ``domes kinematics`` takes them."""

import json
import math

import numpy as np
import pytest

from domes.cli import main
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism, load_spatial, save_spatial
from domes.model.spatial import SpatialMechanism
from domes.motion.spatial.rssr import RSSR

RSSR_FILE = "examples/spatial/rssr-seed001.json"


def test_round_trip(tmp_path):
    m = load_spatial(RSSR_FILE)
    save_spatial(m, tmp_path / "m.json")
    again = load_spatial(tmp_path / "m.json")
    assert again.joints == m.joints and again.inputs[0].speed == pytest.approx(m.inputs[0].speed)
    assert m.inputs[0].speed == pytest.approx(10.0)           # 572.96 deg/s


def test_kinematics_command_equals_the_closed_form(capsys):
    assert main(["kinematics", RSSR_FILE, "--sweep", "0:330:30", "--outputs", "angle:B0", "--order", "2",
                 "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    alpha = np.radians([r["input"] for r in doc["steps"]])
    r = RSSR.paper()
    beta = np.unwrap(r.beta(alpha))
    bd, bdd = r.rates(alpha, beta, 10.0)
    np.testing.assert_allclose(np.radians([s["angle:B0"] for s in doc["steps"]]), beta, atol=1e-12)
    np.testing.assert_allclose(np.radians([s["angle:B0''"] for s in doc["steps"]]), bdd, rtol=1e-9)
    assert doc["idle"] == 1 and doc["max_residual"] < 1e-12 and doc["status"] == "complete"


def test_a_limit_is_reported_by_the_command(tmp_path, capsys):
    data = json.load(open(RSSR_FILE))
    data["inputs"] = [{"joint": "B0", "speed": 1}]
    path = tmp_path / "rocker-driven.json"
    path.write_text(json.dumps(data))
    assert main(["kinematics", str(path), "--sweep", "0:90:5", "--outputs", "angle:A0"]) == 0
    out = capsys.readouterr().out
    assert "# limit at input 68.14" in out and "status: stopped" in out        # β max 1.189368 rad = 68.145°


@pytest.mark.parametrize("change, message", [
    (lambda d: d["joints"][0].pop("axis"), "needs its 'axis'"),
    (lambda d: d["joints"][1].update(axis=[1, 0, 0]), "an S joint has no axis"),
    (lambda d: d["joints"][0].update(at=[0, 0]), r"joints\[0\].at: expected \[x, y, z\]"),
    (lambda d: d["joints"][0].update(type="Q"), "type 'Q' is not one of"),
    (lambda d: d.update(space="planar"), "space: 'spatial'"),
    (lambda d: d.update(space="plane"), r"space: 'plane' is not a space .*the spaces are 'planar' and 'spatial'"),
    (lambda d: d["inputs"][0].update(variable="slide"), "has no 'slide' to drive"),
    (lambda d: d["joints"][0].update(axis=[0, 0, 0]), "has no direction"),
])
def test_mistakes_name_the_file_and_the_field(tmp_path, change, message):
    data = json.load(open(RSSR_FILE))
    change(data)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match=message):
        load_spatial(path)


def test_planar_commands_say_a_spatial_file_is_not_theirs():
    with pytest.raises(InputError, match="a spatial mechanism; this command takes planar ones"):
        load_mechanism(RSSR_FILE)


def test_an_rccc_file_sweeps(tmp_path, capsys):
    # a hand-made RCCC in its drawn pose: four axes, the input at the R joint
    rng = np.random.default_rng(7)
    axes = [v / np.linalg.norm(v) for v in rng.normal(size=(4, 3))]
    pts = rng.normal(size=(4, 3)) * 2
    links = ["frame", "input", "coupler", "output"]
    kinds = ["R", "C", "C", "C"]
    pairs = [("frame", "input"), ("input", "coupler"), ("coupler", "output"), ("output", "frame")]
    data = {"space": "spatial", "name": "RCCC", "links": links, "ground": "frame",
            "joints": [{"name": f"J{k + 1}", "type": kinds[k], "links": list(pairs[k]), "at": list(pts[k]),
                        "axis": list(axes[k])} for k in range(4)],
            "inputs": [{"joint": "J1", "speed": 30}]}
    path = tmp_path / "rccc.json"
    path.write_text(json.dumps(data))
    m = SpatialMechanism.from_dict(json.loads(path.read_text()), str(path))
    assert m.dof == 1 and m.idle == 0
    assert main(["kinematics", str(path), "--sweep", "0:10:2", "--order", "1", "--format", "csv"]) == 0
    lines = capsys.readouterr().out.strip().splitlines()
    assert lines[0].startswith("input,angle:J1,angle:J1',angle:J2") and len(lines) == 7
    assert math.isclose(float(lines[-1].split(",")[0]), 10.0)


def test_an_axis_of_huge_components_is_a_direction_and_a_file_says_it_is_too_large(tmp_path, capsys):
    # issue 25, item 18: an axis of 1e300 overflowed to no direction, and the mobility check's SVD failed
    import dataclasses

    from domes.motion.spatial.sweep import spatial_sweep

    m = load_spatial(RSSR_FILE)
    joints = [dataclasses.replace(m.joints[0], axis=(0.0, 0.0, 1e300)), *m.joints[1:]]
    huge = SpatialMechanism.build(m.name, m.links, m.ground, joints, m.inputs, m.points)
    assert huge.joints[0].axis == (0.0, 0.0, 1.0)
    assert spatial_sweep(huge, 0.0, 1.0, 0.5, outputs=["angle:B0"]).success
    data = json.load(open(RSSR_FILE))
    data["joints"][0]["axis"] = [0, 0, 1e300]
    path = tmp_path / "huge-axis.json"
    path.write_text(json.dumps(data))
    assert main(["kinematics", str(path), "--sweep", "0:60:30"]) == 2
    assert "joints[0].axis[2]: 1e+300 is too large (at most 1e+50 in size)" in capsys.readouterr().err
