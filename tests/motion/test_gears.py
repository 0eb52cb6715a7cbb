"""Gear pairs in the planar backend: ordinary and epicyclic trains, racks, gears on linkages.

Independent closed forms: an ordinary train's ratio is the product of the
tooth ratios with a sign per external mesh; an epicyclic train obeys Willis'
formula ``(ω_b − ω_arm)/(ω_a − ω_arm) = ∓z_a/z_b``; a rack moves by the
pitch radius times the pinion's turn. Seed 002 counts a gear pair as a
two-freedom joint (``j_G``, eq. 3-13); the DOF checks below use that count.
"""

from __future__ import annotations

import json
import math
import random

import numpy as np
import pytest

from domes.design.dynamics import inverse_dynamics
from domes.errors import InputError
from domes.model.gears import GearPair
from domes.model.laws import Motion, Segment
from domes.model.mechanism import Input, Joint, Mechanism
from domes.motion.planar.batch import batch
from domes.motion.planar.examples import four_bar
from domes.motion.planar.kernel import vectorizable
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import sweep
from domes.motion.planar.timed import timed
from domes.typesynth.number import number_synthesis

MODULE = 0.1


def train(teeth, internal=(), speed=2.0, acceleration=0.5):
    """Gears in a row on the frame, meshing in turn; ``internal`` indices mesh inside the next (a ring)."""
    links = ["frame"] + [f"g{k}" for k in range(len(teeth))]
    joints, gears = [Joint("J0", "R", ("frame", "g0"), (0.0, 0.0))], []
    x = 0.0
    for k in range(1, len(teeth)):
        ra, rb = MODULE * teeth[k - 1] / 2, MODULE * teeth[k] / 2
        inside = k - 1 in internal
        centre = x + (rb - ra if inside else ra + rb)
        pitch = x + (-ra if inside else ra)
        joints.append(Joint(f"J{k}", "R", ("frame", links[k + 1]), (centre, 0.0)))
        gears.append(GearPair(f"M{k}", (links[k], links[k + 1]), (pitch, 0.0), teeth=(teeth[k - 1], teeth[k])))
        x = centre
    return Mechanism.build("train", links, "frame", joints, [Input("J0", speed, acceleration)], gears=gears)


def planetary(zs, zp, arm_input=False, ring_fixed=True):
    """Sun, planet on an arm, ring: the ring is the frame (1 DOF) or a link on the frame (2 DOF, a differential)."""
    rs, rp = MODULE * zs / 2, MODULE * zp / 2
    zr = zs + 2 * zp
    ring = "frame" if ring_fixed else "ring"
    links = ["frame", "sun", "arm", "planet"] + ([] if ring_fixed else ["ring"])
    joints = [Joint("O", "R", ("frame", "sun"), (0.0, 0.0)), Joint("O2", "R", ("frame", "arm"), (0.0, 0.0)),
              Joint("P", "R", ("arm", "planet"), (rs + rp, 0.0))]
    if not ring_fixed:
        joints.append(Joint("O3", "R", ("frame", "ring"), (0.0, 0.0)))
    inputs = [Input("O2", 1.5, -0.25)] if arm_input else [Input("O", 3.0, 0.75)]
    if not ring_fixed:
        inputs = [Input("O", 3.0, 0.75), Input("O2", 1.5, -0.25)]
    gears = [GearPair("SP", ("sun", "planet"), (rs, 0.0), teeth=(zs, zp)),
             GearPair("PR", ("planet", ring), (rs + 2 * rp, 0.0), teeth=(zp, zr))]
    return Mechanism.build("planetary", links, "frame", joints, inputs, points=[], gears=gears)


# -- ordinary trains --------------------------------------------------------------


@pytest.mark.parametrize("seed", range(8))
def test_ordinary_train_ratio_is_the_product_of_the_tooth_ratios(seed):
    rng = random.Random(seed)
    teeth = [rng.randint(12, 80) for _ in range(rng.randint(2, 6))]
    internal = {k for k in range(len(teeth) - 1) if rng.random() < 0.3 and teeth[k + 1] > teeth[k] + 4}
    m = train(teeth, internal)
    expected = 1.0
    for k in range(len(teeth) - 1):
        expected *= (1.0 if k in internal else -1.0) * teeth[k] / teeth[k + 1]
    last = f"angle:g{len(teeth) - 1}"
    sw = sweep(m, 0.0, 2 * math.pi, math.radians(15), outputs=[last], order=2)
    assert sw.success
    q = sw.inputs
    assert np.allclose(sw.table[last], expected * q, rtol=0, atol=1e-12 * max(1.0, abs(expected) * 2 * math.pi))
    assert np.allclose(sw.table[last + "'"], expected * 2.0, rtol=1e-13)
    assert np.allclose(sw.table[last + "''"], expected * 0.5, rtol=1e-13)
    assert m.dof == 1 and number_synthesis(1, len(teeth) - 1, gear_pairs=len(teeth) - 1).links == len(m.links)


