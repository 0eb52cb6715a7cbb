"""Inverse dynamics of planar mechanisms (issue 16, item 2).

Checked against methods that share nothing with the Newton–Euler solve:
free-body diagrams solved by hand for a static slider-crank and four-bar
(two-force members), the energy method (the driving torque times the crank
speed equals the rate of change of the kinetic and potential energy, both
differentiated numerically from positions alone), and the power balance of
every example mechanism with masses, springs, dampers and gravity.
"""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from domes.design.dynamics import inverse_dynamics
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.model.masses import LinkMass, Load, MassModel, Spring
from domes.motion.planar.examples import four_bar, slider_crank
from domes.motion.planar.sweep import sweep

#: Every example mechanism, gear trains and cams included (their contact forces: test_dynamics_contacts.py).
EXAMPLES = sorted((Path(__file__).resolve().parents[2] / "examples" / "mechanisms").glob("*.json"))


def with_masses(mech, gravity=(0.0, -9.81), springs=True):
    """Every moving link gets a mass at the centroid of its joints, an inertia; gravity; a spring and damper."""
    masses = []
    for k, link in enumerate(x for x in mech.links if x != mech.ground):
        pts = np.array([j.at for j in mech.joints_of(link)])
        c = pts.mean(axis=0) + np.array([0.05, -0.03]) * mech.size
        masses.append(LinkMass(link, 1.0 + k, (float(c[0]), float(c[1])), 0.02 * (k + 1) * mech.size ** 2))
    extra = ()
    if springs:
        names = [j.name for j in mech.joints if j.kind == "R"]
        a, b = names[0], names[-1]
        if mech.joint(a).at != mech.joint(b).at:
            extra = (Spring("s", (a, b), rate=50.0, free_length=None, damping=3.0, preload=2.0),)
    link = masses[-1].link
    loads = (Load("push", link, (3.0, -1.0), mech.joints_of(link)[0].at, 0.7),)
    return dataclasses.replace(mech, masses=MassModel(tuple(masses), loads, extra, gravity))


@pytest.mark.parametrize("path", EXAMPLES, ids=[p.stem for p in EXAMPLES])
def test_power_balance_of_every_example_with_masses(path):
    mech = with_masses(load_mechanism(path))
    joint = mech.joint(mech.inputs[0].joint)
    if joint.kind == "R":
        start, stop, step = joint_range(mech)
    else:
        s0 = joint.s0
        start, stop, step = s0, s0 + 0.05 * mech.size * math.copysign(1, mech.inputs[0].speed), 0.005 * mech.size
    dyn = inverse_dynamics(mech, start, stop, step)
    assert dyn.inputs.size > 5
    assert dyn.peak_power > 0
    assert dyn.max_imbalance < 1e-9, dyn.message


def joint_range(mech):
    from domes.motion.planar.checks import rotatability
    if mech.gears or mech.cams:   # the example trains and cams turn fully (Grashof's test is for four-bars)
        return 0.0, 2 * math.pi, math.radians(3)
    r = rotatability(mech)
    lo, hi = r.reachable
    if r.full:
        return 0.0, 2 * math.pi, math.radians(3)
    pad = 0.02 * (hi - lo)
    return lo + pad, hi - pad, (hi - lo) / 60


