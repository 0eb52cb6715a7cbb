"""A drawn path's timing: the input crank's angle at each of the user's points, or the time it was drawn.

A :class:`Timing` gives one value per point: crank **angles** (degrees; only
their differences count, the crank's zero is free) or **times**, the crank
turning at constant speed, ``angle = θ0 + ω·t``: ``θ0`` is always found by
the fit, ``ω`` (degrees per unit of time, its sign the direction; positive
is anticlockwise) is given or, when None, found too. The crank angles are
then no free unknowns of the fit: :func:`timed_fits` fits the nine
dimensions of a four-bar, ``θ0`` and (when free) ``ω`` by the bounded least
squares of the path task's timed targets
(:class:`~domes.motion.coupler.minimax.TimedProblem`), started from each
untimed fit's linkage, its Roberts-Chebyshev cognates and each driven from
either frame pivot (the timing tells them apart) and from random starts
(:func:`~domes.motion.coupler.minimax.timed_fit`). Every fit is measured
by the kinematics kernel driving its crank through the user's points at
their timed angles in one motion: the distance of each point from the
coupler point there.

>>> s = schedule(Timing([0, 10, 30, 45, 60, 90, 100, 120, 150]), 9, range(9), closed=False)
>>> s.free, [round(float(r), 4) for r in s.rotations[:3]]
(False, [0.1745, 0.5236, 0.7854])
>>> schedule(Timing([0, 1, 3, 2, 4, 5, 6, 7, 8], "time"), 9, range(9), closed=False)
Traceback (most recent call last):
 ...
domes.errors.InputError: times must increase: point 3's time 2 is not after point 2's 3
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.motion.coupler.fit import Fit, _coupler, _lengths
from domes.motion.coupler.match import cognates
from domes.motion.coupler.minimax import TimedProblem, _nearest, _start, timed_fit
from domes.motion.planar.batch import batch
from domes.results import Status

#: The kinds of timing: crank angles (degrees) or times.
KINDS = ("angle", "time")
#: Starts of the timed least squares taken from the untimed fits (the nearest at their estimated timing), and random
#: starts (:func:`~domes.motion.coupler.minimax.timed_fit`).
FROM_FITS, RANDOM = 12, 8
#: The largest crank step (degrees) between the positions at which the kernel checks a timed fit's motion.
STEP = 2.0
#: Two timed fits whose coupler points at the timing are this share of the size apart at most are one answer.
SAME = 1e-3


@dataclass(frozen=True)
class Timing:
    """One value per point of a sketch: crank angles in degrees (``kind`` "angle") or times (``kind`` "time", with
    the crank's ``speed`` in degrees per unit of time, or None: found by the fit).

    >>> Timing((0, 0.5, 1.0), "time", speed=120).kind
    'time'
    """

    values: tuple
    kind: str = "angle"
    speed: float | None = None


@dataclass(frozen=True)
class Schedule:
    """A checked timing of the sketch's (kept) points: each point's crank ``rotations`` from the first (rad), or
    with ``free`` speed its time from the first over ``span`` (0 to 1), the crank's turn over them found by the
    fit."""

    rotations: np.ndarray
    free: bool
    span: float
    timing: Timing


def schedule(timing: Timing, count: int, kept, closed: bool) -> Schedule:
    """The timing of a sketch of ``count`` points, checked, at the points ``kept`` (indices: repeats dropped);
    an InputError says what is wrong and where (points counted from 0)."""
    if not isinstance(timing, Timing):
        timing = Timing(tuple(timing))
    if timing.kind not in KINDS:
        raise InputError(f"timing kind {timing.kind!r}: give \"angle\" (crank angles, degrees) or \"time\"")
    try:
        v = np.asarray(timing.values, dtype=float)
    except (TypeError, ValueError):
        raise InputError("the timing must be a list of numbers, one per point") from None
    if v.ndim != 1 or len(v) != count:
        raise InputError(f"the timing has {v.size} values for {count} points: give one per point")
    bad = np.flatnonzero(~np.isfinite(v))
    if bad.size:
        raise InputError(f"the timing of point {bad[0]} is not a finite number: {v[bad[0]]}")
    word = "angle" if timing.kind == "angle" else "time"
    if timing.speed is not None:
        if timing.kind != "time":
            raise InputError("a crank speed goes with times, not with crank angles")
        if not (isinstance(timing.speed, (int, float)) and math.isfinite(timing.speed) and timing.speed != 0):
            raise InputError(f"the crank's speed must be a finite, non-zero number of degrees per unit of time, got "
                             f"{timing.speed!r}")
    kept = np.asarray(list(kept), dtype=int)
    if timing.kind == "time":
        _one_way(v, kept, word, increasing=True, why="times must increase")
    elif closed:
        _one_way(v, kept, word, increasing=v[kept[-1]] > v[kept[0]],
                 why="a closed path's crank angles must turn one way")
    t = v[kept] - v[kept[0]]
    if timing.kind == "angle":
        turn, free, span = np.radians(t), False, 1.0
    elif timing.speed is not None:
        turn, free, span = np.radians(timing.speed * t), False, 1.0
    else:
        span = float(t[-1])
        turn, free = t / span, True
    if closed and not free and abs(turn[-1]) >= 2 * math.pi:
        raise InputError(f"a closed path is one turn of the crank, but its timing turns it by "
                         f"{math.degrees(abs(turn[-1])):.6g}° from point {kept[0]} to point {kept[-1]}")
    return Schedule(turn[1:], free, span, timing)


def _one_way(v, kept, word: str, increasing: bool, why: str) -> None:
    step = np.diff(v[kept])
    wrong = np.flatnonzero(step <= 0 if increasing else step >= 0)
    if wrong.size:
        j = wrong[0]
        a, b = kept[j], kept[j + 1]
        raise InputError(f"{why}: point {b}'s {word} {v[b]:g} is not {'after' if word == 'time' else 'beyond'} "
                         f"point {a}'s {v[a]:g}")


@dataclass(frozen=True, eq=False)
class TimedFit(Fit):
    """A four-bar fitted to a timed sketch: ``after`` the largest and RMS distance of the user's points from its
    coupler point at their timed crank angles (the kernel driving it), ``angles`` those crank angles (world,
    degrees), ``speed`` the crank's speed (degrees per unit of time; None for crank angles), ``curve`` the
    largest and RMS distance of the points from its traced curve, wherever on it."""

    angles: tuple = ()
    speed: float | None = None
    curve: tuple = (math.inf, math.inf)

    @property
    def message(self) -> str:
        speed = "" if self.speed is None else f", crank speed {self.speed:.6g}°/unit"
        return (super().message + f"; at the given timing (crank {self.angles[0]:.6g}° at the first point{speed}); "
                f"from the curve: largest {self.curve[0]:.3g}, RMS {self.curve[1]:.3g}")


def timed_fits(points, plan: Schedule, starts, tol: float, random: int = RANDOM, tick=lambda what: None
               ) -> list[TimedFit]:
    """The four-bars meeting the sketch's ``points`` at their timing ``plan``: from each linkage in ``starts``
    (untimed fits' mechanisms) and ``random`` random starts; best first, each measured by the kernel."""
    P = np.asarray(points, dtype=float)
    problem = TimedProblem(P, plan.rotations, speed=plan.free)
    guesses = []
    for mech in starts:
        for g in _drivable(mech):
            guesses.append(_guess(problem, g, plan.free))
    guesses = [q for q in guesses if q is not None]
    guesses.sort(key=lambda q: q[0])
    found = []
    for k, (_, x0, sign) in enumerate(guesses[:FROM_FITS]):
        tick(f"timed fit {k + 1} of {min(FROM_FITS, len(guesses))} from the untimed fits")
        found.append((_error(problem, x0, sign), *_solved(problem, x0, sign)))
    if random:
        tick(f"timed fit from {random} random starts")
        speed = float(np.median([q[1][10] for q in guesses[:FROM_FITS]])) if plan.free and guesses else (
            2 * math.pi)
        r = timed_fit(P, plan.rotations * (speed if plan.free else 1.0), starts=random)
        if r is not None:
            A, D, a, b, c, uv = _start(r[0])
            x0 = [A.real, A.imag, D.real, D.imag, a, b, c, uv.real, uv.imag, r[1], speed]
            found.append(((r[2], math.inf), *_solved(problem, x0, _sign(r[0]))))
    out, moves = [], []
    for before, worst, x, sign, used in sorted(found, key=lambda f: f[1]):
        measured = _measured(problem, x, sign, plan, tol, before, used)
        if measured is None:
            continue
        f, pts = measured
        if not any(np.max(np.abs(pts - q)) <= SAME * problem.size for q in moves):
            out.append(f)
            moves.append(pts)
    out.sort(key=lambda f: (not f.success, f.after[1]))
    return out


def _solved(problem: TimedProblem, x0, sign: float):
    """``(worst, x, sign, evaluations)``: the timed least squares from ``x0``."""
    used = problem.evaluations
    worst, x, sign = problem.solve(x0, sign)
    return worst, x, sign, problem.evaluations - used


def _drivable(mech):
    """The linkage vectors ``(ax ay dx dy a b c u v)`` tracing the curve of ``mech`` with each of its three timings:
    driven by its crank, by its rocker (from the other frame pivot), and by the crank of its first cognate, which
    turns with its coupler (Roberts-Chebyshev: the other three ways of driving a cognate repeat these timings)."""
    A, B, C, D = (complex(*mech.joint(n).at) for n in "ABCD")
    P = complex(*mech.point("P")[1])
    ways = [(A, B, C, D), (D, C, B, A)]
    if B != C:
        ways.append(tuple(cognates(A, B, C, D, P)[0][:4]))
    out = []
    for p0, p1, q1, q0 in ways:
        if not all(np.isfinite(z) for z in (p0, p1, q1, q0)) or min(abs(p1 - p0), abs(q1 - p1), abs(q0 - q1)) <= 0:
            continue                                        # a degenerate linkage (a link of no length) drives nothing
        uv = (P - p1) / ((q1 - p1) / abs(q1 - p1))
        out.append(np.array([p0.real, p0.imag, q0.real, q0.imag, abs(p1 - p0), abs(q1 - p1), abs(q0 - q1),
                             uv.real, uv.imag]))
    return out


def _guess(problem: TimedProblem, g, free: bool):
    """``(error, x0, sign)``: the linkage ``g`` with the crank angle at the first point (and the speed, when free)
    that best agree with the crank angles of the points' nearest positions on its curve (the RMS distance of the
    points from its coupler point at those angles); None when a point has no position."""
    T, rel = problem.T, problem.rel
    d, theta, signs = _nearest(g, T)
    if not np.all(np.isfinite(d)):
        return None
    sign = 1.0 if np.sum(signs > 0) >= len(signs) / 2 else -1.0
    if free:
        speed, first = np.polyfit(rel, np.unwrap(theta), 1)
    else:
        speed, first = 1.0, float(np.angle(np.mean(np.exp(1j * (theta - rel)))))
    x0 = np.r_[g, first, speed]
    return _error(problem, x0, sign)[1], x0, sign


def _error(problem: TimedProblem, x, sign: float) -> tuple[float, float]:
    """The largest and RMS distance of the points from the coupler point of ``x`` at their timed crank angles."""
    P = problem.positions(x, sign)
    d = np.where(np.isfinite(P), np.abs(P - problem.T), math.inf)
    return float(np.max(d)), float(np.sqrt(np.mean(d ** 2)))


def _sign(mech) -> float:
    """The assembly mode of a drawn four-bar as :mod:`~domes.motion.coupler.minimax` counts it."""
    A, B, C, D = (complex(*mech.joint(n).at) for n in "ABCD")
    return 1.0 if ((C - B) / (D - B)).imag >= 0 else -1.0


def driven(mech, angles) -> tuple[np.ndarray, int | None]:
    """``(points, stuck)``: the coupler point of ``mech`` as the kernel drives its crank through ``angles`` (world,
    rad) in one motion, on its drawn assembly mode, with steps of at most :data:`STEP` degrees between; ``stuck``
    the first point the crank cannot reach from the one before (None when it reaches all).

    >>> from domes.motion.coupler.fourbar import four_bar
    >>> pts, stuck = driven(four_bar(1, 3.5, 3, 2, 0, 2), np.radians([0, 90, 180]))
    >>> pts.shape, stuck
    ((3, 2), None)
    """
    angles = np.asarray(angles, dtype=float)
    gaps = [np.linspace(a, b, max(2, int(math.ceil(abs(b - a) / math.radians(STEP)))) + 1)[1:-1]
            for a, b in zip(angles[:-1], angles[1:])]
    b = batch(mech, inputs=np.concatenate([angles] + gaps), outputs=["point:P"])
    n = len(angles)
    pts = np.c_[b.values["point:P.x"][0, :n], b.values["point:P.y"][0, :n]]
    ok = b.assembled[0]
    stuck, at = (None if ok[0] else 0), n
    for j, gap in enumerate(gaps, 1):
        if stuck is None and not (ok[at:at + gap.size].all() and ok[j]):
            stuck = j
        at += gap.size
    return pts, stuck


def _measured(problem: TimedProblem, x, sign: float, plan: Schedule, tol: float, before, used: int):
    """``(fit, points)``: the linkage ``x`` as a :class:`TimedFit`, measured by the kernel at its timed crank angles
    (``before``: its start's error, ``used`` the evaluations), and its coupler point there; None when it does not
    close at the first point."""
    if not problem.closes(x, sign):
        return None
    mech = problem.mechanism(x, sign)
    angles = x[9] + x[10] * problem.rel
    pts, stuck = driven(mech, angles)
    d = np.hypot(*(pts - np.c_[problem.T.real, problem.T.imag]).T)
    d = np.where(np.isfinite(d), d, math.inf)
    status, note = Status.COMPLETE, ""
    if stuck is not None:
        status, note = Status.STOPPED, f"the crank cannot turn on from point {stuck - 1} to point {stuck} in one motion"
    speed = None
    if plan.timing.kind == "time":
        speed = plan.timing.speed if not plan.free else math.degrees(x[10]) / plan.span
    after = (float(np.max(d)), float(np.sqrt(np.mean(d ** 2))))
    return TimedFit(mech, _lengths(mech), tuple(float(t) for t in _coupler(mech)), before, after, problem.size, tol,
                    used, status, note, tuple(np.degrees(angles).tolist()), speed), np.where(np.isfinite(pts), pts, 0.0)


__all__ = ["KINDS", "Schedule", "TimedFit", "Timing", "driven", "schedule", "timed_fits"]
