"""Pyslvs' metaheuristic four-bar path synthesis on a wanted closed path, as a peer for our path synthesis.

:func:`pyslvs_path_synthesis` gives Pyslvs' dimensional synthesis (the objective
:class:`pyslvs.optimization.FPlanar` behind its "dimensional synthesis" dialog,
solved by one of the algorithms of :mod:`pyslvs.metaheuristics`: DE, RGA, FA
(Firefly), TLBO, PSO) the points of a wanted path, an ``(n, 2)`` array, for the
coupler point of the collection "Four bar linkage mechanism" (crank P0-P2,
coupler P2-P3 carrying the coupler point P4, rocker P3-P1). It returns the
wall time, the linkage found and its fit, measured here and not by Pyslvs: the
coupler curve of the linkage found is traced over a full crank turn and each
wanted point's distance to it is taken. It returns None when Pyslvs is not
installed.

Run ``python benchmarks/peer_synthesis.py`` to fit the 48 points of
``examples/curves/figure-eight.csv`` with DE for 100 and 300 generations.
"""

from __future__ import annotations

import ctypes
import ctypes.util
import math
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
#: The Pyslvs collection whose four-bar is synthesised, its input pair, ground joints and coupler point.
COLLECTION = "Four bar linkage mechanism"
#: The expression stack Pyslvs builds for it; it fixes the layout of the variable vector.
STACK = [("PLA", "P0", "L0", "I0", "P2"), ("PLLP", "P2", "L1", "L2", "P1", "P3"),
         ("PLAP", "P2", "L3", "A0", "P3", "P4")]
#: Short names of the algorithms (``pyslvs.metaheuristics.AlgorithmType`` member names, values also accepted).
ALIASES = {"FIREFLY": "FA", "GA": "RGA"}
SAMPLES = 3600


def _algorithm_type(name):
    """The ``AlgorithmType`` called ``name`` (a member name, an alias or the full name)."""
    from pyslvs.metaheuristics import AlgorithmType

    key = ALIASES.get(name.upper(), name.upper())
    for member in AlgorithmType:
        if key == member.name or name.lower() == member.value.lower():
            return member
    raise ValueError(f"unknown algorithm {name!r}; one of {[m.name for m in AlgorithmType]} or 'Firefly'")


def _seed_libc(seed):
    """Seed the C library's ``rand``, the only random source of Pyslvs' algorithms (they seed it with the time).

    ``srand(seed + 1)``: glibc takes seed 0 as 1, so seeds 0 and 1 would give the same run.
    """
    libc = ctypes.CDLL(ctypes.util.find_library("c") or None)
    libc.srand(ctypes.c_uint((seed + 1) & 0xFFFFFFFF))


