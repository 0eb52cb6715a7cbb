"""Tolerance analysis at the edges (issue 31, item 5): dead points, large tolerances, what the output needs.

Monte Carlo at 1000 times the tolerances of ``docs/tolerance.md`` (10% of
each length) is checked against an independent Monte Carlo written here:
the same perturbation arrays (drawn by hand from the same seeds), each
linkage placed by closed forms on the nominal's branch (a four-bar's rocker
joint by the intersection of two circles, a slider-crank's pin by a circle
and a line, a coupler point by its triangle), with numpy only. The module's
failures must be the samples the closed forms cannot place, its σ theirs.
"""

import json
import math

import numpy as np
import pytest

from domes.design import tolerance
from domes.design.tolerance import (
    BATCH,
    OTHER_MODE,
    OUT_OF_SPEC,
    UNASSEMBLED,
    Tolerancing,
    compare,
    monte_carlo,
    sensitivity,
)
from domes.io.mechanisms import load_mechanism
from tests.design.test_tolerance import run_cli

ANGLES = np.radians(np.arange(0.0, 360.0, 30.0))
LARGE = 0.1                      # 1000 times the documented 1e-4 of each length


def draws(tol, samples, seed):
    """The dimension values of ``samples`` normal samples as monte_carlo draws them: batch k from the k-th child of
    SeedSequence(seed), nominal + N(0, 1) · tolerance / 3 (built here, not by the module)."""
    sizes = [min(BATCH, samples - k) for k in range(0, samples, BATCH)]
    children = np.random.SeedSequence(seed).spawn(len(sizes))
    nominal = np.array([d.nominal for d in tol.dimensions])
    sigma = np.array([d.tolerance for d in tol.dimensions]) / 3.0
    return np.vstack([nominal + np.random.default_rng(c).standard_normal((n, nominal.size)) * sigma
                      for c, n in zip(children, sizes)])


def side(a, b, c):
    """Which side of the line a→b the point c is on (+1 left, −1 right), from the drawing."""
    return math.copysign(1.0, (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))


def apex(p, q, along, first, second, sign):
    """The third corner of a triangle on p→q (|q − p| = ``along``), ``first`` from p and ``second`` from q, on the
    side ``sign``; NaN where the three lengths do not close."""
    with np.errstate(invalid="ignore"):
        cos = (first ** 2 + along ** 2 - second ** 2) / (2 * first * along)
        angle = np.where(np.abs(cos) <= 1, np.arccos(np.clip(cos, -1, 1)), np.nan)
    return p + first * np.exp(1j * (np.angle(q - p) + sign * angle))


def four_bar(mech, names, values, inputs, point=None):
    """Rocker angle (and a coupler point) of four-bar loops A-B-C-D: B on the crank at the input angle, C where the
    coupler's and rocker's circles meet, on the drawing's side of B→D; NaN where they do not meet."""
    at = {j.name: j.at for j in mech.joints} | {p.name: p.at for p in mech.points}
    a, b, c, d = names
    v = {dim.name: values[:, k] for k, dim in enumerate(TOL[id(mech)].dimensions)}
    pa = (v[f"{a}.x"] + 1j * v[f"{a}.y"])[:, None]
    pd = (v[f"{d}.x"] + 1j * v[f"{d}.y"])[:, None]
    crank, coupler, rocker = (next(v[k][:, None] for k in v if k.endswith(f":{u}-{w}")) for u, w in ((a, b), (b, c), (c, d)))
    pb = pa + crank * np.exp(1j * inputs[None, :])
    pc = apex(pb, pd, np.abs(pd - pb), coupler, rocker, side(at[b], at[d], at[c]))
    out = {"angle": np.angle(pc - pd)}
    if point is not None:
        to_b, to_c = (next(v[k][:, None] for k in v if k.endswith(f":{u}-{point}")) for u in (b, c))
        out["point"] = apex(pb, pc, coupler, to_b, to_c, side(at[b], at[c], at[point]))
    return out


def slider_crank(mech, values, inputs):
    """Slide and coupler point M of the offset slider-crank: B on the crank, C on the line n·X = offset at the rod's
    length from B, on the drawing's side; the slide is C's place along the line from the drawn origin."""
    at = {j.name: j.at for j in mech.joints} | {p.name: p.at for p in mech.points}
    v = {dim.name: values[:, k][:, None] for k, dim in enumerate(TOL[id(mech)].dimensions)}
    u = np.exp(1j * v["S.angle"])
    pb = v["A.x"] + 1j * v["A.y"] + v["crank:A-B"] * np.exp(1j * inputs[None, :])
    height = v["S.offset"] - (pb * np.conj(1j * u)).real              # B's distance below the line, along n = i·u
    with np.errstate(invalid="ignore"):
        along = np.sqrt(v["rod:B-C"] ** 2 - height ** 2)
    line = mech.joint("S").direction                                 # C ahead of B along the line, as drawn
    ahead = math.copysign(1.0, (at["C"][0] - at["B"][0]) * math.cos(line) + (at["C"][1] - at["B"][1]) * math.sin(line))
    pc = pb + height * 1j * u + ahead * along * u
    origin = complex(*mech.joint("S").slide_origin)
    slide = ((pc - origin) * np.conj(u)).real
    point = apex(pb, pc, v["rod:B-C"], v["rod:B-M"], v["rod:C-M"], side(at["B"], at["C"], at["M"]))
    return {"slide": slide, "point": point}


