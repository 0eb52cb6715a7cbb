"""Divergence stages that change a chain's elements (seed 002, §3-3-II: stage 3, pair types R → P; stage 4, a
binary link becomes a gear or cam pair or a force member), against an independent brute force.

The digest of seed 002 gives no count for these stages (§1.11 gives only ``S_i = Π n_j``, acceptance check A7;
the worked examples of chapters 4 and 5 assign roles only), so every count here is checked against a brute
force written from the stage definitions: all states (roles on links, types on joints) on the numbered links of
every chain, each change admitted by its structural conditions (a converted link is binary with revolute
joints and no role; the mechanism it leaves has one joint between two links) and by the rules written as Python
predicates; classes under the chain's automorphisms (networkx VF2); the mechanisms contracted independently and
compared with networkx isomorphism. No nauty, no rule parser, none of the engine's helpers.
"""

from __future__ import annotations

import json
import math
import pickle
import textwrap
from itertools import combinations
from pathlib import Path

import networkx as nx
import pytest

from domes.cli import main
from domes.errors import DomesError
from domes.io.scenes import load_scene
from domes.model.chain import Chain
from domes.model.labelled import LabelledChain
from domes.typesynth import chains, regenerate
from domes.typesynth.generalize import generalize

# -- the brute force ---------------------------------------------------------------------------------------------


def automorphisms(g):
    return [dict(m) for m in nx.algorithms.isomorphism.GraphMatcher(g, g).isomorphisms_iter()]


def edge(u, v):
    return (min(u, v), max(u, v))


class State:
    """Roles on the links and the types of the joints that are not revolute, on a numbered chain."""

    def __init__(self, g, roles, types):
        self.g, self.roles, self.types = g, roles, types  # roles: tuple of frozensets; types: frozenset of (edge, t)

    @property
    def key(self):
        return self.roles, self.types

    def with_role(self, links, role):
        return State(self.g, tuple(r | {role} if v in links else r for v, r in enumerate(self.roles)), self.types)

    def with_type(self, e, t):
        return State(self.g, self.roles, self.types | {(e, t)})

    def type(self, u, v):
        return dict(self.types).get(edge(u, v), "R")

    def having(self, role):
        return {v for v, r in enumerate(self.roles) if role in r}


def adjacent(s, a, b, joint=None):
    """Some link of set ``a`` is jointed to some link of set ``b`` (by a joint of type ``joint``)."""
    return any(s.g.has_edge(x, y) and (joint is None or s.type(x, y) == joint) for x in a for y in b)


def every_adjacent(s, a, b):
    """Every link of ``a`` is jointed to a link of ``b`` (the rules' "the A must be adjacent to the B")."""
    return all(adjacent(s, {x}, b) for x in a)


def mechanism(s, marks):
    """Contract every link carrying a conversion role (``marks``: role -> joint type) into a joint between the
    links outside it; None when the result would join two links twice (or a link to itself)."""
    converted = {v for v, r in enumerate(s.roles) if r & set(marks)}
    m = nx.Graph()
    for v in s.g.nodes:
        if v not in converted:
            m.add_node(v, roles=frozenset(s.roles[v]))
    joints = [(u, v, s.type(u, v)) for u, v in s.g.edges if u not in converted and v not in converted]
    for part in nx.connected_components(s.g.subgraph(converted)):
        ends = [x for p in part for x in s.g.neighbors(p) if x not in converted]
        (role,) = {r for p in part for r in s.roles[p] if r in marks}
        joints.append((ends[0], ends[1], marks[role]))
    for u, v, t in joints:
        if u == v or m.has_edge(u, v):
            return None
        m.add_edge(u, v, type=t)
    return m


def brute(links, stages, marks, clash=None):
    """Per stage (classes, raw states) over the chains of ``links`` links, DOF 1, and the final mechanisms.

    ``stages``: dicts with ``kind`` (role, joint type, higher pair, force member), ``select``, ``role``,
    ``joint``, ``optional`` and ``ok`` (the rules: state -> bool); ``clash``: a state -> bool that rejects."""
    graphs = [c.to_networkx() for c in chains(links=links, dof=1)]
    per_graph = [{State(g, tuple(frozenset() for _ in g.nodes), frozenset()).key: None} for g in graphs]
    autos = [automorphisms(g) for g in graphs]
    out = []
    for stage in stages:
        classes = raw = 0
        for k, g in enumerate(graphs):
            following = {}
            for key in per_graph[k]:
                s = State(g, *key)
                converted = {v for v, r in enumerate(s.roles) if r & set(marks)}
                children = [s] if stage.get("optional") else []
                children += list(_changes(s, stage, converted, marks))
                for child in children:
                    if stage["ok"](child) and not (clash and clash(child)):
                        following[child.key] = None
            per_graph[k] = following
            raw += len(following)
            classes += len({_canonical(key, autos[k]) for key in following})
        out.append((classes, raw))
    finals = [mechanism(State(g, *key), marks) for k, g in enumerate(graphs) for key in per_graph[k]]
    return out, finals


