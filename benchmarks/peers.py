"""The same position sweeps in the peer libraries Pyslvs and pylinkage, for ``bench_kernel.py``.

Each adapter takes a mechanism (:class:`domes.motion.Mechanism`), an array
``qs`` of absolute input angles (rad, as our model defines the input) and the
name of a joint or coupler point. It builds the peer's model of the
mechanism once, in its drawn pose, then times solving every input in
``qs`` in-process and returns ``(positions, seconds)``: the ``(len(qs), 2)``
world positions of the point and the time of the solving loop only. It
returns None when the peer is not installed and raises
:class:`NotImplementedError` (with the reason) when the peer cannot express
the mechanism.

Both peers measure the crank angle as the direction from the ground pivot
to a pin of the crank (Pyslvs' ``expr_solving`` in degrees, its geometric
functions and pylinkage in radians); the adapters convert from our input
angle. Both keep the drawn assembly mode: Pyslvs picks each dyad's solution
by the orientation of the drawn pose (refused if it is not the drawn one),
pylinkage the solution nearest the previous step, starting from the drawn
pose.

Run ``python benchmarks/peers.py`` to time both peers (and Pyslvs'
``expr_solving``) on the example mechanisms beside our ``run_sweep`` and
compare their positions with ours.
"""

from __future__ import annotations

import math
import statistics
import sys
import time
from functools import partial
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

#: The clock the solving loops are timed by: wall time, or ``time.process_time`` (CPU time of this process) when a
#: benchmark runs with ``--clock cpu`` (``bench_kernel.py`` sets it).
CLOCK = time.perf_counter

#: Examples of ``examples/mechanisms`` and the joint compared: one solved in the last group.
EXAMPLES = {"four-bar.json": "C", "watt-six-bar.json": "f", "stephenson-six-bar.json": "G"}
STEPS = 3600
REPEAT = 5


def _driver(mech):
    """``(input joint, driven link, drawn input value)``; only an R joint to the ground is supported."""
    from domes.motion import Kinematics

    if len(mech.inputs) != 1:
        raise NotImplementedError(f"{mech.name}: {len(mech.inputs)} inputs; the peer adapters drive one crank")
    joint = mech.joint(mech.inputs[0].joint)
    if joint.kind != "R" or mech.ground not in joint.links:
        raise NotImplementedError(f"{mech.name}: input {joint.name} is not an R joint to the ground; "
                                  "the peers drive cranks only")
    link = joint.links[1] if joint.links[0] == mech.ground else joint.links[0]
    return joint, link, Kinematics(mech).drawn_inputs()[joint.name]


def _points(mech):
    """Every named point as ``name -> (links it belongs to, drawn position)``: joints, then coupler points."""
    out = {j.name: ((j.links[1],) if j.kind == "P" else j.links, j.at) for j in mech.joints}
    out.update({p.name: ((p.link,), p.at) for p in mech.points})
    return out


def _crank_pin(mech, joint, link):
    """A point of the driven link away from the input joint: the crank pin the peers turn."""
    for name, (links, at) in _points(mech).items():
        if name != joint.name and link in links and math.dist(at, joint.at) > 1e-9 * mech.size:
            return name
    raise NotImplementedError(f"{mech.name}: the driven link {link} has no point besides {joint.name}")


def _angle(p, q):
    return math.atan2(q[1] - p[1], q[0] - p[0])


# ----------------------------------------------------------------------------------------------------------------------
# Pyslvs


