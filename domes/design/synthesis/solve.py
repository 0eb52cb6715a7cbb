"""One entry point for dimensional synthesis: a task in, every solution out, checked and ranked.

:func:`synthesize` follows ``scipy.optimize``: one function for every kind
of task, a result object (:class:`Synthesis`) with ``status``, ``success``,
``message``, the solutions and the numbers that show their quality (the
residual at every precision position, the checks, the structural error).

Every solution is then moved by the kinematics kernel
(:mod:`~domes.design.synthesis.verify`) through the crank angles it claims,
on the assembly mode of its first position: its ``residuals`` are the
distances of what the kernel gives from what the task wants, and it is
usable only when every one is within the task's ``tolerance`` (relative to
its size, default :data:`~domes.design.synthesis.verify.TOLERANCE`). Roots
that are no linkage worth listing (a link of zero length, pivots running off
to infinity, links beyond ``max_link_ratio`` times the task) are grouped in
``degenerate``, counted and named, not listed.

Solutions are ranked by a documented score: usable ones (no defect) first,
those without a warning (a smallest transmission angle below
:data:`MIN_TRANSMISSION_DEG` or the task's) before those with one, then
function generators by their largest structural error, smaller first, then
by the smallest transmission angle at the precision positions, larger first.
Rejected solutions stay in the result with their reasons.

>>> from domes.design.synthesis.task import task_from_dict
>>> task = task_from_dict({"kind": "function", "rotations_deg": [[-30, 15], [-60, 45]], "rocker_pin": [0.375, 0.1875]})
>>> result = synthesize(task)                                     # seed 002 §2-3, Example 4
>>> [round(x, 6) for x in result.solutions[0].fourbar.a1]
[0.346046, 0.52925]
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from domes.design.synthesis import function as fn
from domes.design.synthesis import guidance as gd
from domes.design.synthesis import path as pt
from domes.design.synthesis import pathfit as pf
from domes.design.synthesis import pathroute as pr
from domes.design.synthesis import sliders as sl
from domes.design.synthesis import verify as vf
from domes.design.synthesis.candidate import CurveTask, Dimensioning, SolutionSet, dimension
from domes.design.synthesis.displacement import moved, rotation_about
from domes.design.synthesis.fourbars import Checks, FourBar, SliderCrank, check, check_slider
from domes.design.synthesis.task import (
    GuidanceTask,
    PathTask,
    RotationTask,
    link_ratio,
    min_transmission,
    relative_tolerance,
)
from domes.design.synthesis.verify import curve_distances
from domes.errors import InputError
from domes.motion.coupler.atlas import Atlas, AtlasSpec, OpenAtlas, build
from domes.motion.coupler.match import cognates, match

#: The smallest transmission angle (°) below which a usable linkage is reported with a warning and ranked after
#: the others. The book asks only for "a reasonable transmission angle" (seed 002 §2-3); 20° is where the design
#: ranking's transmission factor reaches zero goodness (docs/expert.md).
MIN_TRANSMISSION_DEG = 20.0


@dataclass(frozen=True)
class Solution:
    """A synthesised four-bar, its checks, and its error at every precision position (in length units).

    ``residuals`` are the kernel's re-evaluation (the distance of the coupler
    point from each path point, the pose error of each guided position, the
    rocker pin's distance from its wanted place); ``equation_residuals`` the
    errors of the synthesis equations the root was found by; ``size`` the
    task's size the tolerance is relative to; ``claim`` what the kernel
    checked.
    """

    fourbar: FourBar | SliderCrank
    checks: Checks
    residuals: tuple[float, ...]
    notes: tuple[str, ...] = ()
    structural: fn.StructuralError | None = None
    respaced: fn.Respacing | None = None
    poses: tuple = ()           # the moving pivots ((a_jx, a_jy), (b_jx, b_jy)) at every precision position
    warnings: tuple[str, ...] = ()   # what a designer should look at in a usable linkage (a poor transmission angle)
    equation_residuals: tuple[float, ...] = ()
    size: float = 1.0
    claim: vf.Claim | None = None

    @property
    def residual(self) -> float:
        return max(self.residuals) if self.residuals else 0.0

    @property
    def usable(self) -> bool:
        return self.checks.usable and not (self.structural is not None and self.structural.defects)

    @property
    def defects(self) -> tuple[str, ...]:
        return self.checks.defects + (self.structural.defects if self.structural is not None else ())


@dataclass(frozen=True, eq=False)
class Synthesis(SolutionSet):
    """Every solution of a task, ranked; ``roots`` is the count of real roots found before the checks, of which
    those in the ``degenerate`` groups are not listed in ``solutions``."""

    task_name: str
    kind: str
    solutions: tuple[Solution, ...]
    roots: int
    seconds: float
    notes: tuple[str, ...] = field(default_factory=tuple)
    min_transmission_deg: float = MIN_TRANSMISSION_DEG
    degenerate: tuple[vf.Degenerate, ...] = ()
    tolerance: float = vf.TOLERANCE
    max_link_ratio: float = vf.MAX_LINK_RATIO
    size: float = 1.0
    items_field = "solutions"

    @property
    def message(self) -> str:
        poor = sum(1 for s in self.usable if any(w.startswith("smallest transmission") for w in s.warnings))
        rocks = sum(1 for s in self.usable if any(w.startswith("the task asks for a crank") for w in s.warnings))
        warned = [f"{poor} of them with a transmission angle below {self.min_transmission_deg:g}°"] if poor else []
        warned += [f"{rocks} of them driven by a link that only rocks"] if rocks else []
        warned = f" ({'; '.join(warned)})" if warned else ""
        grouped = sum(g.count for g in self.degenerate)
        grouped = f", {grouped} degenerate (grouped)" if grouped else ""
        return (f"{self.status}: {self.task_name}: {self.roots} real root(s), {len(self.solutions)} linkage(s), "
                f"{len(self.usable)} usable{warned}{grouped}; {self.seconds * 1e3:.1f} ms")

    def _repr_html_(self) -> str | None:
        """Each solution at its precision positions, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


