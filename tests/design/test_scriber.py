"""The 2-RPR scriber of seed 003 (Deng et al.): the digest's test values D-1 .. D-15.

The paper prints no numbers (its results are Fig. 5, lost); the values below
are the digest's (``shared/digests/seed-003-parallel-2dof.md`` §9, §10),
computed there by three routes (finite differences, a symbolic Lagrangian,
the closed-form mass matrix) with the paper's geometry (H = 317 mm,
s_a = s_b = 0, l = 400 mm) and assumed masses m = 1 kg. D-16 (the blade's six
segments) cannot be reproduced: the paper gives no coordinates.
"""

import math

import numpy as np
import pytest

from domes.design.contour import Contour
from domes.design.dynamics import inverse_dynamics
from domes.design.scriber import Scriber, follow
from domes.errors import InputError

S = Scriber(H=0.317)
D1 = np.array([0.2 + 0.1j])


def state(P, V, A):
    return S.rates(np.array([P]), np.array([V]), np.array([A]))


def forces(P, V, A, kinetic="corrected", equations="corrected"):
    q, th, qd, qdd = state(P, V, A)
    return S.forces(q, th, qd, qdd, kinetic, equations)


def test_d1_inverse_kinematics():
    q, th = S.inverse(D1)
    np.testing.assert_allclose(q[:, 0] * 1000, [223.6068, 295.1085], atol=5e-5)  # the printed digits
    np.testing.assert_allclose(np.degrees(th[:, 0]), [26.5651, -47.3345], atol=5e-5)
    np.testing.assert_allclose(q[:, 0], [math.hypot(0.2, 0.1), math.hypot(0.2, 0.217)], rtol=1e-15)


def test_d2_forward_kinematics_both_branches():
    q, _ = S.inverse(D1)
    np.testing.assert_allclose(S.forward(q), D1, rtol=1e-12)
    np.testing.assert_allclose(S.forward(q, branch=-1), [-0.2 + 0.1j], rtol=1e-12)
    assert np.isnan(S.forward(np.array([[0.1], [0.1]]))).all()  # |q1 − q2| ≤ d ≤ q1 + q2 fails


def test_d3_jacobian_and_finite_differences_of_forward_kinematics():
    J, Jinv, sine = S.jacobian(D1)
    np.testing.assert_allclose(J[0], [[0.76534188, 0.46547075], [0.70538422, -0.93094150]], rtol=1e-7)
    np.testing.assert_allclose(Jinv[0], [[0.89442719, 0.44721360], [0.67771694, -0.73532288]], rtol=1e-7)
    np.testing.assert_allclose(sine, [-0.96077701], rtol=1e-7)
    q, _ = S.inverse(D1)
    h = 1e-6
    for k in range(2):
        dq = np.zeros((2, 1))
        dq[k] = h
        col = (S.forward(q + dq) - S.forward(q - dq)) / (2 * h)
        np.testing.assert_allclose([col.real[0], col.imag[0]], J[0][:, k], rtol=1e-7)


def test_d4_partial_velocities_of_eq7():
    q, th = S.inverse(D1)
    u = S.partials(q, th)[:, :, 0]
    np.testing.assert_allclose(u[0], [1.29085312, -4.65470749], rtol=1e-7)
    np.testing.assert_allclose(u[1], [3.52692110, -0.97809307], rtol=1e-7)
    h = 1e-6
    for k in range(2):
        dq = np.zeros((2, 1))
        dq[k] = h
        plus, minus = S.inverse(S.forward(q + dq))[1], S.inverse(S.forward(q - dq))[1]
        np.testing.assert_allclose((plus - minus)[:, 0] / (2 * h), u[:, k], rtol=1e-7)


def test_d5_singularity_on_the_line_ab():
    P = np.array([1e-6 + 0.15j, 0.2 + 0.1j])
    check = S.check(P)
    assert check["singular"].tolist() == [True, False]
    q = check["q"]
    np.testing.assert_allclose(check["sine"][0], -1e-6 * 0.317 / (q[0, 0] * q[1, 0]), rtol=1e-6)
    J, _, _ = S.jacobian(P)
    assert np.linalg.cond(J[0]) > 1e4 * np.linalg.cond(J[1])
    q, th = S.inverse(P)
    M = S.mass_matrix(q, th)
    assert np.abs(M[0]).max() > 1e6 * np.abs(M[1]).max()


