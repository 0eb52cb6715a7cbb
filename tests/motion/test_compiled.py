"""The kernel's compiled route (numba) against its numpy route (issue 28, item 2).

Both routes evaluate the same closed forms; the compiled one in one loop per configuration. They agree to
rounding: 1e-14 of the size where the dyads are well away from a limit. Nearer a limit an RRR dyad's position
moves by the rounding of its discriminant over the root (``ε·size/root``, the sine of the transmission angle
there), so the comparison allows ``1e-15·size/root`` too; statuses, NaN patterns and extremes' indices agree
exactly. Sweeps and batches are run whole in both routes (``DOMES_KERNEL``, ``route=``).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from kinematics_cases import example
from test_dyads import _dyad_mechanisms

from domes.errors import InputError, NumericalError
from domes.motion import CouplerPoint, Input, Joint, Kinematics, Mechanism
from domes.motion.planar import compiled, onepass
from domes.motion.planar.batch import ExtremesSink, batch
from domes.motion.planar.continuation import Continuation, grid, grid_points
from domes.motion.planar.examples import parallelogram, triple_rocker
from domes.motion.planar.kernel import Program
from domes.motion.planar.sweep import run_sweep, sweep

numba = pytest.importorskip("numba")

TEMPLATE = Mechanism.build("fb", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
                            Joint("C", "R", ("coupler", "rocker"), (3.5, math.sqrt(6.0))),
                            Joint("D", "R", ("rocker", "f"), (3.0, 0.0))],
                           [Input("A", 2.0, 0.5)], points=[CouplerPoint("P", "coupler", (2.0, 2.0))])


def _mechanisms():
    out = {name: example(name) for name in ("four-bar.json", "watt-six-bar.json", "stephenson-six-bar.json",
                                            "slider-crank.json", "inverted-slider.json")}
    out.update(_dyad_mechanisms())
    return out


def _close(a, b, scale, root=None, what=""):
    """``a`` and ``b`` are NaN at the same places and elsewhere within 1e-14 of ``scale`` (and 1e-15 of it over
    ``root``)."""
    a, b = np.broadcast_arrays(np.asarray(a), np.asarray(b))
    assert np.array_equal(np.isnan(a), np.isnan(b)), what
    allowed = 1e-14 * scale
    if root is not None:  # near a limit or a dead point: the rounding over the root
        allowed = np.maximum(allowed, 1e-15 * scale / np.maximum(np.asarray(root), 1e-300))
    gap = np.abs(np.where(np.isnan(a), 0, a - b))
    assert np.all(gap <= allowed), (what, float(np.max(gap / allowed)))


def _conditioning(prog, geom, pose):
    """Each configuration's smallest dyad root (RRR, RPR, RRP) or sine between slides (PRP, RPP), at most 1: the
    rounding of a position grows as its inverse."""
    worst = np.ones(np.shape(next(iter(pose.unassembled.values()))))
    for r in pose.root.values():
        worst = np.minimum(worst, r)
    for kind, g, *rest in prog.steps:
        if kind == "dyad" and rest[0].kind in ("PRP", "RPP"):
            plan, ka, kc = rest
            first, second = (plan.a, plan.c) if plan.kind == "PRP" else (plan.b, plan.c)
            u1 = pose.links[ka if plan.kind == "PRP" else kc][0] * geom.direction[first.name]
            u2 = pose.links[kc][0] * geom.direction[second.name]
            worst = np.minimum(worst, np.abs(u1.real * u2.imag - u1.imag * u2.real))
    return worst


def test_route_is_chosen_by_name_and_environment(monkeypatch):
    assert not compiled.choose(10 ** 9, "numpy")
    assert compiled.choose(1, "numba")
    monkeypatch.setenv(compiled.VARIABLE, "numpy")
    assert compiled.route() == "numpy" and not compiled.choose(10 ** 9)
    monkeypatch.setenv(compiled.VARIABLE, "fast")
    with pytest.raises(InputError, match="DOMES_KERNEL='fast'.*auto, numpy, numba"):
        compiled.route()


def test_poses_equal_numpy_on_every_dyad_kind():
    for name, m in _mechanisms().items():
        kin = Kinematics(m, None, 0)
        slow, fast = Program(kin, "numpy"), Program(kin, "numba")
        geom = slow.geometry()
        q0 = kin.drawn_inputs()[m.inputs[0].joint]
        qs = q0 + np.linspace(-1.0, 1.0, 201) if m.joint(m.inputs[0].joint).kind == "P" else \
            q0 + np.linspace(0.0, 2 * math.pi, 361)
        a, b = slow.poses(geom, qs), fast.poses(geom, qs)
        root = _conditioning(slow, geom, a)
        assert set(a.links) == set(b.links) and set(a.slides) == set(b.slides) and set(a.root) == set(b.root), name
        for link in a.links:
            for x, y in zip(a.links[link][:2], b.links[link][:2]):
                _close(x, y, m.size, root, what=(name, link))
        for j in a.slides:
            _close(a.slides[j], b.slides[j], m.size, root, what=(name, j))
        for i in a.unassembled:
            assert np.array_equal(np.broadcast_to(a.unassembled[i], qs.shape), b.unassembled[i]), (name, i)
            assert np.array_equal(np.broadcast_to(a.undetermined[i], qs.shape), b.undetermined[i]), (name, i)
            _close(a.closure[i], b.closure[i], m.size, what=(name, "closure"))
        for i in a.root:
            _close(a.root[i], b.root[i], 1.0, root, what=(name, "root"))
            _close(a.margin[i], b.margin[i], m.size, root, what=(name, "margin"))


@pytest.mark.parametrize("order", [0, 1, 2])
def test_sweeps_equal_numpy(monkeypatch, order):
    # the benchmark's mechanisms, and a four-bar that meets a limit (seed 000 T6's crank-rocker made a triple rocker)
    stuck = Mechanism.build("tr", ["f", "crank", "coupler", "rocker"], "f",
                            [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.6, 0.0)),
                             Joint("C", "R", ("coupler", "rocker"), (3.0, 1.5)),
                             Joint("D", "R", ("rocker", "f"), (3.0, 0.0))], [Input("A", 2.0, 0.5)])
    cases = [example(n) for n in ("four-bar.json", "watt-six-bar.json", "stephenson-six-bar.json")] + [stuck]
    for m in cases:
        q0 = Kinematics(m).drawn_inputs()[m.inputs[0].joint]
        runs = []
        for route in ("numpy", "numba"):
            monkeypatch.setenv(compiled.VARIABLE, route)
            runs.append(sweep(m, q0, q0 + 2 * math.pi, 2 * math.pi / 720, order=order))
        a, b = runs
        assert a.status == b.status and a.inputs.size == b.inputs.size, m.name
        assert [(d.kind, d.group) for d in a.dead_points] == [(d.kind, d.group) for d in b.dead_points], m.name
        for d, e in zip(a.dead_points, b.dead_points):
            assert abs(d.input - e.input) <= d.within + e.within, m.name
        for c in a.columns:
            k = len(c) - len(c.rstrip("'"))
            scale = (1.0 if c.startswith("angle") else m.size) * abs(m.inputs[0].speed) ** k
            # to 1e-14 of the scale and the value, times the condition number per derivative (near the limit)
            _close(a.column(c), b.column(c), (scale + np.abs(a.column(c))) * a.conditions ** k, what=(m.name, c))
        assert np.allclose(a.conditions, b.conditions, rtol=1e-12, atol=0), m.name
        assert np.all(np.abs(a.residuals - b.residuals) <= 1e-15), m.name


def _four_bars(count, seed):
    rng = np.random.default_rng(seed)
    c = {"B": np.c_[rng.uniform(0.5, 1.5, count), rng.uniform(-0.4, 0.4, count)],
         "C": np.c_[rng.uniform(2.5, 4.0, count), rng.uniform(1.5, 3.0, count)],
         "D": np.c_[rng.uniform(2.5, 3.5, count), np.zeros(count)],
         "P": np.c_[rng.uniform(0.0, 4.0, count), rng.uniform(0.0, 4.0, count)]}
    c["B"][-2:, 1] = 0.0  # the last two drawn on a dead point (B, D, C collinear): ambiguous
    c["C"][-2:] = c["D"][-2:] + [0.7, 0.0]
    return c


@pytest.mark.parametrize("outputs", [["point:P"], ["point:P", "angle:rocker"]])
def test_batches_equal_numpy(outputs):
    coords = _four_bars(400, 7)
    qs = np.radians(np.arange(0.0, 360.0, 2.0))
    a = batch(TEMPLATE, coords, qs, outputs=outputs, route="numpy")
    b = batch(TEMPLATE, coords, qs, outputs=outputs, route="numba")
    assert set(a.kinds) >= {"complete", "limit", "ambiguous"}
    assert np.array_equal(a.kinds, b.kinds) and np.array_equal(a.assembled, b.assembled)
    prog = Program(Kinematics(TEMPLATE, outputs), "numpy")
    root = next(iter(prog.poses(prog.geometry(coords), qs[None, :]).root.values()))
    for c in a.values:  # each four-bar is at least 3 long
        _close(a.values[c], b.values[c], 1.0 if c.startswith("angle") else 3.0, root, what=c)
    _close(a.transmission, b.transmission, 1.0, np.nan_to_num(a.transmission, nan=1.0), what="transmission")
    assert np.all(np.abs(a.residual - b.residual) <= 1e-15)
    ex = batch(TEMPLATE, coords, qs, outputs=outputs, route="numba", sink=ExtremesSink()).result
    for c in b.values:  # the compiled reduction: numpy's nanmin / nanargmin ... of the same values, exactly
        some = ~np.isnan(b.values[c]).all(axis=1)
        assert np.array_equal(ex.minimum[c][some], np.nanmin(b.values[c][some], axis=1))
        assert np.array_equal(ex.maximum[c][some], np.nanmax(b.values[c][some], axis=1))
        assert np.array_equal(ex.argmin[c][some], np.nanargmin(b.values[c][some], axis=1))
        assert np.array_equal(ex.argmax[c][some], np.nanargmax(b.values[c][some], axis=1))
        assert np.all(ex.argmin[c][~some] == -1) and np.all(np.isnan(ex.minimum[c][~some]))


def _taken(kin, start, stop, step):
    """Whether the sweep goes by the one compiled pass (``onepass``), not handed to the numpy walk."""
    cont = Continuation(kin)
    return onepass.sweep(kin, cont, grid_points(start, stop, step)) is not None


def _same_sweeps(a, b, m, what, near=False):
    """The two routes' sweeps: the same steps, columns and dead points; numbers within 1e-14 of their scale (times
    the condition number per derivative; once more for every column ``near`` a singular point, where the pose
    itself is known only to ``cond·ε``)."""
    assert a.status == b.status and np.array_equal(a.inputs, b.inputs) and a.reachable == b.reachable, what
    assert a.columns == b.columns and set(a.states) == set(b.states), what
    assert [(d.kind, d.group) for d in a.dead_points] == [(d.kind, d.group) for d in b.dead_points], what
    for d, e in zip(a.dead_points, b.dead_points):
        assert abs(d.input - e.input) <= d.within + e.within, what
    speed, extra = abs(m.inputs[0].speed), 1 if near else 0
    for c in a.columns:
        k = len(c) - len(c.rstrip("'"))
        scale = (1.0 if c.startswith("angle") else m.size) * speed ** k
        _close(a.column(c), b.column(c), (scale + np.abs(a.column(c))) * a.conditions ** (k + extra), what=(what, c))
    for v in a.states:
        scale = 1.0 if v.startswith("rot:") or (v.startswith("q:") and m.joint(v[2:]).kind == "R") else m.size
        _close(a.states[v], b.states[v], (scale + np.abs(a.states[v])) * a.conditions ** extra, what=(what, v))
    assert np.allclose(a.conditions, b.conditions, rtol=1e-12 * (1e3 if near else 1), atol=0) and \
        np.all(np.abs(a.residuals - b.residuals) <= 1e-15), what


def _both(monkeypatch, m, start, stop, step, outputs=None, order=2):
    """The sweep by each route (or the error each raises)."""
    runs = []
    for route in ("numpy", "numba"):
        monkeypatch.setenv(compiled.VARIABLE, route)
        try:
            runs.append(run_sweep(Kinematics(m, outputs, order), start, stop, step))
        except NumericalError as exc:
            runs.append(str(exc))
    return runs


def test_one_pass_equals_numpy_on_every_dyad_kind(monkeypatch):
    # every mechanism of drivers and dyads above, all outputs and rates, a full turn (or ±1 of a slide) from the
    # drawn pose; the benchmark's mechanisms also from away from the drawn pose, backwards, by steps longer than the
    # resolution (the walk there, the steps between)
    # (the PRP's slider jumps before 90°, where the numpy walk takes seconds to locate the discontinuity: 54°)
    cases = [(name, m, 0.0, 0.15 if name == "PRP" else 1.0, 1 / 90) for name, m in _mechanisms().items()]
    cases += [(name, example(name), 0.3, -0.1, 1 / 37) for name in ("four-bar.json", "watt-six-bar.json",
                                                                     "stephenson-six-bar.json")]
    taken = compared = 0
    for name, m, lo, hi, step in cases:
        q0 = Kinematics(m).drawn_inputs()[m.inputs[0].joint]
        span = 1.0 if m.joint(m.inputs[0].joint).kind == "P" else 2 * math.pi
        a, b = _both(monkeypatch, m, q0 + lo * span, q0 + hi * span, step * span)
        if isinstance(a, str) or isinstance(b, str):
            assert a == b, name
            continue
        _same_sweeps(a, b, m, name)
        compared += 1
        taken += _taken(Kinematics(m, None, 2), q0 + lo * span, q0 + hi * span, step * span)
    assert taken == compared >= 10  # every kind of dyad, and the walk from away from the drawn pose, in one pass
    for name in ("four-bar.json", "watt-six-bar.json", "stephenson-six-bar.json"):  # nothing there to decide
        m = example(name)
        q0 = Kinematics(m).drawn_inputs()[m.inputs[0].joint]
        assert _taken(Kinematics(m, None, 2), q0, q0 + 2 * math.pi, math.pi / 180), name


def test_one_query_swept_again_keeps_its_walk_apart(monkeypatch):
    # one query swept over a grid, another grid, then the first again: the walk's points kept on the query are the
    # grid's own, and a sweep's inputs are its own (writing one does not move the next)
    m = example("four-bar.json")
    q0 = Kinematics(m).drawn_inputs()[m.inputs[0].joint]
    monkeypatch.setenv(compiled.VARIABLE, "numba")
    kin = Kinematics(m, None, 2)
    first = run_sweep(kin, q0, q0 + 1.0, 1 / 50)
    first.inputs[:] = np.nan
    other = run_sweep(kin, q0 - 0.5, q0 + 0.5, 1 / 40)
    again = run_sweep(kin, q0, q0 + 1.0, 1 / 50)
    for got, (lo, hi, step) in ((other, (-0.5, 0.5, 1 / 40)), (again, (0.0, 1.0, 1 / 50))):
        monkeypatch.setenv(compiled.VARIABLE, "numpy")
        _same_sweeps(got, run_sweep(Kinematics(m, None, 2), q0 + lo, q0 + hi, step), m, (lo, hi))
        monkeypatch.setenv(compiled.VARIABLE, "numba")


def test_decisions_are_left_to_the_numpy_walk(monkeypatch):
    # a limit (the triple rocker) and branch points (the parallelogram's, twice a turn): the one pass declines,
    # and the compiled route reports them as the numpy route does
    for m, start, stop in ((triple_rocker(), 0.0, math.radians(130)), (parallelogram(), 1.0, 1.0 + 2 * math.pi)):
        assert not _taken(Kinematics(m, ["angle:rocker"], 1), start, stop, math.radians(1)), m.name
        a, b = _both(monkeypatch, m, start, stop, math.radians(1), ["angle:rocker"], 1)
        assert b.dead_points, m.name
        _same_sweeps(a, b, m, m.name, near=True)


def test_angle_is_numpys_to_two_units_in_the_last_place():
    rng = np.random.default_rng(3)
    z = rng.normal(size=20_000) * np.exp(rng.uniform(-3, 3, 20_000)) + 1j * rng.normal(size=20_000)
    z = np.concatenate((z, [1, -1, 1j, -1j, complex(-1, 0.0), complex(-1, -0.0), complex(-2, 1e-300), 0j]))
    onepass._passer()
    got = np.array([onepass._angle(w) for w in z])
    want = np.angle(z)
    assert np.all(np.abs(got - want) <= 2 * np.spacing(np.abs(want) + np.pi / 4))


def test_small_turns_are_numpys_to_an_ulp_or_two():
    # the series the one-pass sweep uses within NEAR of an anchor: atan of a small tangent, e^{id} of a small angle
    t = np.concatenate((np.linspace(-onepass.NEAR, onepass.NEAR, 4001), [0.0, 1e-300, -1e-12, 3e-9]))
    onepass._passer()
    got = np.array([onepass._small_atan(x) for x in t])
    assert np.all(np.abs(got - np.arctan(t)) <= 2 * np.spacing(np.abs(np.arctan(t))))
    turn = np.array([onepass._small_turn(x) for x in t])
    assert np.all(np.abs(turn.real - np.cos(t)) <= 2 * np.spacing(1.0))
    assert np.all(np.abs(turn.imag - np.sin(t)) <= 2 * np.spacing(np.abs(np.sin(t))))


def test_grid_points_are_the_grid():
    for start, stop, step in ((0.0, 1.0, 0.25), (0.3, -2.0, 0.07), (1.0, 1.0, 0.5), (0.0, 2 * math.pi, math.pi / 1800)):
        assert grid_points(start, stop, step).tolist() == grid(start, stop, step)
