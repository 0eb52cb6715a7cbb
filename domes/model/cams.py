"""Cam pairs of a planar mechanism: a cam turning on a carrier drives a follower by its motion law or its profile.

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
:func:`domes.design.cam.design_cam`'s. ``at`` is the drawn contact point,
for drawing.

Or the pair is given by its cam's outline, a :class:`CamProfile` (points
and the follower's face, plain data): then ``L`` is the contact of the
follower with that outline, found by the kinematics backend
(:class:`domes.motion.camcontact.ProfileLaw`, which a ``CamProfile``
evaluates through).

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
from functools import cached_property
from typing import ClassVar

import numpy as np

from domes.errors import InputError

Point2 = tuple[float, float]

#: Follower kinds and faces a profile is followed with.
KINDS = ("translating", "oscillating")
FACES = ("knife", "roller", "flat")
#: The fewest and the most points a cam's profile takes.
MIN_POINTS = 16
MAX_POINTS = 1_000_000


def profile_points(points) -> np.ndarray:
    """A cam's outline ``points`` (x, y) as an array in counter-clockwise order, checked: at least
    :data:`MIN_POINTS` finite points going once round the cam's centre (the origin), in order.

    >>> import math
    >>> ring = [(math.cos(-k * math.pi / 10), math.sin(-k * math.pi / 10)) for k in range(20)]   # clockwise
    >>> P = profile_points(ring); round(float(P[1][1]), 6) > 0
    True
    """
    try:
        P = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError("a cam profile's points must be pairs of numbers (x, y)") from None
    if P.ndim != 2 or P.shape[1] != 2 or not MIN_POINTS <= len(P) <= MAX_POINTS:
        raise InputError(f"a cam profile needs {MIN_POINTS} to {MAX_POINTS:,} points (x, y), got an array of shape "
                         f"{P.shape}")
    if not np.all(np.isfinite(P)):
        raise InputError(f"a cam profile's points must be finite; point {int(np.flatnonzero(~np.isfinite(P).all(1))[0])}"
                         " is not")
    ang = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
    if ang[-1] < ang[0]:
        P, ang = P[::-1], ang[::-1]
    step = np.diff(ang)
    if np.any(np.hypot(P[:, 0], P[:, 1]) == 0) or np.any(step <= 0) \
            or not abs(ang[-1] - ang[0] - 2 * math.pi) < 2 * math.pi / len(P) * 1.5:
        bad = np.flatnonzero(step <= 0)
        at = f" (it turns back at point {int(bad[0]) + 1} of {len(P)})" if bad.size else ""
        raise InputError("the profile's points must go once round the cam's centre, in order (a star-shaped "
                         f"outline about the origin){at}")
    return P


@dataclass(frozen=True)
class Follower:
    """A follower: ``kind`` translating or oscillating, ``face`` knife, roller or flat.

    Translating: its axis is parallel to +y at ``offset`` from the cam's centre.
    Oscillating: its pivot at ``(pivot, 0)``; a knife or roller at ``arm``
    from the pivot; a flat face along the arm's line, ``face_offset`` from the
    pivot towards the cam. ``roller`` is the roller's radius.

    >>> Follower("oscillating", "roller", roller=8, pivot=100, arm=80).kind
    'oscillating'
    """

    kind: str
    face: str
    roller: float = 0.0
    offset: float = 0.0
    pivot: float = 0.0
    arm: float = 0.0
    face_offset: float = 0.0

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InputError(f"follower kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        if self.face not in FACES:
            raise InputError(f"follower face must be one of {', '.join(FACES)}, got {self.face!r}")
        for name in ("roller", "offset", "pivot", "arm", "face_offset"):
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and math.isfinite(v)):
                raise InputError(f"follower {name} must be a finite number, got {v!r}")
        if self.face == "roller" and not self.roller > 0:
            raise InputError(f"a roller follower needs a roller radius > 0, got {self.roller!r}")
        if self.face != "roller" and self.roller:
            raise InputError(f"a {self.face} follower has no roller (roller = {self.roller!r})")
        if self.kind == "oscillating":
            if not self.pivot > 0:
                raise InputError(f"an oscillating follower needs its pivot's distance from the cam > 0, got {self.pivot!r}")
            if self.face != "flat" and not self.arm > 0:
                raise InputError(f"an oscillating {self.face} follower needs an arm > 0, got {self.arm!r}")


@dataclass(frozen=True)
class CamProfile:
    """A cam's outline and its follower, as data: what a cam pair follows by contact instead of a law.

    ``points`` are the outline in the profile's frame as ``domes cam`` writes
    it, for its :class:`Follower`: the cam's centre at the origin; a
    translating follower's axis parallel to +y at x = ``offset``, rising
    towards +y; an oscillating follower's pivot at (``pivot``, 0), its arm
    (``arm`` to the knife edge or the roller's centre) on the +y side, rising
    as it turns away from the cam.
    ``direction`` is the way the cam was designed to turn (1
    counter-clockwise, −1 clockwise: the frame is seen mirrored). Like a law
    it has ``periodic``, ``period`` and :meth:`evaluate`, which the
    kinematics backend computes (:class:`domes.motion.camcontact.ProfileLaw`):
    the follower's lift (a length, or a counter-clockwise angle as the
    mechanism sees it) and two derivatives at cam angles ``θ``.
    ``base_radius`` only sets the lift's zero (default: the outline's
    nearest point to the centre).

    >>> import math
    >>> ring = [(10 * math.cos(k * math.pi / 18), 10 * math.sin(k * math.pi / 18)) for k in range(36)]
    >>> CamProfile(tuple(ring), Follower("translating", "roller", roller=2.0)).follower.face
    'roller'
    """

    points: tuple[Point2, ...]
    follower: Follower
    base_radius: float | None = None
    direction: int = 1

    periodic: ClassVar[bool] = True
    period: ClassVar[float] = 2 * math.pi

    def __post_init__(self):
        f = self.follower
        if not isinstance(f, Follower):
            raise InputError(f"a cam profile's follower must be a Follower, got {type(f).__name__}")
        if f.kind == "oscillating" and f.face == "flat":
            raise InputError("an oscillating flat face is not followed on a given profile (knife or roller only)")
        if self.base_radius is not None and (isinstance(self.base_radius, bool) or not (
                isinstance(self.base_radius, (int, float)) and math.isfinite(self.base_radius))):
            raise InputError(f"the base radius must be a finite number, got {self.base_radius!r}")
        if self.base_radius is not None and not self.base_radius > 0:
            raise InputError(f"the base radius must be > 0, got {self.base_radius!r}")
        if self.direction not in (1, -1):
            raise InputError(f"direction must be 1 (counter-clockwise) or -1 (clockwise), got {self.direction!r}")
        profile_points(self.points)
        object.__setattr__(self, "points", tuple((float(x), float(y)) for x, y in self.points))   # as given, hashable

    @cached_property
    def law(self):
        """The backend's law for this profile (built once)."""
        if _PROFILE_LAW is None:
            raise RuntimeError("a cam profile is followed by the kinematics backend: import domes.motion.camcontact")
        return _PROFILE_LAW(self)

    def evaluate(self, x, order: int = 2) -> tuple[np.ndarray, ...]:
        """The follower's lift and its derivatives at cam angles ``x`` (``order`` 0 to 2), by contact."""
        return self.law.evaluate(x, order)


