"""`domes regenerate SCENE --format html`: the candidates' atlas page, read back from its HTML and SVG."""

import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import networkx as nx

import domes.sketch.atlas as atlas
from domes.cli import main
from domes.errors import DomesError
from domes.typesynth import chains

XHTML = "{http://www.w3.org/1999/xhtml}"
SVG = "{http://www.w3.org/2000/svg}"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
# Suzuki RM-250X full floater, seed 002 §4-1 (digest 2.2): links 1..6 as 0..5, ground 1,
# swing arm 3, shock absorber 5-6 (pair g).
SUZUKI_PAIRS = [(0, 1), (0, 2), (1, 3), (2, 3), (1, 4), (2, 5), (4, 5)]
SUZUKI_ROLES = {0: "ground", 2: "swing_arm", 4: "shock_absorber", 5: "shock_absorber"}


def _graph(edges, roles):
    g = nx.Graph(edges)
    nx.set_node_attributes(g, {v: roles.get(v, "") for v in g}, "role")
    return g


def _same(g, h):
    return nx.is_isomorphic(g, h, node_match=lambda a, b: a["role"] == b["role"])


def _book_candidates():
    """Yan's rules (§4-1, digest 2.2) by brute force over numbered links, then classes by networkx (VF2)."""
    found = []
    for chain in chains(links=6, dof=1):  # Watt and Stephenson
        g = chain.to_networkx()
        for ground in g:
            for a, b in g.edges:
                if ground in (a, b) or g.degree(a) != 2 or g.degree(b) != 2:
                    continue
                for arm in g:
                    if arm in (ground, a, b) or not g.has_edge(arm, ground):
                        continue
                    candidate = _graph(g.edges, {ground: "ground", a: "shock_absorber", b: "shock_absorber", arm: "swing_arm"})
                    if not any(_same(candidate, other) for other in found):
                        found.append(candidate)
    return found


def _read_card(card):
    """``(graph with roles, marked)`` read from a card: joints from its property list, roles from its drawing."""
    values = dict(zip((dt.text for dt in card.iter(XHTML + "dt")), (dd.text for dd in card.iter(XHTML + "dd"))))
    edges = [tuple(map(int, pair.split("-"))) for pair in values["joints"].split()]
    (svg,) = card.iter(SVG + "svg")
    roles = {}
    for el in svg.iter():
        classes = el.get("class", "").split()
        if "link" in classes and el.get("fill") == "url(#hatch)":  # the ground: hatched
            roles[int(el.get("data-link"))] = "ground"
        elif "member" in classes and "shock" in classes:  # cylinder-and-rod with its spring
            assert any("shock-absorber" in c.get("class", "") for c in el.iter())
            assert any("shock-spring" in c.get("class", "") for c in el.iter())
            for v in el.get("data-links").split("-"):
                roles[int(v)] = "shock_absorber"
        elif "role" in classes and el.text == "swing arm":
            roles[int(el.get("data-link"))] = "swing_arm"
    ground = [v for v, r in roles.items() if r == "ground"]
    pivots = [el for el in svg.iter() if el.get("class") == "ground-pivot"]
    assert len(ground) == 1 and len(pivots) == sum(ground[0] in e for e in edges)  # a fixed pivot per ground joint
    return _graph(edges, roles), "marked" in card.get("class").split()


def _cards(page):
    root = ET.fromstring(page[len("<!DOCTYPE html>\n"):])
    return [el for el in root.iter(XHTML + "div") if "card" in el.get("class", "").split()]


def test_motorcycle_page_shows_the_six_candidates_with_their_symbols(capsys):
    # seed 002 §4-1, Fig. 4-12: six candidates (a, b, d, f, h, i), the Suzuki RM-250X among them
    assert main(["regenerate", "motorcycle", "--format", "html"]) == 0
    cards = _cards(capsys.readouterr().out)
    assert [c.get("data-id") for c in cards] == ["1", "2", "3", "4", "5", "6"]
    drawn = [_read_card(card) for card in cards]
    book = _book_candidates()
    assert len(book) == 6
    for expected in book:  # every candidate of the book's rules drawn exactly once
        assert sum(_same(expected, g) for g, _ in drawn) == 1
    suzuki = _graph(SUZUKI_PAIRS, SUZUKI_ROLES)
    assert [_same(suzuki, g) for g, _ in drawn] == [marked for _, marked in drawn]
    assert sum(marked for _, marked in drawn) == 1
    marked = next(card for card, (_, m) in zip(cards, drawn) if m)
    assert "existing design" in "".join(marked.itertext()) and "Suzuki RM-250X" in "".join(marked.itertext())


def test_new_only_leaves_out_the_existing_design(capsys):
    assert main(["regenerate", "motorcycle", "--format", "html", "--new-only"]) == 0
    cards = _cards(capsys.readouterr().out)
    assert len(cards) == 5 and not any("marked" in c.get("class") for c in cards)


def test_regeneration_page_is_byte_identical_across_processes():
    # same input, same bytes: two interpreters with different hash seeds
    pages = []
    for seed in ("1", "2"):
        env = {**os.environ, "PYTHONHASHSEED": seed}
        run = subprocess.run([sys.executable, "-m", "domes", "regenerate", "motorcycle", "--format", "html"], cwd=ROOT, env=env, capture_output=True, check=True)
        pages.append(run.stdout)
    assert pages[0] == pages[1] and pages[0].startswith(b"<!DOCTYPE html>")


def test_a_candidate_that_cannot_be_drawn_gets_a_placeholder_card(monkeypatch, capsys):
    def refuse(*args, **kwargs):
        raise DomesError("no planar part found")

    monkeypatch.setattr(atlas, "mechanism_svg", refuse)
    assert main(["regenerate", "motorcycle", "--format", "html"]) == 0
    page = capsys.readouterr().out
    assert len(_cards(page)) == 6 and page.count('class="not-drawn"') == 6
    assert "not drawn: no planar part found" in page and page.count('class="card marked"') == 1
