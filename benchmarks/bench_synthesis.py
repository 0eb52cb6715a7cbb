"""Dimensional synthesis: time per task and real roots found (issue 13, item 7).

Run ``python benchmarks/bench_synthesis.py``. For the book's examples
(seed 002 §2-3: Example 4, Example 2 with circle points on two lines,
Example 5), the log10 function generator at 3, 4 and 5 points (with and
without re-spacing) and random tasks (five coupler positions of a random
four-bar: Burmester points; five precision points of a random four-bar's
input-output function; five path points of a random four-bar with its fixed
pivots given; Table 2-1's other free choices, prescribed input angles), the
least-squares path through twelve points and the rising-rate suspension
(every candidate of the motorcycle scene),
it prints the median time, the real roots and the usable linkages found, and
for the random tasks how often the generating linkage is among them, for
the exact method (every root) and the fast one (Newton from 64 random
starts).
"""

from __future__ import annotations

import argparse
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from domes.design.synthesis import function as fn  # noqa: E402
from domes.design.synthesis import guidance as gd  # noqa: E402
from domes.design.synthesis import path as pt  # noqa: E402
from domes.design.synthesis import synthesize, task_from_dict  # noqa: E402
from domes.design.synthesis.pathfit import crank_rocker_path  # noqa: E402
from domes.io.tasks import load_task  # noqa: E402


def timed(task, repeats=5, method="exact"):
    times = []
    for _ in range(repeats):
        t = time.perf_counter()
        result = synthesize(task, method)
        times.append(time.perf_counter() - t)
    return statistics.median(times), result


def book_rows():
    tasks = [("Example 4 (3 positions, inversion + Freudenstein)", load_task(ROOT / "examples/synthesis/ch2-example-4.json")),
             ("Example 2 (4 positions, circle points on x = -1, 0)", load_task(ROOT / "examples/synthesis/ch2-example-2.json")),
             ("Example 5 (5 path points, a0 and b0 given)", load_task(ROOT / "examples/synthesis/ch2-example-5.json"))]
    for n, start in ((3, [25, 105]), (4, [20, None]), (5, [None, None])):
        for respace in (False, True):
            tasks.append((f"log10, {n} points{', re-spaced' if respace else ''}",
                          task_from_dict({"kind": "function", "function": "log10(x)", "range": [1, 10], "input_deg": 60,
                                          "output_deg": -90, "points": n, "start_deg": start, "respace": respace})))
    tasks.append(("Example 5, fast (64 random starts)", tasks[2][1]))
    tasks.append(("Example 2 + slider (4 positions, circle point on x = 0)",
                  load_task(ROOT / "examples/synthesis/ch2-example-2-slider.json")))
    tasks.append(("12 path points, a0 given (least squares)", load_task(ROOT / "examples/synthesis/path-twelve-points.json")))
    for name, task in tasks:
        repeats = 1 if "least squares" in name else 5
        seconds, result = timed(task, repeats, method="fast" if "fast" in name else "exact")
        extra = ""
        best = result.usable[0] if result.usable else None
        if best is not None and best.structural is not None:
            extra = f"largest error {math.degrees(best.structural.largest):.4f}°"
            if best.respaced is not None:
                extra += f" → {math.degrees(best.respaced.after.largest):.4f}° (spread {best.respaced.after.spread:.1e})"
        if best is not None and "least squares" in name:
            extra = f"largest distance {max(best.residuals):.2g} (points read to 0.01)"
        yield name, seconds, result.roots, len(result.solutions), len(result.usable), extra


def candidate_rows():
    """The rising-rate suspension: every candidate of the motorcycle scene dimensioned by least squares."""
    task = load_task(ROOT / "examples/synthesis/rising-rate.json")
    for method in ("exact", "fast"):
        t = time.perf_counter()
        result = synthesize(task, method)
        seconds = time.perf_counter() - t
        for cid, _ in task.candidates:
            mine = [s for s in result.usable if s.candidate == cid]
            best = min((s.error for s in mine), default=math.inf)
            yield method, cid, len(mine), best, seconds / len(task.candidates)


#: Table 2-1 rows measured: points, pivot coordinates given, prescribed input angles.
PATH_ROWS = ((4, ("a0x", "a0y", "a1x", "a1y", "b0x"), False), (6, ("a0x", "a0y", "b0x"), False),
             (7, ("a0x", "a0y"), False), (5, (), True))


def path_rows(count, method):
    rng = np.random.default_rng(3)
    for n, keys, timing in PATH_ROWS:
        times, roots, hits = [], [], 0
        for _ in range(count):
            P, a0, b0, A, B, ths = crank_rocker_path(rng, n)
            values = {"a0x": a0[0], "a0y": a0[1], "b0x": b0[0], "b0y": b0[1], "a1x": A[0][0], "a1y": A[0][1]}
            data = {"kind": "path", "points": P.tolist(), "given": {k: float(values[k]) for k in keys}}
            if timing:
                data["crank_deg"] = np.degrees(ths[1:] - ths[0]).tolist()
            t = time.perf_counter()
            result = synthesize(task_from_dict(data), method)
            times.append(time.perf_counter() - t)
            roots.append(result.roots)
            hits += any(math.dist(s.fourbar.a1, A[0]) < 1e-6 and math.dist(s.fourbar.b1, B[0]) < 1e-6
                        for s in result.solutions)
        given = ", ".join(keys) if keys else "nothing"
        yield (f"random: {n} path points, {given} given{', input angles prescribed' if timing else ''}",
               statistics.median(times), statistics.median(roots), f"{hits}/{count} generating linkages found")


