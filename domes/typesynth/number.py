"""Number synthesis: links and joints from the structural attributes.

DOMES (seed 002, §7-2; digest part 4.2) solves the mobility equation
``W = λ(i − j − 1) + Σ f_k`` together with ``L_ind = j − i + 1`` for the
number of links ``i`` and joints ``j``, counting a gear pair as a 2-DOF
joint (``Σ f_k = j + j_G``)::

    i = W + (λ − 1)·L_ind − j_G + 1
    j = W + λ·L_ind − j_G

Link assortments (§3-2-I.3, Table 3-1) are the ways of splitting the links
into binary, ternary, ... links: ``Σ n_d = i`` and ``Σ d·n_d = 2j``.
"""

from __future__ import annotations

from dataclasses import dataclass

from domes.errors import DomesError, InputError

#: Motion-space DOF λ of a planar and of a spatial mechanism.
PLANAR, SPATIAL = 3, 6


@dataclass(frozen=True)
class NumberSynthesis:
    """The link and joint numbers of a problem (DOMES §7-2).

    >>> number_synthesis(dof=1, loops=2)
    NumberSynthesis(dof=1, loops=2, space=3, gear_pairs=0, links=6, joints=7)
    """

    dof: int
    loops: int
    space: int
    gear_pairs: int
    links: int
    joints: int


def _check_int(name: str, value: object, minimum: int) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(f"{name} must be an integer, got {value!r}")
    if value < minimum:
        raise InputError(f"{name} must be >= {minimum}, got {value}")
    return value


def number_synthesis(dof: int, loops: int, space: int = PLANAR, gear_pairs: int = 0) -> NumberSynthesis:
    """Links ``i`` and joints ``j`` for DOF ``W``, loops ``L_ind``, λ and ``j_G``.

    ``space`` is λ: 3 for planar, 6 for spatial mechanisms.

    >>> number_synthesis(dof=1, loops=3).joints
    10
    >>> number_synthesis(dof=1, loops=2, gear_pairs=1)
    NumberSynthesis(dof=1, loops=2, space=3, gear_pairs=1, links=5, joints=6)
    """
    _check_int("dof (W)", dof, 0)
    _check_int("loops (L_ind)", loops, 0)
    _check_int("gear_pairs (j_G)", gear_pairs, 0)
    if space not in (PLANAR, SPATIAL):
        raise InputError(f"space (λ) must be 3 (planar) or 6 (spatial), got {space!r}")
    links = dof + (space - 1) * loops - gear_pairs + 1
    joints = dof + space * loops - gear_pairs
    if gear_pairs > joints:
        raise InputError(
            f"{gear_pairs} gear pairs cannot fit in a chain of {joints} joints "
            f"(W={dof}, L={loops}, λ={space}); use fewer gear pairs or more loops"
        )
    if links < 2 and (loops or joints):
        raise InputError(
            f"W={dof}, L={loops}, λ={space}, j_G={gear_pairs} gives {links} links: "
            "no mechanism has fewer than 2 links; use fewer gear pairs or more loops"
        )
    return NumberSynthesis(dof, loops, space, gear_pairs, links, joints)


def chain_joints(links: int, dof: int) -> int:
    """Joints of a planar chain of revolute joints: ``j = (3(n − 1) − F)/2``.

    >>> chain_joints(10, 1)
    13
    >>> chain_joints(5, 1)
    Traceback (most recent call last):
    ...
    domes.errors.InputError: no planar chain of simple revolute joints has 5 links and DOF 1: the joint count (3(n-1) - F)/2 = 11/2 is not an integer; try 4 or 6 links
    """
    _check_int("links", links, 1)
    _check_int("dof", dof, 0)
    twice = 3 * (links - 1) - dof
    if twice % 2:
        raise InputError(
            f"no planar chain of simple revolute joints has {links} links and DOF {dof}: "
            f"the joint count (3(n-1) - F)/2 = {twice}/2 is not an integer; "
            f"try {links - 1} or {links + 1} links"
        )
    if twice < 0:
        raise InputError(f"a chain of {links} links cannot have DOF {dof} (at most {3 * (links - 1)})")
    return twice // 2


def chain_loops(links: int, dof: int) -> int:
    """Independent loops ``L = j − n + 1`` of a planar revolute chain.

    >>> chain_loops(12, 1)
    5
    """
    return chain_joints(links, dof) - links + 1


@dataclass(frozen=True)
class LinkAssortment:
    """How many links carry 2, 3, 4, ... joints (``n_d`` of Table 3-1).

    >>> a = LinkAssortment({2: 4, 3: 2})
    >>> a.links, a.joints, a.multi_links, a.branches
    (6, 7, 2, 3)
    """

    counts: dict[int, int]

    @property
    def links(self) -> int:
        """``n = Σ n_d``."""
        return sum(self.counts.values())

    @property
    def joints(self) -> int:
        """``m = Σ d·n_d / 2``."""
        return sum(d * k for d, k in self.counts.items()) // 2

    @property
    def multi_links(self) -> int:
        """``b``: links with three or more joints (vertices of the contracted graph)."""
        return sum(k for d, k in self.counts.items() if d >= 3)

    @property
    def branches(self) -> int:
        """``l``: edges of the contracted graph, ``2l = Σ_{d≥3} d·n_d`` (3-16)."""
        return sum(d * k for d, k in self.counts.items() if d >= 3) // 2

    def as_tuple(self) -> tuple[int, ...]:
        """``(n_2, n_3, ..., n_dmax)``."""
        top = max(self.counts, default=2)
        return tuple(self.counts.get(d, 0) for d in range(2, top + 1))


def link_assortments(links: int, joints: int, max_degree: int | None = None) -> list[LinkAssortment]:
    """Every assortment ``{d: n_d}`` with ``Σ n_d = links``, ``Σ d·n_d = 2·joints``.

    Each link carries at least two joints. ``max_degree`` defaults to
    ``L + 1`` (the largest link of a chain with ``L`` loops and no cut link,
    §3-2-I.3), with at least 2. Assortments are listed with the most binary
    links first; zero counts are left out.

    >>> [a.as_tuple() for a in link_assortments(8, 10)]
    [(6, 0, 2), (5, 2, 1), (4, 4)]
    """
    _check_int("links", links, 1)
    _check_int("joints", joints, 0)
    loops = joints - links + 1
    if loops < 1:
        raise InputError(f"{links} links and {joints} joints form no closed loop (L = j - n + 1 = {loops})")
    top = max(2, loops + 1) if max_degree is None else _check_int("max_degree", max_degree, 2)
    excess = 2 * joints - 2 * links  # Σ (d − 2)·n_d
    found: list[LinkAssortment] = []

    def extend(degree: int, left_links: int, left_excess: int, counts: dict[int, int]) -> None:
        if left_excess == 0:
            found.append(LinkAssortment({2: left_links, **counts} if left_links else dict(counts)))
            return
        if degree < 3:
            return
        for k in range(min(left_links, left_excess // (degree - 2)), -1, -1):
            if k:
                counts[degree] = k
            extend(degree - 1, left_links - k, left_excess - k * (degree - 2), counts)
            counts.pop(degree, None)

    extend(top, links, excess, {})
    found = [LinkAssortment(dict(sorted(a.counts.items()))) for a in found]
    found.sort(key=lambda a: tuple(-a.counts.get(d, 0) for d in range(2, top + 1)))
    return found
