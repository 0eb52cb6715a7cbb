"""What a mechanism weighs and what acts on it: mass properties, external loads, springs and dampers, gravity.

A mechanism file may give, per link, its ``mass``, the drawn-pose position
of its centre of mass (``centre``) and its moment of inertia about it
(``inertia``); external ``loads`` (a force at a point of a link, or a
torque on it), ``springs`` between two named joints or points (rate, free
length, damping: a shock absorber), and ``gravity``. Everything defaults to
nothing, so a file without them is what it was: a kinematic mechanism.
Units are the user's, consistent (SI: kg, m, kg·m², N, N/m, N·s/m, m/s²).

>>> model = MassModel.from_dict({"gravity": [0, -9.81],
...     "springs": [{"name": "shock", "between": ["A", "C"], "rate": 2e4, "free_length": 0.3}]},
...     {"crank": {"mass": 1.5, "centre": [0.5, 0], "inertia": 0.01}}, "<file>")
>>> model.mass_of("crank").mass, model.mass_of("frame").mass, model.springs[0].rate
(1.5, 0.0, 20000.0)
>>> model.to_dict()["gravity"]
[0.0, -9.81]
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field
from typing import Mapping

from domes.errors import InputError
from domes.model.fields import check_keys as _keys
from domes.model.fields import read_list as _list
from domes.model.fields import read_number as _finite
from domes.model.fields import read_xy as _xy

Point2 = tuple[float, float]


@dataclass(frozen=True)
class LinkMass:
    """A link's mass, centre of mass (drawn pose) and moment of inertia about the centre."""

    link: str
    mass: float = 0.0
    centre: Point2 | None = None
    inertia: float = 0.0


@dataclass(frozen=True)
class Load:
    """An external load on ``link``: a ``force`` at the drawn-pose point ``at`` (it turns with the link, its
    direction stays), and/or a ``torque`` (counter-clockwise positive)."""

    name: str
    link: str
    force: Point2 = (0.0, 0.0)
    at: Point2 | None = None
    torque: float = 0.0


@dataclass(frozen=True)
class Spring:
    """A spring and damper between two named joints or points: ``rate`` (force per length), ``free_length``
    (``None``: the drawn length, no force there), ``damping`` (force per speed), ``preload`` (force at the free
    length, pushing the ends apart when positive)."""

    name: str
    between: tuple[str, str]
    rate: float = 0.0
    free_length: float | None = None
    damping: float = 0.0
    preload: float = 0.0


