"""Batches (issue 12, item 3): many four-bars and slider-cranks at once equal each one built and solved alone."""

import math

import numpy as np
import pytest

from domes.errors import InputError, NumericalError
from domes.motion import CouplerPoint, Input, Joint, Mechanism, solve
from domes.motion.planar.batch import batch
from domes.motion.planar.checks import grashof, transmission_angle
from domes.motion.planar.examples import slider_crank


def _four_bar(b, c, d, p):
    return Mechanism.build("fb", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), b),
                            Joint("C", "R", ("coupler", "rocker"), c), Joint("D", "R", ("rocker", "f"), d)],
                           [Input("A", 2.0, 0.5)], points=[CouplerPoint("P", "coupler", p)])


def _random_four_bars(count, seed):
    rng = np.random.default_rng(seed)
    return {"B": np.c_[rng.uniform(0.5, 1.5, count), rng.uniform(-0.4, 0.4, count)],
            "C": np.c_[rng.uniform(2.5, 4.0, count), rng.uniform(1.5, 3.0, count)],
            "D": np.c_[rng.uniform(2.5, 3.5, count), np.zeros(count)],
            "P": np.c_[rng.uniform(0.0, 4.0, count), rng.uniform(0.0, 4.0, count)]}


TEMPLATE = _four_bar((1.0, 0.0), (3.5, math.sqrt(6.0)), (3.0, 0.0), (2.0, 2.0))


def test_batch_equals_each_mechanism_solved_alone():
    # 40 random four-bars × 24 inputs, positions, velocities and accelerations of a coupler point and the rocker
    # angle: each row equals the scalar backend on the mechanism built from that row.
    coords = _random_four_bars(40, 1)
    qs = np.radians(np.arange(0.0, 360.0, 15.0))
    b = batch(TEMPLATE, coords, qs, outputs=["point:P", "angle:rocker"], order=2)
    assert b.values["point:P.x''"].shape == (40, 24)
    checked = 0
    for m in range(40):
        mech = _four_bar(*(tuple(coords[k][m]) for k in "BCDP"))
        for n, q in enumerate(qs):
            if not b.assembled[m, n]:
                assert math.isnan(b.values["point:P.x"][m, n])
                continue
            try:
                ref = solve(mech, q, outputs=["point:P", "angle:rocker"], order=2).values
            except NumericalError:  # not reachable from the drawn pose (the far side of a limit): not comparable
                continue
            for col, value in ref.items():
                got = b.values[col][m, n]
                err = abs(math.remainder(got - value, 2 * math.pi)) if col == "angle:rocker" else abs(got - value)
                assert err <= 1e-9 * (1 + abs(value)), (m, q, col)
            checked += 1
    assert checked > 500


def test_batch_status_follows_grashof():
    # Independent check: a four-bar whose crank is the shortest link and s + l < p + q (a crank-rocker or
    # double-crank) assembles at every input; any other cannot turn its crank fully and meets a limit.
    coords = _random_four_bars(300, 2)
    b = batch(TEMPLATE, coords, np.radians(np.arange(0.0, 360.0, 2.0)), outputs=["point:C"])
    for m in range(300):
        mech = _four_bar(*(tuple(coords[k][m]) for k in "BCDP"))
        turns = grashof(mech).input_rotates
        assert b.kinds[m] == ("complete" if turns else "limit"), m
        if not turns:
            assert b.limits(m)
    assert {"complete", "limit"} <= set(b.kinds) and b.residual.max() <= 1e-14


def test_transmission_is_the_sine_of_the_smallest_transmission_angle():
    coords = _random_four_bars(12, 3)
    qs = np.radians(np.arange(0.0, 360.0, 0.5))
    b = batch(TEMPLATE, coords, qs, outputs=["point:C"])
    for m in np.flatnonzero(b.kinds == "complete")[:5]:
        mech = _four_bar(*(tuple(coords[k][m]) for k in "BCDP"))
        located = transmission_angle(mech, 0.0, 2 * math.pi)
        assert b.transmission[m] == pytest.approx(math.sin(located.minimum), abs=2e-4)


def test_slider_crank_batch_and_its_slide():
    # Slider-cranks of different offsets (the slider joint's drawn position): slide x = r cos θ + √(L² − (r sin θ − e)²).
    offsets = np.array([0.0, 0.3, -0.5])
    template = slider_crank(1.0, 3.0, 0.0)
    xs = np.sqrt(9.0 - (1.0 - offsets) ** 2)
    coords = {"C": np.c_[xs, offsets], "S": np.c_[xs, offsets], "B": np.c_[np.zeros(3), np.ones(3)]}
    qs = np.radians(np.arange(0.0, 360.0, 30.0))
    b = batch(template, coords, qs, outputs=["slide:S"], order=1)
    assert b.kinds.tolist() == ["complete"] * 3
    for m, e in enumerate(offsets):
        exact = np.cos(qs) + np.sqrt(9.0 - (np.sin(qs) - e) ** 2)
        assert np.allclose(b.values["slide:S"][m], exact, atol=1e-12)
        rate = -np.sin(qs) - (np.sin(qs) - e) * np.cos(qs) / np.sqrt(9.0 - (np.sin(qs) - e) ** 2)
        assert np.allclose(b.values["slide:S'"][m], rate, atol=1e-12)


def test_a_mechanism_drawn_on_a_dead_point_is_ambiguous():
    coords = {"C": np.array([[3.5, math.sqrt(6.0)], [4.0, 0.0]])}  # the second: B, C, D collinear (l2 = 1)
    b = batch(TEMPLATE, coords, np.radians([0.0, 10.0]), outputs=["point:C"])
    assert b.kinds.tolist()[1] == "ambiguous" and np.isnan(b.values["point:C.x"][1]).all()


def test_bad_batches_are_refused_with_the_reason():
    with pytest.raises(InputError, match="shape"):
        batch(TEMPLATE, {"C": np.zeros(4)}, [0.0])
    with pytest.raises(InputError, match="not a joint or point"):
        batch(TEMPLATE, {"Z": np.zeros((2, 2))}, [0.0])
    with pytest.raises(InputError, match="same mechanisms"):
        batch(TEMPLATE, {"B": np.zeros((2, 2)), "C": np.ones((3, 2))}, [0.0])
    with pytest.raises(InputError, match="finite"):
        batch(TEMPLATE, None, [0.0, math.nan])
    with pytest.raises(InputError, match="finite"):
        batch(TEMPLATE, {"C": np.array([[math.inf, 0.0]])}, [0.0])
