"""A cam in parallel with a two-input linkage: the cam that makes a point follow a path (seed 002 §3-3-III.2, Fig. 3-28).

Parallel combination: the base mechanism has two inputs, a crank turning
on the frame and a follower sliding on it; a cam fixed to the crank drives
the follower, so the whole is a one-DOF mechanism. Choosing the linkage's
dimensions so that a point ``C`` follows a wanted closed path ``S`` fixes,
at every crank angle ``φ₁``, where the follower must be: ``S_D(φ₁)``. That
function is the cam's motion law, and the cam profile follows from it
(:func:`domes.design.cam.design_cam`).

:func:`cam_for_path` finds ``S_D(φ₁)`` by continuation round one turn of the
crank: at each angle Newton's method solves ``C(φ₁, s) = S(u)`` for the
follower's slide ``s`` and the path's parameter ``u``, with the kinematics
backend's positions and rates. The cam's centre is the crank's pivot; its
follower is the slider's point at the P joint (a roller there if
``roller > 0``): the follower's axis, offset and base radius come from the
linkage. The result is checked the other way round: the follower is moved
by the designed cam's profile (the contact condition,
:func:`domes.design.cam.follow`), the linkage is placed at those two inputs
and the point's distance from the path is measured.

>>> import numpy as np
>>> from domes.io.mechanisms import load_mechanism
>>> mech = load_mechanism("examples/mechanisms/five-bar-cam.json")
>>> t = np.linspace(0, 2 * np.pi, 73)
>>> combo = cam_for_path(mech, np.c_[np.cos(t), 2.2 + 0.6 * np.sin(t)], "C", roller=0.2)
>>> combo.success, combo.turns, combo.path_error < 1e-8
(True, 0, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from domes.design.cam import MAX_POINTS, Cam, Follower, design_cam, follow
from domes.errors import InputError, NumericalError
from domes.model.laws import from_table
from domes.model.mechanism import Mechanism
from domes.motion.planar.query import Kinematics
from domes.results import Result, Status


@dataclass(frozen=True, eq=False)
class CamCombination(Result):
    """The cam for a path: the follower's slide ``drive`` at crank angles ``theta`` (from the drawn pose), the
    designed :class:`~domes.design.cam.Cam` and its profile in the crank's frame (``profile``, mechanism
    coordinates at the drawn pose), and the check: ``path_error``, the largest distance of the point from the
    path with the follower moved by the cam's profile, relative to the mechanism's size."""

    mechanism: str
    point: str
    theta: np.ndarray
    drive: np.ndarray
    cam: Cam
    profile: np.ndarray
    path_error: float
    turns: int
    covered: float
    status: Status = Status.COMPLETE

    @property
    def warnings(self) -> tuple[str, ...]:
        return self.cam.warnings

    @property
    def message(self) -> str:
        stroke = float(np.ptp(self.drive))
        how = ("goes round the path once per turn" if self.turns else
               f"runs back and forth over {100 * self.covered:.1f}% of the path's length each turn")
        return (f"{self.status}: a cam on the crank of {self.mechanism} drives its follower through a stroke of "
                f"{stroke:.6g}; {self.point} {how}, at most {self.path_error:.2g} of the size from it with the "
                f"follower moved by the cam's profile; {self.cam.message.split(': ', 1)[1]}")


def _inputs(mech: Mechanism):
    if len(mech.inputs) != 2:
        raise InputError(f"{mech.name}: a cam in parallel needs a linkage of two inputs (a crank and a follower's "
                         f"slide), this one has {len(mech.inputs)}")
    crank, slide = (mech.joint(i.joint) for i in mech.inputs)
    if crank.kind != "R" or mech.ground not in crank.links:
        raise InputError(f"{mech.name}: the first input {crank.name!r} must be a revolute on the frame (the crank "
                         "carrying the cam)")
    if slide.kind != "P" or slide.links[0] != mech.ground:
        raise InputError(f"{mech.name}: the second input {slide.name!r} must be a P joint whose guide is the frame "
                         "(the translating follower)")
    return crank, slide


def _path(points):
    """A cubic spline through the path's points by chord length: periodic when the last point repeats the first."""
    P = np.asarray(points, dtype=float)
    if P.ndim != 2 or P.shape[1] != 2 or len(P) < 8 or not np.all(np.isfinite(P)):
        raise InputError(f"the path needs at least 8 finite points (x, y), got an array of shape {P.shape}")
    closed = bool(np.all(P[0] == P[-1]))
    u = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(P, axis=0).T))])
    if np.any(np.diff(u) <= 0):
        raise InputError("the path repeats a point; give distinct points in order along the path")
    return CubicSpline(u, P, bc_type="periodic" if closed else "not-a-knot"), float(u[-1]), closed


