"""Multi-level screening and the relevance vector (seed 002 §5-2 IV, §7-2; digest 4.3, 4.4, A9)."""

import itertools
import json
from pathlib import Path

import pytest

from domes.errors import DomesError
from domes.io.criteria import read_knowledge
from domes.knowledge.frames import CriterionFrame
from domes.knowledge.relevance import Problem, RelevanceVector, relevance_vector
from domes.knowledge.screening import CostlyCriterion, screen
from domes.language.evaluate import compile_criterion, graph_features
from domes.model import LabelledChain
from domes.typesynth import chains

ROOT = Path(__file__).resolve().parents[2]  # the checkout


def motorcycle_candidates():
    """Every role assignment on the Watt and Stephenson chains: ground, swing arm, two shock links (ordered choice)."""
    out = []
    for c in chains(links=6, dof=1):
        for ground, swing in itertools.permutations(range(6), 2):
            for pair in itertools.combinations(sorted(set(range(6)) - {ground, swing}), 2):
                roles = {ground: {"ground"}, swing: {"swing_arm"}, pair[0]: {"shock_absorber"}, pair[1]: {"shock_absorber"}}
                out.append(LabelledChain.build(6, c.edges, None, roles))
    return out


def frames(*pairs):
    return [CriterionFrame.create(i, t) for i, t in pairs]


DYAD = ("dyad", "the vertices representing “shock absorber” must be binary and adjacent to a vertex representing "
                "“shock absorber” and not represent “ground”")
ARM = ("arm", "the swing arm is adjacent to the ground")
LOOP_RULE = ("loops", "every loop must have length at most 5")


def test_levels_run_cheap_to_costly_and_every_rejection_names_its_criterion():
    candidates = motorcycle_candidates()
    criteria = frames(LOOP_RULE, ARM, DYAD)  # given costly-first: screening reorders by level
    assert [c.level for c in criteria] == [3, 2, 2]
    result = screen(candidates, criteria)
    assert result.applied == ("arm", "dyad", "loops")
    # Each rejection is by the first criterion (in level order) that the candidate fails.
    tests = {c.id: compile_criterion(c.tree) for c in criteria}
    for r in result.rejections:
        f = graph_features(candidates[r.index])
        failed = [cid for cid in result.applied if not tests[cid](f)]
        assert failed[0] == r.criterion
    for i in result.kept_indices:
        assert all(t(graph_features(candidates[i])) for t in tests.values())
    assert len(result.kept) + len(result.rejections) == len(candidates)
    assert [lvl for lvl, _ in result.levels] == [2, 3]
    # Seed 002 §4-1 (digest A8): 6 distinct designs have a dyad shock absorber and the swing arm on
    # the ground, 2 + 2 on the Watt chain and 1 + 1 on the Stephenson chain; the Watt chain has a
    # 6-loop, so the loop rule leaves the 2 Stephenson designs.
    assert len(set(screen(candidates, frames(ARM, DYAD)).kept)) == 6
    assert len(set(result.kept)) == 2


def test_emptied_set_skips_the_remaining_criteria_and_names_the_culprit():
    candidates = motorcycle_candidates()
    impossible = ("no-binary", "every vertex must have degree at least 3")
    result = screen(candidates, frames(DYAD, impossible, LOOP_RULE, ARM))
    assert result.kept == ()
    assert result.emptied_by == "no-binary"
    assert result.applied == ("no-binary",)  # level 1 runs first and removes every candidate
    assert set(result.skipped) == {"dyad", "arm", "loops"}
    assert "'no-binary'" in result.message and "skipped" in result.message


def test_relevance_decides_which_criteria_apply():
    shipped = read_knowledge(ROOT / "knowledge")
    motorcycle = Problem(dof=1, loops=2, links=6, joints=7, slider_pairs=0,
                         names=frozenset({"ground", "swing_arm", "shock_absorber"}))
    vector = relevance_vector(shipped, motorcycle)
    assert len(vector) == len(shipped)  # one element per criterion of the knowledge base
    relevant = set(vector.relevant_ids())
    assert {"swing-arm-on-ground", "shock-absorber-dyad", "shock-absorber-two-links", "one-ground"} <= relevant
    assert not relevant & {"book-i", "book-ii", "book-iii", "book-iv", "book-v", "book-vi", "tiles-radial", "input-on-ground"}
    result = screen(motorcycle_candidates(), shipped, motorcycle)
    assert set(result.applied) == relevant
    assert len(set(result.kept)) == 6  # seed 002 §4-1: designs a, b, d, f, h, i


