"""Values drawn in a notebook (docs/notebook.md): each repr parses and holds the value's drawing; what cannot be drawn
gives None; the values' layers import neither the drawings nor IPython."""

from __future__ import annotations

import doctest
import math
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

from domes.design.synthesis import synthesize
from domes.design.synthesis.candidate import Dimensioned, Dimensioning
from domes.design.synthesis.spatialresult import SpatialSynthesis
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism, load_spatial
from domes.io.tasks import load_task
from domes.model import Chain, Input, Joint, LabelledChain, Mechanism, display
from domes.motion import sweep
from domes.motion.coupler.atlas import Atlas, AtlasSpec, OpenAtlas, build, build_windows
from domes.motion.planar.examples import four_bar
from domes.motion.spatial.sweep import spatial_sweep
from domes.results import Status
from domes.sketch import notebook
from domes.typesynth import chains

ROOT = Path(__file__).resolve().parents[2]
SVG = "{http://www.w3.org/2000/svg}"


def classes(el) -> list[str]:
    return el.get("class", "").split()


def svg_root(text: str):
    root = ET.fromstring(text)
    assert root.tag == SVG + "svg"
    return root


def cards(text: str) -> list:
    """The cards of an HTML drawing, which must parse as XML and be a scoped fragment, not a page."""
    root = ET.fromstring(text)
    assert root.tag == "div" and root.get("class") == notebook.ROOT
    assert "<body" not in text and "<html" not in text
    style = root.find("style").text
    assert "body" not in style and all(line.strip().startswith(f".{notebook.ROOT}") for line in style.split("}") if line.strip())
    return [el for el in root.iter("div") if "card" in classes(el)]


def joint_circles(root) -> list:
    return [el for el in root.iter(SVG + "circle") if "joint" in classes(el)]


def test_a_chain_is_its_skeleton():
    for chain in chains(links=8, dof=1)[:4]:
        root = svg_root(chain._repr_svg_())
        joints = {el.get("data-joint") for el in joint_circles(root)}
        assert joints == {f"{u}-{v}" for u, v in chain.edges}
        drawn = {el.get("data-link") for el in root.iter() if "link" in classes(el)}
        assert drawn == {str(v) for v in range(chain.links)}


def test_a_labelled_chain_is_its_sketch():
    slider = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(0, 3): "P"},
                                 roles={0: {"ground"}, 1: {"input"}})
    root = svg_root(slider._repr_svg_())
    assert {el.get("data-joint") for el in joint_circles(root)} == {"0-1", "1-2", "2-3"}     # the R joints
    assert [el.get("data-joint") for el in root.iter(SVG + "g") if "P" in classes(el)] == ["0-3"]
    roles = {el.get("data-link"): el.text for el in root.iter(SVG + "text") if "role" in classes(el)}
    assert roles == {"0": "ground", "1": "input"}


def test_a_mechanism_is_drawn_to_scale_with_its_coupler_curve():
    mech = load_mechanism(ROOT / "examples/mechanisms/four-bar.json")
    root = svg_root(mech._repr_svg_())
    at = {el.get("data-joint"): (float(el.get("cx")), float(el.get("cy"))) for el in joint_circles(root)}
    assert set(at) == {j.name for j in mech.joints}
    given = {j.name: j.at for j in mech.joints}
    # to scale: every distance between joints in the drawing is the file's, times one scale; y points down
    pairs = [(a, b) for a in at for b in at if a < b]
    ratios = [math.dist(at[a], at[b]) / math.dist(given[a], given[b]) for a, b in pairs]
    assert max(ratios) == pytest.approx(min(ratios), rel=1e-3)
    assert (at["C"][1] < at["A"][1]) == (given["C"][1] > given["A"][1])
    points = [el.get("data-point") for el in root.iter(SVG + "circle") if "coupler-point" in classes(el)]
    assert points == [p.name for p in mech.points]
    assert any("coupler-curve" in classes(el) for el in root.iter())


def test_a_spatial_mechanism_is_drawn_at_its_pose():
    mech = load_spatial(ROOT / "examples/spatial/rssr-seed001.json")
    root = svg_root(mech._repr_svg_())
    drawn = [el for el in root.iter() if "joint" in classes(el)]
    assert sorted(c for el in drawn for c in classes(el) if c != "joint") == sorted(j.kind for j in mech.joints)


