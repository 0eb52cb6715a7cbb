"""Closed forms of the class-II Assur groups (dyads): RRR, RRP, RPR, PRP, RPP.

Seed 002, chapter 2 (§2-1, after Suh): a dyad is two links and three joints;
its two outer joints sit on links already known, so the dyad's pose follows
in closed form. The book gives RRR (2-1)–(2-7) and the guide-bar RPR
(2-8)–(2-17); RRP, PRP and RPP follow the digest's supplement (§F.1).
:func:`rrr` and :func:`rpr` are the book's formulas for points (with the
digest's corrections: the sign of (2-16) and the y-row of (2-17));
:class:`DyadPlan` solves a dyad inside a mechanism, its assembly mode fixed
by the drawn pose. A dyad that cannot be assembled raises
:class:`Unassembled`; one whose pose is undetermined (coincident joints,
parallel guides) raises :class:`Undetermined`.

>>> p3, th1, th2 = rrr((0.0, 0.0), (2.0, 0.0), 2 ** 0.5, 2 ** 0.5, +1)
>>> [round(v, 12) for v in p3], round(math.degrees(th1), 9)
([1.0, 1.0], 45.0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from domes.errors import InputError, NumericalError

#: Relative slack on an assembly condition before a dyad is declared unassemblable.
ASSEMBLY_SLACK = 1e-14


class Unassembled(NumericalError):
    """The dyad cannot be assembled at this input (beyond a limit position)."""

    def __init__(self, message: str):
        super().__init__(message, kind="limit")


class Undetermined(NumericalError):
    """The dyad's pose is not determined by its outer joints (coincident joints, parallel guides)."""

    def __init__(self, message: str):
        super().__init__(message, kind="undetermined")


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1]


def _sub(a, b):
    return (a[0] - b[0], a[1] - b[1])


def _rot(angle, v):
    c, s = math.cos(angle), math.sin(angle)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1])


def _sqrt_diff(a, b, scale, what):
    """``sqrt(a² − b²)`` for ``a, b ≥ 0`` computed as ``sqrt((a − b)(a + b))``; tiny negatives are rounding."""
    d = (a - b) * (a + b)
    if d < 0:
        if d < -ASSEMBLY_SLACK * scale * scale * 64:
            raise Unassembled(what)
        return 0.0
    return math.sqrt(d)


# -- the book's point formulas --------------------------------------------------------


def rrr(p1, p2, l1, l2, sign):
    """RRR dyad position (2-1)–(2-3): ``(p3, θ1, θ2)``; ``sign`` (±1) is the assembly mode.

    >>> rrr((0, 0), (5, 0), 1, 1, 1)
    Traceback (most recent call last):
    ...
    domes.motion.planar.dyads.Unassembled: RRR dyad cannot be assembled: d = 5 > l1 + l2 = 2
    """
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    d = math.hypot(dx, dy)
    if d == 0.0:
        raise Undetermined("RRR dyad: outer joints coincide, the middle joint can be anywhere on a circle")
    if d > l1 + l2 or d < abs(l1 - l2):
        near = (d - (l1 + l2)) if d > l1 + l2 else (abs(l1 - l2) - d)
        if near > ASSEMBLY_SLACK * 64 * max(d, l1, l2):
            bound = f"d = {d:.12g} > l1 + l2 = {l1 + l2:.12g}" if d > l1 + l2 else f"d = {d:.12g} < |l1 − l2| = {abs(l1 - l2):.12g}"
            raise Unassembled(f"RRR dyad cannot be assembled: {bound}")
    # sin α from Heron's product (accurate near the limits), cos α from the law of cosines.
    prod = (l1 + d + l2) * (l1 + d - l2) * (l1 - d + l2) * (-l1 + d + l2)
    alpha = math.atan2(math.sqrt(max(prod, 0.0)), l1 * l1 + d * d - l2 * l2)
    th1 = math.atan2(dy, dx) + sign * alpha
    p3 = (p1[0] + l1 * math.cos(th1), p1[1] + l1 * math.sin(th1))
    th2 = math.atan2(p3[1] - p2[1], p3[0] - p2[0])
    return p3, th1, th2


