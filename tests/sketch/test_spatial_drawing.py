"""Drawings of spatial mechanisms (issue 15, item 5): the axonometric SVG and the page's data."""

import json
import math
import re

import numpy as np
import pytest

from domes.cli import main
from domes.motion.spatial.examples import rssr
from domes.motion.spatial.loops import Loops
from domes.sketch.spatial import project, spatial_svg

FILE = "examples/spatial/rssr-seed001.json"


def test_projection_is_a_rotation_then_a_view_from_the_side():
    p = np.array([[1.0, 0, 0], [0, 1.0, 0], [0, 0, 1.0]])
    np.testing.assert_allclose(project(p, 0.0, 0.0), [[1, 0], [0, 0], [0, 1]], atol=1e-15)
    s = project(p, 90.0, 0.0)
    np.testing.assert_allclose(s[1], [-1, 0], atol=1e-15)      # y turned onto −x
    lengths = np.linalg.norm(project(np.random.default_rng(1).normal(size=(20, 3)), 30, 20), axis=1)
    assert np.all(lengths <= np.linalg.norm(np.random.default_rng(1).normal(size=(20, 3)), axis=1) + 1e-12)


def test_the_svg_shows_the_moved_mechanism(capsys):
    assert main(["draw", FILE, "--at", "90"]) == 0
    svg = capsys.readouterr().out
    assert svg.count('class="joint') == 4 and svg.count('class="bar') == 3 and svg.count('class="axis ground"') == 2
    kin = Loops(rssr())
    moved = kin.places(kin.positions({"A0": math.radians(90)}, kin.drawn())[0])
    assert moved["A"][1] == pytest.approx(250.0)                # the crank at 90°: A on +y
    drawn = spatial_svg(rssr(), {j.name: j.at for j in rssr().joints})
    assert drawn != svg.strip()


def test_the_page_carries_every_frame_of_the_sweep(capsys):
    assert main(["draw", FILE, "--format", "html", "--sweep", "0:90:10"]) == 0
    page = capsys.readouterr().out
    data = json.loads(re.search(r"const DATA = (\{.*?\});\n", page, re.S).group(1))
    assert len(data["frames"]) == 10 and data["inputs"][-1] == pytest.approx(90.0)
    kin = Loops(rssr())
    at = kin.places(kin.positions({"A0": math.radians(90)}, kin.drawn())[0])
    np.testing.assert_allclose(data["frames"][-1]["B"], at["B"], atol=1e-9)


def test_a_point_to_trace_must_exist(capsys):
    assert main(["draw", FILE, "--coupler", "nowhere"]) == 2
    assert "--coupler ['nowhere']: not joints or points" in capsys.readouterr().err
