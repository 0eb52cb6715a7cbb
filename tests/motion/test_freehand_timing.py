"""Paths drawn by hand with their timing: the crank's angle, or the time, at each point (issue 27, item 3)."""

import json
import runpy
from pathlib import Path

import numpy as np
import pytest

from domes.errors import InputError
from domes.io.curves import read_timing
from domes.motion.coupler.curves import trace
from domes.motion.coupler.fourbar import four_bar
from domes.motion.coupler.freehand import match_drawn
from domes.motion.coupler.timing import TimedFit, Timing, schedule
from domes.motion.planar.batch import batch
from tests.shared import shared_file

ROOT = Path(__file__).resolve().parents[2]
LOOP = ROOT / "examples/curves/timed-loop.csv"


def timed_sample(seed, count=60, noise=0.01):
    """A random crank-rocker's curve (random lengths and coupler point, not an atlas point): ``count`` points at
    random crank angles (the kernel's trace gives each point's angle), noise of ``noise`` times the size added to
    each coordinate; returns ``(curve, size, clean points, their crank angles in degrees, noisy points)``.
    (``benchmarks/bench_freehand_timed.py`` draws its cases with it.)"""
    rng = np.random.default_rng(seed)
    while True:
        lengths, uv = rng.uniform(0.3, 1.7, 4), rng.uniform(-3, 3, 2)
        try:
            circuit = trace(four_bar(*lengths, *uv), "P", 720).circuits[0]
        except InputError:
            continue
        if circuit.full_turn:
            break
    size = float(np.max(np.ptp(circuit.points, axis=0)))
    idx = np.sort(rng.choice(len(circuit.points), count, replace=False))
    clean, angles = circuit.points[idx], np.degrees(np.unwrap(circuit.inputs))[idx]
    return circuit.points, size, clean, angles, clean + rng.normal(0, noise * size, clean.shape)


def _dense_distances(mech, points, samples=20000):
    """Brute force, independent of the code under test: each point's distance from the nearest of ``samples``
    points per turn of the circuit of the traced curve the points are nearest (RMS)."""
    per = [np.array([np.min(np.hypot(*(c.points - p).T)) for p in points]) for c in trace(mech, "P", samples).circuits]
    return min(per, key=lambda d: np.mean(d ** 2))


@pytest.mark.parametrize("kind", ["angle", "time"])
def test_a_noisy_timed_curve_recovers_a_linkage_that_keeps_the_timing(kind, small_atlas):
    # Issue 27 acceptance (freehand, with the timing given): noise of 1% of the size added to a four-bar's curve
    # still recovers a linkage within 2% of it, and the linkage meets the points at their given timing. Crank
    # angles: their zero is free; times: the crank turning at 90° a unit of time, which the fit finds.
    # (One curve of each kind here; 20 in benchmarks/bench_freehand_timed.py, docs/curves.md.)
    curve, size, clean, angles, noisy = timed_sample(27 if kind == "angle" else 5)
    timing = (Timing(tuple(angles - angles[0] + 17.0)) if kind == "angle" else
              Timing(tuple((angles - angles[0]) / 90.0 + 3.0), "time"))
    m = match_drawn(noisy, small_atlas, results=1, closed=True, timing=timing)
    best = m.fits[0]
    assert isinstance(best, TimedFit) and "at their timing" in m.message
    # the curve: every point of the noise-free curve within 2% of the size of the found linkage's curve
    assert np.max(_dense_distances(best.mechanism, curve[::6])) <= 0.02 * size, m.message
    # the timing: the crank angles the fit reports differ from the given ones by one offset (and for times by the
    # speed found, within 1% of 90°/unit) ...
    given = angles if kind == "angle" else 90.0 * (np.array(timing.values) - timing.values[0])
    scale = 1.0 if kind == "angle" else best.speed / 90.0
    assert kind == "angle" or best.speed == pytest.approx(90.0, rel=0.01)
    offset = np.remainder(np.array(best.angles) - scale * given + 180.0, 360.0) - 180.0
    assert np.ptp(offset) < 1e-6
    # ... and the kernel, driving the found linkage to those angles, puts its coupler point within 2% of the size of
    # each noise-free point, and measures the user's noisy points where the answer says
    b = batch(best.mechanism, inputs=np.radians(best.angles), outputs=["point:P"])
    driven = np.c_[b.values["point:P.x"][0], b.values["point:P.y"][0]]
    assert np.max(np.hypot(*(driven - clean).T)) <= 0.02 * size
    mine = np.hypot(*(driven - noisy).T)
    assert best.after == pytest.approx((np.max(mine), np.sqrt(np.mean(mine ** 2))), rel=1e-9)


def test_an_untimed_sketch_is_matched_against_its_curve_as_before():
    # No timing: match_drawn's answer is an untimed fit (the timed route is not taken) and its message says the
    # errors are distances from the traced curve. (The untimed route's results: tests/motion/test_freehand.py.)
    from domes.motion.coupler.atlas import Atlas, AtlasSpec, build

    atlas = Atlas(build(AtlasSpec("test", 12, 1.0)))
    _, _, _, _, noisy = timed_sample(3, 40)
    m = match_drawn(noisy, atlas, results=1, candidates=2, closed=True)
    assert m.fits and not isinstance(m.fits[0], TimedFit) and m.message.endswith("traced curve")


