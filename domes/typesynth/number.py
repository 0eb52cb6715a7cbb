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

from domes.errors import InputError
from domes.model.mobility import PLANAR, SPATIAL, chain_joints, chain_loops, check_count, mobility
from domes.results import Result, Status

__all__ = [
    "LinkAssortment", "NumberSynthesis", "chain_joints", "chain_loops", "count_link_assortments", "link_assortments",
    "number_synthesis",
]


@dataclass(frozen=True)
class NumberSynthesis(Result):
    """The link and joint numbers of a problem (DOMES §7-2); exact, so always COMPLETE.

    >>> result = number_synthesis(dof=1, loops=2)
    >>> result
    NumberSynthesis(dof=1, loops=2, space=3, gear_pairs=0, links=6, joints=7)
    >>> result.success, result.message
    (True, 'W=1, L=2, λ=3, j_G=0: 6 links, 7 joints')
    """

    dof: int
    loops: int
    space: int
    gear_pairs: int
    links: int
    joints: int

    status = Status.COMPLETE

    @property
    def message(self) -> str:
        return f"W={self.dof}, L={self.loops}, λ={self.space}, j_G={self.gear_pairs}: {self.links} links, {self.joints} joints"


def number_synthesis(dof: int, loops: int, space: int = PLANAR, gear_pairs: int = 0) -> NumberSynthesis:
    """Links ``i`` and joints ``j`` for DOF ``W``, loops ``L_ind``, λ and ``j_G``.

    ``space`` is λ: 3 for planar, 6 for spatial mechanisms.

    >>> number_synthesis(dof=1, loops=3).joints
    10
    >>> number_synthesis(dof=1, loops=2, gear_pairs=1)
    NumberSynthesis(dof=1, loops=2, space=3, gear_pairs=1, links=5, joints=6)
    """
    check_count("dof (W)", dof, 0)
    check_count("loops (L_ind)", loops, 0)
    check_count("gear_pairs (j_G)", gear_pairs, 0)
    if space not in (PLANAR, SPATIAL):
        raise InputError(f"space (λ) must be 3 (planar) or 6 (spatial), got {space!r}")
    joints = dof + space * loops - gear_pairs  # W = λ(i − j − 1) + j + j_G with i − j − 1 = −L
    links = joints - loops + 1
    assert mobility(links, joints, space, freedom=joints + gear_pairs) == dof
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
    top, excess = _degrees(links, joints, max_degree)  # excess = Σ (d − 2)·n_d
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


def _degrees(links: int, joints: int, max_degree: int | None) -> tuple[int, int]:
    """The largest link degree allowed and the excess ``2(j − n)`` of a chain of ``links`` and ``joints``."""
    check_count("links", links, 1)
    check_count("joints", joints, 0)
    loops = joints - links + 1
    if loops < 1:
        raise InputError(f"{links} links and {joints} joints form no closed loop (L = j - n + 1 = {loops})")
    top = max(2, loops + 1) if max_degree is None else check_count("max_degree", max_degree, 2)
    return top, 2 * joints - 2 * links


def count_link_assortments(links: int, joints: int, max_degree: int | None = None) -> int:
    """How many assortments :func:`link_assortments` lists, counted without listing them.

    An assortment spreads the excess ``Σ (d − 2)·n_d = 2(j − n)`` over links of
    3 to ``max_degree`` joints: the partitions of the excess into parts of at
    most ``max_degree − 2`` (there are always enough links for the parts).

    >>> count_link_assortments(8, 10), len(link_assortments(8, 10))
    (3, 3)
    >>> count_link_assortments(801, 1200) > 10**20     # 400 loops: far too many to list
    True
    """
    top, excess = _degrees(links, joints, max_degree)
    ways = [1] + [0] * excess  # ways[e]: partitions of e into the parts seen so far
    for part in range(1, top - 1):
        for e in range(part, excess + 1):
            ways[e] += ways[e - part]
    return ways[excess] if excess <= links * (top - 2) else 0
