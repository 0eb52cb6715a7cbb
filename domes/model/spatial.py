"""A dimensioned spatial mechanism: links, joints R, P, C, S, H with their axes, ground, inputs, points.

The mechanism file is the planar one extended to 3-D (``docs/spatial.md``):
``"space": "spatial"``, every ``at`` three numbers, and an ``axis`` (three
numbers, any length) for the joints that have one: R (revolute), P
(prismatic), C (cylindric), H (helical, with its ``pitch``: slide per
radian). S (spherical) joints have none. Inputs drive an R joint (its
angle), a P joint (its slide), or a C joint (``"variable": "angle"`` or
``"slide"``). The drawn pose is an assembled configuration; joint values
are measured from it.

>>> m = SpatialMechanism.from_dict({"space": "spatial", "links": ["frame", "crank", "rod", "rocker"],
...     "ground": "frame", "angle_unit": "rad", "joints": [
...     {"name": "A0", "type": "R", "links": ["frame", "crank"], "at": [0, 0, 700], "axis": [0, 0, 1]},
...     {"name": "A", "type": "S", "links": ["crank", "rod"], "at": [250, 0, 700]},
...     {"name": "B", "type": "S", "links": ["rod", "rocker"], "at": [700, 550, 0]},
...     {"name": "B0", "type": "R", "links": ["rocker", "frame"], "at": [700, 0, 0], "axis": [1, 0, 0]}],
...     "inputs": [{"joint": "A0", "speed": 10}]})
>>> m.dof, m.idle, [j.kind for j in m.joints]
(2, 1, ['R', 'S', 'S', 'R'])
>>> sorted(m.labelled().joint_types)
['R', 'R', 'Sph', 'Sph']
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass
from typing import Mapping

from domes.errors import InputError, shown
from domes.model.fields import LARGEST, check_keys, check_space, read_list, read_number
from domes.model.labelled import LabelledChain
from domes.model.linkage import Linkage
from domes.model.mobility import mobility

Point3 = tuple[float, float, float]

#: Each joint type's freedom (relative motions it allows).
FREEDOM = {"R": 1, "P": 1, "C": 2, "S": 3, "H": 1}
#: The labels of the joint types in a labelled chain (C, S, H there name a cam, a spring, a cylinder).
LABELS = {"R": "R", "P": "P", "C": "Cyl", "S": "Sph", "H": "Hel"}
#: The joint types that have an axis.
AXIAL = ("R", "P", "C", "H")
SPATIAL = 6


@dataclass(frozen=True)
class SpatialJoint:
    """A joint of two links at ``at``; ``axis`` a unit vector (R, P, C, H); ``pitch`` slide per radian (H)."""

    name: str
    kind: str
    links: tuple[str, str]
    at: Point3
    axis: Point3 | None = None
    pitch: float = 0.0

    @property
    def variables(self) -> tuple[str, ...]:
        """The joint's own coordinates that an input may drive."""
        return {"R": ("angle",), "P": ("slide",), "C": ("angle", "slide"), "H": ("angle",), "S": ()}[self.kind]


@dataclass(frozen=True)
class SpatialInput:
    """A driven joint variable (``angle`` in rad, ``slide`` in length) with its speed and acceleration."""

    joint: str
    variable: str = "angle"
    speed: float = 1.0
    acceleration: float = 0.0


@dataclass(frozen=True)
class SpatialPoint:
    """A named point of a link (drawn position)."""

    name: str
    link: str
    at: Point3


