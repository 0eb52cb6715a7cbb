"""Four-position RCCC synthesis (issue 15, item 4): seed 004 (Cao & Han), the digest's TC-1 .. TC-9.

The paper prints no final numbers (its figures are lost), so the main test
is TC-6: an RCCC planted by hand is moved to four poses by the general
spatial solver, and the synthesis must find it again: the zero-slide
parameters of its driver coincide and the feet are the planted ones. TC-3
(the paper's Table 1 producing its published axes) fails under every
standard orientation convention and is kept as an expected failure.
"""

import math

import numpy as np
import pytest

from domes.design.synthesis.rccc import (
    Displacement,
    burmester_matrix,
    centre_point,
    check_task,
    circle_determinant,
    circle_points,
    displacements,
    foot_on,
    input_angle,
    minmax_slide,
    pose_rotation,
    rccc,
    slides,
    solution_lines,
)
from domes.errors import InputError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism
from domes.motion.spatial.loops import Loops
from domes.motion.spatial.sweep import spatial_sweep

POINTS = [np.array(p, float) for p in [(0, 0, 0), (30, 5, 10), (60, 40, 5), (20, 60, -5)]]
DIRS = [np.array(u, float) / np.linalg.norm(u) for u in [(0.1, 0.2, 1.0), (0.3, -0.2, 1.0), (-0.2, 0.4, 1.0),
                                                          (0.1, -0.3, 1.0)]]
TABLE_1 = [((15, 90, 0), (0, 0, 0)), ((20, 40, 45), (-23, 8, 13)), ((25, 35, 25), (-42, 9, 13)),
           ((30, 40, 5), (-55, -3, 1))]


def planted():
    joints = (SpatialJoint("z0", "R", ("frame", "driver"), tuple(POINTS[0]), tuple(DIRS[0])),
              SpatialJoint("z1", "C", ("driver", "coupler"), tuple(POINTS[1]), tuple(DIRS[1])),
              SpatialJoint("z2", "C", ("coupler", "follower"), tuple(POINTS[2]), tuple(DIRS[2])),
              SpatialJoint("z3", "C", ("frame", "follower"), tuple(POINTS[3]), tuple(DIRS[3])))
    return SpatialMechanism.build("planted RCCC", ("frame", "driver", "coupler", "follower"), "frame", joints,
                                  (SpatialInput("z0"),))


def planted_moves(thetas=(25, 50, 80)):
    mech = planted()
    kin = Loops(mech)
    k = kin.index["coupler"]
    moves = []
    for th in thetas:
        s = spatial_sweep(mech, 0.0, math.radians(th), math.radians(5)).states[-1]
        R = s.R[k]
        moves.append(Displacement(R, s.o[k] * kin.scale - R @ (kin.centre[k] * kin.scale)))
    return moves


MOVES = planted_moves()


def table_1_moves():
    R = [pose_rotation(a, "lon-lat-roll") for a, _ in TABLE_1]
    return displacements(R, [p for _, p in TABLE_1])


def test_tc1_pose_ingestion_needs_a_named_convention():
    for convention in ("lon-lat-roll", "zyx", "zyz", "xyz"):
        for angles, _ in TABLE_1:
            R = pose_rotation(angles, convention)
            assert np.max(np.abs(R.T @ R - np.eye(3))) <= 1e-12 and np.linalg.det(R) == pytest.approx(1.0)
    moves = table_1_moves()
    for m, (_, p) in zip(moves, TABLE_1[1:]):
        np.testing.assert_array_equal(m.d, p)              # p1 = 0: d_j = p_{j+1} exactly
    with pytest.raises(InputError, match="the paper names none; say which"):
        pose_rotation((15, 90, 0), "")


def test_planted_displacements_equal_the_digest():
    # TC-6's generated relative displacements (the forward kinematics, cross-checked)
    expected = [(12.980763, (-0.223316, 0.536220, 0.814001), (0.762345, 5.064615, 11.108913)),
                (29.399363, (-0.185674, 0.395517, 0.899495), (10.410488, 10.188525, 36.634334)),
                (49.723908, (-0.184637, 0.303163, 0.934880), (20.098785, 25.323358, 65.566160))]
    for m, (angle, axis, d) in zip(MOVES, expected):
        C = m.C
        w = np.array([C[2, 1] - C[1, 2], C[0, 2] - C[2, 0], C[1, 0] - C[0, 1]])
        assert math.degrees(math.acos((np.trace(C) - 1) / 2)) == pytest.approx(angle, abs=1e-6)
        np.testing.assert_allclose(w / np.linalg.norm(w), axis, atol=1e-6)
        np.testing.assert_allclose(m.d, d, atol=1e-6)


