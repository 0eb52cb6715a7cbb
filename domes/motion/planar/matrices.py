"""Planar displacement, velocity and acceleration matrices (seed 002, §2-2, after Suh).

A body turned by ``θ`` whose reference point moved from ``p1`` to ``p``
carries every point ``q1`` to ``q = D·[q1; 1]`` (2-24)–(2-26); with the
reference point's velocity and acceleration and ``θ̇, θ̈`` the same point has
velocity ``V·[q; 1]`` (2-32) and acceleration ``A·[q; 1]`` (2-33), with the
angular-acceleration matrix ``[[−θ̇², −θ̈], [θ̈, −θ̇²]]`` (the digest's reading
of the garbled (2-30)).

>>> D = displacement_matrix(math.radians(60), (1, 1), (3, 2))
>>> [round(x, 3) for x in D[0]], apply(D, (3, 1))
([0.5, -0.866, 3.366], (4.0, 3.732050807568877))
"""

from __future__ import annotations

import math


def displacement_matrix(theta, p1, p):
    """``D = [[R_θ, p − R_θ p1], [0, 0, 1]]`` (2-25)."""
    c, s = math.cos(theta), math.sin(theta)
    return ((c, -s, p[0] - c * p1[0] + s * p1[1]),
            (s, c, p[1] - s * p1[0] - c * p1[1]),
            (0.0, 0.0, 1.0))


def velocity_matrix(theta_d, p, p_d):
    """``V = [[W, ṗ − W p], [0, 0, 0]]`` with ``W = [[0, −θ̇], [θ̇, 0]]`` (2-29), (2-32)."""
    return ((0.0, -theta_d, p_d[0] + theta_d * p[1]),
            (theta_d, 0.0, p_d[1] - theta_d * p[0]),
            (0.0, 0.0, 0.0))


def acceleration_matrix(theta_d, theta_dd, p, p_dd):
    """``A = [[A_ω, p̈ − A_ω p], [0, 0, 0]]`` with ``A_ω = [[−θ̇², −θ̈], [θ̈, −θ̇²]]`` (2-30), (2-33)."""
    w2 = theta_d * theta_d
    return ((-w2, -theta_dd, p_dd[0] + w2 * p[0] + theta_dd * p[1]),
            (theta_dd, -w2, p_dd[1] - theta_dd * p[0] + w2 * p[1]),
            (0.0, 0.0, 0.0))


def apply(M, q):
    """``M·[q; 1]`` as a pair."""
    return (M[0][0] * q[0] + M[0][1] * q[1] + M[0][2], M[1][0] * q[0] + M[1][1] * q[1] + M[1][2])
