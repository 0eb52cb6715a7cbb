"""The book's link similarity (seed 002, §3-3-III.1), as an explanation of the orbits.

``B = A²`` is the position-relation matrix; two links with the same number
of joints are *parallel similar* when their rows of ``B`` agree off the
pair. Links are *similar* when an automorphism maps one onto the other: the
similarity matrix ``C`` is the orbit partition (digest §1.12, A6). The
regeneration decides by orbits; these matrices only explain them.

>>> from domes.model import Chain
>>> s = similarity(Chain(4, ((0, 1), (1, 2), (2, 3), (0, 3))))
>>> s.position.tolist()[0]
[2, 0, 2, 0]
>>> s.similar.tolist()[0]
[1, 1, 1, 1]
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from domes.model.chain import Chain


@dataclass(frozen=True)
class Similarity:
    """``B = A²``, the orbit similarity ``C`` (1 = similar) and the parallel-similar pairs."""

    position: np.ndarray
    similar: np.ndarray
    parallel_pairs: tuple[tuple[int, int], ...]


def similarity(chain: Chain) -> Similarity:
    """The matrices of §3-3-III.1 for ``chain`` (see the module doc)."""
    a = np.zeros((chain.n, chain.n), dtype=np.int64)
    for u, v in chain.edges:
        a[u, v] = a[v, u] = 1
    b = a @ a
    orbit = np.array(chain.automorphisms.orbit_of)
    c = (orbit[:, None] == orbit[None, :]).astype(np.int64)
    parallel = []
    for s in range(chain.n):
        for t in range(s + 1, chain.n):
            if chain.degrees[s] == chain.degrees[t]:
                others = [j for j in range(chain.n) if j not in (s, t)]
                if np.array_equal(b[s, others], b[t, others]):
                    parallel.append((s, t))
    return Similarity(b, c, tuple(parallel))
