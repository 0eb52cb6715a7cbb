"""Mechanism descriptions, MTM/TYPE matrices, generalization and joint labelling (seed 002, §3-3, §4-1, §5-3)."""

from itertools import combinations, permutations

import networkx as nx
import pytest

from domes.errors import DomesError
from domes.io.resources import knowledge_dir
from domes.io.topology import from_mtm, from_type_matrix, read_topology, to_mtm, type_matrix, write_topology
from domes.model import LabelledChain
from domes.typesynth import chains, generalize, label_joints

# §4-1, Fig. 4-6: the Suzuki RM-250X MTM, row 4 corrected from "c c" to "c e" (digest 2.2).
SUZUKI_MTM = """
G R R 0 0 0
a L 0 R R 0
b 0 L R 0 R
0 c e L 0 0
0 d 0 0 P P
0 0 f 0 g C
"""


def test_suzuki_mtm_generalizes_to_the_stephenson_chain():
    m = from_mtm(SUZUKI_MTM, name="Suzuki RM-250X")
    assert to_mtm(m) == SUZUKI_MTM.strip()
    g = generalize(m)
    assert (g.chain.n, len(g.chain.edges)) == (6, 7)  # a 6-link, 7-joint chain (§4-1)
    assert g.unlabelled.common_name == "Stephenson"
    assert g.marks == {"P": ["5-6"]}
    # same chain as the shipped mechanism file
    shipped = read_topology(knowledge_dir() / "mechanisms" / "suzuki-rm250x.toml")
    assert generalize(shipped).chain == g.chain


def test_mtm_errors_name_the_entry():
    with pytest.raises(DomesError, match=r"MTM \(1,2\)"):
        from_mtm("G R\n0 L")
    with pytest.raises(DomesError, match="row 2"):
        from_mtm("G R\na")
    with pytest.raises(DomesError, match="unknown link type"):
        from_mtm("X R\na L")


def test_type_matrix_of_the_book_example():
    # §5-3: TYPE matrix of a regenerated hinge clamp: link 5 (ternary) the frame,
    # link 1 the driver E, links 4 / 3 the cylinder halves H1 / H2.
    book = "M N G E H1 H2\n1 2 0 1 0 0\n2 3 0 0 0 0\n3 2 0 0 0 1\n4 2 0 0 1 0\n5 3 1 0 0 0\n6 2 0 0 0 0"
    adjacency = "\n".join(
        " ".join("1" if {i, k} in ({1, 2}, {2, 3}, {3, 4}, {4, 5}, {5, 6}, {6, 1}, {2, 5}) else "0" for k in range(1, 7))
        for i in range(1, 7)
    )
    m = from_type_matrix(adjacency, book)
    assert type_matrix(m) == book
    assert sorted(m.roles[4]) == ["ground"] and sorted(m.roles[0]) == ["input"]


def test_mechanism_file_round_trip(tmp_path):
    m = read_topology(knowledge_dir() / "mechanisms" / "tyre-drum-fig5-1.toml")
    write_topology(m, tmp_path / "drum.toml")
    again = read_topology(tmp_path / "drum.toml")
    assert again == m and again.to_dict() == m.to_dict()  # the same chain, names and all


def test_mechanism_file_errors_name_file_and_line(tmp_path):
    path = tmp_path / "bad.toml"
    path.write_text('name = "x"\n[[links]]\nname = "1"\n[[links]]\nname = "2"\n[[joints]]\nlinks = ["1", "3"]\n')
    with pytest.raises(DomesError, match=r"bad\.toml.*unknown link '3'"):
        read_topology(path)
    path.write_text('name = "x"\n[[links]\n')
    with pytest.raises(DomesError, match=r"bad\.toml: TOML syntax error.*line 2"):
        read_topology(path)


def kutzbach(m: LabelledChain) -> int:
    """Planar DOF of a mechanism, counted independently: lower pairs remove 2, higher pairs 1, force elements 0."""
    removed = {"R": 2, "P": 2, "O": 2, "G": 1, "C": 1}
    return 3 * (m.n - 1) - sum(removed.get(t, 0) for t in m.joint_types)


