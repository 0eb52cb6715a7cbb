"""The active-pair criterion (seed 002 §3-2-I.5 (1), Fig. 3-19) and DOF types (§3-2-I.5 (2)).

:func:`domes.model.active.active_pairs` (pebble game; exact rank modulo a
prime with sliders) is compared with an independent method: the rank, in
floating point, of the loop-closure Jacobian (joint rates as unknowns, three
equations per independent loop of a networkx cycle basis, the twist of each
joint at random dimensions) with the driven joints' columns removed. The
driven joints can be active together exactly when what is left is square
and of full rank: no motion left (full column rank) and no redundant loop
equation (full row rank). Then the criterion in the language: parsed,
compiled, rendered and explained.
"""

import itertools

import networkx as nx
import numpy as np
import pytest

from domes.errors import InputError
from domes.language import explain, holds, parse_criterion, render_criterion
from domes.language.evaluate import compile_criterion, graph_features
from domes.language.tree import ActivePairs, category, from_json, level, names_used, to_json
from domes.model import LabelledChain
from domes.model.active import active_pairs, can_be_active, input_joints
from domes.typesynth.atlas import ChainGenerator

GENERATOR = ChainGenerator()


def rank_says_active(chain: LabelledChain, driven, rng, trials: int = 2) -> bool:
    """The loop-closure Jacobian without the driven columns is square and regular at random dimensions."""
    graph = nx.Graph()
    graph.add_nodes_from(range(chain.n))
    graph.add_edges_from(chain.edges)
    index = {e: i for i, e in enumerate(chain.edges)}
    loops = nx.cycle_basis(graph)
    keep = [i for i in range(len(chain.edges)) if i not in set(driven)]
    for _ in range(trials):                      # a regular matrix at any one trial settles it
        twists = []
        for t in chain.joint_types:
            if t == "R":
                x, y = rng.normal(size=2)
                twists.append((1.0, y, -x))       # a unit rotation about (x, y)
            else:
                a = rng.uniform(0, np.pi)
                twists.append((0.0, np.cos(a), np.sin(a)))   # a unit slide
        rows = []
        for loop in loops:
            block = np.zeros((3, len(chain.edges)))
            for a, b in zip(loop, loop[1:] + loop[:1]):
                i = index[(min(a, b), max(a, b))]
                block[:, i] += (1 if a < b else -1) * np.array(twists[i])
            rows.append(block)
        jacobian = np.vstack(rows)[:, keep] if rows else np.zeros((0, len(keep)))
        rank = np.linalg.matrix_rank(jacobian, tol=1e-8) if jacobian.size else 0
        if rank == jacobian.shape[0] == jacobian.shape[1]:
            return True
    return False


def atlas(links: int, dof: int) -> list[LabelledChain]:
    """Every chain of the atlas, fractionated and degenerate (clamping) ones included."""
    return [LabelledChain.build(n, edges)
            for n, edges in GENERATOR.chains(links, dof, include_fractionated=True, clamping=True)]


@pytest.mark.parametrize(("links", "dof", "chains", "sets", "feasible"), [
    (7, 2, 8, 224, 113),
    (9, 2, 144, 7920, 2860),
    (8, 3, 12, 1008, 433),
])
def test_pebble_game_agrees_with_the_rank_of_the_loop_closure_jacobian(links, dof, chains, sets, feasible):
    """Every set of ``dof`` joints of every chain (8 links give no DOF 2: the 8-link chains of DOF 3, by threes)."""
    rng = np.random.default_rng(links * 10 + dof)
    found = atlas(links, dof)
    assert len(found) == chains
    compared = agreed = yes = 0
    for chain in found:
        for joints in itertools.combinations(range(len(chain.edges)), dof):
            ours = can_be_active(chain, joints)
            compared += 1
            agreed += ours == rank_says_active(chain, joints, rng)
            yes += ours
    assert (compared, agreed, yes) == (sets, sets, feasible)


def test_with_sliders_the_exact_rank_agrees_with_the_loop_closure_jacobian():
    """Random slider labellings (loops of sliders only, and sliders closing a loop between rigid parts)."""
    rng = np.random.default_rng(7)
    compared = 0
    for links, dof in ((4, 1), (5, 2), (6, 1), (7, 2)):
        for chain in atlas(links, dof):
            for share in (0.3, 0.6, 0.9):
                labelled = chain.with_joint_types("P" if rng.random() < share else "R" for _ in chain.edges)
                for joints in itertools.combinations(range(len(chain.edges)), dof):
                    assert can_be_active(labelled, joints) == rank_says_active(labelled, joints, rng), \
                        (labelled.to_dict(), joints)
                    compared += 1
    assert compared == 819


