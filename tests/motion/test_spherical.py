"""The spherical four-bar in closed form against the loop closure (issue 15, item 2)."""

import math

import numpy as np
import pytest

from domes.errors import InputError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism
from domes.motion.spatial.spherical import SphericalFourBar
from domes.motion.spatial.sweep import spatial_sweep


def linkage(v, u0, w0, vs, centre=(0.0, 0.0, 0.0)):
    c = np.asarray(centre, float)
    axes = [np.asarray(x, float) / np.linalg.norm(x) for x in (v, u0, w0, vs)]
    joints = tuple(SpatialJoint(name, "R", pair, tuple(c + 2.0 * a), tuple(a)) for name, pair, a in
                   zip(("A0", "A", "B", "B0"), (("frame", "input"), ("input", "coupler"), ("coupler", "output"),
                                                ("frame", "output")), axes))
    return SpatialMechanism.build("spherical four-bar", ("frame", "input", "coupler", "output"), "frame", joints,
                                  (SpatialInput("A0", "angle", 2.0, 0.5),))


@pytest.mark.parametrize("seed", range(4))
def test_closed_form_equals_the_loop_closure(seed):
    rng = np.random.default_rng(seed)
    while True:
        axes = rng.normal(size=(4, 3))
        mech = linkage(*axes, centre=rng.normal(size=3))
        s = SphericalFourBar.of(mech)
        if s.input_turns_fully():
            break
    sw = spatial_sweep(mech, 0.0, 2 * math.pi, math.radians(10), outputs=["angle:B0"], order=2)
    if not sw.success:
        pytest.skip("the sampled linkage meets a limit between samples")
    psi = np.unwrap(s.psi(sw.inputs))
    np.testing.assert_allclose(sw.table["angle:B0"], psi - psi[0] + sw.table["angle:B0"][0], atol=1e-9)
    pd, pdd = s.rates(sw.inputs, psi, 2.0, 0.5)
    np.testing.assert_allclose(sw.table["angle:B0'"], pd, rtol=1e-8, atol=1e-9)
    np.testing.assert_allclose(sw.table["angle:B0''"], pdd, rtol=1e-7, atol=1e-8)


def test_axes_that_do_not_meet_are_refused():
    mech = linkage((1, 0, 0), (0.6, 0.8, 0), (0.1, 0.4, 0.9), (0.3, 0.3, 0.9))
    moved = SpatialMechanism.build(mech.name, mech.links, mech.ground,
                                   mech.joints[:3] + (SpatialJoint("B0", "R", ("frame", "output"), (5.0, 1.0, 0.0),
                                                                   mech.joints[3].axis),), mech.inputs)
    with pytest.raises(InputError, match="do not meet in one point"):
        SphericalFourBar.of(moved)