def pyslvs_sweep(mech, qs, point, api="tinycadlib"):
    """Positions of ``point`` at the inputs ``qs`` and the seconds to solve them in Pyslvs, or None if not installed.

    The model is a list of ``VPoint`` (R joints, P joints as sliders on their
    guide, coupler points as one-link points) and one input pair (input
    joint, crank pin); ``t_config`` turns it once into Pyslvs' triangular
    expression stack. Each input is then solved by

    - ``api="tinycadlib"`` (the default, the fastest): the stack run as calls
      of Pyslvs' compiled geometric functions (``plap``, ``pllp``, ``plpp``,
      ...), as Pyslvs' own solver runs it, with the lengths and angles taken
      once from the drawn pose;
    - ``api="expr_solving"``: one call of ``expr_solving`` (the API Pyslvs'
      GUI sweeps with), which takes the lengths and angles from the drawn
      pose again at every call.
    """
    try:
        import pyslvs
    except ImportError:
        return None
    vpoints, names, exprs, pair, offset, q_drawn = _pyslvs_model(pyslvs, mech)
    if point not in names:
        raise NotImplementedError(f"{mech.name}: no joint or point {point!r}")
    angles = (np.asarray(qs, dtype=float) + offset).tolist()  # Pyslvs' crank angles (rad)
    index = names.index(point)
    rows = [(math.nan, math.nan)] * len(angles)
    if api == "expr_solving":

        def solve(a):  # expr_solving takes degrees; a slider's row is (slot point, slider point)
            return [c[1] if isinstance(c[0], tuple) else c for c in pyslvs.expr_solving(exprs, vpoints, {pair: a})]

        _check_drawn(mech, names, solve(math.degrees(q_drawn + offset)), "Pyslvs")
        degrees = np.degrees(angles).tolist()
        slider = vpoints[index].is_slider()
        t0 = CLOCK()
        for k, a in enumerate(degrees):
            try:
                c = pyslvs.expr_solving(exprs, vpoints, {pair: a})[index]
            except ValueError:  # cannot be assembled at this input
                continue
            rows[k] = c[1] if slider else c
        return np.array(rows, dtype=float), CLOCK() - t0
    if api != "tinycadlib":
        raise ValueError(f"api must be 'tinycadlib' or 'expr_solving', got {api!r}")
    drawn = {f"P{k}": _points(mech)[name][1] for k, name in enumerate(names)}
    for g in mech.joints:  # each slide line's second point (S): one unit along the slide from its pin
        if g.kind == "P":
            drawn.update({f"S{k}": (j.at[0] + math.cos(g.direction), j.at[1] + math.sin(g.direction))
                          for k, j in enumerate(mech.joints) if j.kind == "R" and g.links[1] in j.links})
    start = {sym: pyslvs.Coord(*at) for sym, at in drawn.items()}
    program = _pyslvs_program(pyslvs, mech, exprs, start)

    def solve(a):
        p = dict(start)  # as Pyslvs' solver: every input starts from the drawn pose
        for target, step in program:
            p[target] = step(p, a)
        return p

    at_drawn = solve(q_drawn + offset)
    _check_drawn(mech, names, [(at_drawn[f"P{k}"].x, at_drawn[f"P{k}"].y) for k in range(len(names))], "Pyslvs")
    key = f"P{index}"
    t0 = CLOCK()
    for k, a in enumerate(angles):
        c = solve(a)[key]
        rows[k] = (c.x, c.y)  # NaN where it cannot be assembled
    return np.array(rows, dtype=float), CLOCK() - t0


def _pyslvs_model(pyslvs, mech):
    """``(vpoints, names, expression stack, input pair, crank angle − our input, our drawn input)``."""
    joint, link, q_drawn = _driver(mech)
    links = {name: pyslvs.VLink.FRAME if name == mech.ground else f"link{k}" for k, name in enumerate(mech.links)}
    vpoints, names = [], []
    for j in mech.joints:
        if j.kind == "R":
            vpoints.append(pyslvs.VPoint.r_joint([links[n] for n in j.links], j.at[0], j.at[1]))
        else:
            vpoints.append(pyslvs.VPoint.slider_joint([links[n] for n in j.links], pyslvs.VJoint.P,
                                                      math.degrees(j.direction), j.at[0], j.at[1]))
        names.append(j.name)
    for p in mech.points:
        vpoints.append(pyslvs.VPoint.r_joint([links[p.link]], p.at[0], p.at[1]))
        names.append(p.name)
    pair = (names.index(joint.name), names.index(_crank_pin(mech, joint, link)))
    status = {}
    exprs = pyslvs.t_config(vpoints, [pair], status)
    unsolved = [names[k] for k, ok in status.items() if not ok]
    if unsolved:
        raise NotImplementedError(f"{mech.name}: Pyslvs' triangular solver cannot place {unsolved} "
                                  "(it would fall back to its BFGS solver)")
    # Pyslvs' input: the direction from the input joint to the crank pin.
    offset = _angle(vpoints[pair[0]].c[0], vpoints[pair[1]].c[0]) - q_drawn
    return vpoints, names, exprs, pair, offset, q_drawn