def test_bad_timing_is_refused_saying_what_and_where():
    ring = np.c_[np.cos(np.linspace(0, 6, 30)), np.sin(np.linspace(0, 6, 30))]
    every = list(range(30))
    angles = list(np.linspace(0, 340, 30))
    with pytest.raises(InputError, match="29 values for 30 points"):
        schedule(Timing(tuple(angles[:-1])), 30, every, True)
    with pytest.raises(InputError, match="point 4 is not a finite number: nan"):
        schedule(Timing(tuple(angles[:4] + [float("nan")] + angles[5:])), 30, every, True)
    back = angles[:10] + [angles[8]] + angles[11:]
    with pytest.raises(InputError, match="turn one way: point 10's angle 93.7931 is not beyond point 9's 105.517"):
        schedule(Timing(tuple(back)), 30, every, True)
    assert schedule(Timing(tuple(back)), 30, every, False).rotations.size == 29       # an open path may swing back
    with pytest.raises(InputError, match="turns it by 377"):
        schedule(Timing(tuple(np.linspace(0, 377, 30))), 30, every, True)
    times = list(np.linspace(0, 2, 30))
    with pytest.raises(InputError, match="times must increase: point 7's time 0.413793 is not after point 6's"):
        schedule(Timing(tuple(times[:7] + [times[6]] + times[8:]), "time"), 30, every, False)
    with pytest.raises(InputError, match="goes with times"):
        schedule(Timing(tuple(angles), speed=90), 30, every, True)
    with pytest.raises(InputError, match="non-zero number of degrees per unit of time, got 0"):
        schedule(Timing(tuple(times), "time", speed=0), 30, every, True)
    with pytest.raises(InputError, match="timing kind 'speed'"):
        schedule(Timing(tuple(times), "speed"), 30, every, True)
    # repeated points are dropped with their timing; the times checked are those of the points kept
    assert schedule(Timing(tuple(times), "time", 180.0), 30, [0, 2, 3], False).rotations.size == 2
    # match_drawn checks the timing before it looks anything up
    with pytest.raises(InputError, match="29 values for 30 points"):
        match_drawn(ring, None, timing=angles[:-1])


def test_the_timed_example_is_made_in_the_repository():
    script = runpy.run_path(str(ROOT / "examples/curves/timed.py"))
    assert script["loop_csv"](script["timed_loop"]()) == LOOP.read_text()


def test_path_files_give_their_timing(tmp_path):
    (tmp_path / "a.csv").write_text("# drawn\nx,y,angle\n0,0,10\n1,0,20\n")
    assert read_timing(tmp_path / "a.csv") == ("angle", [10.0, 20.0], None)
    (tmp_path / "plain.csv").write_text("x,y\n0,0\n1,0\n")
    assert read_timing(tmp_path / "plain.csv") is None
    (tmp_path / "gap.csv").write_text("x,y,time\n0,0,0\n1,0\n")
    with pytest.raises(InputError, match="gap.csv, line 3: no time"):
        read_timing(tmp_path / "gap.csv")
    (tmp_path / "t.json").write_text(json.dumps({"points": [[0, 0], [1, 0]], "times": [0, 0.5], "speed": 90}))
    assert read_timing(tmp_path / "t.json") == ("time", [0.0, 0.5], 90.0)
    (tmp_path / "bad.json").write_text(json.dumps({"points": [[0, 0], [1, 0]], "angles": [0, "x"]}))
    with pytest.raises(InputError, match=r"angles\[1\]: expected a finite number"):
        read_timing(tmp_path / "bad.json")
    (tmp_path / "both.json").write_text(json.dumps({"points": [[0, 0]], "angles": [0], "speed": 9}))
    with pytest.raises(InputError, match="\"speed\" goes with \"times\", not with \"angles\""):
        read_timing(tmp_path / "both.json")


def test_the_command_fits_a_timed_path(tmp_path, tmp_path_factory, monkeypatch, capsys):
    # a quick atlas (40 four-bars, built once in a test run: tests/shared.py): the command's route, not its quality
    from domes.cli import main
    from domes.io.atlas import save_atlas
    from domes.motion.coupler.atlas import AtlasSpec, build

    monkeypatch.setenv("DOMES_HOME", str(tmp_path))
    spec = AtlasSpec("test", 40, 1.0)
    atlas = str(shared_file(tmp_path_factory, "fourbar-test40.h5", lambda path: save_atlas(build(spec), path)))
    rows = np.loadtxt(LOOP, delimiter=",", skiprows=1)
    half = tmp_path / "half.json"                      # every other point (closed, as said): the route, in less time
    half.write_text(json.dumps({"points": rows[::2, :2].tolist(), "times": rows[::2, 2].tolist(), "closed": True}))
    status = main(["curves", "match", str(half), "--drawn", "--atlas", atlas, "--results", "1", "--candidates", "1",
                   "--speed", "180", "--format", "json"])
    out = capsys.readouterr()
    assert status in (0, 1), out.err
    doc = json.loads(out.out)
    timed = doc["fits"][0]["timing"]
    assert "crank's speed 180°/unit" in doc["message"] and len(timed["angles_deg"]) == 36
    assert np.allclose(np.diff(timed["angles_deg"]), 180.0 * np.diff(rows[::2, 2]))     # the timing, kept
    assert timed["speed_deg_per_unit"] == 180.0
    (tmp_path / "plain.csv").write_text("x,y\n" + "".join(f"{x},{y}\n" for x, y, _ in rows))
    assert main(["curves", "match", str(tmp_path / "plain.csv"), "--drawn", "--speed", "90", "--atlas", atlas]) == 2
    assert "gives no times" in capsys.readouterr().err
    assert main(["curves", "match", str(LOOP), "--atlas", atlas]) == 2
    assert "give --drawn" in capsys.readouterr().err
    (tmp_path / "short.json").write_text(json.dumps({"points": rows[:, :2].tolist(), "times": rows[1:, 2].tolist()}))
    assert main(["curves", "match", str(tmp_path / "short.json"), "--drawn", "--atlas", atlas]) == 2
    assert "short.json: the timing has 71 values for 72 points" in capsys.readouterr().err