def synthesize(task, method: str = "exact", seeds: int = 64, progress=None, executor=None,
               min_transmission_deg: float | None = None, tolerance: float | None = None,
               max_link_ratio: float | None = None, atlas=None, timed_starts: int = pr.TIMED_STARTS,
               ) -> Synthesis | Dimensioning:
    """Dimension a four-bar for ``task`` (guidance, function, rotations or path): every real solution, checked.

    A :class:`~domes.design.synthesis.candidate.CurveTask` dimensions its
    labelled candidates by least squares instead and returns a
    :class:`~domes.design.synthesis.candidate.Dimensioning` (``executor``, see :mod:`domes.execution`,
    dimensions the candidates side by side). ``progress``, a callback, hears what the search is doing now and
    then (path points and curve tasks, the long ones).

    ``method="exact"`` finds every real root (closed forms, resultants, the
    path search); ``method="fast"`` polishes ``seeds`` random starts where
    the exact route searches (five positions, five precision points, five
    path points) and may miss roots; closed forms are the same either way.

    ``min_transmission_deg`` (default: the task's, else
    :data:`MIN_TRANSMISSION_DEG`): a usable four-bar whose smallest
    transmission angle at the precision positions is below it gets a warning
    and is ranked after the others; for a curve task it replaces the task's
    ``limits.min_transmission_deg``.

    ``tolerance`` (default: the task's, else :data:`~domes.design.synthesis.verify.TOLERANCE`): the largest
    re-evaluated error of a usable linkage, relative to the task's size (the spread of the path points or of the
    positions' points, the frame length of a function generator); for a curve task it replaces
    ``wanted.tolerance``. ``max_link_ratio`` (default: the task's, else
    :data:`~domes.design.synthesis.verify.MAX_LINK_RATIO`): roots with a longer link than this many times the task's
    extent (the spread of its points and given pivots) are grouped as degenerate.

    ``atlas`` (path tasks of nine points or more): the coupler-curve atlas
    (:class:`~domes.motion.coupler.atlas.Atlas`) whose look-up and refinement
    (``domes curves match``) seed the least squares besides the random
    starts; None builds a quick one in memory once (:func:`seed_atlas`);
    False leaves the look-up out. ``timed_starts``: the random starts of the bounded least squares a path
    task with prescribed timing ends in when its own fit misses (:func:`.pathroute.bounded_timing`).
    """
    if method not in ("exact", "fast"):
        raise InputError(f"method must be 'exact' or 'fast', got {method!r}")
    if not (isinstance(seeds, int) and 1 <= seeds <= 100_000):
        raise InputError(f"seeds must be a whole number from 1 to 100,000, got {seeds!r}")
    if min_transmission_deg is not None:
        min_transmission_deg = min_transmission(min_transmission_deg, "min_transmission_deg")
        if isinstance(task, CurveTask):
            task = replace(task, min_transmission=math.radians(min_transmission_deg))
    if tolerance is not None:
        tolerance = relative_tolerance(tolerance, "tolerance")
        if isinstance(task, CurveTask):
            task = replace(task, tolerance=tolerance)
    if max_link_ratio is not None:
        max_link_ratio = link_ratio(max_link_ratio, "max_link_ratio")
    if not (atlas is None or atlas is False or isinstance(atlas, (Atlas, OpenAtlas))):
        raise InputError(f"atlas must be a coupler-curve Atlas, None (the quick one) or False (none), got "
                         f"{type(atlas).__name__}")
    if isinstance(task, CurveTask):
        if not task.candidates:
            raise InputError(f"{task.name}: no candidate to dimension (give a scene or candidates)")
        return dimension(task, task.candidates, method, seeds, progress=progress, executor=executor)
    started = time.perf_counter()
    if not isinstance(task, (GuidanceTask, RotationTask, fn.FunctionTask, PathTask)):
        raise InputError(f"not a synthesis task: {type(task).__name__}")
    tol = _first(tolerance, task.tolerance, vf.TOLERANCE)
    ratio = _first(max_link_ratio, task.max_link_ratio, vf.MAX_LINK_RATIO)
    size, extent = task_size(task)
    knobs = {"method": method, "seeds": seeds}
    if isinstance(task, GuidanceTask):
        roots, sols, notes = _guidance(task, size, **knobs)
        kind, what = "guidance", "position"
    elif isinstance(task, RotationTask):
        roots, sols, notes = _rotations(task)
        kind, what = "function", "precision point"
    elif isinstance(task, fn.FunctionTask):
        roots, sols, notes = _function(task, **knobs)
        kind, what = "function", "precision point"
    else:
        roots, sols, notes = _path(task, tol, (size, extent, ratio), progress=progress, atlas=atlas,
                                   timed_starts=timed_starts, **knobs)
        kind, what = "path", "point"
    sols, groups = _settle(sols, tol, ratio, size, extent, what)
    notes = list(notes) + [g.text for g in groups]
    fits = [s for s in sols if s.claim is not None and s.claim.on_curve]
    if fits and not any(s.usable for s in fits):
        best = min(max(s.residuals) for s in fits)
        notes.append(f"no least-squares linkage is within the tolerance {tol:g} of the task's size {size:.3g} "
                     f"({tol * size:.3g}): the nearest misses by {best:.3g} ({best / size:.2g} of the size); loosen "
                     "the tolerance (task entry tolerance, --tolerance) to accept it")
    if min_transmission_deg is None:
        min_transmission_deg = getattr(task, "min_transmission_deg", None)
    if min_transmission_deg is None:
        min_transmission_deg = MIN_TRANSMISSION_DEG
    sols = [_transmission_warning(s, min_transmission_deg) for s in sols]
    if getattr(task, "driver", "any") == "crank":
        sols = [_driver_warning(s) for s in sols]
    ranked = sorted(sols, key=_score)
    return Synthesis(task.name, kind, tuple(ranked), roots, time.perf_counter() - started, tuple(notes),
                     min_transmission_deg, groups, tol, ratio, size)


