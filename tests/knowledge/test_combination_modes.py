"""Combination modes (seed 002 §3-3-III.2): the classification and the shipped criteria, two codings of one rule.

The book's rules: series when a binary link is the driver and a link joined to it is the frame (Fig. 3-29);
parallel when a multi-pair link (three pairs or more) is the driver and a link adjacent to it is the frame, in
a one-DOF chain (Fig. 3-28). Feedback and stacking are DOMES-py's readings (docs/knowledge.md). The criteria
of knowledge/criteria/04-combination.toml are evaluated by the criterion language (bit masks, every simple
cycle); domes.model.combination_modes reads degrees and biconnected components off the graph.
"""

from __future__ import annotations

from itertools import permutations, product
from pathlib import Path

import networkx as nx
import pytest
from networkx.algorithms.isomorphism import GraphMatcher

from domes.errors import InputError
from domes.io.criteria import read_knowledge
from domes.io.scenes import load_scene
from domes.knowledge.relevance import Problem, is_relevant
from domes.knowledge.screening import screen
from domes.language.parse import parse_criterion
from domes.language.render import render_criterion
from domes.model import LabelledChain, combination_modes
from domes.model.combination_modes import MODES, combination_phrase
from domes.typesynth import chains, regenerate

ROOT = Path(__file__).resolve().parents[2]
CRITERIA = {f.id: f for f in read_knowledge(ROOT / "knowledge")}

# Fig. 3-28c: the five-bar 0-1-2-3-4 (crank AB = 1, follower 4 sliding on the frame) and the cam 1-4.
FIG_3_28 = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (0, 4), (1, 4)], {(0, 4): "P", (1, 4): "C"},
                               roles={0: {"ground"}, 1: {"input"}})
# Fig. 3-29: the elliptical gears 1, 2 on the frame 0, in series with the sine mechanism 2-3-4 (yoke 4).
FIG_3_29 = LabelledChain.build(5, [(0, 1), (0, 2), (1, 2), (2, 3), (3, 4), (0, 4)], {(1, 2): "G", (3, 4): "P",
                               (0, 4): "P"}, roles={0: {"ground"}, 1: {"input"}})


def modes(chain, dof=None) -> set[str]:
    return {m.mode for m in combination_modes(chain, dof)}


def test_the_books_figures():
    # seed 002 §3-3-III.2: "with link 0 as frame and link 1 as driver" Fig. 3-28c is the parallel mechanism
    # of Fig. 3-28a; Fig. 3-29's binary elliptical gear on the frame drives a series combination.
    assert modes(FIG_3_28, dof=1) == {"parallel"}
    assert modes(FIG_3_29, dof=1) == {"series"}
    (parallel,) = combination_modes(FIG_3_28)
    assert "multi-pair link (3 pairs)" in parallel.reason and parallel.source == "seed 002 §3-3-III.2"
    assert combination_phrase(FIG_3_29) == "series combination: a binary driver on the frame"
    # the five-bar alone is the 2-DOF base mechanism: no rule of the book applies to it
    assert modes(FIG_3_28, dof=2) == set()
    # the coupler 2 as the driver is off the frame: the driver's actuator would ride on the crank
    assert modes(FIG_3_28.with_roles({0: {"ground"}, 2: {"input"}})) == {"stacking"}


def test_feedback_reading():
    # the output 4 turns on the frame and closes the loop 1-2-3-4 with the driver, without the frame
    looped = FIG_3_28.with_roles({0: {"ground"}, 1: {"input"}, 4: {"output"}})
    assert modes(looped) == {"parallel", "feedback"}
    assert "feedback" not in modes(FIG_3_28.with_roles({0: {"ground"}, 1: {"input"}, 3: {"output"}}))  # off the frame
    # a four-bar's rocker is on the frame, but every loop through it and the crank passes through the frame
    four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)],
                                   roles={0: {"ground"}, 1: {"input"}, 3: {"output"}})
    assert modes(four_bar) == {"series"}


def labellings(links: int, dof: int) -> list[LabelledChain]:
    """Every labelling of the chains with one ground, one other link the input, and no output or one."""
    out = {}
    for chain in chains(links, dof):
        base = LabelledChain.from_chain(chain)
        for ground, driver, output in product(range(links), range(links), [None, *range(links)]):
            if driver == ground or output == ground:
                continue
            roles = {ground: {"ground"}, driver: {"input"}}
            if output is not None:
                roles[output] = roles.get(output, set()) | {"output"}
            labelled = base.with_roles(roles)
            out.setdefault(labelled.certificate, labelled)
    return list(out.values())


def scene_candidates() -> list[LabelledChain]:
    """The regenerated candidates of the shipped scenes with a driver, as they are and with each output."""
    out = []
    for name in ("cam-linkage", "window-lifter", "tyre-drum"):
        for c in regenerate(load_scene(name)).candidates:
            m = c.labelled
            out.append(m)
            ground = m.links_with_role("ground")[0]
            out += [m.with_roles({**dict(enumerate(m.roles)), v: m.roles[v] | {"output"}})
                    for v in range(m.n) if v != ground]
    return out


