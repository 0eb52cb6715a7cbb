"""Active pairs: which joints can drive a chain together, and the DOF type they give (seed 002 §3-2-I.5).

**Active-pair existence criterion** (主动副存在准则, §3-2-I.5 (1)): ``W``
pairs of a chain of DOF ``W`` can be its inputs together exactly when, with
all of them rigidified at once, every loop keeps its number ``ξ`` of
independent displacement equations; equivalently, each chosen pair takes
exactly one DOF away. Fig. 3-19 is a 2-DOF chain whose pairs A and C cannot
both be active: with both rigidified, one loop's ``ξ`` drops to 2 while
another part of the chain is still free.

Each link is a body with 3 freedoms and each joint a number of constraints
(*bars*): a revolute or rolling pair is a pin (2 bars through its point), a
prismatic pair a rotation lock and a bar across the slide, a gear or cam pair
a bar along the contact normal, a spring, cylinder or force none (it stands
for a dyad, Table 3-5). Driving a joint adds one bar: a revolute or slider
becomes rigid, a cylinder keeps its length. The chosen pairs can be active
exactly when the bars are *independent* (none is implied by the others: no
over-constrained sub-chain, every loop keeps its ``ξ``) and leave no
freedom (``3(n − 1)`` independent bars). Both are generic answers, true for
almost every choice of dimensions, as the book's counting is:

* without prismatic pairs, the pebble game (Jacobs and Hendrickson; Lee and
  Streinu's ``(k, l) = (3, 3)`` form, as :mod:`domes.model.pebble` plays
  ``(3, 4)`` for sub-chain counts) decides in ``O(n·e)`` steps: a set of
  bars is independent when every set ``S`` of links holds at most
  ``3(|S| − 1)`` of them;
* a slider is a pin at infinity, so sliders are not in general position (a
  loop of prismatic pairs only has ``ξ = 2``, (3-11), and so has a loop of
  sliders between rigid parts), which no count sees: with a prismatic pair
  the rank of the constraint Jacobian at random integer dimensions,
  modulo a 61-bit prime (exact arithmetic), decides.

``tests/language/test_active_pair_criterion.py`` compares the answer with the rank of
the loop-closure Jacobian (another formulation, in floating point) for every
pair of joints of the atlas chains of 7 and 9 links and DOF 2, every three
joints of those of 8 links and DOF 3 (8 links give no DOF 2), and chains
with sliders.

**DOF types** (§3-2-I.5 (2)), for pairs that can be active:

* ``fractionated``: the chain has a cut link, and the active pairs lie in
  two or more of the loop blocks it joins (each block then has its own DOF);
* ``partial``: some driven link (neither the ground nor an input link, i.e.
  a link jointed to the ground by an active pair) moves with fewer than all
  ``W`` inputs, the others held;
* ``full``: every driven link moves with each input. A one-DOF chain is
  always ``full`` (:attr:`domes.model.Chain.dof_type` calls it ``total``).

A two-DOF chain of seven links and pairs A-H (the book's letters; the
drawing of Fig. 3-19 is lost, see the tests): the four-bar loop of the
links 0, 1, 2, 3 (pairs A, B, C, D) and a branch of three binary links 4, 5,
6 (pairs E, F, G, H) from link 0 to link 2.

>>> from domes.model import LabelledChain
>>> fig = LabelledChain.from_named("Fig. 3-19", [("0", ["ground"]), ("1", []), ("2", []), ("3", []),
...     ("4", []), ("5", []), ("6", [])], [("A", "0", "1", "R"), ("B", "1", "2", "R"), ("C", "2", "3", "R"),
...     ("D", "3", "0", "R"), ("E", "0", "4", "R"), ("F", "4", "5", "R"), ("G", "5", "6", "R"), ("H", "6", "2", "R")])
>>> print(active_pairs(fig, [(0, 1), (2, 3)]).reason)
A and C cannot both be active: with them driven, links 0, 1, 2, 3 are over-constrained and 1 DOF is left
>>> result = active_pairs(fig, [(0, 1), (0, 4)])
>>> result.feasible, result.dof_type, result.moved_by
(True, 'partial', ((1, 2, 3, 5, 6), (4, 5, 6)))

A chain without a ground link (a plain :class:`~domes.model.chain.Chain` of
the atlas) has a DOF type *whatever link is the ground*: ``partial`` when
some choice of ground makes it partial, i.e. two links not jointed by an
active pair keep their relative position while one input moves.
:func:`active_sets` tabulates every set of ``W`` joints of an atlas chain,
up to its automorphisms, with the sub-chain counts: the chosen joints can be
active together exactly when every set ``S`` of links keeps
``F(S) = 3(|S| − 1) − 2e(S)`` at least the number of chosen joints inside
it, and the DOF is partial exactly when, besides, some set of three or more
links has ``F(S)`` equal to the chosen joints inside it while some chosen
joint lies outside (those links are then rigid with that input held).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations
from typing import Iterable

import networkx as nx
import numpy as np

from domes.errors import InputError
from domes.model.labelled import LabelledChain
from domes.model.pebble import PebbleGame
from domes.model.rigidity import MAX_LINKS, subset_dof_table, subset_sizes

#: Bars of each joint type: a revolute or rolling pair is a pin (2 bars), a prismatic pair a rotation lock and a
#: bar across the slide, a gear or cam pair one bar along the contact normal, and a spring, cylinder or force
#: none (Table 3-5: it stands for a dyad).
BARS: dict[str, int] = {"R": 2, "O": 2, "P": 2, "G": 1, "C": 1, "S": 0, "H": 0, "F": 0, "Fp": 0, "Fr": 0}
#: What driving a joint of the type adds: a revolute or rolling pair becomes rigid, a slider stops, a cylinder,
#: spring or force keeps its length (one bar each). A gear or cam pair is not driven.
DRIVEN_BAR: dict[str, str] = {"R": "lock", "O": "lock", "P": "stop", "S": "length", "H": "length", "F": "length",
                              "Fp": "length", "Fr": "length"}
#: The DOF types of §3-2-I.5 (2).
DOF_TYPES = ("full", "partial", "fractionated")


@dataclass(frozen=True)
class ActivePairs:
    """Whether the ``joints`` (indices into ``chain.edges``) of a chain can be driven together.

    ``dof`` is the chain's DOF by the count (Grübler, with the bars of each
    joint type); ``remaining`` the DOF left with the joints driven (0 when
    they determine the motion); ``over_constrained`` the links of the first
    set found with more bars than its freedoms (empty if none);
    ``feasible``: the joints are independent and leave no DOF. For feasible
    joints, ``dof_type`` (:data:`DOF_TYPES`; ``None`` for a chain of DOF 0
    or with two or more ground links; without a ground link, the type
    whatever link is the ground) and ``moved_by`` (per driven joint, the
    links that move with it while the others are held; empty without a
    single ground link) say how the inputs share the links. ``reason`` says
    it in words.
    """

    joints: tuple[int, ...]
    names: tuple[str, ...]
    dof: int
    remaining: int
    over_constrained: tuple[int, ...]
    before_driving: bool
    dof_type: str | None
    moved_by: tuple[tuple[int, ...], ...]
    reason: str

    @property
    def feasible(self) -> bool:
        return not self.over_constrained and self.remaining == 0

    @property
    def independent(self) -> bool:
        """Each driven joint takes exactly one DOF away (there may be DOF left)."""
        return not self.over_constrained


def input_joints(chain, role: str = "input", ground: str = "ground") -> tuple[int, ...]:
    """The joints a labelled chain is driven by: between its ground and each link with role ``role``.

    The rule of :func:`domes.model.mechanism.from_labelled`; an InputError if
    there is not exactly one ground link or an input link is not jointed to it.

    >>> from domes.model import LabelledChain
    >>> input_joints(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)], roles={0: {"ground"}, 1: {"input"}}))
    (0,)
    """
    grounds = chain.links_with_role(ground)
    if len(grounds) != 1:
        found = "no link" if not grounds else f"links {', '.join(map(chain.link_name, grounds))}"
        raise InputError(f"the input pairs need exactly one link representing “{ground}”; {found} does")
    g = grounds[0]
    index = {e: i for i, e in enumerate(chain.edges)}
    out = []
    for k in chain.links_with_role(role):
        if k == g:
            raise InputError(f"link {chain.link_name(k)} represents both “{role}” and “{ground}”")
        i = index.get((min(g, k), max(g, k)))
        if i is None:
            raise InputError(f"link {chain.link_name(k)} (“{role}”) is not jointed to the ground "
                             f"{chain.link_name(g)}: no input pair")
        out.append(i)
    return tuple(sorted(out))


def _joint_indices(chain, joints: Iterable) -> tuple[int, ...]:
    index = {e: i for i, e in enumerate(chain.edges)}
    out = set()
    for j in joints:
        if isinstance(j, int) and not isinstance(j, bool):
            if not 0 <= j < len(chain.edges):
                raise InputError(f"joint {j} is not one of the joints 0..{len(chain.edges) - 1}")
            out.add(j)
            continue
        try:
            u, v = (int(x) for x in j)
        except (TypeError, ValueError):
            raise InputError(f"{j!r} is not a joint: give a joint index or a pair of links (u, v)") from None
        i = index.get((min(u, v), max(u, v)))
        if i is None:
            raise InputError(f"links {u} and {v} are not jointed")
        out.add(i)
    return tuple(sorted(out))


#: The prime of the exact rank test (arithmetic modulo a Mersenne prime on integer dimensions).
PRIME = (1 << 61) - 1
#: Seed of the random integer dimensions of the rank test (fixed: the answer is the same on every run).
SEED = 3219


def _bars(chain, driven: Iterable[int]) -> tuple[list[tuple[int, int, str, int]], list[tuple[int, int, str, int]]]:
    """``(u, v, kind, joint)`` bars: the joints' own, then those the driven joints add.

    ``kind``: ``x``/``y`` a pin's two bars, ``lock`` a rotation lock, ``slide`` the bar across a slider,
    ``normal`` a contact normal, ``stop`` the bar that stops a slider, ``length`` a force member's length.
    """
    own = {"R": ("x", "y"), "O": ("x", "y"), "P": ("lock", "slide"), "G": ("normal",), "C": ("normal",),
           "S": (), "H": (), "F": (), "Fp": (), "Fr": ()}
    base, extra = [], []
    for i, ((u, v), t) in enumerate(zip(chain.edges, chain.joint_types)):
        if t not in BARS:
            raise InputError(f"joint {u}-{v} has type {t!r}: the active-pair criterion is for planar chains "
                             f"(joint types {' '.join(BARS)})")
        base += [(u, v, kind, i) for kind in own[t]]
    for i in driven:
        (u, v), t = chain.edges[i], chain.joint_types[i]
        if t not in DRIVEN_BAR:
            raise InputError(f"joint {chain.joint_name(i)} is a {'gear' if t == 'G' else 'cam'} pair: "
                             "a higher pair is not driven as an active pair")
        extra.append((u, v, {"R": "lock", "O": "lock", "P": "stop"}.get(t, "length"), i))
    return base, extra


class _Pebbles(PebbleGame):
    """The (3, 3) pebble game on bars: each link a body of 3 freedoms, each bar one constraint, all in general
    position."""

    def __init__(self, n: int):
        super().__init__(n, k=3, l=3)

    def add(self, bar) -> set[int] | None:
        """Accept the bar if it is independent of those accepted; else the links of the set it over-constrains."""
        return super().add(bar[0], bar[1])


class _Rank:
    """The constraint Jacobian at random integer dimensions, row-reduced modulo :data:`PRIME` as rows come.

    For chains with prismatic pairs: a slider is a pin at infinity, so its
    bars are not in general position (a loop of sliders only has ``ξ = 2``,
    (3-11)), which the pebble game cannot see. Each link ``u`` has columns
    ``ω, t_x, t_y``; a bar with normal ``m`` at the point ``p`` is the row
    ``m·(v_u(p) − v_v(p))`` with ``v(p) = t + ω × p``; a rotation lock is
    ``ω_u − ω_v``.
    """

    def __init__(self, n: int, geometry):
        self.n = n
        self.geometry = geometry
        self.pivots: dict[int, list[int]] = {}

    def row(self, bar) -> list[int]:
        u, v, kind, key = bar
        r = [0] * (3 * self.n)
        if kind == "lock":
            r[3 * u], r[3 * v] = 1, -1
            return r
        p, d, m = self.geometry(key)
        normal = {"x": (1, 0), "y": (0, 1), "slide": (-d[1], d[0]), "stop": d}.get(kind, m)
        arm = -normal[0] * p[1] + normal[1] * p[0]
        for link, sign in ((u, 1), (v, -1)):
            r[3 * link] += sign * arm
            r[3 * link + 1] += sign * normal[0]
            r[3 * link + 2] += sign * normal[1]
        return r

    def add(self, bar) -> bool:
        """Reduce the bar's row by the rows kept; keep it (True) if something is left."""
        r = [x % PRIME for x in self.row(bar)]
        for col, pivot in self.pivots.items():
            if r[col]:
                f = r[col]
                r = [(a - f * b) % PRIME for a, b in zip(r, pivot)]
        for col, x in enumerate(r):
            if x:
                inv = pow(x, PRIME - 2, PRIME)
                r = [a * inv % PRIME for a in r]
                for other in self.pivots.values():
                    if other[col]:
                        f = other[col]
                        other[:] = [(a - f * b) % PRIME for a, b in zip(other, r)]
                self.pivots[col] = r
                return True
        return False