def test_tc2_burmester_invariants():
    for moves in (MOVES, table_1_moves()):
        scale = max(np.linalg.norm(m.C - np.eye(3), 2) for m in moves) ** 3
        pts = circle_points(moves, meridians=36)
        assert len(pts) >= 36
        for u in pts:
            assert abs(circle_determinant(moves, u)) <= 1e-10 * scale
            v = centre_point(moves, u)
            for m in moves:
                assert abs(u @ (m.C.T - np.eye(3)) @ v) <= 1e-10
        for m in moves:                          # the poles lie on the curve
            w = np.array([m.C[2, 1] - m.C[1, 2], m.C[0, 2] - m.C[2, 0], m.C[1, 0] - m.C[0, 1]])
            pole = w / np.linalg.norm(w)
            assert abs(circle_determinant(moves, pole)) <= 1e-12
            assert np.linalg.matrix_rank(burmester_matrix(moves, pole), tol=1e-9) == 2   # one row vanishes
    # two displacements about one axis: at that axis two rows vanish (rank 1), the centre is not unique
    from domes.design.synthesis.sphere import rot
    axis = unit(np.array([0.2, 0.3, 1.0]))
    shared = [Displacement(rot(axis, 0.3), np.zeros(3)), Displacement(rot(axis, 0.7), np.zeros(3)),
              Displacement(rot(unit(np.array([1.0, 0.2, 0.1])), 0.5), np.zeros(3))]
    with pytest.raises(InputError, match="pole"):
        centre_point(shared, axis)


def test_tc3_published_pairs_are_burmester_pairs_of_one_task():
    # convention-free: some rotation C satisfies u·(Cᵀ − I)v = 0 for the four published pairs (eqs. (28), (30),
    # u0x read 0.993); we check the digest's three rotations do, to the data's three decimals
    pairs = [((-0.970, 0.206, 0.127), (-0.981, 0.193, 0.01)), ((-0.002, 0.032, 0.998), (0.417, 0.495, 0.762)),
             ((0.993, 0.104, 0.058), (0.975, 0.165, 0.158)), ((0.295, 0.036, -0.955), (-0.145, 0.280, 0.949))]
    pairs = [(np.array(u) / np.linalg.norm(u), np.array(v) / np.linalg.norm(v)) for u, v in pairs]
    from domes.design.synthesis.sphere import rot
    for angle, axis in ((11.565, (-0.5304, -0.4087, 0.7427)), (18.445, (-0.7617, -0.5075, 0.4028)),
                        (17.540, (-0.766, -0.628, -0.1372))):
        C = rot(np.array(axis) / np.linalg.norm(axis), math.radians(angle))
        assert max(abs(u @ (C.T - np.eye(3)) @ v) for u, v in pairs) <= 3e-3


@pytest.mark.xfail(reason="seed 004 never says how (azimuth, longitude, latitude) make a rotation; no standard "
                          "convention turns Table 1 into rotations for which the published axes (28), (30) are "
                          "Burmester pairs (digest §4.4); refs [8], [9] are needed", strict=True)
def test_tc3_table_1_reproduces_the_published_axes():
    pairs = [((-0.970, 0.206, 0.127), (-0.981, 0.193, 0.01)), ((-0.002, 0.032, 0.998), (0.417, 0.495, 0.762))]
    for convention in ("lon-lat-roll", "zyx", "zyz", "xyz"):
        R = [pose_rotation(a, convention) for a, _ in TABLE_1]
        moves = displacements(R, [p for _, p in TABLE_1])
        worst = max(abs(np.array(u) / np.linalg.norm(u) @ (m.C.T - np.eye(3)) @ (np.array(v) / np.linalg.norm(v)))
                    for u, v in pairs for m in moves)
        if worst <= 3e-3:
            return
    raise AssertionError("no convention reproduces the published Burmester pairs")


