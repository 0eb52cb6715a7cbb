"""Chains by canonical augmentation (McKay, "Isomorph-free exhaustive generation", J. Algorithms 26, 1998).

Every chain without a cut link of ``L ≥ 2`` loops is a smaller one (its
*parent*) plus an ear: a branch of ``k`` binary links between two links of
three or more joints (see :mod:`domes.typesynth.atlas`). A branch is
*removable* when what remains is 2-connected: exactly the ears the merge
generator adds. Of a chain's removable branches one orbit (under the
chain's automorphisms) is *canonical*: the largest by a cheap invariant
(branch length, degrees at its ends and their neighbours'), ties broken by
nauty's canonical labelling. A child is kept only if the ear just added is
canonical, and each parent adds one ear per orbit of its own automorphism
group on pairs of links. Then every chain is made exactly once, from one
parent, and no set of certificates is needed: every parent, and every slice
of parents, is independent.

:func:`descend` walks depth first from given chains down to the target size
(``L`` loops, DOF ``F``): the intermediate chains it needs are those of
``L′ < L`` loops with ``1 ≤ F′ ≤ F + 2(L − L′)``. Its result is the target's
chains as fixed-width *records* (sort key, then graph6), sorted; records of
slices are merged by :func:`merge_records` into the atlas's order (link
assortment, most binary links first, then nauty's certificate).

>>> records, stats = descend([cycle(4)], loops=2, dof=1)      # the Watt and Stephenson chains
>>> [graph6_of(r) for r in records], stats.kept
(['E_lo', 'E`dg'], 2)
"""

from __future__ import annotations

import heapq
import pickle
import time
from dataclasses import dataclass, field

import numpy as np
import pynauty

from domes.model.canon import nauty, pair_orbits
from domes.model.pebble import encode_graph6
from domes.typesynth import earkernel

Edge = tuple[int, int]
Graph = tuple[int, tuple[Edge, ...]]


def cycle(n: int) -> Graph:
    """The single loop of ``n`` links, the root of every chain of DOF ``n − 3``."""
    return n, tuple((i, (i + 1) % n) if i + 1 < n else (0, n - 1) for i in range(n))


def in_region(loops: int, dof: int, target_loops: int, target_dof: int) -> bool:
    """True if chains of ``loops`` loops and DOF ``dof`` lie on the way to the target (or are it)."""
    if loops == target_loops:
        return dof == target_dof
    return loops < target_loops and 1 <= dof <= target_dof + 2 * (target_loops - loops)


def roots(target_loops: int, target_dof: int) -> list[Graph]:
    """The single loops every chain of the target descends from."""
    if target_loops == 1:
        return [cycle(target_dof + 3)]
    return [cycle(f + 3) for f in range(1, target_dof + 2 * (target_loops - 1) + 1)]


def _nauty_graph(n: int, edges: tuple[Edge, ...]) -> pynauty.Graph:
    """The pynauty graph of a chain, :func:`~domes.model.canon.nauty_graph` made without pynauty's checks of
    every vertex (a third of a walk's nauty time went to them)."""
    adjacency: dict[int, list[int]] = {}
    for u, v in edges:
        if u in adjacency:
            adjacency[u].append(v)
        else:
            adjacency[u] = [v]
    graph = object.__new__(pynauty.Graph)
    graph.number_of_vertices = n
    graph.directed = False
    graph._adjacency_dict = adjacency
    graph._vertex_coloring = []
    return graph


# -- the canonical-ear test -----------------------------------------------------------------------------------------

Branch = tuple[int, int, tuple[int, ...]]          # (a, b, inner links from a to b), a < b


def _bits(mask: int):
    while mask:
        bit = mask & -mask
        mask ^= bit
        yield bit.bit_length() - 1


