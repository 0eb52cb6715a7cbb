"""A second, independent reading of criterion trees: a plain interpreter over networkx.

It shares nothing with domes.language.evaluate (no bit masks, no compiled
closures, no Topology): loops come from networkx.simple_cycles, the rank of a
set of loops from Gaussian elimination of a 0/1 numpy matrix mod 2, distances
from networkx.shortest_path_length. The fuzz tests compare the two on random
trees; the meaning of each construct is the one of docs/knowledge.md.
"""

from __future__ import annotations

import networkx as nx
import numpy as np

from domes.language.tree import (
    Adjacent,
    And,
    Count,
    Distance,
    ForAll,
    HasMember,
    InLoop,
    JointCount,
    Not,
    Or,
    Represents,
    SharesJoint,
    TypeIs,
)

FAR = 1 << 30  # the distance to a role no link carries, or across parts


def rank_mod2(rows: list[list[int]]) -> int:
    """Rank of a 0/1 matrix over GF(2) by Gaussian elimination."""
    if not rows:
        return 0
    m = np.array(rows, dtype=np.uint8) % 2
    rank = 0
    for col in range(m.shape[1]):
        pivot = next((r for r in range(rank, m.shape[0]) if m[r, col]), None)
        if pivot is None:
            continue
        m[[rank, pivot]] = m[[pivot, rank]]
        for r in range(m.shape[0]):
            if r != rank and m[r, col]:
                m[r] ^= m[rank]
        rank += 1
    return rank


class Reference:
    """A labelled chain read plainly: links, typed joints, roles, named loops, every loop."""

    def __init__(self, chain):
        self.chain = chain
        self.graph = chain.to_networkx()
        self.type_of = {frozenset(e): t for e, t in zip(chain.edges, chain.joint_types)}
        self.loops = []
        for cycle in nx.simple_cycles(nx.Graph(list(chain.edges))):
            joints = [frozenset(p) for p in zip(cycle, cycle[1:] + cycle[:1])]
            self.loops.append((set(cycle), joints))
        self.independent = len(chain.edges) - chain.n + nx.number_connected_components(self.graph)
        self.named = {}
        for name, links in chain.named_loops:
            ring = list(links)
            self.named[name] = (set(ring), [frozenset(p) for p in zip(ring, ring[1:] + ring[:1])])

    # -- conditions on a link -------------------------------------------------------

    def joints_at(self, v):
        return [frozenset((v, w)) for w in self.graph[v]]

    def vertex(self, c, v) -> bool:
        roles = self.chain.roles
        if isinstance(c, TypeIs):
            return relate(c.relation, {self.type_of[j] for j in self.joints_at(v)}, set(c.joints))
        if isinstance(c, JointCount):
            joints = self.joints_at(v)
            count = len(joints) if c.joint is None else sum(self.type_of[j] == c.joint for j in joints)
            return c.comparison(count)
        if isinstance(c, Adjacent):
            return any(c.role in roles[w] and (c.joint is None or self.type_of[frozenset((v, w))] == c.joint)
                       for w in self.graph[v])
        if isinstance(c, Distance):
            lengths = nx.single_source_shortest_path_length(self.graph, v)
            targets = [lengths.get(u, FAR) for u in range(self.chain.n) if c.role in roles[u]]
            return c.comparison(min(targets, default=FAR))
        if isinstance(c, Represents):
            return c.role in roles[v]
        if isinstance(c, InLoop):
            return c.loop in self.named and v in self.named[c.loop][0]
        return self.combine(c, lambda x: self.vertex(x, v))

    # -- conditions on a loop -------------------------------------------------------

    def loop(self, c, loop) -> bool:
        links, joints = loop
        if isinstance(c, TypeIs):
            return relate(c.relation, {self.type_of[j] for j in joints}, set(c.joints))
        if isinstance(c, JointCount):
            return c.comparison(len(joints) if c.joint is None else sum(self.type_of[j] == c.joint for j in joints))
        if isinstance(c, HasMember):
            return any(c.role in self.chain.roles[v] for v in links)
        if isinstance(c, SharesJoint):
            return c.loop in self.named and bool(set(joints) & set(self.named[c.loop][1]))
        return self.combine(c, lambda x: self.loop(x, loop))

    @staticmethod
    def combine(c, test) -> bool:
        if isinstance(c, Not):
            return not test(c.item)
        if isinstance(c, And):
            return all(test(x) for x in c.items)
        if isinstance(c, Or):
            return any(test(x) for x in c.items)
        raise TypeError(f"not a condition: {c!r}")

    def rank(self, loops) -> int:
        index = {frozenset(e): i for i, e in enumerate(self.chain.edges)}
        rows = []
        for _, joints in loops:
            row = [0] * len(index)
            for j in joints:
                row[index[j]] = 1
            rows.append(row)
        return rank_mod2(rows)

    # -- statements -------------------------------------------------------------------

    def holds(self, tree) -> bool:
        d = tree.domain
        if isinstance(tree, Count):
            if d.kind == "vertex":
                value = sum(tree.condition is None or self.vertex(tree.condition, v) for v in range(self.chain.n))
            elif d.kind == "loop":
                value = sum(tree.condition is None or self.loop(tree.condition, lp) for lp in self.loops)
            elif tree.condition is None:
                value = self.independent
            else:  # the fewest loops with the condition that any cycle basis can have
                value = self.independent - self.rank([lp for lp in self.loops if not self.loop(tree.condition, lp)])
            return tree.comparison(value)
        assert isinstance(tree, ForAll)
        if d.kind == "vertex":
            scope = [v for v in range(self.chain.n) if d.name is None or d.name in self.chain.roles[v]]
            return all(self.vertex(tree.condition, v) for v in scope)
        if d.name is not None:
            return d.name not in self.named or self.loop(tree.condition, self.named[d.name])
        good = [lp for lp in self.loops if self.loop(tree.condition, lp)]
        if d.kind == "loop":
            return len(good) == len(self.loops)
        return self.rank(good) == self.independent


def relate(relation: str, have: set, given: set) -> bool:
    return {"=": have == given, "!=": have != given, "contains": have >= given, "within": have <= given}[relation]
