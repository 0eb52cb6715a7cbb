"""Extremes (issue 5 acceptance): link ratios 1e-6 and 1e6, an input within 1e-9 rad of a toggle,
coincident joints. Each returns an accurate answer (checked against mpmath at 40 digits) or a precise error."""

import math

import mpmath
import pytest

from domes.errors import DomesError, NumericalError
from domes.motion import Input, Joint, Mechanism, solve, sweep
from domes.motion.planar.examples import slider_crank, triple_rocker

mpmath.mp.dps = 40


def _mp_four_bar(a, b, c, d, theta, sign=1):
    """Rocker angle of a four-bar (ground A=(0,0), D=(d,0)) by the law of cosines in mpmath."""
    theta = mpmath.mpf(theta)
    bx, by = a * mpmath.cos(theta), a * mpmath.sin(theta)
    dx, dy = d - bx, -by
    r = mpmath.sqrt(dx ** 2 + dy ** 2)
    alpha = mpmath.acos((c ** 2 + r ** 2 - b ** 2) / (2 * c * r))
    return mpmath.atan2(dy, dx) + mpmath.pi - sign * alpha  # angle of D→C (D→B turned by −α)


def _four_bar(a, b, c, d, deg):
    theta = math.radians(deg)
    bpt = (a * math.cos(theta), a * math.sin(theta))
    phi = float(_mp_four_bar(mpmath.mpf(a), mpmath.mpf(b), mpmath.mpf(c), mpmath.mpf(d), theta))
    cpt = (d + c * math.cos(phi), c * math.sin(phi))
    return Mechanism.build("4bar", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), bpt),
                            Joint("C", "R", ("coupler", "rocker"), cpt), Joint("D", "R", ("rocker", "f"), (d, 0.0))],
                           [Input("A")], link_angles={"rocker": phi})


@pytest.mark.parametrize("method", ["assur", "newton"])
def test_crank_of_1e_minus_6(method):
    # Link ratio 1e-6: the rocker's swing is ~1e-6 rad; its angle and rate must still be right to 1e-9 relative.
    a, b, c, d = 1e-6, 3.5, 2.5, 3.0
    m = _four_bar(a, b, c, d, 90.0)
    for deg in (0.0, 137.0, 250.0):
        step = solve(m, math.radians(deg), outputs=["angle:rocker"], order=1, method=method)
        ref = _mp_four_bar(mpmath.mpf(a), mpmath.mpf(b), mpmath.mpf(c), mpmath.mpf(d), math.radians(deg))
        rate = mpmath.diff(lambda t: _mp_four_bar(mpmath.mpf(a), mpmath.mpf(b), mpmath.mpf(c), mpmath.mpf(d), t),
                           mpmath.mpf(math.radians(deg)))
        assert step.values["angle:rocker"] == pytest.approx(float(ref), abs=1e-14)
        assert step.values["angle:rocker'"] == pytest.approx(float(rate), rel=1e-8)
        assert step.residual <= 1e-10


@pytest.mark.parametrize("method", ["assur", "newton"])
def test_rod_of_1e6(method):
    # Link ratio 1e6: slider-crank with crank 1 and rod 1e6; the slide x = r cos θ + sqrt(L² − r² sin² θ).
    m = slider_crank(1.0, 1e6)
    for deg in (10.0, 100.0, 300.0):
        step = solve(m, math.radians(deg), outputs=["slide:S"], order=2, method=method)
        t = mpmath.mpf(math.radians(deg))
        x = lambda t: mpmath.cos(t) + mpmath.sqrt(mpmath.mpf(10) ** 12 - mpmath.sin(t) ** 2)  # noqa: E731
        assert step.values["slide:S"] == pytest.approx(float(x(t)), abs=1e-10 * 1e6)
        assert step.values["slide:S'"] == pytest.approx(float(mpmath.diff(x, t)), rel=1e-9)
        assert step.values["slide:S''"] == pytest.approx(float(mpmath.diff(x, t, 2)), rel=1e-7)
        assert step.residual <= 1e-10


def _mp_triple_rocker(theta):
    """Seed 000 T9 coupler angle φ2 in mpmath (upper branch)."""
    theta = mpmath.mpf(theta)
    b = (2 * mpmath.cos(theta), 2 * mpmath.sin(theta))
    dx, dy = 3 - b[0], -b[1]
    r = mpmath.sqrt(dx ** 2 + dy ** 2)
    alpha = mpmath.acos((4 + r ** 2 - mpmath.mpf(6.25)) / (4 * r))
    return mpmath.atan2(dy, dx) + alpha


@pytest.mark.parametrize("method", ["assur", "newton"])
def test_input_within_1e_minus_9_of_the_toggle(method):
    # Seed 000 T9's limit q* = arccos(−29/48): at q* − 1e-9 the mechanism still assembles and the answer is
    # accurate to its own error bound (condition × residual; the condition is ~5e4 there, the rate ~1.2e4);
    # at q* + 1e-9 it is an error naming the joints and the angle.
    qstar = mpmath.acos(mpmath.mpf(-29) / 48)
    q = float(qstar - mpmath.mpf("1e-9"))
    step = solve(triple_rocker(), q, outputs=["angle:coupler"], order=1, method=method)
    assert 1e4 < step.condition < 1e6 and step.residual < 1e-15
    ref = _mp_triple_rocker(q)
    err_bound = step.condition * max(step.residual, 1e-16) + 1e-12
    assert abs(step.values["angle:coupler"] - float(ref)) <= err_bound
    rate = mpmath.diff(_mp_triple_rocker, mpmath.mpf(q))
    assert step.values["angle:coupler'"] == pytest.approx(float(rate), rel=1e-4)
    with pytest.raises(NumericalError, match=r"(joints B, C, D|crank, coupler, rocker).*127\.16889965"):
        solve(triple_rocker(), float(qstar + mpmath.mpf("1e-9")), order=0, method=method)