def _coupler_positions(rng):
    """Five coupler positions of a random four-bar (A = (0, 0), D = (d, 0)), and its moving pivots B, C in the
    first one; linkages whose loop does not close at a drawn crank angle are drawn again."""
    while True:
        a, b, c, d = 1.0, rng.uniform(2.5, 3.5), rng.uniform(2.0, 3.0), rng.uniform(2.0, 3.0)
        u, v = rng.uniform(0, 1), rng.uniform(0.5, 1.5)
        out, known = [], None
        for th in np.sort(rng.uniform(0, 2 * math.pi, 5)):
            B = np.array([a * math.cos(th), a * math.sin(th)])
            D = np.array([d, 0.0])
            r = np.linalg.norm(D - B)
            along = (b * b + r * r - c * c) / (2 * r)
            if b * b - along * along <= 0:
                break
            e = (D - B) / r
            C = B + along * e + math.sqrt(b * b - along * along) * np.array([-e[1], e[0]])
            P = B + u * (C - B) / b + v * np.array([-(C - B)[1], (C - B)[0]]) / b
            out.append(gd.Position(tuple(P), math.atan2(*(C - B)[::-1])))
            known = known or (B, C)
        if len(out) == 5:
            return out, known


def random_rows(count, method):
    rng = np.random.default_rng(1)
    times, roots, hits = [], [], 0
    for _ in range(count):
        pos, (B, C) = _coupler_positions(rng)
        t = time.perf_counter()
        found = gd.burmester_points(pos, method=method)
        times.append(time.perf_counter() - t)
        roots.append(len(found))
        hits += all(any(math.dist(f.a1, k) < 1e-6 for f in found) for k in (B, C))
    yield ("random: 5 coupler positions (Burmester points)", statistics.median(times), statistics.median(roots),
           f"{hits}/{count} generating cranks found")
    times, roots, hits = [], [], 0
    for _ in range(count):
        a, b, c, d = 1.0, rng.uniform(3.0, 4.0), rng.uniform(2.5, 3.5), rng.uniform(2.5, 3.5)
        th0, span = rng.uniform(0, 2 * math.pi), rng.uniform(0.8, 1.5)

        def out(x, a=a, b=b, c=c, d=d, th0=th0):
            px, py = a * np.cos(th0 + x) - d, a * np.sin(th0 + x)
            A, Bc, Cc = -2 * c * px, -2 * c * py, px * px + py * py + c * c - b * b
            return np.arctan2(Bc, A) + np.arccos(-Cc / np.hypot(A, Bc))

        y0, y1 = float(out(0.0)), float(out(span))
        task = fn.FunctionTask(out, 0.0, span, span, y1 - y0, tuple(span * fn.chebyshev(5)), (None, None), d)
        t = time.perf_counter()
        sols = fn.solve(task, method)
        times.append(time.perf_counter() - t)
        roots.append(len(sols))
        hits += any(np.allclose((s.crank, s.coupler, s.rocker), (a, b, c), atol=1e-7) for s in sols)
    yield ("random: 5-point function generators", statistics.median(times), statistics.median(roots),
           f"{hits}/{count} generating linkages found")
    times, roots, hits = [], [], 0
    for _ in range(count):
        pos, (B, C) = _coupler_positions(rng)
        pts = [p.point for p in pos]
        a0, b0 = (0.0, 0.0), tuple(gd.centre_point(pos, C))      # the generating four-bar's pivots A and D
        t = time.perf_counter()
        sols = pt.five_points(pts, a0, b0, method=method)
        times.append(time.perf_counter() - t)
        roots.append(len(sols))
        hits += any(math.dist(s.a1, B) < 1e-8 and math.dist(s.b1, C) < 1e-8 for s in sols)
    yield ("random: 5 path points, a0 and b0 given", statistics.median(times), statistics.median(roots),
           f"{hits}/{count} generating linkages found")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--random", type=int, default=50, help="random tasks of each kind (default 50)")
    args = ap.parse_args(argv)
    print("| task | time ms | real roots | linkages | usable | quality |")
    print("|---|---:|---:|---:|---:|---|")
    for name, seconds, roots, linkages, usable, extra in book_rows():
        print(f"| {name} | {seconds * 1e3:.1f} | {roots} | {linkages} | {usable} | {extra} |", flush=True)
    print()
    print("| random tasks | method | median time ms | median real roots | recovered |")
    print("|---|---|---:|---:|---|")
    for method in ("exact", "fast"):
        for name, seconds, roots, hits in random_rows(args.random, method):
            print(f"| {name} | {method} | {seconds * 1e3:.1f} | {roots:g} | {hits} |", flush=True)
    for method in ("exact", "fast"):
        for name, seconds, roots, hits in path_rows(max(1, args.random // 5), method):
            print(f"| {name} | {method} | {seconds * 1e3:.1f} | {roots:g} | {hits} |", flush=True)
    print()
    print("| rising-rate suspension | candidate | verified layouts | best leverage error | seconds per candidate |")
    print("|---|---:|---:|---:|---:|")
    for method, cid, count, best, seconds in candidate_rows():
        print(f"| {method} | {cid} | {count} | {100 * best:.3g}% | {seconds:.2f} |", flush=True)


if __name__ == "__main__":
    main()
