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
points (any cam), by the contact condition alone.

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
from domes.results import Result, Status

KINDS = ("translating", "oscillating")
FACES = ("knife", "roller", "flat")
#: Profile points per turn of the cam (the table the design reports and writes).
POINTS = 720
#: The most profile points a design takes (a million: far finer than any cam is cut).
MAX_POINTS = 1_000_000


def _rot(a):
    """Rotation matrices for the angles ``a`` (shape ``(..., 2, 2)``)."""
    a = np.asarray(a, dtype=float)
    c, s = np.cos(a), np.sin(a)
    return np.stack([np.stack([c, -s], -1), np.stack([s, c], -1)], -2)


def _apply(R, v):
    return np.einsum("...ij,...j->...i", R, v)


def _J(v):
    """``v`` turned by +90°."""
    return np.stack([-v[..., 1], v[..., 0]], -1)


@dataclass(frozen=True)
class Follower:
    """A follower: ``kind`` translating or oscillating, ``face`` knife, roller or flat.

    Translating: its axis is parallel to +y at ``offset`` from the cam's centre.
    Oscillating: its pivot at ``(pivot, 0)``; a knife or roller at ``arm``
    from the pivot; a flat face along the arm's line, ``face_offset`` from the
    pivot towards the cam. ``roller`` is the roller's radius.
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


# -- the converse: a follower on a given profile --------------------------------------------------------------

@dataclass(frozen=True)
class FollowerMotion:
    """The follower's displacement ``s`` and its derivatives in the cam's angle, and the contact residual."""

    theta: np.ndarray
    s: np.ndarray
    ds: np.ndarray
    dds: np.ndarray
    residual: float


def profile_curve(points):
    """A closed curve through the profile ``points`` (counter-clockwise or not): a periodic quintic spline in the
    points' angle, with its first three derivatives."""
    from scipy.interpolate import make_interp_spline
    P = np.asarray(points, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or len(P) < 16 or not np.all(np.isfinite(P)):
        raise InputError(f"a cam profile needs at least 16 finite points (x, y), got an array of shape {P.shape}")
    ang = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
    if ang[-1] < ang[0]:
        P, ang = P[::-1], ang[::-1]
    if np.any(np.diff(ang) <= 0) or not abs(ang[-1] - ang[0] - 2 * math.pi) < 2 * math.pi / len(P) * 1.5:
        raise InputError("the profile's points must go once round the cam's centre, in order (a star-shaped outline)")
    t = np.append(ang, ang[0] + 2 * math.pi)
    return make_interp_spline(t, np.vstack([P, P[:1]]), k=5, bc_type="periodic"), float(ang[0])


def follow(profile, follower: Follower, base_radius: float, theta, direction: int = 1) -> FollowerMotion:
    """The follower's motion at cam angles ``theta`` on ``profile``: a designed :class:`Cam` (its exact pitch
    curve) or the profile's points in the cam's frame (a periodic quintic spline through them).

    Each position comes from the contact condition alone: the contact's
    parameter on the profile is followed by continuation on a coarse grid of
    angles (every :data:`COARSE` rad), then Newton on arrays for all angles at
    once; the rates come from differentiating the condition. Point followers
    (knife, roller) on a translating or oscillating follower, and
    translating flat faces (from points).

    >>> from domes.model.laws import Motion
    >>> cam = design_cam(Motion.cam([("cycloidal", 180, 8), ("cycloidal", 180, -8)]), Follower("translating", "knife"), 30)
    >>> round(float(follow(cam, cam.follower, 30, [math.pi / 2]).s[0]), 9)
    4.0
    """
    if follower.face == "flat" and follower.kind != "translating":
        raise InputError("follow() handles an oscillating follower with a knife or a roller; an oscillating flat face "
                         "is designed by design_cam but not yet followed on a given profile")
    theta = np.asarray(theta, dtype=float)
    if theta.ndim != 1 or theta.size == 0 or not np.all(np.isfinite(theta)):
        raise InputError("theta must be a non-empty list of finite angles")
    r = follower.roller
    flat = follower.face == "flat"
    if isinstance(profile, Cam):
        if flat:
            raise InputError("follow() takes a flat face's profile as points (cam.profile)")
        exact, t0 = profile, 0.0

        def curve(t):
            return exact.pitch_at(t)
    else:
        spline, t0 = profile_curve(profile)
        d = [spline.derivative(k) if k else spline for k in range(4)]

        def curve(t):
            X, X1, X2, X3 = (d[k](t) for k in range(4))
            if flat:
                return X, X1, X2
            sp = np.linalg.norm(X1, axis=-1)
            T = X1 / sp[..., None]
            cr = X1[..., 0] * X2[..., 1] - X1[..., 1] * X2[..., 0]
            k = cr / sp ** 3
            sig1 = np.einsum("...i,...i", T, X2)
            k1 = (X1[..., 0] * X3[..., 1] - X1[..., 1] * X3[..., 0]) / sp ** 3 - 3 * cr * sig1 / sp ** 4
            Y = X - r * _J(T)                                   # counter-clockwise curve: outward on the right
            a = sp * (1 + r * k)                                # dn/dt = σ k T for the right normal
            Y1 = a[..., None] * T
            Y2 = (sig1 * (1 + r * k) + sp * r * k1)[..., None] * T + (a * sp * k)[..., None] * _J(T)
            return Y, Y1, Y2

    sense = _Sense(follower, base_radius, direction, flat)
    order = np.argsort(theta, kind="stable")
    sorted_th = theta[order]
    coarse = np.linspace(sorted_th[0], sorted_th[-1], max(2, int(np.ceil((sorted_th[-1] - sorted_th[0]) / COARSE)) + 1))
    tc = _contacts(sense, curve, coarse, t0)
    guess = np.interp(sorted_th, coarse, tc)
    tt = _newton(sense, curve, guess, sorted_th)
    s, ds, dds, residual = sense.motion(curve, tt, sorted_th)
    back = np.empty_like(order)
    back[order] = np.arange(order.size)
    return FollowerMotion(theta, s[back], ds[back], dds[back], float(np.max(np.abs(residual))))


#: The coarse grid (rad) on which :func:`follow` walks the contact before solving every angle at once.
COARSE = math.radians(5.0)


class _Sense:
    """The contact condition of a follower on a profile curve, on arrays: ``g`` and its slope in the curve's
    parameter, the height that picks the contact on the follower's side, and the motion from the contact."""

    def __init__(self, follower: Follower, base: float, direction: int, flat: bool):
        self.f, self.base, self.delta, self.flat = follower, base, direction, flat

    def g(self, curve, t, th):
        Y, Y1, Y2 = curve(t)
        R = _rot(self.delta * th)
        W, W1 = _apply(R, Y), _apply(R, Y1)
        if self.flat:
            return W1[..., 1], _apply(R, Y2)[..., 1]
        if self.f.kind == "translating":
            return W[..., 0] - self.f.offset, W1[..., 0]
        rel = W - np.array([self.f.pivot, 0.0])
        return np.einsum("...i,...i", rel, rel) - self.f.arm ** 2, 2 * np.einsum("...i,...i", rel, W1)

    def height(self, curve, t, th):
        return _apply(_rot(self.delta * th), curve(t)[0])[..., 1]

    def motion(self, curve, t, th):
        dl = self.delta
        Y, Y1, Y2 = curve(t)
        R = _rot(dl * th)
        W, W1, W2 = _apply(R, Y), _apply(R, Y1), _apply(R, Y2)
        if self.flat:                                       # h = max over the profile of (R X)_y
            t1 = -dl * W1[..., 0] / W2[..., 1]
            return (W[..., 1] - self.base, dl * W[..., 0], dl * (-dl * W[..., 1] + W1[..., 0] * t1), W1[..., 1])
        if self.f.kind == "translating":                    # (R Y)_x = e
            JW = _J(W)
            t1 = -dl * JW[..., 0] / W1[..., 0]
            JW1 = _J(W1)
            t2 = -(-W[..., 0] + 2 * dl * JW1[..., 0] * t1 + W2[..., 0] * t1 * t1) / W1[..., 0]
            y0 = math.sqrt((self.base + self.f.roller) ** 2 - self.f.offset ** 2)
            return (W[..., 1] - y0, dl * JW[..., 1] + W1[..., 1] * t1,
                    -W[..., 1] + 2 * dl * JW1[..., 1] * t1 + W2[..., 1] * t1 * t1 + W1[..., 1] * t2,
                    W[..., 0] - self.f.offset)
        O, arm = np.array([self.f.pivot, 0.0]), self.f.arm   # |R Y − O| = arm
        rel = W - O
        JW = _J(W)
        dot = lambda a, b: np.einsum("...i,...i", a, b)      # noqa: E731
        t1 = -dl * dot(rel, JW) / dot(rel, W1)
        V = dl * JW + W1 * t1[..., None]
        A0 = dl * _J(V) + dl * _J(W1) * t1[..., None] + W2 * (t1 * t1)[..., None]
        t2 = -(dot(rel, A0) + dot(V, V)) / dot(rel, W1)
        A = A0 + W1 * t2[..., None]
        psi = np.arctan2(rel[..., 1], -rel[..., 0])
        rp = self.base + self.f.roller
        psi0 = math.acos((self.f.pivot ** 2 + arm ** 2 - rp ** 2) / (2 * self.f.pivot * arm))
        w2 = dot(rel, rel)
        p1 = (-rel[..., 0] * V[..., 1] + rel[..., 1] * V[..., 0]) / w2
        p2 = (-rel[..., 0] * A[..., 1] + rel[..., 1] * A[..., 0]) / w2 - 2 * p1 * dot(rel, V) / w2
        return psi - psi0, p1, p2, np.sqrt(w2) - arm


def _contacts(sense, curve, angles, t0) -> np.ndarray:
    """The contact's parameter at each of ``angles``: of the roots of the condition among 720 samples round the
    profile, the one with the largest height (on the follower's side), polished by Newton; unwrapped."""
    us = t0 + (np.arange(721) + 0.37) * (2 * math.pi / 720)      # off the profile's own samples: no root on a node
    vals = sense.g(curve, us[None, :], angles[:, None])[0]
    heights = sense.height(curve, us[None, :], angles[:, None])
    change = (vals[:, :-1] == 0) | (vals[:, :-1] * vals[:, 1:] < 0)
    if not np.all(change.any(axis=1)):
        k = int(np.flatnonzero(~change.any(axis=1))[0])
        raise InputError(f"the follower does not touch the profile at cam angle {math.degrees(angles[k]):.2f}° (no "
                         "contact on its axis or arm)")
    pick = np.argmax(np.where(change, heights[:, :-1], -np.inf), axis=1)
    a, b = vals[np.arange(angles.size), pick], vals[np.arange(angles.size), pick + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(a == b, 0.0, a / (a - b))
    return np.unwrap(_newton(sense, curve, us[pick] + frac * (us[1] - us[0]), angles))


def _newton(sense, curve, t, angles) -> np.ndarray:
    """The contact condition's roots in the profile's parameter, by Newton on arrays from ``t``."""
    for _ in range(60):
        value, slope = sense.g(curve, t, angles)
        step = value / slope
        t = t - step
        if np.all(np.abs(step) < 1e-14 * max(1.0, float(np.max(np.abs(t))))):
            break
    return t
