"""The synthesis panel: four-bars for a sketched path, and for precision positions of a body.

Every answer is measured again here with the kinematics kernel (domes.motion.planar.batch) on the mechanism
file the route returned: the path's points against the coupler curve on both assembly modes, the guided
body's point and turn at each precision position.
"""

from __future__ import annotations

import json
import math
import shutil

import numpy as np
import pytest

from domes.model.mechanism import Mechanism
from domes.motion.planar.batch import batch
from tests.shared import shared_file, studio_server

#: Example 2 of seed 002 §2-3: four positions, the circle points on the lines x = -1 and x = 0.
EXAMPLE_2 = [[1.0, 1.0, 0.0], [2.0, 0.5, 0.0], [3.0, 1.5, 45.0], [2.0, 2.0, 90.0]]


@pytest.fixture(scope="module")
def atlas(tmp_path_factory):
    """A small atlas (40 four-bars, coupler points every 1.0) and its open-path index, built once in a test run
    (tests/shared.py): its table, and the files by the names ``domes curves match`` gives the small one's."""
    from domes.io.atlas import load_atlas, save_atlas
    from domes.motion.coupler.atlas import AtlasSpec, build, build_windows

    spec = AtlasSpec("test", 40, 1.0)
    closed = shared_file(tmp_path_factory, "fourbar-test40.h5", lambda path: save_atlas(build(spec), path))
    windows = shared_file(tmp_path_factory, "fourbar-test40-open.h5",
                          lambda path: save_atlas(build_windows(spec), path))
    return load_atlas(closed), {"fourbar-small.h5": closed, "fourbar-small-open.h5": windows}


def use_as_small(home, atlas) -> None:
    """Put the test atlas (and its open-path index) where ``domes curves match`` keeps the data folder's small one."""
    (home / "atlas").mkdir(exist_ok=True)
    for name, path in atlas[1].items():
        shutil.copyfile(path, home / "atlas" / name)


def planted(table, every: int = 12) -> np.ndarray:
    """Points of the coupler curve of a crank-rocker near (not in) the atlas: an atlas linkage's lengths changed by
    a few percent, its coupler point off the atlas's grid; turned, scaled and moved."""
    from domes.design.synthesis.fourbars import grashof_class
    from domes.motion.coupler.curves import trace
    from domes.motion.coupler.fourbar import four_bar

    a, b, c, d = next(row for row in table.linkages
                      if grashof_class(*row)[0] == "Grashof crank-rocker" and min(row) >= 0.6)
    curve = trace(four_bar(a * 1.04, b * 0.97, c, d * 1.02, 1.2, 0.8), "P", 720).circuits[0].points
    turn = np.array([[0.8, 0.6], [-0.6, 0.8]])
    return curve[::every] @ turn * 5.0 + [3.0, 2.0]


def crossed(mech: Mechanism) -> dict:
    """The four-bar's other assembly mode at its drawn crank angle: C mirrored in the line BD, P turned with it."""
    at = {j.name: np.array(j.at) for j in mech.joints}
    B, C, D = at["B"], at["C"], at["D"]
    u = (D - B) / np.linalg.norm(D - B)
    C2 = B + 2 * np.dot(C - B, u) * u - (C - B)
    turn = math.atan2(*(C2 - B)[::-1]) - math.atan2(*(C - B)[::-1])
    P = np.array(mech.point("P")[1]) - B
    P2 = B + [P[0] * math.cos(turn) - P[1] * math.sin(turn), P[0] * math.sin(turn) + P[1] * math.cos(turn)]
    return {"C": np.array([C, C2]), "P": np.array([mech.point("P")[1], P2])}


def _segments(curve, p) -> float:
    a, b = curve[:-1], curve[1:]
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0, 1)
    dist = np.linalg.norm(a + t[:, None] * d - p, axis=1)
    return float(np.nanmin(dist)) if np.isfinite(dist).any() else math.inf


