"""Mechanism sketches from labelled chains (DOMES module 8; §5-3 step 2: "annotate the link behaviours").

The chain is laid out as a skeleton (:func:`~domes.sketch.layout.skeleton_layout`)
or placed at given joint positions (a kinematic solution), then drawn with
the symbols of its labels, after Table 3-5 of seed 002:

* the ground link hatched, with a fixed-pivot symbol at each of its joints;
* the input link marked with a curved arrow at its pivot;
* ``P`` joints as a slider block on a guide (the guide on the ground, else
  on the link with more joints);
* ``H`` joints, and links with the role ``shock_absorber``, as
  cylinder-and-rod (a shock absorber also with its spring); ``S`` joints as
  zigzag springs; ``F`` joints as dashed force members marked F: when both
  links at the joint are binary the pair is drawn as the one straight
  member it stands for (the dyad of Table 3-5, its middle joint on the line
  between the dyad's outer joints), otherwise the joint is marked with its
  letter;
* ``G`` joints as two pitch circles touching, ``C`` joints as a cam and
  roller follower, ``O`` joints as a roller on a track;
* every role written beside its link.

>>> from domes.model import LabelledChain
>>> crank_slider = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(0, 3): "P"},
...                                    roles={0: {"ground"}, 1: {"input"}})
>>> svg = mechanism_svg(crank_slider)
>>> [name in svg for name in ("slider-block", "ground-pivot", "input-arrow", ">input<")]
[True, True, True, True]
"""

from __future__ import annotations

import math
from typing import Mapping

from domes.sketch import symbols
from domes.sketch.draw import INK, PLATE_FILL, SIZE, Frame, joint_circles, label_point, link_shape, median_link_length
from domes.sketch.layout import Point, SkeletonLayout, layout_from_positions, skeleton_layout
from domes.sketch.svg import document, num, tag

Edge = tuple[int, int]
#: Joint types drawn as a member replacing a two-link dyad (Table 3-5).
MEMBER_JOINTS = ("H", "S", "F")
HATCH = tag(
    "defs",
    children=[
        tag(
            "pattern",
            {"id": "hatch", "patternUnits": "userSpaceOnUse", "width": "6", "height": "6", "patternTransform": "rotate(45)"},
            [tag("rect", {"width": "6", "height": "6", "fill": "#eeeeee"}), tag("line", {"x1": "0", "y1": "0", "x2": "0", "y2": "6", "stroke": "#777777", "stroke-width": "1.5"})],
        )
    ],
)


def _other_end(layout: SkeletonLayout, frame: Frame, v: int, k: int) -> Point:
    """The far end of link ``v`` seen from its joint ``k``: the other joint of a bar, else the centre."""
    ring = layout.link_rings[v]
    if len(ring) == 2 and k in ring:
        return frame(layout.positions[ring[0] if ring[1] == k else ring[1]])
    return frame(layout.link_centres[v])


