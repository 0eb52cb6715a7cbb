"""Cam pairs given by their cam's profile: the follower moved by its contact with the outline (issue 26).

Independent check: the cam is designed for a known law (design_cam, closed
form from the law), its profile's points are given to the mechanism, and
the follower's slide or angle, rate and acceleration from the contact (a
quintic spline through the points, kernel and scalar path) are compared
with the law (``L'·θ̇``, ``L''·θ̇² + L'·θ̈``); a linkage after the follower
against the same mechanism with the law (examples/mechanisms/cam-rocker.json).
"""

from __future__ import annotations

import json
import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from domes.design.cam import Follower, design_cam
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.model.cams import CamPair, CamProfile
from domes.model.laws import Motion
from domes.model.mechanism import Input, Joint, Mechanism
from domes.motion.planar.continuation import Continuation, grid
from domes.motion.planar.kernel import vectorizable
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import _scalar_sweep, sweep

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"
SPEED, ACCEL = 2.0, 0.5
POINTS = 3600
LIFT = Motion.cam([("cycloidal", 120, 0.5), ("dwell", 60), ("3-4-5", 120, -0.5), ("dwell", 60)])
SWING = Motion.cam([("cycloidal", 120, math.radians(15)), ("dwell", 60), ("3-4-5", 120, -math.radians(15)),
                    ("dwell", 60)])


def _both_paths(m, col):
    """The column, its rate and acceleration on a 2° grid over a turn: from the kernel's sweep and step by step."""
    fast = sweep(m, 0.0, 2 * math.pi, math.radians(2), outputs=[col], order=2)
    kin = Kinematics(m, [col], 2)
    assert vectorizable(kin) and [g.kind for g in kin.structure.groups][:2] == ["driver", "cammed"]
    slow = _scalar_sweep(kin, Continuation(kin), np.asarray(grid(0.0, 2 * math.pi, math.radians(2))), None)
    assert fast.success and slow.success
    return [(sw.inputs, [sw.column(c) for c in (col, col + "'", col + "''")]) for sw in (fast, slow)]


def _errors(got, q, law, phase, sign=1.0):
    """The largest differences of (position, rate, acceleration) from the law at cam turns ``q``."""
    s, d1, d2 = law.evaluate(phase + q)
    want = (sign * (s - law.evaluate(phase, 0)[0]), sign * SPEED * d1, sign * (SPEED ** 2 * d2 + ACCEL * d1))
    return [float(np.max(np.abs(g - w))) for g, w in zip(got, want)]


def _translating(cam, k):
    """A translating follower on the designed ``cam`` at design angle ``theta[k]`` in the drawn pose."""
    f = cam.follower
    profile = CamProfile(tuple(map(tuple, cam.profile)), f, base_radius=cam.base_radius)
    return Mechanism.build(
        "profile cam", ["frame", "cam", "follower"], "frame",
        [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("S", "P", ("frame", "follower"), (f.offset, 2.0), math.pi / 2)],
        [Input("A", SPEED, ACCEL)], cams=[CamPair("K", ("cam", "follower"), tuple(cam.contact[k]), profile, cam.theta[k])])


@pytest.mark.parametrize("follower", [Follower("translating", "roller", roller=0.2, offset=0.15),
                                      Follower("translating", "flat")], ids=["roller with offset", "flat face"])
def test_translating_follower_moves_by_its_design_law(follower):
    cam = design_cam(LIFT, follower, 1.6, points=POINTS)
    k = 300                                             # the drawn pose at 30° of the design: the grid meets the joins
    m = _translating(cam, k)
    for q, got in _both_paths(m, "slide:S"):
        pos, rate, acc = _errors(got, q, LIFT, cam.theta[k])
        # measured: roller 1.6e-15, 9.5e-10, 1.7e-3; flat face 1.3e-15, 3.1e-9, 1.7e-3 (peak rate 0.95, peak
        # acceleration 3.0): the spline through 3,600 points; the acceleration only as h, since these laws' jerk
        # jumps where the segments meet
        assert pos < 1e-12 and rate < 1e-8 and acc < 5e-3, (pos, rate, acc)


