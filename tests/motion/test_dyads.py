"""Seed 002 chapter 2 (§2-1, §2-2): the Assur-group dyads and the relative-angle four-bar (digest part E.1)."""

import math

import pytest
from kinematics_cases import solve_at

from domes.motion import Input, Joint, Mechanism, Structure
from domes.motion.planar.dyads import Unassembled, Undetermined, rpr, rrr, rrr_motion


def _traj(t):
    """Smooth outer-joint motions p1(t), p2(t)."""
    p1 = (0.2 * math.cos(t), 0.1 + 0.3 * math.sin(2 * t))
    p2 = (2.5 + 0.4 * math.sin(t), 0.5 * math.cos(t))
    return p1, p2


def _d(f, t, h):
    a, b = f(t + h), f(t - h)
    return tuple((x - y) / (2 * h) for x, y in zip(a, b))


def _dd(f, t, h):
    a, b, c = f(t + h), f(t), f(t - h)
    return tuple((x - 2 * y + z) / h ** 2 for x, y, z in zip(a, b, c))


def test_k05_rrr_dyad_against_finite_differences():
    # Seed 002 E.1 K-05: p3 keeps both lengths; θ̇ and θ̈ from (2-5)/(2-7) match FD (1e-6 / 1e-4 relative).
    l1, l2, t = 1.7, 1.4, 0.4

    def theta(tt):
        p1, p2 = _traj(tt)
        _, th1, th2 = rrr(p1, p2, l1, l2, 1)
        return th1, th2

    p1, p2 = _traj(t)
    p3, th1, th2 = rrr(p1, p2, l1, l2, 1)
    assert math.dist(p3, p1) == pytest.approx(l1, abs=1e-14)
    assert math.dist(p3, p2) == pytest.approx(l2, abs=1e-14)
    v1, v2 = _d(lambda x: _traj(x)[0], t, 1e-6), _d(lambda x: _traj(x)[1], t, 1e-6)
    a1, a2 = _dd(lambda x: _traj(x)[0], t, 1e-4), _dd(lambda x: _traj(x)[1], t, 1e-4)
    w1, w2, e1, e2 = rrr_motion(p1, p2, p3, v1, v2, a1, a2)
    assert (w1, w2) == pytest.approx(_d(theta, t, 1e-6), rel=1e-6)
    assert (e1, e2) == pytest.approx(_dd(theta, t, 1e-4), rel=1e-4)


def test_k06_rrr_cannot_be_assembled():
    # Seed 002 E.1 K-06: d > l1 + l2 or d < |l1 − l2| is refused.
    with pytest.raises(Unassembled):
        rrr((0, 0), (3, 0), 1, 1.5, 1)
    with pytest.raises(Unassembled):
        rrr((0, 0), (0.2, 0), 1, 2, 1)
    with pytest.raises(Undetermined):
        rrr((1, 1), (1, 1), 1, 1, 1)


def test_k07_rpr_dyad_corrected_signs():
    # Seed 002 E.1 K-07: e = 0.3, l3 = 1.7; θ̇, l̇2, θ̈, l̈2 and p̈3 match FD; the printed (2-16) sign would fail.
    e, l3, t = 0.3, 1.7, 0.7

    def at(tt):
        p1, p2 = _traj(tt)
        return rpr(p1, p2, e, l3, 1)

    p1, p2 = _traj(t)
    v1, v2 = _d(lambda x: _traj(x)[0], t, 1e-6), _d(lambda x: _traj(x)[1], t, 1e-6)
    a1, a2 = _dd(lambda x: _traj(x)[0], t, 1e-4), _dd(lambda x: _traj(x)[1], t, 1e-4)
    r = rpr(p1, p2, e, l3, 1, v1, v2, a1, a2)
    # p2 = p1 + l2·u(θ) + e·(sin θ, −cos θ)
    th, l2 = r["theta"], r["l2"]
    assert (p1[0] + l2 * math.cos(th) + e * math.sin(th), p1[1] + l2 * math.sin(th) - e * math.cos(th)) == \
        pytest.approx(p2, abs=1e-13)
    fd1 = _d(lambda x: (at(x)["theta"], at(x)["l2"]), t, 1e-6)
    fd2 = _dd(lambda x: (at(x)["theta"], at(x)["l2"]), t, 1e-4)
    assert (r["theta_d"], r["l2_d"]) == pytest.approx(fd1, rel=1e-5)
    assert (r["theta_dd"], r["l2_dd"]) == pytest.approx(fd2, rel=1e-5, abs=1e-6)
    assert r["p3_dd"] == pytest.approx(_dd(lambda x: at(x)["p3"], t, 1e-4), rel=1e-5, abs=1e-6)
    assert -r["l2_dd"] != pytest.approx(fd2[1], rel=1e-3)  # the book's printed sign of (2-16)