def test_tc4_solution_line_invariants():
    moves = table_1_moves()
    u = circle_points(moves, meridians=12)[3]
    v = centre_point(moves, u)
    lines = solution_lines(moves, u, v)
    assert lines.singular > 1e-10
    size = 55.09
    hs = []
    for t in (0.0, 1.0, 37.3, -12.0):
        M, F = lines.feet(t)
        assert abs(u @ (M - F)) <= 1e-10 * size and abs(v @ (M - F)) <= 1e-10 * size
        h = []
        for m in [Displacement(np.eye(3), np.zeros(3))] + list(moves):
            uj, Mj = m.C @ u, m.C @ M + m.d
            assert uj @ v == pytest.approx(u @ v, abs=1e-12)            # constant twist
            n = np.cross(uj, v)
            h.append(abs((Mj - F) @ n) / np.linalg.norm(n))
        assert np.ptp(h) <= 1e-9 * size                                  # constant common normal
        hs.append(h[0])
    # h(t) = |h0 + h1 t|: affine up to sign
    h0, h1 = hs[0], hs[1] - hs[0]
    assert hs[2] == pytest.approx(abs(h0 + 37.3 * h1), rel=1e-9) or hs[2] == pytest.approx(abs(h0 - 37.3 * h1), rel=1e-9)
    s0, s1, s2 = (slides(moves, lines, t) for t in (0.0, 1.0, 37.3))
    np.testing.assert_allclose(s2, s0 + 37.3 * (s1 - s0), atol=1e-9 * size)


def test_tc5_a_4c_from_region_2_meets_the_poses_exactly():
    # the 4C: driver and follower points anywhere on their lines, the driver's C joint driven by angle and slide
    moves = table_1_moves()
    pts = circle_points(moves, meridians=24)
    u, w = pts[2], pts[11]
    d, f = solution_lines(moves, u, centre_point(moves, u)), solution_lines(moves, w, centre_point(moves, w))
    M, F = d.feet(7.0)
    D, G = f.feet(-3.0)
    joints = (SpatialJoint("z0", "C", ("frame", "driver"), tuple(F), tuple(d.v)),
              SpatialJoint("z1", "C", ("driver", "coupler"), tuple(M), tuple(d.u)),
              SpatialJoint("z2", "C", ("coupler", "follower"), tuple(D), tuple(f.u)),
              SpatialJoint("z3", "C", ("frame", "follower"), tuple(G), tuple(f.v)))
    mech = SpatialMechanism.build("4C", ("frame", "driver", "coupler", "follower"), "frame", joints,
                                  (SpatialInput("z0", "angle"), SpatialInput("z0", "slide")))
    kin = Loops(mech)
    k = kin.index["coupler"]
    from domes.design.synthesis.rccc import rotation_angle
    for theta, slide, m in zip(input_angle(moves, d), slides(moves, d, 7.0), moves):
        state = kin.drawn()
        for frac in np.linspace(0, 1, 41)[1:]:                 # walk there, continuing the drawn assembly
            state, residual = kin.positions({"z0.angle": frac * theta, "z0.slide": frac * slide}, state)
        R = state.R[k]
        moved = state.o[k] * kin.scale - R @ (kin.centre[k] * kin.scale)
        assert rotation_angle(m.C.T @ R) <= 1e-9
        assert np.linalg.norm(moved - m.d) <= 1e-8 * 55.09


