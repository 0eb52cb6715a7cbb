"""The mechanism editor's routes: a linkage re-solved over its input's sweep, saved, and started from an example.

``POST /api/mechanism/solve`` answers what ``domes kinematics`` and ``domes draw`` compute for a mechanism file:
every joint and coupler point at each step of the input's sweep (on the kernel's arrays), the coupler curves,
the dead and branch points, whether the input turns fully, and the assembly modes of its dyads;
``POST /api/mechanism/save`` writes a mechanism file the command line loads; ``GET /api/mechanism/examples``
lists the shipped mechanisms and the library's model linkages to start from. A spatial file is answered with
the turning view of ``domes draw`` (:mod:`domes.sketch.spatial`).

>>> from domes.motion.planar.examples import four_bar
>>> motion = solve_motion(four_bar(), samples=36)
>>> motion["full_turn"], len(motion["positions"]["C"]), motion["modes"]["current"]
(True, 36, '+')
"""

from __future__ import annotations

import base64
import json
import math

import numpy as np
from starlette.responses import Response

from domes.errors import DomesError, InputError
from domes.io.files import write_atomic
from domes.io.resources import shipped_data
from domes.model.mechanism import Mechanism
from domes.model.spatial import SpatialMechanism
from domes.motion.planar.kernel import SIGNED, Program, blocked
from domes.motion.planar.query import Kinematics, accuracy
from domes.motion.planar.sweep import run_sweep
from domes.results import Status
from domes.sketch.dimensioned import _with_guide_points
from domes.studio.app import api

#: Steps of the sweep answered by default, and the most a request may ask for.
SAMPLES, MAX_SAMPLES = 360, 7200
#: The accuracy of the sweeps (``domes kinematics``'s default): 1° resolution, dead points located to 1e-10 rad.
ACCURACY = "default"
#: Where the input stops at two limits, the sweeps to them take steps this many times finer than ``samples``.
FINER = 4
#: Sign combinations listed as assembly modes at most (2 ** 6); more dyads are listed one flip at a time.
MAX_MODES = 64


def read_mechanism(data, where: str = "mechanism", compile: bool = True) -> Mechanism | SpatialMechanism:
    """The mechanism of a file's JSON value, checked as ``domes kinematics`` loads it (planar or spatial; with
    ``compile``, its kinematics compiled too, which refuses a drawn pose on a dead point)."""
    if not isinstance(data, dict):
        raise InputError(f"{where}: a mechanism file's JSON object is needed, got {type(data).__name__}")
    if data.get("space") == "spatial":
        from domes.motion.spatial.loops import Loops

        mech = SpatialMechanism.from_dict(data, where)
        if compile:
            Loops(mech)
        return mech
    mech = Mechanism.from_dict(data, where)
    if compile:
        Kinematics(mech)
    return mech


def _samples(body: dict) -> int:
    value = body.get("samples", SAMPLES)
    if isinstance(value, bool) or not isinstance(value, (int, float)) or value != int(value) or \
            not 8 <= value <= MAX_SAMPLES:
        raise InputError(f"samples: a whole number from 8 to {MAX_SAMPLES} is needed, got {value!r}")
    return int(value)


# -- assembly modes -----------------------------------------------------------------------------


def _signed(kin: Kinematics) -> list:
    """The dyads of ``kin`` that have two assembly modes (RRR, RPR, RRP), in the order they are solved."""
    return [g for g in kin.groups if g.index in kin.plans and kin.plans[g.index].kind in SIGNED]


def _modal(kin: Kinematics) -> bool:
    """Whether the other assembly modes can be drawn: only drivers and dyads (no gears, cams or larger groups)."""
    return not blocked(kin) and not kin.mech.gears and not kin.mech.cams and \
        all(g.kind == "driver" or g.index in kin.plans for g in kin.groups)


def _key(signs) -> str:
    return "".join("+" if s > 0 else "-" if s < 0 else "0" for s in signs)