def _place(kin, crank, slide, q1, q2, point):
    """The point and its rate in the follower's slide at inputs ``(q1, q2)``; None where the linkage does not assemble."""
    try:
        v = kin.at({crank: q1, slide: q2}, order=1, speeds={crank: 0.0, slide: 1.0}).values
    except NumericalError:
        return None
    return (np.array([v[f"point:{point}.x"], v[f"point:{point}.y"]]),
            np.array([v[f"point:{point}.x'"], v[f"point:{point}.y'"]]))


def _solve(kin, crank, slide, q1, q2, u, spline, size, point, end=math.inf):
    """Damped Newton on ``C(q1, q2) = S(u)`` for ``q2`` and ``u``, from the last crank angle's solution.

    ``end`` is an open path's length: a foot beyond an end is refused.
    """
    here = _place(kin, crank, slide, q1, q2, point)
    for _ in range(60):
        if here is None:
            break
        C, dC = here
        r = C - spline(u)
        J = np.column_stack([dC, -spline(u, 1)])
        try:
            dx = np.linalg.solve(J, -r)
        except np.linalg.LinAlgError:
            break
        if np.max(np.abs(dx)) <= 1e-13 * size:
            return q2, u, float(np.hypot(*r))
        for _ in range(40):  # halve the step until the linkage assembles and the miss shrinks
            nxt = _place(kin, crank, slide, q1, q2 + dx[0], point)
            if nxt is not None and np.hypot(*(nxt[0] - spline(u + dx[1]))) < max(np.hypot(*r), 1e-12 * size) * 1.5:
                break
            dx = dx / 2
        else:
            break
        q2, u, here = q2 + dx[0], u + dx[1], nxt
        if not -1e-9 * end <= u <= end * (1 + 1e-9):
            raise InputError(f"at crank angle {math.degrees(q1):.2f}° {point} would run off the end of the path (an "
                             "open path must hold every position of a turn)")
    raise NumericalError(f"at crank angle {math.degrees(q1):.2f}° no position of the follower puts {point} on the path: "
                         "the linkage cannot reach it there")


def _distance(spline, C, u, lo=-math.inf, hi=math.inf) -> float:
    """The distance of ``C`` from the path, by Newton on the foot's parameter from ``u`` (kept in ``[lo, hi]``)."""
    for _ in range(30):
        r, t, k = spline(u) - C, spline(u, 1), spline(u, 2)
        du = -float(np.dot(r, t)) / (float(np.dot(t, t)) + float(np.dot(r, k)))
        u = min(max(u + du, lo), hi)
        if abs(du) < 1e-15 * (1.0 + abs(u)):
            break
    return float(np.hypot(*(spline(u) - C)))