def _geometry(chain):
    """Random integer dimensions, the same for a key on every call: a point, a slide direction, a normal."""
    import random

    rng = random.Random(SEED)
    table: dict = {}

    def geometry(key):
        if key not in table:
            table[key] = tuple((rng.randint(-10**6, 10**6), rng.randint(-10**6, 10**6)) for _ in range(3))
        return table[key]

    return geometry


def _play(chain, bars, locate: bool = True) -> tuple[int, set[int] | None, int]:
    """``(bars accepted, an over-constrained set of links, index of the first bar found dependent)``.

    The pebble game decides, unless a prismatic pair is present: then the rank test, which finds a smallest
    over-constrained set by deleting links (only if ``locate``; else the set is all the links).
    """
    n = chain.n
    if "P" not in chain.joint_types:
        game = _Pebbles(n)
        accepted, first, where = 0, None, -1
        for k, bar in enumerate(bars):
            bad = game.add(bar)
            if bad is None:
                accepted += 1
            elif first is None:
                first, where = bad, k
        return accepted, first, where
    geometry = _geometry(chain)
    system = _Rank(n, geometry)
    kept = [system.add(bar) for bar in bars]
    accepted = sum(kept)
    if all(kept):
        return accepted, None, -1
    where = kept.index(False)
    if not locate:
        return accepted, set(range(n)), where

    def dependent(links: set[int]) -> bool:
        sub = _Rank(n, geometry)
        inside = [b for b in bars if b[0] in links and b[1] in links]
        return not all(sub.add(b) for b in inside)

    links = set(range(n))
    for x in range(n):                       # a smallest over-constrained set, by deletion
        if dependent(links - {x}):
            links.discard(x)
    return accepted, links, where


