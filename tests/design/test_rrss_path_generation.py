"""RRSS spatial path generation (seed 002 §2-3, Fig. 2-25, Table 2-3; digest seed-002-ch2-ch6.md A.3.5)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from domes.design.synthesis import rrss
from domes.design.synthesis.sphere import rot
from domes.errors import InputError
from tests.sampling import FULL, allowed_misses, cases

KEYS = ("u0x", "u0y", "u1x", "u1y", "a1x", "b0x", "b0y", "b0z")
#: Table 2-3's free choices given from the planted RRSS: ``9 − n`` of the chain's, ``7 − n`` of the S-S link's
#: (seed 002 §2-3 suggests a0 and b0 at n = 5; the split takes u0x for b0z).
GIVEN = {4: ("u0x", "u0y", "a0x", "a0y", "a0z", "b0x", "b0y", "b0z"), 5: ("u0x", "a0x", "a0y", "a0z", "b0x", "b0y"),
         6: ("a0x", "a0y", "a0z", "b0x"), 7: ("a0x", "a0y")}


def _unit(v):
    return v / np.linalg.norm(v)


def _closure(theta, u0, a0, u1, a1, b0, b1):
    """The S-S condition |B(θ, φ) − b0| = |b1 − b0| at the crank's turn θ reads ``A cos(φ − φ*) = γ`` in the
    coupler's turn φ on the crank: ``(φ*, γ / A)``."""
    v = b1 - a1
    along = u1 * (u1 @ v)
    e, f = v - along, np.cross(u1, v - along)
    k = a1 - a0 + along - rot(u0, -theta) @ (b0 - a0)
    a, b, g = 2 * k @ e, 2 * k @ f, (b1 - b0) @ (b1 - b0) - k @ k - e @ e
    return math.atan2(b, a), g / math.hypot(a, b)


def planted(rng, n, span=15.0):
    """A random RRSS and ``n`` points of its coupler point's own motion, by the loop's closure in closed form
    (independent of the solver): the crank turns by equal steps of 12–25°, the coupler's turn on the crank
    followed continuously from 0 on a fine grid. Drawn again when the motion passes within 2 % of a dead point
    (|cos| > 0.98, where the branch is ill defined) or the coupler turns on the crank by less than ``span``
    degrees over the points (then the path is nearly a circle about the fixed axis and the chain is determined
    only to ~1e-4: the chain's Jacobian has σ_min ≲ 1e-6 there)."""
    while True:
        u0, u1 = _unit(rng.normal(size=3)), _unit(rng.normal(size=3))
        if abs(u0 @ u1) > 0.95:
            continue
        a0 = rng.uniform(-1, 1, 3)
        a1 = a0 + _unit(np.cross(u0, u1)) * rng.uniform(0.3, 1.5) * rng.choice([-1, 1])
        b0, b1, p1 = rng.uniform(-2, 2, 3), rng.uniform(-1.5, 1.5, 3), rng.uniform(-1.5, 1.5, 3)
        if np.linalg.norm(b1 - b0) < 0.5:
            continue
        thetas = math.radians(rng.uniform(12, 25)) * np.arange(n)
        centre, _ = _closure(0.0, u0, a0, u1, a1, b0, b1)
        side = math.copysign(1.0, (-centre + math.pi) % (2 * math.pi) - math.pi)
        phi, phis, ok = 0.0, [], True
        for t in np.linspace(0, thetas[-1], 40 * (n - 1) + 1):
            centre, c = _closure(t, u0, a0, u1, a1, b0, b1)
            if abs(c) > 0.98:
                ok = False
                break
            phi += (centre + side * math.acos(c) - phi + math.pi) % (2 * math.pi) - math.pi
            phis.append(phi)
        phis = np.array(phis[::40]) if ok else None
        if not ok or math.degrees(np.ptp(phis)) < span:
            continue
        pts = np.array([a0 + rot(u0, t) @ (a1 - a0 + rot(u1, f) @ (p1 - a1)) for t, f in zip(thetas, phis)])
        truth = dict(zip(rrss.NAMES, map(float, np.concatenate([u0, a0, u1, a1, b0, b1]))))
        return pts, truth


def planted_rate(n, cases, seed, every=False):
    """Solve ``cases`` planted problems; every solution meets the book's equations and the guiding links' check;
    the planted RRSS, where found, is driven through every point by the spatial solver. With ``every``, each
    solution is driven by it (``check=True``): it meets the points on its branch (1e-8 of the size) or plainly
    does not (the walk stops before a point, or the points are 1e-6 of the size away or more: another branch),
    never in between. Returns ``(found, methods)``."""
    rng = np.random.default_rng(seed)
    found, methods = 0, set()
    for _ in range(cases):
        pts, truth = planted(rng, n)
        r = rrss.rrss_path(pts, fixed={k: truth[k] for k in GIVEN[n]}, check=every)
        methods.add(r.method)
        size = max(1.0, float(np.max(np.linalg.norm(pts - pts.mean(0), axis=1))))
        for s in r:
            assert s.residual < 1e-9 and s.link_check < 1e-9
            if every:
                assert s.path_error <= 1e-8 or s.path_error >= 1e-6 or (math.isnan(s.path_error) and s.reach), s
        near = [s for s in r if s.distance(truth) <= 1e-6 * size]
        if near:
            err, why = (near[0].path_error, near[0].reach) if every else rrss.path_errors(near[0], pts)
            assert err <= 1e-8, why
            found += 1
    return found, methods


