"""Chain drawings: the mechanism skeleton (and optionally the abstract graph) as SVG.

Every drawn item carries its meaning in attributes, so a program can read
the drawing back: a link is a ``line`` (bar) or ``polygon`` (plate) of class
``link`` with ``data-link``; a joint is a ``circle`` of class ``joint`` with
``data-joint="u-v"``.

>>> from domes.model import Chain
>>> svg = chain_svg(Chain.from_graph6("Cr"))
>>> svg.count('class="link bar"'), svg.count('class="joint"')
(4, 4)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Iterable, Sequence

from domes.sketch.layout import Point, SkeletonLayout, skeleton_layout
from domes.sketch.svg import document, num, points, tag

#: Default drawing size (user units, = CSS pixels).
SIZE = 220.0
INK = "#1d3557"
PLATE_FILL = "#d8e2f0"
JOINT_RADIUS = 3.6


@dataclass(frozen=True)
class Frame:
    """Maps layout coordinates (y up) into a square SVG box (y down) with a margin."""

    scale: float
    x0: float
    y0: float
    left: float
    top: float
    size: float

    @classmethod
    def fit(cls, pts: Iterable[Point], size: float, margin: float, left: float = 0.0) -> "Frame":
        pts = list(pts)
        xs, ys = [p[0] for p in pts], [p[1] for p in pts]
        span = max(max(xs) - min(xs), max(ys) - min(ys), 1e-9)
        scale = (size - 2 * margin) / span
        pad_x = (size - (max(xs) - min(xs)) * scale) / 2
        pad_y = (size - (max(ys) - min(ys)) * scale) / 2
        return cls(scale, min(xs), max(ys), left + pad_x, pad_y, size)

    def __call__(self, p: Point) -> Point:
        return (self.left + (p[0] - self.x0) * self.scale, self.top + (self.y0 - p[1]) * self.scale)


def median_link_length(layout: SkeletonLayout, frame: Frame) -> float:
    """The median link size (:meth:`SkeletonLayout.link_lengths`) in drawing units."""
    sizes = sorted(layout.link_lengths())
    middle = len(sizes) // 2
    value = sizes[middle] if len(sizes) % 2 else (sizes[middle - 1] + sizes[middle]) / 2
    return value * frame.scale


def link_shape(layout: SkeletonLayout, frame: Frame, v: int, attrs: dict[str, str]) -> list[str]:
    """Link ``v`` as a bar (line) or plate (polygon), plus arms to pins off its outline."""
    ring = [frame(layout.positions[k]) for k in layout.link_rings[v]]
    base = {"data-link": str(v), **attrs}
    if len(ring) == 2:
        (x1, y1), (x2, y2) = ring
        items = [tag("line", {"class": "link bar", "x1": num(x1), "y1": num(y1), "x2": num(x2), "y2": num(y2), **base})]
    else:
        items = [tag("polygon", {"class": "link plate", "points": points(ring), **base})]
    centre = frame(layout.link_centres[v])
    for k in layout.link_pins[v]:
        pin = frame(layout.positions[k])
        if math.dist(pin, centre) > 1e-6:
            items.append(
                tag("line", {"class": "link arm", "x1": num(centre[0]), "y1": num(centre[1]), "x2": num(pin[0]), "y2": num(pin[1]), **base})
            )
    return items


def joint_circles(layout: SkeletonLayout, frame: Frame, which: Sequence[int] | None = None) -> list[str]:
    """Small circles at the joints (all, or the given joint indices)."""
    items = []
    for k in range(len(layout.joints)) if which is None else which:
        x, y = frame(layout.positions[k])
        u, v = layout.joints[k]
        items.append(
            tag("circle", {"class": "joint", "data-joint": f"{u}-{v}", "cx": num(x), "cy": num(y), "r": num(JOINT_RADIUS), "fill": "#ffffff", "stroke": INK, "stroke-width": "1.5"})
        )
    return items


def label_point(layout: SkeletonLayout, frame: Frame, v: int, offset: float) -> Point:
    """Where to write about link ``v``: its centre, moved off a bar sideways by ``offset``."""
    cx, cy = frame(layout.link_centres[v])
    ring = layout.link_rings[v]
    if len(ring) != 2:
        return cx, cy
    (x1, y1), (x2, y2) = (frame(layout.positions[k]) for k in ring)
    length = math.hypot(x2 - x1, y2 - y1) or 1.0
    nx_, ny_ = -(y2 - y1) / length, (x2 - x1) / length
    if ny_ > 0 or (ny_ == 0 and nx_ > 0):
        nx_, ny_ = -nx_, -ny_  # write above the bar
    return cx + offset * nx_, cy + offset * ny_


def skeleton_items(layout: SkeletonLayout, frame: Frame, numbers: bool = True) -> list[str]:
    """The links, joints and link numbers of a chain drawing."""
    items = []
    for v in range(layout.n):
        style = {"fill": PLATE_FILL, "stroke": INK, "stroke-width": "2", "stroke-linejoin": "round"}
        if len(layout.link_rings[v]) == 2:
            style = {"stroke": INK, "stroke-width": "3.5", "stroke-linecap": "round"}
        items.extend(link_shape(layout, frame, v, style))
    items.extend(joint_circles(layout, frame))
    if numbers:
        for v in range(layout.n):
            x, y = label_point(layout, frame, v, 8.0)
            items.append(
                tag("text", {"class": "link-number", "x": num(x), "y": num(y + 3.5), "font-size": "10", "text-anchor": "middle", "font-family": "sans-serif", "fill": "#6b2c00"}, text=str(v))
            )
    return items


def graph_items(layout: SkeletonLayout, frame: Frame) -> list[str]:
    """The abstract graph (links as vertices) on the same planar geometry.

    A vertex sits at its link's centre; the edge of joint ``u-v`` runs from
    ``u``'s centre through the joint to ``v``'s centre, inside the two links,
    so a planar layout gives a planar graph drawing.
    """
    items = []
    for k, (u, v) in enumerate(layout.joints):
        path = [frame(layout.link_centres[u]), frame(layout.positions[k]), frame(layout.link_centres[v])]
        items.append(tag("polyline", {"class": "graph-edge", "data-joint": f"{u}-{v}", "points": points(path), "fill": "none", "stroke": "#7a7a7a", "stroke-width": "1.5"}))
    for v in range(layout.n):
        x, y = frame(layout.link_centres[v])
        items.append(tag("circle", {"class": "graph-vertex", "data-link": str(v), "cx": num(x), "cy": num(y), "r": "7", "fill": "#ffffff", "stroke": INK, "stroke-width": "1.5"}))
        items.append(tag("text", {"x": num(x), "y": num(y + 3.5), "font-size": "9", "text-anchor": "middle", "font-family": "sans-serif", "fill": INK}, text=str(v)))
    return items


def chain_svg(chain, layout: SkeletonLayout | None = None, *, size: float = SIZE, graph: bool = False, numbers: bool = True, title: str | None = None) -> str:
    """A chain drawn as a mechanism skeleton, as an SVG document.

    ``graph=True`` adds the abstract graph (links as vertices) beside it;
    ``numbers`` writes each link's number. Same input, same bytes.

    >>> from domes.typesynth import chains
    >>> svg = chain_svg(chains(links=6, dof=1)[1], graph=True)
    >>> svg.count('class="link plate"'), svg.count('class="graph-vertex"')
    (2, 6)
    """
    layout = layout or skeleton_layout(chain)
    frame = Frame.fit(layout.positions, size, 14.0)
    items = [tag("g", {"class": "skeleton"}, skeleton_items(layout, frame, numbers))]
    width = size
    if graph:
        frame2 = Frame.fit(list(layout.positions) + list(layout.link_centres), size, 14.0, left=size)
        items.append(tag("g", {"class": "graph"}, graph_items(layout, frame2)))
        width = 2 * size
    return document(width, size, items, title=title)
