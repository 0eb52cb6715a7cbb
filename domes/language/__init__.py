"""The criterion language: one near-English language for screening criteria and scene rules.

A sentence parses to a typed tree (:mod:`domes.language.tree`), renders back to
canonical text, compiles to a test over a labelled graph's features, and
explains in words why a graph fails it. DOMES's screening criteria (the six
categories of the knowledge engineer, seed 002 §7-2) and Yan's scene rules
are written in it; it is never evaluated as code.

>>> from domes.model import LabelledChain
>>> rule = parse_criterion("the swing arm is adjacent to the ground")
>>> design = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={0: {"ground"}, 2: {"swing_arm"}})
>>> holds(rule, design), explain(rule, design)
(False, 'not met by link 2: must be adjacent to “ground”')
"""

from domes.language.evaluate import compile_criterion, graph_features, holds
from domes.language.explain import explain
from domes.language.parse import CriterionSyntaxError, normalise_name, parse_criterion, parse_relevance
from domes.language.render import render_criterion, render_relevance

__all__ = [
    "CriterionSyntaxError", "compile_criterion", "explain", "graph_features", "holds", "normalise_name",
    "parse_criterion", "parse_relevance", "render_criterion", "render_relevance",
]
