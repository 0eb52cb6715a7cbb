"""``domes curves``: classify, trace, describe, atlas and match from the command line."""

import json
from pathlib import Path

import numpy as np
import pytest

from domes.cli import main
from domes.io.atlas import save_atlas
from domes.io.curves import points_csv, read_points
from domes.motion.coupler.atlas import AtlasSpec, build
from domes.motion.coupler.curves import trace
from domes.motion.coupler.fourbar import four_bar

ROOT = Path(__file__).resolve().parents[2]


def test_classify_text_and_json(capsys):
    assert main(["curves", "classify", "1", "1.25", "0.25", "1.5"]) == 0
    assert "region 2" in capsys.readouterr().out
    assert main(["curves", "classify", "1", "1", "1", "1", "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["region"] is None and doc["regions"] == list(range(1, 9))
    assert main(["curves", "classify", "1", "1", "1", "3"]) == 2
    assert "at least as long as the other three" in capsys.readouterr().err


def test_trace_formats(capsys, tmp_path):
    args = ["curves", "trace", "--four-bar", "0.4", "1.2", "1.0", "1.4", "1.3076", "0.2058", "--samples", "360"]
    assert main(args) == 0
    out = capsys.readouterr().out
    assert "2 circuits" in out and "cusps (1.2188" in out
    assert main(args + ["--format", "csv", "-o", str(tmp_path / "c.csv")]) == 0
    lines = (tmp_path / "c.csv").read_text().splitlines()
    assert lines[0] == "circuit,index,input_deg,x,y" and len(lines) == 1 + 720
    assert main(args + ["--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert len(doc["circuits"]) == 2 and len(doc["circuits"][0]["cusps"]) == 1
    assert main(args + ["--format", "html", "-o", str(tmp_path / "c.html")]) == 0
    page = (tmp_path / "c.html").read_text()
    assert page.count('class="card"') == 2 and "<animate " in page
    assert main(["curves", "trace", str(ROOT / "examples/mechanisms/stephenson-six-bar.json"), "--point", "T"]) == 0
    assert "4 circuits" in capsys.readouterr().out


def test_trace_errors(capsys):
    assert main(["curves", "trace"]) == 2
    assert "give a mechanism file" in capsys.readouterr().err
    assert main(["curves", "trace", str(ROOT / "examples/mechanisms/eight-bar-class-iv.json"), "--point", "K"]) == 2
    assert "Newton" in capsys.readouterr().err


def test_describe_points_file(capsys, tmp_path):
    pts = trace(four_bar(1, 3.5, 3, 2, 0, -2), "P", 360).circuits[0].points
    path = tmp_path / "eight.csv"
    path.write_text("# the figure-eight\n" + points_csv(pts))
    assert np.allclose(read_points(path), pts)
    assert main(["curves", "describe", str(path)]) == 0
    out = capsys.readouterr().out
    assert "fuzzy type II" in out and "a[+1] =  1.000000" in out
    bad = tmp_path / "bad.csv"
    bad.write_text("x,y\n1,2\n3,four\n")
    assert main(["curves", "describe", str(bad)]) == 2
    assert "line 3" in capsys.readouterr().err


def test_atlas_and_match(capsys, tmp_path, monkeypatch):
    # A small atlas file; the wanted path is a curve of one of its own linkages at another coupler point, moved.
    atlas = tmp_path / "a.h5"
    save_atlas(build(AtlasSpec("test", 60, 1.0)), atlas)
    assert main(["curves", "atlas", "info", "--file", str(atlas)]) == 0
    assert "60 four-bars" in capsys.readouterr().out
    pts = trace(four_bar(1, 3.5, 2.5, 3, 1.2, 0.9), "P", 720).circuits[0].points[::12] * 5 + [100, 50]
    wanted = tmp_path / "wanted.csv"
    wanted.write_text(points_csv(pts))
    best = tmp_path / "best.json"
    code = main(["curves", "match", str(wanted), "--atlas", str(atlas), "--results", "1", "--save", str(best),
                 "--format", "json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 0 and doc["fits"][0]["success"] and best.is_file()
    assert doc["fits"][0]["after"]["max"] <= 1e-6 * doc["size"]
    assert main(["curves", "match", str(wanted), "--atlas", str(tmp_path / "none.h5")]) == 2
    assert "no atlas file" in capsys.readouterr().err


@pytest.mark.slow
def test_documented_match_builds_the_small_atlas(capsys, tmp_path, monkeypatch):
    monkeypatch.setenv("DOMES_HOME", str(tmp_path))
    assert main(["curves", "match", str(ROOT / "examples/curves/figure-eight.csv"), "--format", "html", "-o",
                 str(tmp_path / "m.html")]) == 0
    assert (tmp_path / "atlas" / "fourbar-small.h5").is_file()
    page = (tmp_path / "m.html").read_text()
    # the three fits are one linkage, driven from either pivot, and its cognate: one card, the others merged into it
    assert page.count('class="card"') == 1 and page.count('class="wanted"') == 48 and page.count("merged") >= 2


def test_match_names_what_it_cannot_do(capsys, tmp_path):
    # Issue 25, item 4: four points on a line answered "largest distance nan" (exit 1).
    path = tmp_path / "line.csv"
    path.write_text("0,0\n1,2\n2,4\n3,6\n")
    assert main(["curves", "match", str(path), "--atlas", str(tmp_path / "none.h5")]) == 2
    err = capsys.readouterr().err
    assert "needs at least 9 points" in err and "got 4" in err and "nan" not in err
