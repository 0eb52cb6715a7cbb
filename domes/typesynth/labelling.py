"""The labelled graph generator: joint types on the joints of chains (DOMES module 7).

Given chains and how many joints of each type they must have (``P``, ``G``,
...; all others revolute), list every labelling that is different up to the
automorphisms of the chain that keep the labels. Joints are typed one at a
time; after each step duplicates are removed by the labelled chain's nauty
certificate, which is exact and complete (every labelling with one joint
less is isomorphic to a kept one).

Loop limits (e.g. "number of gear pairs should not be more than 1 for any
independent loop", seed 002 §7-2, digest 4.5 criterion iii) hold when some
cycle basis consists of loops within the limits, i.e. the simple cycles
within the limits span the cycle space (their GF(2) rank is ``L``). No one
basis is invariant under isomorphism; "every simple cycle" would be too
strict, since in a chain without cut links any two joints share a cycle.

>>> from domes.typesynth import chains
>>> len(label_joints(chains(links=4, dof=1), {"P": 1}))
1
>>> len(label_joints(chains(links=4, dof=1), {"P": 2}))
2
>>> len(label_joints(chains(links=6, dof=1), {"G": 2}, per_loop_max={"G": 1}))
11
"""

from __future__ import annotations

from typing import Iterable, Mapping

import networkx as nx

from domes.errors import InputError
from domes.model.chain import Chain
from domes.model.labelled import JOINT_TYPES, LabelledChain


def _cycles(chain: LabelledChain) -> list[tuple[int, frozenset[int]]]:
    """Every simple cycle, as a bit mask and as the set of its joint indices."""
    index = {e: i for i, e in enumerate(chain.edges)}
    graph = nx.Graph(chain.edges)
    out = []
    for cycle in nx.simple_cycles(graph):
        ring = zip(cycle, cycle[1:] + cycle[:1])
        joints = frozenset(index[(min(u, v), max(u, v))] for u, v in ring)
        out.append((sum(1 << j for j in joints), joints))
    return out


def _rank(masks: Iterable[int]) -> int:
    """Rank over GF(2) of joint-set bit masks."""
    basis: list[int] = []
    for m in masks:
        for b in basis:
            m = min(m, m ^ b)
        if m:
            basis.append(m)
    return len(basis)


def _within_limits(cycles: list[tuple[int, frozenset[int]]], types: tuple[str, ...], limits: Mapping[str, int], loops: int) -> bool:
    ok = (mask for mask, joints in cycles if all(sum(types[j] == t for j in joints) <= m for t, m in limits.items()))
    return _rank(ok) == loops


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
            raise InputError(f"cannot count joint type {t!r}; choose among {', '.join(x for x in JOINT_TYPES if x != 'R')}")
        if not isinstance(k, int) or k < 0:
            raise InputError(f"the number of {t} joints must be a whole number >= 0, got {k!r}")
    limits = dict(per_loop_max or {})
    for t in limits:
        if t not in JOINT_TYPES:
            raise InputError(f"unknown joint type {t!r} in the loop limits")
    result: list[LabelledChain] = []
    for chain in chains:
        start = chain if isinstance(chain, LabelledChain) else LabelledChain.build(chain.n, chain.edges)
        if sum(counts.values()) > len(start.edges):
            continue
        cycles = _cycles(start) if limits else []
        loops = len(start.edges) - start.n + 1
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
                        if limits and not _within_limits(cycles, new_types, limits, loops):
                            continue
                        child = LabelledChain.build(labelled.n, labelled.edges, new_types, dict(enumerate(labelled.roles)))
                        seen.setdefault(child.certificate, child)
                layer = list(seen.values())
        result.extend(sorted(layer, key=lambda c: c.certificate))
    return result
