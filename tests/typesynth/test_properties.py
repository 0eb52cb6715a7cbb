"""Per-chain properties against the seed's worked examples (seed 002, chapter 3)."""

from collections import Counter
from itertools import combinations

import networkx as nx
import pytest
from reference import brute_force_degenerate

from domes.errors import DomesError
from domes.model import Chain, chain_properties
from domes.model.charpoly import characteristic_polynomial
from domes.typesynth import chains


def test_basic_chains_structural_number_table_3_4():
    # Table 3-4 (digest A2): V = 1: K = 0; V = 2, 3: K = 1; V = 4: 24 chains with K = 1, 4 with K = 2.
    expected = {1: Counter({0: 1}), 2: Counter({1: 1}), 3: Counter({1: 3}), 4: Counter({1: 24, 2: 4})}
    for loops, distribution in expected.items():
        atlas = chains(links=2 * loops + 1, dof=0)
        assert Counter(c.structural_number for c in atlas) == distribution


def _greedy_k(g):
    """The book's algorithm for K (§3-2-I.4): the smallest-Δ loop first, then
    repeatedly the smallest-Δ SOC on what is built, branching on ties."""
    edges = [tuple(sorted(e)) for e in g.edges]

    def ears(used):
        placed = {v for e in used for v in e}
        found = []

        def walk(path, path_edges):
            for w in g[path[-1]]:
                e = tuple(sorted((path[-1], w)))
                if e in used or e in path_edges:
                    continue
                if w in placed:
                    if w != path[0] or len(path_edges) >= 2:
                        found.append(frozenset(path_edges | {e}))
                elif w not in path:
                    walk(path + [w], path_edges | {e})

        for v in placed:
            walk([v], frozenset())
        return set(found)

    def best(used, total):
        if len(used) == len(edges):
            return total
        options = ears(used)
        smallest = min(len(o) for o in options)
        return min(best(used | o, total + max(len(o) - 3, 0)) for o in options if len(o) == smallest)

    cycles = [frozenset(tuple(sorted(p)) for p in zip(c, c[1:] + c[:1])) for c in nx.simple_cycles(g)]
    girth = min(len(c) for c in cycles)
    return min(best(c, max(girth - 3, 0)) for c in cycles if len(c) == girth)


@pytest.mark.parametrize("loops", [2, 3, 4])
def test_structural_number_agrees_with_the_books_greedy_rule(loops):
    # digest §1.7 and A2: the exact minimum over SOC decompositions and the
    # book's greedy rule give the same K on all basic chains with V <= 4.
    for chain in chains(links=2 * loops + 1, dof=0):
        assert chain.structural_number == _greedy_k(chain.to_networkx())


def test_table_3_1_distribution_of_v3_basic_chains():
    # digest §1.6 [computed]: V = 3 basic chains per Table 3-1 column: No. 3 -> 2, No. 4 -> 1, No. 5 -> 0.
    counts = Counter(tuple(sorted(c.assortment.items())) for c in chains(links=7, dof=0))
    assert counts == {((2, 3), (3, 4)): 2, ((2, 4), (3, 2), (4, 1)): 1}


def test_fig_3_13_incidence_matrix_chain():
    # §3-1-II, Fig. 3-13: the 8-link, 10-joint chain read from the incidence matrix
    # (A, F ternary; C quaternary) is one of the 16 one-DOF eight-bar chains.
    names = "ABCDEFGH"
    joints = ["FG", "CG", "CH", "FH", "AF", "AB", "BC", "CD", "DE", "AE"]
    chain = Chain(8, tuple((names.index(a), names.index(b)) for a, b in joints))
    assert chain.dof == 1 and not chain.is_degenerate
    assert chain.assortment == {2: 5, 3: 2, 4: 1}
    assert chain in set(chains(links=8, dof=1))


def test_degenerate_six_link_graphs_section_1_2():
    # digest §1.2: the three degenerate (6, 7) graphs and the rigid sub-chain in each.
    cases = {
        "triangle + pentagon on an edge": [(0, 1), (1, 2), (2, 0), (0, 3), (3, 4), (4, 5), (5, 1)],
        "figure eight": [(0, 1), (1, 2), (2, 0), (0, 3), (3, 4), (4, 5), (5, 0)],
        "dumbbell": [(0, 1), (1, 2), (2, 0), (2, 3), (3, 4), (4, 5), (5, 3)],
    }
    for name, edges in cases.items():
        props = chain_properties(edges)
        assert props["degenerate"], name
        rigid = set(props["rigid_subchain"])
        inside = sum(1 for u, v in edges if u in rigid and v in rigid)
        assert 3 * (len(rigid) - 1) - 2 * inside <= 0, name
        assert len(rigid) == 3, name  # the triangle is the smallest rigid sub-chain
        assert brute_force_degenerate(6, edges)


def test_watt_chain_orbits_a6():
    # digest A6: the Watt chain numbered 1-2 adjacent ternaries, 1-4-3-2, 1-5-6-2
    # has similar-link classes (orbits) {1, 2} and {3, 4, 5, 6}.
    watt = Chain.from_networkx(nx.Graph([(1, 2), (1, 4), (4, 3), (3, 2), (1, 5), (5, 6), (6, 2)]))
    assert watt.link_orbits == [[0, 1], [2, 3, 4, 5]]  # links 1..6 relabelled 0..5 in order
    assert watt.automorphisms.order == 4