def _moves(chain, bars, ground: int) -> tuple[int, ...]:
    """The links not held rigidly to the ground by independent ``bars``: one more bar to the ground is free."""
    return tuple(x for x in range(chain.n)
                 if x != ground and _play(chain, bars + [(ground, x, "normal", ("test", x))], False)[1] is None)


def _names(chain, joints) -> str:
    names = [chain.joint_name(i) for i in joints]
    if len(names) <= 1:
        return "".join(names)
    return ", ".join(names[:-1]) + " and " + names[-1]


def _links(chain, links) -> str:
    links = sorted(links)
    return ("link " if len(links) == 1 else "links ") + ", ".join(map(chain.link_name, links))


def _labelled(chain):
    """A plain :class:`~domes.model.chain.Chain` as a labelled chain of revolute joints without roles."""
    if hasattr(chain, "joint_types"):
        return chain
    try:
        n, edges = chain.n, chain.edges
    except AttributeError:
        raise InputError(f"{chain!r} is not a chain: give a Chain or a LabelledChain") from None
    return LabelledChain.build(n, edges)


def active_pairs(chain, joints: Iterable | None = None, *, role: str = "input", types: bool = True) -> ActivePairs:
    """Whether ``joints`` (indices into ``chain.edges`` or link pairs; default :func:`input_joints`) of a
    :class:`~domes.model.LabelledChain` or a plain :class:`~domes.model.Chain` (revolute joints, no ground)
    can be its active pairs together, and the DOF type they give (``types=False``: not worked out, ``dof_type``
    None and ``moved_by`` empty; on a chain without a ground the type takes one pebble game per link).

    >>> from domes.model import LabelledChain
    >>> five_bar = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (4, 0)],
    ...                                roles={0: {"ground"}, 1: {"input"}, 4: {"input"}})
    >>> r = active_pairs(five_bar)
    >>> r.feasible, r.dof, r.dof_type
    (True, 2, 'full')
    >>> active_pairs(five_bar, [(0, 1)]).reason
    '0-1 leaves 1 of the 2 DOF: the chain needs 2 active pairs'
    >>> from domes.model import Chain
    >>> active_pairs(Chain.from_graph6("Dhc"), [(0, 1), (0, 4)]).dof_type     # the five-bar, no ground
    'full'
    """
    chain = _labelled(chain)
    chosen = input_joints(chain, role) if joints is None else _joint_indices(chain, joints)
    base, extra = _bars(chain, chosen)
    n = chain.n
    dof = 3 * (n - 1) - len(base)
    accepted, bad, where = _play(chain, base + extra)
    remaining = 3 * (n - 1) - accepted
    before = bad is not None and where < len(base)
    over = tuple(sorted(bad)) if bad is not None else ()
    names = tuple(chain.joint_name(i) for i in chosen)
    grounds = chain.links_with_role("ground")
    dof_type, moved = None, ()
    said = _names(chain, chosen) or "no pair"
    if before:
        reason = f"{_links(chain, over)} are over-constrained before any pair is driven"
    elif bad is not None:
        verb = "cannot all be" if len(chosen) > 2 else "cannot both be" if len(chosen) == 2 else "cannot be"
        left = f" and {remaining} DOF {'is' if remaining == 1 else 'are'} left" if remaining else ""
        them = "them" if len(chosen) > 1 else "it"
        reason = f"{said} {verb} active: with {them} driven, {_links(chain, over)} are over-constrained{left}"
    elif not chosen:
        reason = (f"no pair is driven: the chain needs {dof} active pair{'s' if dof != 1 else ''}" if remaining
                  else f"no pair is driven, and none is needed (DOF {dof})")
    elif remaining:
        reason = (f"{said} {'leaves' if len(chosen) == 1 else 'leave'} {remaining} of the {dof} DOF: "
                  f"the chain needs {dof} active pair{'s' if dof != 1 else ''}")
    else:
        if types and dof >= 1 and len(grounds) == 1:
            dof_type, moved = _dof_type(chain, chosen, base, extra, grounds[0])
        elif types and dof >= 1 and not grounds:
            dof_type = _dof_type_any_ground(chain, chosen, base, extra)
        kind = f", {dof_type} DOF" if dof_type else ""
        reason = f"{said} can drive the chain together (DOF {dof}{kind})"
    return ActivePairs(chosen, names, dof, remaining, over, before, dof_type, moved, reason)


