"""DOMES-py: a rule-based expert system for creative mechanism design.

The package follows the design pipeline (docs/architecture.md):

- :mod:`domes.model` -- chains, labelled chains, dimensioned mechanisms
- :mod:`domes.language` -- the criterion language of criteria and scene rules
- :mod:`domes.typesynth` -- number synthesis, the chain atlas, labelling, regeneration
- :mod:`domes.knowledge` -- criterion and problem frames, relevance, screening
- :mod:`domes.motion` -- the kinematics backend
- :mod:`domes.design` -- dimensional verification (synthesis, dynamics, tolerances to come)
- :mod:`domes.expert` -- the design expert: rules, case-based reasoning, the dialogue
- at the edge: :mod:`domes.io` (files, package data), :mod:`domes.store` (SQL),
  :mod:`domes.sketch` (drawings, pages), :mod:`domes.cli` (the command line)

Example
-------
>>> import domes
>>> domes.number_synthesis(dof=1, loops=2).links
6
>>> len(domes.chains(links=8, dof=1))
16
"""

from domes.errors import DomesError
from domes.model import Chain, chain_properties
from domes.typesynth import NumberSynthesis, chains, link_assortments, number_synthesis

__version__ = "0.1.0"

__all__ = [
    "Chain",
    "DomesError",
    "NumberSynthesis",
    "chain_properties",
    "chains",
    "link_assortments",
    "number_synthesis",
]
