"""The RCCC in closed form against the loop closure (issue 15, item 2)."""

import math

import numpy as np
import pytest

from domes.errors import InputError
from domes.io.mechanisms import load_spatial
from domes.motion.spatial.cylindric import RCCCLinkage
from domes.motion.spatial.loops import Loops
from domes.motion.spatial.sweep import spatial_sweep

PLANTED = "examples/spatial/rccc-planted.json"


def test_closed_form_coupler_equals_the_loop_closure():
    mech = load_spatial(PLANTED)
    closed = RCCCLinkage.of(mech)
    sw = spatial_sweep(mech, 0.0, math.radians(80), math.radians(4), outputs=["slide:z1"])
    kin = Loops(mech)
    k = kin.index["coupler"]
    for q, s, slide in zip(sw.inputs, sw.states, sw.table["slide:z1"]):
        C, d, sigma = closed.coupler(float(q))
        R = s.R[k]
        moved = s.o[k] * kin.scale - R @ (kin.centre[k] * kin.scale)
        np.testing.assert_allclose(C, R, atol=1e-12)
        np.testing.assert_allclose(d, moved, atol=1e-9)
        assert sigma == pytest.approx(slide, abs=1e-9)


def test_the_planted_poses_of_the_synthesis():
    # the closed form gives seed 004's TC-6 displacements directly
    closed = RCCCLinkage.of(load_spatial(PLANTED))
    C, d, _ = closed.coupler(math.radians(25))
    np.testing.assert_allclose(d, (0.762345, 5.064615, 11.108913), atol=1e-6)
    assert math.degrees(math.acos((np.trace(C) - 1) / 2)) == pytest.approx(12.980763, abs=1e-6)


def test_not_an_rccc():
    with pytest.raises(InputError, match="not an RCCC"):
        RCCCLinkage.of(load_spatial("examples/spatial/rssr-seed001.json"))


def test_a_4c_driven_by_angle_and_slide():
    # the planted linkage with its R joint made cylindric: the closed form with the driver's slide equals the
    # loop closure driven by both of z0's variables
    from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism

    base = load_spatial(PLANTED)
    z0 = base.joint("z0")
    joints = (SpatialJoint("z0", "C", z0.links, z0.at, z0.axis),) + base.joints[1:]
    mech = SpatialMechanism.build("4C", base.links, base.ground, joints,
                                  (SpatialInput("z0", "angle"), SpatialInput("z0", "slide")))
    closed = RCCCLinkage.make([(j.at, j.axis) for j in mech.joints])
    kin = Loops(mech)
    k = kin.index["coupler"]
    state = kin.drawn()
    for frac in np.linspace(0, 1, 31)[1:]:
        theta, slide = frac * math.radians(40), frac * 7.5
        state, _ = kin.positions({"z0.angle": theta, "z0.slide": slide}, state)
        C, d, _ = closed.coupler(theta, slide=slide)
        R = state.R[k]
        np.testing.assert_allclose(C, R, atol=1e-12)
        np.testing.assert_allclose(d, state.o[k] * kin.scale - R @ (kin.centre[k] * kin.scale), atol=1e-9)
