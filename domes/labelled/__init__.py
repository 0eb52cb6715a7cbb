"""Stage 3 -- labelled graphs: mechanisms, generalization, joint types and link roles.

>>> LabelledChain.build(3, [(0, 1), (1, 2), (0, 2)], {(0, 1): "P"}).joint_types
('P', 'R', 'R')
"""

from domes.labelled.generalize import Generalization, generalize
from domes.labelled.graph import JOINT_TYPES, LabelledChain
from domes.labelled.joints import label_joints
from domes.labelled.mechanism import Joint, Mechanism

__all__ = ["Generalization", "JOINT_TYPES", "Joint", "LabelledChain", "Mechanism", "generalize", "label_joints"]
