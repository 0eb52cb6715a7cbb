"""Issue 31, item 3: "usable" means checked, for dimensional synthesis (seed 002 §2-3, path generation).

Path tasks with points in line, nearly in line, repeated, nearly repeated, on a circle, with pivots on the
points' line: every linkage called usable is re-evaluated here by an independent method, the four-bar loop
solved by hand with numpy (circle-circle intersection on the assembly mode of the drawn pose), and must
meet every point within the task's tolerance. Degenerate roots (pivots running off to infinity, links of
zero length, links beyond max_link_ratio) are grouped and counted, not listed.
"""

import json
import math

import numpy as np
import pytest
from scipy.optimize import minimize_scalar

from domes.cli import main
from domes.design.synthesis import synthesize, task_from_dict
from domes.errors import InputError


def _coupler(fb, theta):
    """The coupler point of the four-bar ``fb`` at crank angles ``theta`` on the assembly mode of its drawn pose
    (NaN where the loop does not close): circle-circle intersection by hand, then the coupler's rigid motion."""
    a0, a1, b1, b0, p = (np.asarray(v, dtype=float) for v in (fb.a0, fb.a1, fb.b1, fb.b0, fb.point))
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    r, b, c = np.linalg.norm(a1 - a0), np.linalg.norm(b1 - a1), np.linalg.norm(b1 - b0)
    A = a0 + r * np.c_[np.cos(theta), np.sin(theta)]
    d = b0 - A
    L = np.linalg.norm(d, axis=1)
    x = (L * L + b * b - c * c) / (2 * L)
    with np.errstate(invalid="ignore"):
        h = np.sqrt(b * b - x * x)
    u = d / L[:, None]
    n = np.c_[-u[:, 1], u[:, 0]]

    def side(C, Aa):
        e, f = C - Aa, b0 - C
        return np.sign(e[..., 0] * f[..., 1] - e[..., 1] * f[..., 0])

    mode = side(b1, a1)
    C = A + x[:, None] * u + h[:, None] * n
    other = A + x[:, None] * u - h[:, None] * n
    C = np.where((side(C, A) == mode)[:, None], C, other)
    turn = np.arctan2(C[:, 1] - A[:, 1], C[:, 0] - A[:, 0]) - math.atan2(b1[1] - a1[1], b1[0] - a1[0])
    q = p - a1
    return A + np.c_[np.cos(turn) * q[0] - np.sin(turn) * q[1], np.sin(turn) * q[0] + np.cos(turn) * q[1]]


def _to_curve(fb, point) -> float:
    """The distance of ``point`` from the coupler curve (drawn assembly mode): a grid of 20,000 crank angles, then
    Brent's method around the nearest."""
    grid = np.linspace(-math.pi, math.pi, 20001)
    dist = np.linalg.norm(_coupler(fb, grid) - point, axis=1)
    if not np.isfinite(dist).any():
        return math.inf
    k = int(np.nanargmin(dist))
    h = grid[1] - grid[0]
    f = lambda t: float(np.nan_to_num(np.linalg.norm(_coupler(fb, t)[0] - point), nan=1e300))   # noqa: E731
    best = minimize_scalar(f, bounds=(grid[k] - h, grid[k] + h), method="bounded", options={"xatol": 1e-13})
    return min(float(best.fun), float(dist[k]))


def _worst(sol, data) -> float:
    """The worst distance of a solution from the task's points, re-evaluated by hand: at its crank angles (the
    prescribed ones with timing), or from its coupler curve for a least-squares answer."""
    fb, P = sol.fourbar, np.asarray(data["points"], dtype=float)
    if sol.claim is not None and sol.claim.on_curve:
        return max(_to_curve(fb, p) for p in P)
    if "crank_deg" in data:
        first = math.atan2(fb.a1[1] - fb.a0[1], fb.a1[0] - fb.a0[0])
        angles = first + np.radians([0.0] + list(data["crank_deg"]))
    else:
        angles = np.radians(sol.checks.crank_angles_deg)
        assert np.all(np.diff(angles) > 0) or np.all(np.diff(angles) < 0)          # in order, one way
        assert abs(angles[-1] - angles[0]) < 2 * math.pi
    dist = np.linalg.norm(_coupler(fb, angles) - P, axis=1)
    return float(np.max(dist)) if np.all(np.isfinite(dist)) else math.inf


