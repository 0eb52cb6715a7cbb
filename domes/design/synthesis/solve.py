"""One entry point for dimensional synthesis: a task in, every solution out, checked and ranked.

:func:`synthesize` follows ``scipy.optimize``: one function for every kind
of task, a result object (:class:`Synthesis`) with ``status``, ``success``,
``message``, the solutions and the numbers that show their quality (the
residual at every precision position, the checks, the structural error).

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
from domes.design.synthesis import sliders as sl
from domes.design.synthesis.candidate import CurveTask, Dimensioning, SolutionSet, dimension
from domes.design.synthesis.displacement import moved, rotation_about
from domes.design.synthesis.fourbars import Checks, FourBar, SliderCrank, check, check_slider
from domes.design.synthesis.task import GuidanceTask, PathTask, RotationTask, min_transmission
from domes.errors import InputError
from domes.motion.planar.batch import batch

#: The smallest transmission angle (°) below which a usable linkage is reported with a warning and ranked after
#: the others. The book asks only for "a reasonable transmission angle" (seed 002 §2-3); 20° is where the design
#: ranking's transmission factor reaches zero goodness (docs/expert.md).
MIN_TRANSMISSION_DEG = 20.0


@dataclass(frozen=True)
class Solution:
    """A synthesised four-bar, its checks, and its residual at every precision position (in length units)."""

    fourbar: FourBar | SliderCrank
    checks: Checks
    residuals: tuple[float, ...]
    notes: tuple[str, ...] = ()
    structural: fn.StructuralError | None = None
    respaced: fn.Respacing | None = None
    poses: tuple = ()           # the moving pivots ((a_jx, a_jy), (b_jx, b_jy)) at every precision position
    warnings: tuple[str, ...] = ()   # what a designer should look at in a usable linkage (a poor transmission angle)

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
    """Every solution of a task, ranked; ``roots`` is the count of real roots found before the checks."""

    task_name: str
    kind: str
    solutions: tuple[Solution, ...]
    roots: int
    seconds: float
    notes: tuple[str, ...] = field(default_factory=tuple)
    min_transmission_deg: float = MIN_TRANSMISSION_DEG
    items_field = "solutions"

    @property
    def message(self) -> str:
        poor = sum(1 for s in self.usable if s.warnings)
        warned = f" ({poor} of them with a transmission angle below {self.min_transmission_deg:g}°)" if poor else ""
        return (f"{self.status}: {self.task_name}: {self.roots} real root(s), {len(self.solutions)} linkage(s), "
                f"{len(self.usable)} usable{warned}; {self.seconds * 1e3:.1f} ms")


def synthesize(task, method: str = "exact", seeds: int = 64, progress=None, executor=None,
               min_transmission_deg: float | None = None) -> Synthesis | Dimensioning:
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
    """
    if method not in ("exact", "fast"):
        raise InputError(f"method must be 'exact' or 'fast', got {method!r}")
    if not (isinstance(seeds, int) and 1 <= seeds <= 100_000):
        raise InputError(f"seeds must be a whole number from 1 to 100,000, got {seeds!r}")
    if min_transmission_deg is not None:
        min_transmission_deg = min_transmission(min_transmission_deg, "min_transmission_deg")
        if isinstance(task, CurveTask):
            task = replace(task, min_transmission=math.radians(min_transmission_deg))
    if isinstance(task, CurveTask):
        if not task.candidates:
            raise InputError(f"{task.name}: no candidate to dimension (give a scene or candidates)")
        return dimension(task, task.candidates, method, seeds, progress=progress, executor=executor)
    started = time.perf_counter()
    knobs = {"method": method, "seeds": seeds}
    if isinstance(task, GuidanceTask):
        roots, sols, notes = _guidance(task, **knobs)
        kind = "guidance"
    elif isinstance(task, RotationTask):
        roots, sols, notes = _rotations(task)
        kind = "function"
    elif isinstance(task, fn.FunctionTask):
        roots, sols, notes = _function(task, **knobs)
        kind = "function"
    elif isinstance(task, PathTask):
        roots, sols, notes = _path(task, progress=progress, **knobs)
        kind = "path"
    else:
        raise InputError(f"not a synthesis task: {type(task).__name__}")
    if min_transmission_deg is None:
        min_transmission_deg = getattr(task, "min_transmission_deg", None)
    if min_transmission_deg is None:
        min_transmission_deg = MIN_TRANSMISSION_DEG
    sols = [_transmission_warning(s, min_transmission_deg) for s in sols]
    ranked = sorted(sols, key=_score)
    return Synthesis(task.name, kind, tuple(ranked), roots, time.perf_counter() - started, tuple(notes),
                     min_transmission_deg)


