"""Evaluation of criteria on labelled graphs: hand-made examples and a brute-force reference."""

import itertools
import random

import networkx as nx
import pytest

from domes.language.evaluate import compile_criterion, graph_features, holds
from domes.language.explain import explain
from domes.language.parse import parse_criterion
from domes.language.tree import (
    Adjacent,
    Comparison,
    Count,
    Distance,
    Domain,
    ForAll,
    HasMember,
    JointCount,
    Not,
    Represents,
    TypeIs,
)
from domes.model import LabelledChain
from domes.model.topology import Topology, simple_cycles
from domes.typesynth import chains

BOOK_I = "THE VALUE OF PROPERTY “TYPE” SHOULD NOT BE EQUAL TO (G P R) FOR ANY VERTEX"
BOOK_II = "THE NUMBER OF VER-TICES WHOSE “TYPE” PROPERTY HAS VALUE (P R) SHOULD NOT BE GREATER THAN 1"
BOOK_III = "NUMBER OF GEAR PAIRS SHOULD NOT BE MORE THAN 1 FOR ANY INDEPENDENT LOOP"
BOOK_IV = "NUMBER OF INDEPENDENT LOOPS WITH A SLIDER PAIR IN IT SHOULD NOT BE MORE THAN 1"
BOOK_V = "THE VERTEX REPRESENTING “PISTON” MUST HAVE ITS “TYPE” PROPERTY-VALUE AS (P R)"
BOOK_VI = "THE INDEPENDENT LOOP REPRESENTING “DRIVE” LOOP MUST NOT HAVE A SLIDER PAIR IN IT"

# Seed 002 §4-1, digest 2.2: the Suzuki RM-250X MTM, links 1..6 renumbered 0..5:
# a 1-2, b 1-3, c 2-4, e 3-4, d 2-5, f 3-6 (R) and g 5-6 (P): a Stephenson chain.
STEPHENSON = [(0, 1), (0, 2), (1, 3), (2, 3), (1, 4), (2, 5), (4, 5)]
# Watt chain: adjacent ternary links 0 and 1 with branches 0-2-3-1 and 0-4-5-1.
WATT = [(0, 1), (0, 2), (2, 3), (1, 3), (0, 4), (4, 5), (1, 5)]
FOUR_BAR = [(0, 1), (1, 2), (2, 3), (0, 3)]


def chain(edges, types=None, roles=None, loops=None, n=None):
    n = n or 1 + max(max(e) for e in edges)
    return LabelledChain.build(n, edges, types or {}, roles, loops)


def keeps(text, graph):
    return holds(parse_criterion(text), graph)


# -- the six book sentences on hand-made graphs (seed 002 §7-2, digest 4.5) ----------


def test_book_i_rejects_a_link_with_gear_slider_and_revolute():
    gpr = chain(STEPHENSON, {(0, 1): "G", (1, 3): "P"})  # link 1: joints 0-1 G, 1-3 P, 1-4 R
    gp = chain(STEPHENSON, {(0, 1): "G", (1, 3): "P", (1, 4): "G"})  # link 1: (G P)
    assert not keeps(BOOK_I, gpr)
    assert keeps(BOOK_I, gp)


def test_book_ii_counts_links_whose_type_is_p_r():
    suzuki = chain(STEPHENSON, {(4, 5): "P"})  # piston 4 and cylinder 5 are both (P R)
    one = chain(STEPHENSON, {(0, 1): "G", (1, 3): "P"})  # only link 3 is (P R); link 1 is (G P R)
    assert not keeps(BOOK_II, suzuki)
    assert keeps(BOOK_II, one)
    assert keeps(BOOK_II, chain(FOUR_BAR))


def test_book_iii_gear_pairs_per_independent_loop():
    # Watt loops: A = 0-2-3-1, B = 0-4-5-1, C = the outer 6-loop (A + B).
    one_each = chain(WATT, {(0, 2): "G", (4, 5): "G"})  # A and B one gear pair each (C has two)
    two_in_a = chain(WATT, {(0, 2): "G", (2, 3): "G"})  # every basis holds A or C, both with two
    assert keeps(BOOK_III, one_each)
    assert not keeps(BOOK_III, two_in_a)
    # "every loop" (every simple cycle) is stricter: C holds two gear pairs.
    assert not keeps("the number of gear pairs should not be more than 1 for any loop", one_each)


