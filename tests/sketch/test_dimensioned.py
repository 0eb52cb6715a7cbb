"""Dimensioned drawings (`domes draw FILE.json`): joint positions and coupler curves read back from the SVG.

The drawing maps the model (y up) into the SVG box (y down) by a scale and a
shift; each test recovers that map by least squares from the drawn joints and
then compares every drawn point with an independent value (closed-form
four-bar geometry, a circle about a fixed pivot, the solver's own output).
"""

import json
import math
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from domes.cli import main
from domes.io.mechanisms import load_mechanism
from domes.motion import solve
from domes.motion.planar.examples import triple_rocker
from domes.sketch.dimensioned import coupler_curves, dimensioned_svg

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
EXAMPLES = os.path.join(ROOT, "examples", "mechanisms")
SVG = "{http://www.w3.org/2000/svg}"
#: Coordinates are written with two decimals: a drawn point is within 0.005·√2 of the exact one.
PX = 0.02


def _elements(svg, cls):
    return [el for el in ET.fromstring(svg).iter() if cls in el.get("class", "").split()]


def _joints(svg):
    return {el.get("data-joint"): (float(el.get("cx")), float(el.get("cy"))) for el in _elements(svg, "joint") if el.tag == SVG + "circle"}


def _polyline(el):
    return [tuple(map(float, p.split(","))) for p in el.get("points").split()]


def _fit(model, drawn):
    """Scale ``k`` and shift ``(a, b)`` with ``x' = a + k x``, ``y' = b − k y`` (least squares), and the map."""
    rows, rhs = [], []
    for (x, y), (u, v) in zip(model, drawn):
        rows += [[x, 1, 0], [-y, 0, 1]]
        rhs += [u, v]
    (k, a, b), *_ = np.linalg.lstsq(np.array(rows, float), np.array(rhs, float), rcond=None)
    return k, lambda p: (a + k * p[0], b - k * p[1]), lambda q: ((q[0] - a) / k, (b - q[1]) / k)


def _four_bar(theta, upper=True):
    """Seed 000 T6 first loop (examples/mechanisms/four-bar.json) in closed form: B, C and coupler point P."""
    b = (math.cos(theta), math.sin(theta))
    d = (3.0, 0.0)
    dist = math.dist(b, d)
    along = (3.5**2 - 2.5**2 + dist**2) / (2 * dist)  # circles |C − B| = 3.5, |C − D| = 2.5
    height = math.sqrt(3.5**2 - along**2)
    ux, uy = (d[0] - b[0]) / dist, (d[1] - b[1]) / dist
    sign = 1 if upper else -1  # the drawn assembly: C to the left of B→D
    c = (b[0] + along * ux - sign * height * uy, b[1] + along * uy + sign * height * ux)
    turn = math.atan2(c[1] - b[1], c[0] - b[0]) - math.atan2(math.sqrt(6.0), 2.5)  # from the drawn pose B0=(1,0), C0=(3.5,√6)
    p0 = (2.0 - 1.0, 2.5)  # P0 − B0
    p = (b[0] + p0[0] * math.cos(turn) - p0[1] * math.sin(turn), b[1] + p0[0] * math.sin(turn) + p0[1] * math.cos(turn))
    return b, c, p


def test_four_bar_joints_are_drawn_where_the_geometry_puts_them(capsys):
    # crank-rocker of seed 000 T6 at crank angle 60°: A, D fixed, B on the crank circle, C by two circles
    assert main(["draw", os.path.join(EXAMPLES, "four-bar.json"), "--at", "60"]) == 0
    svg = capsys.readouterr().out
    b, c, p = _four_bar(math.radians(60))
    model = {"A": (0.0, 0.0), "B": b, "C": c, "D": (3.0, 0.0)}
    drawn = _joints(svg)
    (point,) = _elements(svg, "coupler-point")
    drawn["P"] = (float(point.get("cx")), float(point.get("cy")))
    model["P"] = p
    names = sorted(model)
    k, to_svg, _ = _fit([model[n] for n in names], [drawn[n] for n in names])
    assert k > 0
    for n in names:
        assert math.dist(to_svg(model[n]), drawn[n]) < PX, n
    # every bar is labelled with its length: crank 1, rocker 2.5, frame 3
    lengths = sorted(el.text for el in _elements(svg, "dimension") if el.get("data-link") in ("crank", "rocker", "frame"))
    assert lengths == ["1", "2.5", "3"]