def test_static_slider_crank_reactions_equal_the_hand_free_body():
    # Massless, at rest, a force P pushing the slider back. The rod is a two-force member: with u the unit
    # vector B→C and k its compression, the slider's x balance gives k = P/u_x, the frame's normal force
    # is −k u_y, the crank torque τ = k (B − A) × u, and every pin carries k u (on the second link).
    base = slider_crank(1.0, 3.0, 0.5)
    P = 40.0
    mech = dataclasses.replace(base, masses=MassModel(loads=(Load("gas", "slider", (-P, 0.0), base.joint("C").at),)))
    angles = np.radians([20.0, 75.0, 130.0, 200.0, 290.0])
    dyn = inverse_dynamics(mech, float(angles[0]), float(angles[-1]), float(angles[1] - angles[0]), speed=0.0)
    run = sweep(mech, float(angles[0]), float(angles[-1]), float(angles[1] - angles[0]),
                outputs=["point:B", "point:C"])
    B = run.table["point:B.x"] + 1j * run.table["point:B.y"]
    C = run.table["point:C.x"] + 1j * run.table["point:C.y"]
    u = (C - B) / np.abs(C - B)
    k = P / u.real
    torque = k * (B.real * u.imag - B.imag * u.real)
    np.testing.assert_allclose(dyn.driving["A"], torque, rtol=1e-10)
    for name in ("A", "B", "C"):
        np.testing.assert_allclose(dyn.reactions[name][:, 0], k * u.real, rtol=1e-10)
        np.testing.assert_allclose(dyn.reactions[name][:, 1], k * u.imag, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(dyn.reactions["S"][:, 1], -k * u.imag, rtol=1e-10, atol=1e-9)
    np.testing.assert_allclose(dyn.reactions["S"][:, 0], 0.0, atol=1e-9)
    np.testing.assert_allclose(dyn.moments["S"], 0.0, atol=1e-9)


def test_static_four_bar_reactions_equal_the_hand_free_body():
    # Massless, at rest, a torque T on the rocker. The coupler is a two-force member along w = (C − B)/|C − B|
    # with tension k: the rocker's moments about D give k = −T / ((C − D) × w), the crank torque is
    # τ = k (B − A) × w, and every pin carries k w from its first link to its second (D: rocker on frame).
    base = four_bar()
    T = 12.0
    mech = dataclasses.replace(base, masses=MassModel(loads=(Load("work", "rocker", torque=T),)))
    dyn = inverse_dynamics(mech, 0.0, math.radians(300.0), math.radians(60.0), speed=0.0)
    run = sweep(mech, 0.0, math.radians(300.0), math.radians(60.0), outputs=["point:B", "point:C"])
    B = run.table["point:B.x"] + 1j * run.table["point:B.y"]
    C = run.table["point:C.x"] + 1j * run.table["point:C.y"]
    D = 3.0
    w = (C - B) / np.abs(C - B)
    cross = lambda p, q: p.real * q.imag - p.imag * q.real  # noqa: E731
    k = -T / cross(C - D, w)
    np.testing.assert_allclose(dyn.driving["A"], k * cross(B, w), rtol=1e-10)
    for name in ("A", "B", "C", "D"):
        np.testing.assert_allclose(dyn.reactions[name][:, 0] + 1j * dyn.reactions[name][:, 1], k * w, rtol=1e-10)


def test_gravity_on_a_crank_held_still():
    # A crank of mass m with its centre at distance r, held at angle θ: τ = m g r cos θ.
    base = four_bar()
    mech = dataclasses.replace(base, masses=MassModel((LinkMass("crank", 2.0, (0.6, 0.0), 0.1),), gravity=(0, -9.81)))
    dyn = inverse_dynamics(mech, 0.0, math.radians(90.0), math.radians(15.0), speed=0.0)
    np.testing.assert_allclose(dyn.driving["A"], 2.0 * 9.81 * 0.6 * np.cos(dyn.inputs), rtol=1e-12, atol=1e-12)


def test_driving_torque_equals_the_energy_method():
    # τ ω = d(T + V)/dt − P(load) at constant crank speed ω. T and V are computed from link positions only
    # (velocities by central differences of positions in the input), then differentiated numerically.
    mech = with_masses(four_bar(), springs=False)
    mech = dataclasses.replace(mech, masses=dataclasses.replace(mech.masses, loads=()))
    omega = 7.0
    q = np.radians(np.arange(5.0, 356.0, 10.0))
    dyn = inverse_dynamics(mech, float(q[0]), float(q[-1]), math.radians(10.0), speed=omega)
    h = 1e-4

    def energy(qs):
        names = [f"point:{j.name}" for j in mech.joints] + [f"angle:{x}" for x in mech.links if x != mech.ground]
        def place(x):
            step = mech  # positions only (order 0)
            from domes.motion.planar.sweep import solve
            return solve(step, float(x), outputs=names).values
        out = []
        for x in qs:
            lo, mid, hi = place(x - h), place(x), place(x + h)
            total = 0.0
            for m in mech.masses.masses:
                link = m.link
                ref = mech.reference_angle(link)
                j0 = mech.joints_of(link)[0]
                def centre(values):
                    rot = values[f"angle:{link}"] - ref
                    a = values[f"point:{j0.name}.x"] + 1j * values[f"point:{j0.name}.y"]
                    return a + np.exp(1j * rot) * (complex(*m.centre) - complex(*j0.at))
                v = (centre(hi) - centre(lo)) / (2 * h) * omega
                w = (hi[f"angle:{link}"] - lo[f"angle:{link}"]) / (2 * h) * omega
                total += 0.5 * m.mass * abs(v) ** 2 + 0.5 * m.inertia * w * w + m.mass * 9.81 * centre(mid).imag
            out.append(total)
        return np.array(out)

    d = 1e-3
    rate = (energy(q + d) - energy(q - d)) / (2 * d) * omega
    np.testing.assert_allclose(dyn.driving["A"] * omega, rate, rtol=1e-4, atol=1e-4 * np.max(np.abs(rate)))


def test_scaling_with_speed_and_reversal():
    mech = with_masses(slider_crank(), gravity=(0.0, 0.0), springs=False)
    mech = dataclasses.replace(mech, masses=dataclasses.replace(mech.masses, loads=()))
    one = inverse_dynamics(mech, 0.0, math.pi, math.radians(15), speed=2.0)
    three = inverse_dynamics(mech, 0.0, math.pi, math.radians(15), speed=6.0)
    back = inverse_dynamics(mech, 0.0, math.pi, math.radians(15), speed=-2.0)
    np.testing.assert_allclose(three.driving["A"], 9.0 * one.driving["A"], rtol=1e-12)
    np.testing.assert_allclose(back.driving["A"], one.driving["A"], rtol=1e-12)
    assert one.time is not None and one.time[-1] == pytest.approx(math.pi / 2.0)


def test_spring_and_damper_loads_balance_and_their_work():
    mech = with_masses(four_bar(), gravity=(0.0, 0.0))
    dyn = inverse_dynamics(mech, 0.0, 2 * math.pi, math.radians(1), speed=3.0)
    assert dyn.max_imbalance < 1e-12
    # over a full turn the kinetic energy and the spring return; the input's work equals the damper's loss
    # plus the work of the constant load, and the total load work is minus the input's
    t = dyn.time
    work_in = np.trapezoid(dyn.input_power, t)
    work_loads = np.trapezoid(dyn.load_power, t)
    assert work_in == pytest.approx(-work_loads, rel=1e-3)


def test_prescribed_motion_equals_the_sweep():
    mech = with_masses(four_bar())
    sw = inverse_dynamics(mech, 0.0, math.pi, math.radians(30), speed=4.0, acceleration=2.0)
    q = sw.inputs
    mo = inverse_dynamics(mech, motion={"A": (q, np.full(q.size, 4.0), np.full(q.size, 2.0))})
    np.testing.assert_allclose(mo.driving["A"], sw.driving["A"], rtol=1e-9)
    assert mo.time is None and mo.joint is None


def test_bad_requests_are_named():
    mech = four_bar()
    with pytest.raises(InputError, match="not a driven joint"):
        inverse_dynamics(mech, 0.0, 1.0, joint="C")
    with pytest.raises(InputError, match="start and stop"):
        inverse_dynamics(mech)
    with pytest.raises(InputError, match="not both"):
        inverse_dynamics(mech, 0.0, 1.0, motion={"A": ([0.0], [1.0], [0.0])})
    with pytest.raises(InputError, match="one length"):
        inverse_dynamics(mech, motion={"A": ([0.0, 1.0], [1.0], [0.0])})
    with pytest.raises(InputError, match="finite"):
        inverse_dynamics(mech, motion={"A": ([math.nan], [1.0], [0.0])})


ROOT = Path(__file__).resolve().parents[2]
OWN = [ROOT / "examples/dynamics/slider-crank-engine.json", ROOT / "knowledge/mechanisms/suzuki-rm250x.json",
       ROOT / "knowledge/mechanisms/tyre-drum-fig5-1.json"]


@pytest.mark.parametrize("path", OWN, ids=[p.stem for p in OWN])
def test_power_balance_of_the_files_with_their_own_masses(path):
    mech = load_mechanism(path)
    assert not mech.masses.empty
    start, stop, step = joint_range(mech)
    dyn = inverse_dynamics(mech, start, stop, step, speed=2.0)
    assert dyn.peak_power > 0 and dyn.max_imbalance < 1e-9, dyn.message


def test_a_sweep_stopped_at_a_dead_point_keeps_what_it_reached():
    from domes.motion.planar.examples import triple_rocker

    mech = with_masses(triple_rocker())
    dyn = inverse_dynamics(mech, 0.0, math.radians(130), math.radians(2))
    assert str(dyn.status) == "stopped" and "stopped:" in dyn.message
    assert dyn.inputs[-1] < math.radians(127.2) and dyn.max_imbalance < 1e-9


def test_a_result_without_forces_says_so():
    # every step refused near a singular point: no peak, and the message still reads
    from domes.design.dynamics import Dynamics
    from domes.results import Status

    nan = np.full(3, np.nan)
    dyn = Dynamics("m", "A", np.array([0.0, 0.1, 0.2]), None, {"A": nan}, {}, {}, np.zeros(3), nan, nan, nan,
                   np.zeros(3), np.ones(3), Status.COMPLETE)
    assert all(math.isnan(x) for x in dyn.peak("A"))
    assert "power balance within 0 of the peak power 0" in dyn.message


def test_numbers_that_overflow_are_a_failure_with_the_reason():
    # issue 25, item 4: a speed of 1e300 gave NaN tables reported as complete
    from domes.errors import NumericalError

    engine = load_mechanism("examples/dynamics/slider-crank-engine.json")
    with pytest.raises(NumericalError, match=r"the forces overflow the floating-point range .* at 3 of 3 steps, the "
                                             "first at input A = 0°: the speed, the acceleration or the loads"):
        inverse_dynamics(engine, 0.0, math.pi, math.pi / 2, speed=1e300)
    loaded = dataclasses.replace(engine, masses=dataclasses.replace(
        engine.masses, loads=(dataclasses.replace(engine.masses.loads[0], force=(-1e308, 0.0)),)))
    with pytest.raises(NumericalError, match="overflow") as caught:
        inverse_dynamics(loaded, 0.0, math.pi, math.pi / 2)
    assert caught.value.kind == "overflow"
    big = inverse_dynamics(engine, 0.0, math.pi, math.pi / 2, speed=1e100)   # huge, but numbers
    assert big.success and np.all(np.isfinite(big.driving["A"]))