def test_d6_mass_matrices_and_the_rigid_body_kinetic_energy():
    q, th = S.inverse(D1)
    MC, MP = S.mass_matrix(q, th)[0], S.mass_matrix(q, th, "paper")[0]
    np.testing.assert_allclose(MC, [[1.30152159, -0.16066207], [-0.16066207, 1.32236742]], atol=5e-9)
    np.testing.assert_allclose(MP, [[1.41497019, -0.19521480], [-0.19521480, 1.34309527]], atol=5e-9)
    np.testing.assert_allclose(np.linalg.eigvalsh(MC), [1.1509447, 1.4729443], rtol=1e-7)
    np.testing.assert_allclose(np.linalg.eigvalsh(MP), [1.1805376, 1.5775279], rtol=1e-7)
    # the rigid-body energy from the centroids' velocities and the centroidal inertia m l²/12:
    qd = np.array([0.3, -0.7])
    _, J = S.jacobian(D1)[:2]
    Pd = np.linalg.solve(J[0], qd)  # Ṗ from q̇ = J⁻¹ Ṗ
    u = S.partials(q, th)[:, :, 0]
    wd = u @ qd
    e = np.exp(1j * th[:, 0])
    kinetic = 0.0
    for i in range(2):
        vc = (Pd[0] + 1j * Pd[1]) - 0.2 * 1j * wd[i] * e[i]  # c_i = P − (l/2) e_i
        kinetic += 0.5 * abs(vc) ** 2 + 0.5 * (0.4 ** 2 / 12) * wd[i] ** 2
    assert 0.5 * qd @ MC @ qd == pytest.approx(kinetic, rel=1e-10)
    r = q[:, 0] - 0.2
    extra = sum(0.5 * r[i] ** 2 * wd[i] ** 2 for i in range(2))
    assert 0.5 * qd @ MP @ qd == pytest.approx(kinetic + extra, rel=1e-10)


def test_mass_derivatives_equal_finite_differences():
    q, th = S.inverse(np.array([0.2 + 0.1j, 0.31 + 0.22j]))
    for kinetic in ("corrected", "paper"):
        dM = S.mass_derivatives(q, th, kinetic)
        h = 1e-6
        for k in range(2):
            dq = np.zeros((2, 1))
            dq[k] = h
            plus = S.mass_matrix(*S.inverse(S.forward(q + dq)), kinetic)
            minus = S.mass_matrix(*S.inverse(S.forward(q - dq)), kinetic)
            np.testing.assert_allclose((plus - minus) / (2 * h), dM[..., k], rtol=1e-7, atol=1e-8)


S1 = (0.2 + 0.13j, 0.1j, 0j)
S2 = (0.3 + 0.15j, 0.1j, -0.2 + 0j)


def test_d7_power_balance_holds_for_the_corrected_equations_and_not_for_the_printed_ones():
    for st in (S1, S2):
        for kinetic in ("corrected", "paper"):
            f = forces(*st, kinetic)
            assert f["power"][0] == pytest.approx(f["energy_rate"][0], rel=1e-12)
    f = forces(*S1, "corrected")
    assert f["power"][0] == pytest.approx(6.2149439e-6, rel=1e-6)
    f = forces(*S1, "paper")
    assert f["power"][0] == pytest.approx(1.6511106e-5, rel=1e-6)
    printed = forces(*S1, "paper", "printed")
    np.testing.assert_allclose(printed["Q"][0], [0.04077693, 0.04402687], rtol=1e-6)
    assert printed["power"][0] == pytest.approx(-7.846e-4, rel=1e-3)
    assert printed["energy_rate"][0] == pytest.approx(1.6511106e-5, rel=1e-6)


def test_d8_forces_scale_with_the_square_of_the_speed():
    slow, fast = forces(*S1), forces(S1[0], 0.3j, 0j)
    np.testing.assert_allclose(fast["Q"][0], [0.20751562, 0.16477221], rtol=1e-7)
    np.testing.assert_allclose(fast["Q"], 9.0 * slow["Q"], rtol=1e-12)


def test_d9_reversing_the_direction_keeps_the_forces():
    np.testing.assert_allclose(forces(S1[0], -0.1j, 0j)["Q"], forces(*S1)["Q"], rtol=1e-12)


def test_d10_mirror_about_half_height_swaps_the_forces():
    mirrored = forces(0.2 + 0.187j, -0.1j, 0j)["Q"][0]
    np.testing.assert_allclose(mirrored, [0.01830802, 0.02305729], atol=5e-9)
    np.testing.assert_allclose(mirrored, forces(*S1)["Q"][0][::-1], rtol=1e-10)