def _frame(rng):
    """A random line: a point, its direction and normal, and a length."""
    u = rng.normal(size=2)
    u /= np.linalg.norm(u)
    return rng.uniform(-2, 2, 2), u, np.array([-u[1], u[0]]), rng.uniform(0.5, 5.0)


def degenerate_tasks(seed: int = 31, count: int = 50):
    """``count`` degenerate path tasks from seeded random numbers, cycling through the kinds; each a task
    dictionary, the random starts of the fast method to give it (fewer for the slow least squares) and, for
    refused ones, the words the refusal must contain."""
    rng = np.random.default_rng(seed)
    scales = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]
    out = []
    for k in range(count):
        kind = k % 12
        c, u, v, L = _frame(rng)
        s = np.sort(rng.uniform(-1, 1, 5)) * L
        eps = scales[k % len(scales)]
        line = c + s[:, None] * u
        near = line + (eps * L * rng.normal(size=5))[:, None] * v
        off = {"a0": (c + rng.uniform(0.3, 2) * L * v + rng.normal() * L * u).tolist(),
               "b0": (c + rng.uniform(-2, 2) * L * v + rng.normal() * L * u).tolist()}
        data, refused, seeds = {"kind": "path", "name": f"degenerate {k} ({kind})"}, None, 16
        if kind == 0:                                     # exactly in line, pivots off it
            data.update(points=line.tolist(), **off)
        elif kind == 1:                                   # nearly in line
            data.update(points=near.tolist(), **off)
        elif kind == 2:                                   # nearly in line, both pivots on the points' line
            data.update(points=near.tolist(), a0=(c + 1.4 * L * u).tolist(), b0=(c - 1.8 * L * u).tolist())
        elif kind == 3:                                   # exactly in line, pivots on it
            data.update(points=line.tolist(), a0=(c + 1.3 * L * u).tolist(), b0=(c - 1.6 * L * u).tolist())
        elif kind in (4, 5):                              # nearly repeated points: within the tolerance or beyond
            P = c + rng.uniform(-L, L, (5, 2))
            j = int(rng.integers(1, 5))
            gap = [1e-8, 1e-7, 1e-5, 1e-3][(k // 12 + kind) % 4]
            step = rng.normal(size=2)
            P[j] = P[j - 1] + gap * float(np.ptp(P, axis=0).max()) * step / np.linalg.norm(step)
            data.update(points=P.tolist(), **off)
            if gap < 1e-6:
                refused = f"points {j} and {j + 1} coincide within the tolerance"
        elif kind == 6:                                   # a point repeated exactly
            P = c + rng.uniform(-L, L, (5, 2))
            j = int(rng.integers(1, 5))
            P[j] = P[j - 1]
            data.update(points=P.tolist(), **off)
            refused = f"points {j} and {j + 1} coincide"
        elif kind == 7:                                   # nearly on a circle, a0 at its centre or not
            t = np.sort(rng.uniform(0, 2 * math.pi, 5))
            rad = L * (1 + eps * rng.normal(size=5))
            data.update(points=(c + np.c_[rad * np.cos(t), rad * np.sin(t)]).tolist(),
                        a0=(c if k % 24 == 7 else c + 0.3 * L * v).tolist(), b0=off["b0"])
        elif kind == 8:                                   # Table 2-1's other free choices, nearly in line
            data.update(points=near.tolist(), a0=off["a0"], given={"b0x": float(c[0] + L), "b1y": float(c[1])})
        elif kind == 9:                                   # prescribed timing, nearly in line
            data.update(points=near.tolist(), crank_deg=np.sort(rng.uniform(5, 300, 4)).tolist())
            seeds = 8
        elif kind == 10:                                  # four points nearly in line
            data.update(points=near[:4].tolist(), given={"a1x": float(c[0])}, **off)
        else:                                             # eight points nearly in line: least squares, loosened
            s8 = np.sort(rng.uniform(-1, 1, 8)) * L
            P = c + s8[:, None] * u + (eps * L * rng.normal(size=8))[:, None] * v
            data.update(points=P.tolist(), a0=off["a0"], given={"b0x": float(c[0] + L)}, tolerance=1e-2)
            seeds = 4
        out.append((data, seeds, refused))
    return out


def test_no_degenerate_path_task_calls_a_linkage_usable_that_misses_its_points():
    # Issue 31, item 3 (acceptance): over 50 degenerate path tasks, no answer called usable has an independently
    # re-evaluated worst distance beyond the task's tolerance; refused tasks name the points.
    checked = tasks = refusals = grouped = 0
    for data, seeds, refused in degenerate_tasks():
        if refused:
            with pytest.raises(InputError, match=refused):
                synthesize(task_from_dict(data), "fast", seeds)
            refusals += 1
            continue
        result = synthesize(task_from_dict(data), "fast", seeds)
        tasks += 1
        P = np.asarray(data["points"], dtype=float)
        size = float(np.ptp(P, axis=0).max())
        bound = data.get("tolerance", 1e-6) * size
        for sol in result.usable:
            worst = _worst(sol, data)
            assert worst <= bound * (1 + 1e-6), (data["name"], worst / size, sol.fourbar)
            assert max(sol.residuals) <= bound                       # what the result reports, the kernel's
            checked += 1
        extent = float(np.ptp(np.vstack([P] + [np.asarray(data[k], float)[None] for k in ("a0", "b0") if k in data]),
                              axis=0).max())
        for s in result.solutions:                                  # links and the coupler's arm to its point
            fb = s.fourbar
            longest = max(fb.lengths + (math.dist(fb.point, fb.a1), math.dist(fb.point, fb.b1)))
            assert longest <= result.max_link_ratio * extent and min(fb.lengths) > 1e-6 * extent
        assert result.roots == len(result.solutions) + sum(g.count for g in result.degenerate) or "least squares" in \
            " ".join(result.notes)
        grouped += sum(g.count for g in result.degenerate)
    assert refusals >= 5 and tasks >= 40 and checked >= 20 and grouped >= 1, (refusals, tasks, checked, grouped)


def test_the_audited_collinear_task_groups_its_runaway_roots(tmp_path, capsys):
    # Issue 31, item 3: five points on one line with both fixed pivots (seed 002 §2-3, Table 2-1's Example 5
    # form) are met in the limit of a translating coupler on endless cranks. Without a limit on the pivots the
    # search found 362 roots, 348 called usable, 347 with cranks up to 4.7e6 times the task's size and 91 of them
    # missing the points by up to 1.2% of it. Now they are one counted group; the listed linkages are checked.
    data = {"kind": "path", "name": "line", "points": [[i, 0] for i in range(5)], "a0": [0, 1], "b0": [3, 1]}
    result = synthesize(task_from_dict(data))
    runaway = [g for g in result.degenerate if g.name == "runaway"]
    assert len(runaway) == 1 and runaway[0].count >= 300
    assert result.roots == len(result.solutions) + sum(g.count for g in result.degenerate)
    assert all(max(s.fourbar.lengths) <= 20 * 4 for s in result.solutions)
    assert "pivots running off to infinity" in runaway[0].text and runaway[0].text in result.notes
    assert any("lie on one line" in n for n in result.notes)
    for sol in result.usable:
        assert _worst(sol, data) <= 1e-6 * 4
    # the runaway roots themselves, listed with the ratio raised: each usable one meets the points within the
    # tolerance (by hand), the others say by how much they miss
    loose = synthesize(task_from_dict({**data, "max_link_ratio": 1e9}))
    assert not any(g.name == "runaway" for g in loose.degenerate) and len(loose.solutions) > 300
    for sol in loose.usable:
        assert _worst(sol, data) <= 1e-6 * 4 * (1 + 1e-6)
    missing = [s for s in loose.solutions if any(d.startswith("misses point") for d in s.defects)]
    assert missing and all("of the task's size 4; tolerance 1e-06" in next(d for d in s.defects
                                                                             if d.startswith("misses")) for s in missing)
    path = tmp_path / "line.json"
    path.write_text(json.dumps(data))
    assert main(["synthesize", str(path), "--max-link-ratio", "20"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert f"{runaway[0].count} degenerate (grouped)" in out[0] and f"# {runaway[0].text}" in out
    assert main(["synthesize", str(path), "--max-link-ratio", "0.5"]) == 2
    assert "--max-link-ratio: the longest link allowed" in capsys.readouterr().err


def test_least_squares_answers_are_usable_only_within_the_tolerance(tmp_path, capsys):
    # Issue 31, item 3: a least-squares answer reports its distances; it is usable only within the task's
    # tolerance (default 1e-6 of the size), which the user may loosen (task entry or --tolerance).
    rng = np.random.default_rng(3)
    P = [[i, 0.02 * math.sin(i) + 1e-3 * rng.normal()] for i in range(8)]
    data = {"kind": "path", "name": "wavy", "points": P, "a0": [1, 2], "given": {"b0x": 5.0}}
    strict = synthesize(task_from_dict(data), "fast", 16)
    assert strict.solutions and not strict.usable
    best = min(max(s.residuals) for s in strict.solutions)
    assert any("no least-squares linkage is within the tolerance 1e-06" in n for n in strict.notes)
    assert all(any(d.startswith("misses point") and "tolerance 1e-06" in d for d in s.defects)
               for s in strict.solutions)
    loose = synthesize(task_from_dict({**data, "tolerance": 2 * best / 7}), "fast", 16)
    assert loose.usable and all(_worst(s, data) <= 2 * best * (1 + 1e-6) for s in loose.usable)
    path = tmp_path / "wavy.json"
    path.write_text(json.dumps(data))
    assert main(["synthesize", str(path), "--method", "fast", "--seeds", "16", "--tolerance", "0.5"]) == 0
    out = capsys.readouterr().out
    assert "1. usable" in out and "kernel: distance of the points from the coupler curve" in out
    assert main(["synthesize", str(path), "--tolerance", "2"]) == 2
    assert "--tolerance: a tolerance relative to the task's size" in capsys.readouterr().err


def test_degenerate_guidance_and_function_roots_are_grouped_or_refused():
    # Guidance through three positions of a body turning about one point with circle points (1, 0) and (0, 1):
    # both centre points are that point, the frame has no length: a zero-link group, not a linkage listed.
    pos = [{"point": [0, 0], "angle_deg": a} for a in (0, 10, 20)]
    result = synthesize(task_from_dict({"kind": "guidance", "positions": pos, "circle_points": [[1, 0], [0, 1]]}))
    assert not result.solutions and [g.name for g in result.degenerate] == ["zero link"]
    assert "link of zero length" in result.notes[-1]
    # Example 2 with a tolerance and link ratio from the task file: every usable linkage's pose error, re-evaluated
    # by the kernel, is within the tolerance; a ratio of 1 groups every linkage longer than the positions' spread
    ex2 = [{"point": [1, 1], "angle_deg": 0}, {"point": [2, 0.5], "angle_deg": 0},
           {"point": [3, 1.5], "angle_deg": 45}, {"point": [2, 2], "angle_deg": 90}]
    result = synthesize(task_from_dict({"kind": "guidance", "positions": ex2, "circle_x": [-1, 0], "tolerance": 1e-9}))
    assert result.usable and all(max(s.residuals) <= 1e-9 * 2 for s in result.usable)
    tight = synthesize(task_from_dict({"kind": "guidance", "positions": ex2, "circle_x": [-1, 0],
                                       "max_link_ratio": 1}))
    assert len(tight.solutions) + sum(g.count for g in tight.degenerate) == len(result.solutions)
    assert any(g.name == "long links" for g in tight.degenerate)
    # a function generator's rocker pin, moved by the kernel, lands where the wanted rotation puts it
    gen = synthesize(task_from_dict({"kind": "function", "function": "x**2", "range": [0, 1], "input_deg": 90,
                                     "output_deg": 90, "points": 5}))
    assert gen.usable and all(max(s.residuals) <= 1e-6 for s in gen.usable)
    assert all(max(s.residuals) > 1e-6 for s in gen.solutions if not s.usable and any(
        d.startswith("misses") for d in s.defects))
