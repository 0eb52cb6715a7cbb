"""The labelled graph generator: joint types on the joints of chains (DOMES module 7).

Given chains and how many joints of each type they must have (``P``, ``G``,
...; all others revolute), list every labelling that is different up to the
automorphisms of the chain that keep the labels. Joints are typed one at a
time; after each step duplicates are removed by the labelled chain's nauty
certificate, which is exact and complete (every labelling with one joint
less is isomorphic to a kept one).

Loop limits (e.g. at most one gear pair in any loop, seed 002 §7-2 and
digest 4.5 criterion iii) are checked on every simple cycle of the chain.

>>> from domes.chains import chains
>>> len(label_joints(chains(links=4, dof=1), {"P": 1}))
1
>>> len(label_joints(chains(links=4, dof=1), {"P": 2}))
2
"""

from __future__ import annotations

from typing import Iterable, Mapping

import networkx as nx

from domes.chains.chain import Chain
from domes.errors import DomesError
from domes.labelled.graph import JOINT_TYPES, LabelledChain


def _cycles(chain: LabelledChain) -> list[frozenset[int]]:
    """Every simple cycle, as the set of joint indices on it."""
    index = {e: i for i, e in enumerate(chain.edges)}
    graph = nx.Graph(chain.edges)
    out = []
    for cycle in nx.simple_cycles(graph):
        ring = zip(cycle, cycle[1:] + cycle[:1])
        out.append(frozenset(index[(min(u, v), max(u, v))] for u, v in ring))
    return out


def label_joints(
    chains: Iterable[Chain | LabelledChain],
    counts: Mapping[str, int],
    per_loop_max: Mapping[str, int] | None = None,
) -> list[LabelledChain]:
    """Every non-isomorphic assignment of ``counts[t]`` joints of type ``t`` (the rest ``R``).

    ``per_loop_max[t]`` bounds the joints of type ``t`` on any loop.
    Labellings are listed chain by chain, in a deterministic order.
    """
    for t, k in counts.items():
        if t not in JOINT_TYPES or t == "R":
            raise DomesError(f"cannot count joint type {t!r}; choose among {', '.join(x for x in JOINT_TYPES if x != 'R')}")
        if not isinstance(k, int) or k < 0:
            raise DomesError(f"the number of {t} joints must be a whole number >= 0, got {k!r}")
    limits = dict(per_loop_max or {})
    for t in limits:
        if t not in JOINT_TYPES:
            raise DomesError(f"unknown joint type {t!r} in the loop limits")
    result: list[LabelledChain] = []
    for chain in chains:
        start = chain if isinstance(chain, LabelledChain) else LabelledChain.build(chain.n, chain.edges)
        if sum(counts.values()) > len(start.edges):
            continue
        cycles = _cycles(start) if limits else []
        layer = [start]
        for t, k in sorted(counts.items()):
            for _ in range(k):
                seen: dict[tuple, LabelledChain] = {}
                for labelled in layer:
                    types = labelled.joint_types
                    for i in range(len(types)):
                        if types[i] != "R":
                            continue
                        new_types = types[:i] + (t,) + types[i + 1 :]
                        if limits and any(sum(new_types[j] == lt for j in c) > m for c in cycles for lt, m in limits.items()):
                            continue
                        child = LabelledChain.build(labelled.n, labelled.edges, new_types, dict(enumerate(labelled.roles)))
                        seen.setdefault(child.certificate, child)
                layer = list(seen.values())
        result.extend(sorted(layer, key=lambda c: c.certificate))
    return result
