"""The synthesis panel's routes: four-bars for a sketched path, and for precision positions of a body.

``POST /api/synthesis/path`` is ``domes curves match``: the path's points looked up in a coupler-curve
atlas and the nearest four-bars refined by least squares (:func:`~domes.motion.coupler.match.match`). Each
linkage's error is the distance of every point from its coupler curve (either assembly mode, by the kinematics
kernel: :func:`from_curve`), relative to the path's size; the linkages are ranked by it. The atlas is the one
``domes synthesize --atlas auto`` takes: the small atlas of the data folder when it is built there (``domes
curves match`` builds it on first use: 8 s or more), else the quick one built in memory
(:func:`~domes.design.synthesis.solve.seed_atlas`: about 6 s, once per server). Matching runs in a worker
process, so the server keeps answering; ``POST /api/synthesis/prepare`` gets the atlas ready there before the
first query (the page asks when the panel is first shown).

``POST /api/synthesis/positions`` is ``domes synthesize`` on a guidance task: the crank dyads through
3, 4 or 5 precision positions and the four-bars they make, with the Burmester curves (circle-point and
centre-point curves of four positions) as point lists.

>>> path_body({"points": [[0, 0], [1, 0]]})
Traceback (most recent call last):
...
domes.errors.InputError: a wanted path needs at least 9 points to fit a four-bar's nine dimensions, got 2
>>> positions_of({"positions": [[0, 0, 0], [1, 0, 10], [2, "x", 20]]})
Traceback (most recent call last):
...
domes.errors.InputError: positions[2]: [2, 'x', 20] is not [x, y, angle_deg] (three numbers)
"""

from __future__ import annotations

import asyncio
import math
import multiprocessing
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path

from starlette.requests import Request
from starlette.responses import Response
from starlette.routing import Route

from domes.errors import DomesError, InputError
from domes.studio.app import Studio, answer, api, body_of, error
from domes.studio.security import Refused

#: Atlas choices besides a file of the data folder: ``auto`` (the small one when built, else the quick one).
ATLASES = ("auto", "quick", "small")
#: Linkages listed at most, and atlas candidates refined at most (``domes curves match --results/--candidates``).
MOST_RESULTS, MOST_CANDIDATES = 20, 100
#: Points of a path at most: each is measured against the matched curves by the kernel (the fit follows 64).
MOST_POINTS = 2000
#: Candidates refined by default: as many as ``domes synthesize`` refines to seed a path task (each takes up to a
#: second or two; a sketch no four-bar traces exactly refines them all).
CANDIDATES = 10
#: Samples of a matched linkage's coupler curve per input turn (drawn over the sketch).
CURVE_SAMPLES = 360
#: The Burmester curves are sampled over this many times the positions' spread round their centre, on lines.
REACH, LINES = 3.0, 161


