"""A follower on a cam's given profile: its displacement and two derivatives by the contact condition alone.

The cam turns about the origin (``θ``, counter-clockwise when ``direction``
is +1); the profile is its outline in its own frame, as points (a periodic
quintic spline through them) or a designed cam's exact pitch curve. The
follower (:class:`Follower`) is translating (its axis parallel to +y at
``offset``) or oscillating (its pivot at ``(pivot, 0)``), with a knife edge,
a roller or a flat face. :func:`follow` gives its motion at any angles;
:class:`ProfileLaw` wraps that as a periodic law over one turn, which a cam
pair of a mechanism given by its profile (:class:`domes.model.cams.CamProfile`)
moves its follower by.

>>> import math
>>> ring = [(10 + 2 * math.cos(k * math.pi / 90), 2 * math.sin(k * math.pi / 90)) for k in range(180)]
>>> eccentric = [(x - 10 + 1, y) for x, y in ring]        # a circle of radius 2 centred 1 off the cam's centre
>>> law = ProfileLaw(eccentric, Follower("translating", "knife"))
>>> [round(float(v), 9) + 0.0 for v in law.evaluate([-math.pi / 2, math.pi / 2], 0)[0]]   # lift from base radius 1
[0.0, 2.0]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.cams import FACES, KINDS, CamProfile, Follower, profile_points, use_profile_law

#: The coarse grid (rad) on which :func:`follow` walks the contact before solving every angle at once.
COARSE = math.radians(5.0)
#: Angles per turn at which :class:`ProfileLaw` keeps the contact's parameter (Newton starts from there).
TABLE = 720


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
class FollowerMotion:
    """The follower's displacement ``s`` and its derivatives in the cam's angle, and the contact residual."""

    theta: np.ndarray
    s: np.ndarray
    ds: np.ndarray
    dds: np.ndarray
    residual: float


def profile_curve(points):
    """A closed curve through the profile ``points`` (counter-clockwise or not): a periodic quintic spline in the
    points' angle, with its first three derivatives; and the parameter of its first point.

    >>> import math
    >>> spline, t0 = profile_curve([(math.cos(k * math.pi / 8), math.sin(k * math.pi / 8)) for k in range(16)])
    >>> round(float(abs(complex(*spline(1.0)))), 3), t0
    (1.0, 0.0)
    """
    from scipy.interpolate import make_interp_spline
    P = profile_points(points)
    ang = np.unwrap(np.arctan2(P[:, 1], P[:, 0]))
    t = np.append(ang, ang[0] + 2 * math.pi)
    return make_interp_spline(t, np.vstack([P, P[:1]]), k=5, bc_type="periodic"), float(ang[0])


def _curve_of(points, follower: Follower):
    """The curve the contact condition runs on (a point follower's pitch curve: the spline through ``points``
    offset outward by the roller; a flat face's profile itself) with two derivatives, and its first parameter."""
    flat, r = follower.face == "flat", follower.roller
    spline, t0 = profile_curve(points)
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

    return curve, t0


def _check_reach(follower: Follower, base: float) -> None:
    """The follower's zero (lift 0 on the base circle) exists: an InputError when it cannot touch that circle."""
    rp = base + follower.roller
    if follower.kind == "translating" and follower.face != "flat" and abs(follower.offset) >= rp:
        raise InputError(f"the follower's offset {follower.offset:g} must be smaller than the prime circle's radius "
                         f"{rp:g} (base radius + roller)")
    if follower.kind == "oscillating" and not abs(follower.pivot - follower.arm) < rp < follower.pivot + follower.arm:
        raise InputError(f"an arm of {follower.arm:g} about a pivot {follower.pivot:g} from the cam cannot reach the "
                         f"prime circle (radius {rp:g}): |pivot − arm| < base radius + roller < pivot + arm is needed")


def follow(profile, follower: Follower, base_radius: float, theta, direction: int = 1) -> FollowerMotion:
    """The follower's motion at cam angles ``theta`` on ``profile``: a designed cam (its exact pitch curve,
    ``pitch_at``) or the profile's points in the cam's frame (a periodic quintic spline through them).

    Each position comes from the contact condition alone: the contact's
    parameter on the profile is followed by continuation on a coarse grid of
    angles (every :data:`COARSE` rad), then Newton on arrays for all angles at
    once; the rates come from differentiating the condition. Point followers
    (knife, roller) on a translating or oscillating follower, and
    translating flat faces (from points).

    >>> import math
    >>> from domes.design.cam import design_cam
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
    flat = follower.face == "flat"
    if hasattr(profile, "pitch_at"):
        if flat:
            raise InputError("follow() takes a flat face's profile as points (cam.profile)")
        curve, t0 = profile.pitch_at, 0.0
    else:
        curve, t0 = _curve_of(profile, follower)
    _check_reach(follower, base_radius)
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


class ProfileLaw:
    """The follower's motion on a profile over one turn of the cam, as a periodic law: :meth:`evaluate` gives the
    lift and its first two derivatives at cam angles ``x`` (arrays), like :class:`~domes.model.laws.Motion`.

    The contact's parameter is found once at :data:`TABLE` angles round the
    turn (as :func:`follow` finds it); each evaluation starts Newton from
    that table. An oscillating follower's lift is returned as the mechanism
    counts it, a counter-clockwise angle: ``−direction`` times
    :func:`follow`'s (which rises turning away from the cam).

    >>> import math
    >>> from domes.design.cam import design_cam
    >>> from domes.model.laws import Motion
    >>> motion = Motion.cam([("cycloidal", 180, 8), ("cycloidal", 180, -8)])
    >>> cam = design_cam(motion, Follower("translating", "roller", roller=5), 30, points=1440)
    >>> law = ProfileLaw(cam.profile, cam.follower, 30)
    >>> float(abs(law.evaluate([1.0], 0)[0][0] - motion.evaluate([1.0], 0)[0][0])) < 1e-12
    True
    """

    periodic = True
    period = 2 * math.pi

    def __init__(self, points, follower: Follower, base_radius: float | None = None, direction: int = 1):
        if follower.face == "flat" and follower.kind != "translating":
            raise InputError("an oscillating flat face is not followed on a given profile (knife or roller only)")
        if direction not in (1, -1):
            raise InputError(f"direction must be 1 (counter-clockwise) or -1 (clockwise), got {direction!r}")
        P = profile_points(points)
        base = float(np.min(np.hypot(P[:, 0], P[:, 1]))) if base_radius is None else float(base_radius)
        _check_reach(follower, base)
        self.follower, self.base_radius, self.direction = follower, base, direction
        self._flat = follower.face == "flat"
        self._curve, t0 = _curve_of(P, follower)
        self._sense = _Sense(follower, base, direction, self._flat)
        self._sign = -direction if follower.kind == "oscillating" else 1.0
        self._th = np.linspace(0.0, 2 * math.pi, TABLE + 1)
        coarse = np.linspace(0.0, 2 * math.pi, int(np.ceil(2 * math.pi / COARSE)) + 1)
        tc = _contacts(self._sense, self._curve, coarse, t0)
        self._t = _newton(self._sense, self._curve, np.interp(self._th, coarse, tc), self._th)
        g = self._sense.g(self._curve, self._t, self._th)[0]
        size = float(np.max(np.hypot(P[:, 0], P[:, 1])))
        if not np.all(np.abs(g) <= 1e-9 * size * (size if follower.kind == "oscillating" else 1.0)):
            k = int(np.argmax(np.abs(g)))
            raise InputError(f"the follower's contact with the profile is lost near cam angle "
                             f"{math.degrees(self._th[k]):.2f}° (the contact condition stays at {abs(g[k]):.3g})")

    @classmethod
    def of(cls, profile: CamProfile) -> "ProfileLaw":
        """The law of a mechanism's :class:`~domes.model.cams.CamProfile`."""
        return cls(profile.points, profile.follower, profile.base_radius, profile.direction)

    def evaluate(self, x, order: int = 2) -> tuple[np.ndarray, ...]:
        """``(s, s', s'')`` up to ``order`` (0 to 2) at cam angles ``x`` (rad, any shape)."""
        if order not in (0, 1, 2):
            raise InputError(f"order must be 0, 1 or 2 for a cam's profile, got {order!r}")
        x = np.asarray(x, dtype=float)
        if not np.all(np.isfinite(x)):
            raise InputError("a cam's profile is followed at finite angles only")
        th = np.mod(x.ravel(), 2 * math.pi)
        t = _newton(self._sense, self._curve, np.interp(th, self._th, self._t), th)
        out = self._sense.motion(self._curve, t, th)[:3]
        return tuple((self._sign * v).reshape(x.shape) for v in out[:order + 1])


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


use_profile_law(ProfileLaw.of)

__all__ = ["COARSE", "FACES", "KINDS", "TABLE", "Follower", "FollowerMotion", "ProfileLaw", "follow", "profile_curve"]