def test_coupler_curve_vertices_lie_on_the_closed_form_path():
    # the coupler curve of P over a full crank turn in 1° steps (accuracy "default"), closed
    mech = load_mechanism(os.path.join(EXAMPLES, "four-bar.json"))
    svg = dimensioned_svg(mech, coupler=["P"])
    (curve,) = _elements(svg, "coupler-curve")
    assert "closed" in curve.get("class").split()
    path = _polyline(curve)
    assert len(path) == 361 and path[0] == path[-1]
    joints = _joints(svg)
    model = [(0.0, 0.0), (1.0, 0.0), (3.5, math.sqrt(6.0)), (3.0, 0.0)]  # the drawn pose (crank at 0°)
    _, to_svg, _ = _fit(model, [joints[n] for n in "ABCD"])
    for k, vertex in enumerate(path[:-1]):
        assert math.dist(vertex, to_svg(_four_bar(math.radians(k))[2])) < PX, k


def test_curve_stops_at_the_located_limits(tmp_path):
    # seed 000 T9: the triple rocker's crank reaches ±arccos(−29/48) = ±127.1689°; the path of its
    # crank pin B is an open arc from limit to limit, each end marked, never across the unreachable arc
    limit = math.acos(-29 / 48)
    path = tmp_path / "triple-rocker.json"
    path.write_text(json.dumps(triple_rocker().to_dict()), encoding="utf-8")
    svg = dimensioned_svg(load_mechanism(str(path)), coupler=["B"])
    (curve,) = _elements(svg, "coupler-curve")
    assert "closed" not in curve.get("class").split()
    assert len(_elements(svg, "dead-point")) == 2
    joints = _joints(svg)
    c = triple_rocker().joint("C").at
    _, _, to_model = _fit([(0.0, 0.0), (2.0, 0.0), c, (3.0, 0.0)], [joints[n] for n in "ABCD"])
    angles = [math.atan2(y, x) for x, y in map(to_model, _polyline(curve))]
    assert angles[0] == pytest.approx(-limit, abs=1e-3) and angles[-1] == pytest.approx(limit, abs=1e-3)
    assert all(b > a for a, b in zip(angles, angles[1:]))  # one way round, through 0, not through 180°
    (traced,) = coupler_curves(triple_rocker(), ["B"])
    assert [d.kind for d in traced.stops] == ["limit", "limit"]
    assert traced.first.input == pytest.approx(-limit, abs=1e-9) and traced.last.input == pytest.approx(limit, abs=1e-9)


def test_slider_and_joints_are_at_the_solver_positions():
    # Watt six-bar with slider (seed 000 Fig. 2 / T6) at crank angle 150°: every joint as solved
    mech = load_mechanism(os.path.join(EXAMPLES, "watt-six-bar.json"))
    q = math.radians(150)
    svg = dimensioned_svg(mech, q)
    names = [j.name for j in mech.joints]
    step = solve(mech, q, outputs=[f"point:{n}" for n in names])
    solved = {n: (step.values[f"point:{n}.x"], step.values[f"point:{n}.y"]) for n in names}
    drawn = _joints(svg)
    (block,) = _elements(svg, "slider-block")
    corners = _polyline(block)
    drawn["g"] = (sum(p[0] for p in corners) / 4, sum(p[1] for p in corners) / 4)  # the block's centre
    _, to_svg, _ = _fit([solved[n] for n in names], [drawn[n] for n in names])
    for n in names:
        assert math.dist(to_svg(solved[n]), drawn[n]) < PX, n
    (rail,) = _elements(svg, "slider-rail")  # the guide on the frame: the line y = −1 from its origin (0, −1)
    start, end = (float(rail.get("x1")), float(rail.get("y1"))), (float(rail.get("x2")), float(rail.get("y2")))
    assert math.dist(start, to_svg((0.0, -1.0))) < PX and math.dist(end, to_svg(solved["g"])) < PX