def _pyslvs_program(pyslvs, mech, exprs, start):
    """The stack as ``(target, step(positions, crank angle))`` calls of Pyslvs' functions; drawn-pose parameters.

    Where a function has two solutions (``inverse``), the one of the drawn
    pose is kept.
    """
    plap, pllp, plpp, ppp, pxy = pyslvs.plap, pyslvs.pllp, pyslvs.plpp, pyslvs.ppp, pyslvs.pxy
    pos = dict(start)
    program = []
    for func, *args in exprs.as_list():
        c1, target = args[0], args[-1]
        xy = [(pos[c].x, pos[c].y) for c in (c1, target)]
        length = math.dist(*xy)
        if func == "PLA":
            steps = [lambda p, a, c1=c1, d=length: plap(p[c1], d, a)]
        elif func == "PLAP":
            c2 = args[3]
            angle = _angle(*xy) - _angle(xy[0], (pos[c2].x, pos[c2].y))
            steps = [lambda p, a, c1=c1, c2=c2, d=length, b=angle: plap(p[c1], d, b, p[c2])]
        elif func == "PLLP":
            c2 = args[3]
            d2 = math.dist((pos[c2].x, pos[c2].y), xy[1])
            steps = [lambda p, a, c1=c1, c2=c2, d=length, d2=d2, op=op: pllp(p[c1], d, d2, p[c2], op)
                     for op in (False, True)]
        elif func == "PLPP":
            c2, c3 = args[2], args[3]
            steps = [lambda p, a, c1=c1, c2=c2, c3=c3, d=length, op=op: plpp(p[c1], d, p[c2], p[c3], op)
                     for op in (False, True)]
        elif func == "PXY":
            dx, dy = xy[1][0] - xy[0][0], xy[1][1] - xy[0][1]
            steps = [lambda p, a, c1=c1, dx=dx, dy=dy: pxy(p[c1], dx, dy)]
        elif func == "PPP":
            steps = [lambda p, a, c1=c1, c2=args[1], c3=args[2]: ppp(p[c1], p[c2], p[c3])]
        else:
            raise NotImplementedError(f"{mech.name}: Pyslvs expression {func} is not supported here")
        # At the drawn input (for PLA: the drawn crank angle) every point is at its drawn place: keep the
        # solution that lands on the drawn target.
        a = _angle(*xy)
        step = min(steps, key=lambda s: math.dist((s(pos, a).x, s(pos, a).y), xy[1]))
        program.append((target, step))
    return program


def _check_drawn(mech, names, solved, peer):
    """Refuse a model that does not reproduce the drawn pose at the drawn input (another assembly mode)."""
    for name, got in zip(names, solved):
        got = got[1] if isinstance(got[0], tuple) else got
        at = _points(mech)[name][1]
        if math.dist(got, at) > 1e-9 * mech.size:
            raise NotImplementedError(f"{mech.name}: {peer} places {name} at {got}, not at its drawn {at} "
                                      "(another assembly mode)")


# ----------------------------------------------------------------------------------------------------------------------
# pylinkage