def test_coincident_joints():
    # A rhombus four-bar (all links 1): at crank angle 0 the crank pin B coincides with the pivot D and the
    # coupler can turn about it: the sweep stops there and names the joints; solving at 0 is an error.
    m = Mechanism.build("rhombus", ["f", "crank", "coupler", "rocker"], "f",
                        [Joint("A", "R", ("f", "crank"), (0, 0)), Joint("B", "R", ("crank", "coupler"), (0, 1)),
                         Joint("C", "R", ("coupler", "rocker"), (1, 1)), Joint("D", "R", ("rocker", "f"), (1, 0))],
                        [Input("A")])
    sw = sweep(m, math.pi / 2, -math.pi / 2, math.radians(1), outputs=["angle:rocker"])
    assert sw.status == "stopped"
    dp = sw.dead_points[0]
    assert dp.kind == "undetermined" and abs(dp.input) <= 1e-9
    assert "joints B and D coincide" in dp.message
    with pytest.raises(DomesError, match=r"joints B and D coincide.*input"):
        solve(m, 0.0, outputs=["angle:rocker"])
    # Just before the coincidence the answer is still exact: C = B + (1, 0) on the rhombus.
    v = solve(m, 1e-6, outputs=["point:C", "point:B"]).values
    assert (v["point:C.x"] - v["point:B.x"], v["point:C.y"] - v["point:B.y"]) == pytest.approx((1.0, 0.0), abs=1e-9)


def test_zero_length_link_is_refused_at_the_drawn_pose():
    # A coupler drawn with coincident ends makes the assembly mode ambiguous: a precise error at build time.
    m = Mechanism.build("zero", ["f", "crank", "coupler", "rocker"], "f",
                        [Joint("A", "R", ("f", "crank"), (0, 0)), Joint("B", "R", ("crank", "coupler"), (0, 1)),
                         Joint("C", "R", ("coupler", "rocker"), (0, 1)), Joint("D", "R", ("rocker", "f"), (1, 0))],
                        [Input("A")])
    with pytest.raises(DomesError, match="joints B, C, D are collinear in the drawn pose"):
        solve(m, 0.5)


def test_an_angle_many_turns_away_is_solved_less_its_whole_turns():
    # issue 25, item 3: --at 1e7 (degrees) walked every turn from the drawn pose (735 MB)
    from domes.motion.planar.examples import four_bar

    far = solve(four_bar(), math.radians(1e7), outputs=["angle:rocker"])       # 1e7° = 27,777 turns + 280°
    near = solve(four_bar(), math.radians(280.0), outputs=["angle:rocker"])
    assert far.inputs["A"] == pytest.approx(math.radians(280.0), abs=1e-9)
    assert far.values["angle:rocker"] == pytest.approx(near.values["angle:rocker"], abs=1e-9)
    sw = sweep(four_bar(), math.radians(1e7), math.radians(1e7 + 20), math.radians(10), outputs=["angle:rocker"])
    assert sw.turns == 27777 and "+27,777 whole turns taken off" in sw.message
    assert [round(math.degrees(q), 6) for q in sw.inputs] == [280.0, 290.0, 300.0]


def test_an_angle_floats_cannot_place_is_refused():
    # issue 25, item 3: 1e300 rad answered 126.8°, an angle floats 1e284 apart cannot mean
    from domes.errors import InputError
    from domes.motion.planar.examples import four_bar

    with pytest.raises(InputError, match=r"input A = .*° is too large to mean an angle: floats there are"):
        solve(four_bar(), 1e300)
    with pytest.raises(InputError, match="too large to mean an angle"):
        sweep(four_bar(), 0.0, 1e300, 1e299)


def test_a_sweep_that_walks_too_far_is_refused_before_it_starts():
    # 1.5e7° by 1.5e6°: 11 grid points, but 1.5e7 steps of the resolution walked
    from domes.errors import InputError
    from domes.motion.planar.examples import four_bar

    with pytest.raises(InputError, match=r"walks from the drawn pose .* more than 10,000,000"):
        sweep(four_bar(), 0.0, math.radians(1.5e7), math.radians(1.5e6))


def test_a_length_input_far_outside_the_mechanism_is_refused():
    import dataclasses

    from domes.errors import InputError

    driven = dataclasses.replace(slider_crank(), inputs=(Input("S"),))
    assert solve(driven, 3.0, outputs=["angle:crank"]).inputs["S"] == 3.0
    with pytest.raises(InputError, match=r"input S = 1e\+300 is far outside slider-crank \(size .*within 100 sizes"):
        solve(driven, 1e300)
