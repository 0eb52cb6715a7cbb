"""Evaluation of criteria on labelled graphs: compiled closures over precomputed graph features.

:func:`graph_features` computes, once per labelled graph, bit masks of its
vertices (by TYPE, degree, incident joint counts, role, neighbours) and of
its loops; the topology part (simple cycles, distances, cycle-space ranks)
is shared by every labelling of the same chain. :func:`compile_criterion`
turns a criterion tree into a closure ``features -> bool`` (True: the graph
meets the requirement and is kept). Vertex conditions compile to functions
returning the bit mask of the vertices that satisfy them, so a statement
over all vertices is a few integer operations.

**Loops.** "Loop" ranges over every simple cycle (circuit) of the graph.
"Independent loop" refers to a cycle basis, and since no particular basis is
invariant under isomorphism, statements quantify over all of them:

* *P holds for any independent loop* means some cycle basis consists of
  loops satisfying P, i.e. the circuits satisfying P span the cycle space
  (their GF(2) rank equals the number of independent loops L);
* *the number of independent loops with P* is the fewest any cycle basis
  can have, ``L − rank(circuits not satisfying P)``.

Both are isomorphism invariants, agree with each other (P holds for any
independent loop exactly when the number of independent loops without P is
0), and never exceed L. See docs/knowledge.md for the reasons.

**Active pairs.** The active-pair criterion (:class:`~domes.language.tree.ActivePairs`)
is computed only when a criterion asks for it, once per role, by
:func:`domes.model.active.active_pairs`, and kept in the features.

>>> from domes.model import LabelledChain
>>> from domes.language.parse import parse_criterion
>>> slider_crank = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], {(3, 0): "P"})
>>> holds(parse_criterion("every vertex must have type (R) or have type (P R)"), slider_crank)
True
"""

from __future__ import annotations

from bisect import bisect_left
from typing import Callable

from domes.errors import InputError
from domes.language.tree import (
    ActivePairs,
    Adjacent,
    And,
    Count,
    Criterion,
    Distance,
    HasMember,
    InLoop,
    JointCount,
    Not,
    Or,
    Represents,
    SharesJoint,
    TypeIs,
)
from domes.model.active import active_pairs
from domes.model.labelled import JOINT_TYPES, LabelledChain
from domes.model.topology import UNREACHABLE

#: Bit of each joint type in a TYPE mask.
JOINT_BIT = {t: 1 << i for i, t in enumerate(JOINT_TYPES)}


def _set_mask(joints) -> int:
    mask = 0
    for j in joints:
        mask |= JOINT_BIT[j]
    return mask


class Features:
    """Precomputed bit masks of one labelled graph (see the module docstring)."""

    __slots__ = (
        "topology", "n", "all", "type_mask", "degree_mask", "count_mask", "neighbours",
        "typed_neighbours", "roles", "edge_types", "named_loops", "all_cycles", "chain", "active",
    )

    def __init__(self, chain: LabelledChain):
        topo = chain.topology
        n = chain.n
        self.topology = topo
        self.n = n
        self.all = (1 << n) - 1
        type_of = [0] * n
        neighbours = [0] * n
        typed: dict[str, list[int]] = {}
        counts: dict[str, list[int]] = {}
        edge_types: dict[str, int] = {}
        for i, ((u, v), t) in enumerate(zip(chain.edges, chain.joint_types)):
            bit = JOINT_BIT[t]
            type_of[u] |= bit
            type_of[v] |= bit
            neighbours[u] |= 1 << v
            neighbours[v] |= 1 << u
            row = typed.get(t)
            if row is None:
                row = typed[t] = [0] * n
                counts[t] = [0] * n
            row[u] |= 1 << v
            row[v] |= 1 << u
            counts[t][u] += 1
            counts[t][v] += 1
            edge_types[t] = edge_types.get(t, 0) | 1 << i
        self.neighbours = neighbours
        self.typed_neighbours = typed
        self.edge_types = edge_types
        self.type_mask = _group(type_of)
        self.degree_mask = _group([bin(m).count("1") for m in neighbours])
        self.count_mask = {t: _group(c) for t, c in counts.items()}
        roles: dict[str, int] = {}
        for v, names in enumerate(chain.roles):
            for r in names:
                roles[r] = roles.get(r, 0) | 1 << v
        self.roles = roles
        loops = {}
        for name, links in chain.named_loops:
            emask = vmask = 0
            for a, b in zip(links, links[1:] + links[:1]):
                emask |= 1 << _edge_index(chain.edges, a, b)
                vmask |= 1 << a
            loops[name] = (emask, vmask, len(links))
        self.named_loops = loops
        self.all_cycles = (1 << len(topo.cycle_edges)) - 1
        self.chain = chain
        self.active: dict = {}

    def active_pairs(self, role: str):
        """The :class:`~domes.model.active.ActivePairs` of the joints between the ground and the links
        representing ``role`` (computed on first use), or, as text, why there are no such joints."""
        found = self.active.get(role)
        if found is None:
            try:
                found = active_pairs(self.chain, role=role)
            except InputError as exc:
                found = str(exc)
            self.active[role] = found
        return found


