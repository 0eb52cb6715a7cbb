"""Type synthesis, stages 1-3 of the pipeline: from a problem's numbers to labelled candidates.

1. number synthesis: links and joints from W, λ, L and j_G (:func:`number_synthesis`);
2. the chain atlas: every non-isomorphic, non-degenerate chain (:func:`chains`);
3. labelling: joint types on the joints (:func:`label_joints`), generalization of
   an existing mechanism (:func:`generalize`), and Yan's regeneration under the
   rules of a design scene (:func:`regenerate`).

Spatial chains (λ = 6) of one loop with R, P, H, C, S joints: :func:`spatial_loops`,
and their function generators (:func:`function_generators`).

>>> number_synthesis(dof=1, loops=2).links, len(chains(links=6, dof=1))
(6, 2)
"""

from domes.typesynth.atlas import ISOMORPHISM_METHODS, ChainGenerator, chains
from domes.typesynth.generalize import Generalization, generalize
from domes.typesynth.labelling import label_joints
from domes.typesynth.number import (
    LinkAssortment,
    NumberSynthesis,
    chain_joints,
    chain_loops,
    link_assortments,
    number_synthesis,
)
from domes.typesynth.regenerate import Candidate, EmptyStage, Regeneration, StageResult, particularize, regenerate
from domes.typesynth.scene import Particularization, Scene, Stage
from domes.typesynth.spatial import SpatialLoop, SpatialLoops, function_generators, spatial_loops

__all__ = [
    "Candidate", "ChainGenerator", "EmptyStage", "Generalization", "ISOMORPHISM_METHODS", "LinkAssortment",
    "NumberSynthesis", "Regeneration", "Scene", "Stage", "StageResult", "chain_joints", "chain_loops", "chains",
    "generalize", "label_joints", "link_assortments", "number_synthesis", "Particularization",
    "particularize", "regenerate", "SpatialLoop", "SpatialLoops", "function_generators", "spatial_loops",
]