def _changes(s, stage, converted, marks):
    kind, g = stage["kind"], s.g
    if kind == "joint type":
        for u, v in g.edges:
            if s.type(u, v) == "R" and u not in converted and v not in converted:
                yield s.with_type(edge(u, v), stage["joint"])
        return
    if kind == "role":
        select = stage.get("select", "link")
        options = ([{v} for v in g.nodes] if select == "link" else
                   [set(e) for e in g.edges] if select == "adjacent pair" else
                   [set(p) for p in combinations(g.nodes, 2)])
        for links in options:
            if not links & converted:
                yield s.with_role(links, stage["role"])
        return

    def free(v):
        return g.degree(v) == 2 and not s.roles[v] and v not in converted and all(
            s.type(v, x) == "R" for x in g.neighbors(v))

    if stage.get("select", "link") == "link":
        options = [{v} for v in g.nodes if free(v)]
    else:
        options = [{u, v} for u, v in g.edges if free(u) and free(v)]
    for links in options:
        outside = {x for v in links for x in g.neighbors(v) if x not in links}
        if outside & converted:
            continue
        child = s.with_role(links, stage["role"])
        if mechanism(child, marks) is not None:
            yield child


def _canonical(key, autos):
    roles, types = key
    return min(
        (tuple(sorted((sigma[v], r) for v, rs in enumerate(roles) for r in rs)),
         tuple(sorted((edge(sigma[u], sigma[v]), t) for (u, v), t in types)))
        for sigma in autos
    )


def same_mechanisms(candidates, finals):
    """The engine's candidates are the brute force's mechanisms, once each (networkx isomorphism; graphs are
    sorted into buckets by their Weisfeiler-Lehman hash first, an invariant, so only a bucket is searched)."""
    def nx_of(m: LabelledChain):
        g = nx.Graph()
        for v in range(m.n):
            g.add_node(v, roles=frozenset(m.roles[v]))
        for (u, v), t in zip(m.edges, m.joint_types):
            g.add_edge(u, v, type=t)
        return g

    def bucket(g):
        nx.set_node_attributes(g, {v: ",".join(sorted(r)) for v, r in g.nodes(data="roles")}, "label")
        return nx.weisfeiler_lehman_graph_hash(g, node_attr="label", edge_attr="type")

    def iso(a, b):
        return nx.is_isomorphic(a, b, node_match=lambda x, y: x["roles"] == y["roles"],
                                edge_match=lambda x, y: x["type"] == y["type"])

    def classes(graphs):
        out: dict[str, list] = {}
        for g in graphs:
            known = out.setdefault(bucket(g), [])
            if not any(iso(g, h) for h in known):
                known.append(g)
        return out

    ours = [nx_of(c.labelled) for c in candidates]
    mine, theirs = classes(ours), classes(finals)
    assert sum(map(len, mine.values())) == len(ours), "a candidate repeats an earlier one"
    assert mine.keys() == theirs.keys()
    assert all(len(mine[k]) == len(theirs[k]) and all(any(iso(g, h) for h in mine[k]) for g in theirs[k]) for k in mine)


def scene_file(tmp_path, text):
    path = tmp_path / "scene.toml"
    path.write_text(textwrap.dedent(text))
    return path


# -- the shipped example scene ----------------------------------------------------------------------------------

