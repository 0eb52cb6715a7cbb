"""DOMES-py: a rule-based expert system for creative mechanism design.

The package follows the design pipeline, one subpackage per stage:

- :mod:`domes.synthesis` -- number synthesis (links and joints from W, λ, L, j_G)
- :mod:`domes.chains` -- the unlabelled graph generator (the atlas of chains)

Example
-------
>>> import domes
>>> domes.number_synthesis(dof=1, loops=2).links
6
>>> len(domes.chains(links=8, dof=1))
16
"""

from domes.errors import DomesError
from domes.synthesis import NumberSynthesis, link_assortments, number_synthesis
from domes.chains import Chain, chains, chain_properties

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
