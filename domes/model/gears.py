"""Gear pairs of a planar mechanism: external, internal and rack-and-pinion meshes.

A gear pair joins two links ``a`` and ``b`` by a higher pair that rolls
their pitch curves on each other (two freedoms, one constraint). Its data is
its *pitch point* ``at`` in the drawn pose, where the pitch circles touch:
the radii and the kind follow from where it lies. Both gears turn on one
*carrier* ``c``: each is joined to ``c`` by a revolute (or shares a hinge
with it), or, for a rack, slides on ``c`` by a prismatic joint. Relative to
the carrier the pair keeps a constant ratio (Willis' formula)::

    ω_b − ω_c = −s·(r_a / r_b)·(ω_a − ω_c)     s = +1 external, −1 internal
    ṡ = σ·m·(ω_a − ω_c)                          rack b on carrier c

with ``m = (P − O_a) × u`` (pitch point from the pinion's centre, crossed
with the slide direction) and ``σ = +1`` when the carrier is the rack's
guide. ``teeth = (z_a, z_b)`` makes the ratio exact (``r_a/r_b = z_a/z_b``)
and is checked against the drawn radii.

>>> from domes.model.mechanism import Joint, Input, Mechanism
>>> m = Mechanism.build("pair", ["frame", "pinion", "wheel"], "frame",
...     [Joint("A", "R", ("frame", "pinion"), (0.0, 0.0)), Joint("B", "R", ("frame", "wheel"), (3.0, 0.0))],
...     [Input("A")], gears=[GearPair("M", ("pinion", "wheel"), (1.0, 0.0), teeth=(20, 40))])
>>> mesh = m.gears[0].mesh(m)
>>> mesh.kind, mesh.carrier, mesh.ratio, m.dof
('external', 'frame', 0.5, 1)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from domes.errors import InputError

Point2 = tuple[float, float]
#: How far (relative to the mechanism's size) a pitch point may lie off the line of centres.
PITCH_SLACK = 1e-9
#: How far a drawn radius ratio may differ (relative) from the ratio of the teeth.
TEETH_SLACK = 1e-6


@dataclass(frozen=True)
class GearPair:
    """A gear (or rack-and-pinion) pair between ``links`` meshing at the pitch point ``at``."""

    name: str
    links: tuple[str, str]
    at: Point2
    teeth: tuple[int, int] | None = None
    carrier: str | None = None

    def mesh(self, mech) -> "Mesh":
        """The pair's kind, carrier, centres, radii and ratio in ``mech`` (checked)."""
        return _mesh(self, mech)


@dataclass(frozen=True)
class Mesh:
    """A resolved gear pair: ``kind`` is ``"external"``, ``"internal"`` or ``"rack"``.

    For gears ``ratio = r_a/r_b`` and the relation is
    ``Δ_b − Δ_c = −sign·ratio·(Δ_a − Δ_c)``; for a rack (``b`` the rack,
    ``a`` the pinion) ``s − s0 = sign·ratio·(Δ_a − Δ_c)`` along ``slide``.
    ``pivots`` names the revolutes at the centres (``None`` for a rack).
    """

    pair: GearPair
    kind: str
    a: str
    b: str
    carrier: str
    centres: tuple[Point2, Point2 | None]
    radii: tuple[float, float]
    ratio: float
    sign: float
    slide: str = ""
    pivots: tuple[str, str | None] = ("", None)


def read_teeth(value, where: str) -> tuple[int, int]:
    """Two positive whole numbers of teeth."""
    if not isinstance(value, list) or len(value) != 2 or not all(
            isinstance(z, int) and not isinstance(z, bool) and z > 0 for z in value):
        raise InputError(f"{where}: teeth must be two positive whole numbers [z_a, z_b], got {value!r}")
    return int(value[0]), int(value[1])


def _pivots(mech, link: str) -> list:
    return [j for j in mech.joints if j.kind == "R" and link in j.links]


def _pivot_on(mech, gear: str, carrier: str):
    """The revolute ``gear`` turns on relative to ``carrier``: theirs, or one of a hinge they share; else None."""
    for j in _pivots(mech, gear):
        if carrier in j.links:
            return j
    for j in _pivots(mech, gear):
        other = j.links[1] if j.links[0] == gear else j.links[0]
        for k in _pivots(mech, carrier):
            if other in k.links and k.at == j.at:
                return j
    return None


def _centre_on(mech, gear: str, carrier: str):
    j = _pivot_on(mech, gear, carrier)
    return None if j is None else j.at


