"""Verification checks (issue 5, item 4) against closed-form geometry."""

import math

import pytest
from kinematics_cases import example

from domes.errors import DomesError
from domes.motion import Input, Joint, Mechanism
from domes.motion.planar.checks import (
    grashof,
    interference,
    output_range,
    polygon_gap,
    rotatability,
    toggle_near,
    transmission_angle,
)
from domes.motion.planar.examples import four_bar, slider_crank, triple_rocker


def _four_bar(ground, crank, coupler, rocker, deg=90.0):
    """A four-bar drawn at crank angle ``deg`` (upper assembly), from its four lengths."""
    a, d = (0.0, 0.0), (ground, 0.0)
    b = (crank * math.cos(math.radians(deg)), crank * math.sin(math.radians(deg)))
    dist = math.dist(b, d)
    x = (coupler ** 2 - rocker ** 2 + dist ** 2) / (2 * dist)
    h = math.sqrt(coupler ** 2 - x ** 2)
    ux, uy = (d[0] - b[0]) / dist, (d[1] - b[1]) / dist
    c = (b[0] + x * ux - h * uy, b[1] + x * uy + h * ux)
    return Mechanism.build("4bar", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), a), Joint("B", "R", ("crank", "coupler"), b),
                            Joint("C", "R", ("coupler", "rocker"), c), Joint("D", "R", ("rocker", "f"), d)], [Input("A")])


@pytest.mark.parametrize("lengths,kind,full", [
    ((3, 1, 3.5, 2.5), "crank-rocker", True),
    ((1, 3, 3.5, 2.5), "double-crank", True),
    ((3, 2, 2, 2.5), "triple-rocker", False),
    ((3, 2.5, 1, 3), "double-rocker", False),
])
def test_grashof_class_agrees_with_numeric_rotatability(lengths, kind, full):
    # Grashof: s + l < p + q and the shortest link is the input (crank-rocker) or ground (double-crank).
    m = _four_bar(*lengths)
    assert grashof(m).kind == kind
    r = rotatability(m)
    assert r.full is full and r.grashof.input_rotates is full


def test_triple_rocker_reachable_range_ends_at_the_limits():
    # Seed 000 T9: the input swings between ±arccos(−29/48) from the drawn pose at 0°.
    r = rotatability(triple_rocker())
    limit = math.acos(-29 / 48)
    assert r.reachable == pytest.approx((-limit, limit), abs=1e-9)


def test_change_point_four_bar():
    # Grashof boundary s + l = p + q: the input turns fully; the branch points (links collinear at 0° and 180°)
    # are reported as bifurcations (issue 12: located like dead points), and at 180° velocities are refused
    # with the joints and the angle named.
    m = _four_bar(2, 1, 2, 1)
    assert grashof(m).kind == "change point"
    r = rotatability(m)
    assert r.full
    branch = sorted(math.degrees(d.input) % 360 for d in r.dead_points if d.kind == "bifurcation")
    assert branch == pytest.approx([0.0, 180.0], abs=1e-4) or branch == pytest.approx([180.0, 360.0], abs=1e-4)
    from domes.motion import solve
    with pytest.raises(DomesError, match=r"joints B, C, D.*input 180°"):
        solve(m, math.pi, order=1)
    v = solve(m, math.pi, outputs=["point:C"]).values
    assert (v["point:C.x"], v["point:C.y"]) == pytest.approx((1.0, 0.0), abs=1e-7)


def test_output_range_of_the_rocker_is_the_toggle_geometry():
    # Crank-rocker extremes: crank and coupler collinear, |AC| = 3.5 ± 1 (law of cosines at D).
    r = output_range(four_bar(), "angle:rocker", 0, 2 * math.pi)
    expect_min = math.pi - math.acos((9 + 6.25 - 4.5 ** 2) / 15)
    expect_max = math.pi - math.acos((9 + 6.25 - 2.5 ** 2) / 15)
    assert r.minimum == pytest.approx(expect_min, abs=1e-12)
    assert r.maximum == pytest.approx(expect_max, abs=1e-12)
    coarse = output_range(four_bar(), "angle:rocker", 0, 2 * math.pi, accuracy="fast")
    assert coarse.maximum <= r.maximum + 1e-15 and coarse.minimum >= r.minimum - 1e-15


