"""A synthesis task as data: what the mechanism must do, and the free choices the designer fixes.

Tasks come as dictionaries (the JSON of ``examples/synthesis/``, read by
:mod:`domes.io.tasks`); :func:`task_from_dict` checks every entry and says
which one is wrong. Kinds:

- ``guidance``: precision positions of a body (``positions``: point and
  ``angle_deg``), 3 to 5; with 3 positions the free choices are the two
  ``circle_points`` (moving pivots in position 1) or ``centre_points``
  (fixed pivots); with 4 the abscissas ``circle_x`` of the circle points
  (each gives up to three cranks); with 5 none (Burmester points). A slider
  (a circle point at infinity) replaces a crank: with 3 positions by its
  direction ``slider_directions_deg``; with 4 or 5 ``"slider": true`` adds
  the slider the positions determine.
- ``function``: ``y = f(x)`` (``function``, an expression in ``x``) over
  ``range``, the crank's and the rocker's rotations ``input_deg`` and
  ``output_deg``, ``points`` (a count: Chebyshev spacing; or the list), the
  start angles ``start_deg`` ``[θ0, φ0]`` where the count needs them
  (``null`` where solved), the ``frame`` length and ``respace`` (equalise
  the structural error's extrema); or, as in Example 4, ``rotations_deg``
  ``[[θ12, φ12], [θ13, φ13]]`` with the rocker pin ``rocker_pin`` (frame
  from (0, 0) to (1, 0)).
- ``path``: ``points`` of the coupler path and the free choices of Table
  2-1: whole pivots ``a0``, ``a1``, ``b0``, ``b1`` or coordinates in
  ``given`` (``{"b0x": 1.5}``), as many as the count of the points leaves;
  ``crank_deg`` prescribes the crank's rotations (timing). More given than
  that: least squares. Five points with ``a0`` and ``b0`` is Example 5.
  ``driver``: ``"crank"`` when the link at ``a0`` must turn fully, else
  ``"any"`` (the default); every answer says which it is.
- ``curve``: any labelled candidate (those of ``scene``, or the ids in
  ``candidates``) dimensioned by least squares: the ``input`` (``role``,
  ``pivot``, ``rotation_deg``, ``overtravel_deg``, ``guide_deg`` of a
  slide) turns a link carrying ``point`` (``name``, ``at``); ``wanted``
  (``quantity`` leverage, length, angle, ratio or slide, ``of`` a role or
  two, ``function`` of x, ``bound``, ``over`` or ``over_last``, ``least``, ``samples``,
  ``tolerance``); the ``box`` the joints are placed in; ``limits``
  (``min_transmission_deg``, ``length``).
  See :mod:`~domes.design.synthesis.candidate`.

>>> t = task_from_dict({"kind": "function", "function": "log10(x)", "range": [1, 10], "input_deg": 60,
...                     "output_deg": -90, "points": 4, "start_deg": [20, None]})
>>> [round(x, 4) for x in t.points]
[1.3425, 3.7779, 7.2221, 9.6575]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from domes.design.synthesis.candidate import CurveTask
from domes.design.synthesis.expressions import expression
from domes.design.synthesis.function import FunctionTask, chebyshev, check_function
from domes.design.synthesis.guidance import Position, check_positions
from domes.design.synthesis.path import check_path
from domes.design.synthesis.pathfit import PIVOTS, check_given, check_points
from domes.errors import InputError, shown
from domes.model.fields import LARGEST


@dataclass(frozen=True)
class GuidanceTask:
    """Precision positions of a body and the free choices of the crank dyads."""

    positions: tuple[Position, ...]
    circle_points: tuple[tuple[float, float], ...] = ()
    centre_points: tuple[tuple[float, float], ...] = ()
    circle_x: tuple[float, ...] = ()
    name: str = "guidance"
    slider_directions: tuple[float, ...] = ()
    slider: bool = False
    min_transmission_deg: float | None = None
    tolerance: float | None = None
    max_link_ratio: float | None = None


#: What a path task may ask of the link at ``a0`` (its ``driver`` entry).
DRIVERS = ("crank", "any")
#: A path task's ``route``: ``"auto"`` (the atlas and least squares; exact roots where Table 2-1 leaves no free
#: choice) or ``"exact"`` (nine points, nothing given: every solution by the nine-point homotopy).
ROUTES = ("auto", "exact")


@dataclass(frozen=True)
class PathTask:
    """Points of a coupler path, the pivot coordinates given (Table 2-1's free choices: ``a0x``, ``a0y``, ...)
    and, optionally, the crank's rotations from point 1 to each later point (prescribed input angles, rad)."""

    points: tuple[tuple[float, float], ...]
    given: tuple[tuple[str, float], ...] = ()
    crank: tuple[float, ...] | None = None
    name: str = "path"
    min_transmission_deg: float | None = None
    tolerance: float | None = None
    max_link_ratio: float | None = None
    #: ``"crank"``: the link at ``a0`` must turn fully (a linkage it only rocks is warned of and ranked after the
    #: others); ``"any"``: either, each answer saying which.
    driver: str = "any"
    #: ``"exact"``: nine points, nothing given, no timing: every four-bar through them
    #: (:func:`~domes.design.synthesis.ninepoint.nine_point_path`, about 20 to 30 s).
    route: str = "auto"

    @property
    def exhaustive(self) -> bool:
        """Example 5's form (five points, both fixed pivots, no timing): searched for every real root."""
        return len(self.points) == 5 and self.crank is None and {k for k, _ in self.given} == {"a0x", "a0y", "b0x",
                                                                                               "b0y"}

    def pivot(self, name: str) -> tuple[float, float]:
        g = dict(self.given)
        return (g[name + "x"], g[name + "y"])


@dataclass(frozen=True)
class RotationTask:
    """Example 4's form: crank and rocker rotations from position 1, the rocker pin, frame (0, 0)-(1, 0)."""

    rotations: tuple[tuple[float, float], ...]
    rocker_pin: tuple[float, float]
    name: str = "rotations"
    min_transmission_deg: float | None = None
    tolerance: float | None = None
    max_link_ratio: float | None = None


def _finite(value) -> bool:
    """Whether ``value`` is a number that a float holds, finite (not an integer too large for one)."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return False
    try:
        return math.isfinite(value)
    except OverflowError:
        return False


def _number(data, key, where, default=None, largest=math.inf):
    value = data.get(key, default)
    if not _finite(value):
        raise InputError(f"{where}: {key!r} must be a finite number, got {shown(value)}")
    if abs(value) > largest:
        raise InputError(f"{where}: {key!r} is {value:g}, more than {largest:g} in size")
    return float(value)


def _pair(value, where):
    if (not isinstance(value, (list, tuple)) or len(value) != 2
            or not all(_finite(v) and abs(v) <= LARGEST for v in value)):
        raise InputError(f"{where}: expected two finite numbers [x, y] (each at most {LARGEST:g} in size), got "
                         f"{shown(value)}")
    return (float(value[0]), float(value[1]))


def _list(data, key, where) -> list:
    """The list ``data[key]``, empty when the entry is left out."""
    value = data.get(key, [])
    if not isinstance(value, list):
        raise InputError(f"{where}: {key!r} must be a list, got {shown(value)}")
    return value


def task_from_dict(data: dict, where: str = "task"):
    """The task of a dictionary (a parsed task file); an InputError naming the entry that is wrong."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: a task is a JSON object with a 'kind', got {type(data).__name__}")
    task = _task(data, where)
    if "min_transmission_deg" in data:
        if isinstance(task, CurveTask):
            raise InputError(f"{where}: a curve task takes its smallest transmission angle in "
                             "'limits': {'min_transmission_deg': ...}")
        task = replace(task, min_transmission_deg=min_transmission(data["min_transmission_deg"],
                                                                   f"{where}: min_transmission_deg"))
    for key, read in (("tolerance", relative_tolerance), ("max_link_ratio", link_ratio)):
        if key in data:
            if isinstance(task, CurveTask):
                hint = " (its tolerance goes in 'wanted': {'tolerance': ...})" if key == "tolerance" else ""
                raise InputError(f"{where}: a curve task takes no {key!r}{hint}")
            task = replace(task, **{key: read(data[key], f"{where}: {key}")})
    return task


