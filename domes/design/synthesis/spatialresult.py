"""What a spatial synthesis task returns, the one reader of its vectors and the spherical four-bar it builds
(shared by the task kinds).

>>> r = SpatialSynthesis("demo", "rccc", Status.EMPTY, ())
>>> r.success, r.message
(False, 'empty: demo (rccc): nothing found')
>>> vector([1, 2, 3], 3, "b1").tolist()
[1.0, 2.0, 3.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError, shown
from domes.model.fields import LARGEST, read_number
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism
from domes.results import Result, Status


def vector(value, n: int, where: str) -> np.ndarray:
    """``n`` numbers of a task file's entry ``where`` as an array; an InputError says what is wrong."""
    if not isinstance(value, list) or len(value) != n:
        raise InputError(f"{where}: expected {n} numbers, got {shown(value)}")
    return np.array([read_number(v, f"{where}[{k}]", LARGEST) for k, v in enumerate(value)])


@dataclass(frozen=True, eq=False)
class SpatialSynthesis(Result):
    """Solutions of a spatial task: ``lines`` of text, ``mechanisms`` (spatial mechanism files where the task
    gives a linkage), ``worst`` (the largest residual or pose error), ``details`` for JSON."""

    name: str
    kind: str
    status: Status
    lines: tuple[str, ...]
    mechanisms: tuple[SpatialMechanism, ...] = ()
    worst: float = 0.0
    details: dict = field(default_factory=dict)

    @property
    def message(self) -> str:
        return f"{self.status}: {self.name} ({self.kind}): " + (self.lines[0] if self.lines else "nothing found")

    def to_dict(self) -> dict:
        return {"name": self.name, "kind": self.kind, "status": str(self.status), "message": self.message,
                "lines": list(self.lines), "worst": self.worst, **self.details,
                "mechanisms": [m.to_dict() for m in self.mechanisms]}

    def _repr_html_(self) -> str | None:
        """Every mechanism found, drawn, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


def spherical_fourbar(alpha: float, a1, b1, name: str) -> SpatialMechanism:
    """The spherical four-bar of Fig. 2-20 as a spatial mechanism: input axis x, output axis at ``alpha`` in the
    x-y plane, moving pivots ``a1``, ``b1`` (unit vectors, position 1)."""
    u = (math.cos(alpha), math.sin(alpha), 0.0)
    joints = (SpatialJoint("A0", "R", ("frame", "input"), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)),
              SpatialJoint("A", "R", ("input", "coupler"), tuple(map(float, a1)), tuple(map(float, a1))),
              SpatialJoint("B", "R", ("coupler", "output"), tuple(map(float, b1)), tuple(map(float, b1))),
              SpatialJoint("B0", "R", ("frame", "output"), u, u))
    return SpatialMechanism.build(name, ("frame", "input", "coupler", "output"), "frame", joints, (SpatialInput("A0"),))


__all__ = ["SpatialSynthesis", "spherical_fourbar", "vector"]