def _edge_index(edges, a: int, b: int) -> int:
    """Index of the joint a-b in the sorted joints of a labelled chain."""
    return bisect_left(edges, (min(a, b), max(a, b)))


def _group(values: list[int]) -> dict[int, int]:
    out: dict[int, int] = {}
    for v, x in enumerate(values):
        out[x] = out.get(x, 0) | 1 << v
    return out


def graph_features(chain: LabelledChain) -> Features:
    """The features of a labelled graph, to evaluate any number of compiled criteria on."""
    return Features(chain)


# -- compilation ---------------------------------------------------------------------

VertexTest = Callable[[Features], int]
LoopTest = Callable[[Features, int, int, int], bool]


def _masks_where(groups: dict[int, int], keep: Callable[[int], bool]) -> int:
    out = 0
    for value, mask in groups.items():
        if keep(value):
            out |= mask
    return out


def compile_vertex(c) -> VertexTest:
    """A vertex condition as a function of the features returning the mask of vertices satisfying it."""
    if isinstance(c, TypeIs):
        s = _set_mask(c.joints)
        if c.relation == "=":
            return lambda f: f.type_mask.get(s, 0)
        if c.relation == "!=":
            return lambda f: f.all ^ f.type_mask.get(s, 0)
        if c.relation == "contains":
            return lambda f: _masks_where(f.type_mask, lambda t: t & s == s)
        return lambda f: _masks_where(f.type_mask, lambda t: t & ~s == 0)
    if isinstance(c, JointCount):
        cmp = c.comparison
        if c.joint is None:
            return lambda f: _masks_where(f.degree_mask, cmp)
        j = c.joint
        zero = cmp(0)

        def count(f: Features) -> int:
            groups = f.count_mask.get(j)
            if groups is None:
                return f.all if zero else 0
            return _masks_where(groups, cmp)

        return count
    if isinstance(c, Represents):
        role = c.role
        return lambda f: f.roles.get(role, 0)
    if isinstance(c, Adjacent):
        role, j = c.role, c.joint

        def adjacent(f: Features) -> int:
            target = f.roles.get(role, 0)
            rows = f.neighbours if j is None else f.typed_neighbours.get(j)
            if not target or rows is None:
                return 0
            out = 0
            for v, row in enumerate(rows):
                if row & target:
                    out |= 1 << v
            return out

        return adjacent
    if isinstance(c, Distance):
        role, cmp = c.role, c.comparison

        def distance(f: Features) -> int:
            target = f.roles.get(role, 0)
            members = [u for u in range(f.n) if target >> u & 1]
            out = 0
            for v, row in enumerate(f.topology.distance):
                d = min((row[u] for u in members), default=UNREACHABLE)
                if cmp(d):
                    out |= 1 << v
            return out

        return distance
    if isinstance(c, InLoop):
        name = c.loop
        return lambda f: f.named_loops[name][1] if name in f.named_loops else 0
    if isinstance(c, Not):
        inner = compile_vertex(c.item)
        return lambda f: f.all ^ inner(f)
    if isinstance(c, And):
        parts = [compile_vertex(x) for x in c.items]

        def both(f: Features) -> int:
            out = f.all
            for p in parts:
                out &= p(f)
            return out

        return both
    if isinstance(c, Or):
        parts = [compile_vertex(x) for x in c.items]

        def either(f: Features) -> int:
            out = 0
            for p in parts:
                out |= p(f)
            return out

        return either
    raise InputError(f"not a vertex condition: {c!r}")