def assembly_modes(kin: Kinematics, q0: float) -> dict:
    """The drawn mode of each two-mode dyad (``current``: a ``+``/``-`` per dyad) and the modes that assemble at
    the drawn input (the kernel's poses with the dyads' signs changed)."""
    dyads = _signed(kin)
    prog = Program(kin) if _modal(kin) and dyads else None
    geom = prog.geometry() if prog else None
    drawn = [geom.sign.get(g.index, 0.0) for g in dyads] if geom else []
    out = {"dyads": [{"group": g.label, "kind": kin.plans[g.index].kind, "joints": list(g.joints)} for g in dyads],
           "current": _key(drawn) if geom else "", "available": []}
    if not geom or 0.0 in drawn:
        return out
    n = len(dyads)
    bits = np.arange(2 ** n) if 2 ** n <= MAX_MODES else np.array([0] + [1 << k for k in range(n)])
    signs = np.array([np.where(bits >> k & 1, -s, s) for k, s in enumerate(drawn)])     # (dyads, modes)
    pose = prog.poses(geom, np.full(bits.size, q0), signs={g.index: signs[k] for k, g in enumerate(dyads)})
    failed = np.broadcast_to(pose.failed, bits.shape)
    out["available"] = [_key(signs[:, m]) for m in range(bits.size) if not failed[m]]
    return out


def redrawn(mech: Mechanism, mode: str) -> Mechanism:
    """``mech`` drawn in the assembly mode ``mode`` (a ``+`` or ``-`` per two-mode dyad, as :func:`assembly_modes`):
    every link placed where the kernel puts it at the drawn input with those signs.

    >>> from domes.motion.planar.examples import four_bar
    >>> other = redrawn(four_bar(), "-")
    >>> [round(v, 12) for v in other.joint("C").at]
    [3.5, -2.449489742783]
    """
    kin = Kinematics(mech)
    dyads = _signed(kin)
    if not _modal(kin):
        raise InputError(f"{mech.name}: assembly modes are changed here for linkages of dyads only (no gear or cam "
                         "pairs, no class-III or larger groups)")
    if len(mode) != len(dyads) or set(mode) - {"+", "-"}:
        raise InputError(f"mode: one '+' or '-' per two-mode dyad ({len(dyads)}: "
                         f"{', '.join(g.label for g in dyads) or 'none'}), got {mode!r}")
    prog = Program(kin)
    geom = prog.geometry()
    q0 = kin.drawn_inputs()[mech.inputs[0].joint]
    pose = prog.poses(geom, q0, signs={g.index: 1.0 if c == "+" else -1.0 for g, c in zip(dyads, mode)})
    if bool(np.any(pose.failed)):
        raise InputError(f"{mech.name}: the linkage does not assemble in the mode {mode} at its drawn input")

    def place(link, name=None, xy=None):
        R, W, P = pose.links[link]
        z = W + R * ((geom.at[name] if name else complex(*xy)) - P)
        return [float(np.real(z)), float(np.imag(z))]

    def turn(link) -> float:
        return float(np.angle(pose.links[link][0]))

    data = mech.to_dict()
    for item in data["joints"]:
        j = mech.joint(item["name"]) if item["type"] in ("R", "P") else None
        if j is None:
            continue
        if j.kind == "P":
            guide, slider = j.links
            item["at"] = place(slider, j.name)
            item["direction"] = math.degrees(j.direction + turn(guide))
            if "origin" in item:
                item["origin"] = place(guide, f"origin:{j.name}")
        else:
            item["at"] = place(j.links[0], j.name)
    for item in data.get("points", []):
        item["at"] = place(item["link"], item["name"])
    for item in data.get("polygons", []):
        item["vertices"] = [place(item["link"], xy=v) for v in item["vertices"]]
    for item in data["links"]:
        if isinstance(item, dict) and "angle" in item:
            item["angle"] += math.degrees(turn(item["name"]))
    return Mechanism.from_dict(data, mech.source or mech.name)


# -- the motion ---------------------------------------------------------------------------------


def _dead(d, shown) -> dict:
    """A dead point as ``domes kinematics --format json`` writes it (``shown``: radians to degrees for an R input)."""
    return {"input": shown(d.input), "within": shown(d.within), "kind": str(d.kind), "group": d.group,
            "joints": list(d.joints), "message": d.message}