CAM_MARKS = {"hs": "C", "return_spring": "S"}
CAM_LINKAGE = [  # knowledge/scenes/cam-linkage.toml, its rules as predicates
    {"kind": "role", "role": "ground", "ok": lambda s: True},
    {"kind": "role", "role": "input",
     "ok": lambda s: all(s.g.degree(v) == 3 for v in s.having("input")) and every_adjacent(s, s.having("input"), s.having("ground"))},
    {"kind": "higher pair", "role": "hs", "joint": "C", "ok": lambda s: every_adjacent(s, s.having("hs"), s.having("input"))},
    {"kind": "role", "role": "follower",
     "ok": lambda s: every_adjacent(s, s.having("follower"), s.having("hs")) and not s.having("follower") & s.having("input")},
    {"kind": "force member", "role": "return_spring", "joint": "S", "select": "adjacent pair",
     "ok": lambda s: every_adjacent(s, s.having("ground"), s.having("return_spring"))
     and every_adjacent(s, s.having("follower"), s.having("return_spring"))},
    {"kind": "joint type", "joint": "P", "optional": True,
     "ok": lambda s: not any(s.type(v, x) == "P" for v in s.having("input") for x in s.g.neighbors(v))},
]


def test_cam_linkage_scene_matches_brute_force():
    result = regenerate(load_scene("cam-linkage"))
    expected, finals = brute(8, CAM_LINKAGE, CAM_MARKS)
    assert [(s.count, s.raw) for s in result.stages] == expected
    # measured (the book has no count for this scene): 71, 67, 69, 69, 3, 12; raw S_i 128, 138, 156, 156, 5, 20
    assert [s.count for s in result.stages] == [71, 67, 69, 69, 3, 12]
    same_mechanisms(result.candidates, finals)
    assert [s.change for s in result.stages] == ["", "", "link→C", "", "dyad→S", "R→P or none"]


def test_cam_linkage_candidates_generalize_back_to_their_chains():
    # Table 3-5 is the inverse: the cam pair becomes the HS link again, the spring a dyad marked S, P a marked
    # revolute; the chain is the one the candidate came from, and the DOF is kept.
    result = regenerate(load_scene("cam-linkage"))
    atlas = chains(links=8, dof=1)
    for c in result.candidates:
        m = c.labelled
        assert m.n == 5 and m.joint_types.count("C") == m.joint_types.count("S") == 1 and m.joint_types.count("P") <= 1
        g = generalize(m)
        assert Chain(g.chain.n, g.chain.edges).certificate == atlas[c.chain_index - 1].certificate
        removed = {"R": 2, "P": 2, "G": 1, "C": 1}
        assert 3 * (m.n - 1) - sum(removed.get(t, 0) for t in m.joint_types) == 1  # Kutzbach, force elements free


def test_divergence_product_is_the_raw_count():
    # seed 002 §3-3-II (digest A7): S_i = Π n_j, the unscreened total the last raw count
    result = regenerate(load_scene("cam-linkage"))
    for i, stage in enumerate(result.stages):
        assert math.isclose(math.prod(result.divergence_numbers()[: i + 1]), stage.raw)


def test_cli_shows_the_new_stages(capsys):
    assert main(["regenerate", "cam-linkage"]) == 0
    out = capsys.readouterr().out
    assert "cam pair on the driver [link→C]" in out and "return spring [dyad→S]" in out
    assert "slider [R→P or none]" in out and "12 candidates" in out
    assert main(["regenerate", "cam-linkage", "--format", "json"]) == 0
    stages = json.loads(capsys.readouterr().out)["stages"]
    assert [s.get("change") for s in stages] == [None, None, "link→C", None, "dyad→S", "R→P or none"]


def test_fig_3_28_cam_linkage_is_regenerated(tmp_path):
    # seed 002 §3-3-III.2, Fig. 3-28: the 2-DOF five-bar 0-1-2-3-4 with the cam mechanism 4-0-1 (cam on the
    # crank 1, follower 4); with link 0 the frame and 1 the driver (Fig. 3-28c) it is a parallel combination:
    # a driver of three pairs, the frame adjacent to it. Regenerated from the six-bar chains by the same rules.
    path = scene_file(tmp_path, """
        name = "fig-3-28"
        [chains]
        links = 6
        dof = 1
        [[stages]]
        role = "ground"
        [[stages]]
        role = "input"
        rules = ["the input must be ternary and be adjacent to the ground"]
        [[stages]]
        kind = "higher pair"
        role = "HS"
        joint = "C"
        rules = ["the HS must be adjacent to the input"]
    """)
    result = regenerate(load_scene(path))
    marks = {"hs": "C"}
    expected, finals = brute(6, CAM_LINKAGE[:3], marks)
    assert [(s.count, s.raw) for s in result.stages] == expected == [(5, 12), (4, 12), (5, 20)]
    same_mechanisms(result.candidates, finals)
    fig = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0), (1, 4)], ["R"] * 5 + ["C"],
                              {0: {"ground"}, 1: {"input"}})
    matches = [c for c in result.candidates if c.labelled.certificate == fig.certificate]
    assert len(matches) == 1 and result.chain_name(matches[0].chain_index) == "Stephenson"


