"""Nine-point path synthesis by parameter homotopy (issue 27, item 4) and Morgan & Wampler's five-point Problem 7."""

import math

import numpy as np
import pytest

from domes.design.synthesis import homotopy as hc
from domes.design.synthesis.fivepoint import PROBLEM_7, five_point_pivots
from domes.design.synthesis.fourbars import check
from domes.design.synthesis.isotropic import DyadSystem, plant
from domes.design.synthesis.ninepoint import (
    CLASSES,
    EXTENDED_DPS,
    REAL,
    REAL_EXTENDED,
    RESIDUAL,
    certify,
    check_points,
    class_key,
    is_real,
    nine_point_path,
    orbit,
    real_fourbar,
    refine_extended,
    start_set,
)
from domes.design.synthesis.pathfit import crank_rocker_path
from domes.design.synthesis.verify import curve_distances
from domes.errors import InputError
from tests.sampling import FULL


@pytest.mark.parametrize("system", [DyadSystem(8), DyadSystem(4, pivots_given=True)], ids=["nine", "five"])
def test_the_bordered_newton_step_is_the_dense_one(system):
    """The step that eliminates each position's rotations equals a dense solve with a finite-difference
    Jacobian."""
    rng = np.random.default_rng(4)
    z, p = plant(system, rng)
    z = z + 0.01 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape))
    J = np.empty((system.m, system.m), complex)
    for k in range(system.m):
        e = np.zeros_like(z)
        e[0, k] = 1e-7
        J[:, k] = (system.residual(z + e, p) - system.residual(z - e, p))[0] / 2e-7
    rhs = system.residual(z, p)
    assert np.allclose(system.solve(z, p, rhs)[0], np.linalg.solve(J, rhs[0]), rtol=1e-5, atol=1e-7)
    assert np.allclose(system.jacobian(z, p)[0], J, atol=1e-6)



def test_newton_on_an_extended_residual_returns_to_the_planted_solution():
    """Mixed-precision Newton (the residual in ``clongdouble``, the step in double) from near planted solutions
    ends on them, as the double one does."""
    system = DyadSystem(8)
    rng = np.random.default_rng(6)
    z, p = plant(system, rng)
    start = z + 1e-3 * (rng.normal(size=z.shape) + 1j * rng.normal(size=z.shape))
    for extended in (False, True):
        w, res, _ = hc.refine(system, start, p, extended=extended)
        assert w.dtype == complex and np.abs(w - z).max() < 1e-10 * (1 + np.abs(z).max()) and res.max() < 1e-12

#: A real solution of query 9 of ``benchmarks/bench_ninepoint.py`` (the last of its 1,442 classes, the member the
#: solver tracked) as the solver returned it in double: ``x, x̄, a, ā, y, ȳ, b, b̄`` (the points scaled to size 1,
#: from point 1) and the eight ``θ``, then ``θ̄``. Its fixed pivot ``a`` is 9·10⁵ sizes out.
FAR_OUT = np.array([
    -88.12985517273783 - 166.82757724140825j, -88.1298551658519 + 166.82757724518012j,
    455451.18062160286 + 776644.1455806266j, 455451.23240023165 - 776644.1152158492j,
    0.33596678401920804 + 1.068940152310454j, 0.3359667840047897 - 1.0689401523157538j,
    0.3993542865760418 + 0.5294073651671714j, 0.39935428656157973 - 0.5294073651724543j,
    0.9913609234445243 - 0.13116218764984164j, 0.9997088795688648 + 0.024127911447551113j,
    0.9936922059262794 - 0.112141873905207j, 0.995347500203577 - 0.09635016263511711j,
    0.9978592961849236 + 0.06539743891349765j, 0.9999571955250182 - 0.009252411464543444j,
    0.9971250347103014 - 0.0757737761698738j, 0.9999931377184261 - 0.0037046614090660976j,
    0.9913609234426684 + 0.13116218764959603j, 0.9997088795692091 - 0.024127911447559394j,
    0.9936922059246831 + 0.11214187390502689j, 0.9953475002022598 + 0.09635016263498973j,
    0.9978592961858063 - 0.06539743891355554j, 0.9999571955248497 + 0.009252411464541931j,
    0.9971250347092425 + 0.07577377616979339j, 0.9999931377183273 + 0.003704661409065859j])