@dataclass(frozen=True)
class SpatialMechanism(Linkage):
    """A spatial mechanism in its drawn (assembled) pose. Build it with :meth:`build` or :meth:`from_dict`."""

    name: str
    links: tuple[str, ...]
    ground: str
    joints: tuple[SpatialJoint, ...]
    inputs: tuple[SpatialInput, ...]
    points: tuple[SpatialPoint, ...] = ()
    source: str = ""

    space = SPATIAL

    @classmethod
    def build(cls, name, links, ground, joints, inputs, points=(), source: str = "") -> "SpatialMechanism":
        """Validate and freeze; axes are normalised. Errors name the joint and what is wrong."""
        where = f"{source}: " if source else ""
        links = tuple(str(x) for x in links)
        if len(set(links)) != len(links):
            raise InputError(f"{where}links: duplicate link names in {list(links)}")
        if ground not in links:
            raise InputError(f"{where}ground: {ground!r} is not one of the links {list(links)}")
        out, names, pairs = [], set(), {}
        for j in joints:
            w = f"{where}joint {j.name!r}"
            if j.name in names:
                raise InputError(f"{w}: duplicate joint name")
            names.add(j.name)
            if j.kind not in FREEDOM:
                raise InputError(f"{w}: type {j.kind!r} is not one of {', '.join(FREEDOM)}")
            if len(j.links) != 2 or j.links[0] == j.links[1] or any(x not in links for x in j.links):
                raise InputError(f"{w}: joins two different links of {list(links)}, got {list(j.links)}")
            key = frozenset(j.links)
            if key in pairs:
                raise InputError(f"{w}: links {sorted(key)} are already joined by joint {pairs[key]!r}")
            pairs[key] = j.name
            if len(j.at) != 3 or not all(math.isfinite(v) for v in j.at):
                raise InputError(f"{w}: 'at' must be three finite numbers, got {list(j.at)}")
            axis = None
            if j.kind in AXIAL:
                if j.axis is None or len(j.axis) != 3 or not all(math.isfinite(v) for v in j.axis):
                    raise InputError(f"{w}: a {j.kind} joint needs its 'axis' (three finite numbers)")
                size = math.hypot(*j.axis)  # no overflow on large components
                if size < 1e-12:
                    raise InputError(f"{w}: the axis {list(j.axis)} has no direction")
                axis = tuple(v / size for v in j.axis)
            elif j.axis is not None:
                raise InputError(f"{w}: an S joint has no axis")
            if j.kind == "H" and not (math.isfinite(j.pitch) and j.pitch != 0):
                raise InputError(f"{w}: a helical joint needs a non-zero 'pitch' (slide per radian)")
            out.append(SpatialJoint(j.name, j.kind, tuple(j.links), tuple(float(v) for v in j.at), axis,
                                    float(j.pitch) if j.kind == "H" else 0.0))
        by_name = {j.name: j for j in out}
        seen = set()
        for i in inputs:
            if i.joint not in by_name:
                raise InputError(f"{where}inputs: joint {i.joint!r} is not one of the joints {sorted(by_name)}")
            if i.variable not in by_name[i.joint].variables:
                raise InputError(f"{where}inputs: joint {i.joint!r} ({by_name[i.joint].kind}) has no {i.variable!r} "
                                 f"to drive; it has {list(by_name[i.joint].variables) or 'none'}")
            if (i.joint, i.variable) in seen:
                raise InputError(f"{where}inputs: {i.joint}.{i.variable} is driven twice")
            seen.add((i.joint, i.variable))
            if not (math.isfinite(i.speed) and math.isfinite(i.acceleration)):
                raise InputError(f"{where}inputs: {i.joint}: speed and acceleration must be finite")
        point_names = [p.name for p in points]
        clash = (set(point_names) & set(by_name)) | {n for n, k in Counter(point_names).items() if k > 1}
        if clash:
            raise InputError(f"{where}points: names {sorted(clash)} are used twice (points and joints share one namespace)")
        for p in points:
            if p.link not in links:
                raise InputError(f"{where}point {p.name!r}: link {p.link!r} is not one of the links")
            if len(p.at) != 3 or not all(math.isfinite(v) for v in p.at):
                raise InputError(f"{where}point {p.name!r}: 'at' must be three finite numbers")
        return cls(str(name), links, str(ground), tuple(out), tuple(inputs),
                   tuple(SpatialPoint(p.name, p.link, tuple(float(v) for v in p.at)) for p in points), source)

    # -- views --------------------------------------------------------------------------------

    @property
    def dof(self) -> int:
        """Grübler–Kutzbach: ``6(n − j − 1) + Σ f`` (idle freedoms included; overconstrained linkages, such as
        the spherical four-bar, count less than they move: the kinematics tells their mobility from the rank)."""
        return mobility(len(self.links), len(self.joints), SPATIAL, sum(FREEDOM[j.kind] for j in self.joints))

    @property
    def idle(self) -> int:
        """Idle freedoms: each link held only by two S joints spins freely about the line through them."""
        count = 0
        for link in self.links:
            mine = self.joints_of(link)
            if link != self.ground and len(mine) == 2 and all(j.kind == "S" for j in mine):
                count += 1
        return count

    def point(self, name: str) -> tuple[str, Point3]:
        """``(link, drawn position)`` of a point or a joint (the joint on its second link)."""
        for p in self.points:
            if p.name == name:
                return p.link, p.at
        for j in self.joints:
            if j.name == name:
                return j.links[1], j.at
        raise InputError(f"{self.name}: no point or joint {name!r}")

    def labelled(self) -> LabelledChain:
        """The topology: a labelled chain whose joint labels are the joint types (R, P, C, S, H)."""
        index = {x: k for k, x in enumerate(self.links)}
        edges = [(index[j.links[0]], index[j.links[1]]) for j in self.joints]
        roles = [frozenset({"ground"}) if x == self.ground else frozenset() for x in self.links]
        return LabelledChain.build(len(self.links), edges, [LABELS[j.kind] for j in self.joints],
                                   {k: r for k, r in enumerate(roles) if r})

    # -- files ----------------------------------------------------------------------------------

    @classmethod
    def from_dict(cls, data: Mapping, source: str = "<dict>") -> "SpatialMechanism":
        """From the JSON structure of ``docs/spatial.md`` (angles in degrees unless ``angle_unit`` is rad)."""
        check_keys(data, {"name", "comment", "space", "angle_unit", "links", "ground", "joints", "inputs", "points"},
                   {"space", "links", "ground", "joints", "inputs"}, source)
        check_space(data, "spatial", source)
        unit = data.get("angle_unit", "deg")
        if unit not in ("deg", "rad"):
            raise InputError(f"{source}: angle_unit must be 'deg' or 'rad', got {unit!r}")
        to_rad = math.radians if unit == "deg" else float
        for key in ("links", "joints", "inputs"):
            if not isinstance(data[key], list):
                raise InputError(f"{source}: {key}: expected a list")
        joints = []
        for k, item in enumerate(data["joints"]):
            w = f"{source}: joints[{k}]"
            check_keys(item, {"name", "type", "links", "at", "axis", "pitch"}, {"name", "type", "links", "at"}, w)
            if not isinstance(item["links"], list):
                raise InputError(f"{w}.links: expected a list of two link names")
            joints.append(SpatialJoint(str(item["name"]), str(item["type"]), tuple(str(x) for x in item["links"]),
                                       _xyz(item["at"], f"{w}.at"),
                                       _xyz(item["axis"], f"{w}.axis") if "axis" in item else None,
                                       read_number(item.get("pitch", 0.0), f"{w}.pitch")))
        kinds = {j.name: j.kind for j in joints}
        inputs = []
        for k, item in enumerate(data["inputs"]):
            w = f"{source}: inputs[{k}]"
            check_keys(item, {"joint", "variable", "speed", "acceleration"}, {"joint"}, w)
            variable = str(item.get("variable", "slide" if kinds.get(item["joint"]) == "P" else "angle"))
            scale = to_rad if variable == "angle" else float
            speed = read_number(item.get("speed", 1.0), f"{w}.speed", LARGEST)
            acceleration = read_number(item.get("acceleration", 0.0), f"{w}.acceleration", LARGEST)
            inputs.append(SpatialInput(str(item["joint"]), variable, scale(speed), scale(acceleration)))
        points = []
        for k, item in enumerate(read_list(data.get("points", []), f"{source}: points")):
            w = f"{source}: points[{k}]"
            check_keys(item, {"name", "link", "at"}, {"name", "link", "at"}, w)
            points.append(SpatialPoint(str(item["name"]), str(item["link"]), _xyz(item["at"], f"{w}.at")))
        return cls.build(str(data.get("name", source)), [str(x) for x in data["links"]], str(data["ground"]), joints,
                         inputs, points, source)

    def to_dict(self) -> dict:
        """The JSON structure (angles in degrees); inverse of :meth:`from_dict`."""
        joints = []
        for j in self.joints:
            item = {"name": j.name, "type": j.kind, "links": list(j.links), "at": list(j.at)}
            if j.axis is not None:
                item["axis"] = list(j.axis)
            if j.kind == "H":
                item["pitch"] = j.pitch
            joints.append(item)
        scale = math.degrees
        return {"name": self.name, "space": "spatial", "angle_unit": "deg", "links": list(self.links),
                "ground": self.ground, "joints": joints,
                "inputs": [{"joint": i.joint, "variable": i.variable,
                            "speed": scale(i.speed) if i.variable == "angle" else i.speed,
                            "acceleration": scale(i.acceleration) if i.variable == "angle" else i.acceleration}
                           for i in self.inputs],
                "points": [{"name": p.name, "link": p.link, "at": list(p.at)} for p in self.points]}

    def _repr_svg_(self) -> str | None:
        """The mechanism drawn at its drawn pose, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "svg")


def _xyz(value, where: str) -> Point3:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise InputError(f"{where}: expected [x, y, z], got {shown(value)}")
    return tuple(read_number(v, f"{where}[{k}]", LARGEST) for k, v in enumerate(value))


__all__ = ["AXIAL", "FREEDOM", "SpatialInput", "SpatialJoint", "SpatialMechanism", "SpatialPoint"]