def _first(*values):
    return next(v for v in values if v is not None)


def _spread(points) -> float:
    """The larger side of the bounding box of ``points`` (0 for none or one)."""
    P = np.asarray(list(points), dtype=float).reshape(-1, 2)
    return float(np.ptp(P, axis=0).max()) if len(P) > 1 else 0.0


def task_size(task) -> tuple[float, float]:
    """``(size, extent)`` of a task: the size its tolerance is relative to (the spread of the path points or of
    the guided positions' points, the frame of a function generator) and the extent its links are measured
    against (the spread of those points and of the pivots the task gives)."""
    if isinstance(task, fn.FunctionTask):
        return abs(task.frame), abs(task.frame)
    if isinstance(task, RotationTask):
        return 1.0, 1.0
    if isinstance(task, GuidanceTask):
        points = [p.point for p in task.positions]
        pivots = list(task.circle_points) + list(task.centre_points)
    else:
        points = list(task.points)
        given = dict(task.given)
        pivots = [(given[k + "x"], given[k + "y"]) for k in ("a0", "a1", "b1", "b0") if k + "x" in given
                  and k + "y" in given]
    extent = _spread(points + pivots)
    size = _spread(points) or extent or 1.0
    return size, max(extent, size)


def _settle(sols, tol: float, ratio: float, size: float, extent: float, what: str):
    """The solutions re-evaluated by the kernel (their defects beyond the tolerance added) and the degenerate
    groups, which leave the list."""
    kept, members = [], {}
    for s in sols:
        key = vf.degenerate_kind(s.fourbar, s.poses, extent, size, ratio)
        if key is not None:
            members.setdefault(key, []).append(s)
            continue
        if s.claim is None:
            kept.append(replace(s, size=size))
            continue
        errors, defects = vf.check(s.fourbar, s.claim, tol, size, what, s.defects)
        kept.append(replace(s, residuals=errors, equation_residuals=s.residuals, size=size,
                            checks=replace(s.checks, defects=s.checks.defects + defects)))
    groups = tuple(vf.group(k, members[k], extent, ratio) for k in vf.GROUPS if k in members)
    return kept, groups


def _claim(checks: Checks, **what) -> vf.Claim:
    """The claim of a solution: at its crank angles (from the checks), ``what`` (points, turns, pins)."""
    return vf.Claim(tuple(math.radians(a) for a in checks.crank_angles_deg), **what)


def _transmission_warning(s: Solution, limit: float) -> Solution:
    """``s`` with a warning when it is usable and its smallest transmission angle is below ``limit`` (°)."""
    mu = s.checks.min_transmission_deg
    if not s.usable or not mu < limit:
        return s
    return replace(s, warnings=s.warnings + (
        f"smallest transmission angle {mu:.1f}° (at the precision positions) below {limit:g}°: the linkage "
        "transmits force poorly there and may jam (limit: min_transmission_deg, --min-transmission)",))