def test_book_iv_independent_loops_with_a_slider():
    in_a = chain(WATT, {(0, 2): "P"})  # in A and C; basis {A, B}: one loop with a slider
    shared = chain(WATT, {(0, 1): "P"})  # in A and B, not C; basis {A, C}: one
    both = chain(WATT, {(0, 2): "P", (4, 5): "P"})  # every loop has a slider: two
    assert keeps(BOOK_IV, in_a)
    assert keeps(BOOK_IV, shared)
    assert not keeps(BOOK_IV, both)


def test_book_v_named_piston_vertex():
    suzuki = {(4, 5): "P"}
    assert keeps(BOOK_V, chain(STEPHENSON, suzuki, roles={4: {"piston"}, 0: {"ground"}}))
    assert not keeps(BOOK_V, chain(STEPHENSON, suzuki, roles={1: {"piston"}}))  # link 1 is (R)
    assert keeps(BOOK_V, chain(STEPHENSON, suzuki))  # no piston yet: nothing to violate


def test_book_vi_named_drive_loop():
    drive = {"drive": [0, 2, 3, 1]}
    assert keeps(BOOK_VI, chain(WATT, {(4, 5): "P"}, loops=drive))
    assert not keeps(BOOK_VI, chain(WATT, {(2, 3): "P"}, loops=drive))
    assert keeps(BOOK_VI, chain(WATT, {(2, 3): "P"}))  # no drive loop named


def test_scene_rules_on_the_suzuki_original():
    # Seed 002 §4-1: ground link 1, swing arm link 3, shock absorber links 5 and 6 (0-based 0, 2, 4, 5).
    suzuki = chain(STEPHENSON, {(4, 5): "P"}, roles={0: {"ground"}, 2: {"swing_arm"}, 4: {"shock_absorber"}, 5: {"shock_absorber"}})
    assert keeps("the swing arm is adjacent to the ground", suzuki)
    assert keeps("the vertices representing “shock absorber” must be binary and adjacent to a vertex representing "
                 "“shock absorber” and not represent “ground”", suzuki)
    assert keeps("the shock absorber must be adjacent to the shock absorber by a prismatic pair", suzuki)
    assert not keeps("the swing arm must share no joint with the ground", suzuki)
    assert keeps("the vertex representing “swing arm” must be at distance 2 from the shock absorber or be adjacent to "
                 "the shock absorber", suzuki)


# -- motorcycle suspension counts through the language (seed 002 §4-1; digest A8) -------

SHOCK_RULES = [
    "the number of vertices representing “ground” must be equal to 1",
    "the number of vertices representing “swing arm” must be equal to 1",
    "the number of vertices representing “shock absorber” should be equal to 2",
    "the vertices representing “shock absorber” must be binary and adjacent to a vertex representing "
    "“shock absorber” and not represent “ground”",
    "the swing arm must not represent the ground and must not represent the shock absorber",
]


def test_motorcycle_ground_and_shock_absorber_counts():
    # Book: 2 + 3 = 5 choices of ground (Fig. 4-9a-e); 4 shock-absorber structures (4-10a-d; 4-9e has none).
    dyad = [compile_criterion(parse_criterion(t)) for t in SHOCK_RULES[2:4]]
    grounds, structures = set(), set()
    for c in chains(links=6, dof=1):
        for ground in range(6):
            grounds.add(LabelledChain.build(6, c.edges, None, {ground: {"ground"}}))
            for pair in itertools.combinations(range(6), 2):
                roles = {v: {"shock_absorber"} for v in pair}
                roles.setdefault(ground, set()).add("ground")
                g = LabelledChain.build(6, c.edges, None, roles)
                if all(t(graph_features(g)) for t in dyad):
                    structures.add(g)
    assert len(grounds) == 5
    assert len(structures) == 4