# -- each kind on its own, against the brute force ---------------------------------------------------------------

GEARS = ("""
    name = "gears"
    [chains]
    links = {links}
    dof = 1
    [[stages]]
    role = "ground"
    [[stages]]
    name = "gear pair"
    kind = "higher pair"
    role = "gear"
    joint = "G"
    rules = ["the “gear” must not be adjacent to the ground"]
    [[stages]]
    name = "second gear pair"
    kind = "higher pair"
    role = "gear"
    joint = "G"
    optional = true
    rules = ["the “gear” must not be adjacent to the ground"]
    [[stages]]
    role = "output"
    rules = ["the output must not be the ground and must be adjacent to the “gear”"]
""", {"gear": "G"}, [
    {"kind": "role", "role": "ground", "ok": lambda s: True},
    {"kind": "higher pair", "role": "gear", "joint": "G", "ok": lambda s: not adjacent(s, s.having("gear"), s.having("ground"))},
    {"kind": "higher pair", "role": "gear", "joint": "G", "optional": True,
     "ok": lambda s: not adjacent(s, s.having("gear"), s.having("ground"))},
    {"kind": "role", "role": "output",
     "ok": lambda s: not s.having("output") & s.having("ground") and every_adjacent(s, s.having("output"), s.having("gear"))},
])

CYLINDER = ("""
    name = "cylinder"
    [chains]
    links = {links}
    dof = 1
    [[stages]]
    role = "ground"
    [[stages]]
    name = "cylinder (an Fp link)"
    kind = "force member"
    role = "cylinder"
    joint = "H"
    rules = ["the cylinder must be adjacent to the ground"]
    [[stages]]
    name = "slider"
    kind = "joint type"
    rules = ["the ground must have at most 1 prismatic pair"]
    [[stages]]
    name = "second slider"
    kind = "joint type"
    optional = true
    rules = ["the ground must have at most 1 prismatic pair"]
""", {"cylinder": "H"}, [
    {"kind": "role", "role": "ground", "ok": lambda s: True},
    {"kind": "force member", "role": "cylinder", "joint": "H", "ok": lambda s: every_adjacent(s, s.having("cylinder"), s.having("ground"))},
    {"kind": "joint type", "joint": "P", "ok": lambda s: all(sum(s.type(v, x) == "P" for x in s.g.neighbors(v)) <= 1 for v in s.having("ground"))},
    {"kind": "joint type", "joint": "P", "optional": True,
     "ok": lambda s: all(sum(s.type(v, x) == "P" for x in s.g.neighbors(v)) <= 1 for v in s.having("ground"))},
])

SPRINGS = ("""
    name = "springs"
    [chains]
    links = {links}
    dof = 1
    [[stages]]
    role = "ground"
    [[stages]]
    name = "spring"
    kind = "force member"
    role = "spring"
    joint = "S"
    select = "adjacent pair"
    [[stages]]
    name = "resisting force"
    kind = "force member"
    role = "load"
    joint = "Fr"
    optional = true
    rules = ["the load must not be adjacent to the ground"]
""", {"spring": "S", "load": "Fr"}, [
    {"kind": "role", "role": "ground", "ok": lambda s: True},
    {"kind": "force member", "role": "spring", "joint": "S", "select": "adjacent pair", "ok": lambda s: True},
    {"kind": "force member", "role": "load", "joint": "Fr", "optional": True,
     "ok": lambda s: not adjacent(s, s.having("load"), s.having("ground"))},
])


#: The counts per stage the brute force confirms (measured; no book counts exist for these stages).
MEASURED = {
    ("gears", 6): [5, 7, 9, 18], ("gears", 8): [71, 160, 272, 664],
    ("cylinder", 6): [5, 5, 21, 60], ("cylinder", 8): [71, 69, 487, 2060],
    ("springs", 6): [5, 2, 2], ("springs", 8): [71, 30, 55],
}