def solve_motion(mech: Mechanism, samples: int = SAMPLES, trace=None, packed: bool = False) -> dict:
    """Every joint, coupler point and slide guide of ``mech`` over its first input's sweep, by the kernel.

    An R input turns a full turn forward from the drawn pose in ``samples`` steps; where it stops at a dead
    point it is swept backward too, and then once more between the two limits, in ``samples`` steps (a P input
    moves ``size`` each way). ``trace`` names the points whose curves are drawn (default: the coupler points).
    Angles (inputs, dead points) are answered in degrees. Each point's path is a list of ``[x, y]``, or with
    ``packed`` (:func:`pack`) the base64 text of its ``x, y, x, y, ...`` as little-endian float64.
    """
    names = [j.name for j in mech.joints] + [p.name for p in mech.points]
    trace = [p.name for p in mech.points] if trace is None else list(trace)
    unknown = [n for n in trace if n not in names]
    if unknown:
        raise InputError(f"trace: {unknown} are not joints or coupler points of {mech.name} ({', '.join(names)})")
    traced, guides = _with_guide_points(mech)
    every = names + [n for pair in guides.values() for n in pair]
    kin = Kinematics(traced, [f"point:{n}" for n in every], 0, "assur", accuracy(ACCURACY))
    joint = mech.inputs[0].joint
    angular = mech.joint(joint).kind == "R"
    shown = math.degrees if angular else float
    q0 = kin.drawn_inputs()[joint]
    reach = 2 * math.pi if angular else mech.size
    # Steps four times finer than asked (the walk's own resolution sets the cost, not the steps kept): a full turn
    # keeps every fourth; where the input stops, the runs both ways from the drawn pose joined give the motion
    # between the limits, of which ``samples`` solved steps are kept, evenly spread (a third sweep between the
    # limits only when the range is too short for that).
    fine = reach / (FINER * samples)
    ahead = run_sweep(kin, q0, q0 + reach, fine, joint)
    runs, full = [ahead], angular and ahead.status is Status.COMPLETE
    if full:
        pick = np.arange(0, min(ahead.inputs.size, FINER * samples), FINER)
        inputs, column = ahead.inputs[pick], lambda c: ahead.table[c][pick]
    else:
        back = run_sweep(kin, q0, q0 - reach, fine, joint)
        runs = [back, ahead]
        joined = np.concatenate([back.inputs[::-1], ahead.inputs[1:]])
        if joined.size >= samples:
            pick = np.round(np.linspace(0, joined.size - 1, samples)).astype(int)
            inputs = joined[pick]
            column = lambda c: np.concatenate([back.table[c][::-1], ahead.table[c][1:]])[pick]  # noqa: E731
        else:
            ends = [next((d for d in sw.dead_points if d.stops), None) for sw in (back, ahead)]
            lo = ends[0].input + ends[0].within if ends[0] else back.reachable[0]
            hi = ends[1].input - ends[1].within if ends[1] else ahead.reachable[1]
            between = run_sweep(kin, lo, hi, (hi - lo) / (samples - 1), joint) if hi > lo else back
            runs.append(between)
            count = min(between.inputs.size, samples)
            inputs, column = between.inputs[:count], lambda c: between.table[c][:count]
    count = inputs.size
    paths = {n: np.column_stack([column(f"point:{n}.x"), column(f"point:{n}.y")]) for n in every}
    if not full and len(runs) == 2 and count:
        # the joined runs end at their last steps, a fraction of a step short of the limits: the ends put there
        inputs = inputs.copy()
        for row, run in ((0, runs[0]), (count - 1, runs[1])):
            stop = next((d for d in run.dead_points if d.stops), None)
            pose = _dead_pose(kin, run, stop, every) if stop is not None else None
            if pose is not None:
                inputs[row] = stop.input - math.copysign(stop.within, stop.input - q0)
                for n, xy in pose.items():
                    paths[n][row] = xy
    positions = {n: pack(xy) if packed else xy.tolist() for n, xy in paths.items()}
    dead, seen = [], []
    for d in [d for run in runs[:2] for d in (*run.dead_points, *run.passed)]:
        if any(d.kind == k and abs(d.input - q) <= max(d.within, w, 1e-9) for k, q, w in seen):
            continue
        seen.append((d.kind, d.input, d.within))
        item = _dead(d, shown)
        near = min(runs, key=lambda run: np.min(np.abs(run.inputs - d.input)) if run.inputs.size else math.inf)
        item["at"] = _dead_pose(kin, near, d, trace + [j for j in d.joints if j in names])
        dead.append(item)
    dead.sort(key=lambda item: item["input"])
    reachable = (q0, q0 + reach) if full else (float(inputs[0]), float(inputs[-1])) if count else (q0, q0)
    return {"name": mech.name, "input": {"joint": joint, "kind": "R" if angular else "P",
                                         "unit": "deg" if angular else "length", "drawn": shown(q0)},
            "inputs": _inputs(inputs, angular, packed),
            "positions": positions, "drawn": _drawn(traced, every), "guides": {j: list(pair) for j, pair in guides.items()},
            "curves": [{"point": n, "closed": full, "points": positions[n]} for n in trace],
            "full_turn": full, "reachable": [shown(reachable[0]), shown(reachable[1])],
            "status": str(ahead.status), "dead_points": dead,
            "modes": assembly_modes(kin, q0), "size": mech.size,
            "max_residual": max(run.max_residual for run in runs)}