def _driver_warning(s: Solution) -> Solution:
    """``s`` with a warning when it is usable and the link at ``A`` does not turn fully (the task asks a crank)."""
    if not s.usable or s.checks.crank_rotates:
        return s
    return replace(s, warnings=s.warnings + (f"the task asks for a crank (driver: crank), but this linkage is "
                                             f"{s.checks.driver.removeprefix('driven by ')}",))


def _score(s: Solution):
    error = s.structural.largest if s.structural is not None else 0.0
    return (not s.usable, bool(s.warnings), error, -s.checks.min_transmission_deg)


# -- guidance --------------------------------------------------------------------------------

def _guidance(task: GuidanceTask, size: float, method: str = "exact", seeds: int = 64):
    positions = list(task.positions)
    n = len(positions)
    notes = []
    wanted = {"points": tuple(p.point for p in positions),
              "turns": tuple(p.angle - positions[0].angle for p in positions), "size": size}
    if n == 3:
        dyads = [gd.dyad(positions, a1) for a1 in task.circle_points]
        dyads += [gd.dyad(positions, gd.circle_point(positions, a0)) for a0 in task.centre_points]
        dyads += [sl.slider_for_direction(positions, angle) for angle in task.slider_directions]
        groups = [[d] for d in dyads]
    elif n == 4:
        groups = [gd.circle_point_curve(positions, [x]) for x in task.circle_x]
    else:
        found = gd.burmester_points(positions, method=method, seeds=seeds)
        groups = [[d] for d in found]
        notes.append(f"{len(groups)} real Burmester point(s)")
    if task.slider and n > 3:
        sliders = sl.slider_points(positions)
        groups.append(sliders)
        notes.append(f"{len(sliders)} slider point(s)" + ("" if sliders or n == 4 else
                                                           ": five positions in general have none"))
    roots = sum(len(g) for g in groups)
    Ds = gd.displacements(positions)
    if n == 5:
        cranks = [g[0] for g in groups[:len(groups) - task.slider]]
        pairs = [(cranks[i], cranks[j]) for i in range(len(cranks)) for j in range(i + 1, len(cranks))]
        if task.slider:
            pairs += [(c, s) for c in cranks for s in groups[-1]]
    else:
        pairs = [(p, q) for p in groups[0] for q in groups[1]] if len(groups) == 2 else []
    sols = []
    for a, b in pairs:
        if isinstance(a, sl.SliderDyad):
            a, b = b, a
        A = [moved(D, a.a1) for D in Ds]
        B = [moved(D, b.a1) for D in Ds]
        if isinstance(b, sl.SliderDyad):
            sc = SliderCrank(a.a0, a.a1, b.a1, b.direction, positions[0].point)
            n_ = np.array([-math.sin(b.direction), math.cos(b.direction)])
            res = tuple(max(abs(np.linalg.norm(A[j] - a.a0) - a.radius), abs(float(n_ @ (B[j] - B[0]))))
                        for j in range(n))
            checks = check_slider(sc, A, B)
            sols.append(Solution(sc, checks, res, poses=_poses(A, B), claim=_claim(checks, **wanted)))
            continue
        fb = FourBar(a.a0, a.a1, b.a1, b.a0, positions[0].point)
        res = tuple(max(abs(np.linalg.norm(A[j] - a.a0) - a.radius), abs(np.linalg.norm(B[j] - b.a0) - b.radius))
                    for j in range(n))
        checks = check(fb, A, B)
        sols.append(Solution(fb, checks, res, poses=_poses(A, B), claim=_claim(checks, **wanted)))
    return roots, sols, notes


def _poses(A, B) -> tuple:
    return tuple(((float(a[0]), float(a[1])), (float(b[0]), float(b[1]))) for a, b in zip(A, B))


# -- function generation ----------------------------------------------------------------------

def _rotations(task: RotationTask):
    """Example 4: the crank pin by inversion (2-109), checked against Freudenstein's equation."""
    th = [r[0] for r in task.rotations]
    ph = [r[1] for r in task.rotations]
    b0 = (1.0, 0.0)
    a1 = fn.inversion_three(th, ph, task.rocker_pin, b0)
    theta1 = math.atan2(a1[1], a1[0])
    phi1 = math.atan2(task.rocker_pin[1] - b0[1], task.rocker_pin[0] - b0[0])
    gen = fn.freudenstein([theta1, theta1 + th[0], theta1 + th[1]], [phi1, phi1 + ph[0], phi1 + ph[1]])
    fb = FourBar((0.0, 0.0), tuple(a1), task.rocker_pin, b0)
    agree = max(abs(x - y) for x, y in zip(fb.lengths, (gen.crank, gen.coupler, gen.rocker, gen.frame)))
    A = [a1] + [moved(rotation_about((0, 0), t), a1) for t in th]
    B = [np.asarray(task.rocker_pin)] + [moved(rotation_about(b0, p), task.rocker_pin) for p in ph]
    b = fb.lengths[1]
    res = tuple(abs(float(np.linalg.norm(np.subtract(B[j], A[j]))) - b) for j in range(3))
    note = f"inversion (2-109) and Freudenstein's equation agree on the lengths to {agree:.1e}"
    checks = check(fb, A, B)
    pins = tuple(tuple(map(float, b)) for b in B)
    return 1, [Solution(fb, checks, res, (note,), poses=_poses(A, B), claim=_claim(checks, pins=pins))], []