def _trace(pivot_a, pivot_d, crank, coupler, rocker, point_len, point_angle, branch, samples=SAMPLES):
    """Coupler point over a crank turn on both branches: ``(points (2, samples, 2), feasible (samples,))``.

    ``branch`` +1 puts the coupler-rocker pin C to the left of the line from the crank pin B to the rocker pivot D
    (Pyslvs' PLLP solution), -1 to the right; the coupler point lies ``point_len`` from B at ``point_angle``
    counter-clockwise from BC.
    """
    theta = np.linspace(0.0, 2 * math.pi, samples, endpoint=False)
    b = np.asarray(pivot_a) + crank * np.column_stack([np.cos(theta), np.sin(theta)])
    bd = np.asarray(pivot_d) - b
    d = np.hypot(bd[:, 0], bd[:, 1])
    feasible = (d <= coupler + rocker) & (d >= abs(coupler - rocker)) & (d > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        e = bd / d[:, None]
        x = (coupler ** 2 - rocker ** 2 + d ** 2) / (2 * d)
        h = np.sqrt(np.clip(coupler ** 2 - x ** 2, 0.0, None))
    perp = np.column_stack([-e[:, 1], e[:, 0]])
    out = np.empty((2, samples, 2))
    for k, s in enumerate((branch, -branch)):
        c = b + x[:, None] * e + s * h[:, None] * perp
        phi = np.arctan2(c[:, 1] - b[:, 1], c[:, 0] - b[:, 0]) + point_angle
        out[k] = b + point_len * np.column_stack([np.cos(phi), np.sin(phi)])
    out[:, ~feasible] = np.nan
    return out, feasible


def _segments(curves, feasible, both):
    """Segments ``(m, 2, 2)`` of the traced curve: one branch if the crank turns fully, else both, joined at dead points."""
    n = len(feasible)
    nxt = np.roll(np.arange(n), -1)
    ok = feasible & feasible[nxt]
    parts = [np.stack([curves[0][ok], curves[0][nxt][ok]], axis=1)]
    if both:
        parts.append(np.stack([curves[1][ok], curves[1][nxt][ok]], axis=1))
        ends = feasible & ~(feasible[nxt] & feasible[np.roll(np.arange(n), 1)])  # last sample before a dead point
        parts.append(np.stack([curves[0][ends], curves[1][ends]], axis=1))
    return np.concatenate(parts)


def _distances(points, segments):
    """Distance from each point to the nearest segment."""
    p0, p1 = segments[:, 0], segments[:, 1]
    d = p1 - p0
    dd = np.einsum("ij,ij->i", d, d)
    rel = points[:, None, :] - p0[None]
    t = np.clip(np.einsum("kij,ij->ki", rel, d) / np.where(dd > 0, dd, 1.0), 0.0, 1.0)
    gap = rel - t[..., None] * d[None]
    return np.sqrt(np.einsum("kij,kij->ki", gap, gap)).min(axis=1)


def pyslvs_path_synthesis(points: np.ndarray, algorithm: str = "DE", max_gen: int = 200,
                          seed: int | None = 0) -> dict | None:
    """Fit Pyslvs' four-bar to the closed path ``points`` (n, 2) with one metaheuristic; None without Pyslvs.

    The dict holds ``seconds`` (wall time of building the objective and running the algorithm), ``lengths``
    (crank, coupler, rocker, frame), ``max_error`` and ``rms_error`` (each wanted point's distance to the traced
    coupler curve, in the units of ``points``), ``pyslvs_fitness`` (Pyslvs' own objective: the sum over points of
    the distance to the coupler point at that point's own crank angle) and ``note``. ``seed`` seeds the C
    library's ``rand`` that Pyslvs draws from (None keeps Pyslvs' seeding by the time).
    """
    try:
        from pyslvs import collection_list, parse_vpoints, t_config
        from pyslvs.metaheuristics import algorithm as algorithm_class
        from pyslvs.metaheuristics import default
        from pyslvs.optimization import FPlanar
    except ImportError:
        return None

    points = np.asarray(points, dtype=float)
    kind = _algorithm_type(algorithm)
    lo, hi = points.min(axis=0), points.max(axis=0)
    centre, size = (lo + hi) / 2, float(np.max(hi - lo))
    reach = 1.5 * size  # pivot boxes: the target's box and a margin of one path size on every side

    base = collection_list(COLLECTION)
    ((pair, angles),) = base["input"]
    vpoints = parse_vpoints(base["expression"])
    stack = t_config(vpoints, [pair]).as_list()
    if stack != STACK:
        raise RuntimeError(f"unexpected Pyslvs expression stack {stack}")
    (target,) = base["target"]  # the coupler point
    config = {
        "expression": vpoints,
        "input": base["input"],
        "placement": {j: (float(centre[0]), float(centre[1]), reach) for j in base["placement"]},
        "target": {target: [tuple(p) for p in points]},
        "same": base["same"],
        "upper": 3.0 * size,
        "lower": 0.05 * size,
        "shape_only": False,
    }
    settings = default(kind)
    settings.update(max_gen=max_gen, report=max(1, max_gen))

    t0 = time.perf_counter()
    func = FPlanar(config)
    solver = algorithm_class(kind)(func, settings)
    if seed is not None:
        _seed_libc(seed)
    solver.run()
    seconds = time.perf_counter() - t0
    v, fitness = solver.result()

    ax, ay, dx, dy, crank, coupler, rocker, point_len, point_angle = v[:9]
    frame = math.hypot(dx - ax, dy - ay)
    curves, feasible = _trace((ax, ay), (dx, dy), crank, coupler, rocker, point_len, point_angle, branch=1)
    turns = bool(feasible.all())
    segments = _segments(curves, feasible, both=not turns)
    err = _distances(points, segments)
    # Pyslvs' own pose (at the first point's crank angle, printed to 4 decimals) must lie on the traced curve.
    pose = parse_vpoints(func.result(v))[target]
    on_curve = float(_distances(np.array([[pose.cx, pose.cy]]), segments)[0])

    params = ", ".join(f"{k}={settings[k]}" for k in settings if k != "report")
    note = (f"Pyslvs {kind.name} ({kind.value}) on FPlanar, collection {COLLECTION!r}, {params}, seed={seed}; "
            f"shape_only=False (fits position, size and rotation), per-point crank angles free in {angles} deg "
            f"(not ordered); pivots within +-{reach:.4g} of the target box centre, links in "
            f"[{0.05 * size:.4g}, {3 * size:.4g}]; {len(v)} variables; Pyslvs fitness {fitness:.6g} "
            f"(sum of point distances, mean {fitness / len(points):.4g}); errors from {SAMPLES} crank samples, "
            + ("crank turns fully, Pyslvs' assembly branch traced" if turns else
               "crank does NOT turn fully (not a crank-driven linkage), both branches traced")
            + f"; Pyslvs' first pose {on_curve:.2g} off the traced curve")
    return {
        "seconds": seconds,
        "lengths": {"crank": float(crank), "coupler": float(coupler), "rocker": float(rocker), "frame": frame},
        "max_error": float(err.max()),
        "rms_error": float(np.sqrt(np.mean(err ** 2))),
        "pyslvs_fitness": float(fitness),
        "note": note,
    }


def _read_points(path):
    """The ``x,y`` rows of a CSV file, skipping comment lines and the header."""
    rows = [line for line in Path(path).read_text().splitlines()
            if line.strip() and not line.startswith("#") and line.strip() != "x,y"]
    return np.array([[float(s) for s in row.split(",")] for row in rows])


if __name__ == "__main__":
    target = _read_points(ROOT / "examples" / "curves" / "figure-eight.csv")
    print(f"target: {len(target)} points of figure-eight.csv")
    for gens in (100, 300):
        res = pyslvs_path_synthesis(target, "DE", max_gen=gens, seed=0)
        if res is None:
            print("pyslvs is not installed")
            break
        print(f"DE max_gen={gens}: {res['seconds']:.2f} s, max_error {res['max_error']:.4f}, "
              f"rms_error {res['rms_error']:.4f}, lengths "
              + ", ".join(f"{k} {x:.3f}" for k, x in res["lengths"].items()))
        print(f"  note: {res['note']}")
