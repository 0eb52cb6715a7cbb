"""Tolerance sensitivity (issue 16, item 5): first order against closed forms, Monte Carlo against first order.

The derivatives of the four-bar's output angle and of the slider-crank's
slide with respect to their link lengths are differentiated by hand from
the loop-closure equations (independent of the kernel and of the re-drawn
poses); Monte Carlo with 10^5 samples must match the first-order standard
deviation within 5% for tolerances of 1e-4 of the link lengths, and part
from it when the tolerances are large.
"""

import math

import numpy as np
import pytest

from domes.design.tolerance import Tolerancing, compare, monte_carlo, sensitivity
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.motion.planar.examples import four_bar
from domes.motion.planar.sweep import sweep

ANGLES = np.radians(np.arange(0.0, 360.0, 30.0))


def column(s, name):
    return s.gradient[0][:, [d.name for d in s.tolerancing.dimensions].index(name)]


def test_four_bar_derivatives_equal_the_loop_closure_ones():
    # a e^{iθ2} + b e^{iθ3} − c e^{iθ4} − d = 0 differentiated, then multiplied by e^{−iθ3}; the real part:
    # ∂θ4/∂a = −cos(θ2−θ3) / (c sin(θ4−θ3)), ∂θ4/∂b = −1 / (c sin(θ4−θ3)),
    # ∂θ4/∂c = cos(θ4−θ3) / (c sin(θ4−θ3)), ∂θ4/∂d = cos θ3 / (c sin(θ4−θ3)).
    mech = four_bar()
    s = sensitivity(Tolerancing(mech, "angle:rocker", ANGLES, relative=1e-4))
    run = sweep(mech, 0.0, math.radians(330.0), math.radians(30.0), outputs=["angle:coupler", "angle:rocker"])
    t3, t4 = (np.asarray(run.table[c], dtype=float) for c in ("angle:coupler", "angle:rocker"))
    c = 2.5
    den = c * np.sin(t4 - t3)
    np.testing.assert_allclose(column(s, "crank:A-B"), -np.cos(ANGLES - t3) / den, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(column(s, "coupler:B-C"), -1.0 / den, rtol=1e-6)
    np.testing.assert_allclose(column(s, "rocker:C-D"), np.cos(t4 - t3) / den, rtol=1e-6)
    np.testing.assert_allclose(column(s, "D.x"), np.cos(t3) / den, rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(column(s, "A.x"), -np.cos(t3) / den, rtol=1e-6, atol=1e-8)


def test_slider_crank_derivatives_equal_the_closed_form():
    # s = r cos θ + √(l² − (r sin θ − e)²) along the line y = e (seed 000's offset slider-crank, crank 1, rod 3).
    mech = load_mechanism("examples/mechanisms/slider-crank.json")
    s = sensitivity(Tolerancing(mech, "slide:S", ANGLES, relative=1e-4))
    r, rod, e = 1.0, 3.0, 0.5
    root = np.sqrt(rod ** 2 - (r * np.sin(ANGLES) - e) ** 2)
    np.testing.assert_allclose(column(s, "crank:A-B"), np.cos(ANGLES) - (r * np.sin(ANGLES) - e) * np.sin(ANGLES) / root,
                               rtol=1e-6, atol=1e-8)
    np.testing.assert_allclose(column(s, "rod:B-C"), rod / root, rtol=1e-6)
    np.testing.assert_allclose(column(s, "S.offset"), (r * np.sin(ANGLES) - e) / root, rtol=1e-6, atol=1e-8)


@pytest.mark.parametrize("path, output", [("four-bar", "angle:rocker"), ("slider-crank", "slide:S"),
                                          ("slider-crank", "point:M")])
def test_monte_carlo_agrees_with_first_order_for_small_tolerances(path, output):
    tol = Tolerancing(load_mechanism(f"examples/mechanisms/{path}.json"), output, ANGLES, relative=1e-4)
    first = sensitivity(tol)
    mc = monte_carlo(tol, samples=100_000, seed=7)
    assert mc.failed == 0 and mc.success
    np.testing.assert_allclose(mc.std, first.std, rtol=0.05)
    assert np.all(np.abs(mc.mean) < 3 * first.std / math.sqrt(1000))
    flat = monte_carlo(tol, samples=100_000, seed=7, distribution="uniform")      # every sample within ± t:
    assert np.all(flat.largest <= first.worst * 1.0001)                          # never beyond the worst case
    np.testing.assert_allclose(flat.std, sensitivity(tol, "uniform").std, rtol=0.05)


def test_estimates_part_for_large_tolerances():
    # The slider-crank's coupler point: a thin triangle B-M-C; at 300x the tolerances some samples cannot be made
    # (and are counted), and the linear estimate is off by more than 5%.
    tol = Tolerancing(load_mechanism("examples/mechanisms/slider-crank.json"), "point:M", ANGLES, relative=1e-4)
    small, large = compare(tol, scales=(1.0, 1000.0), samples=20_000)
    assert abs(small.ratio - 1) < 0.02 and small.failed == 0
    assert abs(large.ratio - 1) > 0.05 and large.failed > 0


def test_allocation_meets_the_wanted_accuracy():
    tol = Tolerancing(four_bar(), "angle:rocker", ANGLES, relative=1e-3)
    first = sensitivity(tol)
    bands = first.allocate(1e-4)
    allocated = Tolerancing(four_bar(), "angle:rocker", ANGLES, relative=1e-3,
                            tolerances={d.name: float(t) for d, t in zip(tol.dimensions, bands)})
    check = sensitivity(allocated)
    # Each dimension takes 1/√D of the 3σ budget at its own worst input: within the budget everywhere, and at
    # least one dimension's part of it somewhere.
    assert 1e-4 / math.sqrt(len(bands)) <= 3 * np.max(check.std) <= 1e-4 * (1 + 1e-6)
    worst = monte_carlo(allocated, 50_000, seed=2)
    assert 3 * np.max(worst.std) <= 1e-4 * 1.03


def test_seeded_monte_carlo_is_reproducible_and_batches_do_not_matter_for_the_seed():
    tol = Tolerancing(four_bar(), "angle:rocker", ANGLES, relative=1e-4)
    one, two = monte_carlo(tol, 30_000, seed=3), monte_carlo(tol, 30_000, seed=3)
    assert np.array_equal(one.std, two.std) and np.array_equal(one.largest, two.largest)
    assert not np.array_equal(one.std, monte_carlo(tol, 30_000, seed=4).std)


def test_bad_input_is_named():
    # an offset slotted lever: its slide runs between two moving links and off the lever's pin
    with pytest.raises(InputError, match="slides between two moving links whose pins O4 and A are not apart on its line"):
        Tolerancing(load_mechanism("examples/mechanisms/inverted-slider.json"), "angle:crank", ANGLES, relative=1e-4)
    with pytest.raises(InputError, match="either an absolute tolerance or a relative one"):
        Tolerancing(four_bar(), "angle:rocker", ANGLES)
    with pytest.raises(InputError, match="'crank:A-Z' is not a dimension"):
        Tolerancing(four_bar(), "angle:rocker", ANGLES, tolerance=1e-3, tolerances={"crank:A-Z": 1e-3})
    with pytest.raises(InputError, match="distribution"):
        monte_carlo(Tolerancing(four_bar(), "angle:rocker", ANGLES, tolerance=1e-3), 100, distribution="cauchy")


def run_cli(*args):
    """``domes tolerance ARGS`` through the command line's entry point in this process (no interpreter to start
    each time): its exit status, its output and what it wrote to stderr, warnings included as a terminal shows
    them."""
    import contextlib
    import io
    import warnings
    from types import SimpleNamespace

    from domes.cli import main

    out, err = io.StringIO(), io.StringIO()
    with warnings.catch_warnings(record=True) as caught, contextlib.redirect_stdout(out), \
            contextlib.redirect_stderr(err):
        warnings.simplefilter("always")
        try:
            code = main(["tolerance", *args])
        except SystemExit as exc:                   # argparse's refusals
            code = 0 if exc.code is None else exc.code
    shown = "".join(warnings.formatwarning(w.message, w.category, w.filename, w.lineno) for w in caught)
    return SimpleNamespace(returncode=code, stdout=out.getvalue(), stderr=err.getvalue() + shown)


def run_process(*args):
    """``domes tolerance ARGS`` as a process of its own."""
    import subprocess
    import sys

    return subprocess.run([sys.executable, "-m", "domes", "tolerance", *args], capture_output=True, text=True)


def test_command_line_json_is_the_same_on_two_workers_and_says_where_estimates_part():
    import json

    # the coupler point M of a thin triangle B-M-C: at 1000x its triangle often cannot close (the slide, which does
    # not need M, agrees at every scale: tests/design/test_tolerance_edges.py)
    args = ["examples/mechanisms/slider-crank.json", "--output", "point:M", "--sweep", "0:360:30", "--relative",
            "1e-4", "--samples", "40000", "--seed", "5", "--scan", "--allocate", "0.001", "--format", "json"]
    here, there = run_cli(*args), run_process(*args, "--workers", "2")      # the pool started by the command
    assert here.returncode == 0 and there.returncode == 0, here.stderr + there.stderr
    assert here.stdout == there.stdout
    doc = json.loads(here.stdout)
    assert doc["monte_carlo"]["agree"] and doc["monte_carlo"]["samples"] == 40000
    assert len(doc["inputs"]) == 24 and doc["inputs"][0]["input"] == 0.0             # 360 is 0 again; x and y
    assert [s["agree"] for s in doc["scan"]] == [True, True, True, False]
    assert doc["dimensions"][0]["name"] == "rod:B-C" and all("allocated" in d for d in doc["dimensions"])


def test_command_line_errors_name_the_problem():
    bad = run_cli("examples/mechanisms/four-bar.json", "--output", "angle:rocker", "--relative", "1e-4",
                  "--set", "crank:A-B")
    assert bad.returncode == 2 and "expected NAME=TOLERANCE" in bad.stderr
    bad = run_cli("examples/mechanisms/four-bar.json", "--output", "angle:rocker", "--relative", "1e-4",
                  "--set", "rocker:A-D=0.1")
    assert bad.returncode == 2 and "'rocker:A-D' is not a dimension" in bad.stderr and "crank:A-B" in bad.stderr
    bad = run_cli("examples/mechanisms/four-bar.json", "--output", "angle:rocker")
    assert bad.returncode == 2 and "--tolerance" in bad.stderr


def test_command_line_takes_angle_tolerances_in_degrees():
    import json

    out = run_cli("examples/mechanisms/slider-crank.json", "--output", "slide:S", "--relative", "1e-4", "--set",
                  "S.angle=0.01", "--samples", "0", "--sweep", "0:90:90", "--format", "json")
    assert out.returncode == 0, out.stderr
    angle = next(d for d in json.loads(out.stdout)["dimensions"] if d["name"] == "S.angle")
    assert angle["tolerance"] == pytest.approx(0.01)


def test_a_tolerance_not_small_beside_the_lengths_is_refused_naming_the_dimension():
    # issue 25, item 1: ± 1e300 overflowed into inf/NaN tables; a band must be small beside what it bands
    crank = load_mechanism("examples/mechanisms/slider-crank.json")
    with pytest.raises(InputError, match=r"±1e\+300 on crank:A-B is not small beside its length 1: .* at most ±0\.1"):
        Tolerancing(crank, "point:M", ANGLES, tolerance=1e300)
    with pytest.raises(InputError, match="relative must be at most 0.1"):
        Tolerancing(crank, "point:M", ANGLES, relative=0.5)
    with pytest.raises(InputError, match="±10° on S.angle is not small beside a radian"):
        Tolerancing(crank, "point:M", ANGLES, tolerance=1e-3, tolerances={"S.angle": math.radians(10.0)})
    Tolerancing(crank, "point:M", ANGLES, tolerance=0.1)                     # a tenth of the crank: taken


def test_command_line_refuses_a_huge_tolerance_quietly():
    bad = run_cli("examples/mechanisms/slider-crank.json", "--output", "point:M", "--tolerance", "1e300")
    assert bad.returncode == 2 and bad.stdout == ""
    assert "tolerance: ±1e+300 on crank:A-B is not small beside its length 1" in bad.stderr
    assert "Warning" not in bad.stderr and "Traceback" not in bad.stderr


def test_command_line_without_any_spread_says_the_ratio_is_not_defined():
    zero = [arg for name in ("A.x", "A.y", "D.x", "D.y", "crank:A-B", "coupler:B-C", "rocker:C-D")
            for arg in ("--set", f"{name}=0")]
    out = run_cli("examples/mechanisms/four-bar.json", "--output", "angle:rocker", "--tolerance", "1e-3",
                  "--samples", "100", "--sweep", "0:90:90", *zero)
    assert out.returncode == 0, out.stderr
    assert "its σ over first order's: not defined" in out.stdout and "Warning" not in out.stderr


def test_command_line_text_labels_every_number_with_its_unit_degrees_for_angles():
    # issue 25, item 6: the table was in degrees, the summary lines in unlabelled radians
    out = run_cli("examples/mechanisms/four-bar.json", "--output", "angle:rocker", "--tolerance", "1e-3",
                  "--samples", "2000", "--sweep", "0:90:30", "--scan")
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert "(deg) at 4 input values of A (deg)" in lines[0]
    rows = [line.split() for line in lines if not line.startswith("#")]
    table = [r for r in rows if len(r) == 6]                       # input, nominal, worst, 3σ first, 3σ MC, largest
    dims = [r for r in rows if len(r) != 6]                        # name, unit, nominal, ±, share, dy/dd, its unit
    assert len(dims) == 9 and all(d[1:3] == ["file", "units"] and d[-1] == "deg/unit" for d in dims)
    units = lines[lines.index(next(x for x in lines if x.startswith("#       input"))) + 1]
    assert units.split() == ["#"] + ["deg"] * 6 and len(table) == 4
    summary = next(x for x in lines if x.startswith("# first order:"))
    worst = float(summary.split("worst case ")[1].split(" deg")[0])
    assert worst == pytest.approx(max(float(r[2]) for r in table), rel=1e-2)  # degrees, as in the table
    mc = next(x for x in lines if x.startswith("# Monte Carlo:"))
    largest = float(mc.split("largest error ")[1].split(" deg")[0])
    assert largest == pytest.approx(max(float(r[5]) for r in table), rel=1e-2)
    assert lines[lines.index(next(x for x in lines if x.startswith("# tolerances scaled"))) + 1].split() == \
        ["#", "×", "deg", "deg", "×", "samples"]
