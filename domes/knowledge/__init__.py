"""Stage 4 -- the knowledge base: criterion frames, the criterion language, screening.

>>> from domes.labelled import LabelledChain
>>> frame = CriterionFrame.create("arm", "the swing arm is adjacent to the ground")
>>> design = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={0: {"ground"}, 2: {"swing_arm"}})
>>> screen([design], [frame]).rejected_by
{0: 'arm'}
"""

from domes.knowledge.evaluate import compile_criterion, graph_features, holds
from domes.knowledge.explain import explain
from domes.knowledge.frames import CriterionFrame
from domes.knowledge.language import CriterionSyntaxError, parse_criterion, parse_relevance
from domes.knowledge.relevance import Problem, RelevanceVector, is_relevant, relevance_vector
from domes.knowledge.render import render_criterion, render_relevance
from domes.knowledge.screening import CostlyCriterion, ScreeningResult, screen
from domes.knowledge.store import KnowledgeBase, build

__all__ = [
    "CostlyCriterion", "CriterionFrame", "CriterionSyntaxError", "KnowledgeBase", "Problem", "RelevanceVector",
    "ScreeningResult", "build", "compile_criterion", "explain", "graph_features", "holds", "is_relevant", "parse_criterion",
    "parse_relevance", "relevance_vector", "render_criterion", "render_relevance", "screen",
]
