"""Dimensional synthesis (seed 002 §2-3, digest A.3): from a task to every four-bar that does it, checked.

:func:`synthesize` takes a task (:mod:`~domes.design.synthesis.task`:
rigid-body guidance, function generation, path generation) and returns a
:class:`~domes.design.synthesis.solve.Synthesis` of every real solution,
each a :class:`~domes.design.synthesis.fourbars.FourBar` with its checks,
ready as a mechanism file for ``domes kinematics`` and ``domes draw``.
"""

from domes.design.synthesis.solve import Solution, Synthesis, synthesize
from domes.design.synthesis.task import GuidanceTask, RotationTask, task_from_dict

__all__ = ["GuidanceTask", "RotationTask", "Solution", "Synthesis", "synthesize", "task_from_dict"]
