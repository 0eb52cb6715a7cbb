"""Stage 3 -- labelled graphs: chains with joint types and link roles.

>>> LabelledChain.build(3, [(0, 1), (1, 2), (0, 2)], {(0, 1): "P"}).joint_types
('P', 'R', 'R')
"""

from domes.labelled.graph import JOINT_TYPES, LabelledChain

__all__ = ["JOINT_TYPES", "LabelledChain"]
