"""Speed and error of the kinematics kernel beside its peers (issue 12, item 5).

Run ``python benchmarks/bench_kernel.py``. It prints, in one run:

1. each example sweep of 3,600 steps (a full turn from the drawn pose),
   order 0 and order 2, all outputs: the median time of ``--repeat`` runs
   in-process, the largest residual, and the error against the 40-digit
   mpmath reference (``bench_kinematics.reference``) at every 100th step;
   for a mechanism with a class-III or class-IV group also the step-by-step
   Newton route (timed once) and the largest difference of the two; beside
   it the same sweep (positions) in Pyslvs and pylinkage when they
   are installed (``benchmarks/peers.py``; a peer that is missing is skipped
   with a note), with their time and error against the same reference;
2. a batch of ``--mechanisms`` random four-bars × 360 inputs (positions of a
   coupler point): time, positions per second, and the error of a sample of
   rows against the reference; beside it the peers' rate on a sample of
   the same four-bars (one mechanism at a time: they have no batch API).

Each of our timed sweeps follows an untimed run of the same sweep, as each
peer's timed loop follows an untimed call of its own solver in its harness
(``--cold``: ours right after the other libraries', as a sweep among other
work).

``--kernel`` picks the kernel's route (``domes.motion.planar.compiled``):
``numpy``, ``numba`` (compiled), or ``both`` (the default: a row for each,
so the table shows what the compiled route buys). With ``--clock cpu`` the
peers' loops are timed by CPU time too.
"""

from __future__ import annotations

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

import peers  # noqa: E402
from bench_kinematics import reference  # noqa: E402
from peers import PEERS  # noqa: E402

from domes.io.mechanisms import load_mechanism  # noqa: E402
from domes.motion import CouplerPoint, Input, Joint, Kinematics, Mechanism, batch  # noqa: E402
from domes.motion.planar.continuation import Continuation  # noqa: E402
from domes.motion.planar.examples import stephenson_iii  # noqa: E402
from domes.motion.planar.kernel import iterated  # noqa: E402
from domes.motion.planar.query import parse_outputs  # noqa: E402
from domes.motion.planar.sweep import _scalar_sweep, run_sweep  # noqa: E402

#: Example files, and ``stephenson-iii`` (:func:`~domes.motion.planar.examples.stephenson_iii`, a triad).
EXAMPLES = ["four-bar.json", "watt-six-bar.json", "stephenson-six-bar.json", "stephenson-iii",
            "eight-bar-class-iv.json"]
STEPS = 3600
#: The joint each example is compared at: one solved last (the far end of the chain of groups).
FAR_JOINT = {"four-bar.json": "C", "watt-six-bar.json": "f", "stephenson-six-bar.json": "G", "stephenson-iii": "B1",
             "eight-bar-class-iv.json": "9"}


#: The clock of :func:`median_time`: wall time, or (``--clock cpu``) this process's CPU time, which a busy machine
#: does not inflate as much (it counts every thread of the process).
CLOCK = time.perf_counter


def median_time(fn, repeat):
    out = fn()
    times = []
    for _ in range(repeat):
        out = None                      # drop the last result first: peak memory is one result, not two
        t = CLOCK()
        out = fn()
        times.append(CLOCK() - t)
    return statistics.median(times), out


def _reference_points(mech, qs, point, every):
    """The mpmath reference position of ``point`` at every ``every``-th input of ``qs`` (from our sweep's states)."""
    full = Kinematics(mech, [f"point:{point}"], 2, "newton", "exact")
    sw = run_sweep(Kinematics(mech, [f"point:{point}"], 0), qs[0], qs[-1], (qs[-1] - qs[0]) / (qs.size - 1))
    j = mech.inputs[0].joint
    out = {}
    for k in range(0, sw.inputs.size, every):
        st = sw.steps[k]
        ref = reference(full, full.positions(st.inputs, st.state))
        out[k] = (float(ref[f"point:{point}.x"]), float(ref[f"point:{point}.y"]))
    assert sw.inputs.size == qs.size and abs(sw.steps[0].inputs[j] - qs[0]) < 1e-12
    return out


def _unit(mech, column):
    """The scale of a column: the size (lengths) times the input speed per derivative order."""
    k = len(column) - len(column.rstrip("'"))
    return (1.0 if column.startswith("angle") else mech.size) * abs(mech.inputs[0].speed) ** k


def _error(points, refs, size):
    return max(math.hypot(points[k][0] - x, points[k][1] - y) for k, (x, y) in refs.items()) / size


def example(name):
    return stephenson_iii() if name == "stephenson-iii" else load_mechanism(str(ROOT / "examples" / "mechanisms" / name))


#: The kernel's routes a run times (``--kernel``).
ROUTES = ("numpy", "numba")


def _route(route):
    """Run the kernel by ``route`` from now on (``DOMES_KERNEL``)."""
    os.environ["DOMES_KERNEL"] = route


