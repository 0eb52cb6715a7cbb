"""Seed 000 (link units, Wang et al. 2010): tests T1, T3–T9 of the digest, §5."""

import math
import random

import pytest
from kinematics_cases import angle_diff, example, solve_at

from domes.errors import DomesError
from domes.motion import CouplerPoint, Input, Joint, Mechanism, Structure, sweep
from domes.motion.planar.examples import triple_rocker
from domes.motion.planar.units import reverse, rp1_unit, rp2_unit, rr_unit

# -- T1: link units are the derivatives of the vector unit; reversal negates -------------------------------


def _fd(f, x, h=1e-6):
    return [(a - b) / (2 * h) for a, b in zip(f(x + h), f(x - h))]


@pytest.mark.parametrize("seed", range(5))
def test_t1_units_are_derivatives(seed):
    # Seed 000 T1: ∇J = ∂∇A/∂vars and ∇J̇ = d∇J/dt along a random trajectory (tol 1e-6, h = 1e-6).
    rnd = random.Random(seed)
    l, alpha, e = rnd.uniform(0.5, 3), rnd.uniform(-3, 3), rnd.uniform(-1, 1)
    phi, s, w, sd = rnd.uniform(-3, 3), rnd.uniform(-2, 2), rnd.uniform(-5, 5), rnd.uniform(-5, 5)
    A, J, Jd = rr_unit(l, alpha, phi, w)
    assert _fd(lambda x: rr_unit(l, alpha, x, w)[0], phi) == pytest.approx(J[0], abs=1e-6)
    assert _fd(lambda t: rr_unit(l, alpha, phi + w * t, w)[1][0], 0.0) == pytest.approx(Jd[0], abs=1e-6)
    A, J, Jd = rp1_unit(e, phi, w)
    assert _fd(lambda x: rp1_unit(e, x, w)[0], phi) == pytest.approx(J[0], abs=1e-6)
    assert _fd(lambda t: rp1_unit(e, phi + w * t, w)[1][0], 0.0) == pytest.approx(Jd[0], abs=1e-6)
    A, J, Jd = rp2_unit(e, phi, s, w, sd)
    assert _fd(lambda x: rp2_unit(e, x, s, w, sd)[0], phi) == pytest.approx(J[0], abs=1e-6)
    assert _fd(lambda x: rp2_unit(e, phi, x, w, sd)[0], s) == pytest.approx(J[1], abs=1e-6)
    for k in (0, 1):
        along = _fd(lambda t: rp2_unit(e, phi + w * t, s + sd * t, w, sd)[1][k], 0.0)
        assert along == pytest.approx(Jd[k], abs=1e-6)
    unit = rp2_unit(e, phi, s, w, sd)
    back = reverse(unit)
    assert back[0] == tuple(-x for x in unit[0])
    assert back[2] == tuple(tuple(-x for x in c) for c in unit[2])


def test_t1_rp2_carries_the_coriolis_term():
    # Seed 000 T1/§2.5: ∇J̇·[φ̇; ṡ] contains 2ṡφ̇ (the printed Table 1 gives (ṡ + φ̇)φ̇).
    e, phi, s, w, sd = 0.0, 0.0, 1.0, 3.0, 5.0
    _, _, Jd = rp2_unit(e, phi, s, w, sd)
    ay = Jd[0][1] * w + Jd[1][1] * sd
    assert ay == pytest.approx(2 * sd * w)


# -- T4/T5: topology counts and the eight-bar's Assur decomposition -------------------------------


def test_t4_six_bar_counts():
    # Seed 000 T4: the six-bar of Fig. 2 has n = 6, p = 7, L = 2, DOF = 1.
    m = example("watt-six-bar.json")
    assert (len(m.links), len(m.joints), m.loops, m.dof) == (6, 7, 2, 1)


def test_t4_compound_hinge_is_split():
    # Seed 000 T4/§2.11: a hinge of m links becomes m − 1 joints at the same point.
    m = Mechanism.build("c", ["g", "a", "b", "c", "d", "e"], "g",
                        [Joint("A", "R", ("g", "a"), (0, 0)), Joint("B", "R", ("a", "b"), (1, 0)),
                         Joint("C", "R", ("b", "c", "d"), (3, 2)), Joint("D", "R", ("c", "g"), (3, 0)),
                         Joint("E", "R", ("d", "e"), (5, 2)), Joint("F", "P", ("g", "e"), (5, 2), 0.0)],
                        [Input("A")])
    assert [j.name for j in m.joints if j.at == (3, 2)] == ["C", "C.1"]
    assert (len(m.links), len(m.joints), m.loops, m.dof) == (6, 7, 2, 1)
    assert [g.kind for g in Structure.of(m).groups] == ["driver", "RRR", "RRP"]


