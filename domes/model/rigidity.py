"""Mobility of sub-chains: degenerate (rigid) sub-chains and ear slack.

For a set ``S`` of links of a chain of planar motion with simple revolute joints, the
sub-chain DOF is ``F(S) = 3(|S| − 1) − 2·e(S)`` where ``e(S)`` counts the
joints between links of ``S`` (Grübler). A chain is *degenerate* when a
proper subset of three or more links has ``F(S) ≤ 0``: it contains a rigid
(structure) or over-constrained sub-chain (seed 002, §3-1-I.3, §3-2-I.5).

All subsets are tabulated at once with numpy (``2**n`` entries), which is
exact and fast for the chain sizes of type synthesis (n ≤ 16).

>>> subchain_dof(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {0, 1, 2, 3})
1
>>> rigid_subchain(5, [(0, 1), (1, 2), (0, 2), (2, 3), (3, 4), (4, 0)])
[0, 1, 2]
"""

from __future__ import annotations

from typing import Iterable, Sequence

import numpy as np

from domes.errors import InputError
from domes.model.mobility import mobility

Edge = tuple[int, int]

#: Largest chain whose subsets are tabulated (2**MAX_LINKS entries).
MAX_LINKS = 20
_BIG = np.int32(1 << 20)


def subset_sizes(n: int) -> np.ndarray:
    """``|S|`` for every subset bitmask of ``n`` links."""
    counts = np.zeros(1 << n, dtype=np.int32)
    for bit in range(n):
        counts[1 << bit : 1 << (bit + 1)] = counts[: 1 << bit] + 1
    return counts


def subset_dof_table(n: int, edges: Iterable[Edge]) -> np.ndarray:
    """``F(S)`` for every subset ``S`` of the ``n`` links, indexed by bitmask.

    >>> int(subset_dof_table(3, [(0, 1), (1, 2), (0, 2)])[0b111])
    0
    """
    if n > MAX_LINKS:
        raise InputError(f"sub-chain tables are limited to {MAX_LINKS} links, got {n}")
    subsets = np.arange(1 << n, dtype=np.int64)
    inside = np.zeros(1 << n, dtype=np.int32)
    for u, v in edges:
        inside += ((subsets >> u) & (subsets >> v) & 1).astype(np.int32)
    return mobility(subset_sizes(n), inside)


def subchain_dof(n: int, edges: Iterable[Edge], links: Iterable[int]) -> int:
    """``F(S) = 3(|S| − 1) − 2·e(S)`` for one set of links."""
    chosen = set(links)
    inside = sum(1 for u, v in edges if u in chosen and v in chosen)
    return mobility(len(chosen), inside)


def rigid_subchain(n: int, edges: Sequence[Edge]) -> list[int] | None:
    """The smallest proper sub-chain (3+ links) with ``F(S) ≤ 0``, or ``None``.

    Among the smallest, the one with the least DOF, then the first in
    lexicographic order; its links are returned sorted.

    >>> rigid_subchain(4, [(0, 1), (1, 2), (2, 3), (0, 3)]) is None
    True
    """
    table = subset_dof_table(n, edges)
    sizes = subset_sizes(n)
    bad = np.flatnonzero((table <= 0) & (sizes >= 3) & (np.arange(1 << n) != (1 << n) - 1))
    if bad.size == 0:
        return None
    best = min(bad.tolist(), key=lambda s: (int(sizes[s]), int(table[s]), sorted(_bits(s))))
    return sorted(_bits(best))


def _bits(mask: int) -> list[int]:
    return [i for i in range(mask.bit_length()) if mask >> i & 1]


def is_degenerate(n: int, edges: Sequence[Edge]) -> bool:
    """True if a proper sub-chain of three or more links is rigid or over-constrained."""
    return rigid_subchain(n, edges) is not None


def pair_slack(n: int, edges: Iterable[Edge]) -> np.ndarray:
    """``slack[u, v] = min F(T)`` over proper link sets ``T`` containing ``u`` and ``v``.

    Adding a branch of ``k`` binary links between ``u`` and ``v`` to a
    non-degenerate chain keeps it non-degenerate exactly when
    ``slack[u, v] ≥ 3 − k``: a rigid set of the new chain must hold the whole
    branch, so it is ``T`` plus the branch, with DOF ``F(T) + k − 2``.

    >>> int(pair_slack(4, [(0, 1), (1, 2), (2, 3), (0, 3)])[0, 2])  # T = {0, 1, 2}
    2
    """
    table = subset_dof_table(n, edges)
    table[-1] = _BIG  # the whole chain is not a proper sub-chain
    # Superset minimum: after the pass over bit i, table[S] = min over supersets
    # of S that differ from S in bits <= i.
    for bit in range(n):
        view = table.reshape(-1, 2, 1 << bit)
        np.minimum(view[:, 0, :], view[:, 1, :], out=view[:, 0, :])
    slack = np.full((n, n), _BIG, dtype=np.int32)
    for u in range(n):
        for v in range(u + 1, n):
            slack[u, v] = slack[v, u] = table[(1 << u) | (1 << v)]
    return slack
