"""Synthesised linkages drawn: a four-bar at each of its precision positions, a candidate beside its curve.

:func:`synthesis_html` makes the page of ``domes synthesize --format html``:
a card per solution. A four-bar is drawn at every precision position (the
first in full ink, the others fainter, in order) over the task's marks (the
body's positions with their angles, or the path points); a function
generator gets its structural error curve; a dimensioned candidate
(least squares) is drawn to scale beside its curve and the wanted one.

>>> svg = curve_svg([0, 1, 2], [("wanted", [1, 2, 3], "#2a9d8f", True), ("achieved", [1, 2.1, 3], "#c1121f", False)],
...                 "x", "y")
>>> svg.count("<polyline"), 'class="curve wanted"' in svg
(2, True)
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np

from domes.design.synthesis.candidate import Dimensioning
from domes.design.synthesis.task import GuidanceTask, PathTask
from domes.sketch.atlas import Card, atlas_html
from domes.sketch.dimensioned import dimensioned_svg
from domes.sketch.draw import Frame
from domes.sketch.svg import document, num, points, tag

SIZE = 360.0
INK = "#1d3557"
MARK = "#2a9d8f"


def precision_svg(solution, marks: Sequence = (), arrows: Sequence = (), size: float = SIZE) -> str:
    """A synthesised four-bar at each precision position, over ``marks`` (points) and ``arrows`` (point, angle)."""
    fb = solution.fourbar
    poses = solution.poses or ((fb.a1, fb.b1),)
    body = list(marks)
    b0 = getattr(fb, "b0", None)                  # None: a slider-crank, its slide drawn through the pin's positions
    pts = [fb.a0] + ([b0] if b0 else []) + [p for pose in poses for p in pose] + body + [a[0] for a in arrows]
    frame = Frame.fit(pts, size, 24.0)
    reach = 0.08 * max(np.ptp(np.array(pts), axis=0).max(), 1e-12)
    items = []
    for k, (a, b) in reversed(list(enumerate(poses))):
        opacity = "1" if k == 0 else f"{max(0.25, 0.7 - 0.1 * k):.2f}"
        style = {"fill": "none", "stroke": INK, "stroke-width": "2" if k == 0 else "1.2", "opacity": opacity,
                 "stroke-linejoin": "round"}
        coupler = [a, b] + ([body[k]] if k < len(body) and solution.fourbar.point is not None else [])
        items.append(tag("g", {"class": "pose", "data-position": str(k + 1)}, [
            tag("polyline", {"class": "crank", "points": points([frame(fb.a0), frame(a)]), **style}),
            tag("polygon", {"class": "coupler", "points": points(frame(p) for p in coupler), **style}),
            tag("polyline", {"class": "rocker", "points": points([frame(b), frame(b0)]), **style}) if b0 else
            tag("rect", {"class": "slider", "x": num(frame(b)[0] - 5), "y": num(frame(b)[1] - 4), "width": "10",
                         "height": "8", **style}),
            tag("text", {"x": num(frame(a)[0] + 4), "y": num(frame(a)[1] - 4), "font-size": "9", "fill": INK,
                         "opacity": opacity}, text=str(k + 1)),
        ]))
    if b0 is None:
        ends = sorted((pose[1] for pose in poses), key=lambda q: q[0] * math.cos(fb.direction)
                      + q[1] * math.sin(fb.direction))
        u = (math.cos(fb.direction), math.sin(fb.direction))
        (x1, y1), (x2, y2) = (frame((q[0] + k * reach * u[0], q[1] + k * reach * u[1]))
                              for q, k in ((ends[0], -1), (ends[-1], 1)))
        items.append(tag("line", {"class": "slide", "x1": num(x1), "y1": num(y1), "x2": num(x2), "y2": num(y2),
                                  "stroke": INK, "stroke-dasharray": "6 3"}))
    for p in (fb.a0, b0) if b0 else (fb.a0,):
        x, y = frame(p)
        items.append(tag("path", {"class": "ground-pivot", "d": f"M{num(x - 7)},{num(y + 9)} L{num(x)},{num(y)} "
                                  f"L{num(x + 7)},{num(y + 9)} Z", "fill": "#e9ecef", "stroke": INK}))
        items.append(tag("circle", {"cx": num(x), "cy": num(y), "r": "3.4", "fill": "#fff", "stroke": INK}))
    for p in body:
        x, y = frame(p)
        items.append(tag("circle", {"class": "wanted", "cx": num(x), "cy": num(y), "r": "3", "fill": MARK}))
    for p, angle in arrows:
        x, y = frame(p)
        ex, ey = frame((p[0] + reach * math.cos(angle), p[1] + reach * math.sin(angle)))
        items.append(tag("line", {"class": "wanted-angle", "x1": num(x), "y1": num(y), "x2": num(ex), "y2": num(ey),
                                  "stroke": MARK, "stroke-width": "2"}))
    return document(size, size, items, title="solution at its precision positions")


def curve_svg(x, series, xlabel: str, ylabel: str, size: float = SIZE) -> str:
    """A plot of ``series`` (``(label, values, colour, dashed)``) over ``x``, with its axes' ranges written."""
    x = np.asarray(x, dtype=float)
    ys = [np.asarray(s[1], dtype=float) for s in series]
    finite = np.concatenate([y[np.isfinite(y)] for y in ys] + [np.zeros(0)])
    lo, hi = (float(finite.min()), float(finite.max())) if finite.size else (0.0, 1.0)
    if hi - lo <= 1e-12 * max(1.0, abs(hi)):
        lo, hi = lo - 0.5, hi + 0.5
    left, right, top, bottom = 52.0, size - 12, 16.0, size - 40
    sx = lambda v: left + (v - x.min()) / max(np.ptp(x), 1e-300) * (right - left)   # noqa: E731
    sy = lambda v: bottom - (v - lo) / (hi - lo) * (bottom - top)                  # noqa: E731
    items = [tag("rect", {"x": num(left), "y": num(top), "width": num(right - left), "height": num(bottom - top),
                          "fill": "none", "stroke": "#adb5bd"})]
    for (label, _, colour, dashed), y in zip(series, ys):
        ok = np.isfinite(y)
        attrs = {"class": f"curve {label}", "fill": "none", "stroke": colour, "stroke-width": "1.6",
                 "points": points((sx(a), sy(b)) for a, b in zip(x[ok], y[ok]))}
        if dashed:
            attrs["stroke-dasharray"] = "6 4"
        items.append(tag("polyline", attrs))
    for k, (label, _, colour, dashed) in enumerate(series):
        items.append(tag("text", {"x": num(left + 8), "y": num(top + 14 + 13 * k), "font-size": "11",
                                  "fill": colour}, text=label + (" (dashed)" if dashed else "")))
    for text, xx, yy, anchor in ((f"{x.min():.4g}", left, bottom + 14, "start"),
                                 (f"{x.max():.4g}", right, bottom + 14, "end"),
                                 (xlabel, (left + right) / 2, bottom + 30, "middle"),
                                 (f"{hi:.4g}", left - 4, top + 10, "end"), (f"{lo:.4g}", left - 4, bottom, "end")):
        items.append(tag("text", {"x": num(xx), "y": num(yy), "font-size": "11", "text-anchor": anchor,
                                  "fill": INK}, text=text))
    items.append(tag("text", {"x": "12", "y": num((top + bottom) / 2), "font-size": "11", "fill": INK,
                              "transform": f"rotate(-90 12 {num((top + bottom) / 2)})", "text-anchor": "middle"},
                     text=ylabel))
    return document(size, size, items, title=f"{ylabel} over {xlabel}")