def test_t5_eight_bar_decomposition():
    # Seed 000 T5: 3 loops, DOF 1; frame U, input X give one class-II dyad and one class-IV group.
    m = example("eight-bar-class-iv.json")
    assert (m.loops, m.dof) == (3, 1)
    groups = Structure.of(m).groups
    assert [(g.kind, set(g.links)) for g in groups] == [
        ("driver", {"X"}), ("RRR", {"Y", "Q"}), ("class-IV", {"Z", "W", "T", "V"})]
    assert sum(g.equations for g in groups) == 2 * m.loops


# -- T6: the six-bar at four input angles --------------------------------------------------------------

T6 = {  # φ1 (deg): φ2, φ3, φ5, s, φ̇2, φ̇3, φ̇5, ṡ, φ̈2, φ̈3, φ̈5, s̈
    0: (0.77519337331, 0.32224085481, -0.42064184862, 8.5483644019, -5.0, -5.0, 2.5977762063, 7.4100992776,
        15.309310892, 76.546554462, -38.452324703, -183.35801951),
    60: (0.45921387904, 0.26579067694, -0.39124121319, 8.6275160378, -0.99565664184, 2.9435363439, -1.5361652992,
         -3.8895520318, 29.227545108, 38.442357534, -19.804669187, -75.850693632),
    150: (0.55265851904, 0.88632613792, -0.69108948831, 7.3467334842, 1.8395447503, 3.5852225797, -1.4708949408,
          -9.3053908589, 13.842310337, -16.979572814, 11.638492688, 33.059984783),
    270: (1.0846921891, 1.1011108318, -0.76961019358, 6.7779396127, 1.7844645406, -2.1378581622, 0.67365039011,
          5.6877547912, -29.350450456, -37.899102501, 14.339888466, 102.06314923),
}
T6_POINTS = {0: {"c": (3.5, 2.4494897428), "e": (4.8970562748, 0.6333857356)},
             150: {"c": (2.1129363759, 2.3373314114), "e": (4.2645252538, 1.5495082712)}}


@pytest.mark.parametrize("method", ["assur", "newton"])
@pytest.mark.parametrize("deg", sorted(T6))
def test_t6_six_bar(deg, method):
    # Seed 000 T6 [D]: positions abs 1e-8; velocities and accelerations 1e-7·max(1, |value|).
    m = example("watt-six-bar.json")
    step = solve_at(m, math.radians(deg), method=method)
    v = step.values
    names = ["angle:coupler", "angle:rocker", "angle:rod", "slide:g"]
    expect = T6[deg]
    for k, name in enumerate(names):
        got = v[name]
        if name.startswith("angle"):
            assert abs(angle_diff(got, expect[k])) <= 1e-8, name
        else:
            assert got == pytest.approx(expect[k], abs=1e-8)
        assert v[name + "'"] == pytest.approx(expect[4 + k], abs=1e-7 * max(1, abs(expect[4 + k]))), name
        assert v[name + "''"] == pytest.approx(expect[8 + k], abs=1e-7 * max(1, abs(expect[8 + k]))), name
    assert step.residual <= 1e-10


@pytest.mark.parametrize("deg", sorted(T6_POINTS))
def test_t6_joint_points(deg):
    # Seed 000 T6 [D], joint-point table (10 digits printed).
    m = example("watt-six-bar.json")
    v = solve_at(m, math.radians(deg), outputs=["point:c", "point:e"], order=0).values
    for name, (x, y) in T6_POINTS[deg].items():
        assert (v[f"point:{name}.x"], v[f"point:{name}.y"]) == pytest.approx((x, y), abs=1e-9)


def test_t6_rocker_rate_is_exactly_minus_five_at_zero():
    # Seed 000 T6 anchor: at φ1 = 0, φ̇2 = φ̇3 = −5 exactly.
    v = solve_at(example("watt-six-bar.json"), 0.0, order=1).values
    assert v["angle:coupler'"] == pytest.approx(-5.0, abs=1e-12)
    assert v["angle:rocker'"] == pytest.approx(-5.0, abs=1e-12)


# -- T7 / T8: the offset slotted lever, two ways -------------------------------------------------------