@pytest.mark.parametrize("direction", [1, -1])
def test_oscillating_roller_turns_by_its_design_law(direction):
    """A cam designed to turn counter-clockwise with the arm on the left of the line from the cam to the pivot
    swings it clockwise as it rises; one designed to turn clockwise, seen mirrored (the arm on the right),
    counter-clockwise: the law itself."""
    f = Follower("oscillating", "roller", roller=8, pivot=100, arm=80)
    cam = design_cam(SWING, f, 40, direction=direction, points=POINTS)
    k = 1200                                            # the drawn pose at 120°, a join: the grid meets the joins
    at = cam.contact[k] * (1, direction)                        # mirrored for a clockwise design
    profile = CamProfile(tuple(map(tuple, cam.profile)), Follower("oscillating", "roller", roller=8, pivot=100, arm=80),
                         base_radius=40, direction=direction)
    m = Mechanism.build("swinging", ["frame", "cam", "arm"], "frame",
                        [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("B", "R", ("frame", "arm"), (100.0, 0.0))],
                        [Input("A", SPEED, ACCEL)], cams=[CamPair("K", ("cam", "arm"), tuple(at), profile, cam.theta[k])])
    for q, got in _both_paths(m, "angle:arm"):
        pos, rate, acc = _errors(got, q, SWING, cam.theta[k], sign=-direction)
        # measured: 1.2e-15 rad, 7.1e-10 rad/s, 8.9e-4 rad/s² (peak rate 0.5, peak acceleration 1.56)
        assert pos < 1e-12 and rate < 1e-8 and acc < 3e-3, (pos, rate, acc)
    back = Mechanism.from_dict(json.loads(json.dumps(m.to_dict())), "again")
    assert back.cams[0].law == profile and back.to_dict() == m.to_dict()


def test_a_linkage_after_the_follower_moves_as_with_the_law():
    """examples/mechanisms/cam-profile-rocker.json (the cam by 720 points) against cam-rocker.json (by its law)."""
    outs = ["slide:S", "angle:rocker", "point:E"]
    by_profile = load_mechanism(EXAMPLES / "cam-profile-rocker.json")
    by_law = load_mechanism(EXAMPLES / "cam-rocker.json")
    assert isinstance(by_profile.cams[0].law, CamProfile) and len(by_profile.cams[0].law.points) == 720
    got = sweep(by_profile, 0.0, 2 * math.pi, math.radians(0.25), outputs=outs, order=2)   # between the points too
    want = sweep(by_law, 0.0, 2 * math.pi, math.radians(0.25), outputs=outs, order=2)
    assert got.success and got.max_residual < 1e-13
    worst = {}
    for col in got.columns:
        order = col.count("'")
        scale = max(1.0, float(np.max(np.abs(want.column(col)))))
        worst[order] = max(worst.get(order, 0.0), float(np.max(np.abs(got.column(col) - want.column(col)))) / scale)
    # measured (relative to each column's peak): positions 5.1e-9, rates 3.4e-6, accelerations 3.4e-3
    assert worst[0] < 2e-8 and worst[1] < 1e-5 and worst[2] < 1e-2, worst


def test_the_file_round_trip_keeps_the_profile(tmp_path):
    m = load_mechanism(EXAMPLES / "cam-profile-rocker.json")
    data = m.to_dict()
    item = data["joints"][-1]
    assert "law" not in item and len(item["profile"]) == 720 and (item["face"], item["roller"]) == ("roller", 0.2)
    path = tmp_path / "saved.json"
    path.write_text(json.dumps(data))                        # the points inline: the file stands alone
    again = load_mechanism(path)
    assert again.cams[0].law == m.cams[0].law and again.to_dict() == data
    shutil.copy(EXAMPLES / "cam-profile-rocker.csv", tmp_path / "outline.csv")
    item["profile"] = "outline.csv"                          # a CSV path, relative to the mechanism file
    path.write_text(json.dumps(data))
    assert load_mechanism(path).cams[0].law == m.cams[0].law
    (tmp_path / "plain.csv").write_text("# x, y\n" + "".join(f"{a!r}, {b!r}\n" for a, b in m.cams[0].law.points))
    item["profile"] = "plain.csv"
    path.write_text(json.dumps(data))
    assert load_mechanism(path).cams[0].law == m.cams[0].law


def _file(tmp_path, change, csv: str | None = None):
    data = load_mechanism(EXAMPLES / "cam-profile-rocker.json").to_dict()
    change(data["joints"][-1])
    if csv is not None:
        (tmp_path / "p.csv").write_text(csv)
    path = tmp_path / "m.json"
    path.write_text(json.dumps(data))
    return path


RING = [[1.6 * math.cos(2 * math.pi * k / 40), 1.6 * math.sin(2 * math.pi * k / 40)] for k in range(40)]