def _transmission_warning(s: Solution, limit: float) -> Solution:
    """``s`` with a warning when it is usable and its smallest transmission angle is below ``limit`` (°)."""
    mu = s.checks.min_transmission_deg
    if not s.usable or not mu < limit:
        return s
    return replace(s, warnings=s.warnings + (
        f"smallest transmission angle {mu:.1f}° (at the precision positions) below {limit:g}°: the linkage "
        "transmits force poorly there and may jam (limit: min_transmission_deg, --min-transmission)",))


def _score(s: Solution):
    error = s.structural.largest if s.structural is not None else 0.0
    return (not s.usable, bool(s.warnings), error, -s.checks.min_transmission_deg)


# -- guidance --------------------------------------------------------------------------------

def _guidance(task: GuidanceTask, method: str = "exact", seeds: int = 64):
    positions = list(task.positions)
    n = len(positions)
    notes = []
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
            sols.append(Solution(sc, check_slider(sc, A, B), res, poses=_poses(A, B)))
            continue
        fb = FourBar(a.a0, a.a1, b.a1, b.a0, positions[0].point)
        res = tuple(max(abs(np.linalg.norm(A[j] - a.a0) - a.radius), abs(np.linalg.norm(B[j] - b.a0) - b.radius))
                    for j in range(n))
        sols.append(Solution(fb, check(fb, A, B), res, poses=_poses(A, B)))
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
    return 1, [Solution(fb, check(fb, A, B), res, (note,), poses=_poses(A, B))], []


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
        sols.append(Solution(fb, check(fb, A, B), res, notes, err, respaced, _poses(A, B)))
    return len(gens), sols, []


def generator_fourbar(g: fn.FunctionGenerator, theta: float, phi: float) -> FourBar:
    """The generator's linkage drawn at crank angle ``theta`` and rocker angle ``phi`` (frame (0, 0)-(d, 0))."""
    return FourBar((0.0, 0.0), (g.crank * math.cos(theta), g.crank * math.sin(theta)),
                   (g.frame + g.rocker * math.cos(phi), g.rocker * math.sin(phi)), (g.frame, 0.0))


# -- path generation ----------------------------------------------------------------------------

def _path(task: PathTask, method: str = "exact", seeds: int = 64, progress=None):
    if not task.exhaustive:
        return _path_fit(task, method, seeds, progress)
    a0, b0 = task.pivot("a0"), task.pivot("b0")
    found = pt.five_points(task.points, a0, b0, method=method, seeds=seeds, progress=progress)
    sols = []
    for f in found:
        fb = FourBar(a0, f.a1, f.b1, b0, task.points[0])
        A, B = pt.coupler_positions(task.points, f)
        a_r, b_r = math.dist(f.a1, a0), math.dist(f.b1, b0)
        res = tuple(max(abs(math.dist(A[j], a0) - a_r), abs(math.dist(B[j], b0) - b_r))
                    for j in range(len(A)))
        sols.append(Solution(fb, check(fb, A, B), res, (
            "coupler rotations θ1j " + ", ".join(f"{math.degrees(r):.4f}°" for r in f.rotations),),
            poses=_poses(A, B)))
    where = (f"on {pt.GRID} × {pt.GRID} grids of (θ12, θ13) and (θ14, θ15)" if method == "exact"
             else f"from {seeds} random starts (fast: some roots may be missing)")
    return len(found), sols, [f"{len(found)} real solution(s) {where}"]