def _function(task: fn.FunctionTask, method: str = "exact", seeds: int = 64):
    gens = fn.solve(task, method, seeds)
    xs = np.sort(np.asarray(task.points, dtype=float))
    sols = []
    for g in gens:
        dth, dph = task.angles(xs)
        th, ph = g.theta0 + dth, g.phi0 + dph
        fb = generator_fourbar(g, th[0], ph[0])
        A = [(g.crank * math.cos(t), g.crank * math.sin(t)) for t in th]
        B = [(g.frame + g.rocker * math.cos(p), g.rocker * math.sin(p)) for p in ph]
        res = tuple(abs(math.dist(A[j], B[j]) - g.coupler) for j in range(xs.size))
        err = fn.structural_error(task, g, xs)
        respaced = fn.respace(task, g) if not err.defects and task.respace else None
        notes = (f"largest structural error {math.degrees(err.largest):.4g}° of rocker rotation "
                 f"({abs(err.largest / task.k_phi):.3g} in y)",) if np.isfinite(err.largest) else ()
        checks = check(fb, A, B)
        sols.append(Solution(fb, checks, res, notes, err, respaced, _poses(A, B),
                             claim=_claim(checks, pins=tuple(B))))
    return len(gens), sols, []


def generator_fourbar(g: fn.FunctionGenerator, theta: float, phi: float) -> FourBar:
    """The generator's linkage drawn at crank angle ``theta`` and rocker angle ``phi`` (frame (0, 0)-(d, 0))."""
    return FourBar((0.0, 0.0), (g.crank * math.cos(theta), g.crank * math.sin(theta)),
                   (g.frame + g.rocker * math.cos(phi), g.rocker * math.sin(phi)), (g.frame, 0.0))


# -- path generation ----------------------------------------------------------------------------

def _path(task: PathTask, tol: float, scale: tuple, method: str = "exact", seeds: int = 64, progress=None,
          atlas=None, timed_starts: int = pr.TIMED_STARTS):
    """The path routes; ``scale`` is the task's ``(size, extent, max_link_ratio)``."""
    kind = "exact" if task.exhaustive else pf.check_given(len(task.points), dict(task.given), task.crank)
    notes = _path_notes(task, tol, kind)
    if task.route == "exact":
        roots, sols, more = _nine_points(task, progress)
        return roots, sols, notes + more
    if not task.exhaustive:
        roots, sols, more = _path_fit(task, scale, method, seeds, progress, atlas, tol, timed_starts)
        return roots, sols, notes + more
    a0, b0 = task.pivot("a0"), task.pivot("b0")
    found = pt.five_points(task.points, a0, b0, method=method, seeds=seeds, progress=progress)
    sols = []
    for f in found:
        fb = FourBar(a0, f.a1, f.b1, b0, task.points[0])
        A, B = pt.coupler_positions(task.points, f)
        checks = check(fb, A, B)
        sols.append(Solution(fb, checks, _crank_residuals(A, B, a0, f.a1, b0, f.b1), (
            "coupler rotations θ1j " + ", ".join(f"{math.degrees(r):.4f}°" for r in f.rotations),),
            poses=_poses(A, B), claim=_claim(checks, points=task.points)))
    where = (f"on {pt.GRID} × {pt.GRID} grids of (θ12, θ13) and (θ14, θ15)" if method == "exact"
             else f"from {seeds} random starts (fast: some roots may be missing)")
    return len(found), sols, notes + [f"{len(found)} real solution(s) {where}"]


def _nine_points(task: PathTask, progress=None):
    """Every four-bar through nine points (:func:`.ninepoint.nine_point_path`): the real ones listed, the counts
    of classes, solutions, real and usable ones in the notes."""
    from domes.design.synthesis import ninepoint as nine

    found = nine.nine_point_path(task.points, progress=progress)
    P = np.asarray(task.points, dtype=float)
    sols = []
    for s in found.real:
        z = np.array(s.z)
        z[:8] /= found.size
        fb, A, B = nine.real_fourbar(z, P, found.size)
        checks = s.checks if s.checks is not None else check(fb, A, B)
        sols.append(Solution(fb, checks, _crank_residuals(A, B, fb.a0, fb.a1, fb.b0, fb.b1), (
            "route: exact, the nine-point homotopy", f"class {s.cls + 1} of {len(found.classes)}, member {s.member}; "
            f"Newton residual {s.residual:.2g}, condition {s.condition:.2g}"), poses=_poses(A, B),
            claim=_claim(checks, points=task.points)))
    return len(found.real), sols, [
        f"nine points, every solution (parameter homotopy from a stored generic set): {len(found.classes)} classes "
        f"of {nine.CLASSES} (six solutions each: three cognates, two labellings), {len(found.solutions)} solutions, "
        f"{len(found.real)} real, {len(found.usable)} usable as found (no branch, order or dead-point defect); "
        f"{found.tracked} paths tracked, {found.failed} failed, {found.retracked} tracked again"] + list(found.notes)