def mechanism_svg(labelled, positions: Mapping[Edge, Point] | None = None, *, size: float = SIZE, numbers: bool = False, title: str | None = None) -> str:
    """A labelled chain drawn as a mechanism sketch, as an SVG document.

    ``positions`` maps each joint (link pair) to a point, for example a
    kinematic solution; by default the skeleton layout places the joints.
    """
    layout = layout_from_positions(labelled, positions) if positions is not None else skeleton_layout(labelled)
    frame = Frame.fit(layout.positions, size, max(34.0, 0.15 * size))
    s = median_link_length(layout, frame)
    pts = [frame(p) for p in layout.positions]
    middle = (sum(p[0] for p in pts) / len(pts), sum(p[1] for p in pts) / len(pts))
    roles = labelled.roles
    kind = {k: labelled.joint_type(*e) for k, e in enumerate(layout.joints)}
    ground = [v for v in range(layout.n) if "ground" in roles[v]]
    members = _members(layout, roles, kind, ground)
    used_links = {v for _, u, w, _ in members for v in (u, w)}
    inside = {k for _, _, _, k in members}

    items: list[str] = [HATCH]
    for v in range(layout.n):
        if v in used_links:
            continue
        bar = len(layout.link_rings[v]) == 2
        if v in ground:
            style = {"fill": "url(#hatch)", "stroke": "#555555", "stroke-width": "2" if not bar else "5", "stroke-linecap": "round"}
        elif bar:
            style = {"stroke": INK, "stroke-width": "3.5", "stroke-linecap": "round"}
        else:
            style = {"fill": PLATE_FILL, "stroke": INK, "stroke-width": "2", "stroke-linejoin": "round"}
        items.extend(link_shape(layout, frame, v, style))
        if v in ground and bar:
            a, b = (pts[k] for k in layout.link_rings[v])
            items.extend(symbols.hatch_ticks(a, b, s, middle))

    for symbol, u, v, k in members:
        if k < 0:
            a, b = (pts[j] for j in layout.link_rings[u])
        else:
            a, b = _other_end(layout, frame, u, k), _other_end(layout, frame, v, k)
        m = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2)  # a member is straight: its middle joint on the line a-b
        group = {"class": f"member {symbol}", "data-links": f"{u}-{v}"}
        if symbol == "S":
            items.append(tag("g", group, symbols.spring(a, b, s)))
        elif symbol == "F":
            items.append(tag("g", group, symbols.force(a, m, b, s)))
        else:
            parts = symbols.cylinder(a, m, b, s, "shock-absorber" if symbol == "shock" else "cylinder")
            if symbol == "shock":
                parts += symbols.spring(a, b, s, "shock-spring", coil=(0.2, 0.8), amplitude=0.14)  # coil-over
            items.append(tag("g", group, parts))

    plain = []
    for k, (u, v) in enumerate(layout.joints):
        t, p = kind[k], pts[k]
        if k in inside:
            continue
        first = _carrier(layout, ground, u, v)
        if t == "P":
            items.append(tag("g", {"class": "joint-symbol P", "data-joint": f"{u}-{v}"}, symbols.slider(p, _direction(_other_end(layout, frame, first, k), p), s)))
        elif t in ("G", "C", "O"):
            draw = {"G": symbols.gear_pair, "C": symbols.cam_pair, "O": symbols.rolling_pair}[t]
            items.append(tag("g", {"class": f"joint-symbol {t}", "data-joint": f"{u}-{v}"}, draw(p, frame(layout.link_centres[first]), s)))
        else:
            plain.append(k)
            if t != "R":
                items.append(tag("text", {"class": "joint-letter", "x": num(p[0] + 6), "y": num(p[1] - 6), "font-size": "10", "font-weight": "bold", "font-family": "sans-serif", "fill": INK}, text=t))
        if u in ground or v in ground:
            items.extend(symbols.ground_pivot(p, s, middle))
    items.extend(joint_circles(layout, frame, plain))

    for v in range(layout.n):
        if "input" in roles[v]:
            pivots = [k for k in layout.link_rings[v] + layout.link_pins[v] if set(layout.joints[k]) & set(ground)]
            k = pivots[0] if pivots else layout.link_rings[v][0]
            items.extend(symbols.input_arrow(pts[k], s))
    items.extend(_role_labels(layout, frame, roles, members, numbers))
    return document(size, size, items, title=title)


def _members(layout: SkeletonLayout, roles, kind: dict[int, str], ground: list[int]) -> list[tuple[str, int, int, int]]:
    """Dyads and links drawn as one member: ``(symbol, link, link, middle joint)``.

    A pair of binary links (neither the ground) joined by an ``H``, ``S`` or
    ``F`` joint, or both with the role ``shock_absorber``; then any other
    binary shock-absorber link alone (middle joint ``-1``).
    """
    binary = [len(layout.link_rings[v]) == 2 and not layout.link_pins[v] and v not in ground for v in range(layout.n)]
    members, used = [], set()
    for k, (u, v) in enumerate(layout.joints):
        shock = "shock_absorber" in roles[u] and "shock_absorber" in roles[v]
        if (kind[k] in MEMBER_JOINTS or shock) and binary[u] and binary[v] and not {u, v} & used:
            members.append(("shock" if shock else kind[k], u, v, k))
            used |= {u, v}
    for v in range(layout.n):
        if "shock_absorber" in roles[v] and binary[v] and v not in used:
            members.append(("shock", v, v, -1))
            used.add(v)
    return members


def _carrier(layout: SkeletonLayout, ground: list[int], u: int, v: int) -> int:
    """The link carrying a joint's guide, cam or larger gear: the ground, else the one with more joints."""
    if (u in ground) != (v in ground):
        return u if u in ground else v
    return u if len(layout.link_rings[u]) >= len(layout.link_rings[v]) else v


def _direction(p: Point, q: Point) -> Point:
    dx, dy = q[0] - p[0], q[1] - p[1]
    return (dx, dy) if math.hypot(dx, dy) > 1e-9 else (1.0, 0.0)


def _role_labels(layout: SkeletonLayout, frame: Frame, roles, members, numbers: bool) -> list[str]:
    """Each link's roles (and number) written beside it; a two-link member is labelled once."""
    skip = {v for _, u, v, k in members if k >= 0 and u != v}
    items = []
    for v in range(layout.n):
        names = sorted(r.replace("_", " ") for r in roles[v])
        if v in skip:
            names = [n for n in names if n != "shock absorber"]
        text = ", ".join(([str(v)] if numbers else []) + names)
        if not text:
            continue
        x, y = label_point(layout, frame, v, 13.0)
        items.append(
            tag("text", {"class": "role", "data-link": str(v), "x": num(x), "y": num(y + 3.5), "font-size": "10", "text-anchor": "middle", "font-family": "sans-serif", "fill": "#6b2c00", "stroke": "#ffffff", "stroke-width": "3", "paint-order": "stroke"}, text=text)
        )
    return items