def _branches(n: int, adjm: list[int], deg: list[int]) -> list[Branch]:
    """The branches of a 2-connected chain that is not a single loop, each once."""
    out = []
    for a in range(n):
        if deg[a] < 3:
            continue
        for y in _bits(adjm[a]):
            prev, x, inner = a, y, []
            while deg[x] == 2:
                inner.append(x)
                p, q = _bits(adjm[x])
                prev, x = x, (q if p == prev else p)
            if a < x:
                out.append((a, x, tuple(inner)))
    return out


def _reach(adjm: list[int], alive: int, a: int) -> int:
    """The links reachable from ``a`` through links of the bitmask ``alive``."""
    seen = frontier = 1 << a
    while frontier:
        new = 0
        while frontier:
            bit = frontier & -frontier
            frontier ^= bit
            new |= adjm[bit.bit_length() - 1]
        frontier = new & alive & ~seen
        seen |= frontier
    return seen


def _removable(adjm: list[int], full: int, branch: Branch) -> bool:
    """True if the chain less the branch is 2-connected.

    The chain is 2-connected, so the rest is connected, and a cut link of it must separate the branch's ends
    ``a`` and ``b``: it lies on every path between them, on a shortest one in particular. Each inner link of a
    shortest path is tried."""
    a, b, inner = branch
    alive = full
    for x in inner:
        alive ^= 1 << x
    if inner and adjm[a] >> b & 1:
        return True                                   # a and b jointed in the rest: nothing separates them
    saved_a, saved_b = adjm[a], adjm[b]
    adjm[a] = saved_a & alive & ~(1 << b)
    adjm[b] = saved_b & alive & ~(1 << a)
    try:
        layers = [1 << a]
        seen = 1 << a
        while not (seen >> b & 1):                    # breadth first to b, layer by layer
            new = 0
            frontier = layers[-1]
            while frontier:
                bit = frontier & -frontier
                frontier ^= bit
                new |= adjm[bit.bit_length() - 1]
            new &= alive & ~seen
            if not new:
                return False
            layers.append(new)
            seen |= new
        x = b                                         # back along a shortest path, trying each inner link
        for layer in reversed(layers[1:-1]):
            w = adjm[x] & layer
            w = (w & -w).bit_length() - 1
            if not (_reach(adjm, alive & ~(1 << w), a) >> b & 1):
                return False
            x = w
        return True
    finally:
        adjm[a], adjm[b] = saved_a, saved_b


def removable_branches(n: int, adjm: list[int], branches: list[Branch]) -> list[bool]:
    """:func:`_removable` for each branch of a 2-connected chain of ``n`` links (neighbours as bitmasks), by the
    compiled test when there is one (:func:`domes.typesynth.earkernel.load`; the same answers)."""
    kernels = earkernel.load() if n <= 62 else None
    if kernels is None:
        full = (1 << n) - 1
        return [_removable(adjm, full, br) for br in branches]
    given = adjm.copy()
    for a, b, links in branches:
        mask = 0
        for x in links:
            mask |= 1 << x
        given += (a, b, mask)
    return kernels.removable(np.array(given, dtype=np.int64), n).tolist()


def _fine(branch: Branch, deg: list[int], adjm: list[int]) -> tuple:
    """A finer invariant of a branch, for ties: its length, and at each end its degree and its neighbours'."""
    a, b, inner = branch
    ea = (deg[a], sorted(deg[y] for y in _bits(adjm[a])))
    eb = (deg[b], sorted(deg[y] for y in _bits(adjm[b])))
    return (len(inner), *sorted((ea, eb), reverse=True))


@dataclass
class Stats:
    """What a walk did: chains expanded per level, target chains kept, candidates tried, nauty calls, CPU time."""

    expanded: dict = field(default_factory=dict)     # (loops, dof) -> parents expanded
    kept: int = 0                                    # chains of the target kept
    candidates: int = 0                              # children tried (ears past the rigidity test)
    nauty_calls: int = 0
    seconds: float = 0.0

    def add(self, other: Stats) -> None:
        for key, value in other.expanded.items():
            self.expanded[key] = self.expanded.get(key, 0) + value
        self.kept += other.kept
        self.candidates += other.candidates
        self.nauty_calls += other.nauty_calls
        self.seconds += other.seconds