def test_toggle_near_finds_the_rocker_toggle():
    # The rocker stands still where crank and coupler are collinear (extended): crank angle from the
    # triangle A, D, C with |AC| = 4.5.
    found = toggle_near(four_bar(), math.radians(40), output="angle:rocker")
    toggle = next(d for d in found if d.kind == "toggle")
    ang_c = math.pi - math.acos((9 + 6.25 - 4.5 ** 2) / 15)
    c = (3 + 2.5 * math.cos(ang_c), 2.5 * math.sin(ang_c))
    assert toggle.input == pytest.approx(math.atan2(c[1], c[0]), abs=1e-9)


def test_toggle_near_finds_the_dead_point_of_the_triple_rocker():
    found = toggle_near(triple_rocker(), math.radians(120), window=math.radians(20))
    assert found[0].kind == "limit"
    assert found[0].input == pytest.approx(math.acos(-29 / 48), abs=1e-9)


def test_transmission_angle_of_the_crank_rocker():
    # μ_min of a crank-rocker at crank 0° or 180°: cos μ = (b² + c² − (d ∓ a)²) / (2bc).
    t = transmission_angle(four_bar(), 0, 2 * math.pi, math.radians(0.5))
    mus = [math.acos((3.5 ** 2 + 2.5 ** 2 - x ** 2) / (2 * 3.5 * 2.5)) for x in (2.0, 4.0)]
    expect = min(min(m, math.pi - m) for m in mus)
    assert t.minimum == pytest.approx(expect, abs=1e-12)


def test_transmission_angle_of_a_slider_crank():
    # In-line slider-crank: μ_min = 90° − asin(r / l) at crank 90°.
    t = transmission_angle(slider_crank(1.0, 3.0), 0, 2 * math.pi, math.radians(0.5))
    assert t.minimum == pytest.approx(math.pi / 2 - math.asin(1 / 3), abs=1e-12)


def test_interference_first_contact():
    # four-bar.json: the coupler's pad meets the frame's stop; check the contact by the gap just before/after.
    m = example("four-bar.json")
    res = interference(m, "pad", "stop", 0, 2 * math.pi)
    assert res.collides
    before = interference(m, "pad", "stop", 0, res.first_contact - 1e-6)
    assert not before.collides and before.min_clearance < 1e-5
    assert not interference(m, "pad", "stop", 0, 1.0).collides


def test_polygon_gap():
    sq = [(0, 0), (1, 0), (1, 1), (0, 1)]
    assert polygon_gap(sq, [(0.5, 0.5), (2, 0.5), (2, 2)]) == 0.0
    assert polygon_gap(sq, [(0.2, 0.2), (0.4, 0.2), (0.3, 0.4)]) == 0.0  # contained
    assert polygon_gap(sq, [(1, 1), (2, 1), (2, 2)]) == 0.0  # touching corner
    assert polygon_gap(sq, [(0, 3), (1, 3), (1, 4)]) == pytest.approx(2.0)


def test_swing_arm_travel_against_shock_length():
    # A driven P joint between two moving links (the shock absorber): the swing arm's angle follows the triangle
    # O, S1, S2 with |S1 S2| = s (law of cosines); the travel over s ∈ [3.5, 4.5] is the difference of the two.
    m = example("swing-arm-shock.json")
    o, s1, s2 = (0.0, 0.0), (0.5, 3.0), (4.0, 0.8)
    a, b = math.dist(o, s1), math.dist(o, s2)

    def swing(length):
        gamma = math.acos((a * a + b * b - length ** 2) / (2 * a * b))
        return math.atan2(s1[1], s1[0]) - gamma

    r = output_range(m, "angle:swing", 3.5, 4.5, joint="shock")
    assert (r.minimum, r.maximum) == pytest.approx((swing(4.5), swing(3.5)), abs=1e-12)
    assert r.travel == pytest.approx(swing(3.5) - swing(4.5), abs=1e-12)
    assert r.stopped_at is None
