"""Active pairs of the atlas chains (seed 002 §3-2-I.5, Fig. 3-19 and 3-20; issue 26, item 6).

:func:`domes.model.active.active_sets` (sub-chain counts over all sets of
links) is compared with two independent methods for every set of ``W``
joints of the atlas chains: the pebble game of
:func:`~domes.model.active.active_pairs` with each link taken as the ground,
and the loop-closure Jacobian in floating point at random dimensions (joint
rates as unknowns, three equations per loop of a networkx cycle basis). In
the Jacobian, the chosen joints can be active together when the columns of
the others are square and regular; each input alone (the others held) then
gives one motion, and with it the twist of every link:

* *partial*: two links not jointed by a chosen pair keep their relative
  position while some input moves (a driven link, with either of them as the
  ground, depends on fewer than ``W`` inputs);
* *fractionated*: relative to a cut link, two inputs move disjoint sets of
  links (sub-chains with DOF of their own);
* *full*: neither.
"""

import itertools
import json
from math import comb

import networkx as nx
import numpy as np
import pytest

from domes.cli import main
from domes.errors import InputError
from domes.model import Chain, LabelledChain
from domes.model.active import DOF_TYPES, active_pairs, active_sets
from domes.typesynth.atlas import ChainGenerator

GENERATOR = ChainGenerator()
TOL = 1e-7


def atlas(links: int, dof: int) -> list[Chain]:
    return [Chain(n, edges) for n, edges in GENERATOR.chains(links, dof, include_fractionated=True)]


def jacobian_type(chain: Chain, chosen, rng) -> str | None:
    """The DOF type of the chosen joints by the loop-closure Jacobian at random dimensions; None if they cannot
    be active together."""
    graph = chain.to_networkx()
    index = {e: i for i, e in enumerate(chain.edges)}
    twists = np.array([(1.0, y, -x) for x, y in rng.normal(size=(len(chain.edges), 2))])   # rotation about (x, y)
    rows = []
    for loop in nx.cycle_basis(graph):
        block = np.zeros((3, len(chain.edges)))
        for a, b in zip(loop, loop[1:] + loop[:1]):
            i = index[(min(a, b), max(a, b))]
            block[:, i] += (1 if a < b else -1) * twists[i]
        rows.append(block)
    jacobian = np.vstack(rows)
    keep = [i for i in range(len(chain.edges)) if i not in chosen]
    held = jacobian[:, keep]
    if held.shape[0] != held.shape[1] or np.linalg.matrix_rank(held, tol=1e-8) < len(keep):
        return None
    tree = list(nx.bfs_edges(graph, 0))
    link_twists = []                                    # per input: the twist of every link, link 0 held
    for k in chosen:
        rates = np.zeros(len(chain.edges))
        rates[k] = 1.0
        rates[keep] = np.linalg.solve(held, -jacobian[:, k])
        twist = {0: np.zeros(3)}
        for a, b in tree:
            i = index[(min(a, b), max(a, b))]
            twist[b] = twist[a] + (1 if a < b else -1) * rates[i] * twists[i]
        link_twists.append(twist)
    still = [{(x, y) for x, y in itertools.combinations(range(chain.n), 2)
              if np.linalg.norm(t[x] - t[y]) < TOL} for t in link_twists]
    for cut in nx.articulation_points(graph):
        moved = [{y for y in range(chain.n) if y != cut and (min(cut, y), max(cut, y)) not in s} for s in still]
        if any(not (a & b) for a, b in itertools.combinations(moved, 2)):
            return "fractionated"
    active = {chain.edges[i] for i in chosen}
    return "partial" if any(pair not in active for s in still for pair in s) else "full"


def labelled_counts(chain: Chain, rng) -> dict[str, int]:
    counts = dict.fromkeys(("sets", "active", *DOF_TYPES), 0)
    for chosen in itertools.combinations(range(len(chain.edges)), chain.dof):
        found = jacobian_type(chain, chosen, rng)
        counts["sets"] += 1
        if found:
            counts["active"] += 1
            counts[found] += 1
    return counts


@pytest.mark.parametrize(("links", "dof"), [(7, 2), (8, 3), (9, 2), (8, 1)])
def test_counts_agree_with_the_loop_closure_jacobian(links, dof):
    """Every set of W joints of every chain (cut links included): the labelled counts by DOF type."""
    rng = np.random.default_rng(100 * links + dof)
    chains = atlas(links, dof)
    assert chains
    types = set()
    for chain in chains:
        found = active_sets(chain)
        assert found.counts(labelled=True) == labelled_counts(chain, rng), chain.edges
        assert sum(c.size for c in found.classes) == comb(chain.joints, dof)
        types |= {c.dof_type for c in found.classes}
    assert types >= ({None, "full", "partial", "fractionated"} if dof > 1 else {"full"})


def test_classes_agree_with_the_pebble_game_on_every_ground():
    """active_pairs on a plain chain (no ground: partial if some link taken as the ground makes it so)."""
    for chain in atlas(7, 2):
        for c in active_sets(chain).classes:
            result = active_pairs(chain, c.joints)
            assert result.feasible == c.feasible and result.dof_type == c.dof_type, (chain.edges, c)
            grounded = [active_pairs(LabelledChain.build(chain.n, chain.edges, roles={g: {"ground"}}), c.joints)
                        for g in range(chain.n)]
            if c.dof_type in ("full", "partial"):
                assert any(r.dof_type == "partial" for r in grounded) == (c.dof_type == "partial")