def _inputs(qs: np.ndarray, angular: bool, packed: bool):
    values = np.degrees(qs) if angular else np.asarray(qs, dtype=float)
    return base64.b64encode(values.astype("<f8").tobytes()).decode("ascii") if packed else values.tolist()


def _drawn(traced: Mechanism, names) -> dict:
    """Each named joint or point where the file draws it (the guides' points as :func:`solve_motion` adds them)."""
    at = {j.name: j.at for j in traced.joints} | {p.name: p.at for p in traced.points}
    return {n: [float(at[n][0]), float(at[n][1])] for n in names}


def _dead_pose(kin: Kinematics, sw, d, names) -> dict | None:
    """The named points at a dead point (just on the reachable side of a limit), from the nearest step solved."""
    if not sw.inputs.size:
        return None
    k = int(np.argmin(np.abs(sw.inputs - d.input)))
    q = float(sw.inputs[k])
    x = d.input if not d.stops else d.input - math.copysign(d.within, d.input - q)
    try:
        step = kin.at({**sw.fixed, sw.joint: x}, {v: float(a[k]) for v, a in sw.states.items()})
    except DomesError:
        return None
    return {n: [step.values[f"point:{n}.x"], step.values[f"point:{n}.y"]] for n in dict.fromkeys(names)}


def pack(xy: np.ndarray) -> str:
    """Points ``(N, 2)`` as base64 text of their little-endian float64 ``x, y, x, y, ...`` (NaN where not solved).

    >>> pack(np.array([[1.0, 2.0]]))
    'AAAAAAAA8D8AAAAAAAAAQA=='
    """
    return base64.b64encode(np.ascontiguousarray(xy, dtype="<f8").tobytes()).decode("ascii")


def _packed(body: dict) -> bool:
    encoding = body.get("encoding", "json")
    if encoding not in ("json", "f64"):
        raise InputError(f"encoding: 'json' (lists of [x, y]) or 'f64' (base64 of float64), got {encoding!r}")
    return encoding == "f64"


def _json(value) -> Response:
    """A JSON answer written at once (the arrays come from ``tolist``; a number that is not finite is refused)."""
    try:
        text = json.dumps(value, separators=(",", ":"), allow_nan=False)
    except ValueError:
        from domes.studio.app import finite

        text = json.dumps(finite(value), separators=(",", ":"))
    return Response(text, media_type="application/json")


# -- routes -------------------------------------------------------------------------------------


def solve(studio, body: dict):
    """``{mechanism, samples?, mode?, trace?, encoding?}``: the motion of a planar mechanism (:func:`solve_motion`;
    ``encoding`` ``"f64"`` packs the paths), drawn first in the assembly ``mode`` when it is not the drawn one (the
    answer's ``mechanism`` is then the file redrawn, :func:`redrawn`). A spatial mechanism is answered with its
    turning view (:func:`spatial_view`: ``azimuth``, ``elevation``, ``step``, ``page``)."""
    data = body.get("mechanism")
    mech = read_mechanism(data, compile=False)
    if isinstance(mech, SpatialMechanism):
        cache = studio.state.setdefault("mechanism", {}).setdefault("spatial", {}) if studio is not None else None
        return spatial_view(mech, body, cache)
    samples, packed = _samples(body), _packed(body)
    trace = body.get("trace")
    if trace is not None and (not isinstance(trace, list) or not all(isinstance(t, str) for t in trace)):
        raise InputError(f"trace: a list of joint or coupler point names is needed, got {trace!r}")
    mode = body.get("mode", body.get("branch"))
    if mode is not None and not isinstance(mode, str):
        raise InputError(f"mode: a '+' or '-' per two-mode dyad is needed, got {mode!r}")
    answer: dict = {}
    if mode:
        kin = Kinematics(mech)
        if mode != assembly_modes(kin, kin.drawn_inputs()[mech.inputs[0].joint])["current"]:
            mech = redrawn(mech, mode)
            answer["mechanism"] = {**data, **mech.to_dict()}
    return _json({**solve_motion(mech, samples, trace, packed), **answer, "space": "planar"})