T7 = {  # φ2 (deg): φ4, s, φ̇4, ṡ, φ̈4, s̈
    0: (1.2417185842, 2.2158519806, 1.4584475811, 9.0258736481, 30.538335518, -36.765269442),
    30: (1.3509568903, 2.6286878856, 2.5747557799, 6.5890318019, 14.340036311, -54.557766584),
    120: (1.8468164455, 2.8938040043, 3.3502912749, -3.4556590513, -1.6304225967, -63.980373226),
    225: (2.276282971, 1.4427657035, -0.55328800517, -9.8021013316, -76.671829343, 31.425868809),
}
T7_WRONG = {0: (35.519125904, -38.2595065584), 30: (18.2719524755, -55.7373414339),
            120: (-9.5099873363, -61.6165038039), 225: (-73.1249904739, 30.3618171487)}


def _slotted_lever_block_offset():
    """Seed 000 T8: the same lever with the offset carried by the block (RP1 with e = −0.3), guide through O4."""
    y = 2 + math.sqrt(0.91)
    return Mechanism.build(
        "T8", ["frame", "crank", "block", "lever"], "frame",
        [Joint("O2", "R", ("frame", "crank"), (0, 2)), Joint("A", "R", ("crank", "block"), (0.3, y)),
         Joint("S", "P", ("lever", "block"), (0.0, y), math.pi / 2, (0.0, 0.0)), Joint("O4", "R", ("lever", "frame"), (0, 0))],
        [Input("O2", 10.0)], link_angles={"lever": math.pi / 2})


@pytest.mark.parametrize("method", ["assur", "newton"])
@pytest.mark.parametrize("deg", sorted(T7))
def test_t7_slotted_lever(deg, method):
    # Seed 000 T7 [D]: guide-type RP2 unit with a rotating guide (tests the Table 1 correction).
    step = solve_at(example("inverted-slider.json"), math.radians(deg), method=method)
    v, e = step.values, T7[deg]
    assert abs(angle_diff(v["angle:lever"], e[0])) <= 1e-8
    assert v["slide:S"] == pytest.approx(e[1], abs=1e-8)
    for name, k in (("angle:lever", 2), ("slide:S", 3)):
        assert v[name + "'"] == pytest.approx(e[k], abs=1e-7 * max(1, abs(e[k])))
        assert v[name + "''"] == pytest.approx(e[k + 2], abs=1e-7 * max(1, abs(e[k + 2])))
    wrong = T7_WRONG[deg]
    assert abs(v["angle:lever''"] - wrong[0]) > 1e-3 and abs(v["slide:S''"] - wrong[1]) > 1e-3


@pytest.mark.parametrize("method", ["assur", "newton"])
@pytest.mark.parametrize("deg", sorted(T7))
def test_t8_shared_rotation_through_p_pair(deg, method):
    # Seed 000 T8: the same mechanism with the offset on the block; results identical to T7 (≤ 1e-9).
    a = solve_at(example("inverted-slider.json"), math.radians(deg), outputs=["angle:lever", "slide:S"]).values
    b = solve_at(_slotted_lever_block_offset(), math.radians(deg), outputs=["angle:lever", "slide:S"], method=method).values
    for k in a:
        assert b[k] == pytest.approx(a[k], abs=1e-9), k


# -- T9: the non-Grashof four-bar's limit ---------------------------------------------------------------

T9 = {30: (48.56357641, 88.72499539), 90: (8.11832252, 114.08033669), 120: (-7.29241781, 143.75255782),
      127: (-18.41348512, 157.28108837)}


@pytest.mark.parametrize("method", ["assur", "newton"])
def test_t9_limit_of_the_triple_rocker(method):
    # Seed 000 T9: 1° steps succeed through 127°, 128° is refused, the limit is arccos(−29/48) (tol 1e-4°).
    sw = sweep(triple_rocker(), 0.0, math.radians(135), math.radians(1), outputs=["angle:coupler", "angle:rocker"],
               method=method)
    assert sw.status == "stopped"
    reached = [round(math.degrees(s.inputs["A"]), 9) for s in sw.steps]
    assert reached[-1] == 127
    limit = sw.dead_points[0]
    assert limit.kind == "limit"
    assert math.degrees(limit.input) == pytest.approx(math.degrees(math.acos(-29 / 48)), abs=1e-4)
    assert set(limit.joints) >= {"B", "C", "D"}
    by_deg = {round(math.degrees(s.inputs["A"])): s for s in sw.steps}
    for deg, (phi2, phi3) in T9.items():
        v = by_deg[deg].values
        assert math.degrees(v["angle:coupler"]) == pytest.approx(phi2, abs=1e-7)
        assert math.degrees(v["angle:rocker"]) == pytest.approx(phi3, abs=1e-7)


def test_t9_solving_beyond_the_limit_is_an_error_naming_the_joints():
    # Seed 000 T9: at 128° there is no solution: a precise error, never a pose.
    with pytest.raises(DomesError, match=r"joints B, C, D.*127\.1688"):
        solve_at(triple_rocker(), math.radians(128), order=0)