def test_relevance_vector_overrides_extension_and_merge():
    criteria = frames(("a", "every vertex must have degree at most 3"), ("b", "the piston must have type (P R)"))
    vector = relevance_vector(criteria, Problem(dof=1))
    assert vector.bits == (1, 0)
    # The designer declares b relevant: screening then applies it.
    forced = vector.set("b", 1)
    g = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={1: {"piston"}})
    assert screen([g], criteria, relevance=forced).rejected_by == {0: "b"}
    assert screen([g], criteria, relevance=vector).kept_indices == (0,)
    # A new criterion extends every vector; merging is element-wise OR.
    grown = criteria + frames(("c", "every loop must have length 4"))
    assert vector.aligned([c.id for c in grown]).bits == (1, 0, 0)
    assert vector.merge(relevance_vector(grown, Problem(names=frozenset({"piston"})))).bits == (1, 1, 1)
    with pytest.raises(DomesError):
        RelevanceVector(("a",), (2,))


def test_costly_criteria_run_last_and_the_depth_knob_stops_before_them():
    calls = []

    def kinematic(candidate):
        calls.append(candidate)
        return candidate.n == 6

    criteria = [CostlyCriterion("kinematic", kinematic), *frames(("binary", "the number of vertices that are binary must be at least 4"))]
    four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
    watt = LabelledChain.build(6, [(0, 1), (0, 2), (2, 3), (1, 3), (0, 4), (4, 5), (1, 5)])
    stephenson = LabelledChain.build(6, [(0, 1), (0, 2), (1, 3), (2, 3), (1, 4), (2, 5), (4, 5)])
    result = screen([four_bar, watt, stephenson], criteria)
    assert result.applied == ("binary", "kinematic")
    assert result.kept_indices == (1, 2)  # the four-bar fails only the kinematic check
    assert result.rejected_by == {0: "kinematic"}
    assert len(calls) == 3
    calls.clear()
    shallow = screen([four_bar, watt, stephenson], criteria, max_level=3)
    assert shallow.applied == ("binary",) and calls == [] and shallow.kept_indices == (0, 1, 2)


def test_disabled_criteria_are_not_applied():
    criteria = [CriterionFrame.create("off", "every vertex must have degree 3", enabled=False)]
    g = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
    assert screen([g], criteria).kept_indices == (0,)


def test_screen_command(tmp_path, capsys):
    from domes.cli import main
    from domes.store.casebase import build

    db = tmp_path / "kb.db"
    build(ROOT / "knowledge", str(db))
    # Seed 002 §4-1: the Suzuki original (swing arm on link 3, 0-based 2) and the same chain
    # with the swing arm on a link not jointed to the ground.
    suzuki = {"links": 6, "joints": [[0, 1], [0, 2], [1, 3], [2, 3], [1, 4], [2, 5], [4, 5, "P"]],
              "roles": {"0": ["ground"], "2": ["swing arm"], "4": ["shock absorber"], "5": ["shock absorber"]}}
    floating = dict(suzuki, roles={"0": ["ground"], "3": ["swing arm"], "4": ["shock absorber"], "5": ["shock absorber"]})
    graphs = tmp_path / "graphs.json"
    graphs.write_text(json.dumps([suzuki, floating]))
    problem = '{"dof": 1, "names": ["ground", "swing arm", "shock absorber"]}'
    assert main(["kb", "screen", str(graphs), "--db", str(db), "--problem", problem, "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["kept"] == [0]
    assert out["rejected"] == [{"graph": 1, "criterion": "swing-arm-on-ground", "level": 2,
                                "reason": "not met by link 3: must be adjacent to “ground”"}]
    graphs.write_text('[{"links": 3, "joints": [[0, 1], [1, 5]]}]')
    assert main(["kb", "screen", str(graphs), "--db", str(db)]) == 2
    assert "graph 0" in capsys.readouterr().err