def canonical_ear(n: int, deg: list[int], adjm: list[int], branches: list[Branch], mine: Branch,
                  edges=None, stats: Stats | None = None, sure: list[bool] | None = None):
    """Whether the branch ``mine`` of a chain (links' degrees ``deg``, neighbours as bitmasks ``adjm``, every
    branch in ``branches``) is, up to the chain's automorphisms, its canonical removable branch: the largest by
    length and end degrees, then by :func:`_fine`, then the one with the least canonical labels (nauty). Returns
    None if not, else nauty's canonical labelling (``order[i]`` is the link that becomes link ``i``) when it
    was computed, or ``()``. ``edges`` (the chain's joints) are needed only for nauty; ``sure[i]``, if given, is
    True for branches known to be removable (not tested)."""
    da, db = deg[mine[0]], deg[mine[1]]
    here = len(mine[2]) << 16 | (da << 8 | db if da >= db else db << 8 | da)      # (length, end degrees), packed
    larger, ties = [], []
    for i, branch in enumerate(branches):
        x, y = deg[branch[0]], deg[branch[1]]
        inv = len(branch[2]) << 16 | (x << 8 | y if x >= y else y << 8 | x)
        if inv > here:
            if sure is not None and sure[i]:
                return None
            larger.append(branch)
        elif inv == here and branch != mine:
            ties.append(branch)
    if larger or ties:
        free = removable_branches(n, adjm, larger + ties)
        if any(free[:len(larger)]):
            return None
        ties = [t for t, f in zip(ties, free[len(larger):]) if f]
    if not ties:
        return ()
    fine = _fine(mine, deg, adjm)
    finer = [(_fine(t, deg, adjm), t) for t in ties]
    if any(f > fine for f, _ in finer):
        return None
    ties = [t for f, t in finer if f == fine]
    if not ties:
        return ()
    # nauty: the canonical branch is the one whose links have the least canonical labels; the ear is kept if
    # an automorphism takes it there.
    graph = _nauty_graph(n, edges if edges is not None else [(a, b) for a in range(n) for b in _bits(adjm[a]) if a < b])
    order = nauty(pynauty.canon_label, graph)
    generators = nauty(pynauty.autgrp, graph)[0]
    if stats is not None:
        stats.nauty_calls += 2
    label = [0] * n
    for i, x in enumerate(order):
        label[x] = i
    best = min([mine, *ties], key=lambda br: sorted(label[x] for x in (br[0], br[1], *br[2])))
    if best is mine or _same_orbit(mine, best, generators, n):
        return order
    return None


def is_canonical_ear(n: int, edges: tuple[Edge, ...], u: int, v: int, k: int):
    """:func:`canonical_ear` for a chain whose last ``k`` links form the ear between ``u`` and ``v``.

    >>> child = (5, ((0, 1), (1, 2), (2, 3), (0, 3), (0, 4), (2, 4)))      # the four-bar with an ear on 0 and 2
    >>> is_canonical_ear(*child, 0, 2, 1) is not None
    True
    """
    adjm = [0] * n
    for a, b in edges:
        adjm[a] |= 1 << b
        adjm[b] |= 1 << a
    deg = [m.bit_count() for m in adjm]
    inner = tuple(range(n - k, n))
    mine = (u, v, inner) if u < v else (v, u, inner[::-1])
    return canonical_ear(n, deg, adjm, _branches(n, adjm, deg), mine, edges)


