"""Four-bars in the convention of seed 002 chapter 6 (digest B.4 and B.6).

The frame pivots are ``A = (0, 0)`` and ``D = (d, 0)``, the crank pin
``B = a(cos θ, sin θ)``; ``C`` closes the loop (``|BC| = b``, ``|DC| = c``)
on the left of the directed line ``B → D`` in the *open* form and on its
right in the *crossed* form. A coupler point has coupler-plane coordinates
``(u, v)``: ``u`` along ``B → C``, ``v`` perpendicular to it,
counter-clockwise. The atlas of §6-4 gives the coupler point instead as the
distance ``P = |BP|`` and the angle ``θ_BP`` of ``BP`` from ``BC``, counter-
clockwise: ``(u, v) = P (cos θ_BP, sin θ_BP)``.

>>> m = four_bar(0.4, 1.2, 1.0, 1.4, 1.3076, 0.2058, theta=math.radians(45))   # Fig. 6-11, the cusp linkage
>>> [round(x, 7) for x in m.joint("C").at]
[1.2529739, 0.9891326]
>>> [round(x, 7) for x in instant_centre(0.4, 1.2, 1.0, 1.4, math.radians(45))]
[1.2188312, 1.2188312]
"""

from __future__ import annotations

import math

from domes.errors import InputError
from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism

LINKS = ("frame", "crank", "coupler", "rocker")


def closure(a: float, b: float, c: float, d: float, theta: float, crossed: bool = False):
    """``(B, C)`` of the loop at crank angle ``theta``, or None where it does not close."""
    bx, by = a * math.cos(theta), a * math.sin(theta)
    dx, dy = d - bx, -by
    r = math.hypot(dx, dy)
    if r == 0.0 or r > b + c or r < abs(b - c):
        return None
    along = (b * b + r * r - c * c) / (2 * r)
    across = math.sqrt(max(b * b - along * along, 0.0)) * (-1.0 if crossed else 1.0)
    ux, uy = dx / r, dy / r
    return (bx, by), (bx + along * ux - across * uy, by + along * uy + across * ux)


def to_world(B, C, u: float, v: float):
    """The world position of the coupler point ``(u, v)`` when the coupler is at ``B → C``."""
    length = math.dist(B, C)
    ex, ey = (C[0] - B[0]) / length, (C[1] - B[1]) / length
    return B[0] + u * ex - v * ey, B[1] + u * ey + v * ex


def to_coupler(B, C, point):
    """The coupler-plane coordinates ``(u, v)`` of a world point when the coupler is at ``B → C``."""
    length = math.dist(B, C)
    ex, ey = (C[0] - B[0]) / length, (C[1] - B[1]) / length
    px, py = point[0] - B[0], point[1] - B[1]
    return px * ex + py * ey, -px * ey + py * ex


def instant_centre(a: float, b: float, c: float, d: float, theta: float, crossed: bool = False):
    """The coupler's instant centre in the frame: the intersection of lines ``AB`` and ``DC`` (digest F.2).

    None when the loop does not close or the lines are parallel (the centre is at infinity).
    """
    loop = closure(a, b, c, d, theta, crossed)
    if loop is None:
        return None
    B, C = loop
    cdx, cdy = C[0] - d, C[1]
    den = B[0] * cdy - B[1] * cdx
    if abs(den) <= 1e-15 * a * max(b, c, d):
        return None
    lam = (d * cdy) / den
    return lam * B[0], lam * B[1]


def joints_meet(a: float, b: float, c: float, d: float, rel: float = 1e-9) -> str | None:
    """What makes the four-bar fold, or None: crank = frame and coupler = rocker let the crank pin ``B`` meet the
    rocker pivot ``D`` (a rhombus meets both cases); crank = coupler and rocker = frame let ``C`` meet ``A``.
    There the dyad's position is undetermined: the linkage is at a change point and can switch branches.

    >>> joints_meet(1, 1, 1, 1)
    'B meets D (crank = frame, coupler = rocker) and C meets A (crank = coupler, rocker = frame)'
    >>> joints_meet(1, 2, 2, 1.5) is None
    True
    """
    same = lambda x, y: abs(x - y) <= rel * max(a, b, c, d)          # noqa: E731
    out = []
    if same(a, d) and same(b, c):
        out.append("B meets D (crank = frame, coupler = rocker)")
    if same(a, b) and same(c, d):
        out.append("C meets A (crank = coupler, rocker = frame)")
    return " and ".join(out) or None


