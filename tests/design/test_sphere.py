"""Spherical synthesis (issue 15, item 3): seed 002 chapter 2, digest tests S-10, S-11, S-13.

S-10: Example 3 (a hip orthosis, Fig. 2-16) with the corrected p1y = 0.482820; fixing a0x = −0.25 and
b0x = −0.15 as the book evidently did gives its cranks to 2e-4. S-11: the data as printed is flagged. S-13:
the spherical function generator's D_R with the corrected elements is a rotation, the printed one is not;
a generator synthesised for three precision points meets them when the general spatial solver moves it.
(S-12, the three-position closed form, is in test_synthesis.py.)
"""

import math

import numpy as np
import pytest

from domes.design.synthesis.sphere import (
    centre_point_curve,
    crank_with,
    function_rotation,
    function_rotation_printed,
    function_three,
    rigidity,
    rot,
    rotations,
)
from domes.errors import InputError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism
from domes.motion.spatial.sweep import spatial_sweep

P = np.array([(0.105040, 0.482820, 0.869397), (0.090725, 0.541283, 0.835931), (0.104155, 0.620000, 0.777658),
              (0.096772, 0.725698, 0.681173)])
Q = np.array([(-0.464640, -0.676760, 0.571057), (-0.133748, -0.751642, 0.645868), (0.161113, -0.702067, 0.693646),
              (0.400762, -0.564306, 0.721769)])
TOWARD = P[0] + Q[0]


def test_s11_example_3_as_printed_is_not_rigid():
    printed = P.copy()
    printed[0, 1] = 0.483820
    check = rigidity(printed, Q)
    assert not check.rigid
    assert check.norm == pytest.approx(4.8e-4, abs=0.1e-4)            # |p1| = 1.000483
    assert check.by_position[1] == pytest.approx(1.1e-3, abs=0.1e-3)  # D12 is not orthogonal
    with pytest.raises(InputError, match=r"not a rigid spherical motion: \|p\| − 1 up to 0.00048"):
        rotations(printed, Q)
    corrected = rigidity(P, Q)
    assert corrected.rigid and corrected.orthogonality < 3e-6


def test_s10_example_3_cranks_with_a_fixed_coordinate():
    Ds = rotations(P, Q)
    a = crank_with(Ds, "x", -0.25, TOWARD)
    b = crank_with(Ds, "x", -0.15, TOWARD)
    book_a = min(a, key=lambda c: np.linalg.norm(c.a0 - (-0.25, 0.1900, 0.9494)))
    book_b = min(b, key=lambda c: np.linalg.norm(c.a0 - (-0.15, 0.5595, 0.8151)))
    np.testing.assert_allclose(book_a.a0, (-0.2500, 0.1900, 0.9494), atol=2e-4)
    np.testing.assert_allclose(book_a.a1, (-0.5839, -0.3149, 0.7482), atol=2e-4)
    np.testing.assert_allclose(book_b.a0, (-0.1500, 0.5595, 0.8151), atol=2e-4)
    np.testing.assert_allclose(book_b.a1, (0.1214, -0.0275, 0.9922), atol=2e-4)
    for crank in a + b:                      # every crank found meets the four positions (2-90), (2-91)
        assert crank.spread < 1e-12
        assert abs(np.linalg.norm(crank.a0) - 1) < 1e-12 and abs(np.linalg.norm(crank.a1) - 1) < 1e-12
    assert len(a) == 4 and len(b) == 4       # the circle a0x = c cuts the centre-point curve four times


def test_the_book_cranks_satisfy_the_constant_length_condition():
    # the book's printed solutions, checked with the corrected data: spread ≤ 5e-5, unit within 1e-4
    Ds = rotations(P, Q)
    for a0, a1 in (((-0.2500, 0.1900, 0.9494), (-0.5839, -0.3149, 0.7482)),
                   ((-0.1500, 0.5595, 0.8151), (0.1214, -0.0275, 0.9922))):
        a0, a1 = np.array(a0), np.array(a1)
        lengths = [np.linalg.norm(D @ a1 - a0) for D in Ds]
        assert np.ptp(lengths) <= 5e-5 and abs(np.linalg.norm(a0) - 1) < 1e-4 and abs(np.linalg.norm(a1) - 1) < 1e-4


