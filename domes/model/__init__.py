"""The data model: chains, labelled chains and dimensioned mechanisms, and what they are made of.

One model serves the whole pipeline, from type synthesis to kinematics:

- :class:`Chain` -- an unlabelled kinematic chain (links and joints), with its
  structural properties (DOF, loops, automorphisms, rigid sub-chains, ...);
- :class:`LabelledChain` -- a chain whose joints carry a type and whose links
  carry roles (the labelled graph of DOMES, a mechanism's topology);
- :class:`Mechanism` -- a dimensioned planar mechanism in a drawn pose
  (the input of the kinematics backend).

>>> c = Chain(4, ((0, 1), (1, 2), (2, 3), (0, 3)))
>>> labelled = LabelledChain.build(c.n, c.edges, {(0, 1): "P"}, roles={0: {"ground"}})
>>> c.dof, labelled.joint_types
(1, ('P', 'R', 'R', 'R'))
"""

from domes.model.chain import Branch, Chain, chain_properties
from domes.model.combination_modes import CombinationMode, combination_modes
from domes.model.labelled import JOINT_TYPES, LabelledChain
from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism, Polygon, from_labelled
from domes.model.mobility import PLANAR, SPATIAL, chain_joints, chain_loops, mobility

__all__ = [
    "Branch", "Chain", "CombinationMode", "CouplerPoint", "Input", "JOINT_TYPES", "Joint", "LabelledChain",
    "Mechanism", "Polygon", "PLANAR", "SPATIAL", "chain_joints", "chain_loops", "chain_properties",
    "combination_modes", "from_labelled", "mobility",
]
