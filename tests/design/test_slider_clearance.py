"""Clearances of prismatic pairs (a slider's block in its guide) in the tolerance analysis (issue 29, item 5).

The model (``domes.design.clearance``): the block shifted by ``u`` and
tilted by ``α = 2w/L`` in a guide ``2c`` wider than it, a corner on a wall
(``|u| + |w| = c``, the contact mode of Flores et al. 2008, "Translational
joints with clearance in rigid multibody systems"), uniform on that square.
Checked here against independent methods: the offset slider-crank's closed
form (seed 002 §7-1's redesign step; the slide ``x = r cos θ + √(l² − (h −
r sin θ)²)`` of a pin at height ``h``, differentiated by hand, the block's
centre placed by rotating its pin by hand), the principle of virtual work
(the guide's normal force and moment from the inverse dynamics under a unit
force along the slide), the moments of the random model, Monte Carlo
against first order (std and worst case within 5%), the combined budget's
sums and the command's report.
"""

import json
import math

import numpy as np
import pytest

from domes.cli import main
from domes.design.clearance import Clearances, budget, compare, monte_carlo
from domes.design.dynamics import inverse_dynamics
from domes.design.forces import _statics
from domes.design.tolerance import Tolerancing, sensitivity
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.model.masses import Load
from domes.model.mechanism import Input, Joint, Mechanism

ANGLES = np.radians(np.arange(0.0, 360.0, 30.0))
SLIDER_CRANK = "examples/mechanisms/slider-crank.json"
R, L, H = 1.0, 3.0, 0.5                       # crank, rod, the pin's line y = H (the file's offset slider-crank)
XC = math.sqrt(L ** 2 - (R - H) ** 2)         # the pin C drawn at crank angle 90°
SLOT = (0.4, -0.2)                            # the block's centre (the slide point) from its pin, along and across
BLOCK = 1.0


def off_centre(slot=SLOT) -> Mechanism:
    """The file's offset slider-crank whose block is centred ``slot`` from its pin: the slide point (and the
    line, y = H + slot[1]) moved, the pin C kept where it is."""
    at = (XC + slot[0], H + slot[1])
    return Mechanism.build(
        "off-centre block", ["frame", "crank", "rod", "slider"], "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)),
         Joint("B", "R", ("crank", "rod"), (0.0, R)),
         Joint("C", "R", ("rod", "slider"), (XC, H)),
         Joint("S", "P", ("frame", "slider"), at, 0.0, (0.0, at[1]))],
        [Input("A")],
    )


def closed_form(theta, u, alpha, slot=SLOT):
    """The block's centre along the line (from x = 0), the block shifted by ``u`` and turned by ``alpha``
    about its centre: the pin's height from the turned slot, the pin's x from the crank and rod, the centre
    from the pin by the turned slot."""
    ca, sa = math.cos(alpha), math.sin(alpha)
    pin_from_centre = (-slot[0] * ca + slot[1] * sa, -slot[0] * sa - slot[1] * ca)
    height = H + slot[1] + u + pin_from_centre[1]
    x_pin = R * np.cos(theta) + np.sqrt(L ** 2 - (height - R * np.sin(theta)) ** 2)
    return x_pin - pin_from_centre[0]


def test_the_slide_gradient_equals_the_offset_slider_cranks_closed_form():
    """Seed 002 §7-1 (redesign: joint clearances): on the in-line pin (block centred on it) the block's shift is
    the slide line's eccentricity: ∂x/∂u = −(h − r sin θ)/√(l² − (h − r sin θ)²), the tilt moves nothing; worst
    case c|∂x/∂u| and σ = c|∂x/∂u|/√3 (u uniform on [−c, c])."""
    tol = Tolerancing(load_mechanism(SLIDER_CRANK), "slide:S", ANGLES, tolerance=0.0)
    cl = Clearances(tol, {"S": 2e-3})
    assert [(c.joint, c.kind, c.carrier, c.block) for c in cl] == [("S", "P", "slider", None)]
    b = budget(cl)
    slope = -(H - R * np.sin(ANGLES)) / np.sqrt(L ** 2 - (H - R * np.sin(ANGLES)) ** 2)
    np.testing.assert_allclose(b.gradient[0, :, 0, 0], slope, atol=1e-8)
    np.testing.assert_allclose(b.gradient[0, :, 0, 1], 0.0, atol=1e-12)
    np.testing.assert_allclose(b.worst[0], 2e-3 * np.abs(slope), atol=1e-12)
    np.testing.assert_allclose(b.std[0], 2e-3 * np.abs(slope) / math.sqrt(3), atol=1e-12)


