"""Seed 002 chapter 6 (digest Part E.3): the four-bar design space, coupler curves and their special points."""

import math

import numpy as np
import pytest

from domes.errors import InputError
from domes.motion.coupler.curves import trace
from domes.motion.coupler.designspace import TABLE_6_1, classify, normalise, table_region
from domes.motion.coupler.fourbar import closure, four_bar, from_atlas, instant_centre, to_coupler
from domes.motion.coupler.special import crossings, cusps, focal_points
from domes.motion.planar.checks import grashof

CUSP_LINKAGE = (0.4, 1.2, 1.0, 1.4)          # Fig. 6-11
THETA = math.radians(45)


def test_c01_normalisation():
    # C-01: a + b + c + d = 4; the fuzzy example's lengths normalise to (0.6154, 1.2308, 0.9231, 1.2308).
    a, b, c, d, L = normalise(99.58, 199.16, 149.37, 199.16)
    assert a + b + c + d == pytest.approx(4.0, abs=1e-12) and L == pytest.approx(161.8175)
    assert (a, b, c, d) == pytest.approx((0.6154, 1.2308, 0.9231, 1.2308), abs=1e-4)
    with pytest.raises(InputError, match="at least as long as the other three"):
        normalise(1, 1, 1, 3)


def test_c02_points_of_the_d_1_5_diagram():
    # C-02: P (a + d = b + c) and Q (two cuts) are boundaries, R is in region ②, G touches all eight.
    p, q, r, g = (classify(*x) for x in [(0.5, 1, 1, 1.5), (1.5, 0.5, 0.5, 1.5), (1, 1.25, 0.25, 1.5), (1, 1, 1, 1)])
    assert p.region is None and p.boundary == ("a + d = b + c",)
    assert q.region is None and len(q.boundary) == 2
    assert r.region == 2
    assert g.region is None and g.regions == tuple(range(1, 9))


@pytest.mark.parametrize("lengths, region", [
    ((0.4, 1.2, 1.0, 1.4), 1),                      # the cusp linkage
    ((99.58, 199.16, 149.37, 199.16), 1),           # the fuzzy example
    ((1, 5, 5, 4), 1), ((1, 5, 5, 3), 1), ((1, 3.5, 3.5, 3.5), 1), ((1, 2.5, 3.5, 2.5), 1),   # airfoils
    ((1, 3, 3.5, 3), 1), ((1, 5, 4, 4), 1), ((1, 3.5, 3, 2), 1),                              # straight, arc, eight
    ((3, 2.5, 3, 1), 8), ((2.5, 2.5, 3.5, 1), 8),   # double loops
])
def test_c03_regions_of_the_books_linkages(lengths, region):
    assert classify(*lengths).region == region


def test_c04_sign_rule_is_table_6_1():
    # C-04: on random valid linkages the sign rule and Table 6-1 read literally agree; ⑦ only for d > 1, ⑧ only
    # for d < 1; the Grashof class follows s + l < p + q.
    rng = np.random.default_rng(4)
    seen = set()
    for lengths in rng.uniform(0.05, 1.0, size=(20000, 4)):
        try:
            p = classify(*lengths)
        except InputError:
            continue
        assert p.region == table_region(p.a, p.b, p.c, p.d)
        assert (p.region != 7 or p.d > 1) and (p.region != 8 or p.d < 1)
        s, pp, q, l = sorted(lengths)
        assert p.grashof == (s + l < pp + q)
        seen.add(p.region)
    assert seen == set(TABLE_6_1)


def test_c05_cusp_from_the_centrode():
    # C-05: the instant centre at θ = 45° is (1.2188312, 1.2188312), coupler coordinates (1.307592, 0.205794); the
    # point (1.3076, 0.2058) traces a cusp there, where its speed is ~0.
    I = instant_centre(*CUSP_LINKAGE, THETA)
    assert I == pytest.approx((1.2188312, 1.2188312), abs=1e-7)
    B, C = closure(*CUSP_LINKAGE, THETA)
    assert to_coupler(B, C, I) == pytest.approx((1.307592, 0.205794), abs=1e-6)
    curve = trace(four_bar(*CUSP_LINKAGE, 1.3076, 0.2058, theta=THETA))
    found = cusps(curve, curve.circuits[0])
    assert len(found) == 1
    assert found[0].at == pytest.approx((1.21883, 1.21883), abs=1e-4)
    assert math.degrees(found[0].inputs[0]) % 360 == pytest.approx(45.0, abs=1e-2)


@pytest.mark.parametrize("alpha, R, uv, passes", [
    (30, (0.56167, 2.60558), (1.59252, 1.71369), 110.6706),
    (90, (1.30051, 0.35970), (0.86796, -0.53684), 345.9213),
    (120, (1.46177, -0.13389), (0.70782, -1.03079), 304.5335),
    (150, (2.09918, -1.16447), (0.61655, -2.23912), 256.9635),
])
def test_c06_c07_crunodes_on_the_focal_curve(alpha, R, uv, passes):
    # C-06/C-07: for the position θ = 45°, a focal point R (6-17)–(6-20, corrected A2) is a crunode of the curve
    # of the coupler point at R: the curve passes R at 45° and again at the tabulated angle; BC and AD subtend
    # the same angle from R (supplementary when R is inside ABCD).
    B, C = closure(*CUSP_LINKAGE, THETA)
    found = [p for p in focal_points(B, C, 1.4, math.radians(alpha)) if math.dist(p, R) < 1e-4]
    assert len(found) == 1
    point = found[0]
    assert to_coupler(B, C, point) == pytest.approx(uv, abs=1e-4)
    view_bc = math.atan2(*reversed(np.subtract(C, point))) - math.atan2(*reversed(np.subtract(B, point)))
    view_ad = math.atan2(-point[1], 1.4 - point[0]) - math.atan2(-point[1], -point[0])
    assert math.remainder(view_bc - view_ad, math.pi) == pytest.approx(0, abs=1e-9)  # equal, or supplementary
    curve = trace(four_bar(*CUSP_LINKAGE, *to_coupler(B, C, point), theta=THETA))
    hits = [c for c in crossings(curve, curve.circuits[0]) if math.dist(c.at, point) < 1e-6]
    assert len(hits) == 1
    assert sorted(math.degrees(q) % 360 for q in hits[0].inputs) == pytest.approx(sorted([45.0, passes]), abs=1e-4)


