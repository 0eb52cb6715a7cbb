"""The topology of a chain: its loops, its cycle space and the distances between its links.

A *loop* is a simple cycle (circuit) of the chain's graph; the *independent
loops* are a basis of its cycle space over GF(2), of size ``L = j − n + c``
for ``c`` connected parts. Loops are bit masks of joints (bit ``i`` is the
chain's ``i``-th joint in sorted order) and of links.

A :class:`Topology` is computed lazily and cached on the object that owns it
(:attr:`Chain.topology <domes.model.chain.Chain.topology>`,
:attr:`LabelledChain.topology <domes.model.labelled.LabelledChain.topology>`);
labelled chains derived from one another share it. Nothing is cached in
module globals.

>>> t = Topology(4, ((0, 1), (0, 2), (0, 3), (1, 2), (2, 3)))   # a square with a diagonal
>>> t.loops, t.cycle_lengths
(2, (3, 3, 4))
>>> t.rank(0b011), t.distance[1][3]
(2, 2)
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import Iterable

Edge = tuple[int, int]

#: Distance to an unreachable link.
UNREACHABLE = 1 << 30


def gf2_rank(vectors: Iterable[int]) -> int:
    """Rank over GF(2) of bit-mask vectors.

    >>> gf2_rank([0b011, 0b110, 0b101])
    2
    """
    pivots: dict[int, int] = {}
    for v in vectors:
        while v:
            top = v.bit_length() - 1
            if top not in pivots:
                pivots[top] = v
                break
            v ^= pivots[top]
    return len(pivots)


def simple_cycles(n: int, edges: Iterable[Edge]) -> list[tuple[int, int, int]]:
    """Every simple cycle of a simple graph as ``(joint mask, link mask, length)``, shortest first.

    >>> len(simple_cycles(4, [(0, 1), (1, 2), (2, 3), (0, 3), (0, 2)]))
    3
    """
    index = {}
    adjacency: list[list[int]] = [[] for _ in range(n)]
    for i, (u, v) in enumerate(edges):
        index[u, v] = index[v, u] = i
        adjacency[u].append(v)
        adjacency[v].append(u)
    found: dict[int, tuple[int, int, int]] = {}
    for start in range(n):
        stack = [(start, iter(adjacency[start]))]
        path_edges, path_vertices = 0, 1 << start
        edge_stack: list[int] = []
        while stack:
            vertex, neighbours = stack[-1]
            advanced = False
            for w in neighbours:
                if w == start and len(stack) >= 3:
                    mask = path_edges | 1 << index[vertex, w]
                    found.setdefault(mask, (mask, path_vertices, len(stack)))
                elif w > start and not path_vertices >> w & 1:
                    bit = 1 << index[vertex, w]
                    edge_stack.append(bit)
                    path_edges |= bit
                    path_vertices |= 1 << w
                    stack.append((w, iter(adjacency[w])))
                    advanced = True
                    break
            if not advanced:
                stack.pop()
                path_vertices &= ~(1 << vertex)
                if edge_stack:
                    path_edges &= ~edge_stack.pop()
    return sorted(found.values(), key=lambda c: (c[2], c[0]))


@dataclass(frozen=True, eq=False)
class Topology:
    """Loops, cycle space and distances of the graph with links ``0..n−1`` and these (sorted) joints."""

    n: int
    edges: tuple[Edge, ...]
    _ranks: dict = field(default_factory=dict, repr=False)

    @cached_property
    def _cycles(self) -> list[tuple[int, int, int]]:
        return simple_cycles(self.n, self.edges)

    @cached_property
    def cycle_edges(self) -> tuple[int, ...]:
        """The joint mask of every simple cycle (loop)."""
        return tuple(c[0] for c in self._cycles)

    @cached_property
    def cycle_vertices(self) -> tuple[int, ...]:
        """The link mask of every loop."""
        return tuple(c[1] for c in self._cycles)

    @cached_property
    def cycle_lengths(self) -> tuple[int, ...]:
        """The number of joints of every loop."""
        return tuple(c[2] for c in self._cycles)

    @cached_property
    def adjacency(self) -> tuple[tuple[int, ...], ...]:
        """The links jointed to each link."""
        out: list[list[int]] = [[] for _ in range(self.n)]
        for u, v in self.edges:
            out[u].append(v)
            out[v].append(u)
        return tuple(tuple(a) for a in out)

    @cached_property
    def distance(self) -> tuple[tuple[int, ...], ...]:
        """Joints on a shortest path between two links (:data:`UNREACHABLE` across parts)."""
        rows = []
        for s in range(self.n):
            row = [UNREACHABLE] * self.n
            row[s] = 0
            frontier = [s]
            while frontier:
                nxt = []
                for u in frontier:
                    for w in self.adjacency[u]:
                        if row[w] == UNREACHABLE:
                            row[w] = row[u] + 1
                            nxt.append(w)
                frontier = nxt
            rows.append(tuple(row))
        return tuple(rows)

    @cached_property
    def loops(self) -> int:
        """Independent loops: the dimension of the cycle space, ``j − n + c``."""
        d = self.distance
        parts = sum(1 for s in range(self.n) if all(d[s][t] == UNREACHABLE for t in range(s)))
        return len(self.edges) - self.n + parts

    def rank(self, subset: int) -> int:
        """GF(2) rank of the loops whose indices are the set bits of ``subset`` (cached)."""
        r = self._ranks.get(subset)
        if r is None:
            r = gf2_rank(self.cycle_edges[i] for i in range(len(self.cycle_edges)) if subset >> i & 1)
            self._ranks[subset] = r
        return r
