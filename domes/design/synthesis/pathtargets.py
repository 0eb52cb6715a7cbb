"""Published path-synthesis targets and their solutions, measured the same way as ours (issue 27, item 1).

A target (one entry of ``benchmarks/data/published_paths.json``) is a list of
points, closed, open or partial, sometimes with prescribed timing (the
crank's angles at the points). A published solution is a four-bar given in
its paper's parameters; :func:`published_fourbar` turns it into a
:class:`~domes.design.synthesis.fourbars.FourBar` in the two conventions the
sources use (four-bar-rs's ``p0x p0y a l1..l5 g inv``; the Freudenstein form
``r1..r4 rcx rcy x0 y0 theta0`` of the metaheuristic literature).
:func:`measure` is the one protocol for every linkage, found or published:
the kinematics kernel traces its coupler curve, and each target point's
distance from the circuit the points lie nearest gives the worst and RMS
error over the target's size; with timing, the kernel also drives the crank
to the prescribed angles and the coupler point's distance from each target
point gives the timed error.

>>> fb = published_fourbar({"convention": "four-bar-rs", "values": {"p0x": 0, "p0y": 0, "a": 0, "l1": 90,
...     "l2": 35, "l3": 70, "l4": 70, "l5": 45, "g": 0.5236, "inv": False}}, 0.0)
>>> [round(v, 3) for v in fb.lengths]
[35.0, 70.0, 70.0, 90.0]
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from domes.design.synthesis.fourbars import FourBar
from domes.design.synthesis.pathroute import fourbar_of, polished_path
from domes.design.synthesis.verify import replay
from domes.errors import InputError
from domes.motion.coupler.curves import trace
from domes.motion.coupler.freehand import polyline_distances

#: Kernel positions per input turn of the traced curve a point's distance is measured from (then refined).
SAMPLES = 20000
#: The conventions :func:`published_fourbar` reads.
CONVENTIONS = ("four-bar-rs", "freudenstein")


@dataclass(frozen=True)
class Measured:
    """Errors of one linkage on one target, as shares of the target's size: the worst and RMS distance of the
    points from its coupler curve (one circuit), and with timing the worst and RMS distance of the coupler point at
    the prescribed crank angles from the points (None without timing; inf where the loop does not close)."""

    worst: float
    rms: float
    timed_worst: float | None = None
    timed_rms: float | None = None


def load(path) -> dict:
    """The targets file (``benchmarks/data/published_paths.json``), each target's points checked."""
    data = json.loads(Path(path).read_text())
    for t in data["targets"]:
        pts = np.asarray(t["points"], dtype=float)
        if pts.ndim != 2 or pts.shape[1] != 2 or not np.isfinite(pts).all():
            raise InputError(f"{path}: target {t.get('id')!r}: points must be finite (x, y) pairs")
    return data


def size_of(points) -> float:
    """A target's size: the larger side of its bounding box."""
    return float(np.max(np.ptp(np.asarray(points, dtype=float), axis=0)))


def crank_angles(target: dict, first: float) -> tuple[float, ...] | None:
    """The prescribed crank angles (rad) at the target's points when the first is ``first``; None without timing.
    ``crank_deg`` lists them from the frame, ``crank_step_deg`` is the rotation from each point to the next."""
    if "crank_deg" in target:
        base = math.radians(target["crank_deg"][0])
        return tuple(first + math.radians(v) - base for v in target["crank_deg"])
    if "crank_step_deg" in target:
        return tuple(first + k * math.radians(target["crank_step_deg"]) for k in range(len(target["points"])))
    return None


def _circles(p, q, r1: float, r2: float, left: bool):
    """The meeting point of the circles (``p``, ``r1``) and (``q``, ``r2``) on the left of ``p → q`` (right when
    not ``left``); None when they do not meet."""
    d = np.subtract(q, p)
    r = math.hypot(*d)
    if r == 0 or r > r1 + r2 or r < abs(r1 - r2):
        return None
    a = 0.5 * (r1 * r1 - r2 * r2 + r * r) / r
    h = math.sqrt(max(r1 * r1 - a * a, 0.0)) * (1 if left else -1)
    c, s = d / r
    return (p[0] + a * c - h * s, p[1] + a * s + h * c)