def _slide_on(mech, rack: str, carrier: str):
    for j in mech.joints:
        if j.kind == "P" and set(j.links) == {rack, carrier}:
            return j
    return None


def _carriers(mech, pair: GearPair) -> list[tuple[str, str, str]]:
    """``(carrier, pinion, rack-or-gear)`` choices: links holding both gears' axes (or the rack's slide)."""
    a, b = pair.links
    found = []
    names = [pair.carrier] if pair.carrier else [x for x in mech.links if x not in pair.links]
    for c in names:
        ca, cb = _centre_on(mech, a, c), _centre_on(mech, b, c)
        if ca is not None and cb is not None:
            found.append((c, a, b))
        elif ca is not None and _slide_on(mech, b, c) is not None:
            found.append((c, a, b))
        elif cb is not None and _slide_on(mech, a, c) is not None:
            found.append((c, b, a))
    return found


def _mesh(pair: GearPair, mech) -> Mesh:
    where = f"{mech.source + ': ' if mech.source else ''}gear pair {pair.name!r}"
    found = _carriers(mech, pair)
    if pair.carrier and not found:
        raise InputError(f"{where}: carrier {pair.carrier!r} holds the axes of {list(pair.links)} neither by revolutes "
                         "nor by a shared hinge (nor the rack by a P joint)")
    if not found:
        raise InputError(f"{where}: gears {list(pair.links)} need a common carrier: a link holding both axes by "
                         "revolute joints (or the rack by a P joint); join them to one link or name it with 'carrier'")
    if len(found) > 1:
        raise InputError(f"{where}: links {[f[0] for f in found]} could each carry the pair; name one with 'carrier'")
    c, a, b = found[0]
    size = mech.size
    P = pair.at
    Oa = _centre_on(mech, a, c)
    ra = math.dist(P, Oa)
    if ra <= PITCH_SLACK * size:
        raise InputError(f"{where}: the pitch point {P} is at the centre of {a!r}; put it where the pitch circles touch")
    slide = _slide_on(mech, b, c)
    if slide is not None and _centre_on(mech, b, c) is None:
        if pair.teeth is not None:
            raise InputError(f"{where}: a rack has no number of teeth per turn; leave out 'teeth' (the pitch point "
                             "gives the pinion's radius)")
        u = (math.cos(slide.direction), math.sin(slide.direction))
        rx, ry = P[0] - Oa[0], P[1] - Oa[1]
        off = rx * u[0] + ry * u[1]
        if abs(off) > PITCH_SLACK * size:
            raise InputError(f"{where}: the pitch point must be the foot of the perpendicular from the pinion's centre "
                             f"{Oa} to the rack's slide direction; it is {off:.3g} along the slide from it")
        m = rx * u[1] - ry * u[0]
        sign = 1.0 if slide.links[0] == c else -1.0
        return Mesh(pair, "rack", a, b, c, (Oa, None), (ra, math.inf), m, sign, slide.name,
                    (_pivot_on(mech, a, c).name, None))
    Ob = _centre_on(mech, b, c)
    rb = math.dist(P, Ob)
    d = math.dist(Oa, Ob)
    if rb <= PITCH_SLACK * size or d <= PITCH_SLACK * size:
        raise InputError(f"{where}: the centres of {a!r} and {b!r} and the pitch point must be three distinct points")
    off = abs((Ob[0] - Oa[0]) * (P[1] - Oa[1]) - (Ob[1] - Oa[1]) * (P[0] - Oa[0])) / d
    if off > PITCH_SLACK * size:
        raise InputError(f"{where}: the pitch point {P} is {off:.3g} off the line of centres {Oa}–{Ob}")
    external = abs(ra + rb - d) <= abs(abs(ra - rb) - d)
    ratio = ra / rb
    if pair.teeth is not None:
        za, zb = pair.teeth
        if abs(ratio - za / zb) > TEETH_SLACK * za / zb:
            raise InputError(f"{where}: teeth {za}:{zb} give the ratio {za / zb:.9g} but the drawn radii "
                             f"{ra:.9g} and {rb:.9g} give {ratio:.9g}; move the pitch point")
        ratio = za / zb
    return Mesh(pair, "external" if external else "internal", a, b, c, (Oa, Ob), (ra, rb), ratio,
                1.0 if external else -1.0, "", (_pivot_on(mech, a, c).name, _pivot_on(mech, b, c).name))


__all__ = ["GearPair", "Mesh", "read_teeth"]
