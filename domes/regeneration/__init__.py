"""Stage 3 -- Yan's chain regeneration under the rules of a design scene.

>>> from domes.regeneration import load_scene, regenerate
>>> [s.count for s in regenerate(load_scene("motorcycle")).stages]
[5, 4, 10, 6]
"""

from domes.regeneration.scene import Scene, Stage, load_scene, parse_scene, scene_names
from domes.regeneration.specialize import Candidate, EmptyStage, Regeneration, StageResult, particularize, regenerate

__all__ = [
    "Candidate",
    "EmptyStage",
    "Regeneration",
    "Scene",
    "Stage",
    "StageResult",
    "load_scene",
    "parse_scene",
    "particularize",
    "regenerate",
    "scene_names",
]
