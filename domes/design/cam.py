"""Disc cams: a profile from a follower's motion law, checked for pressure angle and undercut (issue 26).

The cam turns about the origin at constant speed (``θ``, counter-clockwise
when ``direction`` is +1); the follower's displacement ``s(θ)`` is a
:class:`~domes.model.laws.Motion` (a length for a translating follower, an
angle in rad for an oscillating one). The profile is the cam's outline in
its own frame, found by kinematic inversion: the follower's reference point
(the knife edge or the roller's centre) traces the *pitch curve*
``P(θ) = R(−θ) C(θ)``; a roller's profile is the pitch curve offset inward
by the roller's radius; a flat face's profile is the envelope of the face's
lines. All in closed form from ``s, s', s''``:

- pressure angle: between the common normal at contact and the direction
  the follower's contact point moves (0 is ideal; the usual limit is 30° for
  translating followers, 45° for oscillating ones);
- radius of curvature of the profile: a roller needs the convex pitch
  curve's radius above its own (else the profile folds over itself:
  undercut); a flat face needs ``ρ > 0`` everywhere (``r_b + s + s''`` for a
  translating one).

:func:`design_cam` refuses an undercut cam with the radius and where it
occurs. :func:`follow` is the converse, a cam pair in the backend: the
follower's displacement, velocity and acceleration from a profile given as
points (any cam), by the contact condition alone; it and :class:`Follower`
live in :mod:`domes.motion.camcontact` (with :class:`ProfileLaw`, what a
mechanism's cam pair given by its profile moves by) and are re-exported here.

>>> from domes.model.laws import Motion
>>> law = Motion.cam([("cycloidal", 120, 20), ("dwell", 60), ("3-4-5", 120, -20), ("dwell", 60)])
>>> cam = design_cam(law, Follower("translating", "roller", roller=10, offset=5), base_radius=40)
>>> round(cam.max_pressure_angle_deg, 2), cam.undercut
(21.28, False)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.motion.camcontact import (
    _J,
    COARSE,
    FACES,
    KINDS,
    Follower,
    FollowerMotion,
    ProfileLaw,
    _apply,
    _rot,
    follow,
    profile_curve,
)
from domes.results import Result, Status

#: Profile points per turn of the cam (the table the design reports and writes).
POINTS = 720
#: The most profile points a design takes (a million: far finer than any cam is cut).
MAX_POINTS = 1_000_000


@dataclass(frozen=True, eq=False)
class Cam(Result):
    """A designed cam: the law, follower, base radius and the profile's table and checks.

    ``theta`` (rad), ``profile`` and ``pitch`` (points in the cam's frame),
    ``contact`` (the contact point in the fixed frame), ``pressure_deg`` and
    ``radius`` (the profile's radius of curvature, positive where convex) at
    every sample.
    """

    motion: object
    follower: Follower
    base_radius: float
    direction: int
    theta: np.ndarray
    pitch: np.ndarray
    profile: np.ndarray
    contact: np.ndarray
    pressure_deg: np.ndarray
    radius: np.ndarray
    pitch_radius: np.ndarray
    max_pressure_deg: float = 30.0

    @property
    def max_pressure_angle_deg(self) -> float:
        return float(np.max(self.pressure_deg))

    @property
    def min_radius(self) -> float:
        """The smallest radius of curvature of the convex parts of the profile."""
        convex = self.radius[self.radius > 0]
        return float(np.min(convex)) if convex.size else float("nan")

    @property
    def undercut(self) -> bool:
        """True where the profile folds over itself (a roller larger than the convex pitch curve's radius, a
        flat face over a concave envelope)."""
        return bool(self.problems_at("undercut").size)

    def pitch_at(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The pitch curve (a point follower's reference point in the cam's frame) and its first two derivatives
        at the design angles ``theta``, in closed form."""
        theta = np.asarray(theta, dtype=float)
        s, s1, s2 = _law(self.motion, theta)
        C, C1, C2, _ = _point_follower(self.follower, self.base_radius, s, s1, s2)
        return _inverted(C, C1, C2, theta, self.direction)

    def problems_at(self, what: str) -> np.ndarray:
        """Indices of the samples where ``what`` (``undercut`` or ``pressure``) fails."""
        if what == "pressure":
            return np.flatnonzero(self.pressure_deg > self.max_pressure_deg)
        if self.follower.face == "roller":
            return np.flatnonzero((self.pitch_radius > 0) & (self.pitch_radius <= self.follower.roller))
        if self.follower.face == "flat":
            return np.flatnonzero(self.radius <= 0)
        return np.array([], dtype=int)

    #: A designed cam is complete; a pressure angle above the limit is a warning (:attr:`warnings`).
    status = Status.COMPLETE

    @property
    def warnings(self) -> tuple[str, ...]:
        bad = self.problems_at("pressure")
        if not bad.size:
            return ()
        deg = np.degrees(self.theta[bad])
        return (f"pressure angle above {self.max_pressure_deg:g}° from θ = {deg.min():.1f}° to {deg.max():.1f}° "
                f"({bad.size} of {self.theta.size} samples; largest {self.max_pressure_angle_deg:.2f}°): the follower "
                "may jam; use a larger base radius, a longer stroke angle or an offset",)

    @property
    def message(self) -> str:
        f = self.follower
        worst = int(np.argmax(self.pressure_deg))
        return (f"{self.status}: {f.kind} {f.face} follower, base radius {self.base_radius:g}; largest pressure "
                f"angle {self.pressure_deg[worst]:.2f}° at θ = {math.degrees(self.theta[worst]):.1f}° (limit "
                f"{self.max_pressure_deg:g}°{', exceeded' if self.warnings else ''}); smallest radius of curvature "
                f"{self.min_radius:.4g}")


def _law(motion, theta, order=2):
    s = motion.evaluate(theta, order)
    return [np.asarray(v, dtype=float) for v in s]


def _point_follower(f: Follower, base: float, s, s1, s2):
    """The reference point ``C`` and its first two derivatives in the fixed frame, and its unit velocity
    direction (positive ``s``)."""
    rp = base + f.roller                          # the prime circle's radius
    if f.kind == "translating":
        if abs(f.offset) >= rp:
            raise InputError(f"the follower's offset {f.offset:g} must be smaller than the prime circle's radius "
                             f"{rp:g} (base radius + roller)")
        y0 = math.sqrt(rp * rp - f.offset * f.offset)
        C = np.stack([np.full_like(s, f.offset), y0 + s], -1)
        C1 = np.stack([np.zeros_like(s), s1], -1)
        C2 = np.stack([np.zeros_like(s), s2], -1)
        up = np.stack([np.zeros_like(s), np.ones_like(s)], -1)
        return C, C1, C2, up
    d, arm = f.pivot, f.arm
    cos0 = (d * d + arm * arm - rp * rp) / (2 * d * arm)
    if not -1 < cos0 < 1:
        raise InputError(f"an arm of {arm:g} about a pivot {d:g} from the cam cannot reach the prime circle "
                         f"(radius {rp:g}): |pivot − arm| < base radius + roller < pivot + arm is needed")
    psi = math.acos(cos0) + s
    beta = math.pi - psi
    cb, sb = np.cos(beta), np.sin(beta)
    C = np.stack([d + arm * cb, arm * sb], -1)
    tang = np.stack([sb, -cb], -1)                # dC/dψ / arm
    C1 = arm * s1[..., None] * tang
    C2 = arm * s2[..., None] * tang - arm * (s1 * s1)[..., None] * np.stack([cb, sb], -1)
    return C, C1, C2, tang


def _angle(u, v) -> np.ndarray:
    """The angle (°, 0 to 90) between the lines of ``u`` and ``v``, accurate near 0 (atan2, not acos)."""
    dot = np.abs(np.einsum("...i,...i", u, v))
    cross = np.abs(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])
    return np.degrees(np.arctan2(cross, dot))


def _inverted(C, C1, C2, theta, direction):
    """The point ``R(−δθ) C`` in the cam's frame and its first two derivatives in ``θ``."""
    R = _rot(-direction * theta)
    P = _apply(R, C)
    P1 = _apply(R, C1 - direction * _J(C))
    P2 = _apply(R, C2 - 2 * direction * _J(C1) - C)
    return P, P1, P2


def design_cam(motion, follower: Follower, base_radius: float, direction: int = 1, points: int = POINTS,
               max_pressure_deg: float | None = None) -> Cam:
    """The profile of a disc cam that gives ``follower`` the motion ``motion`` (see the module's docstring).

    Refuses an undercut cam (an InputError with the radius of curvature, the
    roller's and where). ``max_pressure_deg`` (default 30° translating, 45°
    oscillating) is the pressure angle above which the result warns.

    >>> from domes.model.laws import Motion
    >>> flat = design_cam(Motion.cam([("harmonic", 180, 10), ("harmonic", 180, -10)]), Follower("translating", "flat"), 20)
    >>> round(flat.min_radius, 9), round(float(flat.radius.max()), 9)     # an eccentric circle: r_b + h/2
    (25.0, 25.0)
    """
    if not (isinstance(base_radius, (int, float)) and math.isfinite(base_radius) and base_radius > 0):
        raise InputError(f"the base radius must be a number > 0, got {base_radius!r}")
    if direction not in (1, -1):
        raise InputError(f"direction must be 1 (counter-clockwise) or -1 (clockwise), got {direction!r}")
    if not (isinstance(points, int) and 16 <= points <= MAX_POINTS):
        raise InputError(f"points must be a whole number from 16 to {MAX_POINTS:,}, got {points!r}")
    if not getattr(motion, "periodic", False) or abs(motion.period - 2 * math.pi) > 1e-9:
        raise InputError("a cam's motion must be periodic over one turn (Motion.cam, or a periodic table over 2π)")
    limit = max_pressure_deg if max_pressure_deg is not None else (30.0 if follower.kind == "translating" else 45.0)
    theta = np.linspace(0.0, 2 * math.pi, points, endpoint=False)
    s, s1, s2 = _law(motion, theta)
    if follower.kind == "translating" and np.min(s) < -base_radius * (1 - 1e-12):
        raise InputError(f"the follower comes down to {np.min(s):g}, inside the cam's centre (base radius {base_radius:g})")
    if follower.face == "flat":
        cam = _flat(motion, follower, base_radius, direction, theta, s, s1, s2, limit)
    else:
        cam = _pointed(motion, follower, base_radius, direction, theta, s, s1, s2, limit)
    bad = cam.problems_at("undercut")
    if bad.size:
        k = int(bad[np.argmin(cam.pitch_radius[bad] if follower.face == "roller" else cam.radius[bad])])
        where = f"at θ = {math.degrees(theta[k]):.1f}°"
        if follower.face == "roller":
            raise InputError(f"undercut {where}: the pitch curve's radius of curvature {cam.pitch_radius[k]:.4g} is "
                             f"not larger than the roller's {follower.roller:g}; use a smaller roller, a larger base "
                             "radius or a gentler law")
        raise InputError(f"undercut {where}: the flat face's envelope has radius of curvature {cam.radius[k]:.4g} "
                         "(it must stay > 0); use a larger base radius or a gentler law")
    return cam


def _pointed(motion, f, base, direction, theta, s, s1, s2, limit) -> Cam:
    C, C1, C2, up = _point_follower(f, base, s, s1, s2)
    P, P1, P2 = _inverted(C, C1, C2, theta, direction)
    speed = np.linalg.norm(P1, axis=-1)
    T = P1 / speed[..., None]
    n = direction * _J(T)                                  # outward normal of the pitch curve (cam's frame)
    cross = P1[..., 0] * P2[..., 1] - P1[..., 1] * P2[..., 0]
    with np.errstate(divide="ignore"):
        rho = -direction * speed ** 3 / cross               # positive where convex
    profile = P - f.roller * n
    N = _apply(_rot(direction * theta), n)                  # the common normal in the fixed frame
    pressure = _angle(N, up)
    contact = C - f.roller * N
    return Cam(motion, f, float(base), direction, theta, P, profile, contact, pressure, rho - f.roller, rho,
               float(limit))


def _flat(motion, f, base, direction, theta, s, s1, s2, limit) -> Cam:
    """A flat face: the envelope of its lines ``n·X = c`` in the cam's frame, by the support function."""
    if f.kind == "translating":
        c, c1, c2 = base + s, s1, s2
        ang = np.full_like(s, math.pi / 2)                  # the face's normal points along +y
        a1, a2 = np.zeros_like(s), np.zeros_like(s)
    else:
        d, e = f.pivot, f.face_offset
        sin0 = (base + e) / d
        if not 0 < sin0 < 1:
            raise InputError(f"a flat face {e:g} from a pivot {d:g} from the cam cannot touch the base circle "
                             f"(radius {base:g}): 0 < base radius + face offset < pivot distance is needed")
        psi = math.asin(sin0) + s
        c = d * np.sin(psi) - e
        c1 = d * np.cos(psi) * s1
        c2 = d * (np.cos(psi) * s2 - np.sin(psi) * s1 * s1)
        ang = math.pi / 2 - psi                             # normal (sin ψ, cos ψ)
        a1, a2 = -s1, -s2
    phi1 = a1 - direction                                   # the normal's angle in the cam's frame: ang − δθ
    if np.any(np.abs(phi1) < 1e-12):
        k = int(np.argmin(np.abs(phi1)))
        raise InputError(f"the flat face turns with the cam at θ = {math.degrees(theta[k]):.1f}°: no envelope")
    dc = c1 / phi1                                          # dc/dφ
    rho = c + (c2 * phi1 - c1 * a2) / phi1 ** 3             # p + p'' of the support function
    nf = np.stack([np.cos(ang), np.sin(ang)], -1) * np.ones_like(s)[..., None]
    contact = c[..., None] * nf + dc[..., None] * _J(nf)    # fixed frame
    profile = _apply(_rot(-direction * theta), contact)
    if f.kind == "translating":
        v = np.stack([np.zeros_like(s), np.ones_like(s)], -1)
    else:
        rel = contact - np.array([f.pivot, 0.0])
        v = -_J(rel) / np.linalg.norm(rel, axis=-1)[..., None]
    pressure = _angle(nf, v)
    return Cam(motion, f, float(base), direction, theta, profile, profile, contact, pressure, rho, rho, float(limit))


__all__ = ["COARSE", "FACES", "KINDS", "MAX_POINTS", "POINTS", "Cam", "Follower", "FollowerMotion", "ProfileLaw",
           "design_cam", "follow", "profile_curve"]
