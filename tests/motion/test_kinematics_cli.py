"""``domes kinematics`` on the example files."""

import csv
import io
import json
import math

import pytest
from kinematics_cases import EXAMPLES

from domes.cli import main

FOUR_BAR = str(EXAMPLES / "four-bar.json")


def test_json_has_residual_condition_and_dead_points(capsys, tmp_path):
    # Seed 000 T9 through the CLI: the triple rocker stops at arccos(−29/48) = 127.168899656°.
    path = tmp_path / "triple-rocker.json"

    from domes.motion.planar.examples import triple_rocker
    path.write_text(json.dumps(triple_rocker().to_dict()))
    assert main(["kinematics", str(path), "--sweep", "0:135:1", "--outputs", "angle:coupler", "--order", "1",
                 "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["status"] == "stopped"
    assert doc["steps"][-1]["input"] == pytest.approx(127)
    assert all(s["residual"] <= 1e-10 and s["condition"] >= 1 for s in doc["steps"])
    dp = doc["dead_points"][0]
    assert dp["kind"] == "limit" and dp["input"] == pytest.approx(math.degrees(math.acos(-29 / 48)), abs=1e-6)
    assert doc["steps"][30]["input"] == pytest.approx(30) and doc["steps"][30]["angle:coupler"] == pytest.approx(48.56357641, abs=1e-6)


def test_csv_columns_and_order(capsys):
    assert main(["kinematics", FOUR_BAR, "--at", str(math.pi / 3), "--outputs", "angle:coupler", "--order", "2",
                 "--format", "csv", "--angles", "rad"]) == 0
    rows = list(csv.reader(io.StringIO(capsys.readouterr().out)))
    assert rows[0] == ["input", "angle:coupler", "angle:coupler'", "angle:coupler''", "residual", "condition"]
    # Seed 000 T6 at φ1 = 60°: φ2 = 0.45921387904, φ̇2 = −0.99565664184, φ̈2 = 29.227545108 (ω = 10 rad/s).
    r = [float(x) for x in rows[1]]
    assert r[1:4] == pytest.approx([0.45921387904, -0.99565664184, 29.227545108], abs=1e-8)


def test_text_default_is_the_drawn_pose(capsys):
    assert main(["kinematics", FOUR_BAR]) == 0
    out = capsys.readouterr().out
    assert "2 of 2 groups" in out and "status: complete" in out


@pytest.mark.parametrize("argv,message", [
    (["--sweep", "0:1:x"], "--sweep"),
    (["--outputs", "angle:nope"], "output 'angle:nope'"),
    (["--input", "B"], "not a driven joint"),
])
def test_errors_exit_2(argv, message, capsys):
    assert main(["kinematics", FOUR_BAR, *argv]) == 2
    assert message in capsys.readouterr().err


def test_an_angle_many_turns_away_says_the_turns_taken_off(capsys):
    # issue 25, item 3: planar and spatial --at walked every turn; 1e300 answered or ran on
    for path, turns in ((FOUR_BAR, "+27,777"), (str(EXAMPLES.parent / "spatial" / "rssr-seed001.json"), "+27,777")):
        assert main(["kinematics", path, "--at", "1e7"]) == 0
        out = capsys.readouterr().out
        assert f"# input A{'0' if 'rssr' in path else ''}: {turns} whole turns taken off" in out
        assert [line.split()[0] for line in out.splitlines() if not line.startswith("#")][1:] == ["280"]
        assert main(["kinematics", path, "--at", "1e300"]) == 2
        assert "is too large to mean an angle" in capsys.readouterr().err


def test_missing_file_exits_2(capsys):
    assert main(["kinematics", "no-such-file.json"]) == 2
    assert "cannot read" in capsys.readouterr().err