def rrr_motion(p1, p2, p3, v1, v2, a1, a2):
    """RRR dyad velocities and accelerations (2-4)–(2-7): ``(θ̇1, θ̇2, θ̈1, θ̈2)``."""
    den = (p3[1] - p1[1]) * (p3[0] - p2[0]) - (p3[1] - p2[1]) * (p3[0] - p1[0])
    if den == 0.0:
        raise Undetermined("RRR dyad: links collinear (Den = 0), velocities undetermined")
    w1 = -((v2[0] - v1[0]) * (p3[0] - p2[0]) + (v2[1] - v1[1]) * (p3[1] - p2[1])) / den
    w2 = -((v2[0] - v1[0]) * (p3[0] - p1[0]) + (v2[1] - v1[1]) * (p3[1] - p1[1])) / den
    E = (a2[0] - a1[0]) + w1 ** 2 * (p3[0] - p1[0]) - w2 ** 2 * (p3[0] - p2[0])
    F = (a2[1] - a1[1]) + w1 ** 2 * (p3[1] - p1[1]) - w2 ** 2 * (p3[1] - p2[1])
    e1 = -(E * (p3[0] - p2[0]) + F * (p3[1] - p2[1])) / den
    e2 = -(F * (p3[1] - p1[1]) + E * (p3[0] - p1[0])) / den
    return w1, w2, e1, e2


def rpr(p1, p2, e, l3, sign, v1=(0.0, 0.0), v2=(0.0, 0.0), a1=(0.0, 0.0), a2=(0.0, 0.0)):
    """Guide-bar RPR dyad (2-8)–(2-17), corrected: guide pivoted at ``p1``, slider pivoted at ``p2``.

    ``p2 = p1 + l2·u(θ) + e·(sin θ, −cos θ)``. Returns a dict with ``theta, l2,
    p3`` and ``theta_d, l2_d, p3_d, theta_dd, l2_dd, p3_dd``, where ``p3`` is the
    guide's point ``l3`` along and ``e`` across. The digest corrects the
    sign of (2-16) (``+``) and the y-row of (2-17) (``l3 cos θ + e sin θ``).
    """
    dx, dy = p2[0] - p1[0], p2[1] - p1[1]
    r = math.hypot(dx, dy)
    l2 = _sqrt_diff(r, abs(e), r, f"RPR dyad cannot be assembled: |p2 − p1| = {r:.12g} < |e| = {abs(e):.12g}")
    theta = math.atan2(dy, dx) + sign * math.atan2(e, l2)
    c, s = math.cos(theta), math.sin(theta)
    p3 = (p1[0] + l3 * c + e * s, p1[1] + l3 * s - e * c)
    den = dx * c + dy * s  # = l2
    if den == 0.0:
        raise Undetermined("RPR dyad: slider pivot at the foot of the guide's perpendicular, velocities undetermined")
    ddx, ddy = v2[0] - v1[0], v2[1] - v1[1]
    th_d = (ddy * c - ddx * s) / den                                     # (2-11)
    l2_d = (ddy * dy + ddx * dx) / den                                   # (2-12)
    p3_d = (v1[0] - th_d * (p3[1] - p1[1]), v1[1] + th_d * (p3[0] - p1[0]))  # (2-13)
    E = (a2[0] - a1[0]) + th_d ** 2 * dx + 2 * th_d * l2_d * s           # (2-14)
    F = (a2[1] - a1[1]) + th_d ** 2 * dy - 2 * th_d * l2_d * c
    th_dd = -(E * s - F * c) / den                                       # (2-15)
    l2_dd = (E * dx + F * dy) / den                                      # (2-16), sign corrected
    p3_dd = (a1[0] - th_dd * (l3 * s - e * c) - th_d ** 2 * (l3 * c + e * s),   # (2-17), y-row corrected
             a1[1] + th_dd * (l3 * c + e * s) - th_d ** 2 * (l3 * s - e * c))
    return {"theta": theta, "l2": l2, "p3": p3, "theta_d": th_d, "l2_d": l2_d, "p3_d": p3_d,
            "theta_dd": th_dd, "l2_dd": l2_dd, "p3_dd": p3_dd}


# -- dyads inside a mechanism --------------------------------------------------------------


