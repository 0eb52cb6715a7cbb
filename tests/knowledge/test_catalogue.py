"""The catalogue of standard mechanisms (issue 26, item 7; seed 002 ch. 1 system search, §5-1 second class).

Each entry's claimed property is measured on its model and checked here by an
independent closed form: the four-bars' coupler points by circle
intersection with numpy, the quick return's time ratio from its geometry,
the Geneva wheel from the pin's position in the slot, the toggle press from
the slider-crank's velocity ratio, the ratchet from the crank-rocker's
Grashof extreme positions and a tooth-by-tooth simulation of the pawl.
"""

import dataclasses
import json
import math
import shutil
import subprocess
import sys

import numpy as np
import pytest

from domes.design.catalogue import measure, propose
from domes.errors import InputError
from domes.io.catalogue import load_catalogue
from domes.io.resources import knowledge_dir
from domes.knowledge.catalogue import requirement
from domes.motion.geneva import Geneva
from domes.motion.planar.sweep import sweep
from domes.results import Status

CATALOGUE = {e.name: e for e in load_catalogue()}


def coupler_path(a0, b0, crank, coupler, rocker, point, angles, mode):
    """The coupler point of a four-bar by circle intersection: crank pin on a circle about a0, rocker pin at
    ``coupler`` from it and ``rocker`` from b0 on the side ``mode`` (±1); ``point`` (u, v) in the coupler's frame
    (u along crank pin → rocker pin)."""
    a = np.asarray(a0) + crank * np.c_[np.cos(angles), np.sin(angles)]
    v = np.asarray(b0) - a
    r = np.linalg.norm(v, axis=1)
    x = (coupler ** 2 - rocker ** 2 + r ** 2) / (2 * r)
    h = np.sqrt(coupler ** 2 - x ** 2)
    u = v / r[:, None]
    n = np.c_[-u[:, 1], u[:, 0]]
    b = a + x[:, None] * u + mode * h[:, None] * n
    e = (b - a) / coupler
    en = np.c_[-e[:, 1], e[:, 0]]
    return a + point[0] * e + point[1] * en


def deviation(xy):
    c = xy - xy.mean(axis=0)
    _, _, vt = np.linalg.svd(c)
    along = c @ vt[0]
    return np.max(np.abs(c @ vt[1])) / (along.max() - along.min()) * 100, along.max() - along.min()


@pytest.mark.parametrize("name, geometry, lo, hi", [
    # (a0, b0, crank, coupler, rocker, point (u, v), mode)
    ("Chebyshev straight-line linkage", ((0, 0), (2, 0), 2.5, 1.0, 2.5, (0.5, 0.0), -1), 37, 93),
    ("Hoeken straight-line linkage", ((0, 0), (2, 0), 1.0, 2.5, 2.5, (5.0, 0.0), -1), 90, 270),
    ("Watt straight-line linkage", ((-1, 0.5), (1, -0.5), 1.0, 1.0, 1.0, (0.5, 0.0), -1), -26, 22),
    ("Roberts straight-line linkage", ((0, 0), (2, 0), 1.2, 1.0, 1.2, (0.5, -math.sqrt(1.2 ** 2 - 0.25)), -1), 30, 78),
])
def test_straight_line_linkages_against_circle_intersection(name, geometry, lo, hi):
    got = measure(CATALOGUE[name])
    angles = np.radians(np.arange(lo, hi + 1e-9, 0.05))
    modes = [coupler_path(*geometry[:6], angles, m) for m in (-1, 1)]
    drawn = np.array([float(v) for v in CATALOGUE[name].mechanism.to_dict()["points"][0]["at"]])
    # the assembly mode whose path passes nearest the drawn coupler point
    path = min(modes, key=lambda p: np.min(np.linalg.norm(p - drawn, axis=1)))
    dev, length = deviation(path)
    assert got["straight-line deviation"].value == pytest.approx(dev, rel=1e-6)
    assert got["straight length"].value == pytest.approx(length, rel=1e-9)
    assert dev < 1.5                                        # nearly straight: the catalogue's claim


