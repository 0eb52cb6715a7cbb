"""The mechanism editor (issue 30, item 2): its routes against the kinematics library, and the panel in a browser."""

from __future__ import annotations

import base64
import json
import math
from pathlib import Path

import numpy as np
import pytest

from domes.io.mechanisms import load_mechanism
from domes.model.mechanism import CouplerPoint, Mechanism
from domes.motion import sweep
from domes.motion.planar.examples import four_bar, parallelogram, triple_rocker
from domes.motion.planar.query import Kinematics
from domes.motion.spatial.examples import rssr
from tests.shared import studio_server

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


def traced_four_bar() -> Mechanism:
    """The library's crank-rocker with a point on its coupler."""
    m = four_bar()
    return Mechanism.build(m.name, m.links, m.ground, m.joints, m.inputs, points=[CouplerPoint("P", "coupler", (2.0, 3.0))],
                           link_angles=dict(m.link_angles))


def kernel_curve(mech: Mechanism, name: str, samples: int = 360) -> np.ndarray:
    """The point ``name`` over a full turn of the input from the drawn pose, by the library's sweep."""
    q0 = Kinematics(mech).drawn_inputs()[mech.inputs[0].joint]
    sw = sweep(mech, q0, q0 + 2 * math.pi, 2 * math.pi / samples, outputs=[f"point:{name}"])
    return np.column_stack([sw.column(f"point:{name}.x"), sw.column(f"point:{name}.y")])[:samples]


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    """One ``domes studio`` for this module's page tests, started once (each test opens a page of its own; none
    writes to the data folder): its address."""
    yield from studio_server(tmp_path_factory.mktemp("home"))


def solve(client, mech, **extra):
    data = mech if isinstance(mech, dict) else mech.to_dict()
    r = client.post("/api/mechanism/solve", json={"mechanism": data, **extra})
    assert r.status_code == 200, r.text
    return r.json()


def test_solve_answers_the_kernels_motion(client):
    mech = traced_four_bar()
    a = solve(client, mech)
    assert a["full_turn"] and a["status"] == "complete" and a["reachable"][1] - a["reachable"][0] == pytest.approx(360)
    (curve,) = a["curves"]
    assert curve["point"] == "P" and curve["closed"] and len(curve["points"]) == 360
    np.testing.assert_allclose(curve["points"], kernel_curve(mech, "P"), rtol=0, atol=1e-9)
    for joint in "ABCD":
        np.testing.assert_allclose(a["positions"][joint], kernel_curve(mech, joint), rtol=0, atol=1e-9)
    assert a["inputs"][0] == pytest.approx(0.0) and a["inputs"][90] == pytest.approx(90.0)
    assert a["dead_points"] == [] and a["modes"]["current"] == "+" and a["modes"]["available"] == ["+", "-"]
    packed = solve(client, mech, encoding="f64", samples=36)
    xy = np.frombuffer(base64.b64decode(packed["curves"][0]["points"]), dtype="<f8").reshape(-1, 2)
    np.testing.assert_allclose(xy, kernel_curve(mech, "P", 36), rtol=0, atol=1e-9)


def test_a_rocker_stops_at_its_limits_and_a_parallelogram_reports_its_branch_points(client):
    a = solve(client, triple_rocker(), trace=["C"])
    limit = math.degrees(math.acos(-29 / 48))          # seed 000 T9: the closed form of the limit
    assert not a["full_turn"] and [d["kind"] for d in a["dead_points"]] == ["limit", "limit"]
    assert [d["input"] for d in a["dead_points"]] == pytest.approx([-limit, limit], abs=1e-6)
    assert a["reachable"] == pytest.approx([-limit, limit], abs=1e-6) and len(a["curves"][0]["points"]) == 360
    mech = triple_rocker()
    for k in (0, 123, 359):                              # each answered step is the kernel's pose at its input
        q = math.radians(a["inputs"][k])
        sw = sweep(mech, 0.0, q, abs(q) / 200 or None, outputs=["point:C"])
        assert a["curves"][0]["points"][k] == pytest.approx([sw.column("point:C.x")[-1], sw.column("point:C.y")[-1]],
                                                           abs=1e-9)
    b = solve(client, parallelogram(), trace=["C"])
    branch = [d for d in b["dead_points"] if d["kind"] == "bifurcation"]
    assert b["full_turn"] and [d["input"] for d in branch] == pytest.approx([180.0, 360.0], abs=1e-5)
    assert all(d["at"]["C"][1] == pytest.approx(0.0, abs=1e-7) for d in branch)   # all four joints on the frame line