def test_the_kernel_and_the_equations_agree_on_a_train():
    """The vectorized kernel (assur) and the scalar path (one group of every link, method newton)."""
    m = train([20, 35, 17, 60], internal={2})
    outs = ["angle:g3", "angle:g2", "angle:g1"]
    a = sweep(m, 0.0, 4.0, 0.25, outputs=outs, order=2)
    b = sweep(m, 0.0, 4.0, 0.25, outputs=outs, order=2, method="newton")
    assert vectorizable(Kinematics(m, outs)) and not vectorizable(Kinematics(m, outs, method="newton"))
    for col in a.table:
        assert np.allclose(a.table[col], b.table[col], rtol=0, atol=1e-12), col


# -- epicyclic trains (Willis) -------------------------------------------------------------


@pytest.mark.parametrize("zs,zp", [(20, 16), (17, 31), (40, 12), (24, 24)])
def test_planetary_train_obeys_willis_formula(zs, zp):
    zr = zs + 2 * zp
    for arm_input in (False, True):
        m = planetary(zs, zp, arm_input)
        sw = sweep(m, 0.0, 2 * math.pi, math.radians(20), outputs=["angle:sun", "angle:arm", "angle:planet"], order=2)
        assert sw.success and sw.residuals.max() == 0.0
        t = sw.table
        for k in ("'", "''"):
            ws, wa, wp = t["angle:sun" + k], t["angle:arm" + k], t["angle:planet" + k]
            # Willis, sun–planet (external) and planet–ring (internal, ring fixed: ω_ring = 0)
            assert np.allclose((wp - wa), -(zs / zp) * (ws - wa), rtol=1e-12, atol=1e-12)
            assert np.allclose((0.0 - wa), (zp / zr) * (wp - wa), rtol=1e-12, atol=1e-12)
        # the classic result: ω_arm / ω_sun = z_s / (z_s + z_r)
        assert np.allclose(t["angle:arm'"], t["angle:sun'"] * zs / (zs + zr), rtol=1e-13)


def test_differential_with_two_inputs():
    zs, zp = 18, 27
    zr = zs + 2 * zp
    m = planetary(zs, zp, ring_fixed=False)
    assert m.dof == 2
    kin = Kinematics(m, outputs=["angle:ring", "angle:planet"], order=2)
    for qs, qa in [(0.3, -1.2), (5.0, 2.0), (-7.5, 0.1)]:
        step = kin.at({"O": qs, "O2": qa}, speeds={"O": 3.0, "O2": 1.5}, accelerations={"O": 0.75, "O2": -0.25})
        # Willis from sun to ring through the planet: (ω_r − ω_a)/(ω_s − ω_a) = −z_s/z_r
        for k, (s, a) in (("'", (3.0, 1.5)), ("''", (0.75, -0.25))):
            assert step.values["angle:ring" + k] == pytest.approx(a - zs / zr * (s - a), abs=1e-12)
        assert step.values["angle:ring"] == pytest.approx(qa - zs / zr * (qs - qa), abs=1e-12)


def test_planet_pitch_point_on_the_fixed_ring_is_at_rest():
    m = planetary(20, 16)
    sw = sweep(m, 0.0, 2 * math.pi, math.radians(30), outputs=["point:P"], order=1)
    assert sw.success
    # the arm's pivot of the planet moves on a circle of radius r_s + r_p at ω_arm·(r_s + r_p)
    speed = np.hypot(sw.table["point:P.x'"], sw.table["point:P.y'"])
    assert np.allclose(speed, 3.0 * 20 / 72 * MODULE * 18, rtol=1e-12)


# -- racks ------------------------------------------------------------------------------------


@pytest.mark.parametrize("driven,direction", [("A", 0.0), ("S", 0.0), ("A", 1.1), ("S", -2.3)])
def test_rack_moves_by_the_pitch_radius_times_the_turn(driven, direction):
    r = 0.75
    u = (math.cos(direction), math.sin(direction))
    pitch = (r * u[1], -r * u[0])  # the foot of the perpendicular from the pinion's centre (0, 0)
    m = Mechanism.build("rack", ["frame", "pinion", "rack"], "frame",
                        [Joint("A", "R", ("frame", "pinion"), (0.0, 0.0)),
                         Joint("S", "P", ("frame", "rack"), pitch, direction)],
                        [Input(driven, 2.0, -1.0)], gears=[GearPair("M", ("rack", "pinion"), pitch)])
    kin = Kinematics(m, outputs=["slide:S", "angle:pinion"], order=2)
    assert vectorizable(kin)
    for method in ("assur", "newton"):
        sw = sweep(m, 0.0, 1.0, 0.125, outputs=["slide:S", "angle:pinion"], order=2, method=method)
        t = sw.table
        assert sw.success
        # a pinion turning counter-clockwise rolls its lowest point (relative to the slide) forward: s = r·θ
        assert np.allclose(t["slide:S"], r * (t["angle:pinion"] - t["angle:pinion"][0]), atol=1e-12)
        assert np.allclose(t["slide:S'"], r * t["angle:pinion'"], atol=1e-12)
        assert np.allclose(t["slide:S''"], r * t["angle:pinion''"], atol=1e-12)


