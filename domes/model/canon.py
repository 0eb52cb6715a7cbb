"""Exact isomorphism by nauty's canonical labelling (through pynauty).

A chain is a simple graph: links are vertices ``0..n-1``, joints are edges.
Two chains are isomorphic exactly when their certificates are equal.

>>> square = (4, ((0, 1), (1, 2), (2, 3), (0, 3)))
>>> certificate(*square) == certificate(4, ((0, 2), (2, 1), (1, 3), (3, 0)))
True
>>> automorphisms(*square).order
8
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Sequence

import pynauty

Edge = tuple[int, int]


def nauty_graph(n: int, edges: Iterable[Edge], coloring: Sequence[set[int]] = ()) -> pynauty.Graph:
    """A pynauty graph on ``n`` vertices with the given edges (and vertex colour classes)."""
    adjacency: dict[int, list[int]] = {}
    for u, v in edges:
        adjacency.setdefault(u, []).append(v)
    return pynauty.Graph(n, adjacency_dict=adjacency, vertex_coloring=list(coloring))


def nauty(call, graph: pynauty.Graph):
    """``call(graph)``, a pynauty function. A Ctrl-C that arrives while pynauty reads the graph's attributes
    reaches Python as ``TypeError: missing 'adjacency_dict' attribute`` (the interrupt replaced by pynauty's
    own error); it is raised again as the KeyboardInterrupt it is, so that a run stops cleanly."""
    try:
        return call(graph)
    except TypeError as exc:
        if str(exc).startswith("missing '") and str(exc).endswith("' attribute"):
            raise KeyboardInterrupt from None
        raise


def certificate(n: int, edges: Iterable[Edge]) -> bytes:
    """nauty's certificate: equal for two graphs exactly when they are isomorphic."""
    return nauty(pynauty.certificate, nauty_graph(n, edges))


def canonical_form(n: int, edges: Iterable[Edge]) -> tuple[bytes, tuple[Edge, ...]]:
    """The certificate and the edges relabelled into nauty's canonical order.

    >>> canonical_form(3, ((0, 1), (1, 2)))[1]
    ((0, 2), (1, 2))
    """
    graph = nauty_graph(n, edges)
    order = nauty(pynauty.canon_label, graph)  # canonical vertex i is original vertex order[i]
    position = {v: i for i, v in enumerate(order)}
    relabelled = tuple(sorted(tuple(sorted((position[u], position[v]))) for u, v in edges))
    return nauty(pynauty.certificate, graph), relabelled


@dataclass(frozen=True)
class Automorphisms:
    """The automorphism group of a chain: its order, generators and link orbits.

    ``orbit_of[v]`` is the smallest link in the orbit of link ``v``; links of
    one orbit are the book's "similar links" (§3-3-III.1).
    """

    order: int
    generators: tuple[tuple[int, ...], ...]
    orbit_of: tuple[int, ...]

    @property
    def orbits(self) -> list[list[int]]:
        """The link orbits, each sorted, in order of their smallest link."""
        groups: dict[int, list[int]] = {}
        for v, rep in enumerate(self.orbit_of):
            groups.setdefault(rep, []).append(v)
        return [groups[r] for r in sorted(groups)]

    def pair_orbit_representatives(self, pairs: Iterable[Edge]) -> list[Edge]:
        """One pair ``(u, v)``, ``u < v``, from each orbit of the group on the given pairs.

        The pairs must be a union of orbits (closed under the group).

        >>> from itertools import combinations
        >>> automorphisms(4, ((0, 1), (1, 2), (2, 3), (0, 3))).pair_orbit_representatives(
        ...     combinations(range(4), 2))
        [(0, 1), (0, 2)]
        """
        return pair_orbits([tuple(sorted(p)) for p in pairs], self.generators)


def pair_orbits(pairs: Iterable[Edge], generators) -> list[Edge]:
    """The least pair of each orbit of the group of ``generators`` (permutations of the links) on ``pairs``
    (each ``(u, v)`` with ``u < v``; a union of orbits), sorted.

    >>> pair_orbits([(0, 1), (1, 2), (2, 3), (0, 3)], [(1, 2, 3, 0)])      # a square turned by a quarter
    [(0, 1)]
    """
    pairs = list(pairs)
    parent = {p: p for p in pairs}

    def find(p: Edge) -> Edge:
        while parent[p] != p:
            parent[p] = parent[parent[p]]
            p = parent[p]
        return p

    for perm in generators:
        for u, v in pairs:
            image = (perm[u], perm[v]) if perm[u] < perm[v] else (perm[v], perm[u])
            if image in parent:
                a, b = find((u, v)), find(image)
                if a != b:
                    parent[max(a, b)] = min(a, b)
    return sorted({find(p) for p in pairs})


def automorphisms(n: int, edges: Iterable[Edge], coloring: Sequence[set[int]] = ()) -> Automorphisms:
    """The automorphism group (preserving vertex colour classes, if given)."""
    generators, mantissa, exponent, orbits, _ = nauty(pynauty.autgrp, nauty_graph(n, edges, coloring))
    order = round(mantissa * 10**exponent)
    first: dict[int, int] = {}
    for v, o in enumerate(orbits):
        first.setdefault(o, v)
    return Automorphisms(order, tuple(tuple(g) for g in generators), tuple(first[o] for o in orbits))