def distances(mechanism: dict, points) -> np.ndarray:
    """The distance of each point from the coupler curve of P, both assembly modes, by the kernel: the nearest of
    20,001 crank angles, then 401 around it."""
    mech = Mechanism.from_dict(mechanism)
    modes = crossed(mech)
    grid = np.linspace(-math.pi, math.pi, 20001)
    coarse = batch(mech, coordinates=modes, inputs=grid, outputs=["point:P"])
    xy = np.stack([coarse.values["point:P.x"], coarse.values["point:P.y"]], axis=-1)       # (2 modes, n, 2)
    pts = np.asarray(points, dtype=float)
    h = grid[1] - grid[0]
    out = []
    for p in pts:
        best = math.inf
        for m in range(2):
            d = np.linalg.norm(xy[m] - p, axis=1)
            if not np.isfinite(d).any():
                continue
            k = int(np.nanargmin(d))
            fine = batch(mech, coordinates={n: v[m:m + 1] for n, v in modes.items()},
                         inputs=np.linspace(grid[k] - 2 * h, grid[k] + 2 * h, 401), outputs=["point:P"])
            local = np.c_[fine.values["point:P.x"][0], fine.values["point:P.y"][0]]
            best = min(best, _segments(local, p), _segments(xy[m], p))
        out.append(best)
    return np.array(out)


def size(points) -> float:
    return float(np.max(np.ptp(np.asarray(points, dtype=float), axis=0)))


# -- the path route -------------------------------------------------------------------------------------------

def test_path_recovers_a_planted_four_bar(client, home, atlas):
    use_as_small(home, atlas)
    assert client.post("/api/synthesis/prepare", json={}).json() == {"preparing": "file", "closed": True}
    points = planted(atlas[0])
    r = client.post("/api/synthesis/path", json={"points": points.tolist(), "results": 1})
    assert r.status_code == 200, r.text
    answer = r.json()
    assert "fourbar-small.h5 in the data folder" in answer["atlas"]
    best = answer["fits"][0]
    assert best["success"] and best["error"]["max"] <= 1e-6
    measured = distances(best["mechanism"], points) / size(points)
    assert measured.max() <= 1e-6
    assert abs(measured.max() - best["error"]["max"]) <= 1e-8
    assert abs(math.sqrt(np.mean(measured ** 2)) - best["error"]["rms"]) <= 1e-8
    lengths = Mechanism.from_dict(best["mechanism"])       # a mechanism file the editor opens
    assert {j.name for j in lengths.joints} == {"A", "B", "C", "D"}
    assert best["input_turns"] == (best["grashof"].endswith(("crank-rocker", "double crank")))
    curve = np.array(best["curves"][best["nearest"]])
    gaps = [np.min(np.linalg.norm(curve - p, axis=1)) for p in points]
    assert max(gaps) <= 0.02 * size(points)                # the curve drawn is the one through the points


def test_path_matches_an_open_stretch(client, home, atlas):
    use_as_small(home, atlas)
    stretch = planted(atlas[0], every=4)[:60]                  # a third of the curve
    r = client.post("/api/synthesis/path", json={"points": stretch.tolist(), "closed": False, "results": 1})
    assert r.status_code == 200, r.text
    answer = r.json()
    assert "fourbar-small-open.h5" in answer["atlas"] and answer["tol"] == 1e-3      # the library's open default
    best = answer["fits"][0]
    measured = distances(best["mechanism"], stretch) / size(stretch)
    assert best["success"] and measured.max() <= 1e-3
    # the route's measure (the library's, on 2,880 crank angles a turn) takes chords too, which may pass a point
    # off the curve a little nearer than the curve does (about 1e-7 of the size here)
    assert abs(measured.max() - best["error"]["max"]) <= 1e-6


@pytest.mark.parametrize("body, said", [
    ({"points": [[0, 0], [1, 0], [1, 1]]}, "at least 9 points"),
    ({"points": [[0, 0]] * 8 + [[1, "a"]]}, "points[8]: [1, 'a'] is not [x, y]"),
    ({"points": "0 0 1 1"}, "points: give a list of [x, y]"),
    ({"points": [[k, k * k] for k in range(12)], "results": 0}, "results: a whole number from 1 to 20"),
    ({"points": [[k, k * k] for k in range(12)], "closed": "yes"}, "closed: true"),
    ({"points": [[k, k * k] for k in range(12)], "tol": -1}, "tol: the largest distance"),
    ({"points": [[k, k * k] for k in range(12)], "atlas": "nowhere.h5"}, "atlas: nowhere.h5 is not a file"),
])
def test_path_refuses_bad_input(client, body, said):
    r = client.post("/api/synthesis/path", json=body)
    assert r.status_code == 400 and said in r.json()["error"], r.text


