"""Mobility: the Grübler–Kutzbach count, for any motion space λ.

``F = λ(n − j − 1) + Σ f`` for ``n`` links and ``j`` joints whose freedoms
add up to ``Σ f`` (seed 002, (3-13); DOMES §7-2 with λ = 3 planar, 6
spatial). With one-freedom joints (revolute, prismatic) ``Σ f = j``, and a
planar chain has ``F = 3(n − 1) − 2j``. Every count of DOF in DOMES-py is
this function; it works on numbers and on numpy arrays alike.

>>> mobility(4, 4)                       # the four-bar
1
>>> mobility(7, 7, space=SPATIAL)         # a spatial 7R loop
1
>>> chain_joints(10, 1)                   # joints of a one-DOF ten-bar chain
13
"""

from __future__ import annotations

from domes.errors import InputError

#: Motion-space DOF λ of a planar and of a spatial mechanism.
PLANAR, SPATIAL = 3, 6


def mobility(links, joints, space: int = PLANAR, freedom=None):
    """``λ(n − j − 1) + Σ f``; ``freedom`` is ``Σ f`` (default ``j``: one-freedom joints).

    >>> mobility(5, 6, freedom=7)     # a geared five-bar: one gear pair (f = 2) among six joints
    1
    """
    if freedom is None:
        freedom = joints
    return space * (links - joints - 1) + freedom


def joints_for(links, dof, space: int = PLANAR):
    """Joints of one freedom that give ``links`` links the mobility ``dof``: ``(λ(n − 1) − F)/(λ − 1)``.

    No checks (arrays welcome); :func:`chain_joints` is the checked form.

    >>> joints_for(6, 1)
    7
    """
    return (space * (links - 1) - dof) // (space - 1)


def chain_joints(links: int, dof: int, space: int = PLANAR) -> int:
    """Joints of a chain of one-freedom joints with ``links`` links and DOF ``dof``.

    >>> chain_joints(5, 1)
    Traceback (most recent call last):
    ...
    domes.errors.InputError: no chain of planar motion with simple revolute joints has 5 links and DOF 1: the joint count (3(n-1) - F)/2 = 11/2 is not an integer; try 4 or 6 links
    """
    check_count("links", links, 1)
    check_count("dof", dof, 0)
    twice = space * (links - 1) - dof
    kind = "chain of planar motion with simple revolute joints" if space == PLANAR else "spatial chain of one-freedom joints"
    if twice % (space - 1):
        raise InputError(
            f"no {kind} has {links} links and DOF {dof}: "
            f"the joint count ({space}(n-1) - F)/{space - 1} = {twice}/{space - 1} is not an integer; "
            f"try {links - 1} or {links + 1} links"
        )
    if twice < 0:
        raise InputError(f"a chain of {links} links cannot have DOF {dof} (at most {space * (links - 1)})")
    return twice // (space - 1)


def chain_loops(links: int, dof: int, space: int = PLANAR) -> int:
    """Independent loops ``L = j − n + 1`` of such a chain (Euler, (3-5)).

    >>> chain_loops(12, 1)
    5
    """
    return chain_joints(links, dof, space) - links + 1


def check_count(name: str, value: object, minimum: int) -> int:
    """``value`` if it is a whole number (not a bool) of at least ``minimum``, else an InputError naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise InputError(f"{name} must be >= {minimum}, got {value}")
    return value