def test_motorcycle_counts_ten_then_six():
    # Book: 10 swing-arm designs (Fig. 4-11a-j); with "the swing arm is adjacent to the ground", 6.
    tests = [compile_criterion(parse_criterion(t)) for t in SHOCK_RULES]
    designs = set()
    for c in chains(links=6, dof=1):
        for ground, swing in itertools.permutations(range(6), 2):
            for pair in itertools.combinations(range(6), 2):
                roles = {v: set() for v in range(6)}
                roles[ground].add("ground")
                roles[swing].add("swing_arm")
                for v in pair:
                    roles[v].add("shock_absorber")
                g = LabelledChain.build(6, c.edges, None, roles)
                f = graph_features(g)
                if all(t(f) for t in tests):
                    designs.add(g)
    assert len(designs) == 10
    adjacent = compile_criterion(parse_criterion("the swing arm is adjacent to the ground"))
    assert sum(adjacent(graph_features(g)) for g in designs) == 6


# -- brute-force reference over cycle bases and networkx ------------------------------


def gf2_rank(rows):
    rows = [list(r) for r in rows]
    rank, cols = 0, len(rows[0]) if rows else 0
    for col in range(cols):
        pivot = next((i for i in range(rank, len(rows)) if rows[i][col]), None)
        if pivot is None:
            continue
        rows[rank], rows[pivot] = rows[pivot], rows[rank]
        for i in range(len(rows)):
            if i != rank and rows[i][col]:
                rows[i] = [a ^ b for a, b in zip(rows[i], rows[rank])]
        rank += 1
    return rank


def reference_cycles(g: nx.Graph):
    edges = sorted(tuple(sorted(e)) for e in g.edges)
    out = []
    for cyc in nx.simple_cycles(g):
        pairs = {tuple(sorted(p)) for p in zip(cyc, cyc[1:] + cyc[:1])}
        out.append((cyc, [1 if e in pairs else 0 for e in edges], [g.edges[e]["type"] for e in pairs]))
    return out


def reference_loop(cond, cyc, types, g):
    if isinstance(cond, JointCount):
        return cond.comparison(len(types) if cond.joint is None else types.count(cond.joint))
    if isinstance(cond, HasMember):
        return any(cond.role in g.nodes[v]["roles"] for v in cyc)
    if isinstance(cond, TypeIs):
        return set(types) == set(cond.joints)
    if isinstance(cond, Not):
        return not reference_loop(cond.item, cyc, types, g)
    raise AssertionError(cond)


def reference_independent(tree, g):
    cycles = reference_cycles(g)
    L = g.number_of_edges() - g.number_of_nodes() + nx.number_connected_components(g)
    best = None
    for basis in itertools.combinations(cycles, L):
        if gf2_rank([v for _, v, _ in basis]) < L:
            continue
        k = sum(reference_loop(tree.condition, c, t, g) for c, _, t in basis)
        if isinstance(tree, ForAll):
            if k == L:
                return True
        else:
            best = k if best is None else min(best, k)
    return False if isinstance(tree, ForAll) else tree.comparison(best)


def reference_vertex(cond, v, g):
    types = {g.edges[v, w]["type"] for w in g[v]}
    if isinstance(cond, TypeIs):
        return types == set(cond.joints)
    if isinstance(cond, JointCount):
        return cond.comparison(sum(1 for w in g[v] if cond.joint in (None, g.edges[v, w]["type"])))
    if isinstance(cond, Adjacent):
        return any(cond.role in g.nodes[w]["roles"] and cond.joint in (None, g.edges[v, w]["type"]) for w in g[v])
    if isinstance(cond, Distance):
        lengths = nx.single_source_shortest_path_length(g, v)
        d = min((lengths[w] for w in lengths if cond.role in g.nodes[w]["roles"]), default=10**9)
        return cond.comparison(d)
    if isinstance(cond, Represents):
        return cond.role in g.nodes[v]["roles"]
    if isinstance(cond, Not):
        return not reference_vertex(cond.item, v, g)
    raise AssertionError(cond)


def random_graphs(rng, count):
    atlas = [c.edges for c in chains(links=6, dof=1)] + [c.edges for c in chains(links=8, dof=1)][:6] + [FOUR_BAR]
    for _ in range(count):
        edges = rng.choice(atlas)
        n = 1 + max(max(e) for e in edges)
        types = [rng.choice("RRRPPG") for _ in edges]
        roles = {v: {rng.choice(["ground", "input", "output"])} for v in rng.sample(range(n), 3)}
        yield LabelledChain.build(n, edges, types, roles)


def random_comparison(rng):
    return Comparison(rng.choice(["<", "<=", "=", "!=", ">=", ">"]), rng.randint(0, 3))