@pytest.mark.parametrize("change, csv, message", [
    (lambda c: c.update(law=[["dwell", 360]]), None, r"joints\[5\]: give the follower's 'law' or the cam's 'profile', not both"),
    (lambda c: c.pop("profile"), None, r"joints\[5\]: a cam pair needs its follower's 'law' .* or its cam's 'profile'"),
    (lambda c: c.update(profile=RING[:10]), None, r"joints\[5\]\.profile: a cam profile needs 16 to 1,000,000 points"),
    (lambda c: c.update(profile=RING[:20] + RING[25:30] + RING[20:25] + RING[30:]), None,
     r"joints\[5\]\.profile: the profile's points must go once round the cam's centre.*turns back at point 25"),
    (lambda c: c.update(profile=[[x + 2, y] for x, y in RING]), None, r"once round the cam's centre"),
    (lambda c: c.update(face="wheel"), None, r"joints\[5\]\.face: unknown face 'wheel'; one of knife, roller, flat"),
    (lambda c: c.pop("face"), None, r"joints\[5\]: a cam pair given by its 'profile' needs its follower's 'face'"),
    (lambda c: c.update(arm=1.0), None, r"joints\[5\]\.arm: the follower is translating; it has an offset"),
    (lambda c: c.update(face="knife"), None, r"joints\[5\]: a knife follower has no roller"),
    (lambda c: c.update(profile_direction="up"), None, r"profile_direction: 'ccw' or 'cw'"),
    (lambda c: c.update(profile="missing.csv"), None, r"joints\[5\]\.profile \(.*missing\.csv\): cannot read the file"),
    (lambda c: c.update(profile="p.csv"), "x,y\n1,2\n3,oops\n", r"p\.csv\): line 3: expected numbers x, y, got '3, oops'"),
    (lambda c: c.update(profile="p.csv"), "theta,s\n1,2\n", r"p\.csv\): line 1: a header must name the columns 'x' and 'y'"),
])
def test_bad_profiles_are_named(tmp_path, change, csv, message):
    with pytest.raises(InputError, match=message):
        load_mechanism(_file(tmp_path, change, csv))


def test_profile_keys_on_a_pair_given_by_its_law_are_refused():
    data = load_mechanism(EXAMPLES / "cam-rocker.json").to_dict()
    data["joints"][-1]["face"] = "roller"
    with pytest.raises(InputError, match=r"joints\[5\]: \['face'\] describe a cam given by its 'profile'; this pair"):
        Mechanism.from_dict(data, "c.json")
    data = load_mechanism(EXAMPLES / "cam-rocker.json").to_dict()
    data["joints"][0]["profile"] = RING
    with pytest.raises(InputError, match=r"joints\[0\]: \['profile'\] belong to cam pairs"):
        Mechanism.from_dict(data, "c.json")


def test_a_follower_that_misses_the_profile_is_named_when_the_backend_takes_it(tmp_path):
    m = load_mechanism(_file(tmp_path, lambda c: c.update(profile=[[x / 4, y / 4] for x, y in RING], base_radius=0.4,
                                                            offset=0.65)))
    with pytest.raises(InputError, match=r"cam pair 'K': the follower's offset 0.65 must be smaller than the prime"):
        Kinematics(m)
    m = load_mechanism(_file(tmp_path, lambda c: c.update(profile=[[x / 4, y / 4] for x, y in RING], base_radius=1.0,
                                                            offset=0.9)))
    with pytest.raises(InputError, match=r"cam pair 'K': the follower does not touch the profile at cam angle"):
        Kinematics(m)


def test_an_oscillating_profile_must_agree_with_the_drawn_joints():
    cam = design_cam(SWING, Follower("oscillating", "roller", roller=8, pivot=100, arm=80), 40, points=360)
    joints = [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("B", "R", ("frame", "arm"), (100.0, 0.0))]

    def build(pivot=100.0, at=tuple(cam.contact[0])):
        profile = CamProfile(tuple(map(tuple, cam.profile)), Follower("oscillating", "roller", roller=8, pivot=pivot,
                                                                    arm=80))
        return Mechanism.build("m", ["frame", "cam", "arm"], "frame", joints, [Input("A")],
                               cams=[CamPair("K", ("cam", "arm"), at, profile)])

    assert build().dof == 1
    with pytest.raises(InputError, match=r"cam pair 'K': the profile's follower pivot is 90 from the cam's centre, the "
                                         r"mechanism's joints 'A' and 'B' are 100 apart"):
        build(pivot=90.0)
    with pytest.raises(InputError, match=r"the drawn contact 'at' .* must lie on the left of the line from the cam's"):
        build(at=tuple(cam.contact[0] * (1, -1)))
    with pytest.raises(InputError, match="an oscillating flat face is not followed"):
        CamProfile(tuple(map(tuple, cam.profile)), Follower("oscillating", "flat", pivot=100))