def _k09_four_bar(speed=1.6, accel=0.8):
    """Seed 002 E.1 K-09/K-11: a0 = (0,0), b0 = (3,0.5), a1 = (0.5,1.0), b1 = (2.5,2.2)."""
    return Mechanism.build("K-09", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("a0", "R", ("f", "crank"), (0, 0)), Joint("a", "R", ("crank", "coupler"), (0.5, 1.0)),
                            Joint("b", "R", ("coupler", "rocker"), (2.5, 2.2)), Joint("b0", "R", ("rocker", "f"), (3, 0.5))],
                           [Input("a0", speed, accel)])


@pytest.mark.parametrize("method", ["assur", "newton"])
def test_k09_relative_coupler_rotation(method):
    # Seed 002 E.1 K-09 [C]: at θ = 30° the coupler's rotation relative to the crank is −38.2379° (first root).
    m = _k09_four_bar()
    q0 = math.atan2(1.0, 0.5)
    v = solve_at(m, q0 + math.radians(30), order=0, method=method).values
    alpha = v["angle:coupler"] - m.reference_angle("coupler") - math.radians(30)
    assert math.degrees(alpha) == pytest.approx(-38.2379, abs=1e-4)


def test_k09_second_root_is_the_other_assembly_mode():
    # Seed 002 E.1 K-09 [C]: the second root −106.4039° is the mirror assembly of b about the line a–b0.
    a1, b0 = (0.5, 1.0), (3.0, 0.5)
    th = math.radians(30)
    a = (a1[0] * math.cos(th) - a1[1] * math.sin(th), a1[0] * math.sin(th) + a1[1] * math.cos(th))
    l1, l2 = math.dist(a1, (2.5, 2.2)), math.dist(b0, (2.5, 2.2))
    b, _, _ = rrr(a, b0, l1, l2, -1)
    rel = math.atan2(b[1] - a[1], b[0] - a[0]) - math.atan2(2.2 - 1.0, 2.5 - 0.5) - th
    assert math.degrees(math.remainder(rel, 2 * math.pi)) == pytest.approx(-106.4039, abs=1e-4)


@pytest.mark.parametrize("method", ["assur", "newton"])
def test_k11_relative_velocity_and_acceleration(method):
    # Seed 002 E.1 K-11 [C]: θ(t) = 0.3 + 1.2t + 0.4t² at t = 0.5 (θ = 1, θ̇ = 1.6, θ̈ = 0.8):
    # α̇ = −1.888889, φ̇ = 1.158487, α̈ = −0.827641.
    m = _k09_four_bar()
    v = solve_at(m, math.atan2(1.0, 0.5) + 1.0, method=method).values
    assert v["angle:coupler'"] - v["angle:crank'"] == pytest.approx(-1.888889, abs=1e-6)
    assert v["angle:rocker'"] == pytest.approx(1.158487, abs=1e-6)
    assert v["angle:coupler''"] - v["angle:crank''"] == pytest.approx(-0.827641, abs=1e-6)


def test_k08_branch_continuity():
    # Seed 002 E.1 K-08: in small steps the solution changes continuously (no jump > step × bound).
    from domes.motion import sweep
    sw = sweep(_k09_four_bar(), 0.0, 2 * math.pi, math.radians(2), outputs=["angle:rocker"], order=1)
    angles = [s.values["angle:rocker"] for s in sw.steps]
    rates = [abs(s.values["angle:rocker'"]) / 1.6 for s in sw.steps]
    bound = 2 * max(rates) * math.radians(2)
    assert max(abs(math.remainder(b - a, 2 * math.pi)) for a, b in zip(angles, angles[1:])) <= bound