def synthesis_html(result, task) -> str:
    """The page of a synthesis result: a card per solution (rejected ones marked with their reasons)."""
    if isinstance(result, Dimensioning):
        cards = [_candidate_card(k, s, task) for k, s in enumerate(result.solutions, 1)]
    else:
        marks, arrows = (), ()
        if isinstance(task, GuidanceTask):
            marks = [p.point for p in task.positions]
            arrows = [(p.point, p.angle) for p in task.positions]
        elif isinstance(task, PathTask):
            marks = list(task.points)
        cards = [_fourbar_card(k, s, marks, arrows) for k, s in enumerate(result.solutions, 1)]
    summary = result.message + "".join(f"; {n}" for n in result.notes)
    return atlas_html(cards, f"Dimensional synthesis: {result.task_name}", summary)


def _fourbar_card(k, s, marks, arrows) -> Card:
    svg = precision_svg(s, marks, arrows)
    if s.structural is not None and np.isfinite(s.structural.error).any():
        svg += "\n" + curve_svg(s.structural.x, [("structural error", np.degrees(s.structural.error), "#c1121f",
                                                  False)], "x", "error (° of rocker rotation)")
    props = [("lengths", ", ".join(f"{name} {v:.6g}" for name, v in s.fourbar.named_lengths().items())),
             ("Grashof", s.checks.grashof), ("transmission", f"{s.checks.min_transmission_deg:.1f}° smallest"),
             ("residual", f"{s.residual:.1e}")]
    props += [("defect", x) for x in s.defects] + [("warning", x) for x in s.warnings]
    return Card(str(k), f"solution {k}", svg, tuple(props), None if s.usable else "rejected")


def _candidate_card(k, s, task) -> Card:
    xlabel = "rise of " + task.point_name if task.quantity == "leverage" else "input rotation (°)"
    svg = dimensioned_svg(s.mechanism) + "\n" + curve_svg(
        s.x, [("achieved", s.achieved, "#c1121f", False), ("wanted", s.wanted, MARK, True)], xlabel, task.quantity)
    props = [("candidate", str(s.candidate)), ("curve error", f"{100 * s.error:.3g}% largest, {100 * s.rms:.3g}% RMS"),
             ("transmission", f"{s.min_transmission_deg:.1f}° smallest")]
    if s.length is not None:
        props.append(("length", f"{s.length[0]:.4g} to {s.length[1]:.4g}"))
    props += [("defect", x) for x in s.defects]
    return Card(str(k), f"candidate {s.candidate}", svg, tuple(props), None if s.usable else "rejected")
