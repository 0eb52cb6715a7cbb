"""Cam pairs in the planar backend: a follower driven by its cam's law, and linkages after it (issue 26).

Independent checks: the follower's slide or angle, rate and acceleration
against the law's closed form with the chain rule (``L'·θ̇``,
``L''·θ̇² + L'·θ̈``, seed 000's laws); a linkage driven by the follower
against the same linkage driven directly at the law's slide, rate and
acceleration (the existing P-input path).
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from domes.errors import InputError
from domes.model.cams import CamPair
from domes.model.gears import GearPair
from domes.model.laws import Motion
from domes.model.mechanism import Input, Joint, Mechanism
from domes.motion.planar.kernel import vectorizable
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import sweep

LAW = Motion.cam([("cycloidal", 120, 0.5), ("dwell", 60), ("3-4-5", 120, -0.5), ("dwell", 60)])
SPEED, ACCEL = 2.0, 0.5


def translating(extra_links=(), extra_joints=(), law=LAW, phase=0.0):
    return Mechanism.build(
        "cam", ["frame", "cam", "follower", *extra_links], "frame",
        [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("S", "P", ("frame", "follower"), (0.0, 2.0), math.pi / 2),
         *extra_joints],
        [Input("A", SPEED, ACCEL)], cams=[CamPair("K", ("cam", "follower"), (0.0, 1.8), law, phase)])


def test_translating_follower_follows_the_law():
    for phase in (0.0, 1.0):
        m = translating(phase=phase)
        kin = Kinematics(m, outputs=["slide:S"], order=2)
        assert [g.kind for g in kin.structure.groups] == ["driver", "cammed"] and vectorizable(kin)
        sw = sweep(m, 0.0, 4 * math.pi, math.radians(5), outputs=["slide:S"], order=2)
        s, d1, d2 = LAW.evaluate(phase + sw.inputs)
        t = sw.table
        assert sw.success
        assert np.max(np.abs(t["slide:S"] - (s - LAW.evaluate(phase, 0)[0]))) < 1e-12
        assert np.max(np.abs(t["slide:S'"] - SPEED * d1)) < 1e-12
        assert np.max(np.abs(t["slide:S''"] - (SPEED ** 2 * d2 + ACCEL * d1))) < 1e-12


def test_oscillating_follower_turns_by_the_law():
    law = Motion.cam([("simple harmonic", 180, math.radians(20)), ("simple harmonic", 180, -math.radians(20))])
    m = Mechanism.build("rocker cam", ["frame", "cam", "arm"], "frame",
                        [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("B", "R", ("frame", "arm"), (3.0, 0.0))],
                        [Input("A", SPEED, ACCEL)], points=[], cams=[CamPair("K", ("cam", "arm"), (1.2, 0.4), law)])
    sw = sweep(m, 0.0, 2 * math.pi, math.radians(10), outputs=["angle:arm"], order=2)
    s, d1, d2 = law.evaluate(sw.inputs)
    t = sw.table
    assert np.max(np.abs(t["angle:arm"] - s)) < 1e-12       # the arm's reference angle is 0: one joint
    assert np.max(np.abs(t["angle:arm'"] - SPEED * d1)) < 1e-12
    assert np.max(np.abs(t["angle:arm''"] - (SPEED ** 2 * d2 + ACCEL * d1))) < 1e-12
    back = Mechanism.from_dict(json.loads(json.dumps(m.to_dict())))
    assert back.to_dict() == m.to_dict() and back.to_dict()["joints"][-1]["law"][0][2] == pytest.approx(20.0)


def test_a_linkage_after_the_follower_moves_as_if_the_slide_were_driven():
    """Cam, follower, then a rod and a rocker (an RRR dyad): against the four-link chain driven at the slide."""
    rod_rocker = (Joint("D", "R", ("follower", "rod"), (0.0, 2.0)), Joint("E", "R", ("rod", "rocker"), (2.5, 3.0)),
                  Joint("F", "R", ("rocker", "frame"), (3.5, 1.0)))
    m = translating(("rod", "rocker"), rod_rocker)
    kin = Kinematics(m, outputs=["angle:rocker", "point:E"], order=2)
    assert [g.kind for g in kin.structure.groups] == ["driver", "cammed", "RRR"]
    direct = Mechanism.build("slid", ["frame", "follower", "rod", "rocker"], "frame",
                             [Joint("S", "P", ("frame", "follower"), (0.0, 2.0), math.pi / 2), *rod_rocker], [Input("S")])
    dkin = Kinematics(direct, outputs=["angle:rocker", "point:E"], order=2)
    sw = sweep(m, 0.0, 2 * math.pi, math.radians(15), outputs=["angle:rocker", "point:E"], order=2)
    assert sw.success and sw.residuals.max() < 1e-14
    s, d1, d2 = LAW.evaluate(sw.inputs)
    for k, q in enumerate(sw.inputs):
        step = dkin.at({"S": s[k]}, speeds={"S": SPEED * d1[k]}, accelerations={"S": SPEED ** 2 * d2[k] + ACCEL * d1[k]})
        for col in sw.table:
            assert sw.table[col][k] == pytest.approx(step.values[col], abs=1e-10), (col, q)


def test_a_cam_on_a_gear_turns_with_it():
    """The cam on a wheel driven by a pinion (ratio 1/2): the follower sees half the input's turn, reversed."""
    m = Mechanism.build("geared cam", ["frame", "pinion", "cam", "follower"], "frame",
                        [Joint("P", "R", ("frame", "pinion"), (-3.0, 0.0)), Joint("A", "R", ("frame", "cam"), (0.0, 0.0)),
                         Joint("S", "P", ("frame", "follower"), (0.0, 2.0), math.pi / 2)],
                        [Input("P", SPEED, 0.0)], gears=[GearPair("M", ("pinion", "cam"), (-2.0, 0.0), teeth=(20, 40))],
                        cams=[CamPair("K", ("cam", "follower"), (0.0, 1.8), LAW)])
    sw = sweep(m, 0.0, 4 * math.pi, math.radians(10), outputs=["slide:S"], order=1)
    s, d1, _ = LAW.evaluate(-0.5 * sw.inputs)
    assert np.max(np.abs(sw.table["slide:S"] - s)) < 1e-12
    assert np.max(np.abs(sw.table["slide:S'"] + 0.5 * SPEED * d1)) < 1e-12


def test_bad_cam_pairs_are_named():
    with pytest.raises(InputError, match="need a common carrier"):
        Mechanism.build("loose", ["frame", "cam", "follower", "x"], "frame",
                        [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("S", "P", ("x", "follower"), (0.0, 2.0)),
                         Joint("X", "R", ("frame", "x"), (1.0, 1.0))],
                        [Input("A")], cams=[CamPair("K", ("cam", "follower"), (0.0, 1.8), LAW)])
    m = translating()
    data = m.to_dict()
    data["joints"][-1]["law"] = [["cycloidal", 120, 0.5], ["dwell", 60]]
    with pytest.raises(InputError, match=r"joints\[2\]\.law: a cam's segments must cover one turn"):
        Mechanism.from_dict(data, "c.json")
    data = m.to_dict()
    data["joints"][0]["law"] = [["dwell", 360]]
    with pytest.raises(InputError, match=r"joints\[0\]: \['law'\] belong to cam pairs"):
        Mechanism.from_dict(data, "c.json")
    data = m.to_dict()
    data["inputs"] = [{"joint": "S", "speed": 1}]
    with pytest.raises(InputError, match="the cam drives it"):
        Kinematics(Mechanism.from_dict(data, "c.json"))