def random_loop_condition(rng):
    kind = rng.randrange(4)
    if kind == 0:
        c = JointCount(rng.choice([None, "R", "P", "G"]), random_comparison(rng))
    elif kind == 1:
        c = HasMember(rng.choice(["ground", "input", "output"]))
    elif kind == 2:
        c = TypeIs("=", tuple(sorted(rng.sample("GPR", rng.randint(1, 3)))))
    else:
        c = JointCount(rng.choice(["P", "G"]), Comparison(">=", 1))
    return Not(c) if rng.random() < 0.3 else c


def random_vertex_condition(rng):
    role = rng.choice(["ground", "input", "output"])
    c = rng.choice([
        TypeIs("=", tuple(sorted(rng.sample("GPR", rng.randint(1, 2))))),
        JointCount(rng.choice([None, "R", "P"]), random_comparison(rng)),
        Adjacent(role, rng.choice([None, "R", "P"])),
        Distance(role, random_comparison(rng)),
        Represents(role),
    ])
    return Not(c) if rng.random() < 0.3 else c


def test_loop_statements_agree_with_brute_force_over_cycle_bases():
    rng = random.Random(4)
    for g in random_graphs(rng, 150):
        nxg = g.to_networkx()
        f = graph_features(g)
        cond = random_loop_condition(rng)
        forall = ForAll(Domain("independent_loop"), cond)
        count = Count(Domain("independent_loop"), cond, random_comparison(rng))
        assert compile_criterion(forall)(f) == reference_independent(forall, nxg), (g.edges, g.joint_types, cond)
        assert compile_criterion(count)(f) == reference_independent(count, nxg), (g.edges, g.joint_types, count)
        every = ForAll(Domain("loop"), cond)
        cycles = reference_cycles(nxg)
        assert compile_criterion(every)(f) == all(reference_loop(cond, c, t, nxg) for c, _, t in cycles)


def test_vertex_statements_agree_with_networkx():
    rng = random.Random(7)
    for g in random_graphs(rng, 200):
        nxg = g.to_networkx()
        f = graph_features(g)
        cond = random_vertex_condition(rng)
        sat = [reference_vertex(cond, v, nxg) for v in range(g.n)]
        cmp = random_comparison(rng)
        assert compile_criterion(ForAll(Domain("vertex"), cond))(f) == all(sat)
        assert compile_criterion(Count(Domain("vertex"), cond, cmp))(f) == cmp(sum(sat))
        assert compile_criterion(ForAll(Domain("vertex", "input"), cond))(f) == all(
            s for v, s in enumerate(sat) if "input" in g.roles[v]
        )


@pytest.mark.parametrize("links", [4, 6, 8])
def test_simple_cycles_match_networkx(links):
    for c in chains(links=links, dof=1):
        g = nx.Graph(list(c.edges))
        assert len(simple_cycles(c.n, c.edges)) == len(list(nx.simple_cycles(g)))
        assert Topology(c.n, tuple(c.edges)).loops == c.loops == c.topology.loops


def test_explanations_name_what_breaks_the_criterion():
    g = chain(WATT, {(0, 2): "G", (2, 3): "G", (1, 3): "P", (4, 5): "P"},
              roles={0: {"ground"}, 3: {"swing_arm"}}, loops={"drive": [0, 2, 3, 1]})
    # Loops of the Watt chain: A = 0-2-3-1 (two gear pairs), B = 0-4-5-1, C = A + B (two gear pairs).
    assert explain(parse_criterion(BOOK_III), g) == (
        "only 1 of the 2 independent loops can be chosen so that each meets: must have at most 1 gear pair")
    assert explain(parse_criterion(BOOK_IV), g).startswith("the number of independent loops that have a prismatic pair is 2")
    assert explain(parse_criterion(BOOK_VI), g) == (
        "not met by the drive loop (links 0, 1, 2, 3): must not have a prismatic pair")
    assert explain(parse_criterion("the swing arm is adjacent to the ground"), g) == (
        "not met by link 3: must be adjacent to “ground”")
    assert explain(parse_criterion("the number of loops must be 2"), g) == "the number of loops is 3, not 2"
    assert explain(parse_criterion(BOOK_I), g) is None