def relative_tolerance(value, where: str) -> float:
    """A tolerance relative to the task's size, above 0 and below 1; an InputError naming ``where`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 < value < 1:
        raise InputError(f"{where}: a tolerance relative to the task's size, above 0 and below 1 (1e-6: a millionth "
                         f"of it), got {shown(value)}")
    return float(value)


def link_ratio(value, where: str) -> float:
    """The longest link allowed over the task's extent, at least 1; an InputError naming ``where`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 1 <= value < math.inf:
        raise InputError(f"{where}: the longest link allowed over the task's extent, a finite number of at least 1, "
                         f"got {shown(value)}")
    return float(value)


def min_transmission(value, where: str) -> float:
    """A smallest transmission angle in degrees, 0 to 90; an InputError naming ``where`` otherwise."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not 0 <= value < 90:
        raise InputError(f"{where}: a smallest transmission angle in degrees, from 0 to under 90, got {shown(value)}")
    return float(value)


def _task(data: dict, where: str):
    kind = data.get("kind")
    name = str(data.get("name", where))
    if kind == "guidance":
        raw = data.get("positions")
        if not isinstance(raw, list):
            raise InputError(f"{where}: 'positions' must be a list of {{'point': [x, y], 'angle_deg': a}}")
        positions = []
        for j, p in enumerate(raw, 1):
            if not isinstance(p, dict):
                raise InputError(f"{where}: position {j} must be an object with 'point' and 'angle_deg'")
            positions.append(Position(_pair(p.get("point"), f"{where}: position {j} point"),
                                      math.radians(_number(p, "angle_deg", f"{where}: position {j}"))))
        check_positions(positions)
        slider = data.get("slider", False)
        if not isinstance(slider, bool):
            raise InputError(f"{where}: 'slider' must be true or false")
        t = GuidanceTask(tuple(positions),
                         tuple(_pair(v, f"{where}: circle_points") for v in _list(data, "circle_points", where)),
                         tuple(_pair(v, f"{where}: centre_points") for v in _list(data, "centre_points", where)),
                         tuple(_number({"x": v}, "x", f"{where}: circle_x", largest=LARGEST)
                               for v in _list(data, "circle_x", where)),
                         name, tuple(math.radians(_number({"a": v}, "a", f"{where}: slider_directions_deg"))
                                     for v in _list(data, "slider_directions_deg", where)), slider)
        n = len(positions)
        if n == 3 and len(t.circle_points) + len(t.centre_points) + len(t.slider_directions) != 2:
            raise InputError(f"{where}: three positions leave each crank one free pivot: give two 'circle_points' "
                             "or two 'centre_points' (or one of each), or one of them and one slide direction "
                             "'slider_directions_deg'")
        if n == 3 and len(t.slider_directions) > 1:
            raise InputError(f"{where}: two sliders make a double slider; give one crank and one slider")
        if n != 3 and t.slider_directions:
            raise InputError(f"{where}: 'slider_directions_deg' is a free choice of three positions; with {n}, "
                             "'slider': true adds the slider the positions determine")
        if n == 3 and slider:
            raise InputError(f"{where}: with three positions choose the slider by its direction "
                             "('slider_directions_deg'), not 'slider': true")
        if n == 4 and len(t.circle_x) + slider != 2:
            raise InputError(f"{where}: four positions leave each crank one free coordinate: give 'circle_x', the "
                             "abscissas of the two circle points (or one, with 'slider': true)")
        if n == 5 and (t.circle_points or t.centre_points or t.circle_x):
            raise InputError(f"{where}: five positions leave no free choice: remove circle_points, centre_points "
                             "and circle_x")
        if n == 2:
            raise InputError(f"{where}: two positions leave a crank two free choices: give a third position, or "
                             "design with three")
        return t
    if kind == "function" and "rotations_deg" in data:
        rot = data["rotations_deg"]
        if not isinstance(rot, list) or len(rot) != 2:
            raise InputError(f"{where}: 'rotations_deg' must be two pairs [[θ12, φ12], [θ13, φ13]]")
        pairs = tuple(tuple(math.radians(v) for v in _pair(r, f"{where}: rotations_deg")) for r in rot)
        return RotationTask(pairs, _pair(data.get("rocker_pin"), f"{where}: rocker_pin"), name)
    if kind == "function":
        f = expression(data.get("function", ""), f"{where}: function")
        lo, hi = _pair(data.get("range"), f"{where}: range")
        count = data.get("points", 3)
        if isinstance(count, int) and not isinstance(count, bool):
            if not 3 <= count <= 5:
                raise InputError(f"{where}: 'points': a four-bar function generator meets 3 to 5 precision points, "
                                 f"got {count}")
            points = tuple(float(x) for x in lo + (hi - lo) * chebyshev(count))
        elif isinstance(count, list):
            points = tuple(_number({"x": v}, "x", f"{where}: points") for v in count)
        else:
            raise InputError(f"{where}: 'points' must be a count (Chebyshev spacing) or a list of x values")
        start = data.get("start_deg", [None, None])
        if not isinstance(start, list) or len(start) != 2:
            raise InputError(f"{where}: 'start_deg' must be [θ0, φ0], null where the synthesis solves for it")
        start = tuple(None if v is None else math.radians(_number({"a": v}, "a", f"{where}: start_deg")) for v in start)
        t = FunctionTask(f, lo, hi, math.radians(_number(data, "input_deg", where)),
                         math.radians(_number(data, "output_deg", where)), points, start,
                         _number(data, "frame", where, 1.0), name, bool(data.get("respace", False)))
        check_function(t)
        return t
    if kind == "path":
        return _path(data, where, name)
    if kind == "curve":
        return _curve(data, where, name)
    raise InputError(f"{where}: 'kind' must be 'guidance', 'function', 'path' or 'curve', got {kind!r}")


def _path(data: dict, where: str, name: str) -> PathTask:
    """A path task: its points, the pivots or coordinates given, optional prescribed input angles."""
    raw = data.get("points")
    if not isinstance(raw, list) or not 3 <= len(raw) <= 100:
        raise InputError(f"{where}: 'points' must be a list of 3 to 100 path points [x, y]; got "
                         f"{len(raw) if isinstance(raw, list) else raw!r}")
    pts = tuple(_pair(p, f"{where}: point {j}") for j, p in enumerate(raw, 1))
    given = {}
    for pivot in ("a0", "a1", "b0", "b1"):
        if pivot in data:
            given[pivot + "x"], given[pivot + "y"] = _pair(data[pivot], f"{where}: {pivot}")
    extra = data.get("given", {})
    if not isinstance(extra, dict):
        raise InputError(f"{where}: 'given' must be an object of pivot coordinates, e.g. {{\"b0x\": 1.5}}")
    for key, value in extra.items():
        if key not in PIVOTS:
            raise InputError(f"{where}: given {key!r} is not a pivot coordinate ({', '.join(PIVOTS)})")
        if key in given:
            raise InputError(f"{where}: {key} is given twice")
        given[key] = _number(extra, key, f"{where}: given", largest=LARGEST)
    crank = data.get("crank_deg")
    if crank is not None:
        if not isinstance(crank, list) or len(crank) != len(pts) - 1:
            raise InputError(f"{where}: 'crank_deg' lists the crank's rotation from point 1 to each later point: "
                             f"{len(pts) - 1} numbers")
        crank = tuple(math.radians(_number({"a": v}, "a", f"{where}: crank_deg")) for v in crank)
        turns = (0.0,) + crank
        for j in range(len(turns)):
            for k in range(j):
                if abs(math.remainder(turns[j] - turns[k], 2 * math.pi)) <= 1e-9:
                    raise InputError(f"{where}: crank_deg puts points {k + 1} and {j + 1} at one crank angle (a whole "
                                     "number of turns apart): a linkage of one degree of freedom has one pose there, "
                                     "so its coupler point cannot be at two points")
    driver = data.get("driver", "any")
    if driver not in DRIVERS:
        raise InputError(f"{where}: 'driver' must be 'crank' (the link at a0 turns fully) or 'any', got "
                         f"{shown(driver)}")
    route = data.get("route", "auto")
    if route not in ROUTES:
        raise InputError(f"{where}: 'route' must be 'auto' or 'exact' (nine points, nothing given: every solution), "
                         f"got {shown(route)}")
    if route == "exact" and (len(pts) != 9 or given or crank is not None):
        raise InputError(f"{where}: route 'exact' takes exactly nine points with no pivot given and no crank_deg "
                         f"(the nine-point problem); got {len(pts)} points" + (", pivots given" if given else "")
                         + (", crank_deg" if crank is not None else ""))
    t = PathTask(pts, tuple(sorted(given.items(), key=lambda kv: PIVOTS.index(kv[0]))), crank, name, driver=driver,
                 route=route)
    if t.exhaustive:
        check_path(t.points, t.pivot("a0"), t.pivot("b0"))
    else:
        check_points(t.points)
        check_given(len(pts), given, crank)
    return t


def _section(data, key, where) -> dict:
    value = data.get(key)
    if not isinstance(value, dict):
        raise InputError(f"{where}: {key!r} must be an object, got {value!r}")
    return value


def _curve(data: dict, where: str, name: str) -> CurveTask:
    """A least-squares task for labelled candidates (kind ``curve``)."""
    inp, wanted = (_section(data, k, where) for k in ("input", "wanted"))
    point = data.get("point", {})
    if not isinstance(point, dict):
        raise InputError(f"{where}: 'point' must be an object with 'name' and 'at', got {point!r}")
    limits = data.get("limits", {})
    if not isinstance(limits, dict):
        raise InputError(f"{where}: 'limits' must be an object")
    box = data.get("box")
    if not isinstance(box, list) or len(box) != 2:
        raise InputError(f"{where}: 'box' must be [[xmin, xmax], [ymin, ymax]], the space the joints are placed in")
    of = wanted.get("of")
    roles = of if isinstance(of, list) else [of]
    for key, value in [("input role", inp.get("role")), ("wanted quantity", wanted.get("quantity"))] + \
            [("wanted of", r) for r in roles]:
        if not isinstance(value, str) or not value:
            raise InputError(f"{where}: {key} must be a name, got {value!r}")
    if isinstance(of, list) and len(of) != 2:
        raise InputError(f"{where}: wanted 'of' is a role, or two roles [cylinder, piston], got {of!r}")
    samples = wanted.get("samples", 25)
    if isinstance(samples, bool) or not isinstance(samples, int):
        raise InputError(f"{where}: wanted samples must be a whole number, got {samples!r}")
    length = limits.get("length")
    scene = data.get("scene")
    if scene is not None and not isinstance(scene, str):
        raise InputError(f"{where}: 'scene' must be a scene name or file, got {scene!r}")
    bound = wanted.get("bound", "equal")
    if not isinstance(bound, str):
        raise InputError(f"{where}: wanted bound must be 'equal', 'at least' or 'at most', got {bound!r}")
    over = wanted.get("over")
    rotation = _number(inp, "rotation_deg", f"{where}: input")
    if "over_last" in wanted:  # the last stretch of the stroke, in x's unit (degrees of the input's rotation)
        if over is not None or wanted.get("quantity") == "leverage":
            raise InputError(f"{where}: wanted 'over_last' (the last degrees of the stroke) replaces 'over' and is "
                             "not taken for a leverage")
        last = _number(wanted, "over_last", f"{where}: wanted")
        if not 0 < last <= abs(rotation):
            raise InputError(f"{where}: wanted 'over_last' must be within the stroke of {abs(rotation):g}°")
        over = sorted([rotation, rotation - math.copysign(last, rotation)])
    guide = inp.get("guide_deg", wanted.get("guide_deg"))
    return CurveTask(
        name, inp["role"], _pair(inp.get("pivot", [0, 0]), f"{where}: input pivot"),
        None if "at" not in point else _pair(point.get("at"), f"{where}: point at"),
        math.radians(rotation),
        wanted["quantity"], tuple(of) if isinstance(of, list) else of,
        expression(wanted.get("function", ""), f"{where}: wanted function"),
        (_pair(box[0], f"{where}: box x"), _pair(box[1], f"{where}: box y")), samples,
        str(point.get("name", "P")),
        math.radians(_number(limits, "min_transmission_deg", f"{where}: limits", 30.0)),
        None if length is None else _pair(length, f"{where}: limits length"),
        _number(wanted, "tolerance", f"{where}: wanted", 0.02), scene,
        bound=bound, over=None if over is None else _pair(over, f"{where}: wanted over"),
        overtravel=math.radians(_number(inp, "overtravel_deg", f"{where}: input", 0.0)),
        guide=None if guide is None else math.radians(_number({"g": guide}, "g", f"{where}: guide_deg")),
        least=None if "least" not in wanted else _number(wanted, "least", f"{where}: wanted"))