def test_stephenson_and_watt_contracted_graphs():
    # Fig. 3-6: Watt has its ternary links adjacent (branches of 0, 2, 2 binaries),
    # Stephenson has them apart (1, 1, 2).
    shapes = sorted(sorted(len(b.binaries) for b in c.contracted_graph) for c in chains(links=6, dof=1))
    assert shapes == [[0, 2, 2], [1, 1, 2]]


@pytest.mark.parametrize("links, dof", [(8, 1), (10, 1), (9, 2), (10, 3), (9, 0)])
def test_contracted_graph_identities(links, dof):
    # (3-15)..(3-18), corrected (digest §1.6): V = l − b + 1, 2l = Σ d·n_d (d ≥ 3), n_2 = n − b.
    for c in chains(links=links, dof=dof, include_fractionated=True):
        branches = c.contracted_graph
        b = sum(k for d, k in c.assortment.items() if d >= 3)
        assert c.loops == len(branches) - b + 1
        assert 2 * len(branches) == sum(d * k for d, k in c.assortment.items() if d >= 3)
        assert sum(len(x.binaries) for x in branches) == c.assortment.get(2, 0)


def test_dof_types_of_seven_link_two_dof_chains():
    # §3-2-I.5: of the four 7-link 2-DOF chains, one has a cut link (fractionated);
    # the theta chain with branches (2, 2, 1) binaries has no four-bar sub-chain
    # (total); the other two contain a four-bar loop (partial).
    types = {}
    for c in chains(links=7, dof=2, include_fractionated=True):
        key = tuple(sorted(len(b.binaries) for b in c.contracted_graph)) if not c.cut_links else "cut"
        types[key] = c.dof_type
    assert types == {"cut": "fractionated", (1, 2, 2): "total", (1, 1, 3): "partial", (0, 2, 3): "partial"}


def test_partial_means_a_loop_with_fewer_dof():
    # Independent restatement of the rule on the 9-link 2-DOF atlas.
    for c in chains(links=9, dof=2):
        g = c.to_networkx()
        lower = any(
            nx.cycle_basis(g.subgraph(s)) and 3 * (len(s) - 1) - 2 * g.subgraph(s).number_of_edges() < 2
            for k in range(3, 9)
            for s in combinations(range(9), k)
        )
        assert (c.dof_type == "partial") == lower


def test_charpoly_collisions_among_ten_bar_chains():
    # digest §1.9 and B6 [computed]: the adjacency characteristic polynomial leaves
    # two colliding pairs among the 230 one-DOF 10-bar chains; VF2 shows each pair
    # is non-isomorphic, so the book's test is not exact.
    atlas = chains(links=10, dof=1)
    by_poly = {}
    for c in atlas:
        by_poly.setdefault(c.characteristic_polynomial, []).append(c)
    collisions = [group for group in by_poly.values() if len(group) > 1]
    assert sorted(len(g) for g in collisions) == [2, 2]
    for a, b in collisions:
        assert not nx.is_isomorphic(a.to_networkx(), b.to_networkx())
    # The book's method, used to remove duplicates, therefore loses chains.
    assert len(chains(links=10, dof=1, isomorphism="charpoly")) < 230


def test_characteristic_polynomial_matches_numpy():
    import numpy as np

    for c in chains(links=8, dof=1):
        a = nx.to_numpy_array(c.to_networkx())
        assert np.allclose(np.poly(a), characteristic_polynomial(c.n, c.edges), atol=1e-6)


@pytest.mark.parametrize(
    "edges, message",
    [
        ([(0, 0)], "itself"),
        ([(0, 1), (1, 0)], "already jointed"),
        ([("a", 1)], "not a pair of link numbers"),
    ],
)
def test_bad_chains_are_refused(edges, message):
    with pytest.raises(DomesError, match=message):
        Chain(3, tuple(edges))


def test_bad_graph6_is_refused():
    with pytest.raises(DomesError, match="not a graph6 string"):
        Chain.from_graph6("not graph6 at all \x01")


def test_json_record_fields():
    record = chains(links=6, dof=1)[0].to_dict()
    assert {"links", "joints", "loops", "assortment", "contracted_graph", "dof_type",
            "automorphism_group_order", "link_orbits", "rigid_subchain", "graph6"} <= set(record)


def test_similarity_matrices_of_the_watt_chain_a6():
    # digest A6 (§3-3-III.1): for the Watt chain numbered 1-2 adjacent ternaries,
    # 1-4-3-2, 1-5-6-2, A² equals the printed B² and C² is the orbit partition.
    from domes.model.similarity import similarity

    printed_b2 = [
        [3, 0, 2, 0, 0, 2],
        [0, 3, 0, 2, 2, 0],
        [2, 0, 2, 0, 0, 1],
        [0, 2, 0, 2, 1, 0],
        [0, 2, 0, 1, 2, 0],
        [2, 0, 1, 0, 0, 2],
    ]
    printed_c2 = [[1, 1, 0, 0, 0, 0]] * 2 + [[0, 0, 1, 1, 1, 1]] * 4
    watt = Chain.from_networkx(nx.Graph([(1, 2), (1, 4), (4, 3), (3, 2), (1, 5), (5, 6), (6, 2)]))
    s = similarity(watt)
    assert s.position.tolist() == printed_b2
    assert s.similar.tolist() == printed_c2