def _same_orbit(one: Branch, other: Branch, generators, n: int) -> bool:
    """True if an automorphism (a product of ``generators``) takes branch ``one`` to branch ``other``."""
    if one[2]:                                       # a branch is the one through any of its inner links
        parent = list(range(n))

        def find(x):
            while parent[x] != x:
                parent[x] = parent[parent[x]]
                x = parent[x]
            return x

        for perm in generators:
            for x in range(n):
                a, b = find(x), find(perm[x])
                if a != b:
                    parent[max(a, b)] = min(a, b)
        return find(one[2][0]) in {find(x) for x in other[2]}
    seen = {(one[0], one[1])}                          # a single joint: its orbit among joints
    todo = [(one[0], one[1])]
    while todo:
        a, b = todo.pop()
        for perm in generators:
            image = (perm[a], perm[b]) if perm[a] < perm[b] else (perm[b], perm[a])
            if image not in seen:
                seen.add(image)
                todo.append(image)
    return (other[0], other[1]) in seen


# -- records: the target's chains, sortable as bytes ----------------------------------------------------------------

def record(n: int, edges: tuple[Edge, ...], order) -> bytes:
    """The record of a chain: its sort key (link assortment, most binary links first, then nauty's certificate,
    compacted) and its canonical graph6. Records of one size have one width; sorted as bytes, they are in the
    atlas's order. ``order`` is nauty's canonical labelling (computed here if empty)."""
    if not order:
        order = nauty(pynauty.canon_label, _nauty_graph(n, edges))
    label = [0] * n
    for i, x in enumerate(order):
        label[x] = i
    width, top, shifts = _layout(n)
    row = 8 * width
    cert = g6 = 0                                     # the certificate's rows and the graph6 bits, as integers
    deg = [0] * n
    for a, b in edges:
        a, b = label[a], label[b]
        if a > b:
            a, b = b, a
        cert |= 1 << (row * (a + 1) - 1 - b) | 1 << (row * (b + 1) - 1 - a)
        g6 |= 1 << (top - (b * (b - 1) // 2 + a))     # column by column: (0,1), (0,2), (1,2), (0,3), ...
        deg[a] += 1
        deg[b] += 1
    counts = [0] * (n + 1)
    for d in deg:
        counts[d] += 1
    counts = counts[2:]
    while counts and not counts[-1]:
        counts.pop()
    key = bytes(255 - c for c in counts).ljust(n - 1, b"\0")
    return (bytes([n]) + key + cert.to_bytes(n * width, "little") + bytes([n + 63])
            + bytes([(g6 >> s & 63) + 63 for s in shifts]))


_LAYOUTS: dict[int, tuple[int, int, tuple[int, ...]]] = {}


def _layout(n: int) -> tuple[int, int, tuple[int, ...]]:
    """For chains of ``n`` links: the bytes of a certificate row, the bit of graph6's first pair (the upper
    triangle's bits, padded with zeros to a multiple of six), and the shifts that cut them into graph6's
    characters, first to last."""
    if n not in _LAYOUTS:
        total = n * (n - 1) // 2
        chars = -(-total // 6)
        _LAYOUTS[n] = (_row_bytes(n), 6 * chars - 1, tuple(6 * (chars - 1 - i) for i in range(chars)))
    return _LAYOUTS[n]


def _row_bytes(n: int) -> int:
    """Bytes of a certificate row (a 64-bit little-endian word, links from the top bit) that can be non-zero."""
    return -(-n // 8)


def record_width(n: int) -> int:
    """The width of a record of ``n`` links: their count, the key, the graph6 string."""
    return 1 + _key_width(n) + len(encode_graph6(n, ()))


def _key_width(n: int) -> int:
    return (n - 1) + n * _row_bytes(n)


def graph6_of(rec: bytes) -> str:
    """The graph6 string of a record."""
    return rec[1 + _key_width(rec[0]):].decode("ascii")


def certificate_of(rec: bytes) -> bytes:
    """nauty's certificate of the chain of a record (as :func:`domes.model.canon.certificate` gives it)."""
    n = rec[0]
    width = _row_bytes(n)
    body = rec[n:n + n * width]
    return b"".join(bytes(8 - width) + body[i * width:(i + 1) * width] for i in range(n))


# -- the walk -------------------------------------------------------------------------------------------------------

class _Parent:
    """A chain about to be given ears: its links' neighbours and degrees, its branches, and which branch each
    binary link lies in, so that each child's branches are the parent's with at most two split."""

    def __init__(self, graph: Graph, shortest: int = 0):
        n, edges = self.graph = graph
        self.n, self.edges = n, edges
        adjm = [0] * n
        for a, b in edges:
            adjm[a] |= 1 << b
            adjm[b] |= 1 << a
        self.adjm = adjm
        self.deg = [m.bit_count() for m in adjm]
        self.loop = max(self.deg) == 2
        self.branches = [] if self.loop else _branches(n, adjm, self.deg)
        self.where: dict[int, tuple[int, int]] = {}       # binary link -> (its branch, its place in it)
        for i, (_, _, inner) in enumerate(self.branches):
            for j, x in enumerate(inner):
                self.where[x] = (i, j)
        #: the branches whose removal leaves the parent 2-connected, longest first: in a child they stay
        #: removable unless the ear splits them (an ear added to a 2-connected chain keeps it so). Only
        #: branches as long as the ``shortest`` ear are tested: a shorter one never competes with an ear.
        long = [i for i, br in enumerate(self.branches) if len(br[2]) >= shortest]
        free = [False] * len(self.branches)
        if long:
            for i, f in zip(long, removable_branches(n, adjm, [self.branches[i] for i in long])):
                free[i] = f
        self.free = free
        self.removable = sorted(((len(br[2]), br[0], br[1], i) for i, (br, f) in enumerate(zip(self.branches, free))
                                 if f), reverse=True)

    def needed(self, k: int) -> list[int] | None:
        """The removable branches of the parent longer than ``k`` (indices): an ear of ``k`` links can be canonical
        only if it splits every one of them, so None when there are more than two (an ear splits at most two)."""
        longer = [i for length, _, _, i in self.removable if length > k]
        return longer if len(longer) <= 2 else None

    def beaten(self, u: int, v: int, k: int) -> bool:
        """True if the child with an ear of ``k`` links on ``u``, ``v`` surely has a removable branch of a larger
        invariant than its ear (a removable branch of the parent that the ear does not split): the ear is not
        canonical, and the child need not be built."""
        deg = self.deg
        du, dv = deg[u] + 1, deg[v] + 1
        here = (k, du, dv) if du >= dv else (k, dv, du)
        split = {self.where[x][0] for x in (u, v) if x in self.where}
        for length, a, b, i in self.removable:
            if length < k:
                return False
            if i in split:
                continue
            if length > k:
                return True
            da = deg[a] + (a == u) + (a == v)
            db = deg[b] + (b == u) + (b == v)
            if ((k, da, db) if da >= db else (k, db, da)) > here:
                return True
        return False

    def child(self, u: int, v: int, k: int):
        """The child with an ear of ``k`` new links from ``u`` to ``v``: its joints, degrees, neighbours,
        branches, the ear as a branch, and for each branch whether it is surely removable (the ear, and the
        parent's removable branches the ear does not split)."""
        n = self.n
        new = tuple(range(n, n + k))
        adjm = self.adjm + [0] * k
        if k:
            edges = (*self.edges, (u, n), *((x, x + 1) for x in range(n, n + k - 1)), (n + k - 1, v))
            adjm[u] |= 1 << n
            adjm[v] |= 1 << (n + k - 1)
            for x in new:
                adjm[x] = 1 << (x - 1 if x > n else u) | 1 << (x + 1 if x < n + k - 1 else v)
        else:
            edges = (*self.edges, (u, v))
            adjm[u] |= 1 << v
            adjm[v] |= 1 << u
        deg = self.deg + [2] * k
        deg[u] += 1
        deg[v] += 1
        mine = (u, v, new) if u < v else (v, u, new[::-1])
        if self.loop:
            branches = _branches(n + k, adjm, deg)
            return edges, deg, adjm, branches, mine, [br == mine for br in branches]
        branches = self.branches.copy()
        sure = self.free.copy()
        where = self.where
        wu, wv = where.get(u), where.get(v)
        if wu is not None and wv is not None and wu[0] == wv[0]:
            cuts = [(wu[0], sorted((wu[1], wv[1])))]
        else:
            cuts = [(w[0], [w[1]]) for w in (wu, wv) if w is not None]
        for i, places in cuts:
            a, b, inner = branches[i]
            ends = [a, *(inner[j] for j in places), b]
            bounds = [-1, *places, len(inner)]
            for s in range(len(ends) - 1):
                piece = inner[bounds[s] + 1:bounds[s + 1]]
                p, q = ends[s], ends[s + 1]
                piece = (p, q, piece) if p < q else (q, p, piece[::-1])
                if s:
                    branches.append(piece)
                    sure.append(False)
                else:
                    branches[i] = piece
                    sure[i] = False
        branches.append(mine)
        sure.append(True)                                 # the parent is 2-connected
        return edges, deg, adjm, branches, mine, sure


def ear_is_free(n: int, deg: list[int], branches: list[Branch], mine: Branch) -> bool:
    """True if the ear ``mine`` of a chain (its other branches from a non-degenerate parent) makes no rigid or
    over-constrained sub-chain: every proper set ``T`` of links holding both its ends has ``F(T) ≥ 1``.

    Only sets made of links of three joints or more (``S``, with the ear's ends) and whole branches between
    them can be the least: a branch of ``m`` binary links adds ``m − 2`` to ``F`` (taken when ``m ≤ 1``), and a
    part of a branch only adds. So ``F`` is tabulated over the subsets of ``S`` (at most ``2**(2L − 4)``
    entries for ``L`` loops), not over all ``2**n`` sets of links.

    >>> parent = _Parent((5, ((0, 2), (2, 1), (0, 3), (3, 4), (4, 1))))     # a five-bar loop
    >>> _, deg, _, branches, mine, _ = parent.child(0, 1, 0)                 # a joint 0-1: a rigid triangle 0-1-2
    >>> ear_is_free(5, deg, branches, mine)
    False
    >>> _, deg, _, branches, mine, _ = parent.child(2, 4, 1)                 # a link on 2 and 4: a four-bar loop
    >>> ear_is_free(6, deg, branches, mine)
    True
    """
    u, v = mine[0], mine[1]
    others = [x for x in range(n) if deg[x] >= 3 and x != u and x != v]
    place = {x: 1 << i for i, x in enumerate(others)}
    place[u] = place[v] = 0
    need, change = [], []
    for a, b, inner in branches:
        if len(inner) <= 1:
            need.append(place[a] | place[b])
            change.append(len(inner) - 2)
    # the whole chain is not a sub-chain: leave one out
    whole = 2 - max(len(br[2]) for br in branches) if len(need) == len(branches) else 0
    kernels = earkernel.load() if len(others) <= 24 else None
    if kernels is not None:
        least = kernels.least_freedom(len(others), np.array(need, dtype=np.int64), np.array(change, dtype=np.int64),
                                      whole)
        return bool(least >= 1)
    subsets = np.arange(1 << len(others), dtype=np.int32)
    table = 3 * (np.bitwise_count(subsets).astype(np.int32) + 1)
    for mask, m in zip(need, change):
        table += np.where(subsets & mask == mask, m, 0).astype(np.int32)
    table[-1] += whole
    return bool(table.min() >= 1)


def _pairs(parent: _Parent, ks: list[int], stats: Stats | None):
    """``(k, u, v)``: for each ear length, one pair of links per orbit of the parent's automorphisms, among the
    pairs whose ear splits every removable branch of the parent longer than the ear (:meth:`_Parent.needed`; the
    others are never canonical). These sets are closed under the automorphisms, so one orbit representative of
    each is taken from the union."""
    n = parent.n
    adjm = parent.adjm
    wanted: dict[int, set[Edge]] = {}
    everything = None
    for k in ks:
        need = parent.needed(k) if parent.branches else []
        if need is None:
            continue
        if not need:
            if everything is None:
                everything = {(u, v) for u in range(n) for v in range(u + 1, n)}
            pairs = everything
        else:
            inner = [parent.branches[i][2] for i in need]
            if len(inner) == 1:
                pairs = {(x, y) if x < y else (y, x) for x in inner[0] for y in range(n) if y != x}
            else:
                pairs = {(x, y) if x < y else (y, x) for x in inner[0] for y in inner[1]}
        if not k:
            pairs = {(u, v) for u, v in pairs if not adjm[u] >> v & 1}
        if pairs:
            wanted[k] = pairs
    if not wanted:
        return
    union = set().union(*wanted.values())
    generators = nauty(pynauty.autgrp, _nauty_graph(n, parent.edges))[0]
    if stats is not None:
        stats.nauty_calls += 1
    reps = pair_orbits(union, generators) if generators else sorted(union)
    for k in ks:
        if k in wanted:
            pairs = wanted[k]
            yield from ((k, u, v) for u, v in reps if (u, v) in pairs)


def children(parent: Graph, k: int, stats: Stats | None = None):
    """``(child, order)`` for each child of ``parent`` with an ear of ``k`` binary links that is its canonical
    ear, one per orbit of the parent's automorphisms on pairs of links (``order`` as :func:`canonical_ear`).

    >>> [c for c, _ in children(cycle(4), 1)]
    [(5, ((0, 1), (1, 2), (2, 3), (0, 3), (0, 4), (4, 2)))]
    """
    yield from _children(parent, [k], stats)


def _children(graph: Graph, ks, stats):
    parent = _Parent(graph, min(ks))
    for k, u, v in _pairs(parent, ks, stats):
        if stats is not None:
            stats.candidates += 1
        if parent.beaten(u, v, k):
            continue
        edges, deg, adjm, branches, mine, sure = parent.child(u, v, k)
        order = canonical_ear(parent.n + k, deg, adjm, branches, mine, edges, stats, sure)
        if order is not None and (k >= 2 or ear_is_free(parent.n + k, deg, branches, mine)):
            yield (parent.n + k, edges), order


def _ears(node_loops: int, node_dof: int, loops: int, dof: int) -> list[int]:
    """The ear lengths ``k`` that take a chain of ``node_loops`` loops and DOF ``node_dof`` a step to the target
    (the child's DOF is ``node_dof + k − 2``)."""
    return [k for k in range(dof + 2 * (loops - node_loops) - node_dof + 3)
            if in_region(node_loops + 1, node_dof + k - 2, loops, dof)]


def descend(starts: list[Graph], loops: int, dof: int, stats: Stats | None = None) -> tuple[list[bytes], Stats]:
    """The records (sorted) of every chain of ``loops`` loops and DOF ``dof`` that descends from ``starts`` (chains
    of the way there, each made by canonical augmentation or a single loop), and what the walk did."""
    stats = stats if stats is not None else Stats()
    start = time.process_time()
    out: list[bytes] = []
    stack = list(reversed(starts))
    while stack:
        n, edges = node = stack.pop()
        node_loops = len(edges) - n + 1
        node_dof = 3 * (n - 1) - 2 * len(edges)
        if node_loops == loops:
            if node_dof == dof:
                out.append(record(n, edges, ()))
                stats.kept += 1
            continue
        ks = _ears(node_loops, node_dof, loops, dof)
        if not ks:
            continue
        stats.expanded[(node_loops, node_dof)] = stats.expanded.get((node_loops, node_dof), 0) + 1
        if node_loops + 1 == loops:
            for child, order in _children(node, ks, stats):
                out.append(record(*child, order))
                stats.nauty_calls += 0 if order else 1
                stats.kept += 1
        else:
            stack.extend(reversed([child for child, _ in _children(node, ks, stats)]))
    out.sort()
    stats.seconds += time.process_time() - start
    return out, stats


def frontier(loops: int, dof: int, depth: int, stats: Stats | None = None) -> list[Graph]:
    """The chains of ``depth`` loops on the way to the target (``loops`` loops, DOF ``dof``), in a fixed order:
    the starts of independent walks (:func:`descend`)."""
    level = roots(loops, dof)
    for here in range(1, min(depth, loops)):
        nxt = []
        for node in level:
            n, edges = node
            ks = _ears(here, 3 * (n - 1) - 2 * len(edges), loops, dof)
            if ks:
                nxt.extend(child for child, _ in _children(node, ks, stats))
        level = nxt
    return level


def merge_records(parts) -> heapq.merge:
    """The records of sorted parts (iterables of records), merged into one sorted stream."""
    return heapq.merge(*parts)


#: The walks start from the chains of this many loops (or two fewer than the target): 16,147 starts for 14
#: links, DOF 1, made here in seconds ...
START_LOOPS = 4
#: ... about this many starts to a part (a task, and a file of a job folder), and at least this many parts a
#: worker. Many starts a part make parts of similar cost, and a few of them a fair sample of the whole.
STARTS_PER_PART = 250
PARTS_PER_WORKER = 8


_STARTS: dict = {}


def plan(loops: int, dof: int, workers: int = 1) -> tuple[list[Graph], int]:
    """The starts of the walks to the chains of ``loops`` loops and DOF ``dof`` (the chains of
    :data:`START_LOOPS` loops, or two fewer than the target, on the way there, by canonical augmentation here)
    and how many parts
    to cut them into: part ``i`` of ``p`` walks from ``starts[i::p]``. The starts are sorted by DOF, whose
    subtrees differ most, so that each part holds its share of every DOF: parts of similar size, and a few
    parts drawn at random tell the size of the whole (:func:`~domes.typesynth.atlas.forecast`)."""
    key = (loops, dof, max(1, min(loops - 2, START_LOOPS)))
    if key not in _STARTS:                             # a forecast and the run after it make the same starts
        _STARTS.clear()
        _STARTS[key] = frontier(*key)
    starts = list(_STARTS[key])
    starts.sort(key=lambda g: 3 * (g[0] - 1) - 2 * len(g[1]))      # by DOF (stable): every part gets its share
    parts = max(1, min(len(starts), max(PARTS_PER_WORKER * workers, -(-len(starts) // STARTS_PER_PART))))
    return starts, parts


def walk_part(task: tuple) -> bytes:
    """The task of one part, sent to a worker: ``(pickled starts, i, parts, loops, dof)`` -> pickled ``(records
    joined, stats)``; its arguments and result are single byte strings, which Dask passes on fast."""
    blob, i, parts, loops, dof = task
    records, stats = descend(pickle.loads(blob)[i::parts], loops, dof)
    return pickle.dumps((b"".join(records), stats), protocol=pickle.HIGHEST_PROTOCOL)


def split_records(data: bytes, links: int) -> list[bytes]:
    """The records of a part (joined), each of :func:`record_width` bytes; ValueError if ``data`` is not a part of
    sorted records of chains of ``links`` links."""
    width = record_width(links)
    if len(data) % width:
        raise ValueError(f"{len(data):,} bytes are not records of {width} bytes")
    out = [data[i:i + width] for i in range(0, len(data), width)]
    if any(r[0] != links for r in out) or any(a >= b for a, b in zip(out, out[1:])):
        raise ValueError(f"it does not hold sorted records of {links}-link chains")
    return out
