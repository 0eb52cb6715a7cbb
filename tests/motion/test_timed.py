"""A mechanism driven by a motion law in time (issue 26, item 3; seed 000 §2.10's motion class).

Independent check: the four-bar's rocker angle in closed form (the circle
intersection on the drawn branch) as a function of the crank angle, the
law's time derivatives by central differences of that closed form in time.
"""

import math
from pathlib import Path

import numpy as np
import pytest

from domes.errors import NumericalError
from domes.io.mechanisms import load_mechanism
from domes.model.laws import Motion
from domes.motion.planar.examples import four_bar, slider_crank, triple_rocker
from domes.motion.planar.timed import timed

ROOT = Path(__file__).resolve().parents[2]


def rocker(theta):
    """Seed 000 T6's crank-rocker (frame (0,0)-(3,0), crank 1, coupler 3.5, rocker 2.5): rocker angle, upper mode."""
    b = np.c_[np.cos(theta), np.sin(theta)]
    d = np.array([3.0, 0.0])
    v = b - d
    r = np.linalg.norm(v, axis=1)
    a = (2.5 ** 2 - 3.5 ** 2 + r ** 2) / (2 * r)            # from D along DB to the chord
    h = np.sqrt(2.5 ** 2 - a ** 2)
    u = v / r[:, None]
    pts = d + a[:, None] * u - h[:, None] * np.c_[-u[:, 1], u[:, 0]]   # the drawn mode: C right of D→B
    return np.arctan2(pts[:, 1], pts[:, 0] - 3.0)


@pytest.mark.parametrize("law", [
    Motion([("3-4-5", 0.4, 2.0), ("dwell", 0.2), ("simple harmonic", 0.4, -2.0)]),
    Motion([("cycloidal", 1.0, 2 * math.pi)]),              # a whole turn: the rocker's rates in time
])
def test_rates_in_time_are_the_law_carried_through_the_loop(law):
    times = np.linspace(0.0, law.period, 41)[1:-1] + 0.003     # off the joins, where the acceleration may jump
    run = timed(four_bar(), law, times, outputs=["angle:rocker"])
    h = 1e-5
    q = lambda t: law.evaluate(t, 0)[0]                        # noqa: E731 (the drawn crank angle is 0)
    phi = rocker(q(times))
    assert np.max(np.abs(np.unwrap(run.table["angle:rocker"]) - np.unwrap(phi))) < 1e-12
    rate = (rocker(q(times + h)) - rocker(q(times - h))) / (2 * h)
    acc = (rocker(q(times + h)) - 2 * phi + rocker(q(times - h))) / h ** 2
    assert np.max(np.abs(run.table["angle:rocker'"] - rate)) < 1e-7 * max(1, np.max(np.abs(rate)))
    assert np.max(np.abs(run.table["angle:rocker''"] - acc)) < 1e-3 * max(1, np.max(np.abs(acc)))
    assert run.success and np.max(run.residuals) < 1e-12


def test_a_slider_in_time_rests_in_a_dwell():
    law = Motion([("cycloidal", 0.3, 1.0), ("dwell", 0.4), ("cycloidal", 0.3, -1.0)])
    run = timed(slider_crank(), law, np.linspace(0, 1, 21), outputs=["slide:S"])
    dwell = (run.times > 0.3) & (run.times < 0.7)
    assert np.all(run.table["slide:S'"][dwell] == 0) and np.all(run.table["slide:S''"][dwell] == 0)
    assert run.table["slide:S"][0] == pytest.approx(run.table["slide:S"][-1], abs=1e-12)


def test_a_law_beyond_the_linkage_names_the_time():
    law = Motion([("3-4-5", 1.0, math.radians(180))])
    with pytest.raises(NumericalError, match=r"the law drives A to [\d.]+° at t = 0\.\d+, beyond what the linkage "
                       r"reaches"):
        timed(triple_rocker(), law, np.linspace(0, 1, 11))


def test_a_newton_group_in_time_agrees_with_differences_of_its_own_positions():
    """The class-IV eight-bar (no closed form: Newton step by step) under a law: rates against central differences
    of the positions the same routine gives at nearby times."""
    mech = load_mechanism(ROOT / "examples" / "mechanisms" / "eight-bar-class-iv.json")
    law = Motion([("cycloidal", 1.0, math.radians(20))])
    times, h = np.array([0.2, 0.5, 0.8]), 1e-4
    run = timed(mech, law, times, outputs=["point:R"])
    at = {dt: timed(mech, law, times + dt, outputs=["point:R"], order=0).table["point:R.x"] for dt in (h, -h)}
    mid = run.table["point:R.x"]
    assert np.max(np.abs(run.table["point:R.x'"] - (at[h] - at[-h]) / (2 * h))) < 1e-6
    assert np.max(np.abs(run.table["point:R.x''"] - (at[h] - 2 * mid + at[-h]) / h ** 2)) < 1e-3
