"""Mechanism symbols (Table 3-5 of seed 002 and the usual sketch conventions), in SVG units.

Each function takes points already in drawing coordinates and returns SVG
elements; ``s`` is the scale of the symbol (about the median link size).

>>> 'class="spring"' in spring((0, 0), (50, 0), 40)[0]
True
"""

from __future__ import annotations

import math

from domes.sketch.svg import num, path_data, points, tag

Point = tuple[float, float]
INK = "#1d3557"
GROUND_INK = "#555555"


def _unit(p: Point, q: Point) -> tuple[Point, float]:
    dx, dy = q[0] - p[0], q[1] - p[1]
    length = math.hypot(dx, dy)
    if length < 1e-9:
        return (1.0, 0.0), 0.0
    return (dx / length, dy / length), length


def _at(p: Point, d: Point, t: float, n: Point = (0.0, 0.0), w: float = 0.0) -> Point:
    """``p + t·d + w·n``."""
    return (p[0] + t * d[0] + w * n[0], p[1] + t * d[1] + w * n[1])


def _line(p: Point, q: Point, cls: str, width: float = 2.0, extra: dict[str, str] | None = None) -> str:
    attrs = {"class": cls, "x1": num(p[0]), "y1": num(p[1]), "x2": num(q[0]), "y2": num(q[1]), "stroke": INK, "stroke-width": num(width), "stroke-linecap": "round"}
    return tag("line", {**attrs, **(extra or {})})


def ground_pivot(p: Point, s: float, away: Point) -> list[str]:
    """A fixed pivot: a triangle under the joint on a hatched base, pointing away from ``away``."""
    (dx, dy), _ = _unit(away, p)
    if dx == 1.0 and dy == 0.0 and away == p:
        dx, dy = 0.0, 1.0
    nx_, ny_ = -dy, dx
    h, b = 0.22 * s, 0.16 * s
    base = _at(p, (dx, dy), h)
    tri = [p, _at(base, (nx_, ny_), b), _at(base, (nx_, ny_), -b)]
    items = [tag("polygon", {"class": "ground-pivot", "points": points(tri), "fill": "#ffffff", "stroke": GROUND_INK, "stroke-width": "1.5"})]
    left, right = _at(base, (nx_, ny_), -1.6 * b), _at(base, (nx_, ny_), 1.6 * b)
    items.append(_line(left, right, "ground-line", 1.5, {"stroke": GROUND_INK}))
    for i in range(6):
        start = _at(left, (nx_, ny_), i * 3.2 * b / 5)
        end = _at(start, (dx, dy), 0.09 * s, (nx_, ny_), -0.09 * s)
        items.append(_line(start, end, "hatch", 1.0, {"stroke": GROUND_INK}))
    return items


def hatch_ticks(a: Point, b: Point, s: float, away: Point) -> list[str]:
    """Short hatch strokes along a ground bar ``a-b``, on the side away from ``away``."""
    d, length = _unit(a, b)
    n = (-d[1], d[0])
    mid = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)
    if (away[0] - mid[0]) * n[0] + (away[1] - mid[1]) * n[1] > 0:
        n = (-n[0], -n[1])
    count = max(2, int(length / (0.12 * s)))
    items = []
    for i in range(1, count):
        start = _at(a, d, i * length / count, n, 0.02 * s)
        items.append(_line(start, _at(start, d, -0.08 * s, n, 0.08 * s), "hatch", 1.0, {"stroke": GROUND_INK}))
    return items


def input_arrow(p: Point, s: float) -> list[str]:
    """A curved arrow about joint ``p``: the input (driving) motion."""
    r = 0.3 * s
    a0, a1 = math.radians(200), math.radians(-20)
    start = (p[0] + r * math.cos(a0), p[1] - r * math.sin(a0))
    end = (p[0] + r * math.cos(a1), p[1] - r * math.sin(a1))
    arc = path_data([("M", start), ("A", (r, r, 0, 1, 1, end[0], end[1]))])  # large arc, clockwise
    tangent = (math.sin(a1), math.cos(a1))  # direction of travel at the end (clockwise on screen)
    normal = (-tangent[1], tangent[0])
    head = [_at(end, tangent, 0.12 * s), _at(end, normal, 0.07 * s), _at(end, normal, -0.07 * s)]
    return [
        tag("path", {"class": "input-arrow", "d": arc, "fill": "none", "stroke": "#c1121f", "stroke-width": "2"}),
        tag("polygon", {"class": "input-arrow-head", "points": points(head), "fill": "#c1121f"}),
    ]


def slider(p: Point, direction: Point, s: float) -> list[str]:
    """A prismatic joint: a guide line along ``direction`` through ``p`` and a block on it."""
    d, _ = _unit((0.0, 0.0), direction)
    n = (-d[1], d[0])
    guide = _line(_at(p, d, -0.45 * s), _at(p, d, 0.45 * s), "slider-guide", 2.0)
    a, b = 0.18 * s, 0.1 * s
    block = [_at(p, d, -a, n, -b), _at(p, d, a, n, -b), _at(p, d, a, n, b), _at(p, d, -a, n, b)]
    return [guide, tag("polygon", {"class": "slider-block", "points": points(block), "fill": "#ffffff", "stroke": INK, "stroke-width": "2"})]