def test_switching_the_assembly_mode_redraws_the_same_links(client):
    mech = traced_four_bar()
    a = solve(client, mech, mode="-")
    other = Mechanism.from_dict(a["mechanism"])
    lengths = lambda m, pairs: [math.dist(m.joint(p).at if p in "ABCD" else m.point(p)[1], m.joint(q).at)  # noqa: E731
                                for p, q in pairs]
    pairs = [("A", "B"), ("B", "C"), ("C", "D"), ("A", "D"), ("P", "B"), ("P", "C")]
    assert lengths(other, pairs) == pytest.approx(lengths(mech, pairs), abs=1e-12)
    assert other.joint("C").at[1] < 0 < mech.joint("C").at[1]          # C mirrored below the line from B to D
    assert a["modes"]["current"] == "-"
    np.testing.assert_allclose(a["curves"][0]["points"], kernel_curve(other, "P"), rtol=0, atol=1e-9)
    r = client.post("/api/mechanism/solve", json={"mechanism": mech.to_dict(), "mode": "+-"})
    assert r.status_code == 400 and "one '+' or '-' per two-mode dyad (1: " in r.json()["error"]


def test_every_assembly_mode_of_a_six_bar_with_a_slider(client):
    mech = load_mechanism(EXAMPLES / "watt-six-bar.json")
    modes = solve(client, mech, samples=36)["modes"]
    assert modes["current"] == "++" and sorted(modes["available"]) == ["++", "+-", "-+", "--"]
    for mode in modes["available"]:
        a = solve(client, mech, mode=mode, trace=["e", "g"])
        other = load_mechanism(EXAMPLES / "watt-six-bar.json") if mode == "++" else Mechanism.from_dict(a["mechanism"])
        assert a["modes"]["current"] == mode
        for link in mech.links:                     # every link keeps its shape
            names = [j.name for j in mech.joints_of(link) if j.kind == "R"]
            assert [math.dist(other.joint(p).at, other.joint(q).at) for p in names for q in names] == pytest.approx(
                [math.dist(mech.joint(p).at, mech.joint(q).at) for p in names for q in names], abs=1e-12)
        for name, curve in zip("eg", a["curves"]):
            np.testing.assert_allclose(curve["points"], kernel_curve(other, name), rtol=0, atol=1e-9)


def test_bad_input_to_solve_says_what_is_wrong(client):
    data = traced_four_bar().to_dict()
    data["joins"] = data.pop("joints")
    r = client.post("/api/mechanism/solve", json={"mechanism": data})
    assert r.status_code == 400 and "did you mean 'joints'" in r.json()["error"]
    r = client.post("/api/mechanism/solve", json={"mechanism": traced_four_bar().to_dict(), "samples": 3})
    assert r.status_code == 400 and "samples" in r.json()["error"]
    r = client.post("/api/mechanism/solve", json={"mechanism": traced_four_bar().to_dict(), "trace": ["Q"]})
    assert r.status_code == 400 and "'Q'" in r.json()["error"]


def test_save_writes_what_the_command_line_loads(client, home):
    mech = traced_four_bar()
    r = client.post("/api/mechanism/save", json={"name": "mechanisms/mine.json", "mechanism": mech.to_dict()})
    assert r.status_code == 200, r.text
    assert load_mechanism(home / "mechanisms" / "mine.json").to_dict() == mech.to_dict()
    assert "mechanisms/mine.json" in client.get("/api/files").json()["files"]


def test_save_refuses_a_broken_mechanism_and_writes_nothing(client, home):
    data = traced_four_bar().to_dict()
    data["joints"][2]["links"] = ["coupler", "rod"]
    r = client.post("/api/mechanism/save", json={"name": "broken.json", "mechanism": data})
    assert r.status_code == 400 and "broken.json" in r.json()["error"] and "rod" in r.json()["error"]
    collinear = traced_four_bar().to_dict()            # the rocker's joint on the line B-D: a drawn dead point
    collinear["joints"][2]["at"] = [2.0, 0.0]
    collinear["joints"][1]["at"] = [1.0, 0.0]
    r = client.post("/api/mechanism/save", json={"name": "dead.json", "mechanism": collinear})
    assert r.status_code == 400, r.text
    r = client.post("/api/mechanism/save", json={"name": "mine.txt", "mechanism": traced_four_bar().to_dict()})
    assert r.status_code == 400 and ".json" in r.json()["error"]
    assert sorted(p.name for p in home.iterdir()) == ["casebase.db"]


def test_save_outside_the_data_folder_is_refused(client, home, tmp_path):
    for name in ("../outside.json", str(tmp_path / "outside.json")):
        r = client.post("/api/mechanism/save", json={"name": name, "mechanism": traced_four_bar().to_dict()})
        assert r.status_code == 403 and "outside the studio's data folder" in r.json()["error"]
    assert not (tmp_path / "outside.json").exists()


def test_examples_are_the_shipped_mechanisms_and_the_librarys_linkages(client):
    from domes.io.resources import shipped_data
    from domes.studio.mechanism import read_mechanism

    found = client.get("/api/mechanism/examples").json()["examples"]
    shipped = sorted(p.name for p in (shipped_data() / "knowledge" / "mechanisms").glob("*.json"))
    assert [x["source"] for x in found][:len(shipped)] == [f"knowledge/mechanisms/{n}" for n in shipped]
    assert any(x["mechanism"].get("space") == "spatial" for x in found)
    for x in found:
        read_mechanism(x["mechanism"], x["source"])       # each loads as the command line would