def _dyad_mechanisms():
    """One mechanism per dyad kind, each with the driver on the ground (seed 002 F.1 kinds)."""
    y = 2 + math.sqrt(0.91)
    rrp = Mechanism.build("RRP", ["g", "crank", "rod", "slider"], "g",
                          [Joint("A", "R", ("g", "crank"), (0, 0)), Joint("B", "R", ("crank", "rod"), (0.6, 0.8)),
                           Joint("C", "R", ("rod", "slider"), (3.2, 0.3)), Joint("S", "P", ("g", "slider"), (3.2, 0.3), 0.2)],
                          [Input("A", 2.0, 0.5)])
    rpr_ = Mechanism.build("RPR", ["g", "crank", "block", "lever"], "g",
                           [Joint("O2", "R", ("g", "crank"), (0, 2)), Joint("A", "R", ("crank", "block"), (0.3, y)),
                            Joint("S", "P", ("lever", "block"), (0.3, y), math.pi / 2, (0.3, 0.0)),
                            Joint("O4", "R", ("lever", "g"), (0, 0))], [Input("O2", 2.0, 0.5)])
    # PRP: a slotted crank drives a block (P), pinned to a slider on a fixed guide (P).
    prp = Mechanism.build("PRP", ["g", "crank", "block", "slider"], "g",
                          [Joint("A", "R", ("g", "crank"), (0, 0)),
                           Joint("P1", "P", ("crank", "block"), (1.5, 0.6), math.atan2(0.6, 1.5)),
                           Joint("B", "R", ("block", "slider"), (1.5, 0.6)),
                           Joint("P2", "P", ("g", "slider"), (1.5, 0.6), math.radians(100))], [Input("A", 2.0, 0.5)])
    # RPP: Scotch yoke: crank pin in a block sliding in a yoke that slides on the frame.
    rpp = Mechanism.build("RPP", ["g", "crank", "block", "yoke"], "g",
                          [Joint("A", "R", ("g", "crank"), (0, 0)), Joint("B", "R", ("crank", "block"), (0.8, 0.6)),
                           Joint("P1", "P", ("yoke", "block"), (0.8, 0.6), math.radians(80)),
                           Joint("P2", "P", ("g", "yoke"), (0.8, -1.0), math.radians(10))], [Input("A", 2.0, 0.5)])
    return {"RRP": rrp, "RPR": rpr_, "PRP": prp, "RPP": rpp}


@pytest.mark.parametrize("kind", ["RRP", "RPR", "PRP", "RPP"])
def test_dyad_closed_forms_agree_with_newton(kind):
    # Seed 002 §2-1 / F.1: each closed-form dyad equals the seed-000 loop-closure Newton solution.
    m = _dyad_mechanisms()[kind]
    groups = Structure.of(m).groups
    assert groups[1].kind == kind
    q0 = Structure.of(m).drawn[f"q:{m.inputs[0].joint}"]
    for dq in (0.4, 1.3, -0.9):
        a = solve_at(m, q0 + dq, method="assur").values
        b = solve_at(m, q0 + dq, method="newton").values
        for k in a:
            assert b[k] == pytest.approx(a[k], abs=1e-9), (k, dq)


# -- §2-2 displacement matrices (digest E.1 K-01..K-04) -----------------------------------------------------


def test_k01_displacement_matrix_example_1():
    # Seed 002 例1 (K-01): θ = 60°, p1 = (1,1), p = (3,2), q1 = (3,1) → D, q = (4.000, 3.732) (abs 1e-3; exact
    # 3.3660254, 0.6339746, 3.7320508).
    from domes.motion.planar.matrices import apply, displacement_matrix
    D = displacement_matrix(math.radians(60), (1, 1), (3, 2))
    assert D[0] == pytest.approx((0.5, -0.866, 3.366), abs=1e-3)
    assert D[1] == pytest.approx((0.866, 0.5, 0.634), abs=1e-3)
    assert (D[0][2], D[1][2]) == pytest.approx((3.3660254, 0.6339746), abs=1e-7)
    assert apply(D, (3, 1)) == pytest.approx((4.0, 3.7320508), abs=1e-7)


def test_k02_to_k04_rigid_velocity_and_acceleration_matrices():
    # K-02: D is rigid (distances kept); K-03/K-04: V·[q;1] and A·[q;1] match FD of D(t)·[q1;1] (1e-7 / 1e-5 rel).
    from domes.motion.planar.matrices import acceleration_matrix, apply, displacement_matrix, velocity_matrix
    p1, q1, r1 = (0.3, -0.2), (1.7, 0.9), (-0.4, 2.2)

    def th(t):
        return 0.4 + 1.3 * t + 0.7 * t * t

    def p(t):
        return (1.0 + 0.5 * t - 0.2 * t * t, -0.3 + 0.8 * t + 0.1 * t ** 3)

    t = 0.6
    D = displacement_matrix(th(t), p1, p(t))
    assert math.dist(apply(D, q1), apply(D, r1)) == pytest.approx(math.dist(q1, r1), abs=1e-14)
    q = apply(D, q1)
    V = velocity_matrix(1.3 + 1.4 * t, p(t), _d(p, t, 1e-6))
    assert apply(V, q) == pytest.approx(_d(lambda x: apply(displacement_matrix(th(x), p1, p(x)), q1), t, 1e-6), rel=1e-7)
    A = acceleration_matrix(1.3 + 1.4 * t, 1.4, p(t), _dd(p, t, 1e-4))
    assert apply(A, q) == pytest.approx(_dd(lambda x: apply(displacement_matrix(th(x), p1, p(x)), q1), t, 1e-4),
                                        rel=1e-5)