def _crank_residuals(A, B, a0, a1, b0, b1) -> tuple[float, ...]:
    """The error of the crank equations (2-113) at every position: how far each crank's length changes."""
    a_r, b_r = math.dist(a1, a0), math.dist(b1, b0)
    return tuple(max(abs(math.dist(A[j], a0) - a_r), abs(math.dist(B[j], b0) - b_r)) for j in range(len(A)))


def _path_notes(task: PathTask, tol: float, kind: str) -> list[str]:
    """Repeated points (within the tolerance: refused where the problem is exact), points in line or on a circle."""
    P = np.asarray(task.points, dtype=float)
    size = _spread(P)
    for j in range(len(P)):
        for k in range(j):
            gap = math.dist(P[j], P[k])
            if gap <= tol * size and kind == "exact":
                raise InputError(f"points {k + 1} and {j + 1} coincide within the tolerance ({gap:.3g} apart, "
                                 f"{gap / size:.2g} of the path's size; tolerance {tol:g}): a repeated point adds no "
                                 "condition, so the problem is not exact; give another point, or a smaller tolerance "
                                 "if they are meant apart")
    notes = []
    if kind != "exact":
        near = [(k + 1, j + 1) for j in range(len(P)) for k in range(j) if math.dist(P[j], P[k]) <= tol * size]
        if near:
            notes.append("points " + ", ".join(f"{a} and {b}" for a, b in near) + f" coincide within the tolerance "
                         f"{tol:g} of the path's size: each pair counts as one point")
    off = pf.line_deviation(P)
    if off <= pf.NEARLY * size and len(pf.on_one_line(P)) <= pf.ON_ONE_LINE:
        within = f" (within {off / size:.2g} of the path's size)" if off > 0 else ""
        notes.append(f"the {len(P)} points lie on one line{within}: such points "
                     "are met in the limit of a translating coupler on endless cranks (roots with pivots running "
                     "off to infinity: grouped as degenerate, not listed)")
    circle = pf.on_one_circle(P)
    if circle is not None and len(P) >= 4:
        centre, radius, off = circle
        at = [name for name in ("a0", "b0") if name + "x" in dict(task.given) and name + "y" in dict(task.given)
              and math.dist(task.pivot(name), centre) <= tol * size]
        notes.append(f"the {len(P)} points lie on one circle (centre {_point(centre)}, radius {radius:.6g}, within "
                     f"{off / size:.2g} of the path's size): a crank pivoted at its centre with its pin at the coupler "
                     "point passes through them all" + (f"; {' and '.join(at)} is that centre, so the four-bars "
                                                        "through them form a family, not isolated roots"
                                                        if at else ""))
    return notes


def _point(p) -> str:
    return f"({p[0]:.6g}, {p[1]:.6g})"