def test_prepare_refuses_bad_input(client):
    r = client.post("/api/synthesis/prepare", json={"closed": "no"})
    assert r.status_code == 400 and "closed: true or false" in r.json()["error"]


def test_path_refuses_points_that_are_not_finite(client):
    text = json.dumps({"points": [[k, k] for k in range(10)]}).replace("[3, 3]", "[NaN, 3]")
    r = client.post("/api/synthesis/path", content=text, headers={"content-type": "application/json"})
    assert r.status_code == 400 and ("NaN" in r.json()["error"] or "points[3]" in r.json()["error"]), r.text


def test_the_atlas_a_fresh_data_folder_uses(studio, home, atlas):
    from domes.studio.synthesis import atlas_source

    assert atlas_source(studio, "auto", True) == ("quick", "closed")     # no long build before the first answer
    assert atlas_source(studio, "auto", False) == ("quick", "open")
    use_as_small(home, atlas)
    assert atlas_source(studio, "auto", True) == ("file", str(home / "atlas" / "fourbar-small.h5"))
    assert atlas_source(studio, "auto", False) == ("file", str(home / "atlas" / "fourbar-small-open.h5"))


# -- the positions route ----------------------------------------------------------------------------------------

def moved(position, first, point) -> np.ndarray:
    """Where ``point`` of the body (given in its first position) is in ``position`` ([x, y, angle_deg])."""
    t = math.radians(position[2] - first[2])
    q = np.asarray(point, dtype=float) - first[:2]
    return np.array(position[:2]) + [q[0] * math.cos(t) - q[1] * math.sin(t), q[0] * math.sin(t) + q[1] * math.cos(t)]


def check_guides(solution: dict, positions) -> None:
    """The four-bar's cranks keep their lengths through every position, and the kernel, driven at each position's
    crank angle, puts the body's point and turn where the position says."""
    mech = Mechanism.from_dict(solution["mechanism"])
    at = {j.name: np.array(j.at) for j in mech.joints}
    scale = size([p[:2] for p in positions])
    first = positions[0]
    assert np.allclose(mech.point("P")[1], first[:2])
    for fixed, moving in (("A", "B"), ("D", "C")):
        radius = np.linalg.norm(at[moving] - at[fixed])
        for p in positions:
            assert abs(np.linalg.norm(moved(p, first, at[moving]) - at[fixed]) - radius) <= 1e-8 * scale
    angles = [math.atan2(*(moved(p, first, at["B"]) - at["A"])[::-1]) for p in positions]
    out = batch(mech, inputs=angles, outputs=["point:P", "angle:coupler"]).values
    turn0 = out["angle:coupler"][0, 0]
    for j, p in enumerate(positions):
        assert math.hypot(out["point:P.x"][0, j] - p[0], out["point:P.y"][0, j] - p[1]) <= 1e-8 * scale
        assert abs(math.remainder(out["angle:coupler"][0, j] - turn0 - math.radians(p[2] - first[2]), 2 * math.pi)) \
            <= 1e-8


def test_four_positions_give_the_curves_and_four_bars_through_them(client):
    r = client.post("/api/synthesis/positions", json={"positions": EXAMPLE_2, "circle_x": [-1, 0]})
    assert r.status_code == 200, r.text
    answer = r.json()
    usable = [s for s in answer["solutions"] if s["usable"]]
    assert usable and len(answer["dyads"]) == 6                    # three cranks on each line (digest S-08)
    for s in usable:
        check_guides(s, EXAMPLE_2)
    on_zero = sorted(d["circle"][1] for d in answer["dyads"] if abs(d["circle"][0]) < 1e-12)
    assert np.allclose(on_zero, [-1.915055, 1.488794, 2.736921], atol=1e-6)
    (curve,) = answer["curves"]
    assert curve["positions"] == [1, 2, 3, 4] and len(curve["circle"]) > 100
    from domes.design.synthesis.guidance import Position, circle_points_at

    pos = [Position(tuple(p[:2]), math.radians(p[2])) for p in EXAMPLE_2]
    for x, y in curve["circle"][::25]:                             # each sampled point is on the cubic
        assert min(abs(y - yy) for yy in circle_points_at(pos, x)) <= 1e-6


