"""Issue 27: the path task (``domes synthesize``) and ``domes curves match`` agree on paths a four-bar traces.

Planted four-bars (crank-rockers, double cranks, rocker-cranks driven round
by the link at b0) give twelve points of their own coupler curve; the path
task must return without a traceback, recover the planted curve exactly
(the first answer's coupler curve, re-traced by the kinematics kernel,
through every point to 1e-8 of the size), say what drives each answer, and
put a full-turning crank first when the task asks for one.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from domes.design.synthesis import synthesize, task_from_dict
from domes.design.synthesis.fourbars import FourBar, grashof_class
from domes.design.synthesis.verify import curve_distances
from domes.errors import InputError
from domes.motion.planar.batch import batch

KINDS = ("crank-rocker", "double crank", "rocker-crank")


def _third(A, D, b, c, sign):
    e = D - A
    r = float(np.hypot(*e))
    along = (b * b + r * r - c * c) / (2 * r)
    across = sign * math.sqrt(max(b * b - along * along, 0.0))
    ux, uy = e / r
    return A + np.array([along * ux - across * uy, along * uy + across * ux])


def planted(rng, kind: str, n: int = 12):
    """``n`` points round the closed coupler curve of a random four-bar of ``kind`` (placed at random), with the
    linkage drawn at the first point."""
    while True:
        a, b, c, d = rng.uniform(0.4, 3.0, 4)
        name, _ = grashof_class(a, b, c, d)
        s, l = min(a, b, c, d), max(a, b, c, d)
        off = abs(s + l - (a + b + c + d - s - l)) / l
        if kind in name and off > 0.05 and l < 4 * s:
            break
    a0 = rng.uniform(-1, 1, 2)
    frame = rng.uniform(-math.pi, math.pi)
    b0 = a0 + d * np.array([math.cos(frame), math.sin(frame)])
    u, v = rng.uniform(-1.5, 1.5, 2) * (a + b + c + d) / 4
    sign = rng.choice([-1.0, 1.0])
    turns = rng.uniform(0, 2 * math.pi) + np.linspace(0, 2 * math.pi, n, endpoint=False)
    pts, first = [], None
    for t in turns:
        if kind == "rocker-crank":                       # the link at b0 turns fully
            B = b0 + c * np.array([math.cos(t), math.sin(t)])
            A = _third(B, a0, b, a, sign)
        else:
            A = a0 + a * np.array([math.cos(t), math.sin(t)])
            B = _third(A, b0, b, c, sign)
        ex, ey = (B - A) / b
        pts.append(A + np.array([u * ex - v * ey, u * ey + v * ex]))
        first = first or FourBar(a0, A, B, b0, pts[0])
    return np.array(pts), first


#: Planted cases: each kind twice, a crank-rocker and a double crank among them with a0 given (:func:`_given`).
CASES = 6


def _cases():
    rng = np.random.default_rng(27)
    return [planted(rng, KINDS[k % len(KINDS)]) for k in range(CASES)]


def _given(k: int) -> bool:
    """Whether case ``k`` gives the crank pivot a0: every other crank-rocker and double crank (a rocker-crank's a0
    is its rocker's pivot: driven from there the points lie on both assembly modes, which no path task accepts)."""
    return KINDS[k % len(KINDS)] != "rocker-crank" and k % 2 == 1


def _size(points) -> float:
    return float(np.ptp(points, axis=0).max())


def _run(points, **entries):
    """The path task's result; a traceback fails the test (an InputError would be a refusal, not an answer)."""
    return synthesize(task_from_dict({"kind": "path", "points": np.asarray(points).tolist(), **entries}), "fast", 2)


@pytest.fixture(scope="module")
def answers():
    cases = _cases()
    out = []
    for k, (P, fb) in enumerate(cases):
        entries = {"a0": list(fb.a0)} if _given(k) else {}
        out.append((P, fb, _run(P, **entries)))
    return out


def test_the_path_route_recovers_planted_four_bars_exactly(answers):
    recovered = 0
    for P, fb, result in answers:
        if not result.solutions:                         # no answer: the notes say what was tried
            assert any("random starts" in n for n in result.notes)
            continue
        worst = max(curve_distances(result.solutions[0].fourbar, P)) / _size(P)    # the kernel's re-trace
        recovered += worst <= 1e-8
        if worst <= 1e-8:
            assert result.solutions[0].usable
    # measured with the quick atlas built in memory and 16 random starts: 4 of the 6 (9 of the first 12 of the same
    # stream). The two misses, a double crank with a0 given and a rocker-crank, are beyond the quick atlas's reach;
    # the work is counted (starts and iterations, no clock), so the count does not depend on the machine's load;
    # benchmarks/bench_path_routes.py measures the small atlas and the default 4,096 starts.
    assert recovered >= 4


def test_a0_given_is_kept(answers):
    for k, (P, fb, result) in enumerate(answers):
        if _given(k):
            assert all(math.dist(s.fourbar.a0, fb.a0) == 0.0 for s in result.solutions)


def test_every_answer_says_what_drives_it(answers):
    for P, fb, result in answers:
        for s in result.solutions:
            fb_ = s.fourbar
            assert s.checks.driver.startswith("driven by a crank" if s.checks.crank_rotates else "driven by a rocker")
            sweep = np.radians(np.arange(0.0, 360.0, 0.5))
            drawn = math.atan2(fb_.a1[1] - fb_.a0[1], fb_.a1[0] - fb_.a0[0])
            closed = batch(fb_.mechanism(), inputs=drawn + sweep, outputs=["point:P"]).assembled[0]
            if s.checks.crank_rotates:
                assert closed.all()                      # the kernel turns it a full turn
                assert s.checks.crank_range_deg is None
                continue
            lo, hi = s.checks.crank_range_deg
            assert f"from {lo:.1f}° to {hi:.1f}°" in s.checks.driver
            assert not closed.all()
            inside = np.radians(np.linspace(lo, hi, 50)[1:-1])
            outside = np.radians([lo - 0.5, hi + 0.5])
            ok = batch(fb_.mechanism(), inputs=np.concatenate([inside, outside]), outputs=["point:P"]).assembled[0]
            assert ok[:-2].all() and not ok[-2:].any()  # the range the kernel closes the loop over


def test_a_task_asking_for_a_crank_gets_a_full_turning_crank_first():
    rng = np.random.default_rng(5)
    P, fb = planted(rng, "crank-rocker")
    result = _run(P, driver="crank")
    first = result.solutions[0]
    assert first.usable and first.checks.crank_rotates and not first.warnings
    assert max(curve_distances(first.fourbar, P)) <= 1e-8 * _size(P)
    rocking = [s for s in result.usable if not s.checks.crank_rotates]
    assert all(any(w.startswith("the task asks for a crank") for w in s.warnings) for s in rocking)
    assert list(result.usable).index(first) == 0


def test_the_driver_entry_is_checked():
    with pytest.raises(InputError, match="'driver' must be 'crank'"):
        task_from_dict({"kind": "path", "points": [[0, 0], [1, 0], [1, 1], [0, 1], [0.5, 2]], "a0": [0, 0],
                        "b0": [1, -1], "driver": "motor"})


def test_singular_and_degenerate_paths_return_without_a_traceback():
    # points on a circle round a0 (a family of roots), points nearly in line, a point repeated to 1e-8 by least
    # squares; a point repeated exactly is refused, naming the points
    circle = [[math.cos(t), math.sin(t)] for t in np.linspace(0, 5, 8)]
    line = [[t, 1e-9 * t * t] for t in range(10)]
    twice = [[math.cos(t), math.sin(2 * t)] for t in np.linspace(0, 6, 8)] + [[1.0, 1e-8]]
    for points, entries in ((circle, {"a0": [0, 0]}), (line, {"a0": [0, 1]}), (twice, {"a0": [0.2, 0.1]})):
        result = _run(points, **entries)
        assert result.message and all(s.checks.driver for s in result.solutions)
    with pytest.raises(InputError, match="points 1 and 9 coincide"):
        _run(twice[:-1] + [[1.0, 0.0]])


def test_the_synthesize_entry_answers_three_random_paths_to_1e_9():
    # issue 27's acceptance: three random four-bars (a crank-rocker, a double crank, a rocker-crank), nothing given,
    # each path given to the function `domes synthesize` calls; the first answer's coupler curve, re-traced by the
    # kernel, passes through every point to 1e-9 of the size (measured: 4e-11, 2e-11, 5e-11), and says its route
    rng = np.random.default_rng(2027)
    for kind in KINDS:
        P, _ = planted(rng, kind)
        first = _run(P).solutions[0]
        assert max(curve_distances(first.fourbar, P)) <= 1e-9 * _size(P)
        assert first.usable and first.notes[0].startswith("route: least squares")


def test_a_noisy_path_ends_in_the_worst_point_polish():
    # fourteen points of a crank-rocker's curve, 1% noise, nothing given: no linkage meets them, so the route ends
    # in the worst-point polish of the best least-squares linkage; the kernel's re-trace of the polished linkage
    # has a lower worst point than every least-squares answer (measured: 0.62% against 1.3% of the size)
    rng = np.random.default_rng(3)
    P, _ = planted(rng, "crank-rocker", 14)
    P = P + rng.normal(0, 0.01 * _size(P), P.shape)
    result = _run(P)
    worst = {}
    for s in result.solutions:
        worst.setdefault(s.notes[0], []).append(max(curve_distances(s.fourbar, P)))
    polished = worst.pop("route: least squares, then the worst point polished")
    assert any(n.startswith("worst-point polish of the best least-squares linkage: worst point") for n in result.notes)
    assert min(polished) < min(min(w) for w in worst.values())