def test_tc6_the_planted_rccc_is_recovered():
    u1, u2 = DIRS[1], DIRS[2]
    assert abs(circle_determinant(MOVES, u1)) <= 1e-12 and abs(circle_determinant(MOVES, u2)) <= 1e-12
    v = centre_point(MOVES, u1)
    vf = centre_point(MOVES, u2)
    assert abs(abs(v @ DIRS[0]) - 1) <= 1e-12 and abs(abs(vf @ DIRS[3]) - 1) <= 1e-12   # the z0, z3 lines' directions
    d = solution_lines(MOVES, u1, v)
    a = slides(MOVES, d, 0.0)
    b = slides(MOVES, d, 1.0) - a
    zeros = -a / b
    assert np.ptp(zeros) <= 1e-8 and zeros[0] == pytest.approx(-22.473098, abs=1e-6)
    t, worst, _, _ = minmax_slide(MOVES, d)
    M, F = d.feet(t)
    np.testing.assert_allclose(M, (22.674419, 9.883721, -14.418605), atol=1e-6)
    np.testing.assert_allclose(F, (-0.968992, -1.937984, -9.689922), atol=1e-6)
    assert np.linalg.norm(M - F) == pytest.approx(26.853753, abs=1e-6)
    assert math.degrees(d.twist) == pytest.approx(24.650470, abs=1e-6)
    f = solution_lines(MOVES, u2, vf)
    for foot, k in (((51.798759, 56.402481, 46.006203), slice(0, 3)), ((25.024121, 44.927636, 45.241213), slice(3, 6))):
        t_f = float((np.array(foot) - f.base[k]) @ f.direction[k] / (f.direction[k] @ f.direction[k]))
        np.testing.assert_allclose(f.base[k] + t_f * f.direction[k], foot, atol=1e-6)
    D, G = f.feet(float((np.array((51.798759, 56.402481, 46.006203)) - f.base[:3]) @ f.direction[:3]
                        / (f.direction[:3] @ f.direction[:3])))
    assert np.linalg.norm(D - G) == pytest.approx(29.139982, abs=1e-5)
    assert math.degrees(f.twist) == pytest.approx(41.536459, abs=1e-6)
    thetas = np.degrees(input_angle(MOVES, d))
    np.testing.assert_allclose(np.abs(thetas), (25, 50, 80), atol=1e-9)        # negated with the opposite v
    sol = rccc(MOVES, (u1, v), (u2, vf))
    assert sol.exact and sol.label == "exact"
    assert max(sol.rotation_errors) <= 1e-9 and max(sol.translation_errors) <= 1e-9 * 76.0


def test_tc7_an_approximate_rccc_on_table_1_is_labelled_with_its_errors():
    from scipy.optimize import linprog

    moves = table_1_moves()
    pts = circle_points(moves, meridians=36)
    u, w = pts[5], pts[20]
    d = solution_lines(moves, u, centre_point(moves, u))
    t, worst, a, b = minmax_slide(moves, d)
    # the same min-max by a linear programme: minimise z subject to −z ≤ a_j + b_j t ≤ z
    A = [[b_j, -1.0] for b_j in b] + [[-b_j, -1.0] for b_j in b]
    lp = linprog([0, 1], A_ub=A, b_ub=list(-a) + list(a), bounds=[(None, None), (0, None)])
    assert worst == pytest.approx(lp.fun, abs=1e-6 * 55.09)
    sol = rccc(moves, (u, centre_point(moves, u)), (w, centre_point(moves, w)))
    assert max(sol.rotation_errors) <= 1e-9                       # orientations stay exact (spherical image)
    if max(np.abs(sol.slides)) > 1e-6:
        assert not sol.exact and sol.label == "approximate" and max(sol.translation_errors) > 0
    assert "RCCC: driver slides" in sol.message


def test_tc8_degenerate_inputs_are_flagged():
    same = [Displacement(np.eye(3), np.array([1.0, 0, 0]))] + list(MOVES[1:])
    assert any("orientation of pose 1" in p for p in check_task(same))
    from domes.design.synthesis.sphere import rot
    one_axis = [Displacement(rot((0, 0, 1), a), np.array([a, 0, 0])) for a in (0.2, 0.5, 0.9)]
    assert any("about one axis" in p for p in check_task(one_axis))
    u1 = DIRS[1]
    with pytest.raises(InputError, match="parallel"):
        solution_lines(MOVES, u1, u1)
    with pytest.raises(InputError, match="orientation convention"):
        pose_rotation((1, 2, 3), "euler")
    bad = np.eye(3)
    bad[0, 0] = 2.0
    with pytest.raises(InputError, match="not a rotation"):
        displacements([np.eye(3), bad], [(0, 0, 0), (1, 1, 1)])