def cylinder(a: Point, m: Point, b: Point, s: float, cls: str = "cylinder") -> list[str]:
    """A cylinder pivoted at ``a`` with its piston at ``m`` and its rod out to ``b``.

    A hydraulic cylinder or shock absorber replaced, in the chain, by the
    dyad ``a-m-b`` (Table 3-5): the body is drawn along ``a→m``, the rod
    along ``m→b``.
    """
    d, length = _unit(a, m)
    n = (-d[1], d[0])
    w = 0.09 * s
    body = [_at(a, d, 0.1 * length, n, -w), _at(m, d, 0.15 * length, n, -w), _at(m, d, 0.15 * length, n, w), _at(a, d, 0.1 * length, n, w)]
    return [
        _line(a, _at(a, d, 0.1 * length), cls + "-mount", 2.5),
        tag("polygon", {"class": cls, "points": points(body), "fill": "#f1f1f1", "stroke": INK, "stroke-width": "2"}),
        _line(_at(m, n, -w), _at(m, n, w), cls + "-piston", 2.5),
        _line(m, b, cls + "-rod", 2.0),
    ]


def spring(a: Point, b: Point, s: float, cls: str = "spring", coil: tuple[float, float] = (0.15, 0.85), amplitude: float = 0.08) -> list[str]:
    """A zigzag spring from ``a`` to ``b``, coiled over the fraction ``coil`` of the way."""
    d, length = _unit(a, b)
    n = (-d[1], d[0])
    turns, amp = 8, amplitude * s
    first, last = coil
    pts = [a, _at(a, d, first * length)]
    for i in range(turns):
        pts.append(_at(a, d, (first + (last - first) * (i + 0.5) / turns) * length, n, amp if i % 2 == 0 else -amp))
    pts += [_at(a, d, last * length), b]
    return [tag("polyline", {"class": cls, "points": points(pts), "fill": "none", "stroke": INK, "stroke-width": "1.8", "stroke-linejoin": "round"})]


def force(a: Point, m: Point, b: Point, s: float) -> list[str]:
    """A force member ``a-m-b``: dashed, arrow heads at both ends, ``F`` at the middle point (Fp/Fr in Table 3-5)."""
    items = [tag("polyline", {"class": "force", "points": points([a, m, b]), "fill": "none", "stroke": INK, "stroke-width": "2", "stroke-dasharray": "5 3"})]
    for end, inner in ((a, m), (b, m)):
        d, _ = _unit(inner, end)
        n = (-d[1], d[0])
        head = [end, _at(end, d, -0.14 * s, n, 0.07 * s), _at(end, d, -0.14 * s, n, -0.07 * s)]
        items.append(tag("polygon", {"class": "force-head", "points": points(head), "fill": INK}))
    items.append(tag("text", {"class": "force-label", "x": num(m[0] + 5), "y": num(m[1] - 5), "font-size": "11", "font-style": "italic", "font-family": "serif", "fill": INK}, text="F"))
    return items


def gear_pair(p: Point, towards_first: Point, s: float) -> list[str]:
    """Two gears meshing at ``p``: pitch circles tangent there, the first towards ``towards_first``."""
    d, _ = _unit(p, towards_first)
    r1, r2 = 0.22 * s, 0.15 * s
    items = []
    for centre, r in ((_at(p, d, r1), r1), (_at(p, d, -r2), r2)):
        items.append(tag("circle", {"class": "gear", "cx": num(centre[0]), "cy": num(centre[1]), "r": num(r), "fill": "none", "stroke": INK, "stroke-width": "1.8", "stroke-dasharray": "6 2 1 2"}))
        items.append(tag("circle", {"class": "gear-centre", "cx": num(centre[0]), "cy": num(centre[1]), "r": "1.8", "fill": INK}))
    return items


def cam_pair(p: Point, towards_cam: Point, s: float) -> list[str]:
    """A cam (egg-shaped disc towards ``towards_cam``) touching a roller follower at ``p``."""
    d, _ = _unit(p, towards_cam)
    a, b = 0.25 * s, 0.17 * s
    centre = _at(p, d, a)
    angle = math.degrees(math.atan2(d[1], d[0]))
    roller = 0.08 * s
    rc = _at(p, d, -roller)
    return [
        tag("ellipse", {"class": "cam", "cx": num(centre[0]), "cy": num(centre[1]), "rx": num(a), "ry": num(b), "transform": f"rotate({num(angle)} {num(centre[0])} {num(centre[1])})", "fill": "#f1f1f1", "stroke": INK, "stroke-width": "1.8"}),
        tag("circle", {"class": "cam-follower", "cx": num(rc[0]), "cy": num(rc[1]), "r": num(roller), "fill": "#ffffff", "stroke": INK, "stroke-width": "1.8"}),
    ]


def rolling_pair(p: Point, towards_roller: Point, s: float) -> list[str]:
    """A roller (towards ``towards_roller``) rolling on a straight track through ``p``."""
    d, _ = _unit(p, towards_roller)
    n = (-d[1], d[0])
    r = 0.2 * s
    centre = _at(p, d, r)
    return [
        tag("circle", {"class": "roller", "cx": num(centre[0]), "cy": num(centre[1]), "r": num(r), "fill": "none", "stroke": INK, "stroke-width": "1.8"}),
        _line(_at(p, n, -0.4 * s), _at(p, n, 0.4 * s), "rolling-track", 2.0),
    ]
