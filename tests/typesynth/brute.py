"""Brute-force regeneration, independent of the engine, the rule parser and nauty.

Rules are written here as Python predicates straight from the book's text;
every role tuple on the numbered links of every chain is enumerated, and
tuples are identified when a chain automorphism (networkx VF2) maps one onto
the other.
"""

from __future__ import annotations

from itertools import combinations

import networkx as nx


def automorphisms(g):
    return [dict(m) for m in nx.algorithms.isomorphism.GraphMatcher(g, g).isomorphisms_iter()]


def _image(selection, sigma):
    if isinstance(selection, frozenset):
        return tuple(sorted(sigma[x] for x in selection))
    return (sigma[selection],)


def orbit_count(g, tuples, autos):
    """Number of classes of role tuples under the automorphisms of g."""
    canon = set()
    for t in tuples:
        canon.add(min(tuple(_image(s, sigma) for s in t) for sigma in autos))
    return len(canon)


def run(graphs, stages):
    """``stages``: list of (kind, predicate) with kind 'link' | 'pair' | 'screen'.

    A predicate gets (g, roles, candidate) where roles is the tuple so far
    (links, or frozensets for pairs) and candidate the new link/pair (None
    for screens). Returns per stage (classes, raw tuples).
    """
    per_graph = [[()] for _ in graphs]
    autos = [automorphisms(g) for g in graphs]
    out = []
    for kind, ok in stages:
        classes = raw = 0
        for k, g in enumerate(graphs):
            nxt = []
            for t in per_graph[k]:
                if kind == "screen":
                    if ok(g, t, None):
                        nxt.append(t)
                    continue
                options = g.nodes if kind == "link" else [frozenset(p) for p in combinations(g.nodes, 2)]
                nxt += [t + (c,) for c in options if ok(g, t, c)]
            per_graph[k] = nxt
            raw += len(nxt)
            classes += orbit_count(g, nxt, autos[k])
        out.append((classes, raw))
    return out


def members(selection):
    return selection if isinstance(selection, frozenset) else {selection}
