"""Spatial synthesis tasks: what a task file asks, and the solution with the numbers that show its quality.

The kinds (format in ``docs/spatial.md``):

- ``spherical-guidance``: measured positions (two body points ``p``, ``q`` per
  position, on the unit sphere, or in any units with ``measured``: fitted to
  concentric spheres and normalised, (2-87)-(2-89)), checked for rigidity; the cranks for four
  positions with one coordinate of the fixed pivot fixed (``fix``), or three
  positions in closed form;
- ``spherical-function``: a spherical four-bar function generator for three
  precision points ``(θ, φ)`` (degrees), output axis at ``alpha_deg``, a chosen
  output pivot ``b1``; each solution moved by the spatial solver to its points
  (up to six points, and the other kinds of :mod:`~domes.design.synthesis.
  spatialkinds`, go there);
- ``rccc``: four poses (an orientation by three angles with a named
  ``convention``, or a rotation matrix; a position), the RCCC of seed 004,
  labelled exact or approximate;
- ``guiding-link``: poses as for ``rccc`` and a ``link`` (S-S, R-S, R-R,
  R-C, C-C) with its free choices ``fixed``: every link found.

>>> t = spatial_task_from_dict({"kind": "spherical-function", "alpha_deg": 70,
...     "precision_deg": [[0, 0], [20, 15], [45, 40]], "b1": [0.2, 0.5, 0.8]}, "doc")
>>> r = solve_spatial(t)
>>> r.success, len(r.mechanisms), r.worst < 1e-9
(True, 2, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.design.synthesis import links, spatialkinds, sphere
from domes.design.synthesis import rccc as rc
from domes.design.synthesis.spatialresult import SpatialSynthesis, spherical_fourbar, vector
from domes.design.synthesis.spherefit import NormalisedMotion, normalise_motion
from domes.design.synthesis.spherical import centre_points_three
from domes.errors import InputError
from domes.model.fields import check_keys, read_number
from domes.results import Progress, Status

KINDS = ("spherical-guidance", "spherical-function", "rccc", "guiding-link") + spatialkinds.KINDS


@dataclass(frozen=True)
class SphericalGuidanceTask:
    name: str
    p: np.ndarray
    q: np.ndarray
    fix: tuple[tuple[str, float], ...]
    #: For measured data: the sphere fit (2-87)-(2-89) that mapped it to the unit sphere.
    measured: NormalisedMotion | None = None


@dataclass(frozen=True)
class SphericalFunctionTask:
    name: str
    alpha: float
    thetas: tuple[float, ...]
    phis: tuple[float, ...]
    b1: np.ndarray


@dataclass(frozen=True)
class GuidingLinkTask:
    name: str
    link: str
    moves: tuple
    fixed: tuple[tuple[str, float], ...]
    starts: int = 48


@dataclass(frozen=True)
class RCCCTask:
    name: str
    moves: tuple
    meridians: int = 180
    tolerance: float = 1e-9
    convention: str = ""


def spatial_task_from_dict(data, where: str = "task"):
    """The task of a parsed task file; an :class:`~domes.errors.InputError` names the entry that is wrong."""
    if not isinstance(data, dict) or data.get("kind") not in KINDS:
        raise InputError(f"{where}: a spatial task's 'kind' is one of {', '.join(KINDS)}")
    kind, name = data["kind"], str(data.get("name", where))
    if kind in spatialkinds.KINDS:
        return spatialkinds.task_from_dict(data, where)
    if kind == "spherical-guidance":
        check_keys(data, {"kind", "name", "comment", "positions", "fix", "measured"}, {"kind", "positions"}, where)
        measured = data.get("measured", False)
        if not isinstance(measured, bool):
            raise InputError(f"{where}: measured: true (points in the units they were measured in, fitted to a "
                             f"sphere and normalised, (2-87)-(2-89)) or false (already on the unit sphere), got "
                             f"{measured!r}")
        raw = data["positions"]
        if not isinstance(raw, list) or not 3 <= len(raw) <= 4:
            raise InputError(f"{where}: positions: three or four, each {{'p': [x, y, z], 'q': [x, y, z]}}")
        p, q = [], []
        for k, item in enumerate(raw, 1):
            check_keys(item, {"p", "q"}, {"p", "q"}, f"{where}: positions[{k}]")
            p.append(vector(item["p"], 3, f"{where}: positions[{k}].p"))
            q.append(vector(item["q"], 3, f"{where}: positions[{k}].q"))
        fix = data.get("fix", {})
        if not isinstance(fix, dict) or any(k not in ("a0x", "a0y", "a0z") for k in fix):
            raise InputError(f"{where}: fix: {{'a0x': value}} (or a0y, a0z), one or more cranks' fixed coordinate")
        if len(raw) == 4 and not fix:
            raise InputError(f"{where}: four positions leave a crank one free choice: give 'fix', e.g. "
                             "{'a0x': -0.25}")
        fixes = tuple((k[-1], read_number(v, f"{where}: fix.{k}")) for k, v in fix.items())
        if measured:
            fitted = normalise_motion(np.stack([np.array(p), np.array(q)], axis=1))
            return SphericalGuidanceTask(name, fitted.directions[:, 0], fitted.directions[:, 1], fixes, fitted)
        return SphericalGuidanceTask(name, np.array(p), np.array(q), fixes)
    if kind == "spherical-function" and ("fixed" in data or "b1" not in data
                                         or len(data.get("precision_deg") or ()) != 3):
        return spatialkinds.spherical_generator_task(data, where)
    if kind == "spherical-function":
        check_keys(data, {"kind", "name", "comment", "alpha_deg", "precision_deg", "b1"},
                   {"kind", "alpha_deg", "precision_deg", "b1"}, where)
        pts = data["precision_deg"]
        if not isinstance(pts, list) or len(pts) != 3:
            raise InputError(f"{where}: precision_deg: three [θ, φ] pairs (degrees), the first [0, 0]")
        pairs = [vector(x, 2, f"{where}: precision_deg[{k}]") for k, x in enumerate(pts)]
        if np.any(pairs[0]):
            raise InputError(f"{where}: precision_deg: the first pair is the reference, [0, 0]")
        b1 = vector(data["b1"], 3, f"{where}: b1")
        if np.linalg.norm(b1) == 0:
            raise InputError(f"{where}: b1 has no direction")
        return SphericalFunctionTask(name, math.radians(read_number(data["alpha_deg"], f"{where}: alpha_deg")),
                                     tuple(math.radians(x[0]) for x in pairs), tuple(math.radians(x[1]) for x in pairs),
                                     b1 / np.linalg.norm(b1))
    if kind == "guiding-link":
        check_keys(data, {"kind", "name", "comment", "link", "convention", "poses", "fixed", "starts"},
                   {"kind", "link", "poses"}, where)
        if data["link"] not in links.KINDS:
            raise InputError(f"{where}: link: one of {', '.join(links.KINDS)}, got {data['link']!r}")
        rotations, positions = _poses(data, where, None)
        moves = rc.displacements(rotations, positions)
        fixed = data.get("fixed", {})
        if not isinstance(fixed, dict):
            raise InputError(f"{where}: fixed: {{'a0x': value, ...}}")
        starts = data.get("starts", 48)
        if not (isinstance(starts, int) and 1 <= starts <= 10_000):
            raise InputError(f"{where}: starts: an integer from 1 to 10,000, got {starts!r}")
        return GuidingLinkTask(name, data["link"], ((np.eye(3), np.zeros(3)),) + tuple((m.C, m.d) for m in moves),
                               tuple((k, read_number(v, f"{where}: fixed.{k}")) for k, v in fixed.items()), starts)
    check_keys(data, {"kind", "name", "comment", "convention", "poses", "meridians", "tolerance"},
               {"kind", "poses"}, where)
    rotations, positions = _poses(data, where, 4)
    convention = data.get("convention", "")
    meridians = data.get("meridians", 180)
    if not (isinstance(meridians, int) and 12 <= meridians <= 3600):
        raise InputError(f"{where}: meridians: an integer from 12 to 3600, got {meridians!r}")
    tolerance = read_number(data.get("tolerance", 1e-9), f"{where}: tolerance")
    if not 0 < tolerance < 1:
        raise InputError(f"{where}: tolerance must be in (0, 1), got {tolerance}")
    return RCCCTask(name, tuple(rc.displacements(rotations, positions)), meridians, tolerance, convention)


def _poses(data, where: str, count: int | None):
    """The rotations and positions of a task's poses (angles with the task's convention, or matrices)."""
    raw = data["poses"]
    if not isinstance(raw, list) or (count is not None and len(raw) != count) or len(raw) < 2:
        raise InputError(f"{where}: poses: {'four' if count else 'two or more'}, each {{'angles_deg': [a, b, c], "
                         "'position': [x, y, z]} (with a 'convention') or {'rotation': [[...], [...], [...]], "
                         "'position': [...]}")
    convention = data.get("convention", "")
    rotations, positions = [], []
    for k, item in enumerate(raw, 1):
        w = f"{where}: poses[{k}]"
        check_keys(item, {"angles_deg", "rotation", "position"}, {"position"}, w)
        positions.append(vector(item["position"], 3, f"{w}.position"))
        if "rotation" in item:
            rows = item["rotation"]
            if not isinstance(rows, list) or len(rows) != 3:
                raise InputError(f"{w}.rotation: three rows of three numbers")
            rotations.append(np.array([vector(r, 3, f"{w}.rotation") for r in rows]))
        elif "angles_deg" in item:
            if not convention:
                raise InputError(f"{w}: angles need the task's 'convention' ({', '.join(rc.CONVENTIONS)}); the paper "
                                 "names none, so none is implied")
            rotations.append(rc.pose_rotation(vector(item["angles_deg"], 3, f"{w}.angles_deg"), convention))
        else:
            raise InputError(f"{w}: give its orientation: 'angles_deg' (with a 'convention') or 'rotation'")
    return rotations, positions


def _xyz(v) -> str:
    return f"({v[0]:.6g}, {v[1]:.6g}, {v[2]:.6g})"


def solve_spatial(task, progress: Progress | None = None) -> SpatialSynthesis:
    """Solve a spatial task; every solution checked (residuals, or the linkage moved by the spatial solver).
    ``progress`` hears of a guiding-link search's starts."""
    from domes.motion.spatial.sweep import spatial_sweep

    if isinstance(task, spatialkinds.TASKS):
        return spatialkinds.solve(task, progress)
    if isinstance(task, SphericalGuidanceTask):
        Ds = sphere.rotations(task.p, task.q)
        toward = task.p[0] + task.q[0]
        out, cranks = [], []
        if len(Ds) == 3:
            for a0 in centre_points_three(task.p[0], task.p[1], task.p[2]):
                cranks.append(sphere.Crank(a0, task.p[0], float(np.ptp([np.linalg.norm(p - a0) for p in task.p]))))
            out.append("three positions: the fixed pivots of the crank through point p, (2-92)-(2-96)")
        else:
            for axis, value in task.fix:
                found = sphere.crank_with(Ds, axis, value, toward)
                out.append(f"a0{axis} = {value:g}: {len(found)} cranks")
                cranks += found
        for c in cranks:
            out.append(f"  a0 = ({c.a0[0]:.6f}, {c.a0[1]:.6f}, {c.a0[2]:.6f}), a1 = ({c.a1[0]:.6f}, {c.a1[1]:.6f}, "
                       f"{c.a1[2]:.6f}), arc {math.degrees(c.arc):.4f}°, spread {c.spread:.2g}")
            if task.measured is not None:
                back = task.measured.frame.back
                out.append(f"    in the measured frame: a0 {_xyz(back(c.a0))}, a1 {_xyz(back(c.a1))}")
        if task.measured is not None:
            fit = task.measured.fit
            out.insert(0, f"measured data fitted to concentric spheres, centre {_xyz(fit.centre)}, radii "
                          f"{', '.join(f'{r:.6g}' for r in fit.radii)}; distance from them {fit.rms:.2g} RMS, "
                          f"{fit.worst:.2g} worst (position {fit.worst_at[0]}, point {'pq'[fit.worst_at[1] - 1]}); "
                          "normalised by (2-89)")
        worst = max((c.spread for c in cranks), default=0.0)
        check = sphere.rigidity(task.p, task.q)
        return SpatialSynthesis(task.name, "spherical-guidance", Status.COMPLETE if cranks else Status.EMPTY,
                                tuple(out), (), worst, {"rigidity": check.message, "cranks": [
                                    {"a0": c.a0.tolist(), "a1": c.a1.tolist(), "spread": c.spread} for c in cranks]})
    if isinstance(task, SphericalFunctionTask):
        out, mechs, worst = [], [], 0.0
        for k, gen in enumerate(sphere.function_three(task.alpha, task.thetas, task.phis, task.b1), 1):
            mech = spherical_fourbar(task.alpha, gen.a1, task.b1, f"{task.name} solution {k}")
            sw = spatial_sweep(mech, 0.0, task.thetas[-1], math.radians(1.0), outputs=["angle:B0"])
            got, missed = [], []
            for point, (theta, phi) in enumerate(zip(task.thetas, task.phis), 1):
                i = int(np.argmin(np.abs(sw.inputs - theta)))
                if abs(sw.inputs[i] - theta) > 1e-12:
                    missed.append(str(point))
                    continue
                got.append(abs(math.remainder(sw.table["angle:B0"][i] - phi, 2 * math.pi)))
            worst = max(worst, math.inf if missed else max(got))
            error = f"output error {max(got):.2g} rad" if got else "no precision point reached"
            if missed:
                error += (f"; precision point(s) {', '.join(missed)} not reached by the sweep from 0° to "
                          f"{math.degrees(task.thetas[-1]):g}°")
            out.append(f"solution {k}: a1 = ({gen.a1[0]:.6f}, {gen.a1[1]:.6f}, {gen.a1[2]:.6f}), coupler arc "
                       f"{math.degrees(gen.coupler):.4f}°; moved to its precision points: {error}"
                       + ("" if sw.limit is None else f" ({sw.limit.message})"))
            mechs.append(mech)
        return SpatialSynthesis(task.name, "spherical-function", Status.COMPLETE, tuple(out), tuple(mechs), worst)
    if isinstance(task, GuidingLinkTask):
        found = links.guiding_links(task.link, list(task.moves), dict(task.fixed) or None, task.starts,
                                    progress=progress)
        out = [f"{len(found)} {task.link} link(s) from {task.starts} starts"]
        fmt = lambda v: "—" if v is None else f"({v[0]:.6g}, {v[1]:.6g}, {v[2]:.6g})"  # noqa: E731
        for k, g in enumerate(found, 1):
            out.append(f"  {k}. a0 {fmt(g.a0)}, u0 {fmt(g.u0)}, a1 {fmt(g.a1)}, u1 {fmt(g.u1)}; residual "
                       f"{g.residual:.1e}, check {links.check(g, list(task.moves)):.1e}")
        worst = max((links.check(g, list(task.moves)) for g in found), default=0.0)
        return SpatialSynthesis(task.name, "guiding-link", Status.COMPLETE if found else Status.EMPTY, tuple(out), (),
                                worst, {"links": [{"a0": g.a0.tolist(), "a1": g.a1.tolist(),
                                                   "u0": None if g.u0 is None else g.u0.tolist(),
                                                   "u1": None if g.u1 is None else g.u1.tolist(),
                                                   "residual": g.residual} for g in found]})
    sol = rc.search(list(task.moves), task.meridians, task.tolerance)
    lines = [sol.message, f"input angles {', '.join(f'{math.degrees(t):.4f}°' for t in sol.thetas)}"]
    for k, (p, u) in enumerate(sol.lines):
        lines.append(f"  z{k}: point ({p[0]:.6g}, {p[1]:.6g}, {p[2]:.6g}), direction ({u[0]:.6f}, {u[1]:.6f}, "
                     f"{u[2]:.6f})")
    return SpatialSynthesis(task.name, "rccc", Status.COMPLETE, tuple(lines), (sol.mechanism(),),
                            max(max(sol.rotation_errors), max(sol.translation_errors)),
                            {"label": sol.label, "slides": list(sol.slides), "thetas_deg": [math.degrees(t) for t in sol.thetas],
                             "rotation_errors": list(sol.rotation_errors),
                             "translation_errors": list(sol.translation_errors), "notes": list(sol.notes),
                             "convention": task.convention or "rotation matrices"})


__all__ = ["GuidingLinkTask", "KINDS", "RCCCTask", "SpatialSynthesis", "SphericalFunctionTask", "SphericalGuidanceTask", "solve_spatial",
           "spatial_task_from_dict"]
