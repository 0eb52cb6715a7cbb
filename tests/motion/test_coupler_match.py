"""Matching a wanted path (issue 25, items 4 and 6): duplicates and cognates merged, paths it cannot match named."""

import numpy as np
import pytest

from domes.errors import InputError
from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism
from domes.motion.coupler.atlas import Atlas, AtlasSpec, build
from domes.motion.coupler.curves import trace
from domes.motion.coupler.fit import Fit
from domes.motion.coupler.match import _merge, cognates, match, relation
from domes.results import Status

#: A four-bar as complex joint positions A, B, C, D and its coupler point P (crank 1, frame 3).
LINKAGE = (0j, 0.6 + 0.8j, 3.2 + 1.9j, 3 + 0j, 1.2 + 2.6j)


def _mechanism(A, B, C, D, P) -> Mechanism:
    xy = lambda z: (float(z.real), float(z.imag))       # noqa: E731
    return Mechanism.build("four-bar", ["frame", "crank", "coupler", "rocker"], "frame", [
        Joint("A", "R", ("frame", "crank"), xy(A)), Joint("B", "R", ("crank", "coupler"), xy(B)),
        Joint("C", "R", ("coupler", "rocker"), xy(C)), Joint("D", "R", ("rocker", "frame"), xy(D))],
        [Input("A")], points=[CouplerPoint("P", "coupler", xy(P))])


def _fit(A, B, C, D, P, after=1e-7) -> Fit:
    lengths = (abs(B - A), abs(C - B), abs(D - C), abs(D - A))
    return Fit(_mechanism(A, B, C, D, P), lengths, (0.0, 0.0), (0.1, 0.1), (after, after), 3.0, 1e-6, 1,
               Status.COMPLETE)


def _distance(points, curve):
    """The largest distance of ``points`` from the closed polyline ``curve``."""
    a, b = curve, np.roll(curve, -1, axis=0)
    d = b - a
    out = []
    for p in points:
        t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.einsum("ij,ij->i", d, d), 0, 1)
        out.append(np.min(np.hypot(*(a + t[:, None] * d - p).T)))
    return max(out)


def test_the_cognates_trace_the_same_curve():
    # Roberts-Chebyshev: the two cognates built from one pose are four-bars whose coupler point traces the
    # original's curve (checked by the kinematics backend on every circuit).
    original = trace(_mechanism(*LINKAGE), "P", 720)
    curve = np.vstack([c.points for c in original.circuits])
    for cog in cognates(*LINKAGE):
        mine = trace(_mechanism(*cog), "P", 720)
        assert _distance(np.vstack([c.points for c in mine.circuits])[::7], curve) < 1e-4


def test_one_linkage_found_again_is_merged_and_named():
    # Issue 25, item 6: the figure-eight's matches 1 and 3 were one linkage with crank and rocker swapped. The
    # same linkage driven from D, its two cognates and its mirror image are merged into it, each saying how it
    # repeats it; another linkage is kept.
    A, B, C, D, P = LINKAGE
    best = _fit(*LINKAGE)
    swapped = _fit(D, C, B, A, P, 2e-7)
    first, second = (_fit(*c, 3e-7) for c in cognates(*LINKAGE))
    mirror = _fit(*(z.conjugate() + 10 for z in LINKAGE), 4e-7)
    other = _fit(A, B, C + 0.5, D + 0.5, P, 5e-7)
    assert "crank and rocker swapped" in relation(best, swapped, 1e-6)
    assert "cognate" in relation(best, first, 1e-6) and "shares frame pivot A" in relation(best, first, 1e-6)
    assert "shares frame pivot D" in relation(best, second, 1e-6)
    assert "mirror image" in relation(best, mirror, 1e-6)
    assert relation(best, other, 1e-6) == ""
    kept, merged = _merge([best, swapped, first, second, mirror, other], 3.0)
    assert kept == [best, other] and [g for g, _ in merged[0]] == [swapped, first, second, mirror]


@pytest.fixture(scope="module")
def atlas():
    return Atlas(build(AtlasSpec("test", 20, 1.0)))


def test_points_on_one_line_are_matched_approximately_and_said_so(atlas):
    # Issue 25, item 4: no coupler curve is straight; the answer says so (and what to do) instead of NaN.
    m = match(np.c_[np.arange(12.0), 2 * np.arange(12.0)], atlas, results=1, candidates=2, max_nfev=20)
    assert "lie on one straight line" in m.message and "--open" in m.message and "nan" not in m.message
    assert not any(f.success for f in m.fits)


def test_too_few_points_are_refused_before_the_look_up(atlas):
    # Four points gave "0 of 30 candidates fit ... largest distance nan": every refinement refused them in turn.
    with pytest.raises(InputError, match="at least 9 points to fit a four-bar's nine dimensions, got 4"):
        match([[0, 0], [1, 0], [2, 0], [3, 0]], atlas)
