"""Stage 1 -- number synthesis: how many links and joints a problem needs.

>>> number_synthesis(dof=1, loops=3)
NumberSynthesis(dof=1, loops=3, space=3, gear_pairs=0, links=8, joints=10)
>>> [a.counts for a in link_assortments(links=6, joints=7)]
[{2: 4, 3: 2}]
"""

from domes.synthesis.number import (
    LinkAssortment,
    NumberSynthesis,
    chain_joints,
    chain_loops,
    link_assortments,
    number_synthesis,
)

__all__ = [
    "LinkAssortment",
    "NumberSynthesis",
    "chain_joints",
    "chain_loops",
    "link_assortments",
    "number_synthesis",
]
