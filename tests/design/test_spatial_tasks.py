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
    data["starts"] = 8                          # of the example's 48: the planted link is found from 4 already
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


def test_an_rssr_function_task_returns_the_seed_001_cranks(capsys, tmp_path):
    """Seed 002 §2-3 (digest A.3.4): an RSSR meets seven precision pairs; the example's pairs come from the sweep
    of the seed 001 §3 RSSR (L1 = 250, L3 = 550 mm) with a 100 mm axis offset, and its cranks are among the
    solutions, each moved to its points by the spatial sweep."""
    status, out, _ = run(capsys, "examples/synthesis/rssr-function.json", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and doc["method"] == "exact" and doc["worst"] < 1e-9
    assert any(abs(s["crank"] - 250) < 1e-5 and abs(s["rocker"] - 550) < 1e-5 for s in doc["solutions"])
    assert all(s["swept_error"] < 1e-9 and s["defect"] == "" for s in doc["solutions"])
    assert len(doc["mechanisms"]) == len(doc["solutions"]) >= 1


@pytest.mark.parametrize("change, message", [
    (lambda d: d["precision_deg"].append([130, 40]), "precision_deg: 2 to 7"),
    (lambda d: d["input_axis"].pop("direction"), "input_axis"),
    (lambda d: d.update(method="guess"), "method: one of"),
    (lambda d: d.update(starts=0), "starts: an integer from 1"),
    (lambda d: d.update(sweep="yes"), "sweep: true or false"),
    (lambda d: d.update(fixed=[1, 2]), "fixed:"),
])
def test_rssr_task_mistakes_are_named(tmp_path, change, message):
    data = json.loads(open("examples/synthesis/rssr-function.json").read())
    change(data)
    path = tmp_path / "t.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match=message):
        load_spatial_task(path)


def test_five_precision_points_return_the_generator_they_came_from(capsys):
    """Seed 002 §2-3 (digest A.3.4): five precision pairs with the output axis angle given fix a spherical
    four-bar function generator; the example's pairs are the motion of a1 = (0.8, 0.6, 0), b1 = (0.36, 0.48, 0.8)
    at α = 70°, and the exhaustive method returns it, moved to its points by the closed-form analysis."""
    status, out, _ = run(capsys, "examples/synthesis/spherical-function-five.json", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and doc["method"].startswith("exhaustive") and doc["worst"] < 1e-9
    assert any(np.allclose(s["a1"], (0.8, 0.6, 0), atol=1e-8) and np.allclose(s["b1"], (0.36, 0.48, 0.8), atol=1e-8)
               for s in doc["solutions"])
    assert len(doc["mechanisms"]) == len(doc["solutions"])


def test_measured_example_3_is_fitted_to_its_sphere_before_synthesis(capsys):
    """Seed 002 §2-3 (2-87)-(2-89) and Example 3: the orthosis data placed about a hip centre at (120, −40, 310)
    mm with radius 95 mm (to 0.1 µm) is fitted and normalised; fixing a0x = −0.25 then gives the book's crank
    a0 = (−0.2500, 0.1900, 0.9494), a1 = (−0.5839, −0.3149, 0.7482) to its printed four digits."""
    status, out, _ = run(capsys, "examples/synthesis/ch2-example-3-measured.json", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and "fitted to concentric spheres, centre (120, -40" in doc["lines"][0]
    assert any(np.allclose(c["a0"], (-0.25, 0.19, 0.9494), atol=1e-4)
               and np.allclose(c["a1"], (-0.5839, -0.3149, 0.7482), atol=1e-4) for c in doc["cranks"])


@pytest.mark.parametrize("change, message", [
    (lambda d: d.pop("alpha_deg"), "alpha_deg: the output axis angle is needed"),
    (lambda d: d.update(fixed={"b1x": 0.3}), "leave 0 of the pivots"),
    (lambda d: d["precision_deg"].extend([[50, 1], [60, 2]]), "precision_deg: 2 to 6"),
])
def test_spherical_generator_task_mistakes_are_named(tmp_path, change, message):
    data = json.loads(open("examples/synthesis/spherical-function-five.json").read())
    change(data)
    path = tmp_path / "t.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match=message):
        task = load_spatial_task(path)
        from domes.design.synthesis.spatialtask import solve_spatial
        solve_spatial(task)


def test_a_spherical_path_task_finds_the_linkage_it_came_from(capsys):
    """Seed 002 §2-3, Table 2-2: seven points on the sphere with the spins β12, β13 given; the points are the
    coupler point of the linkage named in the file's comment (to its six printed digits), which is among the
    solutions (an axis and its opposite are one pivot), every solution moved to the points by the spatial
    solver."""
    status, out, _ = run(capsys, "examples/synthesis/spherical-path-seven.json", "--format", "json")
    doc = json.loads(out)
    a0, b0 = np.array((0.003034, 0.736797, -0.676107)), np.array((-0.632398, -0.322856, -0.704156))
    assert status == 0 and doc["method"] == "seeded" and doc["worst"] < 1e-9
    assert (doc["equations"], doc["unknowns"], len(doc["given"])) == (16, 18, 2)
    assert any(abs(abs(np.dot(s["a0"], a0)) - 1) < 1e-5 and abs(abs(np.dot(s["b0"], b0)) - 1) < 1e-5
               for s in doc["solutions"])
    assert len(doc["mechanisms"]) == len(doc["solutions"])


def test_spherical_path_task_mistakes_are_named(tmp_path):
    data = json.loads(open("examples/synthesis/spherical-path-seven.json").read())
    data["points"][2] = [1, 1, 1]
    path = tmp_path / "t.json"
    path.write_text(json.dumps(data))
    with pytest.raises(InputError, match="normalise"):
        from domes.design.synthesis.spatialtask import solve_spatial
        solve_spatial(load_spatial_task(path))


def test_an_rrss_path_task_finds_the_linkage_it_came_from(capsys):
    """Seed 002 §2-3, Fig. 2-25, Table 2-3: five points in space with six free choices (u0x, a0, b0x, b0y); the
    points are the coupler point of the RRSS named in the file's comment, which is among the solutions (axes up
    to their sign), driven through the points by the spatial solver."""
    status, out, _ = run(capsys, "examples/synthesis/rrss-path-five.json", "--format", "json")
    doc = json.loads(out)
    truth = {"u0": (0.018681, 0.742907, 0.669134), "u1": (-0.644292, -0.376203, -0.665852),
             "a1": (-1.235255, -1.388621, 1.626787), "b0": (0.04556, 0.651372, -0.898765),
             "b1": (-1.086096, 0.864119, 0.511082)}
    assert status == 0 and doc["method"] == "conic"

    def coords(s, name):
        return np.array([s[name + c] for c in "xyz"])

    hits = [s for s in doc["solutions"]
            if all(abs(abs(coords(s, k) @ np.array(truth[k])) - 1) < 1e-5 for k in ("u0", "u1"))
            and all(np.allclose(coords(s, k), truth[k], atol=1e-5) for k in ("a1", "b0", "b1"))]
    assert len(hits) == 1 and hits[0]["path_error"] < 1e-8
    assert all(s["residual"] < 1e-9 for s in doc["solutions"]) and len(doc["mechanisms"]) == len(doc["solutions"])
