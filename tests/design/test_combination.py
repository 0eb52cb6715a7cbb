"""A cam in parallel with a two-input five-bar (seed 002 §3-3-III.2, Fig. 3-28).

The five-bar's point C must follow a path S; the follower's slide S_D(φ₁) is
checked against an independent closed form (C on the ellipse at the
coupler's length from B, found by a scalar root on the ellipse's angle; D on
the slide at the link's length from C), and the designed cam, followed by
its contact condition, must put C back on the path.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from domes.cli import main
from domes.design.combination import cam_for_path
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.motion.planar.examples import four_bar

FILE = "examples/mechanisms/five-bar-cam.json"
PATH = "examples/mechanisms/five-bar-cam-path.csv"


def ellipse(n=73):
    t = np.linspace(0, 2 * np.pi, n)
    P = np.c_[np.cos(t), 2.2 + 0.6 * np.sin(t)]
    P[-1] = P[0]
    return P


def closed_form(theta, t0):
    """S_D by geometry: B on the crank circle, C on the ellipse at 2.2 from B (continued in the ellipse's angle), D."""
    out, t = [], t0
    for th in theta:
        B = 0.5 * np.array([math.cos(th), math.sin(th)])

        def f(s):
            return math.hypot(math.cos(s) - B[0], 2.2 + 0.6 * math.sin(s) - B[1]) - 2.2

        t = brentq(f, t - 0.2, t + 0.2) if f(t - 0.2) * f(t + 0.2) < 0 else brentq(f, t - 0.05, t + 0.05)
        C = (math.cos(t), 2.2 + 0.6 * math.sin(t))
        out.append(C[0] + math.sqrt(3.5 ** 2 - C[1] ** 2) + 1.5)  # the follower's point E, 1.5 beyond D
    return np.array(out)


def test_the_follower_motion_matches_the_geometry_and_the_cam_puts_c_back_on_the_path():
    mech = load_mechanism(FILE)
    combo = cam_for_path(mech, ellipse(), "C", roller=0.2)
    assert combo.success and combo.turns == 0 and 0.2 < combo.covered < 0.3
    E0 = mech.joint("E").at[0]
    want = closed_form(combo.theta, math.radians(-5.4069945808269715))
    # the drive is the slide coordinate of E (0 at the drawn pose), up to the spline through 72 points (h⁴ ~ 1e-6)
    assert np.max(np.abs(combo.drive + E0 - want)) < 5e-6
    fine = cam_for_path(mech, ellipse(721), "C", roller=0.2, samples=72)
    assert np.max(np.abs(fine.drive + E0 - want[::5])) < 1e-9
    # the cam's lift is the drive above its lowest point
    s = combo.cam.motion.evaluate(combo.theta, 0)[0]
    assert np.allclose(s, combo.drive - combo.drive.min(), atol=1e-12)
    assert combo.path_error < 1e-7 and not combo.cam.undercut and not combo.warnings
    # the profile, put back on the crank in the drawn pose, touches the roller (centre E, radius 0.2) at θ = 0
    assert math.dist(combo.profile[0], (E0 + combo.drive[0], 0.0)) == pytest.approx(0.2, abs=1e-9)


def test_bad_combinations_are_named():
    mech = load_mechanism(FILE)
    with pytest.raises(InputError, match="two inputs"):
        cam_for_path(four_bar(), ellipse(), "B")
    with pytest.raises(InputError, match="from the path; draw it on the path"):
        cam_for_path(mech, ellipse() + [0.0, 0.3], "C")
    with pytest.raises(InputError, match="at least 8 finite points"):
        cam_for_path(mech, ellipse()[:5], "C")
    with pytest.raises(InputError, match="run off the end of the path"):
        cam_for_path(mech, ellipse()[60:73].tolist() + ellipse()[1:4].tolist(), "C")


def test_cam_command_designs_the_cam_from_the_mechanism(capsys):
    assert main(["cam", "--mechanism", FILE, "--path", PATH, "--point", "C", "--roller", "0.2"]) == 0
    out = capsys.readouterr().out
    assert "runs back and forth over 26.4% of the path's length" in out
    assert main(["cam", "--mechanism", FILE, "--path", PATH, "--point", "C", "--roller", "0.2",
                 "--base-radius", "3"]) == 2
    assert "leave out --segment, --table and --base-radius" in capsys.readouterr().err
