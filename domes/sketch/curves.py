"""Coupler curves drawn: a mechanism moving along a circuit, its curve, and a wanted path over it.

:func:`moving_svg` draws a mechanism's links at the poses of one traced
circuit and animates them (SVG ``<animate>``, no script), with the coupler
curve and, for a match, the wanted points; :func:`curves_html` puts such
drawings on one page, a card each (the page of :mod:`domes.sketch.atlas`).

>>> from domes.motion.coupler.fourbar import four_bar
>>> from domes.motion.coupler.curves import trace
>>> m = four_bar(1, 3.5, 2.5, 3, 1.0, 0.8)
>>> svg = moving_svg(m, trace(m, "P", 90, extra=joint_names(m)).circuits[0])
>>> svg.count("<animate "), 'class="coupler-curve"' in svg
(24, True)

:func:`animated_svg` does the same for any joint tracks (a dimensioned design moving through its stroke).
"""

from __future__ import annotations

import numpy as np

from domes.model.mechanism import Mechanism
from domes.sketch.atlas import Card, atlas_html
from domes.sketch.draw import Frame
from domes.sketch.svg import document, num, points, tag

SIZE = 360.0
#: Poses in one cycle of the animation.
FRAMES = 72
#: Seconds for one cycle.
SECONDS = 6


def joint_names(mech: Mechanism) -> tuple[str, ...]:
    """The joints a drawing follows (each joint once, compound hinges by their first name)."""
    seen, out = set(), []
    for j in mech.joints:
        if j.at not in seen:
            seen.add(j.at)
            out.append(j.name)
    return tuple(out)


def moving_svg(mech: Mechanism, circuit, wanted=None, size: float = SIZE, point: str = "P") -> str:
    """The mechanism animated along ``circuit`` (traced with ``extra=joint_names(mech)``), its curve and ``wanted``."""
    pts = circuit.points
    frames = np.unique(np.linspace(0, len(pts) - 1, min(FRAMES, len(pts))).astype(int))
    tracks = {name: np.asarray(circuit.extra[name])[frames] for name in circuit.extra}
    tracks[point] = np.asarray(pts)[frames]
    return animated_svg(mech, tracks, path=np.vstack([pts, pts[:1]]), wanted=wanted, size=size, point=point)


def animated_svg(mech: Mechanism, tracks, path=None, wanted=None, size: float = SIZE, point: str | None = None,
                 seconds: float = SECONDS, title: str | None = None) -> str:
    """The mechanism's links moving through the poses of ``tracks`` (joint or point name -> ``(F, 2)``
    positions, one row per frame; SVG ``<animate>``, no script), with a ``path`` drawn under it and ``wanted``
    points; ``point`` is a coupler point that moves with its link."""
    everything = [tuple(p) for arr in tracks.values() for p in np.asarray(arr)]
    if path is not None:
        everything += [tuple(p) for p in np.asarray(path)]
    if wanted is not None:
        everything += [tuple(p) for p in np.asarray(wanted)]
    frame = Frame.fit(everything, size, 18.0)
    items = []
    if path is not None:
        items.append(tag("polyline", {"class": "coupler-curve", "points": points(frame(tuple(p)) for p in np.asarray(path)),
                                      "fill": "none", "stroke": "#c1121f", "stroke-width": "1.2"}))
    if wanted is not None:
        for p in np.asarray(wanted):
            x, y = frame(tuple(p))
            items.append(tag("circle", {"class": "wanted", "cx": num(x), "cy": num(y), "r": "2.2", "fill": "#2a9d8f"}))
    dur = f"{seconds:g}s"

    def moving(attr, values):
        return tag("animate", {"attributeName": attr, "values": ";".join(num(v) for v in values), "dur": dur,
                               "repeatCount": "indefinite"})

    def track(name):
        return np.array([frame(tuple(p)) for p in np.asarray(tracks[name])])

    grounded = {j.name for j in mech.joints if mech.ground in j.links}
    first = {}
    for j in mech.joints:  # joints drawn at one place (a compound hinge, a block's pin and slide) are drawn once
        first.setdefault(j.at, j.name)
    for link in mech.links:
        if link == mech.ground:
            continue
        names = list(dict.fromkeys(first[j.at] for j in mech.joints if link in j.links and first[j.at] in tracks))
        if point is not None and point in tracks and mech.point(point)[0] == link and point not in names:
            names.append(point)
        xy = {n: track(n) for n in names}
        for a, b in zip(names, names[1:] + names[:1] if len(names) > 2 else names[1:]):
            ta, tb = xy[a], xy[b]
            kids = [moving("x1", ta[:, 0]), moving("y1", ta[:, 1]), moving("x2", tb[:, 0]), moving("y2", tb[:, 1])]
            items.append(tag("line", {"class": "link", "x1": num(ta[0, 0]), "y1": num(ta[0, 1]), "x2": num(tb[0, 0]),
                                      "y2": num(tb[0, 1]), "stroke": "#1d3557", "stroke-width": "2.5",
                                      "stroke-linecap": "round"}, kids))
    for name in tracks:
        if name == point:
            continue
        t = track(name)
        if name in grounded:
            items.append(tag("rect", {"class": "pivot", "x": num(t[0, 0] - 4), "y": num(t[0, 1] - 4), "width": "8",
                                      "height": "8", "fill": "#1d3557"}))
        else:
            items.append(tag("circle", {"class": "joint", "cx": num(t[0, 0]), "cy": num(t[0, 1]), "r": "3",
                                        "fill": "#fff", "stroke": "#1d3557"},
                             [moving("cx", t[:, 0]), moving("cy", t[:, 1])]))
    return document(size, size, items, title=title or mech.name)


def curves_html(cards, title: str, summary: str = "") -> str:
    """A page of curve cards (:class:`~domes.sketch.atlas.Card`)."""
    return atlas_html(cards, title, summary)


__all__ = ["Card", "curves_html", "joint_names", "moving_svg"]