def test_tc9_the_planted_rccc_is_a_crank_moving_in_order():
    v = centre_point(MOVES, DIRS[1])
    thetas = input_angle(MOVES, solution_lines(MOVES, DIRS[1], v))
    assert all(abs(b) > abs(a) for a, b in zip(thetas, thetas[1:]))            # 0 < 25 < 50 < 80 in one sense
    sw = spatial_sweep(planted(), 0.0, math.radians(85), math.radians(5))
    assert sw.success and np.max(sw.residuals) < 1e-12                         # one branch, continuously


def unit(x):
    return x / np.linalg.norm(x)


def test_line_transform_and_the_twist_identity():
    rng = np.random.default_rng(5)
    from domes.design.synthesis.sphere import rot
    for _ in range(10):
        C = rot(unit(rng.normal(size=3)), rng.uniform(-3, 3))
        dvec = rng.normal(size=3) * 5
        P, u = rng.normal(size=3) * 3, unit(rng.normal(size=3))
        cu, moment = Displacement(C, dvec).line(u, np.cross(P, u))
        np.testing.assert_allclose(moment, np.cross(C @ P + dvec, cu), atol=1e-12)
        Q, w = rng.normal(size=3) * 3, unit(rng.normal(size=3))
        n = np.cross(u, w)
        h = (Q - P) @ n / np.linalg.norm(n)
        sin_a = np.linalg.norm(n)
        # u·w̄ + ū·w = −h sin α (signed common-normal length along u × w)
        assert u @ np.cross(Q, w) + np.cross(P, u) @ w == pytest.approx(-h * sin_a, abs=1e-12)
        F = foot_on(P, u, Q, w)
        assert abs((F - foot_on(Q, w, P, u)) @ u) <= 1e-9 and abs((F - foot_on(Q, w, P, u)) @ w) <= 1e-9


def test_the_search_finds_the_planted_rccc():
    from domes.design.synthesis.rccc import search

    sol = search(MOVES, meridians=90)
    assert max(np.abs(sol.slides)) <= 1e-9 and max(sol.rotation_errors) <= 1e-9
    assert max(sol.translation_errors) <= 1e-9 * 76.0 and sol.label == "exact"


def test_the_search_on_table_1_is_approximate_and_says_so():
    # informational (an assumed convention; digest §4.5): the best min-max slide is about 0.53, never 0
    from domes.design.synthesis.rccc import drivers, search

    moves = table_1_moves()
    best = drivers(moves, 90)[0][0]
    assert 0.3 < best < 1.0
    sol = search(moves, meridians=90)
    assert sol.label == "approximate" and max(sol.rotation_errors) <= 1e-9 and max(sol.translation_errors) > 1e-3
    assert sol.message.startswith("approximate RCCC")
    # the reported errors equal an independent forward run (a finer walk of the same linkage: 120 steps to each
    # pose, under a degree, where the product sweeps in 2° steps)
    mech = sol.mechanism()
    kin = Loops(mech)
    k = kin.index["coupler"]
    for theta, m, reported in zip(sol.thetas, moves, sol.translation_errors):
        state = kin.drawn()
        for frac in np.linspace(0, 1, 121)[1:]:
            state, _ = kin.positions({"z0": frac * theta}, state)
        R = state.R[k]
        moved = state.o[k] * kin.scale - R @ (kin.centre[k] * kin.scale)
        assert np.linalg.norm(moved - m.d) == pytest.approx(reported, abs=1e-6 * 55.09)


def test_defects_agree_with_moving_the_linkage():
    from domes.design.synthesis.rccc import defects, drivers

    moves = table_1_moves()
    found = drivers(moves, 45)
    checked = {"defect free": 0, "defective": 0}
    for _, u, v, t in found[:3]:
        for _, w, vf, _ in found[5:40:5]:
            if abs(float(w @ u)) > 0.999:
                continue
            flagged = defects(moves, (u, v), (w, vf))
            try:
                sol = rccc(moves, (u, v), (w, vf))
            except InputError:
                assert flagged                               # it cannot even be moved there: flagged
                checked["defective"] += 1
                continue
            if flagged:
                checked["defective"] += 1
                if any("branch" in f for f in flagged):
                    assert max(sol.rotation_errors) > 1e-3   # it reaches the other assembly mode
            else:
                checked["defect free"] += 1
                assert max(sol.rotation_errors) <= 1e-9
    assert checked["defective"] > 0
