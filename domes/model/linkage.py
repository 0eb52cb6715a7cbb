"""What planar and spatial mechanisms share: looking up joints, the links' joints, the loops, the size.

>>> from domes.motion.planar.examples import four_bar
>>> m = four_bar()
>>> m.joint("B").links, [j.name for j in m.joints_of("rocker")], m.loops, round(m.size, 6)
(('crank', 'coupler'), ['C', 'D'], 1, 4.272002)
"""

from __future__ import annotations

import math

from domes.errors import InputError


class Linkage:
    """A mixin of :class:`~domes.model.mechanism.Mechanism` and :class:`~domes.model.spatial.SpatialMechanism`
    (fields ``name``, ``links``, ``joints``, ``points``; joints and points have ``at``)."""

    def joint(self, name: str):
        for j in self.joints:
            if j.name == name:
                return j
        raise InputError(f"{self.name}: no joint {name!r}; joints are {[j.name for j in self.joints]}")

    def joints_of(self, link: str) -> list:
        return [j for j in self.joints if link in j.links]

    @property
    def loops(self) -> int:
        """Independent loops ``L = j − n + 1``."""
        return len(self.joints) - len(self.links) + 1

    @property
    def size(self) -> float:
        """The largest distance between two joints or points: the length scale of tolerances and residuals."""
        pts = [j.at for j in self.joints] + [p.at for p in self.points]
        best = 0.0
        for i, p in enumerate(pts):
            for q in pts[i + 1:]:
                best = max(best, math.dist(p, q))
        return best or 1.0


__all__ = ["Linkage"]
