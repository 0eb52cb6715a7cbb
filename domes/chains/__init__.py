"""Stage 2 -- the unlabelled graph generator: the atlas of kinematic chains.

>>> from domes.chains import chains
>>> [c.dof_type for c in chains(links=7, dof=2)]
['total', 'partial', 'partial']
"""

from domes.chains.chain import Branch, Chain, chain_properties
from domes.chains.generate import ISOMORPHISM_METHODS, ChainGenerator, chains

__all__ = ["Branch", "Chain", "ChainGenerator", "ISOMORPHISM_METHODS", "chain_properties", "chains"]
