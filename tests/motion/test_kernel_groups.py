"""Class-III and class-IV groups on arrays (issue 28): the kernel's Newton on arrays equals the step-by-step Newton
route (positions, velocities, accelerations to 1e-12 of the size), finds the limits and branch points at the same
inputs, refuses the same derivatives, and follows the branch whose velocities are continuous."""

import dataclasses
import math

import numpy as np
import pytest
from kinematics_cases import example

from domes.errors import InputError
from domes.model.mechanism import Input, Joint, Mechanism
from domes.motion import Kinematics, batch
from domes.motion.planar.continuation import Continuation
from domes.motion.planar.examples import four_bar, stephenson_iii
from domes.motion.planar.kernel import Program, blocked, iterated, vectorizable
from domes.motion.planar.query import error_bounds
from domes.motion.planar.sweep import _scalar_sweep, grid, run_sweep


def _stephenson_at_f():
    """The Stephenson six-bar example driven at F: its four other moving links form a triad that meets limits."""
    m = example("stephenson-six-bar.json")
    return dataclasses.replace(m, name="Stephenson six-bar driven at F", inputs=(Input("F", 360.0),))


def _parallelogram_triad():
    """A triad whose links 1 and 2 and coupler form a parallelogram with the frame: it folds (a branch point) when
    link1 lies along the frame, at crank angles 180° and 360°; link3 translates (at 60°)."""
    h = 3 * math.sin(math.pi / 3)
    return Mechanism.build("parallelogram triad", ["frame", "crank", "coupler", "link1", "link2", "link3"], "frame",
                           [Joint("O", "R", ("frame", "crank"), (3.0, 0.5 + h)),
                            Joint("Q", "R", ("crank", "link3"), (3.0, 2.5 + h)),
                            Joint("B3", "R", ("link3", "coupler"), (1.5, 2.5)),
                            Joint("B1", "R", ("coupler", "link1"), (0.0, 2.0)),
                            Joint("P1", "R", ("link1", "frame"), (0.0, 0.0)),
                            Joint("B2", "R", ("coupler", "link2"), (3.0, 2.0)),
                            Joint("P2", "R", ("link2", "frame"), (3.0, 0.0))],
                           [Input("O", 1.0)])


def _both(mech, span, step, order=2, outputs=None):
    """The sweep on arrays and the step-by-step sweep over the same grid, from the drawn pose."""
    kin = Kinematics(mech, outputs, order)
    cont = Continuation(kin)
    a = run_sweep(kin, cont.q0, cont.q0 + span, step)
    b = _scalar_sweep(kin, cont, grid(cont.q0, cont.q0 + span, step), None)
    return kin, a, b


def _scale(mech, column):
    k = len(column) - len(column.rstrip("'"))
    speed = abs(mech.inputs[0].speed) ** k
    return speed if column.startswith("angle") else mech.size * speed


def _assert_equal(mech, a, b, upto=None, bound=False):
    """Tables equal to 1e-12 of the size (plus, with ``bound``, the condition number's error bound), NaN alike."""
    n = b.inputs.size if upto is None else upto
    assert np.array_equal(a.inputs[:n], b.inputs[:n])
    for col in b.table:
        x, y = a.table[col][:n], b.table[col][:n]
        assert np.array_equal(np.isnan(x), np.isnan(y)), col
        k = len(col) - len(col.rstrip("'"))
        tol = 1e-12 * _scale(mech, col) * np.ones(n)
        if bound and k:
            tol = tol + 10 * error_bounds(b.conditions[:n], 2)[k] * np.abs(y)
        ok = np.isnan(y) | (np.abs(x - y) <= tol)
        assert ok.all(), (col, float(np.nanmax(np.abs(x - y))))
    assert np.max(a.residuals[:n]) <= 1e-14


def test_the_groups_the_kernel_takes_on_arrays():
    kin = Kinematics(stephenson_iii(), None, 2)
    label = "class-III group {coupler, link1, link2, link3}"
    assert [g.kind for g in kin.groups] == ["driver", "class-III"]
    assert iterated(kin) == [label] and blocked(kin) == [] and not vectorizable(kin)
    eight = Kinematics(example("eight-bar-class-iv.json"))
    assert iterated(eight) == ["class-IV group {Z, W, T, V}"] and not blocked(eight)
    assert iterated(Kinematics(example("swing-arm-shock.json"))) == ["3-link group {swing, cylinder, piston}"]
    whole = Kinematics(four_bar(), method="newton")  # the whole loop-closure model stays the reference route
    assert blocked(whole) == ["3-link group {crank, coupler, rocker}"] and iterated(whole) == []


