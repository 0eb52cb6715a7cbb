"""Structural characteristic number K of a zero-DOF chain (§3-2-I.4, (3-21)).

A zero-DOF chain of ``V`` loops is a base loop plus ``V − 1`` single open
chains (SOCs, ears) added in sequence; the SOC with ``m_j`` joints has the
structural factor ``Δ_j = m_j − 3`` and ``Σ Δ_j = 0``. The structural
characteristic number is the least, over all such decompositions, of the
sum of the positive factors: ``K = min_t Σ_j Δ_j⁺``.

Computed exactly by a shortest-path search over the sets of joints already
placed (the digest's Appendix A recipe), not by the book's greedy rule.

>>> structural_number(3, [(0, 1), (1, 2), (0, 2)])
0
"""

from __future__ import annotations

import heapq
from typing import Sequence

from domes.errors import InputError
from domes.model.mobility import mobility

Edge = tuple[int, int]


def _ears(n: int, adjacency: list[list[tuple[int, int]]], placed_vertices: int, used: int):
    """Every SOC on the placed sub-chain: a path from a placed link through new
    links back to a placed link (the same one for a closed SOC).

    Yields ``(edge_mask, joints)``; an open SOC is reported from its smaller end.
    """
    for start in range(n):
        if not placed_vertices >> start & 1:
            continue
        stack = [(start, 0, 0, 0)]  # (link, joints on the path, new links on the path, length)
        while stack:
            v, path_edges, path_vertices, length = stack.pop()
            for w, e in adjacency[v]:
                if (used | path_edges) >> e & 1:
                    continue
                if placed_vertices >> w & 1:
                    if start < w or (start == w and length > 1):
                        yield path_edges | (1 << e), length + 1
                elif not path_vertices >> w & 1:
                    stack.append((w, path_edges | (1 << e), path_vertices | (1 << w), length + 1))


def structural_number(n: int, edges: Sequence[Edge]) -> int:
    """``K`` of a zero-DOF chain (``3(n − 1) = 2j``); see the module doc.

    >>> structural_number(5, [(0, 1), (1, 2), (2, 0), (0, 3), (3, 4), (4, 1)]) in (0, 1)
    True
    """
    dof = mobility(n, len(edges))
    if dof != 0:
        raise InputError(f"K is defined for zero-DOF chains; {n} links and {len(edges)} joints have DOF {dof}")
    adjacency: list[list[tuple[int, int]]] = [[] for _ in range(n)]
    for index, (u, v) in enumerate(edges):
        adjacency[u].append((v, index))
        adjacency[v].append((u, index))
    full = (1 << len(edges)) - 1
    ends = [(1 << u) | (1 << v) for u, v in edges]
    best: dict[int, int] = {}
    queue: list[tuple[int, int]] = []
    # Base loops: every cycle, found as an ear closing back on a single start link.
    for start in range(n):
        for edge_mask, joints in _ears(n, adjacency, 1 << start, 0):
            cost = max(joints - 3, 0)
            if best.get(edge_mask, 1 << 30) > cost:
                best[edge_mask] = cost
                heapq.heappush(queue, (cost, edge_mask))
    while queue:
        cost, used = heapq.heappop(queue)
        if cost > best.get(used, 1 << 30):
            continue
        if used == full:
            return cost
        vertices = 0
        for e in range(len(edges)):
            if used >> e & 1:
                vertices |= ends[e]
        for edge_mask, joints in _ears(n, adjacency, vertices, used):
            total = cost + max(joints - 3, 0)
            state = used | edge_mask
            if best.get(state, 1 << 30) > total:
                best[state] = total
                heapq.heappush(queue, (total, state))
    raise InputError("the chain is not connected: it has no SOC decomposition")
