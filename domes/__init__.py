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

The names below are loaded on first use (PEP 562), so ``import domes`` (and the command line) stays quick.

Example
-------
>>> import domes
>>> domes.number_synthesis(dof=1, loops=2).links
6
>>> len(domes.chains(links=8, dof=1))
16
"""

from __future__ import annotations

from domes.io.lazy import exports

__version__ = "0.1.0"

#: Each name of the package's surface and the module it comes from, imported on first use.
_LAZY = {
    "Chain": "domes.model",
    "DomesError": "domes.errors",
    "NumberSynthesis": "domes.typesynth",
    "chain_properties": "domes.model",
    "chains": "domes.typesynth",
    "link_assortments": "domes.typesynth",
    "number_synthesis": "domes.typesynth",
}

__all__ = [
    "Chain",
    "DomesError",
    "NumberSynthesis",
    "chain_properties",
    "chains",
    "link_assortments",
    "number_synthesis",
]


__getattr__, __dir__ = exports(globals(), _LAZY)