def test_a_solution_far_out_is_certified_in_extended_precision():
    """The class of query 9 whose cognates have a dyad with both pivots 9·10⁵ sizes out: from the double
    approximation, a cognate stays over 1e-8 of the size in double (also with a ``clongdouble`` residual), and
    the members' conjugates, after double Newton, are 1e-8 to 1e-7 apart; refined in mpmath, all six are real
    and their dyads keep their lengths in every position, measured as distances between the real pivots."""
    import mpmath

    rng = np.random.default_rng(0)
    for _ in range(10):                                     # the benchmark's points of query 9
        P = rng.uniform(0, 1, (9, 2))
    rel = (P - P[0]) / np.ptp(P, axis=0).max()
    d = rel[1:, 0] + 1j * rel[1:, 1]
    p = np.concatenate([d, d.conj()])
    system = DyadSystem(8)
    members = [w[0] for w in orbit(FAR_OUT[None], p[None])]
    rough = hc.refine(system, hc.refine(system, members[2][None], p[None])[0], p[None], extended=True)[0]
    assert system.point_error(rough, p[None])[0] > RESIDUAL
    # double Newton leaves the members' conjugates 1e-8 to 1e-7 apart: the double test of being real is at a loss
    assert not all(is_real(hc.refine(system, z[None], p[None])[0][0], REAL / 10) for z in members)
    for z in members:
        w, error = refine_extended(system, z, p)
        assert error < RESIDUAL
        with mpmath.workdps(EXTENDED_DPS):
            assert is_real(w, REAL_EXTENDED)
            x, a, y, b = (mpmath.re(w[k]) + 1j * mpmath.im(w[k]) for k in (0, 2, 4, 6))
            for j in range(8):
                turn = w[8 + j] / abs(w[8 + j])
                for arm, pivot in ((x, a), (y, b)):
                    assert abs(abs(d[j] + turn * arm - pivot) - abs(arm - pivot)) < RESIDUAL


def _isotropic(P, a0, b0, A, B):
    """A real four-bar's isotropic coordinates (points scaled by the bounding box, from point 1) and parameters."""
    c = P[:, 0] + 1j * P[:, 1]
    size = float(np.ptp(P, axis=0).max())
    x, y = (complex(*A[0]) - c[0]) / size, (complex(*B[0]) - c[0]) / size
    a, b = (complex(*a0) - c[0]) / size, (complex(*b0) - c[0]) / size
    th = np.array([(complex(*A[j]) - complex(*B[j])) / (complex(*A[0]) - complex(*B[0])) for j in range(1, 9)])
    z = np.concatenate([[x, x.conjugate(), a, a.conjugate(), y, y.conjugate(), b, b.conjugate()], th, th.conj()])
    d = (c[1:] - c[0]) / size
    return z[None], np.concatenate([d, d.conj()])[None], size


def test_the_six_members_of_a_class_trace_the_same_curve():
    """Roberts' cognates and the relabelled linkage, made by :func:`orbit`, are solutions and real four-bars (every
    link keeps its length through the nine positions), and the kernel draws the coupler curve of each usable one
    (the crank-rocker the points came from, generated without the kernel, and its crank-rocker cognate) through
    the nine points."""
    P, a0, b0, A, B, _ = crank_rocker_path(np.random.default_rng(11), 9)
    z, p, size = _isotropic(P, a0, b0, A, B)
    system = DyadSystem(8)
    keys, usable = [], 0
    for w in orbit(z, p):
        assert np.abs(system.residual(w, p)).max() < 1e-12
        assert is_real(w[0])
        keys.append(class_key(w, p))
        fb, AA, BB = real_fourbar(w[0], P, size)
        AA, BB = np.array(AA), np.array(BB)
        for link in (AA - fb.a0, BB - fb.b0, BB - AA, P - AA):
            length = np.linalg.norm(link, axis=1)
            assert np.ptp(length) < 1e-12 * size
        if not check(fb, AA, BB).defects:
            usable += 1
            assert max(curve_distances(fb, P)) < 1e-9 * size
    assert usable == 2
    assert np.abs(np.concatenate(keys) - keys[0]).max() < 1e-12


def test_morgan_wampler_problem_7():
    """Morgan & Wampler (1990), Problem 7: five points in line, pivots (0, 0) and (1, 0): 33 solutions, 15 real
    (as the paper reports; the phcpy documentation's use case of it repeats the counts)."""
    r = five_point_pivots(PROBLEM_7, (0.0, 0.0), (1.0, 0.0))
    assert (len(r.solutions), len(r.real), r.infinite) == (33, 15, 3)
    assert all(s.residual < 1e-12 and s.condition < 1e10 for s in r.solutions)
    assert r.success and "33 finite solution(s)" in r.message


def _query(P):
    size = float(np.ptp(P, axis=0).max())
    rel = (P - P[0]) / size
    d = rel[1:, 0] + 1j * rel[1:, 1]
    return np.concatenate([d, d.conj()])[None]


