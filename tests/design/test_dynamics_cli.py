"""``domes dynamics`` (issue 16, item 6): the document it writes is the library's result; mistakes are named."""

import json

import pytest

from domes.cli import main

ENGINE = "examples/dynamics/slider-crank-engine.json"
SCRIBER = "examples/dynamics/scriber-stadium.json"


def run(capsys, *words):
    status = main(["dynamics", *words])
    out = capsys.readouterr()
    return status, out.out, out.err


def test_mechanism_json_and_csv(capsys):
    import math

    from domes.design.dynamics import inverse_dynamics
    from domes.io.mechanisms import load_mechanism

    status, out, _ = run(capsys, ENGINE, "--sweep", "0:360:10", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and doc["status"] == "complete" and doc["max_imbalance"] < 1e-12
    dyn = inverse_dynamics(load_mechanism(ENGINE), 0.0, 2 * math.pi, math.radians(10))
    assert doc["columns"]["drive:A"] == pytest.approx(dyn.driving["A"].tolist(), rel=1e-12)
    assert doc["drives"]["A"]["kind"] == "torque"
    status, out, _ = run(capsys, ENGINE, "--sweep", "0:360:10", "--format", "csv")
    lines = out.strip().splitlines()
    assert len(lines) == 38 and lines[0].startswith("input (deg),time,drive:A,reaction:A.x")


def test_speed_knob_scales_the_inertia_forces(capsys):
    # without gravity and loads the torque would scale with the speed squared; here the gas force and gravity
    # stay, so only the difference of two speeds scales
    docs = []
    for speed in ("9000", "18000", "36000"):
        _, out, _ = run(capsys, ENGINE, "--sweep", "10:350:20", "--speed", speed, "--format", "json")
        docs.append(json.loads(out)["columns"]["drive:A"])
    import numpy as np
    a, b, c = (np.array(d) for d in docs)
    np.testing.assert_allclose(c - a, 5.0 * (b - a), rtol=1e-9, atol=1e-9)


def test_gear_and_cam_contacts_are_reported(capsys, tmp_path):
    import math

    data = json.loads(open("examples/mechanisms/planetary.json").read())
    data["loads"] = [{"name": "out", "link": "arm", "torque": 5.0}]
    (tmp_path / "planetary.json").write_text(json.dumps(data))
    status, out, _ = run(capsys, str(tmp_path / "planetary.json"), "--sweep", "0:360:30", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and doc["max_imbalance"] < 1e-12 and doc["pressure_angle_deg"] == 20.0
    assert doc["columns"]["drive:O"] == pytest.approx([-5.0 * 20 / 72] * 13, rel=1e-12)     # Willis
    assert doc["contacts"]["SP"]["kind"] == "tooth force" and doc["contacts"]["SP"]["pair"] == "gear"
    tangential = 5.0 / (2 * 1.8)                                                            # the planet's free body
    assert [abs(v) for v in doc["columns"]["contact:SP"]] == pytest.approx([tangential / math.cos(math.radians(20))] * 13)
    status, out, _ = run(capsys, str(tmp_path / "planetary.json"), "--sweep", "0:360:30", "--pressure-angle", "0")
    assert status == 0 and "contact:SP" in out and "# SP: gear pair, peak tooth force -1.38889" in out
    status, out, _ = run(capsys, str(tmp_path / "planetary.json"), "--sweep", "0:360:30", "--format", "csv")
    assert "contact:SP,contact:SP.x,contact:SP.y,contact:PR" in out.splitlines()[0]
    cam = json.loads(open("examples/mechanisms/cam-rocker.json").read())
    cam["loads"] = [{"name": "weight", "link": "follower", "force": [0.0, -20.0], "at": [0.0, 2.0]}]
    (tmp_path / "cam.json").write_text(json.dumps(cam))
    status, out, _ = run(capsys, str(tmp_path / "cam.json"), "--sweep", "0:360:30", "--format", "json")
    doc = json.loads(out)
    assert status == 0 and doc["contacts"]["K"] == {"kind": "force", "pair": "cam (translating follower)",
                                                    "peak": pytest.approx(20.0), "at": 0.0}
    assert "pressure_angle_deg" in doc and doc["pressure_angle_deg"] is None


def test_scriber_text_and_json(capsys):
    status, out, _ = run(capsys, SCRIBER, "--points", "400")
    assert status == 0 and "junction 1 at s = 0.1: corner 0°" in out and "lines: Q in" in out
    status, out, _ = run(capsys, SCRIBER, "--points", "400", "--kinetic", "paper", "--equations", "printed",
                         "--format", "json")
    doc = json.loads(out)
    assert doc["max_imbalance"] > 0.1            # the printed equations break the power balance (D-7)
    assert len(doc["columns"]["Q1"]) == 400 and len(doc["junctions"]) == 4


def test_scriber_out_of_stroke_stops_and_exits_1(capsys, tmp_path):
    # issue 25, item 4: 4,000 rows and exit 0 although the contour leaves the stroke
    task = json.loads(open(SCRIBER).read())
    task["contour"] = {"start": [0.25, 0.1085], "segments": [{"line": [0.45, 0.1085]}, {"line": [0.25, 0.1085]}]}
    (tmp_path / "far.json").write_text(json.dumps(task))
    status, out, err = run(capsys, str(tmp_path / "far.json"))
    rows = [line for line in out.splitlines() if not line.startswith("#")]
    assert status == 1 and len(rows) == 914 and float(rows[-1].split()[1]) < 0.3414
    assert "stopped: the contour leaves the scriber's reach at s = 0.0913616 (x = 0.341362, y = 0.1085): the " \
           "stroke ends there" in err


def test_overflowing_forces_exit_2_with_the_reason(capsys):
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")                                    # no RuntimeWarning reaches the user
        status, out, err = run(capsys, ENGINE, "--sweep", "0:180:90", "--speed", "1e300")
    assert status == 2 and out == "" and "the forces overflow the floating-point range" in err


@pytest.mark.parametrize("words, message", [
    ([ENGINE, "--points", "10"], "--points is for a scriber task file"),
    ([SCRIBER, "--sweep", "0:1:1"], "--sweep is for a mechanism file"),
    ([SCRIBER, "--points", "1"], "points: an integer from 2"),
    ([ENGINE, "--sweep", "0:360:0.00001"], "at most 1,000,000"),
    ([ENGINE, "--speed", "nan"], "--speed: must be a finite number"),
    ([ENGINE, "--input", "B"], "not a driven joint"),
    ([ENGINE, "--pressure-angle", "90"], "--pressure-angle: must be at least 0 and below 90"),
])
def test_mistakes_are_named(capsys, words, message):
    status, _, err = run(capsys, *words)
    assert status == 2 and message in err