@pytest.mark.parametrize(
    "joints",
    [
        [("0", "1", "R"), ("1", "2", "C"), ("2", "0", "R")],  # cam with rocker follower (Fig. 3-21a)
        [("0", "1", "R"), ("1", "2", "G"), ("2", "0", "R")],  # gear pair (Fig. 3-21b)
        [("0", "1", "R"), ("1", "2", "R"), ("2", "3", "R"), ("3", "0", "R"), ("1", "3", "S")],  # spring
        [("0", "1", "R"), ("1", "2", "R"), ("2", "3", "R"), ("3", "0", "R"), ("0", "2", "H")],  # cylinder
        [("0", "1", "R"), ("1", "2", "P"), ("2", "3", "R"), ("3", "0", "R"), ("1", "3", "Fp")],  # force
    ],
)
def test_generalization_keeps_the_dof(joints):
    # Table 3-5: each replacement leaves the mobility unchanged.
    names = sorted({x for a, b, _ in joints for x in (a, b)})
    m = LabelledChain.from_named("m", [(n, []) for n in names], [("", a, b, t) for a, b, t in joints])
    g = generalize(m)
    assert g.unlabelled.dof == kutzbach(m)
    assert set(g.chain.joint_types) <= {"R", "P", "S", "H", "F", "Fp", "Fr"}


def brute_labellings(chain, counts, per_loop_max=None):
    """Orbits of joint-type assignments under the chain's automorphisms (networkx VF2)."""
    g = chain.to_networkx()
    edges = [tuple(sorted(e)) for e in g.edges]
    autos = list(nx.algorithms.isomorphism.GraphMatcher(g, g).isomorphisms_iter())
    cycles = [set(tuple(sorted(p)) for p in zip(c, c[1:] + c[:1])) for c in nx.simple_cycles(g)]
    loops = g.number_of_edges() - g.number_of_nodes() + 1

    def spans(label):
        # some cycle basis within the limits: greedy basis search by brute force over cycle subsets
        ok = [c for c in cycles if all(sum(label.get(e) == t for e in c) <= m for t, m in per_loop_max.items())]
        for basis in combinations(ok, loops):
            if independent(basis):
                return True
        return False

    def independent(basis):
        vectors = [frozenset(c) for c in basis]
        for r in range(1, len(vectors) + 1):
            for subset in combinations(vectors, r):
                acc = frozenset()
                for v in subset:
                    acc = acc ^ v
                if not acc:
                    return False
        return True

    classes = set()
    slots = [t for t in sorted(counts) for _ in range(counts[t])]
    for chosen in combinations(edges, len(slots)):
        for order in set(permutations(slots)):
            label = dict(zip(chosen, order))
            if per_loop_max and not spans(label):
                continue
            canon = min(tuple(sorted((tuple(sorted((s[u], s[v]))), t) for (u, v), t in label.items())) for s in autos)
            classes.add(canon)
    return len(classes)


@pytest.mark.parametrize(
    "links, counts, limits",
    [(6, {"P": 1}, None), (6, {"P": 2}, None), (6, {"P": 1, "G": 1}, None), (8, {"P": 1}, None), (6, {"G": 2}, {"G": 1}), (8, {"G": 2}, {"G": 1})],
)
def test_label_joints_against_brute_force(links, counts, limits):
    atlas = chains(links=links, dof=1)
    ours = label_joints(atlas, counts, limits)
    assert len(ours) == sum(brute_labellings(c, counts, limits) for c in atlas)
    assert len({x.certificate for x in ours}) == len(ours)


def test_label_joints_refuses_bad_counts():
    with pytest.raises(DomesError, match="cannot count"):
        label_joints(chains(links=4, dof=1), {"X": 1})


def test_labelled_chain_certificate_sees_roles_and_types():
    square = [(0, 1), (1, 2), (2, 3), (3, 0)]
    a = LabelledChain.build(4, square, {(0, 1): "P"}, {0: {"ground"}})
    b = LabelledChain.build(4, square, {(2, 3): "P"}, {3: {"ground"}})
    c = LabelledChain.build(4, square, {(1, 2): "P"}, {0: {"ground"}})
    assert a == b and a != c


def test_labelled_chain_plain_data_round_trip():
    chain = LabelledChain.build(
        4, [(0, 1), (1, 2), (2, 3), (3, 0)], {(2, 3): "P"}, {0: {"ground"}, 1: {"input"}}, {"drive": [0, 1, 2, 3]}
    )
    again = LabelledChain.from_dict(chain.to_dict())
    assert again == chain and again.named_loops == chain.named_loops
    with pytest.raises(DomesError, match="graph 3: joint"):
        LabelledChain.from_dict({"links": 3, "joints": [[0, 1, 2, 3]]}, "graph 3")
