"""Link units of seed 000 (Wang, Huang, Zhang, Fang 2010, Table 1).

A loop that passes through a link contributes the vector ``∇A`` from the
joint where it enters to the joint where it leaves, the Jacobian unit
``∇J = ∂∇A/∂(link variables)`` and the Jacobian-velocity unit
``∇J̇ = d∇J/dt``. Each function returns ``(A, J, Jd)`` with ``A`` a pair
and ``J``, ``Jd`` tuples of columns (one column per link variable).
``lib`` supplies ``cos`` and ``sin`` (``math`` by default; ``mpmath`` for a
high-precision reference).

The RP2 unit is the corrected one: the printed Table 1 has ``φ̇`` where
``ṡ`` belongs in the first column of ``∇J̇`` (digest of seed 000, §0, §2.5),
which drops half of the Coriolis term ``2ṡφ̇``.

>>> A, J, Jd = rr_unit(2.0, 0.0, 0.0, 1.0)
>>> A, J, Jd
((2.0, 0.0), ((-0.0, 2.0),), ((-2.0, -0.0),))
"""

from __future__ import annotations

import math


def rr_unit(l, alpha, phi, phid, lib=math):
    """Unit of the edge of an R–R (or RRR1) link: ``∇A = l·u(φ + α)``; variable ``φ``.

    >>> rr_unit(1.0, math.pi / 2, 0.0, 0.0)[0][1]
    1.0
    """
    c, s = lib.cos(phi + alpha), lib.sin(phi + alpha)
    return (l * c, l * s), ((-l * s, l * c),), ((-l * phid * c, -l * phid * s),)


def rp1_unit(e, phi, phid, lib=math):
    """Unit of an RP1 link (slider-type P element): ``∇A = e·u(φ + 90°)``; variable ``φ``.

    >>> rp1_unit(2.0, 0.0, 0.0)[0]
    (-0.0, 2.0)
    """
    c, s = lib.cos(phi), lib.sin(phi)
    return (-e * s, e * c), ((-e * c, -e * s),), ((e * phid * s, -e * phid * c),)


def rp2_unit(e, phi, s, phid, sd, lib=math):
    """Unit of an RP2 link (guide-type P element): ``∇A = e·u(φ − 90°) + s·u(φ)``; variables ``(φ, s)``.

    Corrected Table 1: the first column of ``∇J̇`` carries ``ṡ``.

    >>> rp2_unit(0.0, 0.0, 3.0, 1.0, 2.0)[2]
    ((-3.0, 2.0), (-0.0, 1.0))
    """
    c, sn = lib.cos(phi), lib.sin(phi)
    A = (e * sn + s * c, -e * c + s * sn)
    J = ((e * c - s * sn, e * sn + s * c), (c, sn))
    Jd = (
        (-e * phid * sn - s * phid * c - sd * sn, e * phid * c - s * phid * sn + sd * c),
        (-phid * sn, phid * c),
    )
    return A, J, Jd


def reverse(unit):
    """The unit of the same path walked the other way: every part negated (``∇X₂₁ = −∇X₁₂``).

    >>> reverse(rr_unit(1.0, 0.0, 0.0, 0.0))[0]
    (-1.0, -0.0)
    """
    A, J, Jd = unit
    return (
        (-A[0], -A[1]),
        tuple((-a, -b) for a, b in J),
        tuple((-a, -b) for a, b in Jd),
    )
