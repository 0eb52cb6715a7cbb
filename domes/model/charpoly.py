"""The book's isomorphism screen: the characteristic polynomial (§3-2-II.4).

The coefficients of ``det(xI − A)`` of the adjacency matrix ``A`` are graph
invariants, computed here exactly in integers (Faddeev–LeVerrier). Equal
polynomials do **not** imply isomorphic chains: among the 230 one-DOF
10-bar chains two pairs collide (seed 002 digest §1.9, B6). Use it as a
fast screen, never as the test.

>>> characteristic_polynomial(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
(1, 0, -4, 0, 0)
"""

from __future__ import annotations

from typing import Iterable

import numpy as np

Edge = tuple[int, int]


def characteristic_polynomial(n: int, edges: Iterable[Edge]) -> tuple[int, ...]:
    """Integer coefficients ``(1, c1, …, cn)`` of ``det(xI − A)``, highest power first."""
    a = np.zeros((n, n), dtype=np.int64)
    for u, v in edges:
        a[u, v] = a[v, u] = 1
    coefficients = [1]
    m = np.zeros((n, n), dtype=np.int64)
    identity = np.eye(n, dtype=np.int64)
    c = 1
    for k in range(1, n + 1):
        m = a @ m + c * identity  # M_k = A·M_{k−1} + c_{k−1}·I
        c = -int(np.trace(a @ m)) // k
        coefficients.append(c)
    return tuple(coefficients)
