"""Clamping chains: W ≤ 0 and immobile sub-chains admitted (seed 002, §3-3-I (4), Fig. 3-23).

The book: clamping mechanisms are special chains with ``W ≤ 0``; unlike
``W ≥ 1`` chains they contain immobile sub-chains, which "must be noted in the
automatic generation of chains containing clamps" (digest seed-002-ch1-3-4-5-7
§1.10). The hinge clamp (§4-2, Fig. 4-15, digest §2.3) has, besides the two
one-DOF six-bar chains (a), (b), "two variant forms of (b)", (c) and (d),
which no non-degenerate chain can be: only 2 non-degenerate and 3 degenerate
(6, 7) graphs exist (digest §2.3, [verified]).

Every count here is computed twice: by the generator and by a method that
shares nothing with it, brute force over every edge set with networkx VF2
(up to 6 links), or nauty's geng filtered by networkx (7 to 9 links).
"""

from itertools import combinations

import networkx as nx
import pytest
from reference import GENG, brute_force_degenerate, match_into

from domes.cli import main
from domes.errors import InputError
from domes.model import Chain
from domes.typesynth.atlas import ChainGenerator, atlas_position, chains, clamping_joints

GEN = ChainGenerator()


def _sizes(links):
    """Every DOF for which ``links`` links make a closed chain of simple joints: (dof, joints)."""
    for joints in range(links, links * (links - 1) // 2 + 1):
        yield 3 * (links - 1) - 2 * joints, joints


def _classes(graphs):
    """Isomorphism classes of networkx graphs (WL-hash buckets, then VF2)."""
    buckets: dict[str, list] = {}
    for g in graphs:
        bucket = buckets.setdefault(nx.weisfeiler_lehman_graph_hash(g, iterations=3), [])
        if not any(nx.is_isomorphic(g, h) for h in bucket):
            bucket.append(g)
    return [g for bucket in buckets.values() for g in bucket]


def _brute_force(links):
    """{joints: (2-connected classes, all classes)} of connected simple graphs with min degree 2, from every edge set."""
    pairs = list(combinations(range(links), 2))
    out = {}
    for _, joints in _sizes(links):
        found = []
        for edges in combinations(pairs, joints):
            g = nx.Graph(edges)
            if g.number_of_nodes() == links and min(d for _, d in g.degree) >= 2 and nx.is_connected(g):
                found.append(g)
        every = _classes(found)
        out[joints] = ([g for g in every if nx.is_biconnected(g)], every)
    return out


def _geng(links, joints):
    import subprocess

    text = subprocess.run([GENG, "-cq", "-d2", str(links), f"{joints}:{joints}"], capture_output=True, text=True,
                          check=True).stdout
    return [nx.from_graph6_bytes(line.encode()) for line in text.split()]


def _same_classes(atlas, reference):
    """The atlas and the reference list the same isomorphism classes, each once."""
    graphs = [c.to_networkx() for c in atlas]
    # every reference class is in the atlas and the counts agree: the atlas holds each class exactly once
    return len(graphs) == len(reference) and None not in match_into(reference, graphs)


@pytest.mark.parametrize("links", [3, 4, 5, 6])
def test_every_size_against_brute_force(links):
    # Brute force: every set of joints on `links` links, reduced by VF2; no nauty, no ears.
    reference = _brute_force(links)
    for dof, joints in _sizes(links):
        blocks, every = reference[joints]
        assert _same_classes(chains(links, dof, clamping=True), blocks), (links, dof)
        assert _same_classes(chains(links, dof, include_fractionated=True, clamping=True), every), (links, dof)


@pytest.mark.skipif(GENG is None, reason="nauty's geng is not installed (Debian package nauty)")
@pytest.mark.parametrize("size", [*[(7, d) for d, _ in _sizes(7)], (8, 3), (8, 1), (8, -1), (8, -3), (8, -9),
                                  (9, 2), (9, 0), (9, -2)])
def test_complete_against_geng(size):
    # geng lists every connected graph of minimum degree 2 with the joints; networkx finds the 2-connected ones.
    links, dof = size
    reference = _geng(links, clamping_joints(links, dof))
    assert _same_classes(chains(links, dof, include_fractionated=True, clamping=True), reference)
    assert _same_classes(chains(links, dof, clamping=True), [g for g in reference if nx.is_biconnected(g)])


@pytest.mark.parametrize("size", [(4, 1), (6, 1), (8, 1), (5, 2), (7, 2), (9, 2), (6, 3), (8, 3), (3, 0), (5, 0),
                                  (7, 0), (9, 0)])
@pytest.mark.parametrize("fractionated", [False, True])
def test_the_mobile_part_is_the_default_atlas(size, fractionated):
    # Admitting immobile sub-chains adds chains and removes none: the clamping atlas without its degenerate
    # chains (brute-force subset test) is the default atlas, whose counts the brief and Table 3-4 give.
    links, dof = size
    mobile = [c for c in chains(links, dof, fractionated, clamping=True) if not brute_force_degenerate(links, c.edges)]
    assert set(mobile) == set(chains(links, dof, fractionated)) and len(mobile) == len(chains(links, dof, fractionated))


def test_basic_chains_are_the_zero_dof_clamping_chains_without_an_immobile_sub_chain():
    # Table 3-4: V = 1..4 loops give 1, 1, 3, 28 basic chains; (3-23) deletes every other [0; V] chain.
    counts = [sum(not brute_force_degenerate(2 * v + 1, c.edges) for c in chains(2 * v + 1, 0, True, clamping=True))
              for v in (1, 2, 3, 4)]
    assert counts == [1, 1, 3, 28]


@pytest.mark.parametrize("size", [*[(n, d) for n in (4, 5, 6, 7) for d, _ in _sizes(n) if d <= -1], (8, -1), (8, -3)])
def test_clamp_chains_below_zero_dof_all_hold_an_immobile_sub_chain(size):
    # Seed 002 §3-3-I (4): unlike W >= 1 chains, clamp chains contain immobile sub-chains. For W <= -1 every one
    # does (a link of two joints leaves a sub-chain of DOF W + 1 <= 0).
    links, dof = size
    atlas = chains(links, dof, include_fractionated=True, clamping=True)
    assert atlas and all(brute_force_degenerate(links, c.edges) for c in atlas)


def test_the_smallest_clamp_chain_of_fig_3_23_dof():
    # Fig. 3-23: a simple clamp whose generalized chain has W = -1. The fewest links with W = -1 are 4 (5 joints):
    # one chain, two rigid triangles sharing a joint.
    with pytest.raises(InputError, match="not an integer"):
        chains(3, -1, clamping=True)
    (clamp,) = chains(4, -1, include_fractionated=True, clamping=True)
    assert clamp == Chain(4, [(0, 1), (1, 2), (2, 0), (1, 3), (2, 3)])
    assert clamp.dof == -1 and clamp.is_degenerate and clamp.dof_type == "rigid"


def test_hinge_clamp_chains_c_and_d_are_generated():
    # Seed 002 §4-2, Fig. 4-15 (digest §2.3): N = 6, J = 7 (W = 1); (a), (b) are the Watt and Stephenson chains,
    # (c), (d) "two variant forms of (b)". Read as the two (6, 7) chains with (b)'s links (four binary, two
    # ternary) that hold an immobile sub-chain (the third degenerate one has a quaternary link instead):
    #   (c) the ternary links jointed, with a branch of one and a branch of three binary links: a rigid triangle;
    #   (d) two rigid triangles joined by one joint between their ternary links (two cut links).
    c = Chain(6, [(0, 1), (0, 2), (2, 1), (0, 3), (3, 4), (4, 5), (5, 1)])
    d = Chain(6, [(0, 2), (2, 3), (3, 0), (0, 1), (1, 4), (4, 5), (5, 1)])
    every = chains(6, 1, include_fractionated=True, clamping=True)
    mobile = [x for x in every if not x.is_degenerate]
    variants = [x for x in every if x.is_degenerate and x.assortment == {2: 4, 3: 2}]
    assert len(every) == 5 and len(mobile) == 2 and len(every) - len(mobile) == 3    # digest §2.3: 2 + 3
    assert sorted(x.common_name for x in mobile) == ["Stephenson", "Watt"]
    assert set(variants) == {c, d}
    assert not c.cut_links and d.cut_links == [0, 1]
    assert c.rigid_subchain == [0, 1, 2] and len(d.rigid_subchain) == 3
    assert c in chains(6, 1, clamping=True) and d not in chains(6, 1, clamping=True)   # (d) needs cut links
    assert c not in chains(6, 1, include_fractionated=True)                          # unreachable by default
    assert atlas_position(c) is None and atlas_position(c, clamping=True) is not None
    assert every[atlas_position(d, clamping=True) - 1] == d


def test_default_behaviour_is_unchanged_and_caches_are_separate():
    gen = ChainGenerator()
    assert len(gen.chains(6, 1, clamping=True)) == 3
    assert len(gen.chains(6, 1)) == 2 and len(gen.chains(9, 0)) == 28
    assert gen.chains(7, -2, clamping=True) is gen.chains(7, -2, clamping=True)
    assert GEN.chains(8, 1, clamping=True) == ChainGenerator().chains(8, 1, clamping=True)   # deterministic


def test_charpoly_knob_for_clamping_chains_is_not_exact():
    # The book's test (§3-2-II.4) merges chains with one characteristic polynomial: here it keeps one chain per
    # polynomial, fewer than there are chains.
    exact = chains(8, -1, include_fractionated=True, clamping=True)
    book = chains(8, -1, include_fractionated=True, clamping=True, isomorphism="charpoly")
    assert len(book) == len({c.characteristic_polynomial for c in exact}) < len(exact)
    assert "not exact" in book.message


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: chains(6, -1), "clamping=True"),
        (lambda: ChainGenerator().chains(8, -3, include_fractionated=True), "clamping=True"),
        (lambda: chains(5, -1, clamping=True), "not an integer"),
        (lambda: chains(4, -5, clamping=True), "only 6 pairs"),
        (lambda: chains(4, 3, clamping=True), "no closed chain"),
        (lambda: chains(2, 0, clamping=True), "links"),
        (lambda: chains(12, -3, clamping=True), "out of reach"),
        (lambda: chains(6, 1.0, clamping=True), "whole number"),
    ],
)
def test_bad_requests_say_what_to_do(call, message):
    with pytest.raises(InputError, match=message):
        call()