def lengths_of(mech: Mechanism) -> tuple[float, float, float, float] | None:
    """Crank, coupler, rocker and frame of a four-bar of R joints driven at a frame pivot; None for other
    mechanisms."""
    if len(mech.links) != 4 or len(mech.joints) != 4 or any(j.kind != "R" for j in mech.joints) or \
            len(mech.inputs) != 1:
        return None
    joints = {j.name: j for j in mech.joints}
    first = joints.get(mech.inputs[0].joint)
    if first is None or mech.ground not in first.links:
        return None
    crank = next(x for x in first.links if x != mech.ground)
    order, link, joint = [first], crank, first
    for _ in range(3):                                   # around the loop: crank, coupler, rocker
        joint = next((j for j in mech.joints if link in j.links and j is not joint), None)
        if joint is None:
            return None
        order.append(joint)
        link = next(x for x in joint.links if x != link)
    if order[-1] is first or mech.ground not in order[-1].links:
        return None
    A, B, C, D = (j.at for j in order)
    return math.dist(A, B), math.dist(B, C), math.dist(C, D), math.dist(A, D)


def four_bar(a: float, b: float, c: float, d: float, u: float, v: float, theta: float | None = None,
             crossed: bool = False, name: str | None = None) -> Mechanism:
    """The four-bar ``a, b, c, d`` with coupler point ``P`` at ``(u, v)``, drawn at crank angle ``theta``.

    ``theta`` defaults to the crank angle (on a 1° grid) with the best
    transmission where the loop closes; an InputError when it never closes.
    """
    for label, x in (("a", a), ("b", b), ("c", c), ("d", d)):
        if not (x > 0 and math.isfinite(x)):
            raise InputError(f"four-bar: the length {label} must be a positive number, got {x!r}")
    if not (math.isfinite(u) and math.isfinite(v)):
        raise InputError(f"four-bar: the coupler point (u, v) must be finite, got ({u!r}, {v!r})")
    if theta is None:
        theta = _best_angle(a, b, c, d, crossed)
    loop = closure(a, b, c, d, theta, crossed)
    if loop is None:
        raise InputError(f"four-bar a, b, c, d = {a:g}, {b:g}, {c:g}, {d:g} does not close at crank angle "
                         f"{math.degrees(theta):g}°")
    B, C = loop
    if abs((C[0] - B[0]) * (0 - B[1]) - (C[1] - B[1]) * (d - B[0])) <= 1e-12 * b * max(c, d):
        raise InputError(f"four-bar a, b, c, d = {a:g}, {b:g}, {c:g}, {d:g}: coupler and rocker are collinear at "
                         f"crank angle {math.degrees(theta):g}° (a dead point): draw it at another angle")
    P = to_world(B, C, u, v)
    return Mechanism.build(
        name or f"four-bar a={a:g} b={b:g} c={c:g} d={d:g} u={u:g} v={v:g}", list(LINKS), "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), B),
         Joint("C", "R", ("coupler", "rocker"), C), Joint("D", "R", ("rocker", "frame"), (d, 0.0))],
        [Input("A")], points=[CouplerPoint("P", "coupler", P)])


def from_atlas(crank: float, coupler: float, follower: float, frame: float, distance: float, angle_deg: float,
               theta: float | None = None) -> Mechanism:
    """A four-bar given as in the atlas of §6-4: lengths A, B, C, D, ``P = |BP|`` and ``θ_BP`` (degrees) from BC.

    >>> m = from_atlas(1, 3.5, 3, 2, 2, 270)                 # the figure-eight of Fig. 6-33
    >>> [round(x, 9) for x in m.point("P")[1]] == [round(x, 9) for x in to_world(m.joint("B").at, m.joint("C").at, 0, -2)]
    True
    """
    t = math.radians(angle_deg)
    return four_bar(crank, coupler, follower, frame, distance * math.cos(t), distance * math.sin(t), theta,
                    name=f"atlas four-bar A={crank:g} B={coupler:g} C={follower:g} D={frame:g} P={distance:g} "
                    f"θBP={angle_deg:g}°")


def _best_angle(a, b, c, d, crossed):
    best, angle = -1.0, None
    for k in range(360):
        theta = math.radians(k + 0.5)
        loop = closure(a, b, c, d, theta, crossed)
        if loop is None:
            continue
        B, C = loop
        # |sin μ|, μ the transmission angle between coupler C→B and rocker C→D.
        s = abs((B[0] - C[0]) * (0.0 - C[1]) - (B[1] - C[1]) * (d - C[0])) / (b * c)
        if s > best:
            best, angle = s, theta
    if angle is None:
        raise InputError(f"four-bar a, b, c, d = {a:g}, {b:g}, {c:g}, {d:g} closes at no crank angle")
    return angle
