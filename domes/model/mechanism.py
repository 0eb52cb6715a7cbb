"""The dimensioned planar mechanism: links, R and P joints, ground, inputs, points.

Coordinates describe the mechanism in one assembled configuration, the
*drawn pose*: every joint at its place, every slide line through its joint.
The drawn pose fixes the link shapes (all distances between a link's joints)
and the assembly mode (branch) that sweeps continue from.

An R joint is a pin at ``at``. A P joint joins a *guide* (``links[0]``,
which carries the slide line) and a *slider* (``links[1]``); the line
passes through ``at`` with direction ``direction``; the slide coordinate
``s`` is the distance along the line from ``origin`` (a point of the guide
on the line, ``at`` by default) to the slider's point that is at ``at`` in
the drawn pose. An R joint of ``m > 2`` links (a compound hinge) is split
into ``m − 1`` joints at the same point (seed 000, §2.11) named ``J``,
``J.1``, ``J.2``, ...

The angle of a link is the direction of its reference line: from its first
joint to its second joint (in the order of :attr:`Mechanism.joints`), unless
given in ``link_angles``. An input is a joint whose joint variable is
prescribed: for an R joint between the ground and link ``k`` the absolute
angle of ``k``; for an R joint between two moving links ``a, b`` the angle of
``b`` minus the angle of ``a``; for a P joint its slide coordinate ``s``.

>>> m = Mechanism.build(
...     name="four-bar", links=["frame", "crank", "coupler", "rocker"], ground="frame",
...     joints=[Joint("A", "R", ("frame", "crank"), (0.0, 0.0)),
...             Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
...             Joint("C", "R", ("coupler", "rocker"), (3.5, 6 ** 0.5)),
...             Joint("D", "R", ("rocker", "frame"), (3.0, 0.0))],
...     inputs=[Input("A")])
>>> m.dof, m.loops, m.size
(1, 1, 4.272001872658765)
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path
from typing import Iterable, Mapping

from domes.errors import InputError, shown
from domes.model.cams import FACES, MAX_POINTS, CamPair, CamProfile, Follower, profile_points
from domes.model.fields import LARGEST, check_space, read_list
from domes.model.fields import check_keys as _keys
from domes.model.fields import read_number as _num
from domes.model.fields import read_xy as _xy
from domes.model.gears import GearPair, read_teeth
from domes.model.labelled import LabelledChain
from domes.model.laws import Motion
from domes.model.linkage import Linkage
from domes.model.masses import MassModel
from domes.model.mobility import mobility

Point2 = tuple[float, float]


@dataclass(frozen=True)
class Joint:
    """A revolute (``"R"``) or prismatic (``"P"``) joint of two links."""

    name: str
    kind: str
    links: tuple[str, str]
    at: Point2
    direction: float = 0.0
    origin: Point2 | None = None

    @property
    def slide_origin(self) -> Point2:
        return self.at if self.origin is None else self.origin

    @property
    def s0(self) -> float:
        """The slide coordinate in the drawn pose."""
        ox, oy = self.slide_origin
        return (self.at[0] - ox) * math.cos(self.direction) + (self.at[1] - oy) * math.sin(self.direction)


@dataclass(frozen=True)
class Input:
    """A driven joint with its speed and acceleration (per unit time)."""

    joint: str
    speed: float = 1.0
    acceleration: float = 0.0


@dataclass(frozen=True)
class CouplerPoint:
    """A named point carried by a link (drawn-pose coordinates)."""

    name: str
    link: str
    at: Point2


@dataclass(frozen=True)
class Polygon:
    """A polygon carried by a link (drawn-pose vertices), for interference checks."""

    name: str
    link: str
    vertices: tuple[Point2, ...]


@dataclass(frozen=True)
class Mechanism(Linkage):
    """A dimensioned planar mechanism in its drawn pose (immutable). Build with :meth:`build`."""

    name: str
    links: tuple[str, ...]
    ground: str
    joints: tuple[Joint, ...]
    inputs: tuple[Input, ...]
    points: tuple[CouplerPoint, ...] = ()
    polygons: tuple[Polygon, ...] = ()
    link_angles: tuple[tuple[str, float], ...] = ()
    source: str = field(default="", compare=False)
    masses: MassModel = MassModel()
    gears: tuple[GearPair, ...] = ()
    cams: tuple[CamPair, ...] = ()

    @classmethod
    def build(cls, name, links, ground, joints, inputs, points=(), polygons=(), link_angles=None, source="",
              masses: MassModel | None = None, gears=(), cams=()):
        """Validate, split compound hinges, and freeze. ``masses`` (:class:`~domes.model.masses.MassModel`):
        mass properties, loads, springs and gravity, for dynamics (none by default); ``gears``
        (:class:`~domes.model.gears.GearPair`): gear and rack pairs; ``cams``
        (:class:`~domes.model.cams.CamPair`): cam pairs given by their follower's law."""
        where = f"{source}: " if source else ""
        links = tuple(str(x) for x in links)
        if len(set(links)) != len(links):
            raise InputError(f"{where}links: duplicate link names in {list(links)}")
        if ground not in links:
            raise InputError(f"{where}ground: {ground!r} is not one of the links {list(links)}")
        split: list[Joint] = []
        names: set[str] = set()
        for j in joints:
            where_j = f"{where}joint {j.name!r}"
            if j.name in names:
                raise InputError(f"{where_j}: duplicate joint name")
            names.add(j.name)
            if j.kind not in ("R", "P"):
                raise InputError(f"{where_j}: type {j.kind!r} is not supported; use 'R' or 'P' (a gear pair is "
                                 "a GearPair, type 'G' in files; model a cylinder as two links joined by a P joint)")
            for x in j.links:
                if x not in links:
                    raise InputError(f"{where_j}: link {x!r} is not one of the links {list(links)}")
            if len(set(j.links)) != len(j.links) or len(j.links) < 2:
                raise InputError(f"{where_j}: needs two or more different links, got {list(j.links)}")
            if not all(math.isfinite(v) for v in j.at) or len(j.at) != 2:
                raise InputError(f"{where_j}: 'at' must be two finite numbers, got {j.at}")
            if j.kind == "P":
                if len(j.links) != 2:
                    raise InputError(f"{where_j}: a P joint joins exactly two links (guide, slider)")
                if j.origin is not None:
                    ox, oy = j.origin
                    off = -(j.at[0] - ox) * math.sin(j.direction) + (j.at[1] - oy) * math.cos(j.direction)
                    scale = max(1.0, abs(j.at[0] - ox) + abs(j.at[1] - oy))
                    if abs(off) > 1e-9 * scale:
                        raise InputError(f"{where_j}: origin {j.origin} is {off:.3g} off the slide line "
                                         "through 'at' with the given direction")
                split.append(j)
            elif len(j.links) == 2:
                split.append(j)
            else:
                first = j.links[0]
                for k, other in enumerate(j.links[1:]):
                    split.append(Joint(j.name if k == 0 else f"{j.name}.{k}", "R", (first, other), j.at))
        pairs: dict[frozenset, str] = {}
        for j in split:
            key = frozenset(j.links)
            if key in pairs:
                raise InputError(f"{where}joint {j.name!r}: links {sorted(key)} are already joined by joint {pairs[key]!r}")
            pairs[key] = j.name
        by_name = {j.name: j for j in split}
        gears, cams = tuple(gears), tuple(cams)
        for g in gears + cams:
            where_g = f"{where}{'gear' if isinstance(g, GearPair) else 'cam'} pair {g.name!r}"
            if g.name in by_name or sum(1 for h in gears + cams if h.name == g.name) > 1:
                raise InputError(f"{where_g}: duplicate joint name")
            if len(g.links) != 2 or g.links[0] == g.links[1] or any(x not in links for x in g.links):
                raise InputError(f"{where_g}: needs two different links of {list(links)}, got {list(g.links)}")
            if g.carrier is not None and g.carrier not in links:
                raise InputError(f"{where_g}: carrier {g.carrier!r} is not one of the links {list(links)}")
            if len(g.at) != 2 or not all(math.isfinite(v) for v in g.at):
                raise InputError(f"{where_g}: 'at' (the pitch point) must be two finite numbers, got {g.at}")
        inputs = tuple(inputs)
        if len({i.joint for i in inputs}) != len(inputs):
            raise InputError(f"{where}inputs: a joint is driven twice")
        for i in inputs:
            if i.joint not in by_name:
                raise InputError(f"{where}inputs: joint {i.joint!r} is not one of the joints {sorted(by_name)}")
        for p in tuple(points) + tuple(polygons):
            if p.link not in links:
                raise InputError(f"{where}{type(p).__name__.lower()} {p.name!r}: link {p.link!r} is not one of the links")
        point_names = [p.name for p in points]
        clash = (set(point_names) & set(by_name)) | {n for n, k in Counter(point_names).items() if k > 1}
        if clash:
            raise InputError(f"{where}points: names {sorted(clash)} are used twice (points and joints share one namespace)")
        for poly in polygons:
            if len(poly.vertices) < 3:
                raise InputError(f"{where}polygon {poly.name!r}: needs three or more vertices")
        angles = dict(link_angles or {})
        for x in angles:
            if x not in links:
                raise InputError(f"{where}link_angles: {x!r} is not one of the links")
        masses = masses or MassModel()
        places = {j.name: j.links[0] for j in split} | {p.name: p.link for p in points}
        masses.check(links, places, where)
        mech = cls(name, links, ground, tuple(split), inputs, tuple(points), tuple(polygons),
                   tuple(sorted(angles.items())), source, masses, gears, cams)
        for g in gears:
            g.mesh(mech)
        for c in cams:
            c.contact(mech)
        dof = mech.dof
        if dof != len(inputs):
            higher = len(gears) + len(cams)
            count = f"3·{len(links) - 1} − 2·{len(split)}" + (f" − {higher}" if higher else "")
            raise InputError(f"{where}the mechanism has {dof} degree(s) of freedom (3(n−1) − 2j{' − j_H' if higher else ''}"
                             f" = {count}) but {len(inputs)} input(s); give one driven joint per degree of freedom")
        return mech

    # -- views -----------------------------------------------------------------

    @property
    def dof(self) -> int:
        """Degrees of freedom by Grübler's count ``3(n − 1) − 2j − j_H`` (a gear or cam pair has two freedoms)."""
        higher = len(self.gears) + len(self.cams)
        pairs = len(self.joints) + higher
        return mobility(len(self.links), pairs, freedom=pairs + higher)

    def meshes(self) -> list:
        """The gear pairs resolved (:class:`~domes.model.gears.Mesh`): kind, carrier, centres, ratio."""
        return [g.mesh(self) for g in self.gears]

    def point(self, name: str) -> tuple[str, Point2]:
        """``(link, drawn position)`` of a coupler point or joint (the joint on its first link)."""
        for p in self.points:
            if p.name == name:
                return p.link, p.at
        for j in self.joints:
            if j.name == name:
                return j.links[-1] if j.kind == "P" else j.links[0], j.at
        raise InputError(f"{self.name}: no point or joint {name!r}")

    def reference_angle(self, link: str) -> float:
        """The angle of ``link``'s reference line in the drawn pose (rad)."""
        given = dict(self.link_angles)
        if link in given:
            return given[link]
        return self.reference_angle_rule(link)

    def reference_angle_rule(self, link: str) -> float:
        """The angle from ``link``'s first joint to its next joint elsewhere (the reference line unless given)."""
        pts = [j.at for j in self.joints_of(link)]
        for p in pts[1:]:
            dx, dy = p[0] - pts[0][0], p[1] - pts[0][1]
            if dx or dy:
                return math.atan2(dy, dx)
        return 0.0

    def labelled(self) -> LabelledChain:
        """The mechanism's topology: a :class:`~domes.model.LabelledChain` with its joint types, ground and names.

        >>> from domes.motion.planar.examples import slider_crank
        >>> chain = slider_crank().labelled()
        >>> chain.joint_types, chain.links_with_role("ground"), chain.link_name(0)
        (('R', 'P', 'R', 'R'), [0], 'frame')
        """
        index = {name: i for i, name in enumerate(self.links)}
        pairs = list(self.joints) + [Joint(g.name, "G", g.links, g.at) for g in self.gears] \
            + [Joint(c.name, "C", c.links, c.at) for c in self.cams]
        return LabelledChain.build(
            len(self.links),
            [(index[j.links[0]], index[j.links[1]]) for j in pairs],
            [j.kind for j in pairs],
            {index[self.ground]: {"ground"}},
            name=self.name,
            link_names=self.links,
            joint_names=[j.name for j in pairs],
        )

    @classmethod
    def from_dict(cls, data: Mapping, source: str = "<dict>") -> "Mechanism":
        """Build a :class:`Mechanism` from the JSON structure documented in ``docs/kinematics.md``.

        >>> m = Mechanism.from_dict({"links": ["g", "a", "b", "c"], "ground": "g",
        ...     "joints": [{"name": "A", "type": "R", "links": ["g", "a"], "at": [0, 0]},
        ...                {"name": "B", "type": "R", "links": ["a", "b"], "at": [1, 0]},
        ...                {"name": "C", "type": "R", "links": ["b", "c"], "at": [2, 2]},
        ...                {"name": "D", "type": "R", "links": ["c", "g"], "at": [3, 0]}],
        ...     "inputs": [{"joint": "A", "speed": 90}]})
        >>> round(m.inputs[0].speed, 6)  # degrees by default
        1.570796
        """
        check_space(data, "planar", source)
        _keys(data, {"name", "angle_unit", "space", "links", "ground", "joints", "inputs", "points", "polygons",
                     "comment", "gravity", "loads", "springs"}, {"links", "ground", "joints", "inputs"}, source)
        unit = data.get("angle_unit", "deg")
        if unit not in ("deg", "rad"):
            raise InputError(f"{source}: angle_unit must be 'deg' or 'rad', got {unit!r}")
        to_rad = math.radians if unit == "deg" else float
        links, link_angles, link_items = [], {}, {}
        if not isinstance(data["links"], list):
            raise InputError(f"{source}: links: expected a list")
        for k, item in enumerate(data["links"]):
            where = f"{source}: links[{k}]"
            if isinstance(item, str):
                links.append(item)
                continue
            _keys(item, {"name", "angle", "mass", "centre", "inertia"}, {"name"}, where)
            links.append(str(item["name"]))
            link_items[links[-1]] = item
            if "angle" in item:
                link_angles[links[-1]] = to_rad(_num(item["angle"], f"{where}.angle"))
        joints, gears, cams = [], [], []
        if not isinstance(data["joints"], list):
            raise InputError(f"{source}: joints: expected a list")
        for k, item in enumerate(data["joints"]):
            where = f"{source}: joints[{k}]"
            _keys(item, {"name", "type", "links", "at", "direction", "origin", "teeth", "carrier", "law", "phase"}
                  | PROFILE_KEYS, {"name", "type", "links", "at"}, where)
            if not isinstance(item["links"], list):
                raise InputError(f"{where}.links: expected a list of link names")
            if item["type"] == "C":
                cams.append((item, where))
                continue
            extra = ({"law", "phase"} | PROFILE_KEYS) & set(item)
            if extra:
                raise InputError(f"{where}: {sorted(extra)} belong to cam pairs (type 'C'), not to a {item['type']!r} joint")
            if item["type"] == "G":
                if len(item["links"]) != 2:
                    raise InputError(f"{where}.links: a gear pair joins exactly two links")
                gears.append(GearPair(str(item["name"]), tuple(str(x) for x in item["links"]), _xy(item["at"], f"{where}.at"),
                                      read_teeth(item["teeth"], f"{where}.teeth") if "teeth" in item else None,
                                      str(item["carrier"]) if "carrier" in item else None))
                continue
            extra = {"teeth", "carrier"} & set(item)
            if extra:
                raise InputError(f"{where}: {sorted(extra)} belong to gear pairs (type 'G'), not to a {item['type']!r} joint")
            joints.append(Joint(
                str(item["name"]), str(item["type"]), tuple(str(x) for x in item["links"]), _xy(item["at"], f"{where}.at"),
                to_rad(_num(item.get("direction", 0.0), f"{where}.direction")),
                _xy(item["origin"], f"{where}.origin") if "origin" in item else None,
            ))
        cams = [_cam_from(item, where, to_rad, joints, source) for item, where in cams]
        inputs = []
        for k, item in enumerate(read_list(data["inputs"], f"{source}: inputs")):
            where = f"{source}: inputs[{k}]"
            _keys(item, {"joint", "speed", "acceleration"}, {"joint"}, where)
            jt = next((j for j in joints if j.name == item["joint"]), None)
            scale = to_rad if jt is not None and jt.kind == "R" else float
            inputs.append(Input(str(item["joint"]), scale(_num(item.get("speed", 1.0), f"{where}.speed", LARGEST)),
                                scale(_num(item.get("acceleration", 0.0), f"{where}.acceleration", LARGEST))))
        points = []
        for k, item in enumerate(read_list(data.get("points", []), f"{source}: points")):
            where = f"{source}: points[{k}]"
            _keys(item, {"name", "link", "at"}, {"name", "link", "at"}, where)
            points.append(CouplerPoint(str(item["name"]), str(item["link"]), _xy(item["at"], f"{where}.at")))
        polygons = []
        for k, item in enumerate(read_list(data.get("polygons", []), f"{source}: polygons")):
            where = f"{source}: polygons[{k}]"
            _keys(item, {"name", "link", "vertices"}, {"name", "link", "vertices"}, where)
            vertices = read_list(item["vertices"], f"{where}.vertices")
            polygons.append(Polygon(str(item["name"]), str(item["link"]),
                                    tuple(_xy(v, f"{where}.vertices[{i}]") for i, v in enumerate(vertices))))
        masses = MassModel.from_dict(data, link_items, source)
        return cls.build(str(data.get("name", source)), links, str(data["ground"]), joints, inputs,
                         points, polygons, link_angles, source, masses, gears, cams)

    def to_dict(self) -> dict:
        """The JSON structure of the mechanism (angles in degrees); inverse of :meth:`from_dict`."""
        mech = self
        angles = dict(mech.link_angles)
        deg = math.degrees
        links = []
        for x in mech.links:
            item = {"name": x, **({"angle": deg(angles[x])} if x in angles else {}), **mech.masses.link_dict(x)}
            links.append(item if len(item) > 1 else x)
        out: dict = {"name": mech.name, "angle_unit": "deg", "ground": mech.ground, "links": links,
                     "joints": [], "inputs": []}
        for j in mech.joints:
            item = {"name": j.name, "type": j.kind, "links": list(j.links), "at": list(j.at)}
            if j.kind == "P":
                item["direction"] = deg(j.direction)
                if j.origin is not None:
                    item["origin"] = list(j.origin)
            out["joints"].append(item)
        for g in mech.gears:
            item = {"name": g.name, "type": "G", "links": list(g.links), "at": list(g.at)}
            if g.teeth is not None:
                item["teeth"] = list(g.teeth)
            if g.carrier is not None:
                item["carrier"] = g.carrier
            out["joints"].append(item)
        for c in mech.cams:
            oscillating = c.contact(mech).kind == "oscillating"
            item = {"name": c.name, "type": "C", "links": list(c.links), "at": list(c.at)}
            if isinstance(c.law, CamProfile):
                item.update(_profile_dict(c.law))
            else:
                item["law"] = [[g.law, deg(g.length), deg(g.rise) if oscillating else g.rise] for g in c.law.segments]
            if c.phase:
                item["phase"] = deg(c.phase)
            if c.carrier is not None:
                item["carrier"] = c.carrier
            out["joints"].append(item)
        for i in mech.inputs:
            scale = deg if mech.joint(i.joint).kind == "R" else float
            out["inputs"].append({"joint": i.joint, "speed": scale(i.speed), "acceleration": scale(i.acceleration)})
        if mech.points:
            out["points"] = [{"name": p.name, "link": p.link, "at": list(p.at)} for p in mech.points]
        if mech.polygons:
            out["polygons"] = [{"name": p.name, "link": p.link, "vertices": [list(v) for v in p.vertices]}
                               for p in mech.polygons]
        out.update(mech.masses.to_dict())
        return out

    def _repr_svg_(self) -> str | None:
        """The mechanism to scale, with its coupler curves, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "svg")


#: A cam pair's keys when it is given by its cam's profile instead of a law.
PROFILE_KEYS = {"profile", "face", "roller", "offset", "arm", "base_radius", "profile_direction"}


def _cam_from(item, where: str, to_rad, joints, source: str = "") -> CamPair:
    """A cam pair from its file item: ``law`` as ``[law, degrees, rise]`` rows over one turn, the rise a length for
    a translating follower (one on a P joint) and an angle in the file's unit for an oscillating one; or its cam's
    ``profile`` (:func:`_profile_from`)."""
    if len(item["links"]) != 2:
        raise InputError(f"{where}.links: a cam pair joins exactly two links [cam, follower]")
    if "law" in item and "profile" in item:
        raise InputError(f"{where}: give the follower's 'law' or the cam's 'profile', not both")
    if "law" not in item and "profile" not in item:
        raise InputError(f"{where}: a cam pair needs its follower's 'law' (rows [law, degrees, rise] over one turn) or "
                         "its cam's 'profile' (points [x, y], or a CSV file of them) with the follower's 'face'")
    cam, follower = (str(x) for x in item["links"])
    on_cam_carrier = {x for j in joints if j.kind == "R" and cam in j.links for x in j.links} - {cam}
    sliding = any(j.kind == "P" and follower in j.links and set(j.links) & on_cam_carrier for j in joints)
    phase = to_rad(_num(item.get("phase", 0.0), f"{where}.phase"))
    carrier = str(item["carrier"]) if "carrier" in item else None
    at = _xy(item["at"], f"{where}.at")
    if "profile" in item:
        law = _profile_from(item, where, joints, (cam, follower), carrier, sliding, source)
        return CamPair(str(item["name"]), (cam, follower), at, law, phase, carrier)
    extra = PROFILE_KEYS & set(item)
    if extra:
        raise InputError(f"{where}: {sorted(extra)} describe a cam given by its 'profile'; this pair gives a 'law'")
    rows = []
    for k, r in enumerate(read_list(item["law"], f"{where}.law")):
        if not isinstance(r, list) or len(r) not in (2, 3):
            raise InputError(f"{where}.law[{k}]: expected [law, degrees] or [law, degrees, rise], got {r!r}")
        rise = _num(r[2], f"{where}.law[{k}][2]") if len(r) == 3 else 0.0
        rows.append((r[0], _num(r[1], f"{where}.law[{k}][1]"), rise if sliding else to_rad(rise)))
    try:
        law = Motion.cam(rows)
    except InputError as exc:
        raise InputError(f"{where}.law: {exc}") from None
    return CamPair(str(item["name"]), (cam, follower), at, law, phase, carrier)


def _profile_from(item, where: str, joints, links, carrier, sliding: bool, source: str) -> CamProfile:
    """A cam pair's :class:`~domes.model.cams.CamProfile` from its file item: ``profile`` (points ``[x, y]`` or a
    CSV file of them, relative to the mechanism file), ``face``, ``roller``, ``offset`` (translating) or ``arm``
    (oscillating), ``base_radius`` and ``profile_direction`` (``ccw`` or ``cw``); an oscillating follower's pivot
    distance from the drawn joints."""
    cam, follower = links
    if "face" not in item:
        raise InputError(f"{where}: a cam pair given by its 'profile' needs its follower's 'face': "
                         f"{', '.join(FACES)}")
    if item["face"] not in FACES:
        raise InputError(f"{where}.face: unknown face {shown(item['face'])}; one of {', '.join(FACES)}")
    value = item["profile"]
    if isinstance(value, str):
        points, here = _profile_csv(value, where, source)
    else:
        here = f"{where}.profile"
        rows = read_list(value, here)
        if len(rows) > MAX_POINTS:
            raise InputError(f"{here}: {len(rows):,} points; at most {MAX_POINTS:,}")
        points = tuple(_xy(r, f"{here}[{k}]") for k, r in enumerate(rows))
    try:
        profile_points(points)
    except InputError as exc:
        raise InputError(f"{here}: {exc}") from None
    kind = "translating" if sliding else "oscillating"
    wrong = ("arm",) if sliding else ("offset",)
    if wrong[0] in item:
        raise InputError(f"{where}.{wrong[0]}: the follower is {kind}; it has "
                         f"{'an offset' if sliding else 'an arm'}, not {'an arm' if sliding else 'an offset'}")
    pivot = 0.0
    if not sliding:
        found = [(c, j, k) for j in joints if j.kind == "R" and cam in j.links
                 for c in set(j.links) - {cam} if carrier is None or c == carrier
                 for k in joints if k.kind == "R" and set(k.links) == {follower, c}]
        if len(found) != 1:
            raise InputError(f"{where}: the follower {follower!r} must slide (P) or turn (R) on one link the cam "
                             f"{cam!r} turns on" + (f"; {len(found)} could carry it: name one with 'carrier'"
                                                     if found else ""))
        pivot = math.dist(found[0][1].at, found[0][2].at)
    direction = item.get("profile_direction", "ccw")
    if direction not in ("ccw", "cw"):
        raise InputError(f"{where}.profile_direction: 'ccw' or 'cw' (the cam's turning its profile was designed for), "
                         f"got {shown(direction)}")
    base = _num(item["base_radius"], f"{where}.base_radius", LARGEST) if "base_radius" in item else None
    try:
        follower = Follower(kind, str(item["face"]), roller=_num(item.get("roller", 0.0), f"{where}.roller", LARGEST),
                            offset=_num(item.get("offset", 0.0), f"{where}.offset", LARGEST), pivot=pivot,
                            arm=_num(item.get("arm", 0.0), f"{where}.arm", LARGEST))
        return CamProfile(points, follower, base_radius=base, direction=1 if direction == "ccw" else -1)
    except InputError as exc:
        raise InputError(f"{where}: {exc}") from None


def _profile_csv(name: str, where: str, source: str) -> tuple[tuple, str]:
    """A profile's points from a CSV file (``domes cam --format csv``'s, by its ``x`` and ``y`` columns; or rows of
    ``x, y``; ``#`` comments), its path relative to the mechanism file ``source``."""
    folder = Path(source).parent if source and not source.startswith("<") else Path(".")
    path = Path(name) if Path(name).is_absolute() else folder / name
    here = f"{where}.profile ({path})"
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(f"{here}: cannot read the file: {getattr(exc, 'strerror', None) or exc}") from None
    points, cols = [], None
    for n, line in enumerate(text.splitlines(), start=1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        cells = [c.strip() for c in (line.split(",") if "," in line else line.split())]
        if cols is None and not points:
            try:
                [float(c) for c in cells]
            except ValueError:
                names = [c.lower() for c in cells]
                if "x" not in names or "y" not in names:
                    raise InputError(f"{here}: line {n}: a header must name the columns 'x' and 'y', got "
                                     f"{shown(line)}") from None
                cols = (names.index("x"), names.index("y"))
                continue
        if cols is None and len(cells) != 2:
            raise InputError(f"{here}: line {n}: expected 'x, y' (or a header naming columns x and y), got "
                             f"{shown(line)}")
        if cols is not None and len(cells) <= max(cols):
            raise InputError(f"{here}: line {n}: {len(cells)} columns, the header has more")
        xy = [cells[i] for i in (cols or (0, 1))]
        try:
            x, y = (float(c) for c in xy)
        except ValueError:
            raise InputError(f"{here}: line {n}: expected numbers x, y, got {shown(', '.join(xy))}") from None
        if not (math.isfinite(x) and math.isfinite(y) and max(abs(x), abs(y)) <= LARGEST):
            raise InputError(f"{here}: line {n}: x and y must be finite numbers at most {LARGEST:g} in size")
        points.append((x, y))
        if len(points) > MAX_POINTS:
            raise InputError(f"{here}: more than {MAX_POINTS:,} points")
    return tuple(points), here


def _profile_dict(p: CamProfile) -> dict:
    """A profile cam pair's file keys (its points written inline, so the file stands alone)."""
    f = p.follower
    out = {"profile": [list(xy) for xy in p.points], "face": f.face}
    if f.face == "roller":
        out["roller"] = f.roller
    if f.kind == "translating":
        if f.offset:
            out["offset"] = f.offset
    else:
        out["arm"] = f.arm
    if p.base_radius is not None:
        out["base_radius"] = p.base_radius
    if p.direction == -1:
        out["profile_direction"] = "cw"
    return out


# -- file format ------------------------------------------------------------------


def from_labelled(chain, at: Mapping, directions: Mapping | None = None, inputs: Iterable | None = None,
                  guides: Mapping | None = None, name: str = "candidate", points: Iterable = ()) -> Mechanism:
    """A dimensioned mechanism from a :class:`~domes.model.LabelledChain` plus joint coordinates.

    ``at[(u, v)]`` is the drawn position of the joint between links ``u`` and
    ``v`` (of a gear pair: its pitch point); ``directions[(u, v)]`` the slide direction (rad) of a P joint,
    whose guide is ``guides[(u, v)]`` (default the lower-numbered link).
    Links are named ``"0"``, ``"1"``, ...; the ground is the link with role
    ``ground``; ``inputs`` lists driven joints as link pairs (default: the
    joint between the ground and each link with role ``input``).

    >>> from domes.model import LabelledChain
    >>> c = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={0: {"ground"}, 1: {"input"}})
    >>> m = from_labelled(c, {(0, 1): (0, 0), (1, 2): (1, 0), (2, 3): (3.5, 2.449), (0, 3): (3, 0)})
    >>> [j.name for j in m.joints], m.inputs[0].joint
    (['J0-1', 'J0-3', 'J1-2', 'J2-3'], 'J0-1')
    """
    def key(pair):
        return (min(pair), max(pair))

    at = {key(k): v for k, v in at.items()}
    directions = {key(k): v for k, v in (directions or {}).items()}
    guides = {key(k): v for k, v in (guides or {}).items()}
    grounds = chain.links_with_role("ground")
    if len(grounds) != 1:
        raise InputError(f"labelled chain: needs exactly one link with role 'ground', found {grounds}")
    joints, gears = [], []
    for (u, v), t in zip(chain.edges, chain.joint_types):
        jname = f"J{u}-{v}"
        if (u, v) not in at:
            raise InputError(f"labelled chain: no coordinates for joint {u}-{v} (at[({u}, {v})])")
        xy = tuple(float(c) for c in at[(u, v)])
        if t == "P":
            if (u, v) not in directions:
                raise InputError(f"labelled chain: P joint {u}-{v} needs a slide direction (directions[({u}, {v})])")
            g = guides.get((u, v), u)
            if g not in (u, v):
                raise InputError(f"labelled chain: guide {g} of joint {u}-{v} is not one of its links")
            joints.append(Joint(jname, "P", (str(g), str(v if g == u else u)), xy, float(directions[(u, v)])))
        elif t == "R":
            joints.append(Joint(jname, "R", (str(u), str(v)), xy))
        elif t == "G":
            gears.append(GearPair(jname, (str(u), str(v)), xy))  # ``at`` is the pitch point
        else:
            raise InputError(f"labelled chain: joint {u}-{v} has type {t!r}; the planar kinematics backend takes "
                             "R, P and gear (G) joints (model a cylinder 'H' as two links joined by a P joint)")
    if inputs is None:
        g = grounds[0]
        inputs = []
        for k in chain.links_with_role("input"):
            if (min(g, k), max(g, k)) not in chain.edges:
                raise InputError(f"labelled chain: input link {k} is not jointed to the ground {g}; name the driven joint")
            inputs.append((g, k))
    ins = [Input(f"J{min(p)}-{max(p)}") for p in inputs]
    return Mechanism.build(name, [str(i) for i in range(chain.n)], str(grounds[0]), joints, ins, tuple(points),
                           gears=gears)