# -- gears on linkages -----------------------------------------------------------------------


def test_sector_gear_on_a_rocker_doubles_its_swing():
    """A gear on the four-bar's rocker drives a pinion of half its radius: the kernel reads the dyad's rotation."""
    fb = four_bar()
    m = Mechanism.build("sector", list(fb.links) + ["pinion"], "frame",
                        list(fb.joints) + [Joint("E", "R", ("frame", "pinion"), (3.0, -1.5))], list(fb.inputs),
                        gears=[GearPair("M", ("rocker", "pinion"), (3.0, -1.0))])
    kin = Kinematics(m, outputs=["angle:pinion", "angle:rocker"], order=2)
    assert [g.kind for g in kin.structure.groups] == ["driver", "RRR", "geared"] and vectorizable(kin)
    sw = sweep(m, 0.0, 2 * math.pi, math.radians(10), outputs=["angle:pinion", "angle:rocker"], order=2)
    t = sw.table
    assert sw.success
    for k in ("", "'", "''"):
        x, y = t["angle:pinion" + k], t["angle:rocker" + k]
        if not k:
            x, y = x - x[0], y - y[0]
        assert np.max(np.abs(x + 2.0 * y)) < 1e-12


def test_geared_five_bar_file_closes_every_two_turns():
    from domes.io.mechanisms import load_mechanism
    m = load_mechanism("examples/mechanisms/geared-five-bar.json")
    assert m.dof == 1 and [g.kind for g in Kinematics(m).structure.groups] == ["driver", "geared", "RRR"]
    sw = sweep(m, 0.0, 4 * math.pi, math.radians(5), outputs=["point:E", "angle:crank2"], order=1)
    assert sw.success and sw.residuals.max() < 1e-14
    assert abs(sw.table["point:E.x"][-1] - sw.table["point:E.x"][0]) < 1e-12
    assert np.allclose(sw.table["angle:crank2'"], -0.5 * m.inputs[0].speed, rtol=1e-13)
    assert m.to_dict() == type(m).from_dict(json.loads(json.dumps(m.to_dict()))).to_dict()


def test_timed_sweep_and_batch_carry_the_law_through_gears():
    m = planetary(20, 16)
    law = Motion((Segment("cycloidal", 1.0, 2 * math.pi),))
    times = np.linspace(0.0, 1.0, 41)
    tm = timed(m, law, times, outputs=["angle:arm"], order=2)
    s, v, a = law.evaluate(times)
    assert np.allclose(tm.table["angle:arm"], s * 20 / 72, atol=1e-12)
    assert np.allclose(tm.table["angle:arm'"], v * 20 / 72, atol=1e-9)
    assert np.allclose(tm.table["angle:arm''"], a * 20 / 72, atol=1e-9)
    b = batch(m, inputs=np.radians([0.0, 90.0, 270.0]), outputs=["angle:planet"])
    assert np.allclose(b.values["angle:planet"][0], np.radians([0.0, 90.0, 270.0]) * 20 / 72 * (1 - 52 / 16), atol=1e-12)
    with pytest.raises(InputError, match="pitch points"):
        batch(m, coordinates={"P": np.array([[1.8, 0.0], [1.9, 0.0]])}, inputs=np.radians([0.0, 90.0]),
              outputs=["angle:planet"])


# -- errors -----------------------------------------------------------------------------------


def _pair(at, teeth=None, carrier=None, links=("pinion", "wheel"), extra=()):
    return Mechanism.build("pair", ["frame", "pinion", "wheel", *extra], "frame",
                           [Joint("A", "R", ("frame", "pinion"), (0.0, 0.0)),
                            Joint("B", "R", ("frame", "wheel"), (3.0, 0.0))],
                           [Input("A")], gears=[GearPair("M", links, at, teeth, carrier)])