def test_d11_reference_inverse_dynamics():
    q, _, qd, qdd = state(*S1)
    np.testing.assert_allclose(q[:, 0], [0.23853721, 0.27380467], rtol=1e-7)
    np.testing.assert_allclose(qd[:, 0], [0.05449884, -0.06829686], rtol=1e-7)
    np.testing.assert_allclose(qdd[:, 0], [0.02947078, 0.01948666], rtol=1e-6)
    np.testing.assert_allclose(forces(*S1)["Q"][0], [0.02305729, 0.01830802], rtol=1e-6)
    np.testing.assert_allclose(forces(*S1, "paper")["Q"][0], [0.01218913, 0.00948480], rtol=1e-6)
    q, _, qd, qdd = state(*S2)
    np.testing.assert_allclose(qdd[:, 0], [-0.15503405, -0.15251420], rtol=1e-7)
    np.testing.assert_allclose(forces(*S2)["Q"][0], [-0.18323286, -0.17452348], rtol=1e-6)
    np.testing.assert_allclose(forces(*S2, "paper")["Q"][0], [-0.20680816, -0.19272086], rtol=1e-6)


def test_lagrange_model_equals_the_newton_euler_solve_of_the_same_mechanism():
    # Independent routes: the scriber's closed-form Lagrange model (Variant C) and the general inverse
    # dynamics (kinematics backend + Newton–Euler per link) of the 2-RPR written as a mechanism.
    pts = 0.2 + 0.13j + 0.01 * np.arange(8) * np.exp(0.1j * np.arange(8))  # a smooth walk
    V = 0.1j * np.exp(0.4j * np.arange(8))
    A = (0.3 - 0.2j) * np.exp(-0.7j * np.arange(8))
    q, th, qd, qdd = S.rates(pts, V, A)
    f = S.forces(q, th, qd, qdd)
    dyn = inverse_dynamics(S.mechanism(pts[0]), motion={"q1": (q[0], qd[0], qdd[0]), "q2": (q[1], qd[1], qdd[1])})
    np.testing.assert_allclose(np.stack([dyn.driving["q1"], dyn.driving["q2"]], 1), f["Q"], rtol=1e-9)
    assert dyn.max_imbalance < 1e-12


def stadium():
    return Contour.from_dict({"name": "stadium", "start": [0.25, 0.1085], "segments": [
        {"line": [0.25, 0.2085]}, {"arc": {"centre": [0.2, 0.2085], "to": [0.15, 0.2085], "turn": "ccw"}},
        {"line": [0.15, 0.1085]}, {"arc": {"centre": [0.2, 0.1085], "to": [0.25, 0.1085], "turn": "ccw"}}]}, "D-14")


def test_d13_line_arc_junction_jumps():
    run = follow(S, stadium(), 0.1, 400)
    j = run.junctions[0]  # line x = 0.25 up into the arc about (0.2, 0.2085), radius 0.05
    assert j.corner == pytest.approx(0.0, abs=1e-12)
    P = 0.25 + 0.2085j
    q, th = S.inverse(np.array([P]))
    nu = -1.0 + 0j  # towards the centre
    e = np.exp(1j * th[:, 0])
    expected = (e.real * nu.real + e.imag * nu.imag) * 0.1 ** 2 / 0.05
    np.testing.assert_allclose(j.jump_qdd, expected, rtol=1e-9)
    M = S.mass_matrix(q, th)[0]
    np.testing.assert_allclose(j.jump_Q, M @ expected, rtol=1e-9)
    # q̇ is continuous there
    seg_a, seg_b = stadium().segments[:2]
    va = S.rates(*seg_a.at(np.array([seg_a.length]), 0.1))[2]
    vb = S.rates(*seg_b.at(np.array([0.0]), 0.1))[2]
    np.testing.assert_allclose(va, vb, rtol=1e-12)


def test_d14_closed_contour_work_and_force_spreads():
    run = follow(S, stadium(), 0.1, 4000)
    assert run.success and run.contour.closed
    assert run.time[-1] + run.time[0] == pytest.approx(5.1416, abs=1e-4)
    assert run.peak_power == pytest.approx(5.74e-3, rel=1e-3)
    assert abs(run.work) <= 1e-6 * run.peak_power * 5.1416
    assert run.max_imbalance < 1e-12
    spreads = run.spreads()
    assert spreads["line"][1] - spreads["line"][0] == pytest.approx(0.0271, rel=1e-2)
    assert spreads["arc"][1] - spreads["arc"][0] == pytest.approx(0.5554, rel=1e-3)
    assert spreads["arc"][0] == pytest.approx(-0.2410, abs=1e-4) and spreads["arc"][1] == pytest.approx(0.3144, abs=1e-4)
    assert spreads["line"][0] == pytest.approx(0.0123, abs=1e-4) and spreads["line"][1] == pytest.approx(0.0395, abs=1e-4)
    paper = follow(S, stadium(), 0.1, 4000, kinetic="paper").spreads()
    assert paper["line"][1] - paper["line"][0] == pytest.approx(0.0336, rel=1e-2)
    assert paper["arc"][1] - paper["arc"][0] == pytest.approx(0.6025, rel=1e-3)


