"""Motion laws and disc cams (issue 26, items 2 and 3; seed 000 §2.10 names the laws).

Independent references: central differences for the laws' derivatives; the
laws' peak factors and the cam formulas of the standard cam literature
(R. L. Norton, *Cam Design and Manufacturing Handbook*, ch. 2, 7, 8: the
pressure angle of a translating roller follower, the pitch curve's radius
of a radial follower, ``r_b + s + s''`` for a flat face); and the converse
problem (the follower's motion from the profile by contact alone).
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from domes.design.cam import Follower, design_cam, follow
from domes.errors import InputError
from domes.model.laws import LAWS, Motion, from_table, normalised

RISES = [law for law in LAWS if law != "dwell"]


@pytest.mark.parametrize("law", RISES)
def test_laws_rise_from_zero_to_one_and_their_derivatives_match_differences(law):
    u = np.linspace(0.01, 0.99, 99)
    h = 1e-5
    assert float(normalised(law, 0.0)) == 0.0 and float(normalised(law, 1.0)) == pytest.approx(1.0, abs=1e-15)
    for k in range(3):
        diff = (normalised(law, u + h, k) - normalised(law, u - h, k)) / (2 * h)
        assert np.max(np.abs(diff - normalised(law, u, k + 1))) < 1e-6 * max(1.0, np.max(np.abs(diff)))


@pytest.mark.parametrize("law, cv, ca", [
    ("cycloidal", 2.0, 2 * math.pi),                 # sine acceleration
    ("simple harmonic", math.pi / 2, math.pi ** 2 / 2),   # cosine acceleration
    ("3-4-5 polynomial", 15 / 8, 10 / math.sqrt(3)),
    ("constant velocity", 1.0, 0.0),
])
def test_peak_velocity_and_acceleration_factors(law, cv, ca):
    u = np.linspace(0, 1, 200_001)
    assert np.max(np.abs(normalised(law, u, 1))) == pytest.approx(cv, rel=1e-9)
    assert np.max(np.abs(normalised(law, u, 2))) == pytest.approx(ca, rel=1e-8, abs=1e-12)


def test_dwell_rise_dwell_return_is_continuous_where_the_law_is():
    cyc = Motion.cam([("dwell", 90), ("cycloidal", 90, 20), ("dwell", 90), ("cycloidal", 90, -20)])
    assert cyc.jumps(1) == [] and cyc.jumps(2) == []
    assert len(cyc.jumps(3)) == 4                           # the cycloid's jerk jumps at every join
    shm = Motion.cam([("dwell", 90), ("harmonic", 90, 20), ("dwell", 90), ("harmonic", 90, -20)])
    jumps = shm.jumps(2)
    assert len(jumps) == 4 and shm.jumps(1) == []
    beta = math.pi / 2                                      # the acceleration jumps by π²/2 · h/β²
    assert max(abs(j) for _, j in jumps) == pytest.approx(math.pi ** 2 / 2 * 20 / beta ** 2, rel=1e-12)
    s = cyc.evaluate(np.radians([0, 90, 135, 180, 270, 315, 359.999]), 0)[0]
    assert s[:6] == pytest.approx([0, 0, 10, 20, 20, 10], abs=1e-12)


def test_motion_input_errors_name_the_segment():
    with pytest.raises(InputError, match="add up to 320"):
        Motion.cam([("cycloidal", 120, 20), ("cycloidal", 200, -20)])
    with pytest.raises(InputError, match="segment 2"):
        Motion.cam([("cycloidal", 180, 20), ("cycloidal", -180, -20)])
    with pytest.raises(InputError, match="return to its start"):
        Motion.cam([("cycloidal", 180, 20), ("dwell", 180)])
    with pytest.raises(InputError, match="unknown motion law 'trapezoid'"):
        Motion.cam([("trapezoid", 360, 0)])


def test_a_table_motion_is_exact_for_a_cubic_and_names_bad_rows():
    xs = np.linspace(0, 2, 9)
    m = from_table(xs, xs ** 3 - xs)
    x = np.linspace(0, 2, 37)
    s, s1, s2 = m.evaluate(x)
    assert np.max(np.abs(s - (x ** 3 - x))) < 1e-12 and np.max(np.abs(s2 - 6 * x)) < 1e-10
    with pytest.raises(InputError, match="rows 2 and 3"):
        from_table([0, 1, 1, 2], [0, 1, 2, 3])
    with pytest.raises(InputError, match="covers x from 0 to 2"):
        m.evaluate(3.0)


LAW = Motion.cam([("cycloidal", 120, 20), ("dwell", 60), ("3-4-5", 120, -20), ("dwell", 60)])


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("offset", [0.0, 6.0, -6.0])
def test_translating_roller_pressure_angle_and_pitch_radius_against_the_closed_forms(direction, offset):
    cam = design_cam(LAW, Follower("translating", "roller", roller=10, offset=offset), 40, direction=direction)
    s, s1, s2 = LAW.evaluate(cam.theta)
    y0 = math.sqrt(50 ** 2 - offset ** 2)
    ref = np.degrees(np.arctan(np.abs(s1 - direction * offset) / (s + y0)))   # tan φ = (s' − e)/(s + √(Rp² − e²))
    assert np.max(np.abs(cam.pressure_deg - ref)) < 1e-9
    if offset == 0:                                          # radial: ρ = (R² + s'²)^1.5 / (R² + 2s'² − R s'')
        R = 50 + s
        rho = (R ** 2 + s1 ** 2) ** 1.5 / (R ** 2 + 2 * s1 ** 2 - R * s2)
        assert np.max(np.abs(cam.pitch_radius - rho) / np.abs(rho)) < 1e-10
        assert np.max(np.abs(cam.radius - (rho - 10))) < 1e-9
    # the profile is the pitch curve moved inwards by the roller: every profile point is 10 from the pitch curve
    gap = np.linalg.norm(cam.pitch - cam.profile, axis=1)
    assert np.max(np.abs(gap - 10)) < 1e-12


def test_flat_face_radius_is_base_plus_s_plus_s2_and_the_harmonic_cam_is_an_eccentric_circle():
    f = Follower("translating", "flat")
    cam = design_cam(LAW, f, 60)
    s, s1, s2 = LAW.evaluate(cam.theta)
    assert np.max(np.abs(cam.radius - (60 + s + s2))) < 1e-10
    assert np.max(np.abs(cam.contact[:, 0] - s1)) < 1e-12          # the contact moves s' along the face
    ecc = design_cam(Motion.cam([("harmonic", 180, 10), ("harmonic", 180, -10)]), f, 20, points=97)
    centre = np.array([0.0, -5.0])                             # in the cam's frame at θ = 0
    assert np.max(np.abs(np.linalg.norm(ecc.profile - centre, axis=1) - 25)) < 1e-12


@pytest.mark.parametrize("direction", [1, -1])
@pytest.mark.parametrize("follower", [
    Follower("translating", "roller", roller=10, offset=5),
    Follower("translating", "knife", offset=-3),
    Follower("translating", "roller", roller=4),
])
def test_follower_on_the_designed_cam_repeats_the_law(follower, direction):
    """A cam pair in the backend: lift, velocity and acceleration from contact alone equal the law to 1e-9."""
    cam = design_cam(LAW, follower, 40, direction=direction)
    th = np.linspace(0, 2 * math.pi, 181)
    got = follow(cam, follower, 40, th, direction=direction)
    for a, b in zip((got.s, got.ds, got.dds), LAW.evaluate(th)):
        assert np.max(np.abs(a - b)) < 1e-9
    assert got.residual < 1e-9


@pytest.mark.parametrize("direction", [1, -1])
def test_oscillating_roller_follower_repeats_its_law_and_converges_from_points(direction):
    law = Motion.cam([("cycloidal", 120, math.radians(15)), ("dwell", 60), ("3-4-5", 120, -math.radians(15)),
                      ("dwell", 60)])
    f = Follower("oscillating", "roller", roller=8, pivot=100, arm=80)
    th = np.linspace(0, 2 * math.pi, 121)
    want = law.evaluate(th)
    exact = follow(design_cam(law, f, 40, direction=direction), f, 40, th, direction=direction)
    for a, b in zip((exact.s, exact.ds, exact.dds), want):
        assert np.max(np.abs(a - b)) < 1e-9
    errors = []
    for n in (360, 1440):                    # from the profile's points alone (a quintic spline through them)
        pts = design_cam(law, f, 40, direction=direction, points=n).profile
        errors.append(np.max(np.abs(follow(pts, f, 40, th, direction=direction).s - want[0])))
    assert errors[1] < errors[0] / 50 and errors[1] < 1e-9


def test_oscillating_flat_face_envelope_touches_every_face_line_and_stays_inside():
    law = Motion.cam([("3-4-5", 150, math.radians(12)), ("dwell", 30), ("3-4-5", 150, -math.radians(12)),
                      ("dwell", 30)])
    f = Follower("oscillating", "flat", pivot=90, face_offset=5)
    cam = design_cam(law, f, 35, points=2000)
    s = law.evaluate(cam.theta, 0)[0]
    psi = math.asin((35 + 5) / 90) + s
    n = np.c_[np.sin(psi), np.cos(psi)]
    c = 90 * np.sin(psi) - 5
    assert np.max(np.abs(np.einsum("ij,ij->i", cam.contact, n) - c)) < 1e-10   # on the face
    for k in range(0, 2000, 97):                  # the turned profile stays on the cam's side of the face
        th = cam.theta[k]
        R = np.array([[math.cos(th), -math.sin(th)], [math.sin(th), math.cos(th)]])
        reach = (cam.profile @ R.T) @ n[k]
        assert reach.max() <= c[k] + 1e-9 * c[k]
        assert reach.max() >= c[k] - 1e-4            # and touches it (polygon of 2000 points)


def test_undercut_is_refused_with_the_radius():
    with pytest.raises(InputError, match=r"undercut at θ = [\d.]+°: the pitch curve's radius of curvature [\d.]+ is "
                       r"not larger than the roller's 10"):
        design_cam(Motion.cam([("cycloidal", 60, 20), ("cycloidal", 60, -20), ("dwell", 240)]),
                   Follower("translating", "roller", roller=10), 5)
    with pytest.raises(InputError, match=r"undercut .*radius of curvature -[\d.]+ \(it must stay > 0\)"):
        design_cam(LAW, Follower("translating", "flat"), 10)
    with pytest.raises(InputError, match="offset 60 must be smaller"):
        design_cam(LAW, Follower("translating", "knife", offset=60), 40)


def test_pressure_above_the_limit_is_a_warning():
    cam = design_cam(LAW, Follower("translating", "roller", roller=5), 15)
    assert cam.max_pressure_angle_deg > 30 and cam.warnings and "pressure angle above 30°" in cam.warnings[0]
    assert "exceeded" in cam.message


def _domes(*args):
    return subprocess.run([sys.executable, "-m", "domes", "cam", *args], capture_output=True, text=True, timeout=120)


def test_cli_writes_every_profile_point_and_reports_errors_in_one_line(tmp_path):
    run = _domes("--segment", "cycloidal", "120", "20", "--segment", "dwell", "60", "--segment", "3-4-5", "120",
                 "-20", "--segment", "dwell", "60", "--roller", "10", "--base-radius", "40", "--format", "json",
                 "--points", "90")
    assert run.returncode == 0, run.stderr
    doc = json.loads(run.stdout)
    assert len(doc["profile"]) == 90 and doc["max_pressure_deg"] == pytest.approx(
        design_cam(LAW, Follower("translating", "roller", roller=10), 40, points=90).max_pressure_angle_deg)
    table = tmp_path / "law.txt"
    xs = np.linspace(0, 360, 361)
    table.write_text("\n".join(f"{x}, {5 * (1 - math.cos(math.radians(x)))}" for x in xs))
    run = _domes("--table", str(table), "--face", "flat", "--base-radius", "20", "--format", "csv", "--points", "36")
    assert run.returncode == 0, run.stderr
    rows = run.stdout.strip().splitlines()
    assert len(rows) == 37 and [float(v) for v in rows[1].split(",")][-1] == pytest.approx(25, abs=1e-3)
    bad = _domes("--segment", "cycloidal", "120", "--roller", "2", "--base-radius", "40")
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and "cover one turn" in bad.stderr
    table.write_text("0, 0\n90, x\n")
    bad = _domes("--table", str(table), "--face", "knife", "--base-radius", "40")
    assert bad.returncode == 2 and "line 2" in bad.stderr and "Traceback" not in bad.stderr