def test_bad_gear_pairs_are_named():
    with pytest.raises(InputError, match=r"gear pair 'M'.* off the line of centres"):
        _pair((1.0, 0.01))
    with pytest.raises(InputError, match=r"teeth 20:30 .* move the pitch point"):
        _pair((1.0, 0.0), teeth=(20, 30))
    with pytest.raises(InputError, match="is at the centre"):
        _pair((0.0, 0.0))
    with pytest.raises(InputError, match="carrier 'pinion'"):
        _pair((1.0, 0.0), carrier="pinion")
    with pytest.raises(InputError, match="two different links"):
        _pair((1.0, 0.0), links=("pinion", "pinion"))
    with pytest.raises(InputError, match=r"3·2 − 2·2 − 1\) but 2 input"):
        Mechanism.build("pair", ["frame", "pinion", "wheel"], "frame",
                        [Joint("A", "R", ("frame", "pinion"), (0.0, 0.0)), Joint("B", "R", ("frame", "wheel"), (3.0, 0.0))],
                        [Input("A"), Input("B")], gears=[GearPair("M", ("pinion", "wheel"), (1.0, 0.0))])


def test_gears_without_a_common_carrier_are_refused():
    fb = four_bar()
    with pytest.raises(InputError, match="need a common carrier"):
        Mechanism.build("loose", list(fb.links) + ["g"], "frame",
                        list(fb.joints) + [Joint("E", "R", ("rocker", "g"), (3.2, 1.0))],
                        list(fb.inputs), gears=[GearPair("M", ("crank", "g"), (2.1, 0.5))])


def test_gear_tying_two_inputs_is_named():
    """Driving both gears of one pair: the count of DOF is met by a free link elsewhere, the inputs are tied."""
    m = Mechanism.build("tied", ["frame", "a", "b", "c"], "frame",
                        [Joint("A", "R", ("frame", "a"), (0.0, 0.0)), Joint("B", "R", ("frame", "b"), (3.0, 0.0)),
                         Joint("C", "R", ("frame", "c"), (9.0, 0.0))],
                        [Input("A"), Input("B")], gears=[GearPair("M", ("a", "b"), (1.0, 0.0))])
    with pytest.raises(InputError, match=r"gear pair 'M' ties the inputs \['A', 'B'\] to each other: they are not independent"):
        Kinematics(m)


def test_file_errors_name_the_field():
    data = train([20, 40]).to_dict()
    data["joints"][-1]["teeth"] = [20, "x"]
    with pytest.raises(InputError, match=r"joints\[2\]\.teeth: teeth must be two positive whole numbers"):
        Mechanism.from_dict(data, "t.json")
    data = train([20, 40]).to_dict()
    data["joints"][0]["teeth"] = [1, 2]
    with pytest.raises(InputError, match=r"joints\[0\]: \['teeth'\] belong to gear pairs"):
        Mechanism.from_dict(data, "t.json")


def test_inverse_dynamics_carries_the_load_through_a_train():
    """A load torque T on the last gear of a three-gear train needs −T·z_0/z_2 at the input (virtual work; two
    external meshes: the last gear turns with the first, the idler drops out); the idler's tooth forces are
    equal (T/r_2 tangential each). Closed forms in tests/design/test_dynamics_contacts.py."""
    import dataclasses

    from domes.model.masses import Load, MassModel
    m = train([20, 30, 50])
    m = dataclasses.replace(m, masses=MassModel(loads=(Load("out", "g2", torque=4.0),)))
    dyn = inverse_dynamics(m, 0.0, 1.0, 0.25, speed=0.0, acceleration=0.0)
    assert np.allclose(dyn.driving["J0"], -4.0 * 20 / 50, rtol=1e-12)
    assert np.allclose(np.abs(dyn.contacts["M1"]), np.abs(dyn.contacts["M2"]), rtol=1e-12)
    assert np.allclose(np.abs(dyn.contacts["M2"]) * math.cos(math.radians(20)), 4.0 / (MODULE * 50 / 2), rtol=1e-12)


def test_a_labelled_chain_with_a_gear_pair_is_dimensioned():
    """A candidate of type synthesis with ``G`` joints becomes a geared mechanism: the gear joint's place is its
    pitch point. The geared five-bar of the indexing session (links 0 frame, 1 input, gear pair 1-2 on carrier 0)."""
    from domes.model import LabelledChain
    from domes.model.mechanism import from_labelled
    chain = LabelledChain.build(5, [(0, 1), (0, 2), (1, 2), (1, 3), (2, 4), (3, 4)], {(1, 2): "G"},
                                roles={0: {"ground"}, 1: {"input"}})
    m = from_labelled(chain, {(0, 1): (0, 0), (0, 2): (3, 0), (1, 2): (1, 0), (1, 3): (0, 1), (2, 4): (3, 0.8),
                              (3, 4): (1.5, 2.8)})
    assert [g.name for g in m.gears] == ["J1-2"] and m.meshes()[0].carrier == "0" and m.dof == 1
    sw = sweep(m, 0.0, 4 * math.pi, math.radians(10), outputs=["angle:2"], order=1)
    assert sw.success and np.allclose(sw.table["angle:2'"], -0.5 * m.inputs[0].speed, rtol=1e-13)
