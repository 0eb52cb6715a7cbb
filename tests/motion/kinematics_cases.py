"""Shared helpers for the kinematics tests: example files, continuation to an input, finite differences."""

from __future__ import annotations

import math
from pathlib import Path

from domes.io.mechanisms import load_mechanism
from domes.motion import Kinematics
from domes.motion.planar.sweep import Continuation

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "mechanisms"


def example(name):
    return load_mechanism(str(EXAMPLES / name))


def solve_at(mech, q, outputs=None, order=2, method="assur", accuracy=None, joint=None):
    """Solve at input ``q`` (continuing from the drawn pose), returning the Step."""
    kin = Kinematics(mech, outputs, order, method, accuracy)
    cont = Continuation(kin, joint)
    state = cont.start(q)
    return kin.at(cont.inputs(q), state)


def angle_diff(a, b):
    return math.remainder(a - b, 2 * math.pi)