def published_fourbar(solution: dict, theta: float) -> FourBar | None:
    """The published ``solution`` as a four-bar drawn with its crank at ``theta`` (rad; four-bar-rs: from the
    frame; Freudenstein: from the frame, before the turn ``theta0``); None where the loop does not close there."""
    v, kind = solution["values"], solution["convention"]
    if kind == "four-bar-rs":
        a0 = (v["p0x"], v["p0y"])
        b0 = (a0[0] + v["l1"] * math.cos(v["a"]), a0[1] + v["l1"] * math.sin(v["a"]))
        a1 = (a0[0] + v["l2"] * math.cos(v["a"] + theta), a0[1] + v["l2"] * math.sin(v["a"] + theta))
        b1 = _circles(a1, b0, v["l3"], v["l4"], not v["inv"])
        if b1 is None:
            return None
        g = math.atan2(b1[1] - a1[1], b1[0] - a1[0]) + v["g"]
        return FourBar(a0, a1, b1, b0, (a1[0] + v["l5"] * math.cos(g), a1[1] + v["l5"] * math.sin(g)))
    if kind == "freudenstein":
        r1, r2, r3, r4, rcx, rcy = (v[k] for k in ("r1", "r2", "r3", "r4", "rcx", "rcy"))
        k1, k4, k5 = r1 / r2, r1 / r3, (r4 ** 2 - r1 ** 2 - r2 ** 2 - r3 ** 2) / (2 * r3 * r2)
        D = math.cos(theta) - k1 + k4 * math.cos(theta) + k5
        E = -2 * math.sin(theta)
        F = k1 + (k4 - 1) * math.cos(theta) + k5
        if E * E - 4 * D * F < 0 or D == 0:
            return None
        t3 = 2 * math.atan((-E - math.sqrt(E * E - 4 * D * F)) / (2 * D))
        a1 = np.array([r2 * math.cos(theta), r2 * math.sin(theta)])
        b1 = a1 + r3 * np.array([math.cos(t3), math.sin(t3)])
        p = a1 + np.array([rcx * math.cos(t3) - rcy * math.sin(t3), rcx * math.sin(t3) + rcy * math.cos(t3)])
        c, s = math.cos(v.get("theta0", 0.0)), math.sin(v.get("theta0", 0.0))
        x0, y0 = v.get("x0", 0.0), v.get("y0", 0.0)

        def world(q):
            return (c * q[0] - s * q[1] + x0, s * q[0] + c * q[1] + y0)

        return FourBar(world((0.0, 0.0)), world(a1), world(b1), world((r1, 0.0)), world(p))
    raise InputError(f"a published solution's convention is one of {', '.join(CONVENTIONS)}, got {kind!r}")


def published_drawn(target: dict, solution: dict) -> tuple[FourBar | None, tuple[float, ...] | None]:
    """The published solution drawn at its first point, and its crank angles (world, rad) at the points when the
    target prescribes timing (else None). A four-bar-rs solution (no printed crank angle) is drawn at the first
    whole degree where its loop closes."""
    v = solution["values"]
    if solution["convention"] == "freudenstein":
        first = v["theta2"][0] if "theta2" in v else math.radians(target["crank_deg"][0])
        return published_fourbar(solution, first), crank_angles(target, first + v.get("theta0", 0.0))
    for k in range(360):
        fb = published_fourbar(solution, math.radians(k))
        if fb is not None:
            return fb, None
    return None, None


def _local(fb: FourBar, circuit, k: int, p: np.ndarray) -> float:
    """The distance of ``p`` from the circuit about its sample ``k``: the linkage drawn there (its assembly mode)
    driven by the kernel over 401 input angles across the samples ``k − 1`` to ``k + 1``, and the distance from
    the chords between those positions; inf where it does not close."""
    n = len(circuit.inputs)
    lo, hi = circuit.inputs[max(k - 1, 0)], circuit.inputs[min(k + 1, n - 1)]
    B, C = circuit.extra["B"][k], circuit.extra["C"][k]
    drawn = FourBar(fb.a0, tuple(B), tuple(C), fb.b0, tuple(circuit.points[k]))
    r = replay(drawn, np.linspace(lo, hi, 401), ["point:P"], between=False)
    xy = np.c_[r.values["point:P.x"], r.values["point:P.y"]]
    xy = xy[np.all(np.isfinite(xy), axis=1)]
    return float(polyline_distances(xy, p[None], closed=False)[0]) if len(xy) > 1 else math.inf


def curve_errors(fb: FourBar, points, samples: int = SAMPLES) -> np.ndarray:
    """The distance of each point from the coupler curve of ``fb`` traced by the kernel: on the circuit the points
    lie nearest (RMS over its ``samples`` positions per turn), the distance from the chords between them or, when
    smaller, from the linkage drawn at the nearest position and driven over 401 input angles about it; inf where
    the linkage has no curve."""
    pts = np.asarray(points, dtype=float)
    try:
        circuits = trace(fb.mechanism(), "P", samples, extra=("B", "C")).circuits
    except InputError:
        circuits = ()
    best, chosen = np.full(len(pts), math.inf), None
    for circuit in circuits:
        ok = np.all(np.isfinite(circuit.points), axis=1)
        if ok.sum() < 3:
            continue
        d = polyline_distances(circuit.points[ok], pts)
        if np.sqrt(np.mean(d ** 2)) < np.sqrt(np.mean(best ** 2)):
            best, chosen = d, circuit
    if chosen is None:
        return best
    gap = np.sum((chosen.points[None, :, :] - pts[:, None, :]) ** 2, axis=2)
    near = np.argmin(np.where(np.isfinite(gap), gap, np.inf), axis=1)
    out = np.array([_local(fb, chosen, int(k), p) for p, k in zip(pts, near)])
    return np.minimum(out, best)