def test_a_loop_of_sliders_between_rigid_parts_is_seen():
    """Driving 0-1 makes links 0, 1, 4, 5 rigid; links 2 and 3 then hang from it by three sliders (a triangle
    of pins at infinity), which keep a DOF that no count sees."""
    chain = LabelledChain.build(6, [(0, 1), (0, 4), (1, 5), (2, 3), (2, 5), (3, 4), (4, 5)],
                                ["R", "P", "R", "P", "P", "P", "R"])
    result = active_pairs(chain, [(0, 1)])
    assert not result.feasible and result.remaining == 1 and result.over_constrained


# -- Fig. 3-19 ----------------------------------------------------------------------------------------------------

def fig_3_19(roles=None) -> LabelledChain:
    """Seed 002 §3-2-I.5 (1), Fig. 3-19: a chain of DOF 2 whose pairs A and C cannot both be active.

    The drawing is lost from the seed; the text gives W = 2, the pairs A-H (seven links, eight pairs) and that
    with A and C rigidified one loop's ξ drops to 2. Rebuilt here as the four-bar loop 0-1-2-3 (pairs A, B, C,
    D) with a branch of three binary links 4, 5, 6 (pairs E, F, G, H) from link 0 to link 2: with A and C
    rigid, the four-bar loop keeps only the pairs B and D (its ξ drops from 3 to 2, an over-constrained
    loop) while the branch still moves. The book names that loop BGH, which no lettering of these eight pairs
    reproduces with the drop to 2; the criterion is the same.
    """
    roles = roles or {"0": ["ground"]}
    links = [(str(v), roles.get(str(v), [])) for v in range(7)]
    joints = [("A", "0", "1", "R"), ("B", "1", "2", "R"), ("C", "2", "3", "R"), ("D", "3", "0", "R"),
              ("E", "0", "4", "R"), ("F", "4", "5", "R"), ("G", "5", "6", "R"), ("H", "6", "2", "R")]
    return LabelledChain.from_named("Fig. 3-19", links, joints, source="seed 002 §3-2-I.5, Fig. 3-19")


def test_fig_3_19_pairs_a_and_c_cannot_both_be_active():
    chain = fig_3_19()
    a_c = active_pairs(chain, [(0, 1), (2, 3)])
    assert a_c.dof == 2 and not a_c.feasible
    assert a_c.names == ("A", "C") and a_c.over_constrained == (0, 1, 2, 3) and a_c.remaining == 1
    assert a_c.reason == ("A and C cannot both be active: with them driven, links 0, 1, 2, 3 are over-constrained "
                          "and 1 DOF is left")
    for joint in ((0, 1), (2, 3)):                # each alone takes one DOF away
        alone = active_pairs(chain, [joint])
        assert alone.independent and alone.remaining == 1
    assert not rank_says_active(chain, [chain.edges.index((0, 1)), chain.edges.index((2, 3))],
                                np.random.default_rng(0))


def test_fig_3_19_which_pairs_can_be_active():
    """Two pairs of the four-bar loop never (it has one DOF of its own); any other two, yes: two on the branch
    leave it a binary link of fixed length that holds the four-bar."""
    chain = fig_3_19()
    loop = {"A", "B", "C", "D"}
    for i, j in itertools.combinations(range(8), 2):
        names = {chain.joint_name(i), chain.joint_name(j)}
        assert can_be_active(chain, [i, j]) == (len(names & loop) < 2), names


def test_dof_types():
    # Fig. 3-19 driven by A and E: the four-bar's links move with A only (Fig. 3-20a, partial)
    chain = fig_3_19({"0": ["ground"], "1": ["input"], "4": ["input"]})
    result = active_pairs(chain)
    assert result.joints == input_joints(chain) and result.names == ("A", "E")
    assert result.feasible and result.dof_type == "partial"
    assert result.moved_by == ((1, 2, 3, 5, 6), (4, 5, 6))
    # the five-bar driven at both ground pairs (Fig. 3-20b, full)
    five_bar = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0)],
                                   roles={0: {"ground"}, 1: {"input"}, 4: {"input"}})
    assert active_pairs(five_bar).dof_type == "full"
    # two four-bars sharing the ground, one input on each (Fig. 3-20c, fractionated)
    twin = LabelledChain.build(7, [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (4, 5), (5, 6), (6, 0)],
                               roles={0: {"ground"}, 1: {"input"}, 4: {"input"}})
    twin_result = active_pairs(twin)
    assert twin_result.feasible and twin_result.dof_type == "fractionated"
    assert not can_be_active(twin, [(0, 1), (2, 3)])      # both on one four-bar
    # one DOF: always full
    four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={0: {"ground"}, 1: {"input"}})
    assert active_pairs(four_bar).dof_type == "full"