def test_tracked_paths_end_on_distinct_certified_classes():
    """A sample of the stored start paths tracked to nine random points: each ends on a solution (its residual,
    as a distance, at round-off), nonsingular, the classes distinct, and the six members of each solutions too."""
    data = start_set()
    system = DyadSystem(8)
    rng = np.random.default_rng(2)
    p1 = _query(rng.uniform(0, 1, (9, 2)))
    pick = rng.choice(len(data["nine_z"]), 20, replace=False)
    end = hc.track(system, data["nine_z"][pick], data["nine_p"][None], p1, gamma=np.exp(0.4j))
    z = hc.refine(system, end.z[end.status == hc.DONE], p1)[0]
    pp = np.broadcast_to(p1, (len(z), system.q))
    assert len(z) >= 19
    res, cond = certify(system, z, p1)
    assert res.max() < 1e-12 and cond.max() < 1e12
    assert len(hc.distinct(class_key(z, pp))) == len(z)
    for w in orbit(z, pp):
        assert certify(system, hc.refine(system, w, pp)[0], p1)[0].max() < 1e-10


def test_paths_near_infinity_are_followed_on_a_projective_chart():
    """A stored path to the nine points of the benchmark's query 8 (its points and γ) passes near infinity, where
    the affine tracker loses it (at t = 0.86, 10⁴ sizes out); on a random projective chart it ends on a certified
    solution, and tracked back along the same arc (``γ`` becomes ``1/γ``) it returns to its own start."""
    rng = np.random.default_rng(0)
    for _ in range(9):
        P = rng.uniform(0, 1, (9, 2))
    p1 = _query(P)
    gamma = np.exp(1j * np.random.default_rng(8).uniform(-np.pi, np.pi))
    data = start_set()
    system = DyadSystem(8)
    z0, p0 = data["nine_z"][[1048]], data["nine_p"][None]
    chart = hc.Projective(system, np.random.default_rng(1))
    end = hc.track(chart, chart.lift(z0), p0, p1, gamma=gamma)
    z = hc.refine(system, chart.drop(end.z), p1)[0]
    assert (end.status == hc.DONE).all() and certify(system, z, p1)[0].max() < 1e-12
    back = hc.track(chart, chart.lift(z), p1, p0, gamma=1 / gamma)
    w = hc.refine(system, chart.drop(back.z), p0)[0]
    assert (back.status == hc.DONE).all() and np.abs(w - z0).max() < 1e-8 * np.abs(z0).max()


@pytest.mark.skipif(not FULL, reason="one full query, 20 to 50 s of CPU: DOMES_FULL_TESTS=1")
def test_nine_points_of_a_crank_rocker():
    """Every class is found (1,442 for generic points; one of this query's paths passes beyond 10⁵ sizes, where
    only the projective chart follows it) and the crank-rocker the points came from is among the usable
    solutions; every solution meets the equations."""
    P, a0, b0, A, B, _ = crank_rocker_path(np.random.default_rng(5), 9)
    r = nine_point_path(P)
    assert len(r.classes) == CLASSES
    assert len(r.solutions) == 6 * len(r.classes)
    assert max(s.residual for s in r.solutions) < 1e-9
    size = r.size
    planted = [s for s in r.usable if math.dist(s.fourbar.a0, a0) < 1e-8 * size and
               math.dist(s.fourbar.b0, b0) < 1e-8 * size and math.dist(s.fourbar.a1, A[0]) < 1e-8 * size]
    assert len(planted) == 1 and max(planted[0].distances) < 1e-8 * size
    assert all(max(s.distances) < 1e-8 * size for s in r.usable)


def test_the_start_set_is_generic():
    """The stored start solutions are distinct classes, nonsingular, and solutions at the stored parameters."""
    data = start_set()
    system = DyadSystem(8)
    z, p = data["nine_z"], np.broadcast_to(data["nine_p"], (len(data["nine_z"]), system.q))
    assert len(z) == CLASSES and len(hc.distinct(class_key(z, p))) == CLASSES
    assert hc.norm(system.residual(z, p)).max() < 1e-10
    assert hc.condition(system, z[:50], p[:50]).max() < 1e12


@pytest.mark.parametrize("points, what", [
    ([(0, 0)] * 2, "expected 9 points"),
    ([(k, k * k) for k in range(8)] + [(float("nan"), 0)], "point 9 is not finite"),
    ([(k, k * k) for k in range(8)] + [(3, 9)], "points 4 and 9 coincide"),
])
def test_bad_points_are_refused(points, what):
    with pytest.raises(InputError, match=what):
        check_points(points)