def compile_loop(c) -> LoopTest:
    """A loop condition as a predicate ``(features, edge mask, vertex mask, length) -> bool``."""
    if isinstance(c, TypeIs):
        s, relation = _set_mask(c.joints), c.relation

        def loop_type(f: Features, em: int, vm: int, length: int) -> bool:
            t = 0
            for j, mask in f.edge_types.items():
                if em & mask:
                    t |= JOINT_BIT[j]
            if relation == "=":
                return t == s
            if relation == "!=":
                return t != s
            if relation == "contains":
                return t & s == s
            return t & ~s == 0

        return loop_type
    if isinstance(c, JointCount):
        cmp, j = c.comparison, c.joint
        if j is None:
            return lambda f, em, vm, length: cmp(length)
        return lambda f, em, vm, length: cmp((em & f.edge_types.get(j, 0)).bit_count())
    if isinstance(c, HasMember):
        role = c.role
        return lambda f, em, vm, length: bool(vm & f.roles.get(role, 0))
    if isinstance(c, SharesJoint):
        name = c.loop
        return lambda f, em, vm, length: name in f.named_loops and bool(em & f.named_loops[name][0])
    if isinstance(c, Not):
        inner = compile_loop(c.item)
        return lambda f, em, vm, length: not inner(f, em, vm, length)
    if isinstance(c, And):
        parts = [compile_loop(x) for x in c.items]
        return lambda f, em, vm, length: all(p(f, em, vm, length) for p in parts)
    if isinstance(c, Or):
        parts = [compile_loop(x) for x in c.items]
        return lambda f, em, vm, length: any(p(f, em, vm, length) for p in parts)
    raise InputError(f"not a loop condition: {c!r}")


def _cycles_where(f: Features, test: LoopTest) -> int:
    topo = f.topology
    out = 0
    for i, (em, vm, length) in enumerate(zip(topo.cycle_edges, topo.cycle_vertices, topo.cycle_lengths)):
        if test(f, em, vm, length):
            out |= 1 << i
    return out


def compile_criterion(tree: Criterion) -> Callable[[Features], bool]:
    """A closure ``features -> bool``: True when the graph meets the criterion (is kept).

    >>> from domes.language.parse import parse_criterion
    >>> from domes.model import LabelledChain
    >>> test = compile_criterion(parse_criterion("the number of vertices whose type is (P R) must be at most 1"))
    >>> test(graph_features(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(0, 1): "P"})))
    False
    """
    if isinstance(tree, ActivePairs):
        role, kind = tree.role, tree.dof_type

        def active(f: Features) -> bool:
            found = f.active_pairs(role)
            return not isinstance(found, str) and found.feasible and (kind is None or found.dof_type == kind)

        return active
    domain = tree.domain
    if isinstance(tree, Count):
        cmp = tree.comparison
        if domain.kind == "vertex":
            if tree.condition is None:
                return lambda f: cmp(f.n)
            test = compile_vertex(tree.condition)
            return lambda f: cmp(test(f).bit_count())
        loop_test = compile_loop(tree.condition) if tree.condition is not None else None
        if domain.kind == "loop":
            if loop_test is None:
                return lambda f: cmp(len(f.topology.cycle_edges))
            return lambda f: cmp(_cycles_where(f, loop_test).bit_count())
        if loop_test is None:
            return lambda f: cmp(f.topology.loops)

        def independent_count(f: Features) -> bool:
            without = f.all_cycles & ~_cycles_where(f, loop_test)
            return cmp(f.topology.loops - f.topology.rank(without))

        return independent_count
    if domain.kind == "vertex":
        test = compile_vertex(tree.condition)
        if domain.name is None:
            return lambda f: test(f) == f.all
        role = domain.name
        return lambda f: f.roles.get(role, 0) & ~test(f) == 0
    loop_test = compile_loop(tree.condition)
    if domain.name is not None:
        name = domain.name

        def named(f: Features) -> bool:
            loop = f.named_loops.get(name)
            return loop is None or loop_test(f, *loop)

        return named
    if domain.kind == "loop":
        return lambda f: _cycles_where(f, loop_test) == f.all_cycles
    return lambda f: f.topology.rank(_cycles_where(f, loop_test)) == f.topology.loops


def holds(tree: Criterion, chain: LabelledChain) -> bool:
    """Whether a labelled graph meets a criterion (one-off; compile once to test many graphs)."""
    return compile_criterion(tree)(graph_features(chain))