def test_joint_types_and_errors():
    slider_crank = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], {(3, 0): "P"},
                                       roles={0: {"ground"}, 1: {"input"}})
    assert can_be_active(slider_crank) and can_be_active(slider_crank, [(0, 3)])
    # a hydraulic cylinder (a force member, no constraint) between links 0 and 2 of a five-bar drives it with 0-1
    five_bar = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0), (0, 2)],
                                   ["R", "R", "R", "R", "R", "H"], roles={0: {"ground"}})
    assert active_pairs(five_bar).dof == 2
    assert can_be_active(five_bar, [(0, 1), (0, 2)])
    with pytest.raises(InputError, match="exactly one link representing “ground”"):
        input_joints(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)]))
    with pytest.raises(InputError, match="not jointed to the ground"):
        input_joints(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={0: {"ground"}, 2: {"input"}}))
    with pytest.raises(InputError, match="higher pair"):
        active_pairs(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], {(0, 1): "G"}), [(0, 1)])
    with pytest.raises(InputError, match="not jointed"):
        active_pairs(slider_crank, [(0, 2)])


# -- the criterion language ---------------------------------------------------------------------------------------

def test_parse_render_json():
    tree = parse_criterion("The “input” joints should be active.")
    assert tree == ActivePairs("input", None)
    assert parse_criterion("the input pairs must be active pairs with a total degree of freedom") == \
        ActivePairs("input", "full")
    for text in ("the input pairs must be active pairs", "the “driving link” pairs must be active pairs with "
                 "fractionated DOF", "the input pairs are active with partial dof"):
        tree = parse_criterion(text)
        assert parse_criterion(render_criterion(tree)) == tree
        assert from_json(to_json(tree), expect="criterion") == tree
    assert render_criterion(ActivePairs("input", "partial")) == "the “input” pairs must be active pairs with partial DOF"
    assert (category(tree), level(tree), names_used(tree)) == ("v", 3, (("ground", "input"), ()))
    for text, message in (("the input pairs must not be active", "cannot be negated"),
                          ("the input pairs must be active with lazy dof", "a DOF type"),
                          ("the input pairs must be passive", "'active'")):
        with pytest.raises(InputError, match=message):
            parse_criterion(text)
    with pytest.raises(InputError, match="dof_type"):
        from_json({"node": "ActivePairs", "role": "input", "dof_type": "half"})


def test_criterion_holds_and_explains():
    rule = parse_criterion("the input pairs must be active pairs")
    full = parse_criterion("the input pairs must be active pairs with full DOF")
    a_e = fig_3_19({"0": ["ground"], "1": ["input"], "4": ["input"]})
    a_d = fig_3_19({"0": ["ground"], "1": ["input"], "3": ["input"]})
    assert holds(rule, a_e) and explain(rule, a_e) is None
    assert not holds(full, a_e)
    assert explain(full, a_e) == "the “input” pairs A, E give partial DOF, not full DOF: link 2 moves with A only"
    assert not holds(rule, a_d)
    assert explain(rule, a_d) == ("A and D cannot both be active: with them driven, links 0, 1, 2, 3 are "
                                  "over-constrained and 1 DOF is left (each active pair must take exactly one DOF "
                                  "away, seed 002 §3-2-I.5)")
    one = fig_3_19({"0": ["ground"], "1": ["input"]})
    assert explain(rule, one) == "A leaves 1 of the 2 DOF: the chain needs 2 active pairs (each active pair must " \
                                 "take exactly one DOF away, seed 002 §3-2-I.5)"
    no_ground = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={1: {"input"}})
    assert not holds(rule, no_ground)
    assert explain(rule, no_ground).startswith("the input pairs need exactly one link representing “ground”")
    assert explain(parse_criterion("the crank pairs must be active"), a_e).startswith("no link represents “crank”")


def test_features_compute_active_pairs_only_when_asked():
    chain = fig_3_19({"0": ["ground"], "1": ["input"], "4": ["input"]})
    features = graph_features(chain)
    compile_criterion(parse_criterion("every vertex must have degree at most 3"))(features)
    assert features.active == {}
    test = compile_criterion(parse_criterion("the input pairs must be active pairs"))
    assert test(features) and set(features.active) == {"input"}
    cached = features.active["input"]
    assert test(features) and features.active["input"] is cached
