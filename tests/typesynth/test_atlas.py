"""The chain atlas: counts from the seed, checked by methods independent of the generator.

Counts: seed 002 §3-1-I.3 (1-DOF: 2, 16, 230 chains; digest A1) and the
project brief's table (DOF 1, 2, 3 with and without cut links); basic chains
V = 1..4 from Table 3-4 (digest A2).
"""

import networkx as nx
import pytest
from reference import GENG, brute_force_degenerate, geng_chains, match_into, pairwise_isomorphic

from domes.typesynth import ChainGenerator, chains

# (links, dof): (count without cut links, count with them)
ATLAS = {
    (4, 1): (1, 1),
    (6, 1): (2, 2),
    (8, 1): (16, 16),
    (10, 1): (230, 230),
    (5, 2): (1, 1),
    (7, 2): (3, 4),
    (9, 2): (35, 40),
    (6, 3): (1, 1),
    (8, 3): (5, 7),
    (10, 3): (74, 98),
    (3, 0): (1, 1),  # Table 3-4, V = 1
    (5, 0): (1, 1),  # V = 2
    (7, 0): (3, 3),  # V = 3
    (9, 0): (28, 28),  # V = 4
}
SLOW_ATLAS = {(11, 2): (753, 839), (12, 1): (6856, 6856)}


@pytest.mark.parametrize("size", sorted(ATLAS))
@pytest.mark.parametrize("fractionated", [False, True])
def test_counts(size, fractionated):
    links, dof = size
    assert len(chains(links=links, dof=dof, include_fractionated=fractionated)) == ATLAS[size][fractionated]


@pytest.mark.slow
@pytest.mark.parametrize("size", sorted(SLOW_ATLAS))
@pytest.mark.parametrize("fractionated", [False, True])
def test_counts_slow(size, fractionated):
    links, dof = size
    assert len(chains(links=links, dof=dof, include_fractionated=fractionated)) == SLOW_ATLAS[size][fractionated]


def _check_atlas(links, dof, fractionated):
    atlas = chains(links=links, dof=dof, include_fractionated=fractionated)
    graphs = [c.to_networkx() for c in atlas]
    for chain, g in zip(atlas, graphs):
        assert nx.is_connected(g)
        assert min(d for _, d in g.degree) >= 2
        assert 3 * (links - 1) - 2 * g.number_of_edges() == dof
        assert not brute_force_degenerate(links, g.edges), chain.graph6
        if not fractionated:
            assert not list(nx.articulation_points(g)), chain.graph6
    assert pairwise_isomorphic(graphs) == []
    return atlas


@pytest.mark.parametrize("size", sorted(s for s in ATLAS if s[0] <= 10))
def test_chains_are_valid_and_pairwise_non_isomorphic(size):
    # Independent of the generator: brute force over every subset, VF2 for isomorphism.
    _check_atlas(*size, fractionated=True)


@pytest.mark.slow
def test_eleven_link_two_dof_chains_are_valid_and_distinct():
    _check_atlas(11, 2, fractionated=True)


@pytest.mark.skipif(GENG is None, reason="nauty's geng is not installed (Debian package nauty)")
@pytest.mark.parametrize("size", [(6, 1), (8, 1), (10, 1), (7, 2), (9, 2), (8, 3), (10, 3), (9, 0)])
def test_complete_against_geng(size):
    # Completeness: geng lists every connected graph with minimum degree 2; the
    # non-degenerate ones must all be in the atlas (and the counts agree).
    links, dof = size
    atlas = [c.to_networkx() for c in chains(links=links, dof=dof, include_fractionated=True)]
    reference = geng_chains(links, atlas[0].number_of_edges(), include_fractionated=True)
    assert len(reference) == len(atlas)
    assert None not in match_into(reference, atlas)


def test_output_is_canonical_and_deterministic():
    assert ChainGenerator().chains(10, 1) == ChainGenerator().chains(10, 1)
    # canonically labelled: relabelling a chain and canonicalising gives it back
    c = chains(links=8, dof=1)[5]
    g = nx.relabel_nodes(c.to_networkx(), {v: (3 * v + 1) % 8 for v in range(8)})
    from domes.model import Chain

    assert Chain.from_networkx(g).canonical().edges == c.edges


def test_generator_reuses_its_atlases():
    gen = ChainGenerator()
    assert gen.chains(8, 1) is gen.chains(8, 1)