def test_a_tilted_off_centre_block_is_exact_and_its_gradient_is_the_closed_forms():
    """The block turned about its centre (its pin 0.4 behind and 0.2 above it): the exact model equals the
    closed form at finite shifts and tilts, and first order is the closed form's derivative
    (∂x/∂α = ∂x/∂h · a_t... derived by hand: −a_t ∂x/∂h − a_n, w = αL/2)."""
    tol = Tolerancing(off_centre(), "slide:S", ANGLES, tolerance=0.0)
    cl = Clearances(tol, {"S": 0.01}, blocks={"S": BLOCK})
    states = np.array([[[0.01, 0.0]], [[0.0, 0.01]], [[-0.004, 0.006]], [[0.003, -0.007]]])
    exact = cl.evaluate(states)["slide:S"]
    for row, ((u, w),) in zip(exact, states):
        np.testing.assert_allclose(row, closed_form(ANGLES, u, 2 * w / BLOCK), atol=1e-12)
    dxdh = -(H - R * np.sin(ANGLES)) / np.sqrt(L ** 2 - (H - R * np.sin(ANGLES)) ** 2)
    along, across = SLOT
    dalpha = -along * dxdh - across                     # the pin's height −a_t α, the centre −a_n α from the pin
    g = budget(cl).gradient[0, :, 0]
    np.testing.assert_allclose(g[:, 0], dxdh, atol=1e-8)
    np.testing.assert_allclose(g[:, 1], dalpha * 2 / BLOCK, atol=1e-8)
    # and a finite difference of the closed form itself
    step = 1e-6
    fd = (closed_form(ANGLES, 0.0, step) - closed_form(ANGLES, 0.0, -step)) / (2 * step)
    np.testing.assert_allclose(dalpha, fd, atol=1e-8)


def test_the_block_follows_the_virtual_work_of_the_guides_force_and_moment():
    """Virtual work (seed 002 §7-1, "treated ... by the principle of virtual work"): under a unit force along
    the slide at the block's centre, the input held, the guide's force F on the block and its moment M about
    the centre give ∂y/∂u = −F·n and ∂y/∂α = −M (inverse dynamics, an independent solver)."""
    mech = off_centre()
    cl = Clearances(Tolerancing(mech, "slide:S", ANGLES, tolerance=0.0), {"S": 1e-3}, blocks={"S": BLOCK})
    g = budget(cl).gradient[0, :, 0]
    at = mech.joint("S").at
    dyn = inverse_dynamics(_statics(mech, (Load("unit", "slider", (1.0, 0.0), at),)), 0.0, math.radians(330.0),
                           math.radians(30.0), speed=0.0, acceleration=0.0)
    np.testing.assert_allclose(g[:, 0], -dyn.reactions["S"][:, 1], atol=1e-7)    # n = +y, the frame's force
    np.testing.assert_allclose(g[:, 1] * BLOCK / 2, -dyn.moments["S"], atol=1e-7)


