"""Cam pairs of a planar mechanism: a cam turning on a carrier drives a follower by its motion law.

A cam pair joins a *cam* (``links[0]``, jointed to the carrier by a
revolute) and a *follower* (``links[1]``): translating when it slides on the
carrier by a P joint, oscillating when it turns on it by a revolute. The
pair is given by the follower's motion law over one turn of the cam
relative to the carrier (:meth:`domes.model.laws.Motion.cam`): the
follower's displacement from the drawn pose is ``L(φ + Δθ) − L(φ)``, a
length along the slide (in its direction, from the guide's side) or an
angle (counter-clockwise), where ``Δθ`` is the cam's turn relative to the
carrier since the drawn pose and ``φ`` (``phase``) the cam's angle in the
law at the drawn pose. This is the cam as designed for its law (the pitch
curve's contact, exact); its profile, pressure angle and undercut are
:func:`domes.design.cam.design_cam`'s, and a given profile's contact
:func:`domes.design.cam.follow`'s. ``at`` is the drawn contact point, for
drawing.

>>> from domes.model.mechanism import Joint, Input, Mechanism
>>> from domes.model.laws import Motion
>>> law = Motion.cam([("cycloidal", 180, 0.5), ("cycloidal", 180, -0.5)])
>>> m = Mechanism.build("cam", ["frame", "cam", "follower"], "frame",
...     [Joint("A", "R", ("frame", "cam"), (0.0, 0.0)), Joint("S", "P", ("frame", "follower"), (0.0, 2.0), 1.5708)],
...     [Input("A")], cams=[CamPair("K", ("cam", "follower"), (0.0, 1.8), law)])
>>> m.cams[0].contact(m).kind, m.dof
('translating', 1)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from domes.errors import InputError

Point2 = tuple[float, float]


@dataclass(frozen=True)
class CamPair:
    """A cam (``links[0]``) driving a follower (``links[1]``) by the periodic motion law ``law``."""

    name: str
    links: tuple[str, str]
    at: Point2
    law: object
    phase: float = 0.0
    carrier: str | None = None

    def contact(self, mech) -> "Contact":
        """The pair's carrier, follower kind and joints in ``mech`` (checked)."""
        return _contact(self, mech)


@dataclass(frozen=True)
class Contact:
    """A resolved cam pair: ``kind`` is ``"translating"`` or ``"oscillating"``; ``joint`` the follower's joint on
    the carrier; ``sign`` +1 when the carrier is the P joint's guide (the slide grows with the law)."""

    pair: CamPair
    kind: str
    cam: str
    follower: str
    carrier: str
    pivot: str
    joint: str
    sign: float = 1.0


def _between(mech, a: str, b: str, kind: str):
    return next((j for j in mech.joints if j.kind == kind and set(j.links) == {a, b}), None)


def _contact(pair: CamPair, mech) -> Contact:
    where = f"{mech.source + ': ' if mech.source else ''}cam pair {pair.name!r}"
    cam, follower = pair.links
    if not (getattr(pair.law, "periodic", False) and abs(pair.law.period - 2 * math.pi) < 1e-9):
        raise InputError(f"{where}: the law must be periodic over one turn of the cam (Motion.cam)")
    names = [pair.carrier] if pair.carrier else [x for x in mech.links if x not in pair.links]
    found = []
    for c in names:
        pivot = _between(mech, cam, c, "R")
        held = _between(mech, follower, c, "P") or _between(mech, follower, c, "R")
        if pivot is not None and held is not None:
            found.append((c, pivot, held))
    if not found:
        raise InputError(f"{where}: the cam {cam!r} and the follower {follower!r} need a common carrier: a link the "
                         "cam turns on by a revolute and the follower slides (P) or turns (R) on"
                         + (f"; {pair.carrier!r} is not one" if pair.carrier else ""))
    if len(found) > 1:
        raise InputError(f"{where}: links {[f[0] for f in found]} could each carry the pair; name one with 'carrier'")
    c, pivot, held = found[0]
    if held.kind == "P":
        return Contact(pair, "translating", cam, follower, c, pivot.name, held.name,
                       1.0 if held.links[0] == c else -1.0)
    return Contact(pair, "oscillating", cam, follower, c, pivot.name, held.name)


__all__ = ["CamPair", "Contact"]