def _path_fit(task: PathTask, scale: tuple, method: str, seeds: int, progress=None, atlas=None, tol=None,
              timed_starts: int = pr.TIMED_STARTS):
    """Table 2-1's other free choices, prescribed input angles, or least squares (:mod:`.pathfit`); an exact
    problem with no root found but degenerate ones is answered by least squares, and the notes say so."""
    given = dict(task.given)
    n = len(task.points)
    kind = pf.check_given(n, given, task.crank)
    starts = 64 * seeds if method == "exact" else 8 * seeds
    eqs, unknowns, _ = pf.problem_counts(n, task.crank)
    line = pf.on_one_line(task.points)
    notes = []
    left_out: dict = {}
    info: dict = {}
    seeded, seed_note = atlas_seeds(task, atlas, progress) if len(line) <= pf.ON_ONE_LINE else ([], "")
    if len(line) > pf.ON_ONE_LINE:
        notes.append(f"points {_numbers(line)} lie on one line: a four-bar's coupler curve (a sextic) meets a line "
                     f"in at most {pf.ON_ONE_LINE} points, so no four-bar passes through them all")
    sols, listed, roots = [], [], 0
    if kind == "exact" and not notes:
        found = pf.fit(task.points, given, task.crank, starts=starts, progress=progress, seeded=seeded, info=info)
        sols = [_fit_solution(task, f, "exact", "exact roots (Table 2-1)") for f in found]
        listed = [x for x in sols if vf.degenerate_kind(x.fourbar, x.poses, scale[1], scale[0], scale[2]) is None]
        roots = len(found)
        note = (f"{len(found)} distinct real root(s) found from {starts} random starts"
                + (f" and {len(seeded)} from the atlas" if seeded else "") + f" ({eqs} equations, {unknowns} "
                f"unknowns, {len(given)} given: Table 2-1); roots no start reached are missing")
        if not listed:
            notes.append(f"no four-bar found through the {n} points exactly ({eqs} equations, {unknowns} unknowns, "
                         f"{len(given)} given: Table 2-1; {starts} random starts" +
                         (f"; {len(found)} degenerate root(s) only)" if found else ")"))
    if kind == "exact" and not listed:
        found = pf.fit(task.points, given, task.crank, starts=starts, least_squares_only=True, progress=progress,
                       left_out=left_out, seeded=seeded, info=info)
        sols += [_fit_solution(task, f, "least squares", _least_squares(seeded)) for f in found]
        notes.append("answered by least squares: the nearest four-bars, each with its distance from every point"
                     if found else "nor by least squares: no minimum met every point on one assembly mode with links "
                     "of useful length; try more starts (seeds) or other points")
        kind, roots = "least squares", roots + len(found)
    elif kind == "least squares":
        found = pf.fit(task.points, given, task.crank, starts=starts, progress=progress, left_out=left_out,
                       seeded=seeded, info=info)
        sols = [_fit_solution(task, f, kind, _least_squares(seeded)) for f in found]
        roots = len(found)
    if kind == "least squares":
        note = (f"least squares: {eqs} equations in {unknowns - len(given)} unknowns (Table 2-1); the {len(found)} "
                f"best local minima of {info.get('random starts', starts)} random starts"
                + (f" and {len(seeded)} from the atlas" if seeded else "")
                + (" (the random starts left out: the atlas's meet every point)" if seeded and not
                   info.get("random starts", starts) else ""))
        if left_out:
            note += "; left out as degenerate: " + ", ".join(f"{count} {why}" for why, count in left_out.items())
    sols, last = _last_steps(task, sols, scale[0] * _first(tol, task.tolerance, vf.TOLERANCE), timed_starts)
    return roots, sols, notes + [note] + ([seed_note] if seed_note else []) + last


def _least_squares(seeded) -> str:
    return "least squares" + (" (atlas and random starts)" if seeded else " (random starts)")


def _last_steps(task: PathTask, sols: list, within: float, starts: int = pr.TIMED_STARTS):
    """The path route's last steps (:mod:`.pathroute`, as the published-targets benchmark): without timing and
    with no pivot given, the best least-squares linkage's worst point polished, kept when that lowers it; with
    timing, the bounded least squares of the timing when no answer is within ``within`` (the tolerance as a
    length) and it comes nearer than the best. ``(solutions, notes)``."""
    P = np.asarray(task.points, dtype=float)
    if task.crank is None:
        fits = [s for s in sols if s.claim is not None and s.claim.on_curve]
        if task.given or not fits:
            return sols, []
        worst, best = min(((max(curve_distances(s.fourbar, P)), k, s) for k, s in enumerate(fits)))[::2]
        if worst <= within:
            return sols, []
        found = pr.polished_path(best.fourbar, P)
        f = None if found is None else pf.seed_from(P, (found[0].a0, found[0].a1, found[0].b1, found[0].b0,
                                                        found[0].point))
        if f is None:
            return sols, ["worst-point polish of the best least-squares linkage: no lower worst point"]
        return sols + [_fit_solution(task, f, "least squares", "least squares, then the worst point polished",
                                     pr.carried(found[0], f.a1, f.b1))], [
            f"worst-point polish of the best least-squares linkage: worst point {found[1]:.3g} -> {found[2]:.3g}"]
    timed = [(_timed_worst(s.fourbar, s.claim.angles, P), s) for s in sols if s.claim is not None]
    best = min((w for w, _ in timed), default=math.inf)
    if best <= within:
        return sols, []
    found = pr.bounded_timing(P, task.crank, dict(task.given), starts)
    if found is None or not found[2] < best:
        return sols, ["bounded least squares of the timing: no nearer linkage"]
    fb = found[0]
    f = pf.PathFit(fb.a0, fb.a1, fb.b1, fb.b0, pr.coupler_turns(fb, found[1]), found[2])
    return sols + [_fit_solution(task, f, "least squares", "bounded least squares of the timing", fb.point)], [
        f"bounded least squares of the timing: largest distance {found[2]:.3g} (the path task's best: {best:.3g})"]


def _timed_worst(fb: FourBar, angles, points) -> float:
    """The largest distance of the coupler point from ``points`` at the crank ``angles`` (the kernel); inf where
    the loop does not close."""
    r = vf.replay(fb, angles, ["point:P"])
    if r.dead is not None:
        return math.inf
    d = np.linalg.norm(np.c_[r.values["point:P.x"], r.values["point:P.y"]] - points, axis=1)
    return float(np.max(d)) if np.all(np.isfinite(d)) else math.inf


#: Atlas candidates refined for the seeds of a path task, and the fits wanted (as ``domes curves match``).
SEED_CANDIDATES, SEED_FITS = 10, 2

#: The quick atlas built in memory when none is given: linkages and coupler-plane step (about 6 s to build).
SEED_ATLAS = AtlasSpec("seeds", 300, 1.0)