def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


def test_cli_lists_clamping_chains(capsys):
    status, out, _ = run(capsys, "chains", "--links", "6", "--dof", "1", "--clamping", "--include-fractionated")
    rows = [line for line in out.splitlines() if not line.startswith("#")]
    assert status == 0 and len(rows) == 5 and sum("immobile sub-chain" in r for r in rows) == 3
    assert "3 with an immobile sub-chain" in out.splitlines()[0]
    assert run(capsys, "chains", "--links", "6", "--dof", "-1", "--clamping", "--count")[1] == "9\n"
    assert run(capsys, "chains", "--loops", "3", "--dof", "-1", "--clamping", "--count")[1] == "9\n"
    status, out, _ = run(capsys, "chains", "--links", "4", "--dof", "-1", "--clamping", "--format", "json")
    import json

    data = json.loads(out)
    assert data["clamping"] is True and data["count"] == 1 and data["chains"][0]["degenerate"]


@pytest.mark.parametrize(
    "argv, message",
    [
        (["chains", "--links", "6", "--dof", "-1"], "--clamping"),
        (["chains", "--links", "6", "--dof", "-1", "--clamping", "--out", "x"], "--out"),
        (["chains", "--loops", "1", "--dof", "-5", "--clamping"], "at least 3 links"),
        (["chains", "--links", "4", "--dof", "-5", "--clamping"], "pairs"),
    ],
)
def test_cli_bad_requests_exit_2(capsys, argv, message):
    status, out, err = run(capsys, *argv)
    assert status == 2 and out == "" and message in err


def test_the_counts_in_docs_are_computed():
    # docs/chains.md lists clamping counts; each is computed again here (the sizes are checked against brute force
    # or geng above).
    import re
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "chains.md").read_text()
    table = page.split("| DOF | links: clamping chains |")[1].split("\n\n")[0]
    rows = re.findall(r"^\| (−?\d+) \| (.+) \|$", table, re.M)
    assert len(rows) == 5
    for dof, cells in rows:
        for links, count, with_cut in re.findall(r"(\d+): (\d+)(?: \((\d+)\))?", cells):
            n, f = int(links), int(dof.replace("−", "-"))
            assert len(chains(n, f, clamping=True)) == int(count), (n, f)
            assert len(chains(n, f, include_fractionated=True, clamping=True)) == int(with_cut or count), (n, f)