def test_five_positions_of_a_coupler_give_its_cranks(client):
    from domes.motion.coupler.fourbar import four_bar

    mech = four_bar(1.0, 3.0, 2.5, 3.2, 1.0, 1.5, theta=0.3)
    grid = np.radians([20, 60, 110, 160, 215])
    out = batch(mech, inputs=grid, outputs=["point:P", "angle:coupler"]).values
    positions = [[float(out["point:P.x"][0, j]), float(out["point:P.y"][0, j]),
                  float(math.degrees(out["angle:coupler"][0, j]))] for j in range(5)]
    r = client.post("/api/synthesis/positions", json={"positions": positions})
    assert r.status_code == 200, r.text
    answer = r.json()
    assert len(answer["curves"]) == 2 and answer["needs"] is None
    pivots = {j.name: np.array(j.at) for j in mech.joints}
    centres = [np.array(d["centre"]) for d in answer["dyads"]]
    for name in ("A", "D"):                                        # the planted cranks' fixed pivots are found
        assert min(np.linalg.norm(c - pivots[name]) for c in centres) <= 1e-6
    assert any(s["usable"] for s in answer["solutions"])
    for s in answer["solutions"]:
        if s["usable"]:
            check_guides(s, positions)


@pytest.mark.parametrize("body, said", [
    ({"positions": [[0, 0, 0], [1, 0, 10]]}, "3, 4 or 5 precision positions"),
    ({"positions": [[0, 0, 0], [1, 0, 10], [2, None, 20]]}, "positions[2]: [2, None, 20] is not [x, y, angle_deg]"),
    ({"positions": [[0, 0, 0], [0, 0, 0], [1, 1, 30], [2, 1, 40]]}, "coincide"),
    ({"positions": EXAMPLE_2, "circle_x": [1]}, "circle_x"),
])
def test_positions_refuse_bad_input(client, body, said):
    r = client.post("/api/synthesis/positions", json=body)
    assert r.status_code == 400 and said in r.json()["error"], r.text


def test_three_positions_ask_for_their_circle_points(client):
    three = EXAMPLE_2[:3]
    answer = client.post("/api/synthesis/positions", json={"positions": three}).json()
    assert answer["solutions"] == [] and "circle points" in answer["needs"]
    four = client.post("/api/synthesis/positions", json={"positions": EXAMPLE_2, "circle_x": [-1, 0]}).json()
    at = {j["name"]: j["at"] for j in next(s for s in four["solutions"] if s["usable"])["mechanism"]["joints"]}
    answer = client.post("/api/synthesis/positions", json={"positions": three,          # its moving pivots
                                                           "circle_points": [at["B"], at["C"]]}).json()
    usable = [s for s in answer["solutions"] if s["usable"]]
    assert len(usable) == 1
    check_guides(usable[0], three)


# -- the page ---------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def page_home(tmp_path_factory):
    """The data folder of the studio this module's page tests share."""
    return tmp_path_factory.mktemp("home")


@pytest.fixture(scope="module")
def server(page_home):
    """One ``domes studio`` for this module's page tests, started once: its address."""
    yield from studio_server(page_home)


