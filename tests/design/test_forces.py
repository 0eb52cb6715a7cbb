"""Design checks that need forces (issue 16, item 4): the hinge clamp's force ratio, the motorcycle's wheel rate,
the tyre drum's actuator torque.

Each is checked against a route that does not use the inverse dynamics:
the principle of virtual work on the kinematics backend's velocities (the
force ratio of a massless mechanism is the inverse ratio of the speeds; a
static driving torque is minus the loads' virtual power per unit input
rate), and the spring's energy (the wheel force's work over the travel).
"""

import dataclasses
import math

import numpy as np
import pytest

from domes.design import forces
from domes.design.verify import Check, matches, verify
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.io.resources import knowledge_dir
from domes.io.scenes import load_scene
from domes.motion.planar.sweep import solve, sweep

CLAMP = load_mechanism(knowledge_dir() / "mechanisms" / "hinge-clamp.json")
SUZUKI = load_mechanism(knowledge_dir() / "mechanisms" / "suzuki-rm250x.json")
DRUM = load_mechanism(knowledge_dir() / "mechanisms" / "tyre-drum-fig5-1.json")


def speed_ratio(mech, q, point="jaw"):
    """|input rate| / |the point's speed| from the kinematics alone (virtual work, massless)."""
    unit = dataclasses.replace(mech, inputs=(dataclasses.replace(mech.inputs[0], speed=1.0),))
    v = solve(unit, q, outputs=[f"point:{point}"], order=1).values
    return 1.0 / math.hypot(v[f"point:{point}.x'"], v[f"point:{point}.y'"])


def test_the_dimensioned_originals_are_the_scenes_existing_designs():
    for scene, mech in (("hinge-clamp", CLAMP), ("motorcycle", SUZUKI), ("tyre-drum", DRUM)):
        assert matches(load_scene(scene).existing[0], mech), scene


def test_clamp_force_ratio_equals_the_speed_ratio():
    r = forces.force_ratio(CLAMP, "point:jaw", 0.106, 0.12, 0.002)
    expected = [speed_ratio(CLAMP, q) for q in r.inputs]
    np.testing.assert_allclose(r.ratio, expected, rtol=1e-9)


def test_clamp_force_ratio_grows_without_bound_toward_the_toggle():
    r = forces.force_ratio(CLAMP, "point:jaw", 0.106, 0.13, 0.001, wanted=20.0)
    (toggle,) = r.toggles
    assert 0.122 < toggle < 0.124
    ratios = []
    for k in range(3, 8):
        d = 10.0 ** -k
        near = forces.force_ratio(CLAMP, "point:jaw", toggle - d, toggle - d / 2, d / 2)
        ratios.append((d, near.ratio[0]))
    values = [x for _, x in ratios]
    assert all(b > 5 * a for a, b in zip(values, values[1:]))          # ten times nearer, about ten times more
    products = [d * x for d, x in ratios[1:]]
    assert max(products) / min(products) < 1.01                        # ratio ~ c / distance: no bound
    q, d_in, d_out = r.reached
    assert speed_ratio(CLAMP, q) == pytest.approx(20.0, rel=1e-6)
    assert d_in == pytest.approx(toggle - q, rel=1e-9) and 0 < d_out < d_in
    assert "the ratio 20 is reached at" in r.message and "toggle (ratio without bound)" in r.message


def test_verify_force_ratio_reports_the_distance():
    v = verify(CLAMP, Check.parse(["force-ratio", "point:jaw", "0.106:0.13", "20"]))
    assert v.success and v.values["distance_input"] > 0 and v.values["toggles"]
    v = verify(CLAMP, Check.parse(["force-ratio", "point:jaw", "0.106:0.11", "20"]))   # the toggle lies beyond
    assert not v.success and "no toggle in the range" in v.message and v.values["maximum"] < 20


def test_wheel_force_does_the_springs_work():
    r = forces.wheel_rate(SUZUKI, "point:axle", "shock", math.radians(-10), math.radians(10), math.radians(0.25))
    k, free = 50000.0, 0.32
    energy = 0.5 * k * (free - r.spring_length) ** 2
    work = np.trapezoid(r.wheel_force, r.travel)
    assert work == pytest.approx(energy[-1] - energy[0], rel=1e-4)
    assert np.all(r.leverage > 0) and np.all(np.diff(r.wheel_rate) > 0)      # a rising rate
    # the wheel rate is k/LR² plus the spring force times the change of 1/LR along the travel
    spring_force = k * (free - r.spring_length)
    expected = k / r.leverage ** 2 + spring_force * np.gradient(1.0 / r.leverage, r.travel)
    np.testing.assert_allclose(r.wheel_rate[1:-1], expected[1:-1], rtol=2e-3)


def test_drum_actuator_torque_equals_the_virtual_work_of_the_loads():
    static = dataclasses.replace(DRUM, inputs=(dataclasses.replace(DRUM.inputs[0], speed=0.0),))
    r = forces.drive(static, math.radians(215), math.radians(390), math.radians(25))
    torque = r.dynamics.driving["O"]
    unit = dataclasses.replace(DRUM, inputs=(dataclasses.replace(DRUM.inputs[0], speed=1.0),))
    sw = sweep(unit, math.radians(215), math.radians(390), math.radians(25), outputs=["point:P1", "point:P2"], order=1)
    power = -200.0 * sw.table["point:P1.y'"] - 150.0 * sw.table["point:P2.y'"]
    np.testing.assert_allclose(torque, -power, rtol=1e-9, atol=1e-9)
    assert "peak" in r.message and "least" in r.message


def test_force_checks_refuse_what_they_cannot_do():
    with pytest.raises(InputError, match="no spring 'coil'"):
        forces.wheel_rate(SUZUKI, "point:axle", "coil", 0.0, 0.1)
    with pytest.raises(InputError, match="a point"):
        forces.wheel_rate(SUZUKI, "angle:3", "shock", 0.0, 0.1)
    with pytest.raises(InputError, match="a point .* or a link"):
        forces.force_ratio(CLAMP, "slide:p", 0.106, 0.11)
    with pytest.raises(InputError, match="nothing to drive"):
        forces.drive(CLAMP, 0.106, 0.11)
    with pytest.raises(InputError, match="RATIO must be a number > 0"):
        Check.parse(["force-ratio", "point:jaw", "0:1", "-3"])
    with pytest.raises(InputError, match="empty range"):
        Check.parse(["drive", "1:1"])


def test_force_checks_take_bare_names_as_the_kinematics_do():
    # issue 25, item 3: 'wheel-rate axle shock -10:10' (a bare point name, as `domes kinematics` takes) crashed the
    # design session with a KeyError; the checks read a bare name as its output, the same as 'point:axle'.
    bare = verify(SUZUKI, Check.parse(["wheel-rate", "axle", "shock", "-10:10"]))
    named = verify(SUZUKI, Check.parse(["wheel-rate", "point:axle", "shock", "-10:10"]))
    assert bare.message == named.message and bare.values == named.values
    bare = verify(CLAMP, Check.parse(["force-ratio", "jaw", "0.106:0.13", "20"]))
    named = verify(CLAMP, Check.parse(["force-ratio", "point:jaw", "0.106:0.13", "20"]))
    assert bare.values == named.values
    with pytest.raises(InputError, match="output 'hub'"):
        verify(SUZUKI, Check.parse(["wheel-rate", "hub", "shock", "-10:10"]))