TOL: dict = {}


def tolerancing(path, output, relative=LARGE, inputs=ANGLES):
    mech = load_mechanism(f"examples/mechanisms/{path}.json")
    tol = Tolerancing(mech, output, inputs, relative=relative)
    TOL[id(mech)] = tol
    return mech, tol


def independent(errors, spec=None):
    """σ, its standard error (fourth moment, delta method) and the failures of closed-form errors ``(C, M, N)``."""
    made = np.all(np.isfinite(errors), axis=(0, 2))
    e = errors[:, made]
    n = e.shape[1]
    std = e.std(axis=1, ddof=1)
    dev = e - e.mean(axis=1, keepdims=True)
    mu2, mu4 = np.mean(dev ** 2, axis=1), np.mean(dev ** 4, axis=1)
    se = np.sqrt((mu4 - mu2 ** 2 * (n - 3) / (n - 1)) / n) / (2 * std)
    off = 0
    if spec is not None:
        size = np.hypot(e[0], e[1]) if len(e) == 2 else np.abs(e[0])
        off = int(np.sum(np.max(size, axis=1) > spec))
    return std, se, int(np.sum(~made)), off


def closed_form_errors(model, nominal_values, values, wrap):
    sample, nominal = model(values), model(nominal_values[None, :])
    errors = sample - nominal
    if wrap:
        errors = np.angle(np.exp(1j * errors))
    return errors


def test_the_samples_are_the_ones_drawn_by_hand():
    _, tol = tolerancing("four-bar", "angle:rocker")
    mine = draws(tol, 25_000, 3)
    theirs = np.vstack([tol.sample(np.random.default_rng(c), n, "normal")
                        for c, n in zip(np.random.SeedSequence(3).spawn(2), (BATCH, 5_000))])
    np.testing.assert_array_equal(mine, theirs)


@pytest.mark.parametrize("output", ["angle:rocker", "point:P"])
def test_four_bar_at_1000_times_the_tolerances_matches_the_closed_forms(output):
    mech, tol = tolerancing("four-bar", output)
    values = draws(tol, 50_000, 11)                       # three batches: the moments are merged
    point = "P" if output == "point:P" else None

    def model(v):
        out = four_bar(mech, "ABCD", v, ANGLES, point)
        return np.stack([out["angle"]]) if point is None else np.stack([out["point"].real, out["point"].imag])

    errors = closed_form_errors(model, tol.nominal, values, wrap=point is None)
    std, se, failed, _ = independent(errors)
    mc = monte_carlo(tol, 50_000, seed=11)
    np.testing.assert_allclose(mc.std, std, rtol=0.01)
    np.testing.assert_allclose(mc.std_error, se, rtol=0.01)
    assert mc.failures == {UNASSEMBLED: failed, OTHER_MODE: 0, OUT_OF_SPEC: 0}
    assert mc.trusted and mc.relative_error < 0.01


def test_slider_crank_slide_ignores_the_coupler_point_it_does_not_need():
    # M sits on the rod in a thin triangle B-M-C that often cannot close at 10% tolerances; the slide does not
    # depend on it: no sample may fail for it (6,358 of 20,000 did), and σ must be the closed form's.
    mech, tol = tolerancing("slider-crank", "slide:S")
    assert tol.ignored == ("M",)
    values = draws(tol, 20_000, 0)
    errors = closed_form_errors(lambda v: slider_crank(mech, v, ANGLES)["slide"][None], tol.nominal, values, False)
    std, se, failed, _ = independent(errors)
    mc = monte_carlo(tol, 20_000, seed=0)
    assert failed == 0 and mc.failed == 0 and sum(mc.failures.values()) == 0
    np.testing.assert_allclose(mc.std, std, rtol=0.01)
    assert mc.trusted
    point = closed_form_errors(lambda v: slider_crank(mech, v, ANGLES)["point"][None], tol.nominal, values, False)
    assert np.sum(~np.all(np.isfinite(point), axis=(0, 2))) > 5_000     # the point itself often cannot be made