def test_c08_at_most_three_double_points():
    # C-08: a four-bar coupler curve (a tricircular sextic) has at most three double points on one circuit.
    rng = np.random.default_rng(8)
    counted = 0
    for lengths in rng.uniform(0.3, 1.7, size=(40, 4)):
        try:
            classify(*lengths)
            m = four_bar(*lengths, *rng.uniform(-2, 2, size=2))
        except InputError:
            continue
        curve = trace(m, samples=360)
        for c in curve.circuits:
            assert len(crossings(curve, c)) + len(cusps(curve, c)) <= 3
        counted += 1
    assert counted >= 20


def _winding(points, p):
    d = points - p
    ang = np.arctan2(d[:, 1], d[:, 0])
    return round(float(np.sum(np.remainder(np.diff(np.append(ang, ang[0])) + np.pi, 2 * np.pi) - np.pi)) / (2 * np.pi))


@pytest.mark.parametrize("args, crossing", [
    ((1, 3.5, 3, 2, 2, 270), (1.969, -1.193)),      # Fig. 6-33's figure-eight
    ((3, 2.5, 3, 1, 3.15, 300), None),              # Fig. 6-34's double loops
    ((2.5, 2.5, 3.5, 1, 2, 270), None),
])
def test_c09_atlas_topology(args, crossing):
    # C-09: one self-intersection each (the figure-eight's at (1.969, −1.193)); the double loops wind twice round
    # the points of their small loop.
    curve = trace(from_atlas(*args))
    found = crossings(curve, curve.circuits[0])
    assert len(found) == 1
    if crossing:
        assert found[0].at == pytest.approx(crossing, abs=5e-3)
    else:
        pts = curve.circuits[0].points
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        grid = [lo + (hi - lo) * (i / 40, j / 40) for i in range(1, 40) for j in range(1, 40)]
        assert max(abs(_winding(pts, g)) for g in grid) == 2


@pytest.mark.parametrize("args", [(1, 5, 5, 4, 7.5, 240), (1, 5, 5, 3, 10.5, 210), (1, 3.5, 3.5, 3.5, 10.25, 240),
                                  (1, 2.5, 3.5, 2.5, 10.25, 0), (1, 3, 3.5, 3, 4.75, 120), (1, 3.5, 3, 3.5, 10.25, 330),
                                  (1, 5, 4, 4, 7.5, 90)])
def test_c10_atlas_simple_curves(args):
    curve = trace(from_atlas(*args))
    assert crossings(curve, curve.circuits[0]) == []


def test_circuits_by_class():
    # Independent check by Grashof: a crank-rocker has two full-turn circuits (open and crossed), a triple rocker
    # one circuit with two limits at ±arccos(−29/48) (seed 000 T9), a parallelogram two circuits crossing at its
    # change points (reported as branch points).
    crank_rocker = four_bar(1, 3.5, 2.5, 3, 1.0, 0.8)
    assert grashof(crank_rocker).kind == "crank-rocker"
    c = trace(crank_rocker)
    assert [x.full_turn for x in c.circuits] == [True, True]
    t9 = trace(four_bar(2, 2, 2.5, 3, 1, 0.5))
    assert len(t9.circuits) == 1
    limits = sorted(math.remainder(d.input, 2 * math.pi) for d in t9.circuits[0].limits)
    assert limits == pytest.approx([-math.acos(-29 / 48), math.acos(-29 / 48)], abs=1e-9)
    para = trace(four_bar(1, 3, 1, 3, 1.5, 0.5, theta=1.0))
    assert len(para.circuits) == 2
    for circuit in para.circuits:
        assert sorted(round(math.degrees(d.input) % 360, 4) % 360 for d in circuit.branch_points) == [0.0, 180.0]
    # The parallelogram's own circuit: the coupler translates, so P stays at B + (1.5, 0.5) (u along BC = +x).
    first = para.circuits[0]
    q = first.inputs
    assert np.allclose(first.points, np.c_[np.cos(q) + 1.5, np.sin(q) + 0.5], atol=1e-9)


@pytest.mark.parametrize("lengths, meet", [
    ((1, 1, 1, 1), "B meets D (crank = frame, coupler = rocker) and C meets A"),
    ((1, 2, 2, 1), "B meets D (crank = frame, coupler = rocker);"),
    ((2, 2, 1, 1), "C meets A (crank = coupler, rocker = frame);"),
])
def test_a_folding_four_bar_is_named_not_traced(lengths, meet):
    # Issue 25, item 6: the rhombus listed ~150 "crossings" of its curve over itself, and a = d, b = c ran for
    # minutes: where two joints meet, the loop's position is undetermined and the motion branches.
    with pytest.raises(InputError, match=r"a folding four-bar .*" + meet.replace("(", r"\(").replace(")", r"\)")):
        trace(four_bar(*lengths, 0.5, 0.3))
    near = trace(four_bar(*lengths[:3], lengths[3] * 1.01, 0.5, 0.3), "P", 360)   # 1% off: traced
    assert near.circuits and all(len(crossings(near, c)) <= 3 for c in near.circuits)
