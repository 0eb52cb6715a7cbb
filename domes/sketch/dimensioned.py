"""Dimensioned drawings: a mechanism file drawn to scale at an input, with its coupler curves.

The joint positions come from the kinematics backend (:mod:`domes.motion`):
:func:`pose` solves the mechanism at one value of its (first) input,
:func:`coupler_curves` sweeps that input and traces named points, and
:func:`dimensioned_svg` draws both. Links are drawn through their joints
and coupler points (a bar for two points, a plate for more), the ground
hatched with a fixed pivot at each of its R joints, P joints as a slider
block on a rail that starts at the guide's slide origin (or as
cylinder-and-rod), the input marked with an arrow, every side with its
length. A curve stops where its sweep
stops (a limit or other dead point, marked with a cross); it is closed only
when the input turns fully and the point comes back to where it started.

>>> from domes.motion.planar.examples import four_bar
>>> p = pose(four_bar(), math.radians(90))
>>> [round(c, 12) for c in p.joints["B"]]
[0.0, 1.0]
>>> svg = dimensioned_svg(four_bar(), math.radians(90), coupler=["C"])
>>> svg.count('class="joint"'), svg.count('class="coupler-curve closed"')
(4, 1)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Mapping, Sequence

from domes.errors import DomesError, InputError
from domes.motion import CouplerPoint, DeadPoint, Kinematics, Mechanism, solve, sweep
from domes.results import Status
from domes.sketch import symbols
from domes.sketch.draw import INK, PLATE_FILL, Frame
from domes.sketch.mechanism import HATCH
from domes.sketch.svg import document, num, path_data, points, tag

Point = tuple[float, float]
#: Default drawing size (user units).
SIZE = 400.0
#: Halvings of a sweep step at most, where a traced point moves more than ``step · size`` in one step.
REFINE_DEPTH = 12
#: Colours of successive coupler curves.
CURVE_COLOURS = ("#c1121f", "#2a9d8f", "#e76f51", "#6a4c93", "#1982c4")


@dataclass(frozen=True)
class Pose:
    """The mechanism solved at one input value.

    ``joints``: each joint's position (for a P joint the slider's point);
    ``points``: each coupler point's; ``guides``: for each P joint the
    guide's slide origin and the slide direction (a unit vector), both as
    they are carried by the guide at this input.
    """

    input: float
    joints: Mapping[str, Point]
    points: Mapping[str, Point]
    guides: Mapping[str, tuple[Point, Point]]
    residual: float
    condition: float


@dataclass(frozen=True)
class CouplerCurve:
    """The path of one point over a sweep: a polyline, closed, or begun and ended at dead points or the sweep's ends.

    ``first`` and ``last`` are the dead points where the path begins and
    ends (``None`` where it ends because the sweep's range does).
    """

    point: str
    path: tuple[Point, ...]
    closed: bool
    first: DeadPoint | None = None
    last: DeadPoint | None = None

    @property
    def stops(self) -> tuple[DeadPoint, ...]:
        """The dead points that end the curve."""
        return tuple(d for d in (self.first, self.last) if d is not None)


def _with_guide_points(mech: Mechanism) -> tuple[Mechanism, dict[str, tuple[str, str]]]:
    """``mech`` with two points on the guide of each P joint (its slide origin, and one ``size`` along the slide)."""
    taken = {j.name for j in mech.joints} | {p.name for p in mech.points}
    extra, names = [], {}
    for j in mech.joints:
        if j.kind != "P":
            continue
        ox, oy = j.slide_origin
        ahead = (ox + mech.size * math.cos(j.direction), oy + mech.size * math.sin(j.direction))
        pair = []
        for what, at in (("origin", (ox, oy)), ("ahead", ahead)):
            name = f"{j.name}/{what}"
            while name in taken:
                name += "'"
            taken.add(name)
            extra.append(CouplerPoint(name, j.links[0], at))
            pair.append(name)
        names[j.name] = (pair[0], pair[1])
    return dataclasses.replace(mech, points=mech.points + tuple(extra)), names


def pose(mech: Mechanism, q: float | None = None, *, accuracy=None) -> Pose:
    """Every joint and coupler point of ``mech`` at input ``q`` (rad, or length for a P input; default the drawn pose).

    The pose is reached from the drawn pose by continuation, so it is on the
    drawn assembly mode; an input that cannot be reached raises
    :class:`~domes.errors.DomesError` naming the group and joints.
    """
    traced, guide_points = _with_guide_points(mech)
    names = [j.name for j in mech.joints] + [p.name for p in traced.points]
    step = solve(traced, q, outputs=[f"point:{n}" for n in names], accuracy=accuracy)
    at = {n: (step.values[f"point:{n}.x"], step.values[f"point:{n}.y"]) for n in names}
    guides = {}
    for joint, (origin, ahead) in guide_points.items():
        (ox, oy), (ax, ay) = at[origin], at[ahead]
        length = math.hypot(ax - ox, ay - oy)
        guides[joint] = ((ox, oy), ((ax - ox) / length, (ay - oy) / length))
    joints = {j.name: at[j.name] for j in mech.joints}
    coupler = {p.name: at[p.name] for p in mech.points}
    return Pose(step.inputs[mech.inputs[0].joint], joints, coupler, guides, step.residual, step.condition)


def _end_point(mech: Mechanism, outputs: list[str], dead: DeadPoint, start: float, accuracy):
    """The traced points at a located dead point, solved just on the reachable side (``None`` if that fails)."""
    q = dead.input - math.copysign(dead.within, dead.input - start)
    try:
        return solve(mech, q, outputs=outputs, accuracy=accuracy)
    except DomesError:
        return None  # the last solved step ends the curve


def coupler_curves(mech: Mechanism, names: Sequence[str], span: tuple[float, float, float | None] | None = None, *, accuracy=None) -> tuple[CouplerCurve, ...]:
    """Trace the points ``names`` (coupler points or joints) while the first input moves.

    ``span = (start, stop, step)`` sweeps that range (rad, or lengths for a P
    input; ``step=None`` takes the accuracy's resolution). By default an R
    input turns a full turn forward from the drawn pose and, if it stops at
    a dead point, a full turn backward too, so the curve runs from dead point
    to dead point; a P input moves ``size`` each way. A curve ends at the
    located dead point where its sweep stops. Where a traced point moves
    more than ``step · size`` (rad × length) in one step, as near a limit of
    a P input, the step is halved (up to :data:`REFINE_DEPTH` times).

    >>> from domes.motion.planar.examples import triple_rocker
    >>> (curve,) = coupler_curves(triple_rocker(), ["B"])
    >>> curve.closed, [str(d.kind) for d in curve.stops]
    (False, ['limit', 'limit'])
    """
    if not names:
        return ()
    known = [j.name for j in mech.joints] + [p.name for p in mech.points]
    for name in names:
        if name not in known:
            raise InputError(f"{mech.source or mech.name}: no coupler point or joint {name!r} to trace; there are {', '.join(known)}")
    # Every joint is solved too: the whole mechanism must assemble, not only the links carrying the points.
    outputs = list(dict.fromkeys([f"point:{n}" for n in names] + [f"point:{j.name}" for j in mech.joints]))
    q0 = pose_input(mech)
    angular = mech.joint(mech.inputs[0].joint).kind == "R"
    reach = 2 * math.pi if angular else mech.size
    if span is not None:
        runs = [sweep(mech, span[0], span[1], span[2], outputs=outputs, accuracy=accuracy)]
    else:
        runs = [sweep(mech, q0, q0 + reach, outputs=outputs, accuracy=accuracy)]
        if runs[0].status is not Status.COMPLETE or not angular:
            runs.insert(0, sweep(mech, q0, q0 - reach, outputs=outputs, accuracy=accuracy))
    steps, first, last = [], None, None
    for k, run in enumerate(runs):
        start = run.steps[0].inputs[run.joint] if run.steps else q0
        stop = next((d for d in run.dead_points if d.stops), None) if run.status is Status.STOPPED else None
        found = list(run.steps)
        end = _end_point(mech, outputs, stop, start, accuracy) if stop else None
        if end is not None:
            found.append(end)
        if k == 0 and len(runs) == 2:
            steps += found[::-1][:-1]  # the backward run, reversed, without its first step (the drawn pose)
            first = stop
        else:
            steps += found
            last = stop
    kin = Kinematics(mech, outputs, accuracy=accuracy)
    chord = kin.accuracy.step * mech.size
    joint = mech.inputs[0].joint
    refined = steps[:1]
    for step in steps[1:]:
        refined += _fill(kin, joint, refined[-1], step, names, chord, REFINE_DEPTH)
    curves = []
    for name in names:
        path = [(st.values[f"point:{name}.x"], st.values[f"point:{name}.y"]) for st in refined]
        closed = span is None and angular and first is None and last is None and len(path) > 2 and math.dist(path[0], path[-1]) <= 1e-6 * mech.size
        curves.append(CouplerCurve(name, tuple(path[:-1] if closed else path), closed, first, last))
    return tuple(curves)


def _fill(kin: Kinematics, joint: str, a, b, names: Sequence[str], chord: float, depth: int) -> list:
    """Steps after ``a`` up to ``b``: halves of the input step while a traced point moves more than ``chord``."""
    far = max(math.dist((a.values[f"point:{n}.x"], a.values[f"point:{n}.y"]), (b.values[f"point:{n}.x"], b.values[f"point:{n}.y"])) for n in names)
    if far <= chord or depth == 0:
        return [b]
    try:
        middle = kin.at({**a.inputs, joint: (a.inputs[joint] + b.inputs[joint]) / 2}, a.state)
    except DomesError:
        return [b]
    return _fill(kin, joint, a, middle, names, chord, depth - 1) + _fill(kin, joint, middle, b, names, chord, depth - 1)


def pose_input(mech: Mechanism) -> float:
    """The value of the first input in the drawn pose."""
    return Kinematics(mech).drawn_inputs()[mech.inputs[0].joint]


def _cylinders(mech: Mechanism) -> dict[str, tuple[str, str]]:
    """P joints drawn as cylinder-and-rod (Table 3-5): between two moving links that have one R joint each.

    Maps the P joint to the cylinder's pivot (the guide's R joint) and the rod's end (the slider's).
    """
    out = {}
    for j in mech.joints:
        if j.kind != "P" or mech.ground in j.links:
            continue
        others = [[k for k in mech.joints_of(x) if k.name != j.name] for x in j.links]
        if all(len(o) == 1 and o[0].kind == "R" for o in others):
            out[j.name] = (others[0][0].name, others[1][0].name)
    return out


def _outline(mech: Mechanism, p: Pose, link: str) -> list[Point]:
    """The points a link is drawn through: its joints (a guide's slide origin for its P joints) and coupler points."""
    pts = []
    for j in mech.joints_of(link):
        pts.append(p.guides[j.name][0] if j.kind == "P" and j.links[0] == link else p.joints[j.name])
    pts += [p.points[c.name] for c in mech.points if c.link == link]
    unique: list[Point] = []
    for q in pts:
        if all(math.dist(q, u) > 1e-9 * mech.size for u in unique):
            unique.append(q)
    if len(unique) > 2:
        cx, cy = sum(q[0] for q in unique) / len(unique), sum(q[1] for q in unique) / len(unique)
        unique.sort(key=lambda q: math.atan2(q[1] - cy, q[0] - cx))
    return unique


def dimensioned_svg(
    mech: Mechanism,
    q: float | None = None,
    *,
    coupler: Sequence[str] = (),
    span: tuple[float, float, float | None] | None = None,
    accuracy=None,
    size: float = SIZE,
    dimensions: bool = True,
) -> str:
    """``mech`` drawn to scale at input ``q`` (default: the drawn pose), with the coupler curves of ``coupler``.

    See :func:`pose` and :func:`coupler_curves` for ``q``, ``span`` and
    ``accuracy``. ``dimensions`` writes the length of every bar and plate
    side (distances between the points a link is drawn through). Same input,
    same bytes.
    """
    p = pose(mech, q, accuracy=accuracy)
    curves = coupler_curves(mech, coupler, span, accuracy=accuracy)
    outlines = {link: _outline(mech, p, link) for link in mech.links}
    cylinders = _cylinders(mech)
    rails = {name: (origin, p.joints[name]) for name, (origin, _) in p.guides.items() if name not in cylinders}
    fitted = [pt for pts in outlines.values() for pt in pts] + [pt for c in curves for pt in c.path]
    for m in mech.meshes():  # the pitch circles are drawn whole
        for pivot, r in zip(m.pivots, m.radii):
            if pivot is not None:
                x, y = p.joints[pivot]
                fitted += [(x - r, y - r), (x + r, y + r)]
    frame = Frame.fit(fitted + [pt for rail in rails.values() for pt in rail], size, max(40.0, 0.12 * size))
    sides = sorted(math.dist(a, b) for pts in outlines.values() for a, b in _sides(pts))
    s = min(max(sides[len(sides) // 2] * frame.scale if sides else 0.0, 0.08 * size), 0.16 * size)  # symbol scale
    middle = tuple(sum(c) / len(fitted) for c in zip(*(frame(pt) for pt in fitted)))

    items: list[str] = [HATCH]
    in_cylinders = {x for name in cylinders for x in mech.joint(name).links}
    for link in mech.links:
        if link not in in_cylinders:
            items.extend(_link_items(link, [frame(q) for q in outlines[link]], link == mech.ground, s, middle))
    for name, (a, b) in cylinders.items():
        ends = frame(p.joints[a]), frame(p.joints[name]), frame(p.joints[b])
        items.append(tag("g", {"class": "member cylinder", "data-joint": name, "data-links": "-".join(mech.joint(name).links)}, symbols.cylinder(*ends, s)))
    for k, curve in enumerate(curves):
        items.extend(_curve_items(curve, frame, CURVE_COLOURS[k % len(CURVE_COLOURS)], s))
    if dimensions:
        for link in mech.links:
            if link not in in_cylinders:
                items.extend(_dimensions(link, outlines[link], frame))
    for name, (origin, at) in rails.items():
        j = mech.joint(name)
        items.append(tag("line", {"class": "slider-rail", "data-link": j.links[0], "x1": num(frame(origin)[0]), "y1": num(frame(origin)[1]), "x2": num(frame(at)[0]), "y2": num(frame(at)[1]), "stroke": INK, "stroke-width": "2", "stroke-dasharray": "6 3"}))
        d = p.guides[name][1]
        items.append(tag("g", {"class": "joint-symbol P", "data-joint": name}, symbols.slider(frame(at), (d[0], -d[1]), s)))
    items.extend(_pitch_items(mech, p, frame))
    for j in mech.joints:
        if j.kind == "R" and mech.ground in j.links:
            items.extend(symbols.ground_pivot(frame(p.joints[j.name]), s, middle))
    driven = mech.joint(mech.inputs[0].joint)
    if driven.kind == "R":
        items.extend(symbols.input_arrow(frame(p.joints[driven.name]), s))
    for j in mech.joints:
        x, y = frame(p.joints[j.name])
        if j.kind == "R":
            items.append(tag("circle", {"class": "joint", "data-joint": j.name, "cx": num(x), "cy": num(y), "r": "3.6", "fill": "#ffffff", "stroke": INK, "stroke-width": "1.5"}))
        items.append(_label(x + 6, y - 6, j.name, "joint-name", {"data-joint": j.name}))
    for c in mech.points:
        x, y = frame(p.points[c.name])
        items.append(tag("circle", {"class": "coupler-point", "data-point": c.name, "cx": num(x), "cy": num(y), "r": "3", "fill": "#c1121f"}))
        items.append(_label(x + 6, y - 6, c.name, "point-name", {"data-point": c.name}))
    unit = "°" if driven.kind == "R" else ""
    value = math.degrees(p.input) if driven.kind == "R" else p.input
    caption = f"{driven.name} = {value:.6g}{unit}"
    items.append(_label(8, 16, caption, "pose-caption", {}, size="12"))
    return document(size, size, items, title=f"{mech.name}: {caption}")


def _pitch_items(mech: Mechanism, p: Pose, frame: Frame) -> list[str]:
    """Each gear pair's pitch circles (dash-dot) about the gears' pivots; a rack's pitch line through the pinion's."""
    items = []
    for m in mech.meshes():
        attrs = {"class": "pitch", "data-gear-pair": m.pair.name, "fill": "none", "stroke": INK,
                 "stroke-width": "1.2", "stroke-dasharray": "6 2 1 2"}
        for pivot, r in zip(m.pivots, m.radii):
            if pivot is not None:
                x, y = frame(p.joints[pivot])
                items.append(tag("circle", {**attrs, "cx": num(x), "cy": num(y), "r": num(r * frame.scale)}))
    return items


def _label(x: float, y: float, text: str, cls: str, attrs: dict, size: str = "10") -> str:
    base = {"class": cls, **attrs, "x": num(x), "y": num(y), "font-size": size, "font-family": "sans-serif", "fill": "#6b2c00", "stroke": "#ffffff", "stroke-width": "3", "paint-order": "stroke"}
    return tag("text", base, text=text)


def _link_items(link: str, pts: list[Point], grounded: bool, s: float, middle: Point) -> list[str]:
    """A link as a bar or plate through its points, hatched (a bar also with hatch strokes) when it is the ground."""
    if len(pts) < 2:
        return []
    if grounded:
        style = {"fill": "url(#hatch)", "stroke": "#555555", "stroke-width": "5" if len(pts) == 2 else "2", "stroke-linecap": "round"}
    elif len(pts) == 2:
        style = {"stroke": INK, "stroke-width": "3.5", "stroke-linecap": "round"}
    else:
        style = {"fill": PLATE_FILL, "fill-opacity": "0.8", "stroke": INK, "stroke-width": "2", "stroke-linejoin": "round"}
    if len(pts) > 2:
        return [tag("polygon", {"class": "link plate", "data-link": link, "points": points(pts), **style})]
    (x1, y1), (x2, y2) = pts
    items = [tag("line", {"class": "link bar", "data-link": link, "x1": num(x1), "y1": num(y1), "x2": num(x2), "y2": num(y2), **style})]
    if grounded:
        items.extend(symbols.hatch_ticks(pts[0], pts[1], s, middle))
    return items


def _sides(pts: list[Point]) -> list[tuple[Point, Point]]:
    """The sides of an outline: one for a bar, all around a plate."""
    return list(zip(pts, pts[1:] + pts[:1])) if len(pts) > 2 else list(zip(pts, pts[1:]))


def _dimensions(link: str, pts: list[Point], frame: Frame) -> list[str]:
    """The length of each side of a link's outline (in the file's unit), written beside the side's middle."""
    items = []
    for a, b in _sides(pts):
        (x1, y1), (x2, y2) = frame(a), frame(b)
        length = math.hypot(x2 - x1, y2 - y1)
        if length < 1e-9:
            continue
        nx_, ny_ = -(y2 - y1) / length, (x2 - x1) / length
        if ny_ > 0 or (ny_ == 0 and nx_ > 0):
            nx_, ny_ = -nx_, -ny_  # above the side
        x, y = (x1 + x2) / 2 + 9 * nx_, (y1 + y2) / 2 + 9 * ny_
        attrs = {"class": "dimension", "data-link": link, "x": num(x), "y": num(y + 3), "font-size": "9", "text-anchor": "middle", "font-family": "sans-serif", "fill": "#555555", "stroke": "#ffffff", "stroke-width": "2.5", "paint-order": "stroke"}
        items.append(tag("text", attrs, text=f"{math.dist(a, b):.4g}"))
    return items


def _curve_items(curve: CouplerCurve, frame: Frame, colour: str, s: float) -> list[str]:
    """The curve as a polyline (its first point repeated when closed), a cross at each end where its sweep stopped."""
    path = [frame(q) for q in curve.path]
    if curve.closed:
        path.append(path[0])
    cls = "coupler-curve closed" if curve.closed else "coupler-curve"
    items = [tag("polyline", {"class": cls, "data-point": curve.point, "points": points(path), "fill": "none", "stroke": colour, "stroke-width": "1.5", "stroke-linejoin": "round"})]
    if path:
        ends = [end for end, dead in ((path[0], curve.first), (path[-1], curve.last)) if dead is not None]
        r = 0.06 * s
        for x, y in ends:
            d = path_data([("M", (x - r, y - r)), ("L", (x + r, y + r)), ("M", (x - r, y + r)), ("L", (x + r, y - r))])
            items.append(tag("path", {"class": "dead-point", "data-point": curve.point, "d": d, "stroke": colour, "stroke-width": "2"}))
    return items