def _path_fit(task: PathTask, method: str, seeds: int, progress=None):
    """Table 2-1's other free choices, prescribed input angles, or least squares (:mod:`.pathfit`); an exact
    problem with no root found is answered by least squares, and the notes say so."""
    given = dict(task.given)
    n = len(task.points)
    kind = pf.check_given(n, given, task.crank)
    starts = 64 * seeds if method == "exact" else 8 * seeds
    eqs, unknowns, _ = pf.problem_counts(n, task.crank)
    line = pf.on_one_line(task.points)
    notes = []
    if len(line) > pf.ON_ONE_LINE:
        notes.append(f"points {_numbers(line)} lie on one line: a four-bar's coupler curve (a sextic) meets a line "
                     f"in at most {pf.ON_ONE_LINE} points, so no four-bar passes through them all")
    found = []
    if kind == "exact" and not notes:
        found = pf.fit(task.points, given, task.crank, starts=starts, progress=progress)
        if not found:
            notes.append(f"no four-bar found through the {n} points exactly ({eqs} equations, {unknowns} unknowns, "
                         f"{len(given)} given: Table 2-1; {starts} random starts)")
    if kind == "exact" and not found:
        kind = "least squares"
        found = pf.fit(task.points, given, task.crank, starts=starts, least_squares_only=True, progress=progress)
        notes.append("answered by least squares: the nearest four-bars, each with its distance from every point"
                     if found else "nor by least squares: no minimum met every point on one assembly mode with links "
                     "of useful length; try more starts (seeds) or other points")
    elif kind == "least squares":
        found = pf.fit(task.points, given, task.crank, starts=starts, progress=progress)
    sols = []
    for f in found:
        fb = FourBar(f.a0, f.a1, f.b1, f.b0, task.points[0])
        A, B = pt.coupler_positions(task.points, pt.PathSolution(f.a1, f.b1, f.rotations, f.residual))
        if kind == "exact":
            a_r, b_r = math.dist(f.a1, f.a0), math.dist(f.b1, f.b0)
            res = tuple(max(abs(math.dist(A[j], f.a0) - a_r), abs(math.dist(B[j], f.b0) - b_r))
                        for j in range(len(A)))
            extra = ()
        else:
            res = curve_distances(fb, task.points)
            extra = (f"least squares: distance of the points from the coupler curve {max(res):.3g} largest, "
                     f"{float(np.sqrt(np.mean(np.square(res)))):.3g} RMS",)
        sols.append(Solution(fb, check(fb, A, B), res, extra + (
            "coupler rotations θ1j " + ", ".join(f"{math.degrees(r):.4f}°" for r in f.rotations),),
            poses=_poses(A, B)))
    if kind == "exact":
        note = (f"{len(found)} distinct real root(s) found from {starts} random starts ({eqs} equations, {unknowns} "
                f"unknowns, {len(given)} given: Table 2-1); roots no start reached are missing")
    else:
        note = (f"least squares: {eqs} equations in {unknowns - len(given)} unknowns (Table 2-1); the {len(found)} "
                f"best local minima of {starts} random starts")
    return len(found), sols, notes + [note]


def _numbers(numbers) -> str:
    """``1, 2, 3`` (or ``1 to 9`` for a run)."""
    numbers = list(numbers)
    if len(numbers) > 3 and numbers == list(range(numbers[0], numbers[-1] + 1)):
        return f"{numbers[0]} to {numbers[-1]}"
    return ", ".join(map(str, numbers))


def curve_distances(fb: FourBar, points) -> tuple[float, ...]:
    """The distance of each point from the coupler curve of ``fb`` on its drawn assembly mode (the one through the
    first point): the nearest of 2,880 crank angles, then 400 around it, evaluated by the kernel."""
    mech = fb.mechanism()
    grid = np.linspace(-math.pi, math.pi, 2881)
    b = batch(mech, inputs=grid, outputs=["point:P"])
    curve = np.c_[b.values["point:P.x"][0], b.values["point:P.y"][0]]
    pts = np.asarray(points, dtype=float)
    near = [int(np.nanargmin(np.linalg.norm(curve - p, axis=1))) for p in pts]
    h = grid[1] - grid[0]
    local = np.concatenate([np.linspace(grid[k] - 2 * h, grid[k] + 2 * h, 401) for k in near])
    fine = batch(mech, inputs=local, outputs=["point:P"])
    xy = np.c_[fine.values["point:P.x"][0], fine.values["point:P.y"][0]].reshape(len(pts), 401, 2)
    return tuple(min(_polyline_distance(xy[j], p, closed=False), _polyline_distance(curve, p))
                 for j, p in enumerate(pts))


def _polyline_distance(poly: np.ndarray, p: np.ndarray, closed: bool = True) -> float:
    """The distance from ``p`` to the polyline ``poly`` (segments with a NaN end left out)."""
    a, b = (poly, np.roll(poly, -1, axis=0)) if closed else (poly[:-1], poly[1:])
    d = b - a
    t = np.clip(np.einsum("ij,ij->i", p - a, d) / np.maximum(np.einsum("ij,ij->i", d, d), 1e-300), 0.0, 1.0)
    return float(np.nanmin(np.linalg.norm(a + t[:, None] * d - p, axis=1)))