def sweeps(repeat, names=EXAMPLES):
    """A row per example, library, route and order: the median and the best of ``repeat`` runs, taken in rounds
    (each round runs every library's sweep of the example once, in turn), so that a change of the machine's load
    falls on all of them alike."""
    rows = []
    for name in names:
        m = example(name)
        j = m.inputs[0].joint
        q0 = Kinematics(m).drawn_inputs()[j]
        qs = q0 + np.linspace(0.0, 2 * math.pi, STEPS + 1)
        point = FAR_JOINT[name]
        refs = _reference_points(m, qs, point, 100)
        outputs = [o.name for o in parse_outputs(m, None)] + [f"point:{point}"]  # all outputs and the far joint
        timed, slow_rows = [], []
        for order in (0, 2):
            kin = Kinematics(m, outputs, order)
            for route in ROUTES:
                timed.append((f"domes ({route})", order, _ours(kin, qs, route)))
            if iterated(kin):  # the step-by-step Newton route the arrays replace (once: it is slow)
                _route(ROUTES[-1])
                sw = run_sweep(kin, qs[0], qs[-1], 2 * math.pi / STEPS)
                cont = Continuation(kin)
                t, slow = median_time(lambda: _scalar_sweep(kin, cont, list(qs), None), 1)
                same = max(float(np.nanmax(np.abs(sw.column(c) - slow.column(c)))) / _unit(m, c) for c in sw.columns)
                pts = np.c_[slow.column(f"point:{point}.x"), slow.column(f"point:{point}.y")]
                slow_rows.append((name, "domes step by step", order, t, t, slow.max_residual,
                                  _error(pts, refs, m.size), f"arrays − steps: {same:.1e} of the scale"))
        for peer, fn in PEERS.items():
            try:
                got = fn(m, qs, point)  # the first run warms the peer up (numba's dispatch, caches), as ours
            except NotImplementedError as exc:
                rows.append((name, peer, 0, None, None, None, None, str(exc)))
                continue
            if got is None:
                rows.append((name, peer, 0, None, None, None, None, "not installed"))
                continue
            timed.append((peer, 0, lambda fn=fn, got=got: (fn(m, qs, point)[1], (got[0], None, 0))))
        for _, _, run in timed:
            run()  # warm up: numba's dispatch, the query's caches
        times = [[] for _ in timed]
        last = [None] * len(timed)
        for _ in range(repeat):
            for k, (_, _, run) in enumerate(timed):
                last[k] = None  # drop the last result first: peak memory is one result, not two
                dt, last[k] = run()
                times[k].append(dt)
        for (lib, order, _), ts, (pts, residual, dead) in zip(timed, times, last):
            rows.append((name, lib, order, statistics.median(ts), min(ts), residual, _error(pts, refs, m.size),
                         None if residual is None else dead))
        rows += slow_rows
    return rows


#: Whether each of our timed sweeps follows an untimed run of the same sweep (``--cold`` turns it off).
WARM = True


def _ours(kin, qs, route):
    """A timed sweep of ``kin`` by ``route``: ``(seconds, (far joint's points, max residual, dead points))``. Unless
    ``--cold``, right after an untimed run of the same sweep, as the peers' harnesses run their own solver before
    the timed loop (pylinkage turns the crank to the start with ``step_fast``, Pyslvs solves the drawn pose), so
    that every library is timed with its own code and data in the caches."""
    far = kin.outputs[-1].target  # the far joint's point is the last output

    def run():
        _route(route)
        if WARM:
            run_sweep(kin, qs[0], qs[-1], 2 * math.pi / STEPS)
        t = CLOCK()
        sw = run_sweep(kin, qs[0], qs[-1], 2 * math.pi / STEPS)
        dt = CLOCK() - t
        return dt, (np.c_[sw.column(f"point:{far}.x"), sw.column(f"point:{far}.y")], sw.max_residual,
                    len(sw.dead_points))
    return run


def four_bar_template():
    return Mechanism.build("four-bar", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
                            Joint("C", "R", ("coupler", "rocker"), (3.5, math.sqrt(6.0))),
                            Joint("D", "R", ("rocker", "f"), (3.0, 0.0))],
                           [Input("A")], points=[CouplerPoint("P", "coupler", (2.0, 2.0))])


def random_four_bars(count, seed=0):
    rng = np.random.default_rng(seed)
    return {"B": np.c_[rng.uniform(0.5, 1.5, count), rng.uniform(-0.3, 0.3, count)],
            "C": np.c_[rng.uniform(2.5, 4.0, count), rng.uniform(1.5, 3.0, count)],
            "D": np.c_[rng.uniform(2.5, 3.5, count), np.zeros(count)],
            "P": np.c_[rng.uniform(0.0, 4.0, count), rng.uniform(0.0, 4.0, count)]}