def test_slider_crank_point_counts_each_failure_once_as_the_closed_forms_do():
    mech, tol = tolerancing("slider-crank", "point:M")
    values = draws(tol, 20_000, 0)

    def model(v):
        m = slider_crank(mech, v, ANGLES)["point"]
        return np.stack([m.real, m.imag])

    errors = closed_form_errors(model, tol.nominal, values, False)
    spec = 0.2
    std, _, failed, off = independent(errors, spec)
    mc = monte_carlo(tol, 20_000, seed=0, spec=spec)
    assert failed > 5_000 and off > 100
    assert mc.failures == {UNASSEMBLED: failed, OTHER_MODE: 0, OUT_OF_SPEC: off}
    assert mc.failed == failed and mc.fraction == pytest.approx((failed + off) / 20_000)
    assert mc.fraction_error == pytest.approx(math.sqrt(mc.fraction * (1 - mc.fraction) / 20_000))
    np.testing.assert_allclose(mc.std, std, rtol=0.01)     # over the samples that can be made
    # ... but with a third of them left out it recommends nothing, and says why
    assert not mc.trusted and "do not assemble" in mc.trust and "σ describes only those that do" in mc.trust


def test_six_bar_keeps_the_nominal_mode_and_ignores_the_dyad_the_output_does_not_need(monkeypatch):
    # Stephenson six-bar: the rocker of its four-bar does not depend on the dyad E-G-F nor on the point T.
    # Newton's method from the drawn pose lands some samples in the other assembly mode of the four-bar; they
    # must be placed on the nominal's branch (as the circles are) or counted as such.
    mech, tol = tolerancing("stephenson-six-bar", "angle:rocker")
    assert set(tol.ignored) == {"E", "G", "T"}
    values = draws(tol, 20_000, 0)
    drawn = np.array([math.atan2(mech.joint("B").at[1] - mech.joint("A").at[1],
                                 mech.joint("B").at[0] - mech.joint("A").at[0])])
    inputs = np.concatenate([ANGLES, drawn])       # each sample is placed at its drawn input first

    def model(v):
        return np.stack([four_bar(mech, "ABCD", v, inputs)["angle"]])

    errors = closed_form_errors(model, tol.nominal, values, wrap=True)
    _, _, failed, _ = independent(errors)
    std, _, _, _ = independent(np.where(np.all(np.isfinite(errors), axis=2, keepdims=True), errors, np.nan)[:, :, :-1])
    mc = monte_carlo(tol, 20_000, seed=0)
    assert 20 < failed < 200                        # some samples cannot turn through the whole range
    assert mc.failures == {UNASSEMBLED: failed, OTHER_MODE: 0, OUT_OF_SPEC: 0}
    np.testing.assert_allclose(mc.std, std, rtol=0.01)
    m, n = len(values), len(tol._unknown)           # Newton alone, from the drawn pose, does land in the other mode
    start = np.broadcast_to(tol._start, (m, n, 2))
    poses, ok = tol._newton(start.copy(), values, np.ones(m, dtype=bool))
    same = tol._same_mode(*tol._coordinates(np.where(ok[:, None, None], poses, start), values))
    other = int(np.sum(ok & ~same))
    assert other > 0
    # without the continuation those samples are counted as in the other mode, each once, never among the made
    monkeypatch.setattr(tolerance, "CONTINUATION", ())
    alone = monte_carlo(tol, 20_000, seed=0)
    assert alone.failures[OTHER_MODE] == other and alone.failures[UNASSEMBLED] == int(np.sum(~ok))
    assert alone.failed == other + int(np.sum(~ok)) >= failed


def test_a_singular_input_is_named_and_first_order_is_not_called_enough():
    # The parallelogram passes its change point at 0 and 180 deg: coupler and rocker in line, no derivative.
    mech, tol = tolerancing("parallelogram", "angle:rocker", relative=1e-4)
    first = sensitivity(tol)
    assert first.notes[0] == first.notes[6] == "singular" and np.all(first.condition[[0, 6]] > 1e7)
    assert np.isnan(first.std[0, 0]) and not first.valid[[0, 6]].any()
    assert "first order is not valid at input 0, 180 deg: the linkage is at a dead point (singular)" in first.message
    out = run_cli("examples/mechanisms/parallelogram.json", "--output", "angle:rocker", "--relative", "1e-4",
                  "--sweep", "0:360:30", "--samples", "20000")
    assert out.returncode == 0, out.stderr
    assert "nan" not in out.stdout and "enough" not in out.stdout
    rows = [line for line in out.stdout.splitlines() if not line.startswith("#")]
    table = [r for r in rows if len(r.split()) >= 6 and r.split()[0] in ("0", "180")]
    assert len(table) == 2 and all(r.split()[2:4] == ["singular", "singular"] for r in table)
    assert all(r.endswith("<- first order not valid: dead point (singular)") for r in table)
    assert "the linkage is at a dead point (singular)" in out.stdout.splitlines()[-1]


