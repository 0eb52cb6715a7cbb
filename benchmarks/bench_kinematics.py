"""Accuracy against time for the kinematics backend's presets (issue 5, item 5).

Run ``python benchmarks/bench_kinematics.py``. For each accuracy preset and
method it times a full-turn sweep (positions, velocities, accelerations, all
outputs) of every linkage in ``examples/mechanisms/`` driven by an R joint (no gear or cam pair) and measures
the error against a 40-digit mpmath reference (Newton on the whole
loop-closure model, derivatives from the same link units in mpmath) at every
10° of input; then the error of the located dead point of seed 000 T9
(exact: arccos(−29/48)), of a change point (exact: 180°), and of the rocker
travel of the crank-rocker (exact: law of cosines). mpmath is used here and in
the tests only, not at runtime.
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import mpmath

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from domes.io.mechanisms import load_mechanism  # noqa: E402
from domes.motion import Input, Joint, Kinematics, Mechanism, accuracy  # noqa: E402
from domes.motion.planar.checks import output_range  # noqa: E402
from domes.motion.planar.examples import four_bar, triple_rocker  # noqa: E402
from domes.motion.planar.structure import evaluate  # noqa: E402
from domes.motion.planar.sweep import run_sweep, sweep  # noqa: E402

mpmath.mp.dps = 40
SAMPLE = math.radians(10)


def reference(kin_full: Kinematics, values: dict) -> dict:
    """Outputs (order 2) at the configuration ``values`` refined in mpmath (Newton on the full model)."""
    g = kin_full.groups[-1]
    mp = {k: mpmath.mpf(v) for k, v in values.items()}
    for _ in range(8):
        A, J = _mp_system(g, mp)
        dx = mpmath.lu_solve(J, -A)
        for v, d in zip(g.unknowns, dx):
            mp[v] += d
    rates = {v: mpmath.mpf(kin_full.inputs[j].speed) for j, v in kin_full.structure.input_vars.items()}
    accels = {v: mpmath.mpf(kin_full.inputs[j].acceleration) for j, v in kin_full.structure.input_vars.items()}
    A, J = _mp_system(g, mp)
    rhs = mpmath.matrix(len(A), 1)
    for i, loop in enumerate(g.loops):
        _, cols, _ = evaluate(loop, mp, lib=mpmath)
        for v, c in cols.items():
            if v not in g.unknowns:
                rhs[2 * i] -= c[0] * rates[v]
                rhs[2 * i + 1] -= c[1] * rates[v]
    sol = mpmath.lu_solve(J, rhs)
    rates.update({v: sol[k] for k, v in enumerate(g.unknowns)})
    rhs = mpmath.matrix(len(A), 1)
    for i, loop in enumerate(g.loops):
        _, cols, dcols = evaluate(loop, mp, rates, lib=mpmath)
        for v, c in cols.items():
            if v not in g.unknowns:
                rhs[2 * i] -= c[0] * accels[v]
                rhs[2 * i + 1] -= c[1] * accels[v]
        for v, c in dcols.items():
            rhs[2 * i] -= c[0] * rates[v]
            rhs[2 * i + 1] -= c[1] * rates[v]
    sol = mpmath.lu_solve(J, rhs)
    accels.update({v: sol[k] for k, v in enumerate(g.unknowns)})
    out = {}
    for o in kin_full.outputs:
        if o.kind == "angle":
            expr = kin_full.structure.rotations[o.target]
            ref = 0.0 if o.target == kin_full.mech.ground else kin_full.mech.reference_angle(o.target)
            comps = [[ref + expr.value(mp)], [expr.rate(rates)], [expr.rate(accels)]]
        elif o.kind == "slide":
            v = kin_full.structure.input_vars.get(o.target, f"s:{o.target}")
            comps = [[mp[v]], [rates[v]], [accels[v]]]
        else:
            a, cols, dcols = evaluate(kin_full._output_paths[o.target], mp, rates, lib=mpmath)
            comps = [list(a), [sum(c[k] * rates[v] for v, c in cols.items()) for k in (0, 1)],
                     [sum(c[k] * accels[v] for v, c in cols.items()) + sum(c[k] * rates[v] for v, c in dcols.items())
                      for k in (0, 1)]]
        for k, comp in enumerate(comps):
            for name, val in zip(o.columns(), comp):
                out[name + "'" * k] = val
    return out


def _mp_system(g, values):
    n = g.equations
    A = mpmath.matrix(n, 1)
    J = mpmath.matrix(n, len(g.unknowns))
    for i, loop in enumerate(g.loops):
        a, cols, _ = evaluate(loop, values, lib=mpmath)
        A[2 * i], A[2 * i + 1] = a
        for k, v in enumerate(g.unknowns):
            if v in cols:
                J[2 * i, k], J[2 * i + 1, k] = cols[v]
    return A, J


def sweep_errors(preset, method, cache):
    """Time of full-turn sweeps of every example and the worst errors (position, velocity, acceleration)."""
    total = 0.0
    worst = [0.0, 0.0, 0.0]
    for path in sorted((ROOT / "examples" / "mechanisms").glob("*.json")):
        m = load_mechanism(str(path))
        if m.joint(m.inputs[0].joint).kind != "R" or m.gears or m.cams:
            continue  # full-turn sweeps of linkages driven by an R joint (the mpmath reference has no gear or cam)
        kin = Kinematics(m, None, 2, method, preset)
        q0 = kin.drawn_inputs()[m.inputs[0].joint]
        t = time.perf_counter()
        sw = run_sweep(kin, q0, q0 + 2 * math.pi)
        total += time.perf_counter() - t
        if sw.dead_points:
            continue  # the parallelogram: its branch points are measured in the change-point column
        full = Kinematics(m, None, 2, "newton", "exact")
        scale = {0: m.size, 1: m.size * abs(m.inputs[0].speed), 2: m.size * m.inputs[0].speed ** 2}
        for st in sw.steps:
            k = (st.inputs[m.inputs[0].joint] - q0) / SAMPLE
            if abs(k - round(k)) > 1e-6:
                continue
            key = (path.name, round(k))
            if key not in cache:
                cache[key] = reference(full, full.positions(st.inputs, st.state))
            ref = cache[key]
            for col, val in st.values.items():
                order = len(col) - len(col.rstrip("'"))
                err = abs(val - ref[col])
                if col.startswith("angle") and order == 0:
                    err = abs(mpmath.mpf(val) - ref[col])
                    err = float(min(err, abs(err - 2 * mpmath.pi)))
                    rel = err
                else:
                    rel = float(err) / (scale[order] if not col.startswith("angle") else
                                        (1 if order == 0 else abs(m.inputs[0].speed) ** order))
                worst[order] = max(worst[order], rel)
    return total, worst


def _change_point():
    m = Mechanism.build("change point", ["f", "crank", "coupler", "rocker"], "f",
                        [Joint("A", "R", ("f", "crank"), (0, 0)), Joint("B", "R", ("crank", "coupler"), (0, 1)),
                         Joint("C", "R", ("coupler", "rocker"), (2, 1)), Joint("D", "R", ("rocker", "f"), (2, 0))],
                        [Input("A")])
    return m


def located(preset, method):
    """Errors of the T9 limit, of the change point at 180°, and of the rocker travel, with their times."""
    t = time.perf_counter()
    sw = sweep(triple_rocker(), 0.0, math.radians(135), outputs=["angle:rocker"], method=method, accuracy=preset)
    t9 = time.perf_counter() - t
    limit = next(d for d in sw.dead_points if d.kind == "limit")
    e9 = abs(mpmath.mpf(limit.input) - mpmath.acos(mpmath.mpf(-29) / 48))
    t = time.perf_counter()
    sw = sweep(_change_point(), math.radians(100.3), math.radians(260), outputs=["angle:rocker"], method=method,
               accuracy=preset)
    tc = time.perf_counter() - t
    sing = [d for d in sw.dead_points if d.kind in ("singular", "bifurcation")]
    ec = min((abs(d.input - math.pi) for d in sing), default=math.inf)
    t = time.perf_counter()
    r = output_range(four_bar(), "angle:rocker", 0, 2 * math.pi, accuracy=preset)
    tr = time.perf_counter() - t
    exact = mpmath.acos(mpmath.mpf(-1) / 3) - mpmath.acos(mpmath.mpf(3) / 5)
    er = abs(mpmath.mpf(r.travel) - exact)
    return (float(e9), t9), (ec, tc), (float(er), tr)


def main(argv=None):
    argparse.ArgumentParser(description=__doc__.splitlines()[0]).parse_args(argv)
    cache = {}
    rows = []
    settings = [(name, method, name) for name in ("fast", "default", "exact") for method in ("assur", "newton")]
    # Newton's own knob: a loose tolerance on the last correction (closed-form dyads ignore it).
    settings += [("fast, tol=1e-2", "newton", accuracy("fast", tol=1e-2)),
                 ("default, tol=1e-4", "newton", accuracy("default", tol=1e-4))]
    for label, method, preset in settings:
        t, (e0, e1, e2) = sweep_errors(preset, method, cache)
        (e9, t9), (ec, tc), (er, tr) = located(preset, method)
        rows.append((label, method, t, e0, e1, e2, math.degrees(e9), t9, math.degrees(ec), tc, er, tr))
    head = ("preset", "method", "sweeps s", "pos err", "vel err", "acc err", "T9 limit err °", "s",
            "change pt err °", "s", "travel err rad", "s")
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for r in rows:
        print(f"| {r[0]} | {r[1]} | {r[2]:.3f} | {r[3]:.1e} | {r[4]:.1e} | {r[5]:.1e} | {r[6]:.1e} | {r[7]:.3f} | "
              f"{r[8]:.1e} | {r[9]:.3f} | {r[10]:.1e} | {r[11]:.3f} |")


if __name__ == "__main__":
    main()