def _row(coords, m):
    t = four_bar_template()
    moved = {k: tuple(v[m]) for k, v in coords.items()}
    joints = [Joint(j.name, j.kind, j.links, moved.get(j.name, j.at)) for j in t.joints]
    return Mechanism.build(f"four-bar {m}", list(t.links), t.ground, joints, list(t.inputs),
                           points=[CouplerPoint("P", "coupler", moved["P"])])


def batches(count, repeat, peer_sample):
    coords = random_four_bars(count)
    qs = np.radians(np.arange(360.0))
    rows = []
    for route in ROUTES:
        b = None
        t, b = median_time(lambda: batch(four_bar_template(), coords, qs, outputs=["point:P"], route=route), repeat)
        # Error: 12 complete rows × every 30th input against the reference.
        worst = 0.0
        for m in np.flatnonzero(b.kinds == "complete")[:12]:
            mech = _row(coords, m)
            refs = _reference_points(mech, qs, "P", 30)
            pts = {k: (b.values["point:P.x"][m, k], b.values["point:P.y"][m, k]) for k in refs}
            worst = max(worst, _error(pts, refs, mech.size))
        rows.append((f"domes batch ({route})", count, t, count * qs.size / t, worst, b.message))
    complete = np.flatnonzero(b.kinds == "complete")[:peer_sample]
    for peer, fn in PEERS.items():
        total, done, err = 0.0, 0, 0.0
        note = ""
        for m in complete:
            mech = _row(coords, m)
            try:
                got = fn(mech, qs, "P")
            except NotImplementedError as exc:
                note = str(exc)
                break
            if got is None:
                note = "not installed"
                break
            pts, dt = got
            total += dt
            done += 1
            mine = np.c_[b.values["point:P.x"][m], b.values["point:P.y"][m]]
            err = max(err, float(np.max(np.hypot(*(pts - mine).T))) / mech.size)
        if done:
            rows.append((peer, done, total, done * qs.size / total, err, "one mechanism at a time; error vs domes"))
        else:
            rows.append((peer, 0, None, None, None, note))
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=7, help="runs per timing (the median is shown)")
    ap.add_argument("--cold", action="store_true", help="time each of our sweeps right after the other libraries' "
                    "(as a sweep among other work), not after an untimed run of its own as the peers' are")
    ap.add_argument("--mechanisms", type=int, default=100_000, help="four-bars in the batch")
    ap.add_argument("--peer-sample", type=int, default=200, help="four-bars of the batch timed in each peer")
    ap.add_argument("--only", help=f"comma-separated examples to sweep (of {', '.join(EXAMPLES)})")
    ap.add_argument("--no-batch", action="store_true", help="sweeps only")
    ap.add_argument("--clock", choices=["wall", "cpu"], default="wall", help="time by the wall clock or by the "
                    "process's CPU time (steadier on a busy machine)")
    ap.add_argument("--kernel", choices=["numpy", "numba", "both"], default="both",
                    help="the kernel's route: numpy, compiled (numba), or a row for each")
    args = ap.parse_args(argv)
    global CLOCK, ROUTES, WARM
    CLOCK = time.process_time if args.clock == "cpu" else time.perf_counter
    WARM = not args.cold
    peers.CLOCK = CLOCK
    ROUTES = ("numpy", "numba") if args.kernel == "both" else (args.kernel,)
    names = args.only.split(",") if args.only else EXAMPLES
    unknown = sorted(set(names) - set(EXAMPLES))
    if unknown:
        ap.error(f"--only: {unknown} are not examples; choose among {EXAMPLES}")
    after = "after the other libraries'" if args.cold else "after an untimed run of its own, as the peers'"
    print(f"## Sweeps of {STEPS:,} steps ({args.repeat} rounds, each library in turn; ours timed {after}; "
          f"{args.clock} time)\n")
    print("| mechanism | library | order | median [ms] | best [ms] | max residual | position error / size | "
          "dead points |")
    print("|---|---|---:|---:|---:|---:|---:|---|")
    for name, lib, order, t, best, res, err, dead in sweeps(args.repeat, names):
        if t is None:
            print(f"| {name} | {lib} | | | | | | skipped: {dead} |")
        else:
            print(f"| {name} | {lib} | {order} | {t * 1e3:.2f} | {best * 1e3:.2f} | "
                  f"{'' if res is None else f'{res:.1e}'} | {err:.1e} | {'' if dead is None else dead} |")
    if args.no_batch:
        return
    print(f"\n## Batch: {args.mechanisms:,} random four-bars × 360 inputs, a coupler point (median of "
          f"{max(1, args.repeat // 3)})\n")
    print("| library | mechanisms | time [s] | positions/s | position error / size | note |")
    print("|---|---:|---:|---:|---:|---|")
    for lib, n, t, rate, err, note in batches(args.mechanisms, max(1, args.repeat // 3), args.peer_sample):
        if t is None:
            print(f"| {lib} | | | | | skipped: {note} |")
        else:
            print(f"| {lib} | {n:,} | {t:.3f} | {rate / 1e6:.2f} M | {err:.1e} | {note} |")


if __name__ == "__main__":
    main()