def test_a_spatial_mechanism_is_answered_with_its_turning_view(client):
    from domes.motion.spatial.loops import Loops
    from domes.motion.spatial.sweep import spatial_sweep
    from domes.sketch.spatial import spatial_svg

    a = solve(client, rssr(), azimuth=10, elevation=20, step=3, page=True)
    assert a["space"] == "spatial" and a["step"] == 3 and a["steps"] == 73
    assert a["input"] == pytest.approx(15.0) and "window.domesView" in a["html"]
    state = spatial_sweep(rssr(), 0.0, math.radians(15), math.radians(5)).states[-1]     # domes draw's view there
    assert a["svg"] == spatial_svg(rssr(), Loops(rssr()).places(state), None, 520.0, (10.0, 20.0))
    assert "html" not in solve(client, rssr(), azimuth=-30)
    r = client.post("/api/mechanism/solve", json={"mechanism": rssr().to_dict(), "step": 99})
    assert r.status_code == 400 and "step" in r.json()["error"]


# -- in the browser ------------------------------------------------------------------------------------------


def _open(page, mech):
    page.click("#tabs button[data-panel=editor]")
    page.evaluate("([m, n]) => Studio.openInEditor(m, n)", [mech, None])
    page.wait_for_function("() => window.studioEditor.idle() && document.querySelector('#panel-editor .editor-canvas "
                           "circle.handle')")


def test_dragging_a_ground_pivot_redraws_the_kernels_coupler_curve(page):
    mech = traced_four_bar()
    _open(page, mech.to_dict())
    handle = page.locator("#panel-editor circle.handle[data-name=D]").bounding_box()
    x, y = handle["x"] + handle["width"] / 2, handle["y"] + handle["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(x + 4 * k, y - 3 * k)
    page.mouse.up()
    page.wait_for_function("() => window.studioEditor.idle()")
    state = page.evaluate("() => ({m: window.studioEditor.state.mechanism, k: window.studioEditor.state.view.k, "
                          "curve: document.querySelector('#panel-editor .coupler-curve').dataset.points})")
    moved = Mechanism.from_dict(state["m"])
    d0, d1 = np.array(mech.joint("D").at), np.array(moved.joint("D").at)
    assert d1 - d0 == pytest.approx([40 / state["k"], 30 / state["k"]], abs=1.5 / state["k"])   # where the mouse went
    drawn = np.array(json.loads(state["curve"]))
    assert drawn.shape == (360, 2)
    np.testing.assert_allclose(drawn, kernel_curve(moved, "P"), rtol=0, atol=1e-6 * moved.size)
    assert len(page.evaluate("() => window.studioEditor.timings")) >= 1


def test_a_drag_where_the_linkage_cannot_be_drawn_says_so_and_keeps_the_last_good_drawing(page):
    mech = traced_four_bar()
    _open(page, mech.to_dict())
    c = page.locator("#panel-editor circle.handle[data-name=C]").bounding_box()
    b = page.locator("#panel-editor circle.handle[data-name=B]").bounding_box()
    page.mouse.move(c["x"] + c["width"] / 2, c["y"] + c["height"] / 2)
    page.mouse.down()
    page.mouse.move(b["x"] + b["width"] / 2 + 2, b["y"] + b["height"] / 2 - 1)   # C onto B (snapped to it)
    page.wait_for_function("() => window.studioEditor.idle()")
    status = page.locator("#panel-editor .status")
    assert "collinear in the drawn pose" in status.text_content() and "error" in status.get_attribute("class")
    drawn = np.array(json.loads(page.locator("#panel-editor .coupler-curve").get_attribute("data-points")))
    page.mouse.up()
    np.testing.assert_allclose(drawn, kernel_curve(mech, "P"), rtol=0, atol=1e-6 * mech.size)
    page.wait_for_function("() => window.studioEditor.idle() && window.studioEditor.state.failed === null")
    at = page.evaluate("() => window.studioEditor.state.mechanism.joints.find(j => j.name === 'C').at")
    assert at == pytest.approx(mech.joint("C").at, abs=1e-12)          # back where it was before the drag
    assert "back to the last position that solved" in status.text_content()


def test_a_spatial_file_shows_the_turning_view(page):
    _open_spatial = rssr().to_dict()
    page.click("#tabs button[data-panel=editor]")
    page.evaluate("([m]) => Studio.openInEditor(m, 'rssr.json')", [_open_spatial])
    page.wait_for_selector("#panel-editor .spatial-view svg .joint")
    assert page.locator("#panel-editor .spatial-view svg .joint").count() == 4
    assert page.locator("#panel-editor .editor-planar").is_hidden()