@dataclass(frozen=True)
class DyadPlan:
    """How to solve one dyad of a mechanism in closed form.

    ``l1`` carries the outer joint ``a`` (an R joint unless the dyad is PRP),
    ``l2`` the outer joint ``c``; ``b`` joins them. ``sign`` is the assembly
    mode read from the drawn pose.
    """

    kind: str
    l1: str
    l2: str
    a: object
    b: object
    c: object
    sign: float

    @classmethod
    def of(cls, mech, group) -> "DyadPlan":
        joints = [mech.joint(n) for n in group.joints]
        b = next(j for j in joints if set(j.links) == set(group.links))
        outer = [j for j in joints if j is not b]
        # l1 carries an R outer joint when there is one (RRP, RPP); PRP and RPR are symmetric.
        a, c = (outer[1], outer[0]) if outer[0].kind == "P" and outer[1].kind == "R" else (outer[0], outer[1])
        l1 = next(x for x in group.links if x in a.links)
        l2 = next(x for x in group.links if x != l1)
        kind = a.kind + b.kind + c.kind
        sign = 1.0
        where = f"{mech.name}: dyad {{{l1}, {l2}}} (joints {a.name}, {b.name}, {c.name})"
        if kind == "RRR":
            sign = math.copysign(1.0, _cross(_sub(c.at, a.at), _sub(b.at, a.at)))
            if _cross(_sub(c.at, a.at), _sub(b.at, a.at)) == 0.0:
                raise InputError(f"{where}: joints {a.name}, {b.name}, {c.name} are collinear in the drawn pose, "
                                 "so the assembly mode is ambiguous; draw the mechanism off this dead point")
        elif kind == "RPR":
            g_pivot, s_pivot = (a, c) if b.links[0] == l1 else (c, a)
            t0 = _dot((math.cos(b.direction), math.sin(b.direction)), _sub(s_pivot.at, g_pivot.at))
            if t0 == 0.0:
                raise InputError(f"{where}: the slider pivot {s_pivot.name} is at the foot of the perpendicular from "
                                 f"{g_pivot.name} in the drawn pose (a dead point); draw the mechanism off it")
            sign = math.copysign(1.0, t0)
        elif kind == "RRP":
            u0 = (math.cos(c.direction), math.sin(c.direction))
            w0 = _dot(u0, _sub(b.at, a.at))
            if w0 == 0.0:
                raise InputError(f"{where}: link {l1} is perpendicular to the slide of {c.name} in the drawn pose "
                                 "(a dead point); draw the mechanism off it")
            sign = math.copysign(1.0, w0)
        elif kind not in ("PRP", "RPP"):
            raise InputError(f"{where}: no closed form for a {kind} dyad")
        return cls(kind, l1, l2, a, b, c, sign)

    def solve(self, world, rotation_of, sign: float | None = None) -> tuple[dict, dict]:
        """Rotations ``{link: Δ}`` and slides ``{joint: s}`` of the dyad.

        ``world(joint)`` is the world position of ``joint``'s point on the
        known link; ``rotation_of(link)`` the current rotation of a link
        whose rotation is already known; ``sign`` overrides the drawn
        assembly mode (after a bifurcation).
        """
        a, b, c = self.a, self.b, self.c
        sign = self.sign if sign is None else sign
        if self.kind == "RRR":
            A, C = world(a), world(c)
            l1 = math.dist(a.at, b.at)
            l2 = math.dist(c.at, b.at)
            try:
                B, th1, th2 = rrr(A, C, l1, l2, sign)
            except Undetermined:
                raise Undetermined(f"joints {a.name} and {c.name} coincide: the dyad {{{self.l1}, {self.l2}}} can turn "
                                   f"about them, joint {b.name} is undetermined") from None
            except Unassembled as exc:
                raise Unassembled(f"dyad {{{self.l1}, {self.l2}}} cannot be assembled at joints {a.name}, {b.name}, "
                                  f"{c.name}: {exc}") from None
            return ({self.l1: th1 - _angle(b.at, a.at), self.l2: th2 - _angle(b.at, c.at)}, {})
        if self.kind == "RPR":
            guide_first = b.links[0] == self.l1
            g_pivot, s_pivot = (a, c) if guide_first else (c, a)
            u0 = (math.cos(b.direction), math.sin(b.direction))
            rel0 = _sub(s_pivot.at, g_pivot.at)
            e, t0 = _cross(u0, rel0), _dot(u0, rel0)
            D = _sub(world(s_pivot), world(g_pivot))
            r = math.hypot(*D)
            t = sign * _sqrt_diff(r, abs(e), r, f"dyad {{{self.l1}, {self.l2}}} cannot be assembled: pivots "
                                       f"{g_pivot.name}, {s_pivot.name} are {r:.12g} apart, closer than the slide "
                                       f"offset {abs(e):.12g}")
            if r == 0.0:
                raise Undetermined(f"joints {a.name} and {c.name} coincide: the slide of {b.name} can turn about them")
            psi = math.atan2(D[1], D[0]) - math.atan2(e, t)
            delta = psi - b.direction
            return ({self.l1: delta, self.l2: delta}, {b.name: b.s0 + t - t0})
        if self.kind == "RRP":
            A = world(a)
            guide = c.links[0]
            dl2 = rotation_of(self.l2)
            u = (math.cos(c.direction + dl2), math.sin(c.direction + dl2))
            sg = 1.0 if guide != self.l2 else -1.0
            p0 = _add(world(c), _rot(dl2, _sub(b.at, c.at)))
            w = _sub(p0, A)
            l1 = math.dist(a.at, b.at)
            h = abs(_cross(u, w))
            root = _sqrt_diff(l1, h, max(l1, h), f"dyad {{{self.l1}, {self.l2}}} cannot be assembled: joint {b.name} "
                              f"is {h:.12g} from the slide line of {c.name}, farther than |{a.name}{b.name}| = {l1:.12g}")
            tau = -_dot(u, w) + sign * root
            B = (p0[0] + tau * u[0], p0[1] + tau * u[1])
            return ({self.l1: _angle(B, A) - _angle(b.at, a.at)}, {c.name: c.s0 + sg * tau})
        if self.kind == "PRP":
            p = []
            for joint, link in ((a, self.l1), (c, self.l2)):
                d = rotation_of(link)
                u = (math.cos(joint.direction + d), math.sin(joint.direction + d))
                sg = 1.0 if joint.links[0] != link else -1.0
                p.append((_add(world(joint), _rot(d, _sub(b.at, joint.at))), u, sg))
            (p1, u1, s1), (p2, u2, s2) = p
            det = -_cross(u1, u2)
            if abs(det) <= 1e-15:
                raise Undetermined(f"slides {a.name} and {c.name} are parallel: joint {b.name} is undetermined")
            rhs = _sub(p2, p1)
            t1 = _cross(rhs, (-u2[0], -u2[1])) / det
            t2 = _cross(u1, rhs) / det
            return ({}, {a.name: a.s0 + s1 * t1, c.name: c.s0 + s2 * t2})
        # RPP: l1 pinned at a; b is the inner P, c the outer P (l2 to the known link).
        dl1 = rotation_of(self.l1)
        dl2 = rotation_of(self.l2)
        A = world(a)
        X1 = _add(A, _rot(dl1, _sub(b.at, a.at)))
        u_in = (math.cos(b.direction + rotation_of(b.links[0])), math.sin(b.direction + rotation_of(b.links[0])))
        u_out = (math.cos(c.direction + rotation_of(c.links[0])), math.sin(c.direction + rotation_of(c.links[0])))
        s_in = 1.0 if b.links[0] == self.l1 else -1.0
        s_out = 1.0 if c.links[0] != self.l2 else -1.0
        rhs = _add(_rot(dl2, _sub(b.at, c.at)), _sub(world(c), X1))
        det = -_cross(u_in, u_out)
        if abs(det) <= 1e-15:
            raise Undetermined(f"slides {b.name} and {c.name} are parallel: link {self.l2} can slide freely")
        t_in = _cross(rhs, (-u_out[0], -u_out[1])) / det
        t_out = _cross(u_in, rhs) / det
        return ({}, {b.name: b.s0 + s_in * t_in, c.name: c.s0 + s_out * t_out})


def _add(a, b):
    return (a[0] + b[0], a[1] + b[1])


def _angle(p, q):
    """Direction of ``p − q``."""
    return math.atan2(p[1] - q[1], p[0] - q[0])
