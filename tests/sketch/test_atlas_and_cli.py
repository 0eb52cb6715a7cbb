"""The HTML atlas page, `domes chains --format html` and `domes draw`."""

import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

import domes.sketch.atlas as atlas
from domes.cli import main
from domes.errors import DomesError
from domes.sketch import Card, atlas_html, chain_atlas_html
from domes.typesynth import chains

XHTML = "{http://www.w3.org/1999/xhtml}"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def _cards(page):
    assert page.startswith("<!DOCTYPE html>\n")
    root = ET.fromstring(page[len("<!DOCTYPE html>\n") :])  # the page is well-formed XML
    return [el for el in root.iter(XHTML + "div") if "card" in el.get("class", "").split()]


def test_eight_bar_atlas_page_has_a_drawn_card_per_chain():
    # seed 002 §3-2-II: the 16 one-DOF eight-bar chains, one card each with id, properties and drawing
    atlas = chains(links=8, dof=1)
    cards = _cards(chain_atlas_html(atlas))
    assert [c.get("data-id") for c in cards] == [str(i) for i in range(1, 17)]
    for card, chain in zip(cards, atlas):
        (svg,) = card.iter("{http://www.w3.org/2000/svg}svg")
        joints = [el for el in svg.iter() if el.get("class") == "joint"]
        assert len(joints) == chain.joints == 10
        values = [dd.text for dd in card.iter(XHTML + "dd")]
        assert chain.graph6 in values


def test_marked_card_and_escaping():
    page = atlas_html([Card("7", "a < b & c", "<svg/>", (("note", "<x>"),), badge="existing design")], "T & T")
    (card,) = _cards(page)
    assert card.get("class") == "card marked"
    assert "a &lt; b &amp; c" in page and "&lt;x&gt;" in page


def test_chains_cli_html(capsys):
    assert main(["chains", "--links", "6", "--dof", "1", "--format", "html"]) == 0
    assert len(_cards(capsys.readouterr().out)) == 2  # Watt and Stephenson


def test_a_chain_that_cannot_be_drawn_gets_a_placeholder_card(monkeypatch):
    # The page is still written when one layout fails; the card says why.
    def refuse(chain):
        raise DomesError("no planar part found")

    monkeypatch.setattr(atlas, "skeleton_layout", refuse)
    page = chain_atlas_html(chains(links=6, dof=1))
    assert len(_cards(page)) == 2 and page.count('class="not-drawn"') == 2
    assert "not drawn: no planar part found" in page


def test_chains_cli_html_with_cut_links_and_a_bridge(capsys):
    # the 8-link DOF-3 atlas with cut links includes two four-bar loops joined by one joint
    assert main(["chains", "--links", "8", "--dof", "3", "--include-fractionated", "--format", "html"]) == 0
    page = capsys.readouterr().out
    assert len(_cards(page)) == 7 and "not-drawn" not in page


def test_draw_cli_writes_svg_and_html(tmp_path, capsys):
    target = tmp_path / "watt.svg"
    graph6 = chains(links=6, dof=1)[0].graph6
    assert main(["draw", graph6, "--graph", "-o", str(target)]) == 0
    root = ET.parse(target).getroot()
    assert root.get("width") == "440.00"
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".draw-")]  # no temporary file left
    assert main(["draw", graph6, "--ground", "0", "--input", "2", "--role", "3=swing_arm", "--format", "html"]) == 0
    (card,) = _cards(capsys.readouterr().out)
    assert "ground-pivot" in ET.tostring(card, encoding="unicode")


@pytest.mark.parametrize(
    "args, message",
    [  # E_lo: the Watt chain, joints 0-1 0-4 1-5 2-4 2-5 3-4 3-5
        (["draw", "not-graph6"], "not a graph6 string"),
        (["draw", "E_lo", "--joint", "0-1=Q"], "unknown joint type"),
        (["draw", "E_lo", "--joint", "0-0=P"], "not jointed"),
        (["draw", "E_lo", "--role", "swing_arm"], "expected LINK=NAME"),
        (["draw", "E_lo", "--size", "5"], "--size"),
    ],
)
def test_draw_cli_errors(args, message, capsys):
    assert main(args) == 2
    assert message in capsys.readouterr().err


def test_draw_is_byte_identical_across_processes(tmp_path):
    # same input, same bytes: two interpreters with different hash seeds
    graph6 = chains(links=10, dof=1)[100].graph6
    outputs = []
    for seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        run = subprocess.run([sys.executable, "-m", "domes", "draw", graph6, "--graph"], cwd=ROOT, env=env, capture_output=True, check=True)
        outputs.append(run.stdout)
    assert outputs[0] == outputs[1] and outputs[0].startswith(b"<svg")