def _dof_type(chain, chosen, base, extra, ground: int) -> tuple[str, tuple[tuple[int, ...], ...]]:
    n = chain.n
    moved = tuple(_moves(chain, base + extra[:k] + extra[k + 1:], ground) for k in range(len(chosen)))
    graph = nx.Graph()
    graph.add_nodes_from(range(n))
    graph.add_edges_from(e for e, t in zip(chain.edges, chain.joint_types) if BARS[t])
    block_of = {}
    for b, block in enumerate(nx.biconnected_component_edges(graph)):
        if len(block) >= 3:
            for u, v in block:
                block_of[(min(u, v), max(u, v))] = b
    if len({block_of[chain.edges[i]] for i in chosen if chain.edges[i] in block_of}) >= 2:
        return "fractionated", moved
    inputs = {ground} | {v for i in chosen for v in chain.edges[i] if ground in chain.edges[i]}
    counts = [0] * n
    for links in moved:
        for x in links:
            counts[x] += 1
    driven = [x for x in range(n) if x not in inputs and counts[x]]
    if any(counts[x] < len(chosen) for x in driven):
        return "partial", moved
    return "full", moved


def _dof_type_any_ground(chain, chosen, base, extra) -> str:
    """The DOF type whatever link is the ground: ``partial`` if some ground makes it so."""
    types = {_dof_type(chain, chosen, base, extra, g)[0] for g in range(chain.n)}
    return next(t for t in ("fractionated", "partial", "full") if t in types)


