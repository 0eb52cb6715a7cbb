"""A batch reduced to extremes in one compiled loop (issue 28): the same numbers as the numpy route and as the
compiled placement followed by the reduction of its positions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from domes.motion import CouplerPoint, Input, Joint, Mechanism
from domes.motion.planar import reduce
from domes.motion.planar.batch import ExtremesSink, _sizes, batch
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import Kinematics

pytest.importorskip("numba")

FOUR_BAR = Mechanism.build("fb", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
                            Joint("C", "R", ("coupler", "rocker"), (3.5, math.sqrt(6.0))),
                            Joint("D", "R", ("rocker", "f"), (3.0, 0.0))],
                           [Input("A")], points=[CouplerPoint("P", "coupler", (2.0, 2.0))])
# A Watt six-bar: the four-bar's rocker carries a second dyad E–F–G; the point Q rides on its link 5.
WATT = Mechanism.build("watt", ["f", "crank", "coupler", "rocker", "l5", "l6"], "f",
                       [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
                        Joint("C", "R", ("coupler", "rocker"), (3.5, math.sqrt(6.0))),
                        Joint("D", "R", ("rocker", "f"), (3.0, 0.0)), Joint("E", "R", ("rocker", "l5"), (4.0, 2.0)),
                        Joint("F", "R", ("l5", "l6"), (6.0, 3.0)), Joint("G", "R", ("l6", "f"), (6.5, 0.0))],
                       [Input("A")], points=[CouplerPoint("Q", "l5", (5.0, 3.5))])

# A slider driven along the ground (the P joint S, the input) carries the dyad B–C–D; Q rides on the link l2.
ACTUATED = Mechanism.build("actuated", ["f", "slider", "l2", "l3"], "f",
                           [Joint("S", "P", ("f", "slider"), (0.0, 0.0), 0.0, (0.0, 0.0)),
                            Joint("B", "R", ("slider", "l2"), (0.0, 0.5)), Joint("C", "R", ("l2", "l3"), (2.0, 2.0)),
                            Joint("D", "R", ("l3", "f"), (3.0, 0.0))],
                           [Input("S")], points=[CouplerPoint("Q", "l2", (1.0, 2.0))])


class PositionsSink(ExtremesSink):
    """The extremes reduced from each chunk's positions (the route without the fused loop)."""


def _drawn(count, seed, names, dead=0):
    """Random poses: each joint and point of WATT moved by up to ±0.9, the last ``dead`` four-bars drawn on a dead
    point (B, C, D collinear: ambiguous)."""
    rng = np.random.default_rng(seed)
    at = {j.name: j.at for j in WATT.joints} | {"P": (2.0, 2.0), "Q": (5.0, 3.5)}
    c = {n: np.asarray(at[n]) + rng.uniform(-0.9, 0.9, (count, 2)) for n in names}
    if dead:
        c["B"][-dead:] = [1.0, 0.0]
        c["D"][-dead:] = [3.0, 0.0]
        c["C"][-dead:] = [3.7, 0.0]
    return c


def _compare(a, b, size, exact):
    tol = 0.0 if exact else 1e-14
    assert (a.kinds == b.kinds).all()
    for col in a.minimum:
        for x, y in ((a.minimum[col], b.minimum[col]), (a.maximum[col], b.maximum[col])):
            assert (np.isnan(x) == np.isnan(y)).all()
            assert np.nanmax(np.abs(x - y) / size, initial=0.0) <= tol, col
        assert (a.argmin[col] == b.argmin[col]).all() and (a.argmax[col] == b.argmax[col]).all()
    assert (np.isnan(a.transmission) == np.isnan(b.transmission)).all()
    assert np.nanmax(np.abs(a.transmission - b.transmission), initial=0.0) <= 1e-12  # a sine, near 0 at limits
    assert np.max(np.abs(a.residual - b.residual)) <= 1e-14  # both are rounding-level closures


@pytest.mark.parametrize("mech, outputs, names", [
    (FOUR_BAR, ["point:P"], ["B", "C", "D", "P"]),
    (WATT, ["point:Q", "point:C"], ["B", "C", "D", "E", "F", "G", "Q"]),
])
def test_fused_extremes_equal_the_numpy_route_and_the_positions(mech, outputs, names):
    coords = _drawn(400, 28, names, dead=3)
    qs = np.radians(np.arange(0.0, 360.0, 2.0))
    prog = Program(Kinematics(mech, outputs))
    assert reduce.spec(prog) is not None  # the fused loop serves this batch
    size = _sizes(prog.geometry(coords, None), 400)
    runs = {}
    for name, sink, route in (("numpy", ExtremesSink(), "numpy"), ("fused", ExtremesSink(), "numba"),
                              ("positions", PositionsSink(), "numba")):
        runs[name] = batch(mech, coords, qs, outputs=outputs, sink=sink, route=route, chunk=150)
    fused = runs["fused"]
    assert fused.counts == runs["numpy"].counts and fused.counts.get("ambiguous") == 3 and fused.counts.get("limit")
    _compare(fused.result, runs["numpy"].result, size, exact=False)
    _compare(fused.result, runs["positions"].result, size, exact=True)  # the same closed forms, the same rounding


def test_angles_and_derivatives_take_the_general_route():
    assert reduce.spec(Program(Kinematics(FOUR_BAR, ["angle:rocker"]))) is None
    assert reduce.spec(Program(Kinematics(FOUR_BAR, ["point:P"], 1))) is None


def test_a_driven_slide_and_its_output_equal_the_numpy_route_and_the_positions():
    rng = np.random.default_rng(29)
    coords = {n: np.asarray(at) + rng.uniform(-0.4, 0.4, (60, 2))
              for n, at in (("B", (0.0, 0.5)), ("C", (2.0, 2.0)), ("D", (3.0, 0.0)), ("Q", (1.0, 2.0)))}
    qs = np.linspace(-1.0, 1.0, 41)  # slides of S, lengths
    outputs = ["point:Q", "slide:S"]
    prog = Program(Kinematics(ACTUATED, outputs))
    assert reduce.spec(prog) is not None
    size = _sizes(prog.geometry(coords, None), 60)
    runs = {name: batch(ACTUATED, coords, qs, outputs=outputs, sink=sink, route=route, chunk=25)
            for name, sink, route in (("numpy", ExtremesSink(), "numpy"), ("fused", ExtremesSink(), "numba"),
                                      ("positions", PositionsSink(), "numba"))}
    assert runs["fused"].counts == runs["numpy"].counts and runs["fused"].counts.get("limit")
    _compare(runs["fused"].result, runs["numpy"].result, size, exact=False)
    _compare(runs["fused"].result, runs["positions"].result, size, exact=True)