@pytest.mark.parametrize("links", [6, 8])
@pytest.mark.parametrize("name, spec", [("gears", GEARS), ("cylinder", CYLINDER), ("springs", SPRINGS)])
def test_each_kind_matches_brute_force(tmp_path, links, name, spec):
    text, marks, rules = spec
    result = regenerate(load_scene(scene_file(tmp_path, text.format(links=links))))
    expected, finals = brute(links, rules, marks)
    assert [(s.count, s.raw) for s in result.stages] == expected
    assert [s.count for s in result.stages] == MEASURED[name, links]
    same_mechanisms(result.candidates, finals)


def test_a_changed_joint_is_not_one_a_particularize_rule_types(tmp_path):
    # The motorcycle's shock absorber gets its inner P from [[particularize]]; a slider stage may not choose that
    # joint (the two labelled chains would give one mechanism), and every candidate appears once.
    path = scene_file(tmp_path, """
        name = "clash"
        [chains]
        links = 6
        dof = 1
        [[stages]]
        role = "ground"
        [[stages]]
        kind = "joint type"
        rules = ["the ground must have no prismatic pair"]
        [[stages]]
        role = "shock absorber"
        select = "adjacent pair"
        rules = ["the shock absorber must be binary and must not be the ground"]
        [[particularize]]
        between = ["shock absorber", "shock absorber"]
        joint = "P"
    """)
    result = regenerate(load_scene(path))

    def shock_joint_changed(s):
        shock = s.having("shock_absorber")
        return any(s.type(u, v) != "R" for u, v in s.g.edges if u in shock and v in shock)

    rules = [
        {"kind": "role", "role": "ground", "ok": lambda s: True},
        {"kind": "joint type", "joint": "P",
         "ok": lambda s: not any(s.type(v, x) == "P" for v in s.having("ground") for x in s.g.neighbors(v))},
        {"kind": "role", "role": "shock_absorber", "select": "adjacent pair",
         "ok": lambda s: all(s.g.degree(v) == 2 for v in s.having("shock_absorber")) and not s.having("shock_absorber") & s.having("ground")},
    ]
    expected, _ = brute(6, rules, {}, clash=shock_joint_changed)
    assert [(s.count, s.raw) for s in result.stages] == expected
    certificates = [c.labelled.certificate for c in result.candidates]
    assert len(set(certificates)) == len(certificates)


def test_an_existing_design_with_fewer_links_is_recognised(tmp_path):
    # an existing design of a scene that turns links into joints has the mechanisms' links, not the chains'
    scene = Path(load_scene("cam-linkage").path).read_text()
    links = "".join(f'[[links]]\nname = "{n}"\nroles = {roles}\n' for n, roles in
                    [("0", "[]"), ("1", "[]"), ("2", '["ground"]'), ("3", '["input"]'), ("4", '["follower"]')])
    joints = "".join(f'[[joints]]\nlinks = ["{a}", "{b}"]\ntype = "{t}"\n' for a, b, t in
                     [("0", "3", "R"), ("0", "4", "R"), ("1", "2", "R"), ("1", "4", "R"), ("2", "3", "R"),
                      ("2", "4", "S"), ("3", "4", "C")])
    (tmp_path / "design.toml").write_text(f'name = "cam-linkage No. 4"\n{links}{joints}')
    (tmp_path / "scene.toml").write_text(scene + '\n[[existing]]\nmechanism = "design.toml"\n')
    result = regenerate(load_scene(tmp_path / "scene.toml"))
    assert [c.id for c in result.candidates if c.existing] == [4]
    (tmp_path / "ring.toml").write_text('name = "eight"\n' + "".join(f'[[links]]\nname = "{n}"\n' for n in range(8))
                                        + "".join(f'[[joints]]\nlinks = ["{n}", "{(n + 1) % 8}"]\n' for n in range(8)))
    (tmp_path / "ring-scene.toml").write_text(scene + '\n[[existing]]\nmechanism = "ring.toml"\n')
    with pytest.raises(DomesError, match=r"ring-scene\.toml:\d+: existing design 'ring.toml' has 8 links; the scene's "
                                         r"chains have 8, its mechanisms 5$"):
        load_scene(tmp_path / "ring-scene.toml")


def test_regeneration_on_two_workers_is_the_same():
    pytest.importorskip("distributed")
    from domes.execution import executor

    scene = load_scene("cam-linkage")
    here = regenerate(scene)
    with executor(workers=2) as run:
        there = regenerate(scene, executor=run)
    assert here.stages == there.stages
    assert [c.labelled.certificate for c in here.candidates] == [c.labelled.certificate for c in there.candidates]


