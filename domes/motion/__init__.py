"""Motion: the kinematics backend (planar now; spatial mechanisms and coupler curves to come).

A :class:`Mechanism` (links, R and P joints in a drawn pose, ground, inputs,
coupler points) is read from a JSON file (:func:`domes.io.load_mechanism`) or built
from a labelled candidate plus dimensions (:func:`from_labelled`). A query
names its outputs and derivative order and solves only the Assur groups they
depend on (:class:`Kinematics`, :func:`solve`, :func:`sweep`); every step
carries its loop-closure residual and condition number; dead points and
branch points are located, never stepped over. :func:`batch` evaluates many
mechanisms of one topology at once. :mod:`domes.motion.planar.checks` holds the
verification checks of the design process.

>>> from domes.motion.planar.examples import four_bar
>>> import math
>>> step = solve(four_bar(), math.radians(60), outputs=["angle:coupler"], order=1)
>>> round(step.values["angle:coupler"], 9), round(step.values["angle:coupler'"], 9)
(0.459213879, -0.995656642)
"""

from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism, Polygon, from_labelled
from domes.motion.planar.batch import Batch, batch
from domes.motion.planar.query import PRESETS, Accuracy, FailureKind, Kinematics, SolveFailure, Step, accuracy
from domes.motion.planar.structure import Structure
from domes.motion.planar.sweep import DeadPoint, DeadPointKind, Sweep, solve, sweep

__all__ = [
    "Accuracy", "Batch", "CouplerPoint", "DeadPoint", "DeadPointKind", "FailureKind", "SolveFailure", "Input", "Joint", "Kinematics", "Mechanism", "PRESETS", "Polygon",
    "Step", "Structure", "Sweep", "accuracy", "batch", "from_labelled", "solve", "sweep",
]