def pylinkage_sweep(mech, qs, point):
    """Positions of ``point`` at the inputs ``qs`` and the seconds to solve them in pylinkage, or None if not installed.

    The model is built from pylinkage's components: ``Ground`` points, a
    ``Crank``, ``RRRDyad`` (circle-circle), ``RRPDyad`` (circle-line, a pin
    in a slider on a known guide) and ``FixedDyad`` (further points of a
    placed link). pylinkage turns the crank by a constant step and solves
    each dyad nearest its previous position, so ``qs`` must be evenly
    spaced; before the timed run the crank is turned (untimed, in steps of
    at most one step of ``qs``) from the drawn pose to one step before
    ``qs[0]``. The timed run is ``Linkage.step`` (``step_fast`` when numba is
    installed: without numba it is the slower of the two). An input where
    the mechanism cannot be assembled raises pylinkage's ``UnbuildableError``.
    """
    try:
        import pylinkage
        from pylinkage._numba_compat import HAS_NUMBA
    except ImportError:
        return None
    qs = np.asarray(qs, dtype=float)
    if qs.size < 2:
        raise NotImplementedError("pylinkage steps its crank: give at least two inputs")
    dq = (qs[-1] - qs[0]) / (qs.size - 1)
    if dq == 0 or not np.allclose(np.diff(qs), dq, rtol=1e-9, atol=1e-12):
        raise NotImplementedError("pylinkage turns its crank by a constant step: the inputs must be evenly spaced")
    joint, link, q_drawn = _driver(mech)
    parts, components = _pylinkage_model(pylinkage, mech, joint, link, dq)
    if point not in parts:
        raise NotImplementedError(f"{mech.name}: pylinkage's dyads cannot place {point!r} "
                                  f"(placed: {sorted(parts)})")
    linkage = pylinkage.Linkage(components, name=mech.name)
    for _ in linkage.step(iterations=1, dt=0.0):  # solve every dyad at the drawn input
        pass
    _check_drawn(mech, list(parts), [c.position for c in parts.values()], "pylinkage")

    turn = qs[0] - dq - q_drawn  # from the drawn pose to one step before qs[0]
    n = math.ceil(abs(turn) / abs(dq) - 1e-9)
    target = parts[point]
    if HAS_NUMBA:
        index = linkage.components.index(target)
        linkage.step_fast(iterations=max(n, 1), dt=turn / (max(n, 1) * dq))  # also compiles
        t0 = CLOCK()
        out = linkage.step_fast(iterations=qs.size)[:, index]
        return out, CLOCK() - t0
    for _ in linkage.step(iterations=n, dt=turn / (n * dq) if n else 0.0):
        pass
    t0 = CLOCK()
    rows = [target.position for _ in linkage.step(iterations=qs.size)]
    seconds = CLOCK() - t0
    return np.array(rows, dtype=float), seconds


def _pylinkage_model(pylinkage, mech, joint, link, dq):
    """``(components by point name, all components)``: every point pylinkage's dyads can place, drawn pose."""
    points = _points(mech)
    pin = _crank_pin(mech, joint, link)
    parts = {name: pylinkage.Ground(at[0], at[1], name=name) for name, (links, at) in points.items()
             if mech.ground in links}
    extra = []  # components that are not named points: the lines of sliders
    crank = pylinkage.Crank(parts[joint.name], math.dist(joint.at, points[pin][1]), angular_velocity=dq,
                            initial_angle=_angle(joint.at, points[pin][1]), name=pin)
    parts[pin] = crank
    placed = {mech.ground}  # links with their points placed
    progress = True
    while progress:
        progress = False
        for name in mech.links:  # a placed link places its other points
            known = [p for p, (links, _) in points.items() if name in links and p in parts]
            if name in placed or len(known) < 2:
                continue
            a, b = known[0], next((p for p in known[1:] if math.dist(points[p][1], points[known[0]][1]) > 0), None)
            if b is None:
                continue
            placed.add(name)
            for p, (links, at) in points.items():
                if name in links and p not in parts:
                    pa, pb = points[a][1], points[b][1]
                    parts[p] = pylinkage.FixedDyad(parts[a], parts[b], math.dist(pa, at),
                                                   _angle(pa, at) - _angle(pa, pb), name=p)
            progress = True
        for j in mech.joints:
            if j.name in parts:
                continue
            if j.kind == "R":  # RRR dyad: each link has one placed point
                anchors = [next((p for p, (links, _) in points.items() if side in links and p in parts), None)
                           for side in j.links]
                if None in anchors or placed & set(j.links):
                    continue
                d = [math.dist(points[p][1], j.at) for p in anchors]
                parts[j.name] = pylinkage.RRRDyad(parts[anchors[0]], parts[anchors[1]], d[0], d[1],
                                                  x=j.at[0], y=j.at[1], name=j.name)
                progress = True
            else:
                progress |= _rrp(pylinkage, mech, j, points, parts, placed, extra)
    return parts, list(dict.fromkeys([*parts.values(), *extra]))


