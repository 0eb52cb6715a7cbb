"""The spatial and spherical generators as task-file kinds: read a task, call its solver, report its solutions.

Each kind reads its task file entries (an InputError names a wrong entry),
calls the solver of its module and returns a
:class:`~domes.design.synthesis.spatialresult.SpatialSynthesis` with every
solution, the method used and each solution's check by the spatial backend
(format in ``docs/spatial.md``):

- ``rssr-function``: an RSSR function generator for 2 to 7 precision pairs
  ``(θ, φ)`` (degrees) about given input and output axes
  (:mod:`~domes.design.synthesis.rssrfg`);
- ``spherical-function`` with 4 to 6 precision pairs, or with ``fixed``: a
  spherical four-bar function generator, every solution
  (:func:`~domes.design.synthesis.sphere.function_generator`; 5 pairs by a
  resultant, 6 with the output axis angle found too); three pairs with a
  chosen ``b1`` stay with :mod:`~domes.design.synthesis.spatialtask`;
- ``spherical-path``: a spherical four-bar whose coupler point passes
  through 2 to 9 points on the unit sphere, Table 2-2's free choices in
  ``fixed`` (spins ``beta12`` .. in degrees)
  (:mod:`~domes.design.synthesis.spherepath`);
- ``rrss-path``: an RRSS whose coupler point passes through 2 to 7 points in
  space, Table 2-3's free choices in ``fixed`` (``u0x`` .. ``b1z``)
  (:mod:`~domes.design.synthesis.rrss`).

>>> t = task_from_dict({"kind": "rssr-function", "input_axis": {"point": [0, 0, 0], "direction": [0, 0, 1]},
...     "output_axis": {"point": [5, 1, 0], "direction": [1, 0, 0]},
...     "precision_deg": [[0, 0], [20, 8], [40, 17]], "fixed": {"a1x": 1, "a1y": 0.5, "a1z": 0.3, "b1z": 2},
...     "sweep": False}, "doc")
>>> type(t).__name__, len(t.thetas)
('RSSRFunctionTask', 3)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.design.synthesis import rrss, rssrfg, sphere, spherepath
from domes.design.synthesis.spatialresult import SpatialSynthesis, spherical_fourbar, vector
from domes.errors import InputError
from domes.model.fields import check_keys, read_number
from domes.results import Progress, Status

KINDS = ("rssr-function", "spherical-path", "rrss-path")


@dataclass(frozen=True)
class RSSRFunctionTask:
    """An RSSR function generator task: axes as ``(point, direction)``, precision angles (rad)."""

    name: str
    input_axis: tuple[np.ndarray, np.ndarray]
    output_axis: tuple[np.ndarray, np.ndarray]
    thetas: tuple[float, ...]
    phis: tuple[float, ...]
    fixed: tuple[tuple[str, float], ...] = ()
    method: str = "auto"
    starts: int = 300
    seed: int = 0
    sweep: bool = True


@dataclass(frozen=True)
class SphericalGeneratorTask:
    """A spherical four-bar function generator task for 3 to 6 precision pairs (rad); ``alpha`` None for 6."""

    name: str
    alpha: float | None
    thetas: tuple[float, ...]
    phis: tuple[float, ...]
    fixed: tuple[tuple[str, object], ...] = ()


@dataclass(frozen=True)
class SphericalPathTask:
    """A spherical path generation task: points on the unit sphere, the given variables (spins in rad)."""

    name: str
    points: np.ndarray
    fixed: tuple[tuple[str, float], ...]
    method: str = "auto"
    starts: int = spherepath.STARTS
    seed: int = 0


@dataclass(frozen=True)
class RRSSPathTask:
    """An RRSS path generation task: points in space, the given first-position coordinates."""

    name: str
    points: np.ndarray
    fixed: tuple[tuple[str, float], ...]
    method: str = "auto"
    starts: int = 512
    seed: int = 0


TASKS = (RSSRFunctionTask, SphericalGeneratorTask, SphericalPathTask, RRSSPathTask)


def _axis(value, where: str) -> tuple[np.ndarray, np.ndarray]:
    check_keys(value, {"point", "direction"}, {"point", "direction"}, where)
    return vector(value["point"], 3, f"{where}.point"), vector(value["direction"], 3, f"{where}.direction")


def _pairs(data, where: str, most: int) -> list[np.ndarray]:
    pts = data["precision_deg"]
    if not isinstance(pts, list) or not 2 <= len(pts) <= most:
        raise InputError(f"{where}: precision_deg: 2 to {most} [θ, φ] pairs (degrees), the first the reference")
    return [vector(x, 2, f"{where}: precision_deg[{k}]") for k, x in enumerate(pts)]


def _count(data, key: str, default: int, low: int, high: int, where: str) -> int:
    value = data.get(key, default)
    if not (isinstance(value, int) and not isinstance(value, bool) and low <= value <= high):
        raise InputError(f"{where}: {key}: an integer from {low} to {high:,}, got {value!r}")
    return value


def _fixed(data, where: str) -> tuple[tuple[str, float], ...]:
    fixed = data.get("fixed", {})
    if not isinstance(fixed, dict):
        raise InputError(f"{where}: fixed: {{'a1x': value, ...}}")
    return tuple((str(k), read_number(v, f"{where}: fixed.{k}")) for k, v in fixed.items())


def task_from_dict(data: dict, where: str = "task"):
    """The task of a parsed task file of one of :data:`KINDS`."""
    kind, name = data["kind"], str(data.get("name", where))
    if kind == "rssr-function":
        check_keys(data, {"kind", "name", "comment", "input_axis", "output_axis", "precision_deg", "fixed", "method",
                          "starts", "seed", "sweep"}, {"kind", "input_axis", "output_axis", "precision_deg"}, where)
        pairs = _pairs(data, where, rssrfg.MOST)
        method = data.get("method", "auto")
        if method not in rssrfg.METHODS:
            raise InputError(f"{where}: method: one of {', '.join(rssrfg.METHODS)}, got {method!r}")
        sweep = data.get("sweep", True)
        if not isinstance(sweep, bool):
            raise InputError(f"{where}: sweep: true or false, got {sweep!r}")
        return RSSRFunctionTask(name, _axis(data["input_axis"], f"{where}: input_axis"),
                                _axis(data["output_axis"], f"{where}: output_axis"),
                                tuple(math.radians(x[0]) for x in pairs), tuple(math.radians(x[1]) for x in pairs),
                                _fixed(data, where), method, _count(data, "starts", 300, 1, 100_000, where),
                                _count(data, "seed", 0, 0, 2**31 - 1, where), sweep)
    if kind == "spherical-path":
        check_keys(data, {"kind", "name", "comment", "points", "fixed", "method", "starts", "seed"},
                   {"kind", "points"}, where)
        raw = data["points"]
        if not isinstance(raw, list) or not 2 <= len(raw) <= 9:
            raise InputError(f"{where}: points: 2 to 9 points [x, y, z] on the unit sphere")
        method = data.get("method", "auto")
        if method not in ("auto", "exhaustive", "seeded"):
            raise InputError(f"{where}: method: one of auto, exhaustive, seeded, got {method!r}")
        fixed = tuple((k, math.radians(v) if k.lower().startswith(("beta", "β")) else v)
                      for k, v in _fixed(data, where))
        return SphericalPathTask(name, np.array([vector(p, 3, f"{where}: points[{k}]") for k, p in enumerate(raw)]),
                                 fixed, method, _count(data, "starts", spherepath.STARTS, 1, 100_000, where),
                                 _count(data, "seed", 0, 0, 2**31 - 1, where))
    if kind == "rrss-path":
        check_keys(data, {"kind", "name", "comment", "points", "fixed", "method", "starts", "seed"},
                   {"kind", "points", "fixed"}, where)
        raw = data["points"]
        if not isinstance(raw, list) or not 2 <= len(raw) <= rrss.MOST:
            raise InputError(f"{where}: points: 2 to {rrss.MOST} points [x, y, z] (Table 2-3; eight are refused: the problem does not split)")
        method = data.get("method", "auto")
        if method not in rrss.METHODS:
            raise InputError(f"{where}: method: one of {', '.join(rrss.METHODS)}, got {method!r}")
        return RRSSPathTask(name, np.array([vector(p, 3, f"{where}: points[{k}]") for k, p in enumerate(raw)]),
                            _fixed(data, where), method, _count(data, "starts", 512, 1, 100_000, where),
                            _count(data, "seed", 0, 0, 2**31 - 1, where))
    raise InputError(f"{where}: unknown kind {kind!r}")


def spherical_generator_task(data: dict, where: str = "task") -> SphericalGeneratorTask:
    """A ``spherical-function`` task of 3 to 6 precision pairs with ``fixed`` choices (``alpha_deg`` left out
    for 6: the output axis angle is found too)."""
    check_keys(data, {"kind", "name", "comment", "alpha_deg", "precision_deg", "fixed"}, {"kind", "precision_deg"},
               where)
    pairs = _pairs(data, where, 6)
    if len(pairs) < 3:
        raise InputError(f"{where}: precision_deg: 3 to 6 [θ, φ] pairs (degrees), the first the reference")
    alpha = None
    if "alpha_deg" in data:
        alpha = math.radians(read_number(data["alpha_deg"], f"{where}: alpha_deg"))
    elif len(pairs) != 6:
        raise InputError(f"{where}: alpha_deg: the output axis angle is needed for 3 to 5 precision pairs (six find "
                         "it too)")
    fixed = data.get("fixed", {})
    if not isinstance(fixed, dict):
        raise InputError(f"{where}: fixed: {{'b1x': value}} (4 pairs) or {{'b1': [x, y, z]}} (3 pairs)")
    chosen = []
    for key, value in fixed.items():
        if key in ("a1", "b1"):
            v = vector(value, 3, f"{where}: fixed.{key}")
            if np.linalg.norm(v) == 0:
                raise InputError(f"{where}: fixed.{key} has no direction")
            chosen.append((key, tuple(v / np.linalg.norm(v))))
        else:
            chosen.append((str(key), read_number(value, f"{where}: fixed.{key}")))
    return SphericalGeneratorTask(str(data.get("name", where)), alpha, tuple(math.radians(x[0]) for x in pairs),
                                  tuple(math.radians(x[1]) for x in pairs), tuple(chosen))


def _fmt(v) -> str:
    return f"({v[0]:.6g}, {v[1]:.6g}, {v[2]:.6g})"


def solve(task, progress: Progress | None = None) -> SpatialSynthesis:
    """Solve a task of one of :data:`KINDS`: every solution, each checked by the spatial backend."""
    if isinstance(task, RSSRFunctionTask):
        r = rssrfg.rssr_function(task.input_axis, task.output_axis, task.thetas, task.phis, dict(task.fixed) or None,
                                 task.method, task.starts, task.seed, sweep=task.sweep)
        lines = [r.message.split(": ", 1)[1]]
        for k, s in enumerate(r.solutions, 1):
            lines.append(f"  {k}. a1 {_fmt(s.a1)}, b1 {_fmt(s.b1)}; crank {s.crank:.6g}, coupler {s.coupler:.6g}, "
                         f"rocker {s.rocker:.6g}; output error {s.error:.2g} rad"
                         + (f", by the sweep {s.swept_error:.2g} rad" if task.sweep else "")
                         + (f"; {s.defect} defect" if s.defect else ""))
        return SpatialSynthesis(task.name, "rssr-function", r.status if r.solutions else Status.EMPTY,
                                tuple(lines), tuple(s.mechanism for s in r.solutions if s.mechanism is not None),
                                r.worst, {"method": r.method, "starts": r.starts,
                                          "solutions": [s.to_dict() for s in r.solutions]})
    if isinstance(task, SphericalGeneratorTask):
        return _spherical(task)
    if isinstance(task, SphericalPathTask):
        return _spherical_path(task)
    if isinstance(task, RRSSPathTask):
        return _rrss_path(task)
    raise InputError(f"not a task of {', '.join(KINDS)}: {type(task).__name__}")


def _spherical_path(task: SphericalPathTask) -> SpatialSynthesis:
    """Every spherical four-bar through the points, each moved to them by the spatial solver."""
    r = spherepath.spherical_path(task.points, dict(task.fixed) or None, task.method, task.starts, task.seed)
    lines = [r.message.split(": ", 1)[1]] + [f"  note: {n}" for n in r.notes]
    for k, s in enumerate(r.solutions, 1):
        check = "" if s.check is None else (f"; coupler point off the path by {s.check.error:.2g}"
                                            + (f"; {', '.join(s.check.defects)} defect" if s.check.defects else ""))
        lines.append(f"  {k}. a0 {_fmt(s.a0)}, a1 {_fmt(s.a1)}, b0 {_fmt(s.b0)}, b1 {_fmt(s.b1)}; residual "
                     f"{s.residual:.1e}{check}")
    mechs = tuple(s.mechanism(task.points[0], f"{task.name} solution {k}") for k, s in enumerate(r.solutions, 1))
    return SpatialSynthesis(task.name, "spherical-path", r.status, tuple(lines), mechs, r.worst, {
        "method": r.method, "starts": r.starts, "equations": r.equations, "unknowns": r.unknowns,
        "given": list(r.given), "solutions": [
            {"a0": s.a0.tolist(), "a1": s.a1.tolist(), "b0": s.b0.tolist(), "b1": s.b1.tolist(),
             "spins_deg": [math.degrees(b) for b in s.spins], "residual": s.residual,
             "check_error": None if s.check is None else s.check.error,
             "inputs_deg": None if s.check is None else [math.degrees(t) for t in s.check.inputs],
             "defects": [] if s.check is None else list(s.check.defects)} for s in r.solutions]})


def _rrss_path(task: RRSSPathTask) -> SpatialSynthesis:
    """Every RRSS the method reaches, each driven through the points by the spatial solver."""
    r = rrss.rrss_path(task.points, dict(task.fixed), task.method, task.starts, task.seed)
    lines = [r.message]
    for k, s in enumerate(r.solutions, 1):
        if not math.isfinite(s.path_error):
            reached = f"not driven through every point ({s.reach})"
        elif s.path_error <= 1e-6:
            reached = f"driven through the points, off by {s.path_error:.2g} of the size"
        else:
            reached = (f"branch defect: driven from position 1 it misses a point by {s.path_error:.2g} of the "
                       "size (the equations hold on another branch)")
        lines.append(f"  {k}. u0 {_fmt(s.u0)} through a0 {_fmt(s.a0)}, u1 {_fmt(s.u1)} through a1 {_fmt(s.a1)}, "
                     f"b0 {_fmt(s.b0)}, b1 {_fmt(s.b1)}; residual {s.residual:.1e}; {reached}")
    return SpatialSynthesis(task.name, "rrss-path", r.status, tuple(lines), tuple(s.mechanism() for s in r.solutions),
                            r.worst, {"method": r.method, "starts": r.starts, "converged": r.converged,
                                      "solutions": [{**s.values(), "residual": s.residual,
                                                     "path_error": s.path_error, "reach": s.reach,
                                                     "thetas_deg": [math.degrees(t) for t in s.thetas]}
                                                    for s in r.solutions]})


def _spherical(task: SphericalGeneratorTask) -> SpatialSynthesis:
    """Every spherical function generator, each moved to its precision inputs by the closed-form analysis and
    the first also by the spatial sweep."""
    fixed = {k: (np.array(v) if isinstance(v, tuple) else v) for k, v in task.fixed}
    r = sphere.function_generator(task.thetas, task.phis, task.alpha, fixed or None)
    lines = [f"{len(r.solutions)} spherical four-bar(s) for {len(task.thetas)} precision points ({r.method})"
             + ("" if not r.degenerate else f"; {r.degenerate} degenerate root(s) left out")]
    mechs = []
    for k, s in enumerate(r.solutions, 1):
        g = s.generator
        lines.append(f"  {k}. a1 {_fmt(g.a1)}, b1 {_fmt(g.b1)}, α {math.degrees(g.alpha):.6g}°; residual "
                     f"{s.residual:.1e}, output error {s.error:.2g} rad"
                     + ("" if s.one_branch else f" (on one assembly mode; {s.error_any:.2g} rad taken apart: a "
                                                "branch defect)"))
        mechs.append(spherical_fourbar(g.alpha, g.a1, g.b1, f"{task.name} solution {k}"))
    return SpatialSynthesis(task.name, "spherical-function", r.status, tuple(lines), tuple(mechs), r.worst_error,
                            {"method": r.method, "solutions": [
                                {"a1": s.generator.a1.tolist(), "b1": s.generator.b1.tolist(),
                                 "alpha_deg": math.degrees(s.generator.alpha), "residual": s.residual,
                                 "error": s.error, "error_any": s.error_any, "one_branch": s.one_branch}
                                for s in r.solutions]})


__all__ = ["KINDS", "RRSSPathTask", "RSSRFunctionTask", "SphericalGeneratorTask", "SphericalPathTask", "TASKS", "solve",
           "spherical_generator_task", "task_from_dict"]
