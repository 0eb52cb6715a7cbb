"""Gear and cam pairs driven by linkages, on arrays (issue 26): the kernel against the scalar path.

Independent checks: the scalar continuation (:func:`~domes.motion.planar.sweep._scalar_sweep`, each step
solved by :meth:`~domes.motion.planar.query.Kinematics.at` from the loop equations) for positions,
velocities and accelerations (1e-10 of each column's size); the cam law's closed form with the chain rule
(``L(φ + Δθ) − L(φ)``, ``L'·θ̇``, ``L''·θ̇² + L'·θ̈``, ``θ`` the cam's turn read from the sweep); Willis'
formula for a gear on a rocker and on a full-turning link (ratio 1.5, three turns of the pinion).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.model.cams import CamPair
from domes.model.gears import GearPair
from domes.model.laws import Motion
from domes.model.mechanism import Input, Joint, Mechanism
from domes.motion.planar.batch import batch
from domes.motion.planar.continuation import Continuation, grid
from domes.motion.planar.examples import four_bar
from domes.motion.planar.kernel import Program, blocked, vectorizable
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import _scalar_sweep, run_sweep

TOL = 1e-10
LAW = Motion.cam([("cycloidal", 120, math.radians(15)), ("dwell", 60), ("3-4-5", 120, -math.radians(15)),
                  ("dwell", 60)])


def sector() -> Mechanism:
    """A gear on the four-bar's rocker drives a pinion of half its radius (Willis: ω_pinion = −2·ω_rocker)."""
    fb = four_bar()
    return Mechanism.build("sector", list(fb.links) + ["pinion"], "frame",
                           list(fb.joints) + [Joint("E", "R", ("frame", "pinion"), (3.0, -1.5))], list(fb.inputs),
                           gears=[GearPair("M", ("rocker", "pinion"), (3.0, -1.0))])


def cam_on_rocker() -> Mechanism:
    """The four-bar's rocker is a cam; an arm pivoted on the frame follows it (oscillating), a rod and a lever
    after the arm: a cam turned by a linkage, and a linkage after the cam."""
    fb = four_bar(2.0)
    joints = list(fb.joints) + [Joint("F", "R", ("frame", "arm"), (5.0, 1.0)),
                                Joint("G", "R", ("arm", "rod"), (5.0, 2.5)),
                                Joint("H", "R", ("rod", "lever"), (7.0, 3.0)),
                                Joint("K", "R", ("lever", "frame"), (7.5, 1.0))]
    return Mechanism.build("cam on a rocker", list(fb.links) + ["arm", "rod", "lever"], "frame", joints,
                           [Input("A", 2.0, 0.5)], cams=[CamPair("K1", ("rocker", "arm"), (4.0, 1.0), LAW, 0.7)])


def drag_link() -> Mechanism:
    """A double crank (frame 1, cranks 3, coupler 3.5) whose follower crank carries a gear of ratio 1.5."""
    b = (0.0, 3.0)
    d = (1.0, 0.0)
    dist = math.dist(b, d)
    a = (3.5 ** 2 - 3.0 ** 2 + dist ** 2) / (2 * dist)
    h = math.sqrt(3.5 ** 2 - a ** 2)
    ux, uy = (d[0] - b[0]) / dist, (d[1] - b[1]) / dist
    c = (b[0] + a * ux - h * uy, b[1] + a * uy + h * ux)
    return Mechanism.build("drag link", ["frame", "crank", "coupler", "follower", "pinion"], "frame",
                           [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), b),
                            Joint("C", "R", ("coupler", "follower"), c), Joint("D", "R", ("follower", "frame"), d),
                            Joint("E", "R", ("frame", "pinion"), (3.0, 0.0))],
                           [Input("A", 3.0, -1.0)], gears=[GearPair("M", ("follower", "pinion"), (2.2, 0.0))])


def example(name: str) -> Mechanism:
    return load_mechanism(f"examples/mechanisms/{name}.json")


CASES = {
    "sector gear on a rocker": (sector, ["driver", "RRR", "geared"]),
    "cam-rocker.json": (lambda: example("cam-rocker"), ["driver", "cammed", "RRR"]),
    "cam on a rocker": (cam_on_rocker, ["driver", "RRR", "cammed", "RRR"]),
    "five-bar-cam.json": (lambda: example("five-bar-cam"), ["driver", "driver", "RRR"]),
    "geared-five-bar.json": (lambda: example("geared-five-bar"), ["driver", "geared", "RRR"]),
    "planetary.json": (lambda: example("planetary"), ["driver", "geared"]),
    "drag link with a gear": (drag_link, ["driver", "RRR", "geared"]),
}


def _close(got, want, col):
    scale = max(1.0, float(np.max(np.abs(want))))
    assert np.all(np.isfinite(got)), col
    assert np.max(np.abs(got - want)) <= TOL * scale, (col, float(np.max(np.abs(got - want))))