@pytest.mark.parametrize("name", ["stephenson-iii", "eight-bar-class-iv.json", "swing-arm-shock.json"])
def test_full_sweep_equals_the_step_by_step_newton_route(name):
    m = stephenson_iii() if name == "stephenson-iii" else example(name)
    angular = m.joint(m.inputs[0].joint).kind == "R"
    span, step = (2 * math.pi, math.radians(1.0)) if angular else (-1.0, 1.0 / 360)
    _, a, b = _both(m, span, step)
    assert str(a.status) == str(b.status) == "complete" and not a.dead_points and not b.dead_points
    _assert_equal(m, a, b)
    assert np.allclose(a.conditions, b.conditions, rtol=1e-6, atol=0)


def test_limits_and_refused_derivatives_at_the_same_inputs():
    # Driven at F the Stephenson six-bar's triad meets a limit on each side of its drawn pose.
    m = _stephenson_at_f()
    for span in (1.0, -0.4):
        kin, a, b = _both(m, span, math.radians(0.5))
        assert str(a.status) == str(b.status) == "stopped" and a.inputs.size == b.inputs.size
        (la,), (lb,) = [[d for d in sw.dead_points if d.kind == "limit"] for sw in (a, b)]
        assert abs(la.input - lb.input) <= la.within + lb.within and la.group == lb.group
        _assert_equal(m, a, b, bound=True)  # derivatives refused (NaN) at the same steps


def test_branch_point_found_at_the_same_input_and_passed_on_the_smooth_branch():
    m = _parallelogram_triad()
    _, a, b = _both(m, math.radians(120), math.radians(1.0), order=1, outputs=["angle:link1", "angle:link3"])
    assert str(a.status) == "complete" and a.inputs.size == 121
    (pa,), (pb,) = [[d for d in sw.dead_points if d.kind == "singular"] for sw in (a, b)]
    assert abs(pa.input - math.pi) <= pa.within and abs(pb.input - pa.input) <= pa.within + pb.within
    before = int(np.searchsorted(a.inputs, math.pi - 1e-9))
    _assert_equal(m, a, b, upto=before)
    # Past the fold the arrays keep the parallelogram branch (link1 turns with the crank, link3 translates);
    # step by step, Newton's method from the last step may land on the other branch.
    after = slice(before + 1, None)
    assert np.allclose(a.table["angle:link1'"][after], 1.0, rtol=0, atol=1e-9)
    assert np.allclose(a.table["angle:link3'"][after], 0.0, rtol=0, atol=1e-9)


def test_program_poses_and_motion_equal_the_scalar_backend():
    m = stephenson_iii()
    kin = Kinematics(m, None, 2)
    prog = Program(kin)
    geom = prog.geometry()
    qs = np.radians(np.arange(0.0, 361.0, 15.0))
    pose = prog.poses(geom, qs)
    out = prog.outputs(geom, pose, prog.motion(geom, pose, 2))
    assert not np.any(pose.failed) and np.max(pose.closure[1]) <= 1e-14 * m.size
    cont = Continuation(kin)
    state = dict(kin.structure.drawn)
    for k, q in enumerate(qs):
        state = cont.walk(state, cont.q0 if k == 0 else qs[k - 1], q)
        ref = kin.at({"O": q}, state).values
        for col, value in ref.items():
            got = out[col][k]
            err = abs(math.remainder(got - value, 2 * math.pi)) if col.startswith("angle") and "'" not in col \
                else abs(got - value)
            assert err <= 1e-12 * _scale(m, col), (col, math.degrees(q))


def test_batch_of_one_mechanism_and_refused_batches():
    m = stephenson_iii()
    qs = np.radians(np.arange(0.0, 360.0, 5.0))
    b = batch(m, None, qs, outputs=["point:T"], order=2)
    sw = run_sweep(Kinematics(m, ["point:T"], 2), 0.0, math.radians(355.0), math.radians(5.0))
    assert b.kinds.tolist() == ["complete"]
    for col in sw.table:
        assert np.allclose(b.values[col][0], sw.table[col], rtol=0, atol=1e-12 * _scale(m, col)), col
    with pytest.raises(InputError, match=r"class-III group \{coupler, link1, link2, link3\}.*Newton's method"):
        batch(m, {"B3": np.array([[1.0, 3.8], [1.1, 3.8]])}, qs, outputs=["point:T"])
