"""The compiled loops of :mod:`domes.typesynth.earkernel` (this module imports numba: import it through
:func:`domes.typesynth.earkernel.load`)."""

import numba
import numpy as np


@numba.njit(cache=True, nogil=True)
def _connected(adj, alive):
    """Whether the links of the bitmask ``alive`` are connected through each other (``adj[i]``: neighbours)."""
    if alive == 0:
        return True
    low = alive & -alive
    seen = low
    frontier = low
    while frontier:
        new = np.int64(0)
        i = 0
        rest = frontier
        while rest:
            if rest & 1:
                new |= adj[i]
            rest >>= 1
            i += 1
        frontier = new & alive & ~seen
        seen |= frontier
    return seen == alive

@numba.njit(cache=True, nogil=True)
def removable(given, n):
    """For each branch of a 2-connected chain of ``n`` links: 1 if the chain less the branch is 2-connected,
    else 0. ``given`` holds the links' neighbours (bitmasks), then per branch its ends and its inner links
    (a bitmask). A cut link of the rest must separate the branch's ends (the chain is 2-connected), so each
    other link is taken out in turn."""
    adj = given[:n]
    count = (given.shape[0] - n) // 3
    full = (np.int64(1) << n) - 1
    out = np.zeros(count, dtype=np.uint8)
    local = adj.copy()
    for j in range(count):
        u, v, inner = given[n + 3 * j], given[n + 3 * j + 1], given[n + 3 * j + 2]
        alive = full & ~inner
        local[u] = adj[u] & alive
        local[v] = adj[v] & alive
        if inner == 0:
            local[u] &= ~(np.int64(1) << v)
            local[v] &= ~(np.int64(1) << u)
        elif (adj[u] >> v) & 1:
            out[j] = 1
            local[u] = adj[u]
            local[v] = adj[v]
            continue
        ok = 1
        for x in range(n):
            if x == u or x == v or not (alive >> x) & 1:
                continue
            if not _connected(local, alive & ~(np.int64(1) << x)):
                ok = 0
                break
        out[j] = ok
        local[u] = adj[u]
        local[v] = adj[v]
    return out

@numba.njit(cache=True, nogil=True)
def least_freedom(size, need, change, whole):
    """The least of ``3·(|T| + 1) + Σ change[e]`` over the subsets ``T`` of ``size`` links, the sum over the
    ``e`` with ``need[e] ⊆ T``; the whole set adds ``whole``."""
    best = np.int64(1) << 40
    last = (np.int64(1) << size) - 1
    for t in range(last + 1):
        value = np.int64(3)
        rest = t
        while rest:
            value += 3 * (rest & 1)
            rest >>= 1
        for e in range(need.shape[0]):
            if t & need[e] == need[e]:
                value += change[e]
        if t == last:
            value += whole
        if value < best:
            best = value
    return best