@pytest.fixture(scope="module")
def solved():
    """Four points traced by the spatial solver on the planted RRSS; the Table 2-3 free choices (8 at n = 4)
    taken from it."""
    m = rrss.planted_example()
    pts, _ = rrss.trace(m, np.radians([0.0, 30.0, 60.0, 90.0]))
    truth = rrss.first_position(m)
    return pts, truth, rrss.rrss_path(pts, fixed={k: truth[k] for k in KEYS}, starts=48, seed=0)


def test_table_2_3_counts():
    """Digest A.3.5, Table 2-3: eqs = 5n − 1, unknowns = 3n + 15, given = 16 − 2n, the book's rows."""
    book = {2: (9, 21, 12), 3: (14, 24, 10), 4: (19, 27, 8), 5: (24, 30, 6), 6: (29, 33, 4), 7: (34, 36, 2),
            8: (39, 39, 0)}
    assert {n: rrss.table_2_3(n) for n in book} == book
    C = [np.eye(3)] * 4
    assert rrss.book_residuals({k: 0.0 for k in rrss.NAMES}, C, np.eye(4, 3)).size == 5 * 4 - 1


def test_solutions_meet_the_book_equations_and_the_spatial_solver(solved):
    """Every root meets the book's 5n − 1 equations (2-57), (2-63)–(2-66) and the guiding links' own check
    (an independent form: distances, twists, feet); the spatial solver, driving the fixed R joint from position 1,
    takes the coupler point of at least one solution through every p_j to 1e-8 of the size on one branch."""
    pts, truth, r = solved
    assert r.success and len(r) >= 1 and r.method == "seeded"
    for s in r:
        assert s.residual < 1e-9 and s.link_check < 1e-9
        assert np.allclose(s.p1, pts[0])
        assert s.mechanism().dof - s.mechanism().idle == 1
    exact = [s for s in r if s.path_error <= 1e-8]
    assert exact
    for s in exact:      # again, through trace(): the sweep plus Newton at each θ_j
        got, _ = rrss.trace(s.mechanism(), s.thetas)
        assert np.max(np.linalg.norm(got - pts, axis=1)) <= 1e-8 * max(1.0, float(np.ptp(pts)))


def test_solutions_are_distinct(solved):
    _, _, r = solved
    for i, s in enumerate(r):
        for t in r.solutions[:i]:
            assert s.distance(t.values()) > 1e-6


@pytest.mark.parametrize("points, fixed, says", [
    ([[0, 0, 0], [1, 0, 0]], {}, "give exactly 12"),
    ([[0, 0, 0]], {}, "2 to 8 points"),
    ([[0, 0, 0, 1], [1, 0, 0, 1]], {}, "n × 3"),
    ([[0, 0, 0], [0, 0, 0], [1, 1, 1], [2, 0, 1]], {k: 0.1 for k in KEYS}, "coincide"),
    ([[0, 0, 0], [1, 0, 0], [1, 1, 1], [2, 0, 1]], {**{k: 0.1 for k in KEYS[:-1]}, "q0x": 1.0}, "not a first-position"),
    ([[0, 0, 0], [1, 0, 0], [1, 1, 1], [2, 0, 1]], {k: 0.1 for k in ("a0x", "a0y", "a0z", "b0x", "b0y", "b0z",
                                                                    "b1x", "b1y")}, "5 of the given"),
    ([[math.cos(k), math.sin(k), 0.1 * k] for k in range(8)], {}, "8 points"),
])
def test_bad_input(points, fixed, says):
    """Bad input names what is wrong (Table 2-3 counts; the chain/link split of the seeded method)."""
    with pytest.raises(InputError, match=says):
        rrss.rrss_path(points, fixed=fixed)


def test_bad_method():
    with pytest.raises(InputError, match="method"):
        rrss.rrss_path([[0, 0, 0], [1, 0, 0]], method="newton")


def test_planted_five_points():
    """Issue acceptance (seed 002 §2-3, Table 2-3 at n = 5: 6 givens): 50 random planted RRSS, five points of
    each one's own motion, the free choices from it; the planted RRSS is among the solutions in ≥ 95 % of cases
    and the spatial solver takes its coupler point through every point to 1e-8 of the size. (The first of the 50
    by default, the same share allowed to miss; all with DOMES_FULL_TESTS=1: tests/sampling.py, which also
    drives every solution by the spatial solver: measured 466 solutions, 263 through every point on their
    branch, 141 on another branch, 62 stopped by a limit of the input before a point.)"""
    count = cases(50)
    found, methods = planted_rate(5, count, seed=5, every=FULL)
    assert methods == {"conic"}
    assert found >= count - allowed_misses(count, 0.04)          # 48 of 50


def test_planted_four_points_by_the_conic():
    """Table 2-3 at n = 4 with the fixed axis given (u0x, u0y, a0, b0): the closed form finds the planted RRSS
    every time."""
    found, methods = planted_rate(4, 10, seed=4)
    assert methods == {"conic"} and found == 10


def test_planted_six_points():
    """Table 2-3 at n = 6 (a0 and b0x given): a fast subset of planted cases (the solver's n = 6 stage is
    slower); all found."""
    found, methods = planted_rate(6, 6, seed=6)
    assert methods == {"conic"} and found == 6


def test_conic_method_needs_axis_givens():
    with pytest.raises(InputError, match="conic"):
        rrss.rrss_path([[0, 0, 0], [1, 0, 0], [1, 1, 1], [2, 0, 1]], fixed={k: 0.1 for k in KEYS}, method="conic")