def test_a_sweep_is_a_card_per_column_over_its_input():
    sw = sweep(four_bar(), 0.0, math.pi, math.radians(5), outputs=["angle:rocker", "point:C"])
    found = cards(sw._repr_html_())
    assert [c.find("h2/span").text for c in found] == list(sw.columns)
    for card, name in zip(found, sw.columns):
        line = next(el for el in card.iter(SVG + "polyline") if "curve" in classes(el))
        assert len(line.get("points").split()) == sw.inputs.size
        values = np.degrees(sw.column(name)) if name.startswith("angle:") else sw.column(name)
        rows = dict(zip([dt.text for dt in card.iter("dt")], [dd.text for dd in card.iter("dd")]))
        assert rows["range"] == f"{values.min():.6g} to {values.max():.6g}"


def test_a_long_sweep_is_plotted_by_some_of_its_steps(monkeypatch):
    monkeypatch.setattr(notebook, "PLOTTED", 50)
    sw = sweep(four_bar(), 0.0, 2 * math.pi, math.radians(1), outputs=["angle:rocker"])
    (card,) = cards(sw._repr_html_())
    line = next(el for el in card.iter(SVG + "polyline") if "curve" in classes(el))
    assert len(line.get("points").split()) == 50
    rows = dict(zip([dt.text for dt in card.iter("dt")], [dd.text for dd in card.iter("dd")]))
    rocker = np.degrees(sw.column("angle:rocker"))
    assert rows == {"range": f"{rocker.min():.6g} to {rocker.max():.6g}", "steps": f"{sw.inputs.size}, 50 plotted"}


def test_a_spatial_sweep_is_drawn_too():
    mech = load_spatial(ROOT / "examples/spatial/rssr-seed001.json")
    sw = spatial_sweep(mech, 0.0, math.pi / 2, math.radians(10))
    assert len(cards(sw._repr_html_())) == len(sw.table)


def test_a_chain_atlas_is_its_cards(monkeypatch):
    atlas = chains(links=6, dof=1)
    found = cards(atlas._repr_html_())
    assert len(found) == len(atlas) == 2
    for card, chain in zip(found, atlas):
        svg = next(el for el in card.iter(SVG + "svg"))
        assert len(joint_circles(svg)) == chain.joints
    monkeypatch.setattr(notebook, "CHAINS_SHOWN", 5)
    bigger = chains(links=8, dof=1)
    text = bigger._repr_html_()
    assert len(cards(text)) == 5 and f"{len(bigger)} chains" in text and "the first 5 drawn" in text


def test_coupler_curve_atlases_show_rows_spread_over_them(monkeypatch):
    monkeypatch.setattr(notebook, "CURVES_SHOWN", 3)
    table = build(AtlasSpec("tiny", 3, 4.0))
    for value in (table, Atlas(table)):
        found = cards(value._repr_html_())
        assert len(found) == 3
        for card in found:
            row = int(card.get("data-id"))
            rows = dict(zip([dt.text for dt in card.iter("dt")], [dd.text for dd in card.iter("dd")]))
            assert rows["a, b, c, d"] == ", ".join(f"{x:.4f}" for x in table.lengths(row))
            assert any("coupler-curve" in classes(el) for el in card.iter())
    assert {int(c.get("data-id")) for c in cards(table._repr_html_())} >= {0, table.count - 1}
    windows = build_windows(AtlasSpec("tiny", 2, 4.0))
    found = cards(OpenAtlas(windows)._repr_html_())
    assert len(found) == 3 and all("window" in [dt.text for dt in c.iter("dt")] for c in found)


def test_a_synthesis_is_a_card_per_solution_at_its_positions():
    result = synthesize(load_task(ROOT / "examples/synthesis/ch2-example-2-slider.json"))
    found = cards(result._repr_html_())
    assert len(found) == len(result.solutions) > 0
    for card, solution in zip(found, result.solutions):
        poses = [el for el in card.iter(SVG + "g") if "pose" in classes(el)]
        assert len(poses) == len(solution.poses)
        assert (card.get("class") == "card marked") == (not solution.usable)