# -- T2: the six-bar's assembled matrices against the paper's symbolic J and B (§2.9) -------------------


def test_t2_six_bar_assembly_matches_the_symbolic_matrices():
    # Seed 000 T2: loops (a,b,c,d), (d,e,f,g); unknowns [φ2, φ3, φ5, s]; J and B equal the §2.9 matrices (up to
    # the orientation of each loop), including the zero pattern J[0:2, 2:4] = 0, J[2:4, 0] = 0, B[2:4] = 0.
    import numpy as np

    from domes.motion import Kinematics
    from domes.motion.planar.structure import evaluate
    m = example("watt-six-bar.json")
    kin = Kinematics(m, order=1, method="newton")
    (g,) = [g for g in kin.groups if g.unknowns]
    assert g.unknowns == ("rot:coupler", "rot:rocker", "rot:rod", "s:g")
    step = solve_at(m, math.radians(60), order=1, method="newton")
    values = step.state
    _, J = kin._assemble(g, values)
    B = np.concatenate([evaluate(loop, values)[1].get("q:a", [0.0, 0.0]) for loop in g.loops])
    p1, (p2, p3, p5, _) = math.radians(60), T6[60][:4]
    al, l1, l2, l3d, l3, l5, guide = math.radians(60), 1.0, 3.5, 2.5, 2.0, 4.0, 0.0
    Jp = np.array([[-l2 * math.sin(p2), l3d * math.sin(p3 + al), 0, 0],
                   [l2 * math.cos(p2), -l3d * math.cos(p3 + al), 0, 0],
                   [0, -l3 * math.sin(p3), -l5 * math.sin(p5), -math.cos(guide)],
                   [0, l3 * math.cos(p3), l5 * math.cos(p5), -math.sin(guide)]])
    Bp = np.array([-l1 * math.sin(p1), l1 * math.cos(p1), 0, 0])
    for rows in (slice(0, 2), slice(2, 4)):
        sign = 1.0 if np.allclose(J[rows], Jp[rows], atol=1e-9) else -1.0
        assert np.allclose(sign * J[rows], Jp[rows], atol=1e-9)
        assert np.allclose(sign * B[rows], Bp[rows], atol=1e-9)


# -- T10: multi-DOF and an open (end) link ----------------------------------------------------------------------


def test_t10_two_dof_five_bar_and_an_end_link():
    # Seed 000 T10 [P]: a 2-DOF five-bar (two grounded cranks as knowns: TK = 2, TU = 2, L = 1) with an end link
    # driven relative to the coupler (open chain: no loop equations). Velocities and accelerations match finite
    # differences of positions when both inputs move.
    from domes.motion import Kinematics
    from domes.motion.planar.sweep import Continuation
    m = Mechanism.build("five-bar", ["g", "c1", "l1", "l2", "c2", "tool"], "g",
                        [Joint("A", "R", ("g", "c1"), (0, 0)), Joint("B", "R", ("c1", "l1"), (0.5, 0.9)),
                         Joint("C", "R", ("l1", "l2"), (2.0, 2.4)), Joint("D", "R", ("l2", "c2"), (3.4, 1.0)),
                         Joint("E", "R", ("c2", "g"), (3.0, 0.0)), Joint("T", "R", ("l1", "tool"), (1.2, 1.6))],
                        [Input("A", 2.0, 0.3), Input("E", -1.0, 0.1), Input("T", 0.5, 0.0)],
                        points=[CouplerPoint("tip", "tool", (1.2, 2.6))])
    kin = Kinematics(m, ["angle:l2", "point:tip"], order=2, accuracy="exact")
    assert [g.kind for g in kin.groups] == ["driver", "driver", "RRR", "driver"]
    assert kin.equations == 2
    drawn = kin.drawn_inputs()
    state = Continuation(kin).start(drawn["A"])
    step = kin.at(drawn, state)

    def pos(t):
        q = {j: drawn[j] + i.speed * t + 0.5 * i.acceleration * t * t for j, i in kin.inputs.items()}
        return kin.output_values(kin.positions(q, state), {}, {}, 0)

    h1, h2 = 1e-6, 1e-4
    for col in ("angle:l2", "point:tip.x", "point:tip.y"):
        d1 = (pos(h1)[col] - pos(-h1)[col]) / (2 * h1)
        d2 = (pos(h2)[col] - 2 * pos(0.0)[col] + pos(-h2)[col]) / h2 ** 2
        assert step.values[col + "'"] == pytest.approx(d1, rel=1e-6, abs=1e-7)
        assert step.values[col + "''"] == pytest.approx(d2, rel=1e-4, abs=1e-5)