def test_the_random_states_have_the_budgets_moments():
    """The Monte Carlo model of a block: every state on the square |u| + |w| = c (a corner on a wall), u uniform
    on [−c, c], so E u² = E w² = c²/3 and E uw = 0: the first-order variance c²|G|²/3 (a pin's: c²|G|²/2)."""
    tol = Tolerancing(load_mechanism(SLIDER_CRANK), "slide:S", ANGLES, tolerance=0.0)
    cl = Clearances(tol, {"B": 2e-3, "S": 2e-3})
    rng = np.random.default_rng(5)
    e = cl.states(rng.uniform(0.0, 2 * math.pi, (200_000, 2)))
    u, w = e[:, 1, 0], e[:, 1, 1]
    np.testing.assert_allclose(np.abs(u) + np.abs(w), 2e-3, rtol=1e-12)
    np.testing.assert_allclose(np.hypot(*e[:, 0].T), 2e-3, rtol=1e-12)
    c2 = 4e-6
    assert np.mean(u ** 2) == pytest.approx(c2 / 3, rel=0.01) and np.mean(w ** 2) == pytest.approx(c2 / 3, rel=0.01)
    assert abs(np.mean(u * w)) < 0.01 * c2
    counts = np.histogram(u, bins=10, range=(-2e-3, 2e-3))[0]
    assert np.all(np.abs(counts / 20_000 - 1) < 0.05)                       # u uniform
    assert np.mean(e[:, 0, 0] ** 2) == pytest.approx(c2 / 2, rel=0.01)


@pytest.mark.parametrize("mech, blocks", [(SLIDER_CRANK, None), ("off-centre", {"S": BLOCK})])
def test_monte_carlo_agrees_with_first_order_with_a_clearance_at_every_joint(mech, blocks):
    """Clearance 1e-3 at A, B, C and the slide (the file's slider-crank; the off-centre block, its tilt acting):
    Monte Carlo's σ and largest error within 5% of first order's σ and worst case (measured: σ within 0.2%,
    largest 0.98 .. 1.00 of the worst case over seeds 1 to 4)."""
    mech = load_mechanism(SLIDER_CRANK) if mech == SLIDER_CRANK else off_centre()
    cl = Clearances(Tolerancing(mech, "slide:S", ANGLES, tolerance=0.0), every=1e-3, blocks=blocks)
    assert cl.joints == ["A", "B", "C", "S"] and cl.slides.tolist() == [False, False, False, True]
    b, mc = budget(cl), monte_carlo(cl, 40_000, seed=1)
    assert mc.failed == 0 and mc.trusted
    assert np.all(np.abs(mc.std / b.std - 1) < 0.05)
    assert np.all(np.abs(mc.largest / b.worst - 1) < 0.05)


def test_the_combined_budget_is_the_sum_of_its_parts():
    """Tolerances and clearances (pins and the tilted block) as independent sources: worst cases sum, variances
    add, each clearance's part its own c|G| and c²|G|²/k (k = 2 a pin, 3 a block)."""
    tol = Tolerancing(off_centre(), "slide:S", ANGLES, relative=1e-4)
    first = sensitivity(tol)
    c = {"A": 5e-4, "B": 1e-3, "C": 2e-4, "S": 1e-3}
    b = budget(Clearances(tol, c, blocks={"S": BLOCK}), first=first)
    g = b.gradient[0]                                                    # (N, K, 2)
    worst = [c["A"] * np.hypot(*g[:, 0].T), c["B"] * np.hypot(*g[:, 1].T), c["C"] * np.hypot(*g[:, 2].T),
             c["S"] * np.max(np.abs(g[:, 3]), axis=1)]
    variance = [c[j] ** 2 * np.sum(g[:, k] ** 2, axis=1) / (3.0 if j == "S" else 2.0) for k, j in enumerate("ABCS")]
    np.testing.assert_allclose(b.clearance_worst[0], np.sum(worst, axis=0), rtol=1e-12)
    np.testing.assert_allclose(b.clearance_std[0], np.sqrt(np.sum(variance, axis=0)), rtol=1e-12)
    np.testing.assert_allclose(b.worst, first.worst + b.clearance_worst, rtol=1e-12)
    np.testing.assert_allclose(b.std, np.sqrt(first.std ** 2 + b.clearance_std ** 2), rtol=1e-12)
    assert b.share.sum() == pytest.approx(1.0) and b.names[-1] == "clearance:S"
    np.testing.assert_allclose(b.share[-1], np.sum(variance[3]) / np.sum(b.std ** 2), rtol=1e-12)
    rows = compare(b.clearances, (1.0, 10.0), samples=10_000, seed=0)    # both scaled: still together
    assert all(abs(r.ratio - 1) < 0.05 for r in rows)