def test_the_whole_family_traced():
    Ds = rotations(P, Q)
    curve = centre_point_curve(Ds, 41)
    assert len(curve) > 40
    np.testing.assert_allclose(np.linalg.norm(curve, axis=1), 1.0, atol=1e-12)
    for a0 in curve[::7]:                    # each point is the fixed pivot of a crank meeting all four positions
        rows = np.array([D.T @ a0 - a0 for D in Ds[1:]])
        a1 = np.linalg.svd(rows)[2][-1]
        lengths = [np.linalg.norm(D @ a1 - a0) for D in Ds]
        assert np.ptp(lengths) < 1e-5       # the data is rigid to 2e-6


def test_s13_function_generator_rotation():
    rng = np.random.default_rng(3)
    for alpha, theta, phi in rng.uniform(-math.pi, math.pi, size=(20, 3)):
        D = function_rotation(alpha, theta, phi)
        np.testing.assert_allclose(D @ D.T, np.eye(3), atol=1e-12)
        assert np.linalg.det(D) == pytest.approx(1.0, abs=1e-12)
        u = (math.cos(alpha), math.sin(alpha), 0.0)
        np.testing.assert_allclose(D, rot(u, -phi) @ rot((1, 0, 0), theta), atol=1e-12)
        printed = function_rotation_printed(alpha, theta, phi)
        assert np.max(np.abs(printed @ printed.T - np.eye(3))) > 1e-6


def test_a_synthesised_spherical_function_generator_meets_its_precision_points():
    # Three precision points; the four-bar built from the synthesis is moved by the general spatial solver
    # (an overconstrained linkage: Grübler's count says −2, the rank of the loop equations says 1)
    alpha = math.radians(70)
    thetas, phis = np.radians([0, 20, 45]), np.radians([0, 15, 40])
    b1 = np.array([0.2, 0.5, 0.8]) / np.linalg.norm([0.2, 0.5, 0.8])
    u = (math.cos(alpha), math.sin(alpha), 0.0)
    for gen in function_three(alpha, thetas, phis, b1):
        joints = (SpatialJoint("A0", "R", ("frame", "input"), (1.0, 0, 0), (1.0, 0, 0)),
                  SpatialJoint("A", "R", ("input", "coupler"), tuple(gen.a1), tuple(gen.a1)),
                  SpatialJoint("B", "R", ("coupler", "output"), tuple(b1), tuple(b1)),
                  SpatialJoint("B0", "R", ("frame", "output"), u, u))
        mech = SpatialMechanism.build("spherical four-bar", ("frame", "input", "coupler", "output"), "frame", joints,
                                      (SpatialInput("A0"),))
        assert mech.dof == -2
        sw = spatial_sweep(mech, 0.0, thetas[-1], math.radians(5), outputs=["angle:B0"])
        at = [int(np.argmin(np.abs(sw.inputs - t))) for t in thetas]
        np.testing.assert_allclose(sw.table["angle:B0"][at], phis, atol=1e-10)
        assert np.max(sw.residuals) < 1e-12


@pytest.mark.parametrize("position, q, message", [
    (0, lambda p: p, r"position 1: p and q are one point"),
    (0, lambda p: -p, r"position 1: p and q are on one line through the sphere's centre"),
    (2, lambda p: p, r"position 3: p and q are one point"),
    (1, lambda p: 0 * p, r"position 2: q is at the sphere's centre"),
])
def test_positions_whose_two_points_do_not_fix_the_body_are_named(position, q, message):
    """Issue 25, item 2: q equal to p left the frame [p, q, p × q] singular (LinAlgError)."""
    bad = Q.copy()
    bad[position] = q(P[position])
    with pytest.raises(InputError, match=message):
        rigidity(P, bad)
    with pytest.raises(InputError, match=message):
        rotations(P, bad)
