"""Rigid sub-chains by the pebble game, and graph6 text without networkx.

The pebble game of Jacobs and Hendrickson (1997), in the (k, l) form of Lee
and Streinu (2008), decides whether a multigraph is *(k, l)-sparse*: every
set ``S`` of vertices spans at most ``k|S| − l`` edges. With every joint
counted twice, ``k = 3`` and ``l = 4``, that is ``2e(S) ≤ 3|S| − 4``, or
``F(S) = 3(|S| − 1) − 2e(S) ≥ 1`` for every set of links: a chain of planar
motion with simple revolute joints is non-degenerate (no rigid or
over-constrained sub-chain, :mod:`domes.model.rigidity`) exactly when its
doubled graph passes, apart from the whole chain itself when its DOF is 0
or less. The game takes ``O(n·e)`` steps where the subset tables of
:mod:`domes.model.rigidity` take ``2**n``: it is the independent check the
atlas is compared with at sizes where those tables per graph are slow.

>>> pebble_degenerate(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
False
>>> pebble_degenerate(5, [(0, 1), (1, 2), (0, 2), (2, 3), (3, 4), (4, 0)])   # a triangle is rigid
True
>>> decode_graph6(encode_graph6(3, [(0, 1), (1, 2)]))
(3, ((0, 1), (1, 2)))
"""

from __future__ import annotations

from collections.abc import Iterable

from domes.errors import InputError

Edge = tuple[int, int]


class PebbleGame:
    """The ``(k, l)`` pebble game played edge by edge (``0 ≤ l < 2k``).

    Each vertex starts with ``k`` pebbles; an edge is accepted when ``l + 1``
    pebbles can be gathered on its two ends (moved along directed edges,
    which are reversed as a pebble travels), and then one is spent on it.
    An edge that cannot be accepted spans, with the vertices reached, a set
    with more than ``k|S| − l`` edges: :meth:`add` returns that set.

    >>> game = PebbleGame(3, k=3, l=3)        # a triangle of pins: 6 bars make it rigid, a 7th is one too many
    >>> [game.add(u, v) for u, v in [(0, 1), (1, 2), (0, 2)] for _ in range(2)] + [game.add(0, 1)]
    [None, None, None, None, None, None, {0, 1, 2}]
    """

    def __init__(self, n: int, k: int = 3, l: int = 4):  # noqa: E741
        if not 0 <= l < 2 * k:
            raise InputError(f"the pebble game needs 0 <= l < 2k, got k={k}, l={l}")
        self.l = l  # noqa: E741
        self.pebbles = [k] * n
        self.heads: list[list[int]] = [[] for _ in range(n)]     # the edges each vertex has spent a pebble on

    def _fetch(self, start: int, other: int) -> bool:
        """Bring one pebble to ``start`` from a vertex reachable from it (not ``other``), reversing the path."""
        parent = {start: -1, other: -1}
        stack = [start]
        while stack:
            x = stack.pop()
            for y in self.heads[x]:
                if y in parent:
                    continue
                parent[y] = x
                if self.pebbles[y]:
                    self.pebbles[y] -= 1
                    self.pebbles[start] += 1
                    while y != start:                      # reverse the path start -> ... -> y
                        x = parent[y]
                        self.heads[x].remove(y)
                        self.heads[y].append(x)
                        y = x
                    return True
                stack.append(y)
        return False

    def add(self, u: int, v: int) -> set[int] | None:
        """Accept the edge ``u-v`` if independent of those accepted (None); else the vertices of the set it
        over-fills."""
        if u == v:
            raise InputError(f"joint ({u}, {v}) joins a link to itself")
        while self.pebbles[u] + self.pebbles[v] <= self.l:
            if not (self._fetch(u, v) or self._fetch(v, u)):
                seen, stack = {u, v}, [u, v]
                while stack:
                    for y in self.heads[stack.pop()]:
                        if y not in seen:
                            seen.add(y)
                            stack.append(y)
                return seen
        if self.pebbles[u]:
            self.pebbles[u] -= 1
            self.heads[u].append(v)
        else:
            self.pebbles[v] -= 1
            self.heads[v].append(u)
        return None


def pebble_sparse(n: int, edges: Iterable[Edge], k: int = 3, l: int = 4, copies: int = 2) -> bool:  # noqa: E741
    """True when the graph with each edge taken ``copies`` times is ``(k, l)``-sparse (:class:`PebbleGame`).

    >>> pebble_sparse(3, [(0, 1), (1, 2), (0, 2)])     # 6 > 3·3 − 4
    False
    """
    game = PebbleGame(n, k, l)
    return all(game.add(u, v) is None for u, v in edges for _ in range(copies))


def pebble_degenerate(n: int, edges: Iterable[Edge]) -> bool:
    """True when a proper sub-chain of three or more links is rigid or over-constrained (by the pebble game).

    A chain of DOF 1 or more is non-degenerate exactly when its doubled
    graph is (3, 4)-sparse. For a chain of DOF 0 or less the whole chain
    breaks the count, so each link is left out in turn: a proper set that
    breaks it lies inside one of those.
    """
    edges = list(edges)
    if 3 * (n - 1) - 2 * len(edges) >= 1:
        return not pebble_sparse(n, edges)
    return any(not pebble_sparse(n, [(a, b) for a, b in edges if x not in (a, b)]) for x in range(n))


def encode_graph6(n: int, edges: Iterable[Edge]) -> str:
    """The graph6 string of a graph on ``0..n−1`` (``n ≤ 62``), as nauty and networkx write it.

    >>> encode_graph6(4, [(0, 1), (1, 2), (2, 3), (0, 3)])     # the four-bar loop
    'Cl'
    """
    if not 0 <= n <= 62:
        raise InputError(f"graph6 strings here hold 0 to 62 links, got {n}")
    bits = 0
    total = n * (n - 1) // 2
    for u, v in edges:
        if u > v:
            u, v = v, u
        bits |= 1 << (total - 1 - (v * (v - 1) // 2 + u))     # column by column: (0,1), (0,2), (1,2), (0,3), ...
    pad = -total % 6
    bits <<= pad
    chars = (total + pad) // 6
    return chr(n + 63) + "".join(chr(((bits >> (6 * (chars - 1 - i))) & 63) + 63) for i in range(chars))


def decode_graph6(text: str) -> tuple[int, tuple[Edge, ...]]:
    """``(n, edges)`` of a graph6 string of at most 62 vertices, the edges sorted by their larger end.

    >>> decode_graph6("Cl")
    (4, ((0, 1), (1, 2), (0, 3), (2, 3)))
    """
    if not text or not 63 <= ord(text[0]) <= 125 or any(not 63 <= ord(c) <= 126 for c in text):
        raise InputError(f"{text!r} is not a graph6 string of at most 62 vertices")
    n = ord(text[0]) - 63
    total = n * (n - 1) // 2
    if len(text) - 1 != -(-total // 6):
        raise InputError(f"{text!r} is not a graph6 string: {n} vertices need {-(-total // 6)} more characters")
    bits = 0
    for c in text[1:]:
        bits = (bits << 6) | (ord(c) - 63)
    bits >>= -total % 6
    edges = []
    index = total - 1
    for v in range(1, n):
        for u in range(v):
            if bits >> index & 1:
                edges.append((u, v))
            index -= 1
    return n, tuple(edges)


__all__ = ["decode_graph6", "encode_graph6", "pebble_degenerate", "pebble_sparse"]
