"""Gear-mesh and cam-contact forces in the inverse dynamics (issue 26).

Independent checks, none through the Newton–Euler solve:

* closed-form statics of a gear pair (external, internal, rack) under a load
  torque or force: the input torque ``T·r_a/r_b`` (the rack: ``F·r``), the
  tangential tooth force ``T/r_b``, the normal one ``T/(r_b·cos α)``, the
  separating one ``|F_t|·tan α`` on the pivot;
* Willis' formula for the planetary train (``ω_arm/ω_sun = z_s/(z_s + z_r)``),
  and the planet's free body (equal tooth forces at sun and ring);
* the principle of virtual work: the input torque times the input's speed
  equals minus the loads' power computed from the kinematics' velocities alone
  (a cam follower under its weight: ``τ = m·g·L'(θ)``; an oscillating
  follower under a torque: ``τ = −T·L'(θ)``);
* the force ratio of :mod:`domes.design.forces` for a gear train;
* the power balance with masses, inertias, gravity, springs and a moving
  carrier (the mesh and contact forces do no net work).

References: the principle of virtual work for ideal constraints (Lanczos,
*The Variational Principles of Mechanics*, ch. III); Willis' formula for
epicyclic trains (R. Willis, *Principles of Mechanism*, 1841; Uicker, Pennock
& Shigley, *Theory of Machines and Mechanisms*, ch. 10); involute tooth forces
``W_t = W cos φ``, ``W_r = W sin φ`` (Shigley's *Mechanical Engineering
Design*, ch. 13).
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from domes.design.dynamics import PRESSURE_ANGLE, inverse_dynamics
from domes.design.forces import force_ratio
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.model.cams import CamPair
from domes.model.gears import GearPair
from domes.model.laws import Motion
from domes.model.masses import LinkMass, Load, MassModel, Spring
from domes.model.mechanism import Input, Joint, Mechanism
from domes.motion.planar.sweep import sweep

LAW = Motion.cam([("cycloidal", 120, 0.5), ("dwell", 60), ("3-4-5", 120, -0.5), ("dwell", 60)])
ANGLES = (0.0, 0.7, 2.0, 4.1)


def pair(kind="external", ra=1.0, rb=2.0, speed=0.0):
    """A pinion on A at the origin meshing at (ra, 0) with a wheel (external) or a ring (internal) on B."""
    centre = ra + rb if kind == "external" else ra - rb
    return Mechanism.build("pair", ["frame", "pinion", "wheel"], "frame",
                           [Joint("A", "R", ("frame", "pinion"), (0.0, 0.0)),
                            Joint("B", "R", ("frame", "wheel"), (centre, 0.0))],
                           [Input("A", speed, 0.0)], gears=[GearPair("M", ("pinion", "wheel"), (ra, 0.0))])


def loaded(mech, *loads, masses=(), gravity=(0.0, 0.0)):
    return dataclasses.replace(mech, masses=MassModel(tuple(masses), tuple(loads), (), gravity))


def at(mech, angles=ANGLES, **kw):
    """Static forces (no speed) at the given input angles, one sweep per angle."""
    out = []
    for q in angles:
        out.append(inverse_dynamics(mech, q, q, 1.0, speed=0.0, acceleration=0.0, **kw))
    return out


@pytest.mark.parametrize("alpha_deg", [0.0, 20.0, 25.0])
@pytest.mark.parametrize("kind, ra, rb", [("external", 1.0, 2.0), ("external", 0.6, 1.5), ("internal", 0.6, 1.5)])
def test_gear_pair_statics_equal_the_closed_form(kind, ra, rb, alpha_deg):
    T = 7.0
    alpha = math.radians(alpha_deg)
    mech = loaded(pair(kind, ra, rb), Load("out", "wheel", torque=T))
    s = 1.0 if kind == "external" else -1.0                    # ω_wheel = −s·(ra/rb)·ω_pinion (Willis, fixed carrier)
    for dyn in at(mech, pressure_angle=alpha):
        assert dyn.driving["A"][0] == pytest.approx(s * T * ra / rb, rel=1e-12)
        # the wheel's moment about B: (P − B) × F_t·(0, 1) + T = 0, P − B = (−s·rb, 0)
        Ft = s * T / rb
        assert dyn.contacts["M"][0] == pytest.approx(Ft / math.cos(alpha), rel=1e-12)
        Fx, Fy = dyn.contact_forces["M"][0]
        # the separating part pushes the wheel (or the ring) along +x, away from the pinion's centre
        assert (Fx, Fy) == pytest.approx((abs(Ft) * math.tan(alpha), Ft), rel=1e-12, abs=1e-12)
        assert np.hypot(Fx, Fy) == pytest.approx(abs(T) / (rb * math.cos(alpha)), rel=1e-12)
        # the wheel's pivot takes the tooth force: the frame's force on the wheel is its opposite
        assert dyn.reactions["B"][0] == pytest.approx([-Fx, -Fy], rel=1e-12, abs=1e-12)
        # and the pinion's pivot the opposite of the force on the pinion
        assert dyn.reactions["A"][0] == pytest.approx([Fx, Fy], rel=1e-12, abs=1e-12)


def test_the_wheel_listed_first_flips_the_sign_not_the_size():
    base = pair()
    flipped = dataclasses.replace(base, gears=(dataclasses.replace(base.gears[0], links=("wheel", "pinion")),))
    a = at(loaded(base, Load("out", "wheel", torque=3.0)))
    b = at(loaded(flipped, Load("out", "wheel", torque=3.0)))
    for x, y in zip(a, b):
        assert y.driving["A"][0] == pytest.approx(x.driving["A"][0], rel=1e-12)
        assert y.contact_forces["M"][0] == pytest.approx(-x.contact_forces["M"][0], rel=1e-12)


def rack(direction=0.0, guide_first=True):
    """A pinion of radius 0.5 on A at the origin; the rack slides along ``direction`` through the pitch point."""
    r = 0.5
    u = complex(math.cos(direction), math.sin(direction))
    P = -1j * u * r                                            # the foot of the perpendicular from A: pinion below
    links = ("frame", "rack") if guide_first else ("rack", "frame")
    return Mechanism.build("rack", ["frame", "pinion", "rack"], "frame",
                           [Joint("A", "R", ("frame", "pinion"), (0.0, 0.0)),
                            Joint("S", "P", links, (P.real, P.imag), direction)],
                           [Input("A", 0.0, 0.0)], gears=[GearPair("M", ("pinion", "rack"), (P.real, P.imag))]), u, r


@pytest.mark.parametrize("direction", [0.0, 1.1, -2.5])
@pytest.mark.parametrize("guide_first", [True, False])
def test_rack_and_pinion_statics(direction, guide_first):
    mech, u, r = rack(direction, guide_first)
    F = 12.0
    mech = loaded(mech, Load("push", "rack", ((-F * u).real, (-F * u).imag), mech.joint("S").at))
    alpha = PRESSURE_ANGLE
    for dyn in at(mech):
        # turning the pinion counter-clockwise moves its lowest point (and the rack) along +u at r·ω
        assert dyn.driving["A"][0] == pytest.approx(F * r, rel=1e-12)
        assert dyn.contacts["M"][0] == pytest.approx(F / math.cos(alpha), rel=1e-12)
        apart = -1j * u                                        # away from the pinion's centre
        expect = F * u + F * math.tan(alpha) * apart
        assert dyn.contact_forces["M"][0] == pytest.approx([expect.real, expect.imag], rel=1e-12, abs=1e-12)
        # the guide's normal force takes the separating part
        N = dyn.reactions["S"][0] * (1 if guide_first else -1)
        assert N == pytest.approx([-(F * math.tan(alpha) * apart).real, -(F * math.tan(alpha) * apart).imag],
                                  rel=1e-12, abs=1e-12)


def test_planetary_train_follows_willis_and_the_planets_free_body():
    mech = load_mechanism("examples/mechanisms/planetary.json")
    T = 5.0
    mech = loaded(mech, Load("out", "arm", torque=T))
    zs, zr = 20, 52                                             # planet 16 teeth
    rs, rp = 1.0, 0.8
    for dyn in at(mech):
        assert dyn.driving["O"][0] == pytest.approx(-T * zs / (zs + zr), rel=1e-12)
        # the planet in equilibrium: equal tangential forces at the sun and the ring, 2·F_t·(rs + rp) = T
        Ft = T / (2 * (rs + rp))
        sp, pr = (dyn.contacts[p][0] * math.cos(PRESSURE_ANGLE) for p in ("SP", "PR"))
        assert abs(sp) == pytest.approx(Ft, rel=1e-12) and abs(pr) == pytest.approx(Ft, rel=1e-12)
        # the sun's pivot takes the whole sun-planet tooth force, the arm's pivot on the frame the planet's two
        sun_on = dyn.contact_forces["SP"][0]
        assert dyn.reactions["O"][0] == pytest.approx(sun_on, rel=1e-12, abs=1e-12)


def test_input_torque_agrees_with_the_force_ratio_of_a_gear_train():
    mech = pair("external", 0.6, 1.5)
    r = force_ratio(mech, "angle:wheel", 0.0, math.radians(30), math.radians(10))
    assert r.success and np.allclose(r.ratio, 1.5 / 0.6, rtol=1e-12)


def test_translating_follower_under_its_weight_needs_m_g_L_prime():
    m, g = 3.0, 9.81
    for guide_first in (True, False):
        links = ("frame", "follower") if guide_first else ("follower", "frame")
        mech = Mechanism.build("cam", ["frame", "cam", "follower"], "frame",
                               [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)),
                                Joint("S", "P", links, (0.0, 2.0), math.pi / 2)],
                               [Input("A", 0.0, 0.0)], cams=[CamPair("K", ("cam", "follower"), (0.0, 1.8), LAW, 0.4)])
        mech = loaded(mech, masses=(LinkMass("follower", m, (0.3, 2.5)),), gravity=(0.0, -g))
        for dyn, q in zip(at(mech), ANGLES):
            L1 = float(LAW.evaluate(0.4 + q, 1)[1])
            assert dyn.contacts["K"][0] == pytest.approx(m * g, rel=1e-12)
            assert dyn.driving["A"][0] == pytest.approx(m * g * L1, rel=1e-12, abs=1e-12)


def test_oscillating_follower_under_a_torque_needs_minus_T_L_prime():
    law = Motion.cam([("simple harmonic", 180, math.radians(20)), ("simple harmonic", 180, -math.radians(20))])
    mech = Mechanism.build("rocker cam", ["frame", "cam", "arm"], "frame",
                           [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("B", "R", ("frame", "arm"), (3.0, 0.0))],
                           [Input("A", 0.0, 0.0)], cams=[CamPair("K", ("cam", "arm"), (1.2, 0.4), law)])
    T = 4.0
    for dyn, q in zip(at(loaded(mech, Load("hold", "arm", torque=T))), ANGLES):
        L1 = float(law.evaluate(q, 1)[1])
        assert dyn.contacts["K"][0] == pytest.approx(-T, rel=1e-12)
        assert dyn.driving["A"][0] == pytest.approx(-T * L1, rel=1e-12, abs=1e-12)


def test_cam_rocker_static_torque_is_the_loads_virtual_work():
    """τ·θ̇ = −Σ F·v, the velocities from the kinematics alone (no forces computed)."""
    base = load_mechanism("examples/mechanisms/cam-rocker.json")
    F = (2.0, -5.0)
    mech = loaded(base, Load("push", "rocker", F, base.joint("E").at), Load("twist", "rod", torque=1.5))
    speed = 1.0
    unit = dataclasses.replace(base, inputs=(dataclasses.replace(base.inputs[0], speed=speed, acceleration=0.0),))
    sw = sweep(unit, 0.1, 6.1, 0.5, outputs=["point:E", "angle:rod"], order=1)
    dyn = inverse_dynamics(mech, 0.1, 6.1, 0.5, speed=0.0, acceleration=0.0)
    t = sw.table
    virtual = -(F[0] * t["point:E.x'"] + F[1] * t["point:E.y'"] + 1.5 * t["angle:rod'"]) / speed
    assert np.allclose(dyn.driving["A"], virtual, rtol=1e-10, atol=1e-10)


def cam_on_a_turning_arm():
    """A cam turning on an arm (input Q) that turns on the frame (input O); the follower slides on the arm."""
    law = Motion.cam([("cycloidal", 180, 0.3), ("cycloidal", 180, -0.3)])
    return Mechanism.build(
        "cam on an arm", ["frame", "arm", "cam", "follower"], "frame",
        [Joint("O", "R", ("frame", "arm"), (0.0, 0.0)), Joint("Q", "R", ("arm", "cam"), (1.0, 0.0)),
         Joint("S", "P", ("arm", "follower"), (1.0, 1.0), math.pi / 2)],
        [Input("O"), Input("Q")], cams=[CamPair("K", ("cam", "follower"), (1.0, 0.8), law, 0.3)])


def test_power_balance_with_a_moving_carrier_and_both_inputs_moving():
    mech = cam_on_a_turning_arm()
    masses = (LinkMass("arm", 2.0, (0.6, 0.1), 0.3), LinkMass("cam", 1.0, (1.05, 0.02), 0.05),
              LinkMass("follower", 0.7, (1.1, 1.3), 0.02))
    springs = (Spring("k", ("O", "S"), rate=30.0, damping=2.0),)
    mech = dataclasses.replace(mech, masses=MassModel(masses, (Load("l", "follower", (1.0, -2.0), (1.0, 1.5), 0.3),),
                                                      springs, (0.0, -9.81)))
    t = np.linspace(0.0, 2.0, 81)
    a, w = 0.8, 1.3
    motion = {"O": (a * np.sin(w * t), a * w * np.cos(w * t), -a * w * w * np.sin(w * t)),
              "Q": (3.0 * t + 0.2 * t * t, 3.0 + 0.4 * t, np.full_like(t, 0.4))}
    dyn = inverse_dynamics(mech, motion=motion, time=t)
    assert dyn.peak_power > 1.0 and dyn.max_imbalance < 1e-9, dyn.message


def test_power_balance_of_a_rack_with_masses_and_a_gear_train_with_inertia():
    mech, _, _ = rack(0.4)
    mech = dataclasses.replace(mech, inputs=(Input("A", 2.0, 0.7),), masses=MassModel(
        (LinkMass("pinion", 1.0, (0.05, 0.0), 0.1), LinkMass("rack", 3.0, (0.2, -0.6), 0.4)),
        (Load("l", "rack", (1.0, 2.0), (0.0, -0.5)),), (), (0.0, -9.81)))
    dyn = inverse_dynamics(mech, 0.0, 3.0, 0.1)
    assert dyn.max_imbalance < 1e-9, dyn.message
    gear = dataclasses.replace(pair("internal", 0.6, 1.5), inputs=(Input("A", 3.0, -1.0),), masses=MassModel(
        (LinkMass("pinion", 1.0, (0.1, 0.0), 0.2), LinkMass("wheel", 4.0, (-0.8, 0.1), 0.9)), (), (), (0.0, -9.81)))
    dyn = inverse_dynamics(gear, 0.0, 2 * math.pi, 0.1)
    assert dyn.max_imbalance < 1e-9, dyn.message
    # no load: the input torque is the two inertias' torques, moved to the input by the ratio (virtual work)
    wheel_turn = 0.6 / 1.5                                        # internal: the ring turns the same way
    inertia = 0.2 + 1.0 * 0.1 ** 2 + (0.9 + 4.0 * abs(complex(-0.8, 0.1) - complex(-0.9, 0.0)) ** 2) * wheel_turn ** 2
    free = dataclasses.replace(gear, masses=MassModel(gear.masses.masses))
    dyn = inverse_dynamics(free, 0.0, 2 * math.pi, 0.1)
    assert np.allclose(dyn.driving["A"], inertia * -1.0, rtol=1e-11)


@pytest.mark.parametrize("name", ["geared-five-bar", "cam-rocker", "planetary"])
def test_driving_torque_equals_the_energy_method(name):
    """τ·ω = d(T + V)/dt at constant input speed, T and V from link positions only (velocities by central
    differences of positions in the input), then differentiated numerically."""
    from domes.motion.planar.sweep import solve

    base = load_mechanism(f"examples/mechanisms/{name}.json")
    moving = [x for x in base.links if x != base.ground]
    masses = []
    for k, link in enumerate(moving):
        j0 = base.joints_of(link)[0]
        masses.append(LinkMass(link, 1.0 + k, (j0.at[0] + 0.3, j0.at[1] - 0.2), 0.05 * (k + 1)))
    mech = dataclasses.replace(base, masses=MassModel(tuple(masses), (), (), (0.0, -9.81)))
    omega = 3.0
    q = np.radians(np.arange(5.0, 356.0, 30.0))
    dyn = inverse_dynamics(mech, float(q[0]), float(q[-1]), math.radians(30.0), speed=omega, acceleration=0.0)
    names = [f"point:{base.joints_of(x)[0].name}" for x in moving] + [f"angle:{x}" for x in moving]
    h, d = 1e-4, 1e-3

    def energy(x):
        lo, mid, hi = (solve(mech, float(x + e), outputs=names).values for e in (-h, 0.0, h))
        total = 0.0
        for m in masses:
            j0 = base.joints_of(m.link)[0]

            def centre(values):
                rot = values[f"angle:{m.link}"] - base.reference_angle(m.link)
                a = values[f"point:{j0.name}.x"] + 1j * values[f"point:{j0.name}.y"]
                return a + np.exp(1j * rot) * (complex(*m.centre) - complex(*j0.at))
            v = (centre(hi) - centre(lo)) / (2 * h) * omega
            w = math.remainder(hi[f"angle:{m.link}"] - lo[f"angle:{m.link}"], 2 * math.pi) / (2 * h) * omega
            total += 0.5 * m.mass * abs(v) ** 2 + 0.5 * m.inertia * w * w + m.mass * 9.81 * centre(mid).imag
        return total

    rate = np.array([(energy(x + d) - energy(x - d)) / (2 * d) * omega for x in q])
    np.testing.assert_allclose(dyn.driving[base.inputs[0].joint] * omega, rate, rtol=1e-4,
                               atol=1e-4 * np.max(np.abs(rate)))


def test_the_separating_force_changes_the_pivots_only():
    mech = loaded(load_mechanism("examples/mechanisms/geared-five-bar.json"), Load("p", "coupler1", (3.0, -4.0),
                                                                                  (1.5, 2.8), 0.5))
    a = inverse_dynamics(mech, 0.0, 2 * math.pi, 0.3, pressure_angle=0.0)
    b = inverse_dynamics(mech, 0.0, 2 * math.pi, 0.3, pressure_angle=math.radians(25))
    assert np.allclose(a.driving["A"], b.driving["A"], rtol=1e-12, atol=1e-12)
    assert np.allclose(a.contacts["M"], b.contacts["M"] * math.cos(math.radians(25)), rtol=1e-12)
    for j in ("B", "C", "E"):
        assert np.allclose(a.reactions[j], b.reactions[j], rtol=1e-12, atol=1e-12)
    assert not np.allclose(a.reactions["A"], b.reactions["A"])


@pytest.mark.parametrize("value, message", [(math.pi / 2, "below 90°"), (-0.1, "at least 0"), (math.nan, "finite"),
                                            ("x", "expected an angle")])
def test_bad_pressure_angles_are_named(value, message):
    with pytest.raises(InputError, match=f"pressure_angle: .*{message}"):
        inverse_dynamics(pair(), 0.0, 1.0, 0.5, pressure_angle=value)


def test_the_winch_example_needs_its_load_torque_through_the_tooth_ratio():
    """examples/dynamics/winch.json: the drum's 196.2 N·m reaches the motor as 196.2·18/72 and loads the teeth with
    196.2/r_drum/cos α (the gears turn about fixed centres at constant speed: no inertia torque)."""
    mech = load_mechanism("examples/dynamics/winch.json")
    for alpha in (20.0, 25.0):
        dyn = inverse_dynamics(mech, 0.0, 2 * math.pi, math.radians(45), pressure_angle=math.radians(alpha))
        np.testing.assert_allclose(np.abs(dyn.driving["M"]), 196.2 * 18 / 72, rtol=1e-12)
        np.testing.assert_allclose(np.abs(dyn.contacts["G"]), 196.2 / 0.144 / math.cos(math.radians(alpha)),
                                   rtol=1e-12)
        assert dyn.max_imbalance < 1e-12
