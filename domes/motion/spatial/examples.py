"""Spatial example mechanisms built in code (the files are in ``examples/spatial/``).

>>> m = rssr()
>>> m.name, round(m.size, 3)
('RSSR of seed 001 (Sun & Zhou, Table 1)', 1132.475)
"""

from __future__ import annotations

from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism


def rssr(M: float = 700.0, N: float = 700.0, L1: float = 250.0, L3: float = 550.0, D: float = 0.0,
         speed: float = 10.0) -> SpatialMechanism:
    """The RSSR of seed 001 §3 (mm): crank A0A about z in the plane z = N, rocker B0B about the line
    {y = D, z = 0} (parallel to x) in the plane x = M; drawn at α = β = 0, so the coupler is
    ``|A1 − B1|`` (the paper's implicit coupler length when D = 0). Angles: α of joint A0, β of joint B0."""
    joints = (SpatialJoint("A0", "R", ("frame", "crank"), (0.0, 0.0, N), (0.0, 0.0, 1.0)),
              SpatialJoint("A", "S", ("crank", "coupler"), (L1, 0.0, N)),
              SpatialJoint("B", "S", ("coupler", "rocker"), (M, D + L3, 0.0)),
              SpatialJoint("B0", "R", ("frame", "rocker"), (M, D, 0.0), (1.0, 0.0, 0.0)))
    return SpatialMechanism.build("RSSR of seed 001 (Sun & Zhou, Table 1)", ("frame", "crank", "coupler", "rocker"),
                                  "frame", joints, (SpatialInput("A0", "angle", speed),))


__all__ = ["rssr"]