def _number(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def _points(raw, where: str, width: int, what: str) -> list[tuple[float, ...]]:
    if not isinstance(raw, list):
        raise InputError(f"{where}: give a list of {what}, got {type(raw).__name__}")
    out = []
    for k, p in enumerate(raw):
        if not (isinstance(p, list) and len(p) == width and all(_number(v) for v in p)):
            raise InputError(f"{where}[{k}]: {p!r} is not {what} ({['', '', 'two', 'three'][width]} numbers)")
        out.append(tuple(float(v) for v in p))
    return out


def _count(body: dict, key: str, default: int, most: int) -> int:
    value = body.get(key, default)
    if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= most:
        raise InputError(f"{key}: a whole number from 1 to {most}, got {value!r}")
    return value


def path_body(body: dict) -> dict:
    """The path query's arguments, checked: points, closed, results, candidates, tol (relative) and atlas."""
    from domes.motion.coupler.fit import check_wanted

    points = _points(body.get("points"), "points", 2, "[x, y]")
    check_wanted(points)
    if len(points) > MOST_POINTS:
        raise InputError(f"points: {len(points):,} points; the panel takes at most {MOST_POINTS:,} (resample the path)")
    closed = body.get("closed", True)
    if not isinstance(closed, bool):
        raise InputError(f"closed: true (a closed curve) or false (an open stretch), got {closed!r}")
    tol = body.get("tol")
    if tol is not None and not (_number(tol) and 0 < tol < 1):
        raise InputError(f"tol: the largest distance accepted relative to the path's size, above 0 and below 1, "
                         f"got {tol!r}")
    atlas = body.get("atlas", "auto")
    if not isinstance(atlas, str) or not atlas:
        raise InputError(f"atlas: one of {', '.join(ATLASES)}, or an atlas file in the data folder; got {atlas!r}")
    drawn = body.get("drawn", False)
    if not isinstance(drawn, bool):
        raise InputError(f"drawn: true (a path drawn by hand: noisy, matched within its own scatter) or false, got "
                         f"{drawn!r}")
    return {"points": points, "closed": closed, "drawn": drawn, "results": _count(body, "results", 5, MOST_RESULTS),
            "candidates": _count(body, "candidates", CANDIDATES, MOST_CANDIDATES), "tol": tol, "atlas": atlas}


def atlas_source(studio: Studio, choice: str, closed: bool) -> tuple:
    """Which atlas a query uses: ``("file", path)``, ``("quick", kind)`` or ``("small", path, kind)`` (to be built
    there). ``auto`` takes the data folder's small atlas when it is built (what ``curves match`` uses), else the
    quick one, as ``domes synthesize --atlas auto`` does.

    >>> import tempfile
    >>> atlas_source(Studio(tempfile.mkdtemp()), "auto", True)
    ('quick', 'closed')
    """
    from domes.io.atlas import atlas_path

    kind = "closed" if closed else "open"
    default = atlas_path("small", kind)
    small = Path(studio.home) / default.parent.name / default.name
    if choice == "auto":
        return ("file", str(small)) if small.is_file() else ("quick", kind)
    if choice == "quick":
        return ("quick", kind)
    if choice == "small":
        return ("small", str(small), kind)
    path = studio.path(choice)
    if not path.is_file():
        raise InputError(f"atlas: {choice} is not a file of the data folder (nor one of {', '.join(ATLASES)})")
    return ("file", str(path))


# -- the worker process: the atlas kept between queries -----------------------------------------------------

_pool: list[ProcessPoolExecutor] = []
_atlases: dict = {}


def _worker() -> ProcessPoolExecutor:
    if not _pool:
        _pool.append(ProcessPoolExecutor(1, mp_context=multiprocessing.get_context("spawn"), initializer=_watch))
    return _pool[0]


def _watch() -> None:
    """In the worker: end it when the server's process ends, however that ends (a killed server leaves no worker)."""
    import os
    import threading
    from multiprocessing.connection import wait

    parent = multiprocessing.parent_process()
    if parent is not None:
        threading.Thread(target=lambda: (wait([parent.sentinel]), os._exit(0)), daemon=True).start()


def load(source: tuple):
    """The atlas of ``source`` (:func:`atlas_source`) with its k-d tree, and what it is; kept for the next query."""
    import os

    from domes.motion.coupler.atlas import Atlas, OpenAtlas

    key = source + ((os.stat(source[1]).st_mtime_ns,) if source[0] == "file" else ())
    if key not in _atlases:
        if source[0] == "quick":
            _atlases[key] = _quick(source[1])
        else:
            from domes.io.atlas import load_atlas, save_atlas
            from domes.motion.coupler.atlas import SIZES, build, build_windows

            if source[0] == "small" and not Path(source[1]).is_file():
                Path(source[1]).parent.mkdir(parents=True, exist_ok=True)
                save_atlas((build if source[2] == "closed" else build_windows)(SIZES["small"]), source[1])
            table = load_atlas(source[1])
            kind = table.meta.get("kind", "closed")
            _atlases[key] = (OpenAtlas(table) if kind == "open" else Atlas(table),
                             f"{table.meta.get('name')} atlas of {Path(source[1]).name} in the data folder")
    return _atlases[key]


def _quick(kind: str):
    from domes.design.synthesis.solve import SEED_ATLAS, seed_atlas
    from domes.motion.coupler.atlas import OpenAtlas, build_windows

    spec = f"{SEED_ATLAS.linkages} four-bars, coupler points every {SEED_ATLAS.step:g}"
    if kind == "closed":
        return seed_atlas(), f"quick atlas built in memory ({spec}), as domes synthesize uses"
    return OpenAtlas(build_windows(SEED_ATLAS)), f"quick open-path index built in memory ({spec})"


def prepare_atlas(source: tuple) -> str:
    """Load or build the atlas of ``source`` in the worker (before the first query)."""
    from domes.execution.threads import limited_threads

    with limited_threads():
        return load(source)[1]


def match_path(points, closed: bool, drawn: bool, results: int, candidates: int, tol, source: tuple) -> dict:
    """``domes curves match`` on ``points`` (``--drawn`` when ``drawn``): the fitting four-bars, best first, as the
    panel shows them."""
    import time

    from domes.execution.threads import limited_threads
    from domes.motion.coupler.atlas import OpenAtlas
    from domes.motion.coupler.freehand import match_drawn
    from domes.motion.coupler.match import match

    started = time.perf_counter()
    with limited_threads():
        atlas, what = load(source)
        if isinstance(atlas, OpenAtlas) == closed:
            raise InputError(f"atlas: {what} is of {'open' if closed else 'closed'} paths, but the path is "
                             f"{'closed' if closed else 'open'}")
        ready = time.perf_counter()
        found = match_drawn(points, atlas, results, candidates, tol, closed) if drawn else \
            match(points, atlas, results, candidates, tol)
        fits = sorted((_fit(f, k, found, points) for k, f in enumerate(found.fits)),
                      key=lambda f: (f["error"] is None, f["error"]["max"] if f["error"] else math.inf))
    for k, f in enumerate(fits, 1):                 # ranked by their distance from the points, as measured
        f["name"] = f"four-bar {k} for the path"
        if f["mechanism"] is not None:
            f["mechanism"]["name"] = f["name"]
    return {"message": found.message, "size": found.size, "tol": found.tol, "tried": found.tried,
            "closed": closed, "points": [list(p) for p in points], "atlas": what,
            "atlas_seconds": ready - started, "lookup_ms": found.lookup_seconds * 1e3,
            "refine_seconds": found.refine_seconds, "fits": fits,
            "sketch": {"noise": found.sketch.noise / found.size, "corners": list(found.sketch.corners),
                       "read": found.sketch.said} if drawn else None}


def _fit(f, k: int, found, points) -> dict:
    from domes.design.synthesis.fourbars import grashof_class
    from domes.motion.coupler.curves import trace

    a, b, c, d = f.lengths
    kind, turns = grashof_class(a, b, c, d)
    out = {"name": None, "success": f.success, "lengths": {"crank": a, "coupler": b, "rocker": c, "frame": d},
           "coupler_point": list(f.coupler), "grashof": kind, "input_turns": turns, "error": None, "distance": None,
           "fitted": {"max": f.after[0] / found.size, "rms": f.after[1] / found.size},
           "before": {"max": f.before[0] / found.size, "rms": f.before[1] / found.size}, "note": f.note,
           "mechanism": None, "curves": [], "nearest": None,
           "merged": [{"relation": why, "mechanism": g.mechanism.to_dict() if g.mechanism else None,
                       "fitted": {"max": g.after[0] / found.size, "rms": g.after[1] / found.size}}
                      for g, why in (found.merged[k] if k < len(found.merged) else ())]}
    if f.mechanism is not None:
        out["mechanism"] = f.mechanism.to_dict()
        circuits = trace(f.mechanism, "P", CURVE_SAMPLES).circuits
        out["curves"] = [c.points.tolist() for c in circuits]
        out["nearest"] = min(range(len(circuits)), key=lambda i: _farthest(circuits[i].points, points))
        near = from_curve(f.mechanism, points)
        out["distance"] = {"max": max(near), "rms": math.sqrt(sum(x * x for x in near) / len(near))}
        out["error"] = {key: value / found.size for key, value in out["distance"].items()}
    return out


def from_curve(mech, points) -> list[float]:
    """The distance of each point from the four-bar's coupler curve of ``P`` (every circuit): the kernel's
    (:func:`~domes.design.synthesis.verify.curve_distances`) on either assembly mode, the nearer."""
    from domes.design.synthesis.fourbars import FourBar
    from domes.design.synthesis.verify import curve_distances

    at = {j.name: j.at for j in mech.joints}
    drawn = FourBar(at["A"], at["B"], at["C"], at["D"], mech.point("P")[1])
    return [min(x, y) for x, y in zip(curve_distances(drawn, points), curve_distances(_other_mode(drawn), points))]


def _other_mode(fb):
    """The four-bar at the same crank angle in its other assembly mode: ``C`` mirrored in the line ``BD``, the
    coupler point turned with the coupler about ``B``."""
    from domes.design.synthesis.fourbars import FourBar

    B, C, D, P = (complex(*p) for p in (fb.a1, fb.b1, fb.b0, fb.point))
    u = (D - B) / abs(D - B)
    mirrored = B + u * u * (C - B).conjugate()
    P2 = B + (P - B) * (mirrored - B) / (C - B)
    return FourBar(fb.a0, fb.a1, (mirrored.real, mirrored.imag), fb.b0, (P2.real, P2.imag))


def _farthest(curve, points) -> float:
    """The largest distance from ``points`` to the nearest sample of ``curve``: which circuit the fit is on."""
    import numpy as np

    p = np.asarray(points, dtype=float)
    return float(np.max(np.min(np.hypot(*(curve[:, None, :] - p[None, :, :]).transpose(2, 0, 1)), axis=0)))


async def _in_worker(fn, *args):
    try:
        return await asyncio.wrap_future(_worker().submit(fn, *args))
    except BrokenProcessPool:
        _pool.clear()
        raise DomesError("the matching worker stopped (out of memory?); ask again to start another") from None


async def path(request: Request) -> Response:
    """``POST /api/synthesis/path``: the four-bars whose coupler curve passes through the points, best first."""
    studio = request.app.state.studio
    try:
        args = path_body(await body_of(request))
        source = atlas_source(studio, args.pop("atlas"), args["closed"])
        value = await _in_worker(match_path, *args.values(), source)
    except Refused as exc:
        return error(str(exc), exc.status)
    except DomesError as exc:
        return error(str(exc))
    return answer(value)


async def prepare(request: Request) -> Response:
    """``POST /api/synthesis/prepare {closed?, atlas?}``: start getting the atlas ready in the worker."""
    studio = request.app.state.studio
    try:
        body = await body_of(request)
        closed = body.get("closed", True)
        if not isinstance(closed, bool):
            raise InputError(f"closed: true or false, got {closed!r}")
        source = atlas_source(studio, str(body.get("atlas", "auto")), closed)
    except Refused as exc:
        return error(str(exc), exc.status)
    except DomesError as exc:
        return error(str(exc))
    _worker().submit(prepare_atlas, source)
    return answer({"preparing": source[0], "closed": closed})


# -- precision positions ---------------------------------------------------------------------------------------

def positions_of(body: dict) -> list:
    """The precision positions of the body: 3 to 5 ``[x, y, angle_deg]``."""
    from domes.design.synthesis.guidance import Position

    raw = _points(body.get("positions"), "positions", 3, "[x, y, angle_deg]")
    if not 3 <= len(raw) <= 5:
        raise InputError(f"positions: rigid-body guidance by a four-bar takes 3, 4 or 5 precision positions, got "
                         f"{len(raw)}")
    return [Position((x, y), math.radians(a)) for x, y, a in raw]


def guidance(studio: Studio, body: dict) -> dict:
    """``POST /api/synthesis/positions``: Burmester curves, crank dyads and four-bars through the positions.

    Free choices as in a task file: ``circle_points`` (three positions: the two moving pivots in position 1),
    ``circle_x`` (four: the abscissas of the two circle points); without them only the curves are given.
    """
    import numpy as np

    from domes.design.synthesis import synthesize, task_from_dict
    from domes.execution.threads import limited_threads

    positions = positions_of(body)
    n = len(positions)
    task = {"kind": "guidance", "name": "precision positions",
            "positions": [{"point": list(p.point), "angle_deg": math.degrees(p.angle)} for p in positions]}
    for key in ("circle_points", "circle_x", "slider"):
        if key in body:
            task[key] = body[key]
    choose = {3: ("circle_points", "three positions leave each crank one free pivot: pick two circle points "
                  "(moving pivots in position 1)"),
              4: ("circle_x", "four positions leave each crank one free coordinate: pick two points on the "
                  "circle-point curve (their abscissas, circle_x)")}.get(n)
    with limited_threads():
        curves = _burmester_curves(positions)
        result = None
        if choose is None or choose[0] in body:
            result = synthesize(task_from_dict(task, "positions"))
    out = {"count": n, "curves": curves, "needs": choose[1] if choose and result is None else None,
           "message": result.message if result else None, "notes": list(result.notes) if result else [],
           "dyads": [], "solutions": []}
    if result is None:
        return out
    seen = []
    for k, s in enumerate(result.solutions, 1):
        fb = s.fourbar
        name = f"guidance four-bar {k}"
        for a0, a1 in ((fb.a0, fb.a1), (getattr(fb, "b0", None), fb.b1)):
            if a0 is not None and not any(np.allclose((a0, a1), d, atol=1e-9 * (1 + np.abs(d).max())) for d in seen):
                seen.append(np.array((a0, a1)))
                out["dyads"].append({"centre": list(a0), "circle": list(a1), "radius": math.dist(a0, a1)})
        out["solutions"].append({
            "name": name, "mechanism": fb.mechanism(name).to_dict(), "usable": s.usable, "defects": list(s.defects),
            "warnings": list(s.warnings), "lengths": fb.named_lengths(), "grashof": s.checks.grashof,
            "driver": s.checks.driver, "min_transmission_deg": s.checks.min_transmission_deg,
            "crank_angles_deg": list(s.checks.crank_angles_deg), "error": s.residual / max(result.size, 1e-300),
            "poses": [list(map(list, p)) for p in s.poses]})
    return out


def _burmester_curves(positions) -> list[dict]:
    """The circle-point and centre-point curves of every four of the positions that the library cuts (1234 for
    four; 1234 and 1235 for five, whose common circle points are the Burmester points), sampled on vertical
    lines and, for the steep parts, on lines of the frame turned by 90°."""
    from domes.design.synthesis.guidance import Position, circle_point_curve, size

    if len(positions) < 4:
        return []
    s = size(positions)
    centre = [sum(p.point[i] for p in positions) / len(positions) for i in (0, 1)]
    out = []
    for four in ([0, 1, 2, 3], [0, 1, 2, 4])[:len(positions) - 3]:
        chosen = [positions[i] for i in four]
        circle, centres = [], []
        for turn in (False, True):
            frame = [Position((-p.point[1], p.point[0]), p.angle + math.pi / 2) for p in chosen] if turn else chosen
            mid = -centre[1] if turn else centre[0]
            xs = [mid + REACH * s * (2 * k / (LINES - 1) - 1) for k in range(LINES)]
            for d in circle_point_curve(frame, xs):
                a1, a0 = ((d.a1[1], -d.a1[0]), (d.a0[1], -d.a0[0])) if turn else (d.a1, d.a0)
                if math.dist(a1, centre) <= REACH * s * 1.5:
                    circle.append(list(a1))
                if math.dist(a0, centre) <= REACH * s * 1.5:
                    centres.append(list(a0))
        out.append({"positions": [i + 1 for i in four], "circle": circle, "centre": centres})
    return out


routes: list = [Route("/api/synthesis/path", path, methods=["POST"]),
                Route("/api/synthesis/prepare", prepare, methods=["POST"]),
                api("/api/synthesis/positions", guidance)]
