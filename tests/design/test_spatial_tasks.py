"""Spatial task files and ``domes synthesize`` on them (issue 15, item 6)."""

import json

import numpy as np
import pytest

from domes.cli import main
from domes.errors import InputError
from domes.io.mechanisms import load_spatial
from domes.io.tasks import load_spatial_task, load_task
from domes.model.spatial import SpatialMechanism


def run(capsys, *words):
    status = main(["synthesize", *words])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_example_3_from_its_file(capsys):
    status, out, _ = run(capsys, "examples/synthesis/ch2-example-3-spherical.json")
    assert status == 0 and "a0 = (-0.250000, 0.189944, 0.949432), a1 = (-0.583949, -0.314924, 0.748216)" in out


def test_the_planted_rccc_from_its_poses(capsys, tmp_path):
    status, out, _ = run(capsys, "examples/synthesis/rccc-planted.json", "--format", "json", "-o",
                         str(tmp_path / "r.json"))
    doc = json.loads((tmp_path / "r.json").read_text())
    assert status == 0 and doc["label"] == "exact" and max(doc["rotation_errors"]) < 1e-9
    mech = SpatialMechanism.from_dict(doc["mechanisms"][0], "result")
    assert [j.kind for j in mech.joints] == ["R", "C", "C", "C"]
    planted = load_spatial("examples/spatial/rccc-planted.json")
    # the recovered z1 is the planted z1 line (up to the direction's sign)
    u = np.asarray(mech.joint("z1").axis)
    assert abs(abs(u @ np.asarray(planted.joint("z1").axis)) - 1) < 1e-9


def test_table_1_is_approximate_and_says_why(capsys):
    status, out, _ = run(capsys, "examples/synthesis/rccc-table-1.json")
    assert status == 0 and "approximate RCCC" in out and "rotation ≤" in out


def test_the_function_generator_meets_its_points(capsys):
    status, out, _ = run(capsys, "examples/synthesis/spherical-function.json", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and doc["worst"] < 1e-9 and len(doc["mechanisms"]) == 2


@pytest.mark.parametrize("change, message", [
    (lambda d: d.pop("convention"), "angles need the task's 'convention'"),
    (lambda d: d.update(convention="abc"), "orientation convention: one of"),
    (lambda d: d["poses"].pop(), "poses: four"),
    (lambda d: d.update(meridians=5), "meridians: an integer from 12"),
    (lambda d: d["poses"][1].pop("angles_deg"), "give its orientation"),
])
def test_task_mistakes_are_named(tmp_path, change, message):
    data = json.loads(open("examples/synthesis/rccc-table-1.json").read())
    change(data)
    path = tmp_path / "t.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match=message):
        load_spatial_task(path)


def test_the_printed_example_3_is_refused(tmp_path, capsys):
    data = json.loads(open("examples/synthesis/ch2-example-3-spherical.json").read())
    data["positions"][0]["p"][1] = 0.483820
    path = tmp_path / "printed.json"
    path.write_text(json.dumps(data))
    status, _, err = run(capsys, str(path))
    assert status == 2 and "not a rigid spherical motion: |p| − 1 up to 0.00048" in err


def test_planar_tasks_are_not_spatial():
    assert load_spatial_task("examples/synthesis/ch2-example-4.json") is None
    assert load_task("examples/synthesis/ch2-example-4.json") is not None


def test_a_guiding_link_task_finds_the_planted_link(tmp_path, capsys):
    data = json.loads(open("examples/synthesis/guiding-link-rr.json").read())
    data["starts"] = 16
    path = tmp_path / "rr.json"
    path.write_text(json.dumps(data))
    status, out, _ = run(capsys, str(path), "--format", "json")
    doc = json.loads(out)
    u0 = np.array([0.2, 0.1, 1.0]) / np.linalg.norm([0.2, 0.1, 1.0])
    assert status == 0 and any(abs(abs(np.array(g["u0"]) @ u0) - 1) < 1e-9 and np.linalg.norm(g["a0"]) < 1e-9
                               for g in doc["links"])
    data["link"] = "S-P"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match="link: one of S-S"):
        load_spatial_task(path)
