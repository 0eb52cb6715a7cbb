"""Drawings: chains as mechanism skeletons, labelled chains as mechanism sketches, atlas pages.

DOMES's mechanism-sketch generator (§7-2, module 8). Everything is written
as SVG by the project itself (:mod:`domes.sketch.svg`), deterministic to
the byte.

>>> from domes.typesynth import chains
>>> svg = chain_svg(chains(links=8, dof=1)[0])
>>> svg.startswith("<svg"), svg.count('class="joint"')
(True, 10)
"""

from domes.sketch.atlas import (
    Card,
    atlas_html,
    candidate_card,
    chain_atlas_html,
    chain_card,
    mechanism_card,
    regeneration_html,
)
from domes.sketch.dimensioned import CouplerCurve, Pose, coupler_curves, dimensioned_svg, pose
from domes.sketch.draw import chain_svg
from domes.sketch.layout import SkeletonLayout, layout_from_positions, layout_quality, skeleton_layout
from domes.sketch.mechanism import mechanism_svg

__all__ = [
    "Card",
    "CouplerCurve",
    "Pose",
    "SkeletonLayout",
    "atlas_html",
    "candidate_card",
    "chain_atlas_html",
    "chain_card",
    "chain_svg",
    "coupler_curves",
    "dimensioned_svg",
    "layout_from_positions",
    "layout_quality",
    "mechanism_card",
    "mechanism_svg",
    "pose",
    "regeneration_html",
    "skeleton_layout",
]