_seed_atlas: list = []


def seed_atlas() -> Atlas:
    """The quick coupler-curve atlas of :data:`SEED_ATLAS`, built once per process."""
    if not _seed_atlas:
        _seed_atlas.append(Atlas(build(SEED_ATLAS)))
    return _seed_atlas[0]


def atlas_seeds(task: PathTask, atlas=None, progress=None) -> tuple[list[pf.PathFit], str]:
    """Starts for the path task's least squares from the atlas look-up and refinement of ``domes curves match``
    (:func:`~domes.motion.coupler.match.match`), and a note: each linkage that fits the points' closed curve,
    in its six forms (itself and its two Roberts-Chebyshev cognates, each driven from either frame pivot), its
    pivots and coupler rotations read where its coupler point is nearest each point (:func:`.pathfit.seed_from`).
    None for fewer than nine points, prescribed timing, or ``atlas`` False.

    >>> atlas_seeds(PathTask(((0, 0), (1, 0), (1, 1), (0, 1)), (("a0x", 0.0), ("a0y", 0.0), ("b0x", 2.0))))
    ([], '')
    """
    if atlas is False or len(task.points) < 9 or task.crank is not None:
        return [], ""
    atlas = seed_atlas() if atlas is None else atlas
    try:
        found = match(np.asarray(task.points, dtype=float), atlas, SEED_FITS, SEED_CANDIDATES, progress=progress)
    except (InputError, ValueError, ArithmeticError, np.linalg.LinAlgError) as exc:
        return [], f"atlas look-up (as curves match) left out: {exc}; random starts only"
    fits = [f for f in found.fits if f.mechanism is not None]
    fits += [g for m in found.merged for g, _ in m if g.mechanism is not None]
    seeds = []
    for f in fits:
        m = f.mechanism
        A, B, C, D = (complex(*m.joint(n).at) for n in "ABCD")
        P = complex(*m.point("P")[1])
        for a0, a1, b1, b0, p in [(A, B, C, D, P)] + cognates(A, B, C, D, P):
            for order in ((a0, a1, b1, b0), (b0, b1, a1, a0)):
                seed = pf.seed_from(task.points, [(z.real, z.imag) for z in order + (p,)])
                if seed is not None:
                    seeds.append(seed)
    given = dict(task.given)
    seeds.sort(key=lambda f: sum(abs(getattr(f, k[:2])[k[2] == "y"] - v) for k, v in given.items()))
    best = min((f.after[0] for f in fits), default=math.inf) / max(found.size, 1e-300)
    if not fits:
        return [], f"atlas look-up (as curves match): no linkage from {found.tried} candidates; random starts only"
    return seeds, (f"atlas look-up (as curves match): {len(fits)} linkage(s) trace the points' closed curve to "
                   f"{best:.2g} of its size; their {len(seeds)} forms (cognates, either frame pivot driving) seed the "
                   "least squares with the random starts")


def _fit_solution(task: PathTask, f: pf.PathFit, kind: str, route: str, point=None) -> Solution:
    """A solution of :func:`.pathfit.fit` with its checks and its claim: the points at its crank angles (exact),
    at the prescribed ones (timing), or anywhere on its coupler curve (least squares); its notes say the
    ``route`` that found it; the coupler point is ``point`` (default: point 1, where the fit puts it)."""
    fb = FourBar(f.a0, f.a1, f.b1, f.b0, task.points[0] if point is None else point)
    A, B = pt.coupler_positions(task.points, pt.PathSolution(f.a1, f.b1, f.rotations, f.residual))
    checks = check(fb, A, B)
    extra = ()
    if task.crank is not None:               # prescribed timing: the kernel drives the crank to those angles
        first = math.atan2(f.a1[1] - f.a0[1], f.a1[0] - f.a0[0])
        claim = vf.Claim((first,) + tuple(first + c for c in task.crank), points=task.points)
    elif kind == "exact":
        claim = _claim(checks, points=task.points)
    else:
        claim = _claim(checks, points=task.points, on_curve=True)
    if kind != "exact":
        far = curve_distances(fb, task.points)
        extra = (f"least squares: distance of the points from the coupler curve {max(far):.3g} largest, "
                 f"{float(np.sqrt(np.mean(np.square(far)))):.3g} RMS",)
    return Solution(fb, checks, _crank_residuals(A, B, f.a0, f.a1, f.b0, f.b1), (f"route: {route}",) + extra + (
        "coupler rotations θ1j " + ", ".join(f"{math.degrees(r):.4f}°" for r in f.rotations),),
        poses=_poses(A, B), claim=claim)


def _numbers(numbers) -> str:
    """``1, 2, 3`` (or ``1 to 9`` for a run)."""
    numbers = list(numbers)
    if len(numbers) > 3 and numbers == list(range(numbers[0], numbers[-1] + 1)):
        return f"{numbers[0]} to {numbers[-1]}"
    return ", ".join(map(str, numbers))