def test_d15_stroke_limits():
    y = 0.317 / 2
    limit = math.sqrt(0.4 ** 2 - y ** 2)
    assert limit == pytest.approx(0.36726, abs=1e-5)
    check = S.check(np.array([0.367 + 1j * y, 0.368 + 1j * y]))
    assert check["stroke"].tolist() == [True, False]
    far = Contour.from_dict({"start": [0.3, y], "segments": [{"line": [0.39, y]}]}, "far")
    run = follow(S, far, 0.1, 90)
    assert not run.success and "out of stroke" in run.message


def test_a_contour_out_of_stroke_stops_where_the_stroke_ends():
    # issue 25, item 4: the run went on through every point out of stroke, its numbers in the table
    y = 0.317 / 2
    limit = math.sqrt(0.4 ** 2 - y ** 2)
    far = Contour.from_dict({"start": [0.3, y], "segments": [{"line": [0.39, y]}, {"line": [0.3, y]}]}, "far")
    run = follow(S, far, 0.1, 900)
    assert str(run.status) == "stopped" and run.s.size == int((limit - 0.3) / 0.18 * 900 + 0.5)
    assert run.P[-1].real < limit and run.junctions == () and np.all(np.isfinite(run.Q))
    assert f"leaves the scriber's reach at s = {limit - 0.3:.6g} (x = {limit:.6g}, y = {y:.6g}): the stroke ends " \
           "there" in run.message
    start = Contour.from_dict({"start": [0.39, y], "segments": [{"line": [0.3, y]}]}, "start")
    with pytest.raises(InputError, match=r"leaves the scriber's reach at s = 0 \(x = 0.39.*before its first sample"):
        follow(S, start, 0.1, 100)


def test_corners_and_bad_contours_are_reported():
    square = Contour.from_dict({"start": [0.2, 0.1], "segments": [{"line": [0.3, 0.1]}, {"line": [0.3, 0.2]}]}, "sq")
    assert "corner of 90°" in follow(S, square, 0.1, 100).message
    with pytest.raises(InputError, match="keeps its radius"):
        Contour.from_dict({"start": [0, 0], "segments": [{"arc": {"centre": [1, 0], "to": [1, 2]}}]}, "bad")
    with pytest.raises(InputError, match=r"segments\[0\]"):
        Contour.from_dict({"start": [0, 0], "segments": [{"spline": [1, 0]}]}, "bad")
    with pytest.raises(InputError, match="speed"):
        follow(S, square, 0.0)
    with pytest.raises(InputError, match="coincide"):
        Scriber(H=0.0)


def test_a_contour_of_too_many_segments_is_refused_and_a_stopped_run_passes_its_junctions():
    # issue 25, item 18 (the file fuzz): 200,000 segments ran for minutes (forces on both sides of every junction);
    # a run stopped before a later junction compared its arc length with a word
    from domes.design.contour import MAX_SEGMENTS

    many = {"start": [0.2, 0.1], "segments": [{"line": [0.3, 0.1]}, {"line": [0.2, 0.1]}] * (MAX_SEGMENTS // 2 + 1)}
    with pytest.raises(InputError, match=f"contour.segments: {MAX_SEGMENTS + 2:,} segments; a contour has at most"):
        Contour.from_dict(many, "many")
    y = 0.317 / 2
    out = Contour.from_dict({"start": [0.3, y], "segments": [{"line": [0.32, y]}, {"line": [0.39, y]},
                                                           {"line": [0.3, y]}]}, "out")
    run = follow(S, out, 0.1, 300)
    assert str(run.status) == "stopped" and [j.index for j in run.junctions] == [1]


def test_a_motion_that_jumps_is_refused_with_its_step():
    from domes.errors import NumericalError
    pts = np.array([0.2 + 0.13j, 0.12 - 0.05j])
    q, th, qd, qdd = S.rates(pts, np.array([0.1j, 0.1j]), np.zeros(2, complex))
    with pytest.raises(NumericalError, match="motion step 1 .*small steps"):
        inverse_dynamics(S.mechanism(pts[0]), motion={"q1": (q[0], qd[0], qdd[0]), "q2": (q[1], qd[1], qdd[1])})