def _rrp(pylinkage, mech, slide, points, parts, placed, extra):
    """Place the pin of a slider (RRP dyad) whose guide is placed; True if placed."""
    guide, slider = slide.links
    others = [j for j in mech.joints if slider in j.links and j is not slide]
    if guide not in placed or len(others) != 1 or others[0].kind != "R" or others[0].name in parts:
        return False
    pin = others[0]
    rod = pin.links[1] if pin.links[0] == slider else pin.links[0]
    anchor = next((p for p, (links, _) in points.items() if rod in links and p in parts), None)
    if anchor is None:
        return False
    # The pin's path: the line through its drawn position along the slide, carried by the guide.
    ends = [pin.at, (pin.at[0] + math.cos(slide.direction), pin.at[1] + math.sin(slide.direction))]
    if guide == mech.ground:
        line = [pylinkage.Ground(x, y) for x, y in ends]
    else:
        known = [p for p, (links, _) in points.items() if guide in links and p in parts]
        pa, pb = points[known[0]][1], points[known[1]][1]
        line = [pylinkage.FixedDyad(parts[known[0]], parts[known[1]], math.dist(pa, e), _angle(pa, e) - _angle(pa, pb))
                for e in ends]
    parts[pin.name] = pylinkage.RRPDyad(parts[anchor], line[0], line[1], math.dist(points[anchor][1], pin.at),
                                        x=pin.at[0], y=pin.at[1], name=pin.name)
    extra.extend(line)
    if math.dist(slide.at, pin.at) <= 1e-12 * mech.size:  # the slide joint's point is the pin's
        parts[slide.name] = parts[pin.name]
    return True


def pylinkage_label() -> str:
    """pylinkage's row label: whether it is timed with numba (``step_fast``) or without (``step``); found without
    importing either."""
    from importlib.util import find_spec

    if find_spec("pylinkage") is None:
        return "pylinkage"
    return "pylinkage (numba, step_fast)" if find_spec("numba") else "pylinkage (no numba, step)"


#: The peers a benchmark runs, by label: Pyslvs's per-angle API, the same stack run through its geometry
#: functions (the route of its C++ solver), and pylinkage (with numba when installed: its ``step_fast``).
PEERS = {"Pyslvs expr_solving": partial(pyslvs_sweep, api="expr_solving"),
         "Pyslvs tinycadlib": pyslvs_sweep, pylinkage_label(): pylinkage_sweep}


def main():
    """Time each peer on a full turn of every example (median of ``REPEAT``) and compare its positions with ours."""
    from domes.io.mechanisms import load_mechanism
    from domes.motion import Kinematics
    from domes.motion.planar.sweep import run_sweep

    runs = {"pyslvs": pyslvs_sweep, "pyslvs (expr_solving)": partial(pyslvs_sweep, api="expr_solving"),
            "pylinkage": pylinkage_sweep}
    print(f"Full turns of {STEPS:,} steps from the drawn pose; median time of {REPEAT} runs (solving only); "
          "largest distance of the peer's positions to ours")
    for name, point in EXAMPLES.items():
        mech = load_mechanism(ROOT / "examples" / "mechanisms" / name)
        q0 = Kinematics(mech).drawn_inputs()[mech.inputs[0].joint]
        qs = q0 + np.linspace(0.0, 2 * math.pi, STEPS + 1)
        kin = Kinematics(mech, [f"point:{point}"], 0)
        times = []
        for _ in range(REPEAT):
            t0 = CLOCK()
            ours = run_sweep(kin, qs[0], qs[-1], 2 * math.pi / STEPS)
            times.append(CLOCK() - t0)
        assert ours.inputs.size == qs.size and np.allclose(ours.inputs, qs, rtol=0, atol=1e-12)
        mine = np.c_[ours.column(f"point:{point}.x"), ours.column(f"point:{point}.y")]
        print(f"\n{name} (joint {point}):")
        print(f"  {'domes':22} {statistics.median(times) * 1e3:8.2f} ms")
        for peer, fn in runs.items():
            try:
                got = [fn(mech, qs, point) for _ in range(REPEAT)]
            except NotImplementedError as exc:
                print(f"  {peer:22} cannot express it: {exc}")
                continue
            if got[0] is None:
                print(f"  {peer:22} not installed")
                continue
            error = max(float(np.max(np.hypot(*(pts - mine).T))) for pts, _ in got)
            seconds = statistics.median(t for _, t in got)
            print(f"  {peer:22} {seconds * 1e3:8.2f} ms   max distance {error:.1e}")


if __name__ == "__main__":
    main()
