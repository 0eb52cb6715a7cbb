"""The pebble game against the subset tables, and the atlas counted a second, independent way.

The independent count (issue 17): nauty's geng lists every 2-connected,
triangle-free graph with the atlas's links and joints (a triangle is a
rigid sub-chain, so none is lost), and the (3, 4) pebble game on the doubled
graph keeps the non-degenerate ones. Neither the generator's ear method, nor
its nauty certificates, nor its subset tables are used.
"""

import random
import subprocess

import pytest
from reference import GENG, brute_force_degenerate, chain_atlas

from domes.model.mobility import chain_joints
from domes.model.pebble import decode_graph6, encode_graph6, pebble_degenerate, pebble_sparse
from domes.model.rigidity import rigid_subchain
from domes.typesynth.atlas import chains

needs_geng = pytest.mark.skipif(GENG is None, reason="nauty's geng is not installed (Debian package nauty)")


def geng(*args):
    return subprocess.run([GENG, "-q", *map(str, args)], capture_output=True, text=True, check=True).stdout.split()


def pebble_count(links, dof):
    joints = chain_joints(links, dof)
    return sum(pebble_sparse(*decode_graph6(g)) for g in geng("-Ct", "-d2", links, f"{joints}:{joints}"))


@needs_geng
@pytest.mark.parametrize("links, joints", [(7, 9), (8, 10), (8, 11), (9, 12), (7, 10)])
def test_pebble_game_agrees_with_brute_force(links, joints):
    # Every connected graph with minimum degree 2: DOF 0, 1 and 2, degenerate or not, fractionated or not.
    graphs = [decode_graph6(g) for g in geng("-c", "-d2", links, f"{joints}:{joints}")]
    assert len(graphs) > 30
    for n, edges in graphs:
        assert pebble_degenerate(n, edges) == brute_force_degenerate(n, edges), encode_graph6(n, edges)
        assert pebble_degenerate(n, edges) == (rigid_subchain(n, edges) is not None)


def test_graph6_codec_round_trips_random_graphs():
    import networkx as nx

    rng = random.Random(17)
    for _ in range(300):
        n = rng.randint(1, 40)
        g = nx.gnp_random_graph(n, rng.random(), seed=rng.randint(0, 10**6))
        text = nx.to_graph6_bytes(g, header=False).decode().strip()
        assert encode_graph6(n, g.edges) == text
        assert set(decode_graph6(text)[1]) == {tuple(sorted(e)) for e in g.edges}


@needs_geng
@pytest.mark.parametrize("links, dof", [(10, 1), (11, 2), (10, 3)])
def test_atlas_count_equals_geng_and_pebble_count(links, dof):
    assert len(chains(links, dof)) == pebble_count(links, dof)


@needs_geng
@pytest.mark.parametrize("links, dof", [(12, 1), pytest.param(13, 2, marks=pytest.mark.slow)])
def test_large_atlas_count_equals_geng_and_pebble_count(tmp_path_factory, links, dof):
    # the atlases built once in a run for the tests that read them (reference.chain_atlas_file)
    assert len(chain_atlas(tmp_path_factory, links, dof)) == pebble_count(links, dof)