def fig_3_19() -> Chain:
    """Seed 002 §3-2-I.5 (1), Fig. 3-19 (the drawing is lost; rebuilt as in
    tests/language/test_active_pair_criterion.py): the four-bar loop 0-1-2-3 (pairs A, B, C, D) and a branch
    of binary links 4, 5, 6 (pairs E, F, G, H) from link 0 to link 2; DOF 2."""
    return Chain(7, [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (4, 5), (5, 6), (6, 2)])


def test_fig_3_19_pairs_a_and_c_cannot_both_be_active():
    chain = fig_3_19()
    assert chain in atlas(7, 2)
    found = active_sets(chain)
    a_c = next(c for c in found.classes if c.edges == ((0, 1), (2, 3)))
    assert not a_c.feasible and not active_pairs(chain, [(0, 1), (2, 3)]).feasible
    # two pairs of the four-bar loop never (it has one DOF of its own), any other two yes
    assert found.counts(labelled=True)["active"] == comb(8, 2) - comb(4, 2)
    # A and E: the four-bar's links move with A only (Fig. 3-20a, partial); E and F in series on the branch: full
    assert {c.edges: c.dof_type for c in found.classes}[((0, 1), (0, 4))] == "partial"
    assert {c.edges: c.dof_type for c in found.classes}[((0, 4), (4, 5))] == "full"


@pytest.mark.parametrize("links", [4, 6, 8, 10])
def test_one_dof_every_joint_can_be_the_input(links):
    """W = 1: in a chain without rigid sub-chains every joint alone drives the chain, with full DOF."""
    for chain in atlas(links, 1):
        counts = active_sets(chain).counts(labelled=True)
        assert counts == {"sets": chain.joints, "active": chain.joints, "full": chain.joints, "partial": 0,
                          "fractionated": 0}


def test_fractionated_chain():
    """Two four-bars on one link (Fig. 3-20c): one input in each is fractionated, two in one four-bar never."""
    twin = Chain(7, [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (4, 5), (5, 6), (6, 0)])
    assert twin.cut_links == [0]
    counts = active_sets(twin).counts(labelled=True)
    assert counts == {"sets": comb(8, 2), "active": 4 * 4, "full": 0, "partial": 0, "fractionated": 4 * 4}


def test_bad_input():
    with pytest.raises(InputError, match="DOF 1 or more; this chain has DOF 0"):
        active_sets(Chain(5, [(0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (4, 2)]))        # a basic chain
    with pytest.raises(InputError, match="links 0, 1, 2 form a rigid"):
        active_sets(Chain(6, [(0, 1), (1, 2), (0, 2), (2, 3), (3, 4), (4, 5), (5, 0)]))
    with pytest.raises(InputError, match="joint types P"):
        active_sets(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], {(0, 1): "P"}))
    with pytest.raises(InputError, match="not a chain"):
        active_sets("Cl")


# -- the command line -----------------------------------------------------------------------------------------

def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_chains_active_text_and_json(capsys):
    status, out, _ = run(capsys, "chains", "-n", "7", "-F", "2", "--include-fractionated", "--active")
    lines = [line for line in out.splitlines() if not line.startswith("#")]
    chains = atlas(7, 2)
    assert status == 0 and len(lines) == len(chains)
    for line, chain in zip(lines, chains):
        assert line.endswith(active_sets(chain).summary())
    status, out, _ = run(capsys, "chains", "-n", "7", "-F", "2", "--include-fractionated", "--active",
                         "--format", "json")
    records = json.loads(out)["chains"]
    assert status == 0
    for record, chain in zip(records, chains):
        found = active_sets(chain)
        assert record["active_sets"] == {"classes": found.counts(), "labelled": found.counts(labelled=True)}
    status, out, _ = run(capsys, "chains", "-n", "7", "-F", "2", "--format", "json")
    assert "active_sets" not in json.loads(out)["chains"][0]


@pytest.mark.parametrize("extra", [["--format", "html"], ["--format", "graph6"], ["--count"], ["--clamping"]])
def test_chains_active_refuses_what_has_no_room(capsys, extra):
    status, _, err = run(capsys, "chains", "-n", "7", "-F", "2", "--active", *extra)
    assert status == 2 and f"--active adds the active pairs to the text and json listings; {extra[0]}" in err


def test_chains_active_needs_dof(capsys):
    status, _, err = run(capsys, "chains", "-n", "6", "-F", "0", "--active")
    assert status == 2 and "--active needs chains of DOF 1 or more" in err


def test_chain_shows_the_active_pairs(capsys):
    chain = fig_3_19()
    status, out, _ = run(capsys, "chain", chain.graph6)
    assert status == 0 and "active pairs (2 joints, classes up to symmetry): 8 of 11 can be active together" in out
    assert "not active   0-1 0-3 (x2); 0-1 1-2 (x2); 0-1 2-3 (x2)" in out
    status, out, _ = run(capsys, "chain", chain.graph6, "--format", "json")
    assert status == 0 and json.loads(out)[0]["active_sets"] == active_sets(Chain.from_graph6(chain.graph6)).to_dict()
    four_bar, triangle = Chain(4, [(0, 1), (1, 2), (2, 3), (3, 0)]), Chain(3, [(0, 1), (1, 2), (2, 0)])
    status, out, _ = run(capsys, "chain", four_bar.graph6, triangle.graph6, "--format", "json")
    assert [r["active_sets"] is None for r in json.loads(out)] == [False, True]      # DOF 0: none
    rigid_inside = Chain(6, [(0, 1), (1, 2), (0, 2), (2, 3), (3, 4), (4, 5), (5, 0)])
    status, out, _ = run(capsys, "chain", rigid_inside.graph6)
    assert status == 0 and "active pairs: not tabulated (links" in out