@pytest.mark.parametrize("name", list(CASES))
def test_kernel_and_vector_sweep_equal_the_scalar_path(name):
    make, kinds = CASES[name]
    m = make()
    kin = Kinematics(m, None, 2)
    assert [g.kind for g in kin.structure.groups] == kinds and vectorizable(kin) and not blocked(kin)
    qs = np.asarray(grid(0.0, 4 * math.pi if name.startswith("drag") else 2 * math.pi, math.radians(4)))
    slow = _scalar_sweep(kin, Continuation(kin), qs, None)
    fast = run_sweep(kin, qs[0], qs[-1], math.radians(4))
    assert slow.success and fast.success and fast.columns == slow.columns and fast.inputs.size == qs.size
    prog = Program(kin)
    geom = prog.geometry()
    pose = prog.poses(geom, qs)
    assert not np.any(pose.failed)
    kernel = prog.outputs(geom, pose, prog.motion(geom, pose, 2))
    for col in slow.columns:
        _close(fast.column(col), slow.column(col), col)
        if col.startswith("angle:") and not col.endswith("'"):  # the kernel's angles are continuous, to a turn
            _close(np.remainder(kernel[col] - slow.column(col) + math.pi, 2 * math.pi) - math.pi, 0.0, col)
        else:
            _close(kernel[col], slow.column(col), col)
    assert fast.max_residual <= 1e-13


def test_gears_on_linkages_obey_willis():
    for make, gear, pinion, ratio in ((sector, "rocker", "pinion", -2.0), (drag_link, "follower", "pinion", -1.5)):
        m = make()
        outs = [f"angle:{gear}", f"angle:{pinion}"]
        sw = run_sweep(Kinematics(m, outs, 2), 0.0, 4 * math.pi, math.radians(2))
        t = sw.table
        for k in ("", "'", "''"):
            x, y = t[f"angle:{pinion}" + k], t[f"angle:{gear}" + k]
            if not k:
                x, y = x - x[0], y - y[0]
            _close(x, ratio * y, k)
    turned = sw.table["angle:pinion"][-1] - sw.table["angle:pinion"][0]   # two turns of the drag link's follower
    assert turned == pytest.approx(-1.5 * 4 * math.pi, abs=1e-9)


def test_translating_follower_follows_its_law_on_arrays():
    m = example("cam-rocker")
    law = m.cams[0].law
    speed = m.inputs[0].speed
    kin = Kinematics(m, ["slide:S", "angle:rocker"], 2)
    qs = np.linspace(0.0, 2 * math.pi, 721)
    prog = Program(kin)
    geom = prog.geometry()
    pose = prog.poses(geom, qs)
    out = prog.outputs(geom, pose, prog.motion(geom, pose, 2))
    s, d1, d2 = law.evaluate(qs)
    _close(out["slide:S"], geom.s0["S"] + s - law.evaluate(0.0, 0)[0], "slide")
    _close(out["slide:S'"], speed * d1, "rate")
    _close(out["slide:S''"], speed ** 2 * d2, "acceleration")


def test_oscillating_follower_on_a_rocking_cam_follows_the_law():
    """The arm turns by ``L(φ + Δ) − L(φ)``, ``Δ`` the rocker's (the cam's) turn: the chain rule on the sweep's
    own rocker angle, rate and acceleration."""
    m = cam_on_rocker()
    sw = run_sweep(Kinematics(m, ["angle:rocker", "angle:arm"], 2), 0.0, 2 * math.pi, math.radians(1))
    t = sw.table
    turn = t["angle:rocker"] - m.reference_angle("rocker")
    s, d1, d2 = LAW.evaluate(0.7 + turn)
    w, a = t["angle:rocker'"], t["angle:rocker''"]
    _close(t["angle:arm"] - m.reference_angle("arm"), s - LAW.evaluate(0.7, 0)[0], "angle")
    _close(t["angle:arm'"], d1 * w, "rate")
    _close(t["angle:arm''"], d2 * w * w + d1 * a, "acceleration")
    assert np.ptp(t["angle:arm"]) > math.radians(1)     # the rocker's swing reaches the law's rise


def test_cam_batches_take_other_coordinates_and_gear_batches_do_not():
    """A cam's law does not depend on the drawing: a batch of moved rockers equals each mechanism built alone."""
    m = example("cam-rocker")
    qs = np.radians(np.arange(0.0, 360.0, 15.0))
    moved = np.array([[3.5, 1.0], [3.6, 0.9], [3.4, 1.2]])
    b = batch(m, {"F": moved}, qs, outputs=["angle:rocker", "slide:S"], order=2)
    assert list(b.kinds) == ["complete"] * 3
    for k, f in enumerate(moved):
        joints = [Joint("F", "R", ("rocker", "frame"), tuple(f)) if j.name == "F" else j for j in m.joints]
        one = batch(Mechanism.build(m.name, list(m.links), "frame", joints, list(m.inputs), cams=list(m.cams)),
                    inputs=qs, outputs=["angle:rocker", "slide:S"], order=2)
        for col, values in b.values.items():
            _close(values[k], one.values[col][0], col)
    with pytest.raises(InputError, match="pitch points"):
        batch(sector(), {"E": np.array([[3.0, -1.5], [3.0, -1.6]])}, qs, outputs=["angle:pinion"])


def test_groups_the_kernel_cannot_evaluate_are_named():
    kin = Kinematics(sector(), ["angle:pinion"], 1, method="newton")
    assert not vectorizable(kin) and blocked(kin) == [kin.groups[0].label]
    with pytest.raises(InputError, match=r"groups \['4-link group \{crank, coupler, rocker, pinion\}'\] are solved "
                                         r"step by step"):
        Program(kin)