def measure(fb: FourBar, points, angles=None, samples: int = SAMPLES) -> Measured:
    """The protocol: ``fb``'s errors on ``points`` (shares of their size; the curve traced at ``samples`` positions
    per turn, then refined), and at the crank ``angles`` (world, rad) when timing is prescribed."""
    pts = np.asarray(points, dtype=float)
    size = size_of(pts)
    d = curve_errors(fb, pts, samples) / size
    if angles is None:
        return Measured(float(np.max(d)), float(np.sqrt(np.mean(d ** 2))))
    r = replay(fb, angles, ["point:P"], between=False)
    xy = np.c_[r.values["point:P.x"], r.values["point:P.y"]]
    e = np.linalg.norm(xy - pts, axis=1) / size
    e = np.where(np.isfinite(e), e, math.inf)
    return Measured(float(np.max(d)), float(np.sqrt(np.mean(d ** 2))), float(np.max(e)), float(np.sqrt(np.mean(e ** 2))))


def timed(target: dict) -> bool:
    """Whether the target prescribes the crank's angles at its points."""
    return "crank_deg" in target or "crank_step_deg" in target


def path_task(target: dict) -> dict:
    """The target as a ``domes synthesize`` path task: its points, the crank's rotations from the first point when
    timing is prescribed, and the crank pivot and frame line when the target fixes them."""
    task = {"kind": "path", "name": target["id"], "points": target["points"]}
    if timed(target):
        task["crank_deg"] = [math.degrees(a) for a in crank_angles(target, 0.0)[1:]]
    if "a0" in target:
        task["a0"] = target["a0"]
        if "frame_deg" in target and math.sin(math.radians(target["frame_deg"])) == 0:
            task["given"] = {"b0y": target["a0"][1]}
    return task


def fit_target(target: dict, closed, opened, candidates: int = 5, seeds: int = 64, starts: int = 512,
               timed_starts: int = 60):
    """Our answer to a target by the best route: ``(FourBar, crank angles or None, route)``, or ``(None, None,
    route)`` when the route finds nothing.

    With timing: the path task of ``domes synthesize`` (``seeds`` × 8 starts), whose route ends, when its own
    fit misses, in the bounded least squares of :func:`domes.motion.coupler.minimax.timed_fit` (``timed_starts``
    random starts; :mod:`.pathroute`): the answer whose kernel-checked error at the prescribed angles is
    smallest. Without timing, nine points or more: the atlas
    look-up and least squares of ``domes curves match`` (``candidates`` refined; the closed atlas ``closed`` or,
    for an open or partial path, the window index ``opened``), the best fit then polished towards the smallest
    worst point (:func:`.pathroute.polished_path`, as the path task). Fewer points: the
    path task's least squares with no pivot given (``starts`` random starts), the root whose points lie on one
    circuit of its curve (the smallest worst error on the kernel's trace).
    """
    from domes.design.synthesis import pathfit as pf
    from domes.design.synthesis.solve import synthesize
    from domes.design.synthesis.task import task_from_dict
    from domes.motion.coupler.match import match

    pts = np.asarray(target["points"], dtype=float)
    if timed(target):
        result = synthesize(task_from_dict(path_task(target)), "fast", seeds, timed_starts=timed_starts)
        answers = []
        for s in result.solutions:
            angles = crank_angles(target, s.claim.angles[0])
            r = replay(s.fourbar, angles, ["point:P"])
            xy = np.c_[r.values["point:P.x"], r.values["point:P.y"]]
            worst = float(np.max(np.linalg.norm(xy - pts, axis=1))) if r.dead is None else math.inf
            route = next((n[len("route: "):] for n in s.notes if n.startswith("route: ")), "path task")
            answers.append((worst, s.fourbar, angles, route if "timing" in route else route + ", timing"))
        answers = [a for a in answers if np.isfinite(a[0])]
        if not answers:
            return None, None, "path task and bounded least squares: no answer"
        _, fb, angles, route = min(answers, key=lambda a: a[0])
        return fb, angles, route
    if len(pts) >= 9:
        atlas = opened if target["kind"] in ("open", "partial") else closed
        found = match(pts, atlas, results=1, candidates=candidates)
        fits = [f for f in found.fits if f.mechanism is not None]
        if not fits:
            return None, None, "curves match: no fit"
        start = min(fits, key=lambda f: f.after[0])
        route = "curves match" + (" (open)" if atlas is opened else "")
    else:
        # an underdetermined task (Table 2-1 leaves free choices): its least-squares roots, of which the one whose
        # points all lie on one circuit of its curve (the kernel's trace) is kept
        found = pf.fit(pts, {}, starts=starts, keep=10, least_squares_only=True)
        if not found:
            return None, None, "path least squares: no answer"
        linkages = [FourBar(f.a0, f.a1, f.b1, f.b0, tuple(pts[0])) for f in found]
        best = min(linkages, key=lambda fb: float(np.max(curve_errors(fb, pts))))
        return best, None, "path least squares, no pivot given"
    start = fourbar_of(start.mechanism)
    found = polished_path(start, pts)
    return (found[0], None, route + ", polished") if found is not None else (start, None, route)