def test_stages_survive_pickling():
    scene = load_scene("cam-linkage")
    again = pickle.loads(pickle.dumps(scene.stages))
    assert [(s.kind, s.joint, s.optional, s.select, s.role) for s in again] == [
        (s.kind, s.joint, s.optional, s.select, s.role) for s in scene.stages]
    assert all(len(s.tests) == len(s.rules) for s in again)


# -- errors name the file and the line ---------------------------------------------------------------------------

BASE = """\
name = "bad"
[chains]
links = 6
dof = 1
[[stages]]
role = "ground"
[[stages]]
name = "cam pair"
kind = "higher pair"
role = "HS"
joint = "C"
"""


@pytest.mark.parametrize(
    "old, new, line, problem",
    [
        ('kind = "higher pair"', 'kind = "cam"', 9, "kind must be one of role, joint type, higher pair, force member, got 'cam'"),
        ('joint = "C"', 'joint = "S"', 11, "a higher pair stage makes a joint G or C (joint = ...), got 'S'"),
        ('role = "HS"\n', '', 7, "a higher pair stage needs a 'role'"),
        ('joint = "C"', 'joint = "C"\nselect = "adjacent pair"', 12, "select must be one of link for a higher pair stage"),
        ('joint = "C"', 'joint = "C"\noptional = "yes"', 12, "optional must be true or false, got 'yes'"),
        ('kind = "higher pair"\nrole = "HS"\njoint = "C"', 'kind = "joint type"\nrole = "HS"', 10, "a joint type stage gives no role"),
        ('kind = "higher pair"\nrole = "HS"\njoint = "C"', 'kind = "joint type"\njoint = "G"', 10, "a joint type stage makes a joint P or O"),
        ('kind = "higher pair"\nrole = "HS"\njoint = "C"', 'role = "HS"\noptional = true', 10, "'optional' belongs to a stage of kind"),
        ('role = "HS"', 'role = "ground"', 7, "role 'ground' is given by stage 1 (ground) as a role; here it is a higher pair"),
    ],
)
def test_stage_errors_name_file_and_line(tmp_path, old, new, line, problem):
    assert old in BASE
    path = tmp_path / "bad.toml"
    path.write_text(BASE.replace(old, new))
    with pytest.raises(DomesError) as info:
        load_scene(path)
    assert str(info.value).startswith(f"{path}:{line}: stage "), str(info.value)
    assert problem in str(info.value)


@pytest.mark.parametrize(
    "extra, line, problem",
    [
        ('[[stages]]\nkind = "higher pair"\nrole = "cam2"\njoint = "C"\n', 12, "joint 'C' is made by stage 2 (cam pair) of the 'hs' links"),
        ('[[stages]]\nkind = "force member"\nrole = "HS"\njoint = "S"\n', 12, "role 'hs' is given by stage 2 (cam pair) as a higher pair (link→C)"),
        ('[[particularize]]\nbetween = ["ground", "HS"]\njoint = "P"\n', 13, "role 'HS' marks the links that stage 2 (cam pair) turns into a joint 'C'"),
        ('[[stages]]\nrole = "arm"\n[[particularize]]\nbetween = ["ground", "arm"]\njoint = "C"\n', 16,
         "joint 'C' is what stage 2 (cam pair) makes of the 'hs' links"),
    ],
)
def test_conversion_roles_and_joints_are_one_to_one(tmp_path, extra, line, problem):
    # each joint of a mechanism must come from one marking: a conversion role has one kind, joint and selection
    path = tmp_path / "bad.toml"
    path.write_text(BASE + extra)
    with pytest.raises(DomesError) as info:
        load_scene(path)
    assert str(info.value).startswith(f"{path}:{line}: "), str(info.value)
    assert problem in str(info.value)


def test_a_stage_that_admits_nothing_is_reported(tmp_path):
    path = tmp_path / "none.toml"
    path.write_text(BASE + '[[stages]]\nname = "spring"\nkind = "force member"\nrole = "spring"\njoint = "S"\n'
                    'select = "adjacent pair"\nrules = ["the “spring” must be adjacent to the HS"]\n')
    with pytest.raises(DomesError, match=rf"{path}:12: stage 3 \(spring\): its rules cannot hold: no dyad of binary "
                                         r"links of any of the \d+ chains so far can become a joint 'S' \('spring'\)"):
        regenerate(load_scene(path))