_PROFILE_LAW = None


def use_profile_law(factory) -> None:
    """Set the factory that turns a :class:`CamProfile` into a law (the kinematics backend sets it on import)."""
    global _PROFILE_LAW
    _PROFILE_LAW = factory


@dataclass(frozen=True)
class CamPair:
    """A cam (``links[0]``) driving a follower (``links[1]``) by the periodic motion law ``law`` (a
    :class:`~domes.model.laws.Motion`, or a :class:`CamProfile` followed by contact)."""

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
    if isinstance(pair.law, CamProfile):
        _check_profile(pair, where, pivot, held)
    if held.kind == "P":
        return Contact(pair, "translating", cam, follower, c, pivot.name, held.name,
                       1.0 if held.links[0] == c else -1.0)
    return Contact(pair, "oscillating", cam, follower, c, pivot.name, held.name)


def _check_profile(pair: CamPair, where: str, pivot, held) -> None:
    """A profile's follower agrees with the mechanism: its kind, its pivot's distance, the arm's side."""
    p = pair.law.follower
    kind = "translating" if held.kind == "P" else "oscillating"
    if p.kind != kind:
        raise InputError(f"{where}: the profile's follower is {p.kind} but the follower's joint {held.name!r} makes it "
                         f"{kind}")
    if kind == "translating":
        return
    d = math.dist(pivot.at, held.at)
    if abs(d - p.pivot) > 1e-9 * max(1.0, d):
        raise InputError(f"{where}: the profile's follower pivot is {p.pivot:.12g} from the cam's centre, the "
                         f"mechanism's joints {pivot.name!r} and {held.name!r} are {d:.12g} apart")
    (ox, oy), (px, py) = pivot.at, held.at
    side = (px - ox) * (pair.at[1] - oy) - (py - oy) * (pair.at[0] - ox)
    turn = pair.law.direction
    if side * turn <= 0:
        want = "left" if turn == 1 else "right"
        raise InputError(f"{where}: the drawn contact 'at' {list(pair.at)} must lie on the {want} of the line from the "
                         f"cam's centre {pivot.name!r} to the follower's pivot {held.name!r}, where a profile designed "
                         f"to turn {'counter-clockwise' if turn == 1 else 'clockwise'} puts the arm")


__all__ = ["CamPair", "CamProfile", "Contact", "Follower", "profile_points", "use_profile_law"]