def test_shock_driven_swing_arm_axle_moves_on_a_circle_about_its_pivot(capsys):
    # the swing arm turns about O, so its axle stays at |O axle| from O; the shock is a cylinder-and-rod
    assert main(["draw", os.path.join(EXAMPLES, "swing-arm-shock.json"), "--coupler", "axle"]) == 0
    svg = capsys.readouterr().out
    mech = load_mechanism(os.path.join(EXAMPLES, "swing-arm-shock.json"))
    (member,) = _elements(svg, "member")
    assert member.get("data-joint") == "shock" and _elements(svg, "cylinder-rod")
    joints = _joints(svg)
    (point,) = _elements(svg, "coupler-point")
    p = solve(mech, None, outputs=["point:O", "point:S1", "point:S2", "point:axle"]).values
    model = [(p[f"point:{n}.x"], p[f"point:{n}.y"]) for n in ("O", "S1", "S2", "axle")]
    k, _, _ = _fit(model, [joints["O"], joints["S1"], joints["S2"], (float(point.get("cx")), float(point.get("cy")))])
    (curve,) = _elements(svg, "coupler-curve")
    radius = math.dist((0.0, 0.0), (6.0, 0.2)) * k
    path = _polyline(curve)
    assert all(abs(math.dist(v, joints["O"]) - radius) < PX for v in path)
    # near the limits the axle swings fast as s changes: steps are halved until it moves at most step·size
    chord = math.radians(1) * mech.size * k  # accuracy "default": step 1° (× size for a P input)
    assert max(math.dist(a, b) for a, b in zip(path, path[1:])) <= chord + PX
    # the shock length s runs between |OS2| − |OS1| and |OS2| + |OS1|, where S1, O, S2 line up
    (traced,) = coupler_curves(mech, ["axle"])
    reach = sorted(d.input for d in traced.stops)
    arm, frame = math.dist((0, 0), (4.0, 0.8)), math.dist((0, 0), (0.5, 3.0))
    assert reach == pytest.approx([arm - frame, arm + frame], abs=1e-6)


def test_same_file_same_bytes_across_processes():
    outputs = []
    for seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        command = [sys.executable, "-m", "domes", "draw", "examples/mechanisms/eight-bar-class-iv.json", "--at", "50", "--coupler", "K", "R"]
        outputs.append(subprocess.run(command, cwd=ROOT, env=env, capture_output=True, check=True).stdout)
    assert outputs[0] == outputs[1] and outputs[0].startswith(b"<svg")


@pytest.mark.parametrize(
    "args, message",
    [
        (["draw", "examples/mechanisms/four-bar.json", "--coupler", "Q"], "no coupler point or joint 'Q'"),
        (["draw", "examples/mechanisms/four-bar.json", "--ground", "1"], "only for a chain"),
        (["draw", "Cr", "--coupler", "P"], "only for a mechanism file"),
        (["draw", "examples/mechanisms/missing.json"], "cannot read"),
        (["draw", "examples/mechanisms/swing-arm-shock.json", "--at", "20"], "not reachable"),
        (["draw", "examples/mechanisms/four-bar.json", "--sweep", "0:x"], "--sweep"),
    ],
)
def test_draw_file_errors(args, message, capsys, monkeypatch):
    monkeypatch.chdir(ROOT)
    assert main(args) == 2
    assert message in capsys.readouterr().err