def test_first_order_says_where_large_tolerances_reach_a_dead_point():
    # Stephenson six-bar at 10%: near 0 deg the transmission angle is smallest and 3σ of the lengths reach the
    # dead point; near 180 deg it is far; at 1e-4 first order is valid everywhere
    _, tol = tolerancing("stephenson-six-bar", "angle:rocker")
    first = sensitivity(tol)
    assert first.notes[0] == "reach" and first.notes[6] == ""
    assert np.argmax(first.condition) == 0
    _, small = tolerancing("stephenson-six-bar", "angle:rocker", relative=1e-4)
    assert sensitivity(small).valid.all()


def test_the_standard_error_of_sigma_is_the_spread_of_sigma_over_seeds():
    _, tol = tolerancing("four-bar", "angle:rocker", relative=1e-3, inputs=ANGLES[:3])
    runs = [monte_carlo(tol, 4_000, seed=s) for s in range(16)]
    spread = np.std([r.std for r in runs], axis=0, ddof=1)
    reported = np.mean([r.std_error for r in runs], axis=0)
    assert np.all((spread / reported > 0.6) & (spread / reported < 1.6))
    assert not runs[0].trusted and "take about" in runs[0].trust     # ±1.1%: more samples wanted


def test_the_scan_parts_only_where_it_should():
    # slide:S: at 1000x first order and Monte Carlo still agree once M cannot make samples fail
    _, tol = tolerancing("slider-crank", "slide:S", relative=1e-4)
    scan = compare(tol, scales=(1.0, 1000.0), samples=20_000)
    assert [s.agree for s in scan] == [True, True] and [s.failed for s in scan] == [0, 0]
    _, tol = tolerancing("slider-crank", "point:M", relative=1e-4)
    large = compare(tol, scales=(1000.0,), samples=20_000)[0]
    assert not large.agree and not large.valid and not large.trusted and large.failed > 5_000


def test_command_line_names_the_failures_and_the_trust():
    out = run_cli("examples/mechanisms/slider-crank.json", "--output", "point:M", "--relative", "0.1", "--sweep",
                  "0:360:30", "--samples", "20000", "--spec", "0.2", "--format", "json")
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    m = doc["monte_carlo"]
    assert m["failures"][UNASSEMBLED] > 5_000 and m["failures"][OTHER_MODE] == 0 and m["failures"][OUT_OF_SPEC] > 100
    assert not m["trusted"] and not m["agree"] and m["verdict"].startswith("no recommendation: Monte Carlo cannot say")
    assert not doc["first_order_valid"] and "a rigid link cannot be made" in doc["first_order_not_valid"]
    assert all(r["first_order_note"] == "unmade" for r in doc["inputs"])
    bad = run_cli("examples/mechanisms/slider-crank.json", "--output", "point:M", "--relative", "1e-4", "--spec", "-1")
    assert bad.returncode == 2 and "--spec must be a positive number" in bad.stderr


def test_a_link_whose_first_joint_the_output_does_not_need(tmp_path):
    # The Stephenson six-bar with joint E listed first: the coupler's triangle is E-B, E-C, B-C. E (and the dyad
    # E-G-F) is not needed for the rocker; the side B-C still is, and its sample must not fail on E's sides.
    doc = json.loads(open("examples/mechanisms/stephenson-six-bar.json").read())
    doc["joints"].sort(key=lambda j: j["name"] != "E")
    path = tmp_path / "stephenson-e-first.json"
    path.write_text(json.dumps(doc))
    mech = load_mechanism(path)
    tol = Tolerancing(mech, "angle:rocker", ANGLES, relative=LARGE)
    TOL[id(mech)] = tol
    assert {"coupler:E-B", "coupler:E-C", "coupler:B-C"} <= {d.name for d in tol.dimensions}
    assert set(tol.ignored) == {"E", "G", "T"}
    values = draws(tol, 20_000, 0)
    drawn = np.array([math.atan2(mech.joint("B").at[1] - mech.joint("A").at[1],
                                 mech.joint("B").at[0] - mech.joint("A").at[0])])
    errors = closed_form_errors(lambda v: np.stack([four_bar(mech, "ABCD", v, np.concatenate([ANGLES, drawn]))["angle"]]),
                                tol.nominal, values, wrap=True)
    _, _, failed, _ = independent(errors)
    std, _, _, _ = independent(errors[:, :, :-1] + np.where(np.isfinite(errors[:, :, -1:]), 0.0, np.nan))
    mc = monte_carlo(tol, 20_000, seed=0)
    assert mc.failures == {UNASSEMBLED: failed, OTHER_MODE: 0, OUT_OF_SPEC: 0}
    np.testing.assert_allclose(mc.std, std, rtol=0.01)