def test_hoeken_runs_straight_for_half_a_turn_over_twice_its_frame():
    got = measure(CATALOGUE["Hoeken straight-line linkage"])
    assert got["straight length"].value == pytest.approx(4.0, abs=1e-6)     # from x = 4 to x = 0 at y = 4


PEAUCELLIER = "Peaucellier-Lipkin straight-line linkage"


def test_peaucellier_is_exactly_straight_where_chebyshev_is_nearly():
    # The inversor: arms OA = OB = 20 and a rhombus of sides 13 make E (the crank pin) and F (the traced P) inverse
    # points about O, OE · OF = 20² − 13² = 231; E runs on the crank's circle through O (centre C = (5.5, 0), radius
    # 5.5), OE = 11 cos(θ/2), so P runs on the line x = 231 / 11 = 21, at y = 21 tan(θ/2) for the crank angle θ.
    # Measured the same way, Chebyshev's deviation is 0.13 % and the Peaucellier's is rounding.
    got = measure(CATALOGUE[PEAUCELLIER])
    chebyshev = measure(CATALOGUE["Chebyshev straight-line linkage"])["straight-line deviation"].value
    assert chebyshev > 0.1 and got["straight-line deviation"].value < 1e-12       # percent of the length
    assert got["straight length"].value == pytest.approx(2 * 21 * math.tan(math.radians(45)), rel=1e-12)
    mech, size = CATALOGUE[PEAUCELLIER].mechanism, 21.0
    for method in ("assur", "newton"):                      # three RRR dyads after the crank, or Newton on them all
        sw = sweep(mech, math.radians(-90), math.radians(90), math.radians(0.5), outputs=["point:P"], method=method)
        assert sw.status is Status.COMPLETE, sw.message
        assert np.max(np.abs(sw.column("point:P.x") - 21)) <= 1e-9 * size, method
        assert np.max(np.abs(sw.column("point:P.y") - 21 * np.tan(sw.inputs / 2))) <= 1e-9 * size, method
    # the crank only oscillates (its motion is "oscillation"): it stops where OE = 20 − 13, 11 cos(θ/2) = 7
    far = sweep(mech, 0, math.pi, math.radians(1))
    assert far.status is not Status.COMPLETE
    assert math.degrees(far.dead_points[0].input) == pytest.approx(2 * math.degrees(math.acos(7 / 11)), abs=1e-6)
    file = knowledge_dir() / "catalogue" / "peaucellier.json"             # and `domes kinematics` on its file
    run = subprocess.run([sys.executable, "-m", "domes", "kinematics", str(file), "--sweep=-90:90:45", "--outputs",
                          "point:P", "--format", "json"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    steps = json.loads(run.stdout)["steps"]
    assert len(steps) == 5 and all(abs(s["point:P.x"] - 21) <= 1e-9 * size for s in steps)


def test_the_motion_search_finds_the_exact_straight_line():
    found = propose(load_catalogue(), "oscillation -> straight line", ["straight-line deviation <= 1e-9"])
    assert {"Chebyshev straight-line linkage", PEAUCELLIER} <= {p.entry.name for p in found}
    assert [p.entry.name for p in found if p.kept] == [PEAUCELLIER]
    assert PEAUCELLIER not in {p.entry.name for p in propose(load_catalogue(), "rotation -> straight line")}


def test_slider_crank_yoke_and_tangent_against_closed_forms():
    assert measure(CATALOGUE["slider-crank"])["stroke"].value == pytest.approx(2.0, abs=1e-12)      # 2 × crank
    yoke = measure(CATALOGUE["Scotch yoke"])
    assert yoke["stroke"].value == pytest.approx(2.0, abs=1e-12) and yoke["harmonic deviation"].value < 1e-9
    tangent = measure(CATALOGUE["tangent mechanism"])
    assert tangent["tangent deviation"].value < 1e-9
    assert tangent["stroke"].value == pytest.approx(2 * math.tan(math.radians(40)), rel=1e-12)


def test_quick_return_time_ratio_from_its_geometry():
    # lever extremes where the crank is square to the lever: the quick arc is 2 acos(r/d), r = 1, d = 2
    psi = math.acos(1 / 2)
    got = measure(CATALOGUE["crank-shaper quick return"])
    assert got["time ratio"].value == pytest.approx((2 * math.pi - 2 * psi) / (2 * psi), rel=1e-7)
    assert got["stroke"].value == pytest.approx(2 * math.degrees(math.asin(1 / 2)), rel=1e-7)


@pytest.mark.parametrize("name, ratio", [
    ("gear train", 18 / 30 * 30 / 54),            # two external meshes: the wheel turns the pinion's way
    ("planetary gear train", 20 / (20 + 52)),     # Willis, ring fixed: z_s / (z_s + z_r)
    ("rack and pinion", 1.0),                     # the pitch radius, per radian
])
def test_gear_entries_measure_their_closed_form_ratio(name, ratio):
    entry = next(e for e in load_catalogue() if e.name == name)
    m = measure(entry)
    assert m["ratio"].value == pytest.approx(ratio, rel=1e-12)
    assert m["ratio variation"].value < 1e-9


@pytest.mark.parametrize("slots", [3, 4, 6, 8])
def test_geneva_against_the_pin_in_the_slot(slots):
    g = Geneva(slots, 2.0)
    alpha = g.index_angle / 2
    t = np.linspace(-alpha, alpha, 401)[1:-1]
    pin = g.crank * np.c_[np.cos(t), np.sin(t)]                  # crank about (0, 0), wheel about (c, 0)
    slot = pin - np.array([g.centre_distance, 0.0])
    beta = np.arctan2(slot[:, 1], -slot[:, 0])                 # the slot's angle from W→O
    got, rate, accel = g.wheel(t)
    assert np.max(np.abs(got - beta)) < 1e-12
    h = 1e-6
    assert np.max(np.abs(rate - (g.wheel(t + h)[0] - g.wheel(t - h)[0]) / (2 * h))) < 1e-8
    assert np.max(np.abs(accel - (g.wheel(t + h)[1] - g.wheel(t - h)[1]) / (2 * h))) < 1e-7
    # tangential entry: the pin moves along the slot as it enters, so the wheel starts from rest
    assert abs(float(g.wheel(alpha)[1][()])) < 1e-12


@pytest.mark.parametrize("slots", [4, 6])
def test_geneva_index_and_dwell_measured(slots):
    got = measure(CATALOGUE[f"Geneva wheel, {slots} slots"])
    assert got["index"].value == pytest.approx(360 / slots, abs=1e-9)
    assert got["dwell"].value == pytest.approx(180 + 360 / slots, abs=1e-6)      # rest: speed below 1e-9 of peak
    lam = math.sin(math.pi / slots)
    assert got["peak speed ratio"].value == pytest.approx(lam / (1 - lam), rel=1e-6)


def slider_crank_rate(crank, rod, theta):
    """dx/dθ of an in-line slider-crank, x = r cos θ + sqrt(l² − r² sin² θ) (crank r, rod l)."""
    root = math.sqrt(rod ** 2 - (crank * math.sin(theta)) ** 2)
    return -crank * math.sin(theta) - crank ** 2 * math.sin(theta) * math.cos(theta) / root


def test_toggle_press_advantage_against_the_slider_crank_velocity_ratio():
    # The knee lever is an in-line slider-crank driven on its crank (lever 1, link 1); by virtual work the ram's
    # force per lever torque is dθ/dx = 1 / |dx/dθ|, here 1 / (2 sin θ): unbounded as lever and link line up.
    entry = CATALOGUE["toggle press"]
    got = measure(entry)
    end, start = math.radians(1), math.radians(40)
    assert got["mechanical advantage"].value == pytest.approx(1 / abs(slider_crank_rate(1, 1, end)), rel=1e-9)
    assert got["advantage growth"].value == pytest.approx(
        slider_crank_rate(1, 1, start) / slider_crank_rate(1, 1, end), rel=1e-9)
    assert got["stroke"].value == pytest.approx(2 * math.cos(end) - 2 * math.cos(start), rel=1e-9)
    previous = 0.0
    for last in (1.0, 0.1, 0.01, 0.001):                     # towards the toggle: ten times the advantage each time
        near = dataclasses.replace(entry, measure={**entry.measure, "range_deg": [40, last]})
        ma = measure(near)["mechanical advantage"].value
        assert ma == pytest.approx(1 / (2 * math.sin(math.radians(last))), rel=1e-9)
        assert ma > 9.9 * previous
        previous = ma
    assert previous > 2.8e4
    at_toggle = dataclasses.replace(entry, measure={**entry.measure, "range_deg": [40, 0]})
    with pytest.raises(InputError, match="toggle press: the output is at rest at 0°, the dead centre"):
        measure(at_toggle)


def crank_rocker_extremes(a, b, c, d):
    """The rocker's extreme angles (from the frame line) and the crank angles there, crank pivot (0, 0), rocker pivot
    (d, 0), rocker pin above the frame: crank and coupler in line, the pin at a + b (extended) or b − a (folded)."""
    out = []
    for reach, turn in ((a + b, 0.0), (b - a, math.pi)):
        x = (reach ** 2 - c ** 2 + d ** 2) / (2 * d)           # the pin on circles about both pivots
        pin = (x, math.sqrt(reach ** 2 - x ** 2))
        out.append((math.atan2(pin[1], pin[0] - d), (math.atan2(pin[1], pin[0]) + turn) % (2 * math.pi)))
    return out                                               # [(ψ, θ) extended, (ψ, θ) folded]


def pawl_advances(low, high, pitch, phase, cycles):
    """The wheel's turn each cycle of a pawl swinging between ``low`` and ``high``: back, it drops behind a tooth;
    forward, it meets the first tooth face ahead of ``low`` and pushes it to ``high`` (faces at phase + j·pitch)."""
    advances = []
    for _ in range(cycles):
        face = phase + math.ceil((low - phase) / pitch) * pitch
        advances.append(high - face if face <= high else 0.0)
        phase = (phase + advances[-1]) % pitch
    return advances


def test_ratchet_against_the_grashof_extremes_and_the_pawl_tooth_by_tooth():
    a, b, c, d, teeth = 1.0, 3.0, 2.5, 3.0, 24                # ratchet-rocker.json and the entry's teeth
    (psi_ext, th_ext), (psi_fold, th_fold) = crank_rocker_extremes(a, b, c, d)
    swing, pitch = psi_fold - psi_ext, 2 * math.pi / teeth   # the forward stroke: crank from th_ext to th_fold
    advances = pawl_advances(psi_ext, psi_fold, pitch, phase=0.123, cycles=4)
    assert advances[1:] == pytest.approx([3 * pitch] * 3, abs=1e-12)   # steady from the second cycle: 3 teeth
    # the pawl engages 3 pitches before the folded extreme: the crank angle there, on the forward stroke
    psi_on = psi_fold - 3 * pitch
    pin = (d + c * math.cos(psi_on), c * math.sin(psi_on))
    phi, r = math.atan2(pin[1], pin[0]), math.hypot(*pin)
    forward = (th_fold - th_ext) % (2 * math.pi)
    cands = [(phi + s * math.acos((a * a + r * r - b * b) / (2 * a * r))) for s in (1, -1)]
    th_on = next(t for t in cands if 0 < (t - th_ext) % (2 * math.pi) < forward)
    driven = (th_fold - th_on) % (2 * math.pi)
    got = measure(CATALOGUE["ratchet, 24 teeth"])
    assert got["index"].value == pytest.approx(45.0, abs=1e-12)
    assert got["swing"].value == pytest.approx(math.degrees(swing), abs=1e-7)
    assert got["lost motion"].value == pytest.approx(math.degrees(swing) - 45, abs=1e-7)
    assert got["dwell"].value == pytest.approx(360 - math.degrees(driven), abs=1e-6)
    assert 90 < got["dwell"].value < 250                        # kept for dwell >= 90, left out for >= 250


def test_ratchet_parameters_are_checked():
    entry = CATALOGUE["ratchet, 24 teeth"]
    coarse = dataclasses.replace(entry, parameters={"teeth": 6})           # 60° pitch: more than the 51.5° swing
    with pytest.raises(InputError, match="swings 51.4564°, less than a tooth's pitch 60°"):
        measure(coarse)
    with pytest.raises(InputError, match="parameters.teeth, a whole number >= 1, got 'many'"):
        measure(dataclasses.replace(entry, parameters={"teeth": "many"}))


def test_cam_dwells_measured_to_the_threshold():
    got = measure(CATALOGUE["dwell-rise-dwell-return cam"])
    assert got["dwell"].value == pytest.approx(180, abs=0.01) and got["stroke"].value == pytest.approx(1.0)


def test_a_problem_of_the_second_class_proposes_the_intermittent_mechanisms():
    """"rotation in, intermittent rotation out, dwell >= 90°" (issue 26's acceptance): both Geneva wheels and the
    ratchet."""
    found = propose(load_catalogue(), "rotation -> intermittent rotation", ["dwell >= 90°"])
    assert found.success and [p.entry.name for p in found if p.kept] == ["Geneva wheel, 4 slots",
                                                                        "Geneva wheel, 6 slots", "ratchet, 24 teeth"]
    assert all("dwell >= 90: has" in p.reasons[0] for p in found)
    strict = propose(load_catalogue(), "rotation -> intermittent rotation", ["dwell >= 260", "index = 90"])
    assert [p.entry.name for p in strict if p.kept] == ["Geneva wheel, 4 slots"]
    none = propose(load_catalogue(), "rotation -> straight line", ["dwell >= 90"])
    assert not none.success and "not a property it has" in none[0].reasons[0]


def test_requirements_and_files_say_what_is_wrong(tmp_path):
    with pytest.raises(InputError, match="NAME OP NUMBER"):
        requirement("dwell is long")
    with pytest.raises(InputError, match="unknown motion 'flying'"):
        propose(load_catalogue(), "rotation -> flying")
    folder = tmp_path / "knowledge"
    shutil.copytree(knowledge_dir(), folder)
    text = (folder / "catalogue.toml").read_text()
    (folder / "catalogue.toml").write_text(text.replace('motion = ["rotation", "reciprocation"]',
                                                        'motion = ["rotation", "wobble"]', 1))
    with pytest.raises(InputError, match=r"catalogue.toml:\d+: slider-crank: motion must be"):
        load_catalogue(folder)
    (folder / "catalogue.toml").write_text(text.replace('model = "slider-crank.json"', 'model = "../x.json"'))
    with pytest.raises(InputError, match=r"catalogue.toml:\d+: slider-crank: the model file"):
        load_catalogue(folder)


def test_cli_lists_measured_properties_as_json_and_fails_when_nothing_meets_the_requirements():
    run = subprocess.run([sys.executable, "-m", "domes", "catalogue", "--motion", "rotation -> straight line",
                          "--format", "json"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    doc = json.loads(run.stdout)
    assert [m["name"] for m in doc["mechanisms"]] == ["Hoeken straight-line linkage"]
    assert doc["mechanisms"][0]["properties"]["straight length"]["value"] == pytest.approx(4.0, abs=1e-6)
    run = subprocess.run([sys.executable, "-m", "domes", "catalogue", "--motion", "rotation -> straight line",
                          "--require", "straight-line deviation <= 0.01"], capture_output=True, text=True, timeout=120)
    assert run.returncode == 1 and "left out" in run.stdout and "Traceback" not in run.stderr