def test_a_dimensioning_draws_each_layout_beside_its_curve():
    mech = four_bar()
    sw = sweep(mech, 0.0, math.pi / 2, math.radians(10), outputs=["angle:rocker"])
    x, achieved = np.degrees(sw.inputs), np.degrees(sw.column("angle:rocker"))
    good = Dimensioned(1, mech, tuple(x), tuple(achieved), tuple(achieved + 0.1), 0.01, 0.005, 40.0, None)
    bad = Dimensioned(2, mech, tuple(x), tuple(achieved), tuple(achieved + 5), 0.2, 0.1, 12.0, None, ("too far",))
    result = Dimensioning("rocker", (good, bad), (1, 2), 100, 10, 0.5)
    found = cards(result._repr_html_())
    assert [c.get("class") for c in found] == ["card", "card marked"]
    for card in found:
        assert len(joint_circles(card)) == len(mech.joints)
        lines = {classes(el)[1]: el for el in card.iter(SVG + "polyline") if "curve" in classes(el)}
        assert set(lines) == {"achieved", "wanted"}
        assert all(len(el.get("points").split()) == x.size for el in lines.values())


def test_a_spatial_synthesis_draws_each_mechanism():
    mech = load_spatial(ROOT / "examples/spatial/rssr-seed001.json")
    result = SpatialSynthesis("demo", "rssr", Status.COMPLETE, ("one linkage",), (mech, mech))
    found = cards(result._repr_html_())
    assert len(found) == 2 and all(len(list(c.iter(SVG + "svg"))) == 1 for c in found)
    assert cards(SpatialSynthesis("none", "rccc", Status.EMPTY, ())._repr_html_()) == []


def test_what_cannot_be_drawn_gives_none_and_draw_says_why():
    apart = Chain(4, [(0, 1), (2, 3)])
    two = LabelledChain.build(2, [(0, 1)])
    at_toggle = Mechanism.build(   # driven by the rocker, drawn where crank and coupler are in line: a dead point
        "toggle", ["frame", "crank", "coupler", "rocker"], "frame",
        [Joint("A", "R", ("frame", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
         Joint("C", "R", ("coupler", "rocker"), (4.5, 0.0)), Joint("D", "R", ("rocker", "frame"), (3.0, 2.0))],
        [Input("D", 1.0)])
    for value, why in ((apart, "not connected"), (two, "at least two joints"), (at_toggle, "collinear")):
        assert value._repr_svg_() is None
        with pytest.raises(InputError, match=why):
            display.draw(value, "svg")
    assert display.render(object(), "svg") is None
    with pytest.raises(InputError, match="no html drawing of a Chain"):
        display.draw(apart, "html")


def test_a_renderer_that_fails_in_any_way_gives_none():
    class Broken:
        def _repr_svg_(self):
            return display.render(self, "svg")

    class NotText(Broken):
        pass

    display.register(Broken, "svg", lambda value: 1 / 0)
    display.register(NotText, "svg", lambda value: 42)
    assert Broken()._repr_svg_() is None and NotText()._repr_svg_() is None
    with pytest.raises(ZeroDivisionError):
        display.draw(Broken(), "svg")
    with pytest.raises(InputError, match="not text"):
        display.draw(NotText(), "svg")
    with pytest.raises(InputError, match="svg, html"):
        display.register(Broken, "png", str)


def test_ipython_shows_the_drawings():
    pytest.importorskip("IPython")
    from IPython.core.formatters import DisplayFormatter

    formatter = DisplayFormatter()
    data, _ = formatter.format(Chain.from_graph6("Cr"))
    assert data["image/svg+xml"].startswith("<svg")
    data, _ = formatter.format(chains(links=6, dof=1))
    assert data["text/html"].count('class="card"') == 2
    data, _ = formatter.format(Chain(4, [(0, 1), (2, 3)]))
    assert "image/svg+xml" not in data and "text/plain" in data


def test_the_values_import_neither_drawings_nor_ipython():
    code = ("import sys, domes.model, domes.typesynth, domes.design.synthesis, domes.motion.coupler.atlas\n"
            "print(sorted(m for m in sys.modules if m.startswith(('domes.sketch', 'IPython', 'domes.model.display'))))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def test_the_notebook_doc_runs():
    result = doctest.testfile(str(ROOT / "docs/notebook.md"), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0 and result.attempted > 10
