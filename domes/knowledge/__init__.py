"""Stage 4 -- the knowledge: criterion frames, problem frames, relevance and multi-level screening.

The frames are values; where they are kept (an SQL case base) is the
business of :mod:`domes.store`, how they are read from files that of
:mod:`domes.io`.

>>> from domes.model import LabelledChain
>>> frame = CriterionFrame.create("arm", "the swing arm is adjacent to the ground")
>>> design = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={0: {"ground"}, 2: {"swing_arm"}})
>>> screen([design], [frame]).rejected_by
{0: 'arm'}
"""

from domes.knowledge.frames import CriterionFrame
from domes.knowledge.problems import ProblemFrame
from domes.knowledge.relevance import Problem, RelevanceVector, is_relevant, relevance_vector
from domes.knowledge.screening import CostlyCriterion, ScreeningResult, screen

__all__ = [
    "CostlyCriterion", "CriterionFrame", "Problem", "ProblemFrame", "RelevanceVector", "ScreeningResult",
    "is_relevant", "relevance_vector", "screen",
]