def can_be_active(chain, joints: Iterable | None = None, *, role: str = "input") -> bool:
    """The predicate of :func:`active_pairs`: the joints can drive the chain together.

    >>> from domes.model import LabelledChain
    >>> can_be_active(LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)]), [(0, 1)])
    True
    """
    return active_pairs(chain, joints, role=role, types=False).feasible


@dataclass(frozen=True)
class JointSet:
    """One class of sets of joints under the chain's automorphisms: ``joints`` (indices into ``chain.edges``,
    the smallest set of the class), ``edges`` (the same as link pairs), ``size`` (sets in the class) and
    ``dof_type`` (:data:`DOF_TYPES`, ``None`` when the joints cannot be active together)."""

    joints: tuple[int, ...]
    edges: tuple[tuple[int, int], ...]
    size: int
    dof_type: str | None

    @property
    def feasible(self) -> bool:
        return self.dof_type is not None


@dataclass(frozen=True)
class ActiveSets:
    """Every set of ``dof`` joints of a chain, as :class:`JointSet` classes under its automorphisms."""

    dof: int
    classes: tuple[JointSet, ...]

    def counts(self, labelled: bool = False) -> dict[str, int]:
        """``sets``, ``active`` (can be active together) and how many give each DOF type: classes, or with
        ``labelled`` every set of joints."""
        weight = (lambda c: c.size) if labelled else (lambda c: 1)
        out = {"sets": sum(map(weight, self.classes)),
               "active": sum(weight(c) for c in self.classes if c.feasible)}
        for t in DOF_TYPES:
            out[t] = sum(weight(c) for c in self.classes if c.dof_type == t)
        return out

    def summary(self) -> str:
        """One line: ``active a/s (full f, partial p, fractionated r)`` over the classes."""
        c = self.counts()
        return (f"active {c['active']}/{c['sets']} (full {c['full']}, partial {c['partial']}, "
                f"fractionated {c['fractionated']})")

    def to_dict(self) -> dict:
        """Plain data: the counts of classes and of sets, and every class."""
        return {"dof": self.dof, "classes": self.counts(), "labelled": self.counts(labelled=True),
                "joint_sets": [{"joints": [list(e) for e in c.edges], "size": c.size, "dof_type": c.dof_type}
                               for c in self.classes]}