def cam_for_path(mech: Mechanism, path, point: str, roller: float = 0.0, samples: int = 360,
                 max_pressure_deg: float | None = None) -> CamCombination:
    """The cam on ``mech``'s crank that drives its follower so that ``point`` follows the closed ``path``.

    ``mech`` has two inputs: a revolute of the crank on the frame, then a P
    joint of the follower on the frame. ``path`` is a curve through points
    (a cubic spline by chord length; closed and periodic when the last point
    repeats the first); the drawn pose's point should lie on it. The point
    may go round a closed path once per turn, or run back and forth over a
    part of it (``turns``, ``covered``). ``samples`` crank angles per turn make the
    cam's table. Raises an InputError where the point cannot go round the
    path once per turn of the crank or the follower cannot be pushed by a
    cam (see the module's docstring).
    """
    crank, slide = _inputs(mech)
    if not (isinstance(samples, int) and 36 <= samples <= MAX_POINTS // 2):
        raise InputError(f"samples must be a whole number from 36 to {MAX_POINTS // 2:,}, got {samples!r}")
    if not (isinstance(roller, (int, float)) and math.isfinite(roller) and roller >= 0):
        raise InputError(f"the roller's radius must be a number >= 0, got {roller!r}")
    spline, length, closed = _path(path)
    kin = Kinematics(mech, outputs=[f"point:{point}", f"point:{slide.name}"], order=1)
    size = mech.size
    drawn = kin.drawn_inputs()
    q1_0, q2 = drawn[crank.name], drawn[slide.name]
    step = kin.at(drawn)
    C0 = np.array([step.values[f"point:{point}.x"], step.values[f"point:{point}.y"]])
    fine = np.linspace(0.0, length, 64 * len(np.atleast_2d(path)), endpoint=False)
    u = float(fine[np.argmin(np.hypot(*(spline(fine) - C0).T))])
    theta = np.linspace(0.0, 2 * math.pi, samples + 1)
    drive, us = np.empty(samples + 1), np.empty(samples + 1)
    for k, t in enumerate(theta):
        if k == 0:
            C = spline(u)
            miss = float(np.hypot(*(C - C0)))
            if miss > 1e-3 * size:
                raise InputError(f"{mech.name}: the drawn pose's {point} is {miss:.3g} from the path; draw it on the path")
        q2, u, _ = _solve(kin, crank.name, slide.name, q1_0 + t, q2, u, spline, size, point,
                          math.inf if closed else length)
        drive[k], us[k] = q2, u
    turns = (us[-1] - us[0]) / length
    if abs(turns - round(turns)) > 1e-6 or abs(round(turns)) > 1 or abs(drive[-1] - drive[0]) > 1e-9 * size:
        raise InputError(f"{mech.name}: as the crank turns once, {point} does not come back to where it started "
                         f"({turns:.3g} times round the path); a cam needs a motion that repeats every turn")
    if np.any(np.abs(np.diff(us)) > 0.25 * length):
        raise InputError(f"{mech.name}: {point} jumps along the path between two crank angles; use more samples")
    covered = 1.0 if round(turns) else float(np.ptp(us)) / length
    # The follower's axis in the frame: the slide line through the follower's point, pointing away from the cam.
    A = np.array(crank.at)
    Rf = np.array(slide.at)
    u_slide = np.array([math.cos(slide.direction), math.sin(slide.direction)])
    along = float(np.dot(Rf - A, u_slide))
    d = (drive - drawn[slide.name]) + along
    sense = 1.0 if np.all(d > 0) else -1.0 if np.all(d < 0) else 0.0
    if not sense:
        raise InputError(f"{mech.name}: the follower's point passes the foot of the perpendicular from the cam's centre "
                         f"{tuple(A)} on its slide: a cam cannot push it both ways; move the slide line or the cam")
    d, out = sense * d, sense * u_slide
    offset = float((Rf - A)[0] * out[1] - (Rf - A)[1] * out[0])
    y0 = float(d.min())
    prime = math.hypot(offset, y0)
    if prime <= roller:
        raise InputError(f"the roller's radius {roller:g} is not smaller than the prime circle's {prime:.4g}")
    follower = Follower("translating", "roller" if roller > 0 else "knife", roller=float(roller), offset=offset)
    motion = from_table(theta, np.append(d[:-1], d[0]) - y0, periodic=True)
    cam = design_cam(motion, follower, prime - roller, 1, 2 * samples, max_pressure_deg)
    # The profile in the frame at the drawn pose: the cam's frame turns the follower's axis to +y.
    turn = math.atan2(out[1], out[0]) - math.pi / 2
    c, s = math.cos(turn), math.sin(turn)
    profile = A + cam.profile @ np.array([[c, s], [-s, c]])
    # The check: the follower moved by the cam's profile, the linkage placed there, the point's distance from the path.
    check = np.linspace(0.0, 2 * math.pi, 4 * samples, endpoint=False)
    moved = follow(cam, follower, cam.base_radius, check)
    worst = 0.0
    for t, lift in zip(check, moved.s):
        q2 = drawn[slide.name] + sense * (lift + y0) - along
        v = kin.at({crank.name: q1_0 + t, slide.name: q2}).values
        worst = max(worst, _distance(spline, np.array([v[f"point:{point}.x"], v[f"point:{point}.y"]]),
                                     float(np.interp(t, theta, us)), *((-math.inf, math.inf) if closed else (0, length))))
    return CamCombination(mech.name, point, theta[:-1], drive[:-1], cam, profile, worst / size, int(round(turns)),
                          covered)


__all__ = ["CamCombination", "cam_for_path"]