@dataclass(frozen=True)
class MassModel:
    """The mass properties, loads, springs and gravity of one mechanism (all empty by default)."""

    masses: tuple[LinkMass, ...] = ()
    loads: tuple[Load, ...] = ()
    springs: tuple[Spring, ...] = ()
    gravity: Point2 = (0.0, 0.0)
    _by_link: dict = field(default=None, init=False, repr=False, compare=False)

    @property
    def empty(self) -> bool:
        return not (self.masses or self.loads or self.springs or any(self.gravity))

    def mass_of(self, link: str) -> LinkMass:
        """The link's mass properties (a massless link when none are given)."""
        if self._by_link is None:
            object.__setattr__(self, "_by_link", {m.link: m for m in self.masses})
        return self._by_link.get(link, LinkMass(link))

    def check(self, links, places: Mapping[str, str], where: str = "") -> None:
        """Check the model against the mechanism's ``links`` and ``places`` (joint or point name -> a link)."""
        for m in self.masses:
            if m.link not in links:
                raise InputError(f"{where}mass of {m.link!r}: not one of the links {list(links)}")
        for load in self.loads:
            if load.link not in links:
                raise InputError(f"{where}load {load.name!r}: link {load.link!r} is not one of the links")
            if any(load.force) and load.at is None:
                raise InputError(f"{where}load {load.name!r}: a force needs the point it acts at ('at')")
        names = [x.name for x in self.loads] + [s.name for s in self.springs]
        twice = sorted(n for n, count in Counter(names).items() if count > 1)
        if twice:
            raise InputError(f"{where}loads and springs: names {twice} are used twice")
        for s in self.springs:
            for end in s.between:
                if end not in places:
                    raise InputError(f"{where}spring {s.name!r}: {end!r} is not a joint or point "
                                     f"(known: {sorted(places)})")
            if s.between[0] == s.between[1]:
                raise InputError(f"{where}spring {s.name!r}: its two ends are the same place {s.between[0]!r}")

    @classmethod
    def from_dict(cls, data: Mapping, link_items: Mapping[str, Mapping], source: str) -> "MassModel":
        """The model of a mechanism file: its top-level ``gravity``, ``loads``, ``springs``, and the ``mass``,
        ``centre``, ``inertia`` keys of its link items (``link_items``: link name -> item)."""
        masses = []
        for link, item in link_items.items():
            where = f"{source}: link {link!r}"
            if not any(k in item for k in ("mass", "centre", "inertia")):
                continue
            mass = _nonnegative(item.get("mass", 0.0), f"{where}.mass")
            inertia = _nonnegative(item.get("inertia", 0.0), f"{where}.inertia")
            centre = _xy(item["centre"], f"{where}.centre") if "centre" in item else None
            if mass > 0 and centre is None:
                raise InputError(f"{where}: a link with a mass needs its centre of mass ('centre': [x, y])")
            masses.append(LinkMass(link, mass, centre, inertia))
        gravity = _xy(data["gravity"], f"{source}: gravity") if "gravity" in data else (0.0, 0.0)
        loads = []
        for k, item in enumerate(_list(data.get("loads", []), f"{source}: loads")):
            where = f"{source}: loads[{k}]"
            _keys(item, {"name", "link", "force", "at", "torque"}, {"name", "link"}, where)
            if "force" not in item and "torque" not in item:
                raise InputError(f"{where}: give a force (with 'at') or a torque")
            loads.append(Load(str(item["name"]), str(item["link"]),
                              _xy(item["force"], f"{where}.force") if "force" in item else (0.0, 0.0),
                              _xy(item["at"], f"{where}.at") if "at" in item else None,
                              _finite(item.get("torque", 0.0), f"{where}.torque")))
        springs = []
        for k, item in enumerate(_list(data.get("springs", []), f"{source}: springs")):
            where = f"{source}: springs[{k}]"
            _keys(item, {"name", "between", "rate", "free_length", "damping", "preload"}, {"name", "between"}, where)
            ends = item["between"]
            if not (isinstance(ends, list) and len(ends) == 2 and all(isinstance(e, str) for e in ends)):
                raise InputError(f"{where}.between: expected two joint or point names, got {ends!r}")
            free = item.get("free_length")
            springs.append(Spring(str(item["name"]), (ends[0], ends[1]),
                                  _nonnegative(item.get("rate", 0.0), f"{where}.rate"),
                                  None if free is None else _positive(free, f"{where}.free_length"),
                                  _nonnegative(item.get("damping", 0.0), f"{where}.damping"),
                                  _finite(item.get("preload", 0.0), f"{where}.preload")))
        return cls(tuple(masses), tuple(loads), tuple(springs), gravity)

    def link_dict(self, link: str) -> dict:
        """The keys this model adds to a link's item in a file (empty for a massless link)."""
        m = next((m for m in self.masses if m.link == link), None)
        if m is None:
            return {}
        out: dict = {"mass": m.mass}
        if m.centre is not None:
            out["centre"] = list(m.centre)
        out["inertia"] = m.inertia
        return out

    def to_dict(self) -> dict:
        """The top-level keys of a file (gravity, loads, springs), only those given."""
        out: dict = {}
        if any(self.gravity):
            out["gravity"] = list(self.gravity)
        if self.loads:
            out["loads"] = [{"name": x.name, "link": x.link,
                             **({"force": list(x.force), "at": list(x.at)} if x.at is not None else {}),
                             **({"torque": x.torque} if x.torque else {})} for x in self.loads]
        if self.springs:
            out["springs"] = [{"name": s.name, "between": list(s.between), "rate": s.rate,
                               **({"free_length": s.free_length} if s.free_length is not None else {}),
                               "damping": s.damping, "preload": s.preload} for s in self.springs]
        return out


def _nonnegative(value, where: str) -> float:
    x = _finite(value, where)
    if x < 0:
        raise InputError(f"{where}: must be >= 0, got {value!r}")
    return x


def _positive(value, where: str) -> float:
    x = _finite(value, where)
    if x <= 0:
        raise InputError(f"{where}: must be > 0, got {value!r}")
    return x


__all__ = ["Load", "LinkMass", "MassModel", "Spring"]