def _set_classes(chain, sets: list[tuple[int, ...]]) -> dict[tuple[int, ...], list[tuple[int, ...]]]:
    """The sets of joints grouped by the chain's automorphisms, keyed by each group's smallest set."""
    index = {e: i for i, e in enumerate(chain.edges)}
    parent = {s: s for s in sets}

    def find(x):
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for perm in chain.automorphisms.generators:
        image_of = [index[(min(perm[u], perm[v]), max(perm[u], perm[v]))] for u, v in chain.edges]
        for s in sets:
            a, b = find(s), find(tuple(sorted(image_of[i] for i in s)))
            if a != b:
                parent[max(a, b)] = min(a, b)
    classes: dict[tuple[int, ...], list[tuple[int, ...]]] = {}
    for s in sets:
        classes.setdefault(find(s), []).append(s)
    return classes


def active_sets(chain) -> ActiveSets:
    """Every set of ``W`` joints of a chain of DOF ``W ≥ 1`` (revolute joints, no rigid sub-chain): whether
    they can be active together and the DOF type they give, whatever link is the ground (see the module).

    Sets related by an automorphism of the chain form one :class:`JointSet` class; ``counts()`` counts
    classes, ``counts(labelled=True)`` sets.

    >>> from domes.model import Chain
    >>> fig_3_19 = Chain(7, [(0, 1), (1, 2), (2, 3), (0, 3), (0, 4), (4, 5), (5, 6), (2, 6)])
    >>> found = active_sets(fig_3_19)
    >>> found.counts()
    {'sets': 11, 'active': 8, 'full': 4, 'partial': 4, 'fractionated': 0}
    >>> found.counts(labelled=True)["sets"], found.counts(labelled=True)["active"]
    (28, 22)
    >>> next(c for c in found.classes if c.edges == ((0, 1), (2, 3))).dof_type is None   # A and C
    True
    """
    if isinstance(chain, LabelledChain):
        if set(chain.joint_types) - {"R"}:
            raise InputError("active_sets counts chains of revolute joints; this chain has joint types "
                             f"{' '.join(sorted(set(chain.joint_types) - {'R'}))}: ask active_pairs per set")
        from domes.model.chain import Chain

        chain = Chain(chain.n, chain.edges)
    if not hasattr(chain, "automorphisms"):
        raise InputError(f"{chain!r} is not a chain: give a Chain (e.g. Chain.from_graph6)")
    n, edges, dof = chain.n, chain.edges, chain.dof
    if dof < 1:
        raise InputError(f"active pairs are for chains of DOF 1 or more; this chain has DOF {dof}")
    if n > MAX_LINKS:
        raise InputError(f"active_sets tabulates the sub-chains of at most {MAX_LINKS} links, got {n}")
    if not chain.is_connected:
        raise InputError("the chain is not connected: active pairs are for one connected chain")
    rigid = chain.rigid_subchain
    if rigid is not None:
        raise InputError(f"links {', '.join(map(str, rigid))} form a rigid or over-constrained sub-chain: "
                         "no DOF types without it")
    free = subset_dof_table(n, edges)                     # F(S) of every set of links; only F(S) <= W can bind
    near = np.flatnonzero(free <= dof)
    near = near[near > 0]
    free, sizes, masks = free[near], subset_sizes(n)[near], near.astype(np.int64)
    inside = np.array([(masks >> u) & (masks >> v) & 1 for u, v in edges], dtype=np.int8)
    loose = (sizes >= 3) & (masks != (1 << n) - 1)         # proper sets of three or more links
    graph = chain.to_networkx()
    block_of = {}
    for b, block in enumerate(nx.biconnected_component_edges(graph)):
        if len(block) >= 3:
            for u, v in block:
                block_of[(min(u, v), max(u, v))] = b
    classes = _set_classes(chain, list(combinations(range(len(edges)), dof)))
    reps = sorted(classes)
    types: list[str | None] = []
    chunk = max(1, (1 << 22) >> n)
    for start in range(0, len(reps), chunk):
        part = np.array(reps[start:start + chunk], dtype=np.int64)
        count = inside[part].sum(axis=1, dtype=np.int16)          # chosen joints inside each set of links
        feasible = (count <= free).all(axis=1)
        partial = ((count == free) & (count < dof) & loose).any(axis=1)
        for rep, ok, part_ in zip(reps[start:start + chunk], feasible, partial):
            if not ok:
                types.append(None)
            elif len({block_of.get(edges[i]) for i in rep} - {None}) >= 2:
                types.append("fractionated")
            else:
                types.append("partial" if part_ else "full")
    return ActiveSets(dof, tuple(JointSet(rep, tuple(edges[i] for i in rep), len(classes[rep]), t)
                                 for rep, t in zip(reps, types)))


__all__ = ["BARS", "DOF_TYPES", "DRIVEN_BAR", "ActivePairs", "ActiveSets", "JointSet", "active_pairs", "active_sets",
           "can_be_active", "input_joints"]