def test_the_command_reports_the_slides_clearance(tmp_path, capsys):
    """`domes tolerance --clearance S=C --block S=L`: the block's row, its length, and the budget's parts in JSON
    (worst cases sum, 3σ root-sum-square)."""
    from domes.io.mechanisms import save_mechanism

    path = str(tmp_path / "off-centre.json")
    save_mechanism(off_centre(), path)
    args = ["tolerance", path, "--output", "slide:S", "--sweep", "0:360:90", "--relative", "1e-4",
            "--clearance-all", "1e-3", "--block", "S=1", "--samples", "20000"]
    assert main(args) == 0
    text = capsys.readouterr().out
    assert "6 dimensions, 4 clearances (contact mode" in text and "clearance:S" in text
    assert "S the block slider (1 long)" in text and "together: worst case" in text
    assert "the first-order estimate is enough (within 5% of Monte Carlo)" in text
    assert main([*args[:-1], "0", "--format", "json"]) == 0                # first order only
    doc = json.loads(capsys.readouterr().out)
    assert doc["clearances"]["joints"][3] == {"joint": "S", "kind": "P", "clearance": 1e-3, "carrier": "slider",
                                              "block": 1.0}
    for row in doc["inputs"]:
        assert row["worst_case"] == pytest.approx(row["worst_case_tolerances"] + row["worst_case_clearances"])
        assert row["three_sigma_first_order"] == pytest.approx(math.hypot(row["three_sigma_tolerances"],
                                                                          row["three_sigma_clearances"]))
    base = args[:8]                                                    # no clearance, no block
    assert main([*base, "--clearance", "S=1e-3", "--samples", "0"]) == 2
    assert "the block length of slide S is needed (its pin C is 0.4472 from the slide point" in capsys.readouterr().err
    assert main([*base, "--block", "S=1", "--samples", "0"]) == 2
    assert "--block: give the slide a clearance too" in capsys.readouterr().err


def test_bad_slide_clearances_are_refused_by_name():
    tol = Tolerancing(off_centre(), "slide:S", ANGLES, tolerance=0.0)
    with pytest.raises(InputError, match="the block length of slide S is needed"):
        Clearances(tol, every=1e-3)
    with pytest.raises(InputError, match="a block length is given for 'C', which is not a slide on the frame"):
        Clearances(tol, {"S": 1e-3}, blocks={"C": 1.0})
    with pytest.raises(InputError, match="the block of S must be longer than 0"):
        Clearances(tol, {"S": 1e-3}, blocks={"S": 0.0})
    with pytest.raises(InputError, match=r"0.06 at S is not small beside half its block, 0.5"):
        Clearances(tol, {"S": 0.06}, blocks={"S": 1.0})
    assert len(Clearances(tol, {"S": 0.06}, blocks={"S": 1.0}, check=False)) == 1
    angle = Tolerancing(load_mechanism(SLIDER_CRANK), "angle:slider", ANGLES, tolerance=0.0)
    with pytest.raises(InputError, match="the output is the angle of its block slider"):
        Clearances(angle, {"S": 1e-3})
    turned = Clearances(angle, {"S": 1e-3}, blocks={"S": 0.5}).evaluate(np.array([[[0.0, 1e-3]]]))
    np.testing.assert_allclose(turned["angle:slider"], 2 * 1e-3 / 0.5, atol=1e-15)     # the block's tilt, exactly
    # a slide between two moving links (a slotted lever whose slot runs through its pivot D) takes no clearance
    lever = Mechanism.build("slotted lever", ["frame", "crank", "block", "lever"], "frame",
                            [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "block"), (0.0, 1.0)),
                             Joint("S", "P", ("block", "lever"), (0.0, 1.0), math.atan2(1.0, -3.0), (3.0, 0.0)),
                             Joint("D", "R", ("lever", "frame"), (3.0, 0.0))], [Input("A")])
    with pytest.raises(InputError, match=r"S slides between two moving links \(block, lever\); a clearance is taken"):
        Clearances(Tolerancing(lever, "angle:lever", ANGLES, tolerance=0.0), {"S": 1e-3})