def test_a_sketched_path_is_matched_on_the_page(page, page_home, atlas):
    use_as_small(page_home, atlas)
    page.click("#tabs button[data-panel=synthesis]")
    page.fill("#synthesis-results", "1")
    # a path drawn to the pixel has no exact four-bar: asked to fit within the pixels' 5e-3 of its size, the match
    # stops at the first candidate that does instead of refining every one of them in vain at the default 1e-6
    page.fill("#synthesis-tol", "0.005")
    box = page.locator("#synthesis-path-pad").bounding_box()
    curve = planted(atlas[0], every=3)
    lo, hi = curve.min(axis=0), curve.max(axis=0)
    scale = 0.7 * min(box["width"] / (hi - lo)[0], box["height"] / (hi - lo)[1])
    centre = (lo + hi) / 2
    screen = [(box["x"] + box["width"] / 2 + scale * (x - centre[0]), box["y"] + box["height"] / 2 - scale * (y - centre[1]))
              for x, y in curve]
    page.mouse.move(*screen[0])
    page.mouse.down()
    for x, y in screen[1:] + screen[:1]:
        page.mouse.move(x, y)
    page.mouse.up()
    assert page.locator("#synthesis-path-pad .synthesis-point").count() == 48         # the resampled points shown
    page.click("#synthesis-match")
    page.wait_for_selector("#synthesis-fits li, #synthesis-path-status.error", timeout=60000)    # (no eval: the CSP)
    last = page.evaluate("window.studioSynthesis.last")
    assert last["error"] is None, last["error"]
    assert last["request"]["tol"] == 0.005
    points, fit = last["request"]["points"], last["answer"]["fits"][0]
    shown = float(page.text_content("#synthesis-fits li[data-rank='1'] .error-max"))
    measured = distances(fit["mechanism"], points).max() / size(points)
    assert measured <= 5e-3                                      # a path drawn to the pixel
    assert abs(measured - shown) <= 0.006 * shown + 1e-9         # what the page says (3 digits)
    page.evaluate("window.addEventListener('domes:open', e => { window.opened = e.detail; })")
    page.click("#synthesis-fits li[data-rank='1'] button.open")
    assert page.evaluate("window.opened.mechanism") == fit["mechanism"]


def test_precision_positions_placed_on_the_page(page):
    page.click("#tabs button[data-panel=synthesis]")
    page.locator("#synthesis-guide").scroll_into_view_if_needed()            # the pad and its button in view
    a, d, e, f = page.evaluate("(() => { const m = document.getElementById('synthesis-positions-pad')"
                               ".getScreenCTM(); return [m.a, m.d, m.e, m.f]; })()")

    def screen(x, y):                                        # the pad's first view: (5, 3.5) in the middle, 50 to 1
        return e + a * (320 + 50 * (x - 5)), f + d * (210 - 50 * (y - 3.5))

    for x, y, _ in EXAMPLE_2:                                # click to place
        page.mouse.click(*screen(x, y))
    assert page.locator("#synthesis-positions-pad .synthesis-body").count() == 4
    handle = page.locator("#synthesis-positions-pad circle.handle[data-index='3']").bounding_box()
    page.mouse.move(handle["x"] + handle["width"] / 2, handle["y"] + handle["height"] / 2)
    page.mouse.down()                                        # drag the handle of position 4 straight above it
    x4, y4 = screen(*EXAMPLE_2[3][:2])
    page.mouse.move(x4, y4 - 30, steps=5)
    page.mouse.up()
    page.fill("#panel-synthesis tbody input[data-index='2'][data-k='2']", "45")      # type the angle of position 3
    page.press("#panel-synthesis tbody input[data-index='2'][data-k='2']", "Tab")
    page.fill("#synthesis-choices", "-1; 0")
    page.click("#synthesis-guide")
    page.wait_for_selector("#synthesis-fourbars li, #synthesis-positions-status.error", timeout=30000)
    last = page.evaluate("window.studioSynthesis.lastPositions")
    assert last["error"] is None, last["error"]
    sent = last["request"]["positions"]
    assert np.allclose(sent, EXAMPLE_2, atol=2e-3), sent
    usable = [s for s in last["answer"]["solutions"] if s["usable"]]
    assert usable and last["request"]["circle_x"] == [-1, 0]
    for s in usable:
        check_guides(s, sent)
    page.evaluate("window.addEventListener('domes:open', e => { window.opened = e.detail; })")
    page.click("#synthesis-fourbars li[data-rank='1'] button.open")
    assert page.evaluate("window.opened.mechanism") == last["answer"]["solutions"][0]["mechanism"]