def spatial_view(mech: SpatialMechanism, body: dict, cache: dict | None = None) -> dict:
    """The turning view of ``domes draw`` for a spatial mechanism: the SVG at ``step`` of the sweep seen from
    ``azimuth``/``elevation`` (degrees), and with ``page`` the whole page
    (:func:`~domes.sketch.spatial.spatial_html`). ``cache`` keeps the sweeps of the last few mechanisms (by
    their JSON), so that turning the view does not sweep again."""
    from domes.sketch.spatial import VIEW, spatial_html, spatial_svg

    if not mech.inputs:
        raise InputError(f"{mech.name}: the mechanism has no input")
    view = []
    for key, default, lo, hi in (("azimuth", VIEW[0], -360.0, 360.0), ("elevation", VIEW[1], -89.0, 89.0)):
        value = body.get(key, default)
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not lo <= value <= hi:
            raise InputError(f"{key}: a number of degrees from {lo:g} to {hi:g} is needed, got {value!r}")
        view.append(float(value))
    key = json.dumps(mech.to_dict(), sort_keys=True)
    if cache is None or key not in cache:
        found = _spatial_sweep(mech)
        if cache is not None:
            cache[key] = found
            while len(cache) > SPATIAL_CACHE:
                cache.pop(next(iter(cache)))
    sw, frames, inputs, angular = cache[key] if cache is not None else found
    k = body.get("step", 0)
    if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < len(frames):
        raise InputError(f"step: a whole number from 0 to {len(frames) - 1} is needed, got {k!r}")
    traces = {p.name: [f[p.name] for f in frames] for p in mech.points if all(p.name in f for f in frames)} or None
    out = {"space": "spatial", "name": mech.name, "svg": spatial_svg(mech, frames[k], traces, 520.0, tuple(view)),
           "steps": len(frames), "step": k, "input": inputs[k], "unit": "deg" if angular else "length",
           "azimuth": view[0], "elevation": view[1], "message": sw.message}
    if body.get("page"):
        out["html"] = spatial_html(mech, frames, inputs, mech.inputs[0].joint, "°" if angular else "",
                                   list(traces or ()), summary=sw.message)
    return out


#: Spatial mechanisms whose sweeps are kept (a view turned is drawn again without sweeping).
SPATIAL_CACHE = 4


def _spatial_sweep(mech: SpatialMechanism) -> tuple:
    """The sweep ``domes draw --format html`` shows: a turn in 5° steps (a slide over a tenth of the size)."""
    from domes.motion.spatial.loops import Loops
    from domes.motion.spatial.sweep import spatial_sweep

    angular = mech.inputs[0].variable == "angle"
    start, stop, step = (0.0, 2 * math.pi, math.radians(5)) if angular else (0.0, 0.1 * mech.size, 0.005 * mech.size)
    sw = spatial_sweep(mech, start, stop, step)
    kin = Loops(mech)
    frames = [kin.places(s) for s in sw.states]
    inputs = [math.degrees(q) for q in sw.inputs] if angular else [float(q) for q in sw.inputs]
    return sw, frames, inputs, angular


def save(studio, body: dict) -> dict:
    """``{name, mechanism}``: the mechanism checked as ``domes kinematics`` loads it, written to ``name`` (a
    ``.json`` file in the data folder) atomically."""
    name = body.get("name")
    if not isinstance(name, str) or not name.strip():
        raise InputError("name: say which file to write, e.g. {\"name\": \"mechanisms/linkage.json\"}")
    if not name.lower().endswith(".json"):
        raise InputError(f"name: {name!r}: a mechanism file is a .json file")
    data = body.get("mechanism")
    read_mechanism(data, name)
    path = studio.path(name)
    if path.is_dir():
        raise InputError(f"name: {name!r} is a folder")
    path.parent.mkdir(parents=True, exist_ok=True)
    write_atomic(path, json.dumps(data, indent=1) + "\n")
    return {"name": name, "path": str(path), "bytes": path.stat().st_size}


def examples(studio, body: dict) -> dict:
    """The mechanisms to start from: the shipped ones (``knowledge/mechanisms``) and the library's model linkages."""
    from domes.motion.planar import examples as planar
    from domes.motion.spatial import examples as spatial

    found = []
    folder = shipped_data() / "knowledge" / "mechanisms"
    for path in sorted(folder.glob("*.json")):
        data = json.loads(path.read_text(encoding="utf-8"))
        found.append({"name": data.get("name", path.stem), "source": f"knowledge/mechanisms/{path.name}",
                      "mechanism": data})
    for make in (planar.four_bar, planar.slider_crank, planar.parallelogram, planar.triple_rocker,
                 planar.stephenson_iii, spatial.rssr):
        mech = make()
        found.append({"name": mech.name, "source": f"{make.__module__}.{make.__name__}()",
                      "mechanism": mech.to_dict()})
    return {"examples": found}


routes = [api("/api/mechanism/solve", solve), api("/api/mechanism/save", save),
          api("/api/mechanism/examples", examples, ("GET",))]

__all__ = ["assembly_modes", "read_mechanism", "redrawn", "routes", "solve_motion", "spatial_view"]
