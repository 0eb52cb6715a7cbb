"""Where a trigonometric polynomial of degree two is negative, or touches zero: a closed-form linkage's gaps and
branch points, found exactly.

The discriminants of the RSSR (``E² + F² − G²``) and of the spherical
four-bar (``A² + B² − C²``) are such polynomials of the input angle, since
``E, F, G`` (``A, B, C``) are linear in its cosine and sine. Eight samples
give the five coefficients exactly (to rounding); with ``z = e^{iθ}`` the
polynomial times ``z²`` is a quartic whose roots on the unit circle are the
candidate sign changes, each polished by Brent's method on the function
itself. No sampling grid, so no gap narrower than a grid's step is missed.

>>> import math
>>> [tuple(round(x, 12) for x in g) for g in negative(lambda t: math.cos(t) - 0.5)]
[(1.047197551197, 5.235987755983)]
>>> [tuple(round(x, 12) for x in g) for g in negative(lambda t: 0.5 - math.sin(t))]
[(0.523598775598, 2.617993877991)]
>>> negative(lambda t: 2 + math.cos(2 * t))
()
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

TAU = 2 * math.pi
#: A root of the quartic this far from the unit circle (relative) is still a candidate (double roots on the circle
#: come out of the eigenvalue solver only to about √ε).
NEAR_CIRCLE = 1e-6


def negative(f, floor: float = 0.0, xtol: float = 1e-15) -> tuple[tuple[float, float], ...]:
    """The intervals of ``[0, 2π]`` where ``f`` (a trigonometric polynomial of degree ≤ 2 in its angle) is < 0.

    An interval that wraps past 2π is given as two, one ending at 2π and one
    starting at 0; the ends are located by Brent's method to ``xtol``. Where
    ``f`` dips no lower than ``−floor`` (its rounding, at a tangency) it is
    taken as not negative.
    """
    _, cuts = _cuts(f)
    if not cuts:
        return ((0.0, TAU),) if float(f(0.0)) < -floor else ()
    points = [0.0, *cuts, TAU]
    signs = [float(f(0.5 * (lo + hi))) < -floor for lo, hi in zip(points[:-1], points[1:])]
    out, begin = [], (0.0 if signs[0] else None)
    for k, cut in enumerate(cuts):
        before, after = signs[k], signs[k + 1]
        if before == after:
            continue  # a double root (tangency) or a root the sign does not change at
        x = _polish(f, cut, xtol)
        if after:
            begin = x
        else:
            out.append((0.0 if begin is None else begin, x))
            begin = None
    if begin is not None:
        out.append((begin, TAU))
    return tuple(out)


def touches(f, floor: float) -> tuple[float, ...]:
    """The angles in ``[0, 2π)`` where ``f`` (as in :func:`negative`) comes down to zero, to within ``floor``,
    without going below ``−floor`` about them: its double roots (where a linkage's two assembly modes meet),
    each the root of ``f``'s derivative found by Brent's method.

    >>> [round(x, 12) for x in touches(lambda t: 1 - math.cos(t - 1), 1e-14)]
    [1.0]
    """
    a, cuts = _cuts(f)

    def slope(x):
        return float(np.real(sum(1j * k * a[k] * np.exp(1j * k * x) for k in a)))

    out: list[float] = []
    for cut in cuts:
        lo, hi = cut - 1e-5, cut + 1e-5
        if not (slope(lo) < 0 < slope(hi)):
            continue  # no minimum there
        x = float(brentq(slope, lo, hi, xtol=1e-15, rtol=4 * np.finfo(float).eps)) % TAU
        if abs(float(f(x))) <= floor and float(f(lo)) >= -floor and float(f(hi)) >= -floor and \
                all(abs(math.remainder(x - y, TAU)) > 1e-9 for y in out):
            out.append(x)
    return tuple(sorted(out))


def _cuts(f):
    """``f``'s coefficients ``a_k`` (``f(θ) = Σ a_k e^{ikθ}``, k = −2..2, from eight samples) and the angles
    in ``[0, 2π)`` of the roots of ``z² f`` on (or within :data:`NEAR_CIRCLE` of) the unit circle."""
    t = np.arange(8) * TAU / 8
    c = np.fft.fft(np.array([float(f(x)) for x in t])) / 8
    a = {k: c[k % 8] for k in range(-2, 3)}
    quartic = [a[2], a[1], a[0], a[-1], a[-2]]  # z² f: highest power first
    scale = max(abs(x) for x in quartic)
    if scale == 0:
        return a, []
    poly = np.array(quartic) / scale
    while poly.size > 1 and abs(poly[0]) <= 1e-14:
        poly = poly[1:]
    roots = np.roots(poly) if poly.size > 1 else []
    return a, sorted({float(np.angle(z)) % TAU for z in roots if abs(abs(z) - 1) <= NEAR_CIRCLE})


def _polish(f, x: float, xtol: float) -> float:
    """The sign change of ``f`` next to the candidate root ``x``: bracketed by doubling, then Brent's method."""
    fx = float(f(x))
    if fx == 0.0:
        return x
    step = 1e-12
    while step < 1.0:
        for y in (x - step, x + step):
            fy = float(f(y))
            if fy == 0.0:
                return y
            if (fy < 0) != (fx < 0):
                lo, hi = sorted((x, y))
                return min(max(float(brentq(f, lo, hi, xtol=xtol, rtol=4 * np.finfo(float).eps)), 0.0), TAU)
        step *= 4
    return x


__all__ = ["negative", "touches"]