@pytest.fixture(scope="module")
def graphs() -> list[LabelledChain]:
    return [*labellings(4, 1), *labellings(6, 1), *labellings(8, 1), *scene_candidates()]


@pytest.mark.parametrize("mode", list(MODES))
def test_the_criteria_keep_exactly_the_chains_in_the_mode(graphs, mode):
    problem = Problem(dof=1, names=frozenset({f"{mode} combination"}))
    relevant = [f for f in CRITERIA.values() if is_relevant(f.relevance, problem)]
    assert {f.id for f in relevant} == {f"{mode}-combination"} if mode != "feedback" else \
        {f.id for f in relevant} == {"feedback-output-on-frame", "feedback-loop"}
    kept = set(screen(graphs, list(CRITERIA.values()), problem).kept_indices)
    classified = {i for i, g in enumerate(graphs) if mode in modes(g, dof=1)}
    assert kept == classified
    assert 0 < len(kept) < len(graphs)


def pair_orbits(links: int) -> dict[str, int]:
    """Orbits of (ground, driver) pairs under each chain's automorphisms (networkx VF2), split by the rules."""
    counts = dict.fromkeys(("series", "parallel", "stacking"), 0)
    for chain in chains(links, 1):
        graph = nx.Graph(chain.edges)
        autos = list(GraphMatcher(graph, graph).isomorphisms_iter())
        seen = set()
        for g, d in permutations(range(links), 2):
            if (g, d) in seen:
                continue
            seen |= {(a[g], a[d]) for a in autos}
            mode = "stacking" if not graph.has_edge(g, d) else "series" if graph.degree(d) == 2 else "parallel"
            counts[mode] += 1
    return counts


@pytest.mark.parametrize("links, expected", [
    (4, {"series": 1, "parallel": 0, "stacking": 1}),
    (6, {"series": 5, "parallel": 4, "stacking": 10}),
    (8, {"series": 69, "parallel": 84, "stacking": 266}),
])
def test_counts_on_the_one_dof_chains(links, expected):
    # measured (the book gives no counts): one-DOF chains with a ground and a driver; the orbits of the
    # (ground, driver) pairs are counted independently of the labelled chains' certificates
    plain = [g for g in labellings(links, 1) if not g.links_with_role("output")]
    counts = {mode: sum(mode in modes(g) for g in plain) for mode in ("series", "parallel", "stacking")}
    assert counts == pair_orbits(links) == expected
    assert not any("feedback" in modes(g) for g in plain)  # no output, no feedback
    # with an output on any link but the frame: 7, 104 and 3146 labellings; a loop without the frame through a
    # driver on the frame needs two more pairs on the driver, so feedback with the driver on the frame is parallel
    everything = labellings(links, 1)
    feedback = [modes(g) for g in everything if "feedback" in modes(g)]
    assert (len(everything), len(feedback)) == {4: (7, 0), 6: (104, 12), 8: (3146, 423)}[links]
    assert all("parallel" in m or "stacking" in m for m in feedback)


def test_the_shipped_criteria_parse_and_render_back():
    for key in ("series-combination", "parallel-combination", "feedback-output-on-frame", "feedback-loop",
                "stacking-combination"):
        frame = CRITERIA[key]
        assert parse_criterion(render_criterion(frame.tree)) == frame.tree
        assert frame.source and frame.explanation and "combination" in frame.relevance_text
    assert "DOMES-py reading" in CRITERIA["stacking-combination"].source


def test_bad_input_names_what_is_wrong():
    with pytest.raises(InputError, match="exactly one link with role 'ground', found none"):
        combination_modes(FIG_3_28.with_roles({1: {"input"}}))
    with pytest.raises(InputError, match="role 'input', found links 1, 2"):
        combination_modes(FIG_3_28.with_roles({0: {"ground"}, 1: {"input"}, 2: {"input"}}))
    with pytest.raises(InputError, match="link 0 is both the frame"):
        combination_modes(FIG_3_28.with_roles({0: {"ground", "input"}}))
    with pytest.raises(InputError, match="expected a labelled chain"):
        combination_modes("0-1 1-2")
    with pytest.raises(InputError, match="dof must be a whole number"):
        combination_modes(FIG_3_28, dof=1.5)


def test_regenerate_shows_the_mode_of_each_candidate(capsys):
    from domes.cli import main

    assert main(["regenerate", "window-lifter"]) == 0
    lines = [line for line in capsys.readouterr().out.splitlines() if "  joints " in line]
    result = regenerate(load_scene("window-lifter"))
    assert len(lines) == len(result.candidates) == 7
    for line, c in zip(lines, result.candidates):
        (mode,) = combination_modes(c.labelled, dof=1)
        assert line.endswith(mode.phrase)
    assert sum(line.endswith("a ternary driver on the frame") for line in lines) == 3
    assert main(["regenerate", "motorcycle"]) == 0  # no driver in the scene: no mode shown
    assert "combination" not in capsys.readouterr().out.split("candidates (")[1]
