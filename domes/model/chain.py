"""A kinematic chain and its structural properties (§3-1-II, §3-2-I).

>>> c = Chain.from_networkx(nx.cycle_graph(4))
>>> c.links, c.joints, c.loops, c.dof, c.dof_type
(4, 4, 1, 1, 'total')
>>> c.automorphisms.order, c.link_orbits
(8, [[0, 1, 2, 3]])
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any, Iterable

import networkx as nx
import numpy as np

from domes.errors import InputError
from domes.model.canon import Automorphisms, automorphisms, canonical_form
from domes.model.charpoly import characteristic_polynomial
from domes.model.mobility import joints_for, mobility
from domes.model.rigidity import rigid_subchain, subset_dof_table, subset_sizes
from domes.model.structural import structural_number
from domes.model.topology import Topology

Edge = tuple[int, int]


@dataclass(frozen=True)
class Branch:
    """A branch of the contracted graph: the binary links between two multi-joint links."""

    ends: tuple[int, int]
    binaries: tuple[int, ...]


@dataclass(frozen=True, eq=False)
class Chain:
    """A kinematic chain of planar motion with simple revolute joints: links ``0..n−1``, joints as link pairs.

    *Planar* is the motion (λ = 3), not the graph: some chains' graphs are not
    planar (11 of the 230 one-DOF ten-bar chains, :attr:`graph_planar`).

    Equality and hashing are by isomorphism class (nauty certificate).
    """

    n: int
    edges: tuple[Edge, ...]

    def __post_init__(self) -> None:
        seen: set[Edge] = set()
        clean = []
        for index, edge in enumerate(self.edges):
            try:
                u, v = (int(x) for x in edge)
            except (TypeError, ValueError):
                raise InputError(f"joint {index}: {edge!r} is not a pair of link numbers") from None
            if not (0 <= u < self.n and 0 <= v < self.n):
                raise InputError(f"joint {index}: ({u}, {v}) names a link outside 0..{self.n - 1}")
            if u == v:
                raise InputError(f"joint {index}: link {u} cannot be jointed to itself")
            key = (min(u, v), max(u, v))
            if key in seen:
                raise InputError(f"joint {index}: links {key[0]} and {key[1]} are already jointed (simple joints only)")
            seen.add(key)
            clean.append(key)
        object.__setattr__(self, "edges", tuple(sorted(clean)))

    # -- construction and export -------------------------------------------

    @classmethod
    def from_networkx(cls, graph: nx.Graph) -> "Chain":
        """A chain from a networkx graph (any hashable node labels, relabelled ``0..n−1`` in sorted order when possible)."""
        if graph.is_directed() or graph.is_multigraph():
            raise InputError("a chain is a simple undirected graph: convert with nx.Graph(graph) first")
        nodes = list(graph.nodes)
        try:
            nodes.sort()
        except TypeError:
            pass
        index = {v: i for i, v in enumerate(nodes)}
        return cls(len(nodes), tuple((index[u], index[v]) for u, v in graph.edges))

    @classmethod
    def from_graph6(cls, text: str) -> "Chain":
        """A chain from a graph6 string (as printed by ``domes chains --format graph6``).

        >>> Chain.from_graph6("Cr").joints
        4
        """
        raw = text.strip()
        if raw.startswith(">>graph6<<"):
            raw = raw[len(">>graph6<<") :]
        if not raw or any(not 63 <= ord(ch) <= 126 for ch in raw):
            raise InputError(f"{text!r} is not a graph6 string: graph6 uses the characters ? to ~ (ASCII 63-126), "
                             "e.g. 'ErOg' (the Stephenson chain)")
        try:
            graph = nx.from_graph6_bytes(raw.encode("ascii"))
        except (ValueError, IndexError, UnicodeEncodeError, nx.NetworkXError) as exc:
            raise InputError(f"{text!r} is not a graph6 string: {exc or type(exc).__name__}") from None
        return cls.from_networkx(graph)

    def to_networkx(self) -> nx.Graph:
        """The chain's graph: links are nodes ``0..n−1``, joints are edges."""
        graph = nx.Graph()
        graph.add_nodes_from(range(self.n))
        graph.add_edges_from(self.edges)
        return graph

    @cached_property
    def graph6(self) -> str:
        """The standard graph6 string (readable by networkx and nauty)."""
        return nx.to_graph6_bytes(self.to_networkx(), header=False).decode("ascii").strip()

    # -- counts ----------------------------------------------------------------

    @property
    def links(self) -> int:
        return self.n

    @property
    def joints(self) -> int:
        return len(self.edges)

    @property
    def loops(self) -> int:
        """Independent loops ``L = j − n + 1`` (Euler, (3-5)) of a connected chain."""
        return self.joints - self.n + 1

    @property
    def dof(self) -> int:
        """``F = 3(n − 1) − 2j`` (Grübler, (3-13)): :func:`~domes.model.mobility.mobility`."""
        return mobility(self.n, self.joints)

    @cached_property
    def degrees(self) -> tuple[int, ...]:
        """Joints on each link."""
        deg = [0] * self.n
        for u, v in self.edges:
            deg[u] += 1
            deg[v] += 1
        return tuple(deg)

    @cached_property
    def assortment(self) -> dict[int, int]:
        """Link assortment ``{d: n_d}``: how many links carry ``d`` joints."""
        counts: dict[int, int] = {}
        for d in self.degrees:
            counts[d] = counts.get(d, 0) + 1
        return dict(sorted(counts.items()))

    # -- isomorphism -----------------------------------------------------------

    @cached_property
    def certificate(self) -> bytes:
        """nauty certificate: equal for isomorphic chains only."""
        return canonical_form(self.n, self.edges)[0]

    def canonical(self) -> "Chain":
        """The same chain relabelled into nauty's canonical order."""
        return Chain(self.n, canonical_form(self.n, self.edges)[1])

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Chain) and self.certificate == other.certificate

    def __hash__(self) -> int:
        return hash(self.certificate)

    @cached_property
    def topology(self) -> Topology:
        """Loops, cycle space and distances of the chain (:class:`~domes.model.topology.Topology`)."""
        return Topology(self.n, self.edges)

    @cached_property
    def automorphisms(self) -> Automorphisms:
        """The automorphism group (order, generators, link orbits)."""
        return automorphisms(self.n, self.edges)

    @property
    def link_orbits(self) -> list[list[int]]:
        """Orbits of links under the automorphisms: the book's similar links (§3-3-III.1)."""
        return self.automorphisms.orbits

    @cached_property
    def characteristic_polynomial(self) -> tuple[int, ...]:
        """The book's screen (§3-2-II.4): not an exact isomorphism test."""
        return characteristic_polynomial(self.n, self.edges)

    # -- structure -------------------------------------------------------------

    @cached_property
    def is_connected(self) -> bool:
        return self.n > 0 and nx.is_connected(self.to_networkx())

    @cached_property
    def cut_links(self) -> list[int]:
        """Links whose removal disconnects the chain (cut vertices), sorted."""
        return sorted(nx.articulation_points(self.to_networkx()))

    @cached_property
    def graph_planar(self) -> bool:
        """Whether the chain's graph can be drawn without crossings (its links move in a plane either way)."""
        return bool(nx.check_planarity(self.to_networkx())[0])

    @cached_property
    def rigid_subchain(self) -> list[int] | None:
        """The smallest proper sub-chain of 3+ links with ``3(|S|−1) − 2e(S) ≤ 0``, if any."""
        return rigid_subchain(self.n, self.edges)

    @property
    def is_degenerate(self) -> bool:
        return self.rigid_subchain is not None

    @cached_property
    def contracted_graph(self) -> list[Branch]:
        """Branches between links of three or more joints (the embryo graph, Fig. 3-8c).

        Each :class:`Branch` keeps its ends and the binary links along it; a
        single loop has no multi-joint link and an empty contracted graph.
        """
        graph = self.to_networkx()
        multi = {v for v in graph if graph.degree(v) >= 3}
        branches = []
        seen: set[Edge] = set()
        for start in sorted(multi):
            for first in sorted(graph[start]):
                if (min(start, first), max(start, first)) in seen:
                    continue
                path, previous, current = [], start, first
                seen.add((min(start, first), max(start, first)))
                while current not in multi:
                    path.append(current)
                    nxt = [w for w in graph[current] if w != previous]
                    if not nxt:
                        break  # a dangling link: no branch end
                    previous, current = current, nxt[0]
                    seen.add((min(previous, current), max(previous, current)))
                else:
                    branches.append(Branch((start, current), tuple(path)))
        return branches

    @cached_property
    def dof_type(self) -> str:
        """``total``, ``partial`` or ``fractionated`` (§3-2-I.5).

        * *fractionated*: the chain has a cut link (it separates into
          sub-chains with DOF of their own);
        * *partial*: some proper sub-chain containing a loop has a DOF below
          the chain's (its links move with fewer than all ``F`` inputs);
        * *total*: otherwise (every one-DOF chain is total).
        Chains of DOF 0 (structures, basic chains) are ``rigid``.
        """
        if self.dof <= 0:
            return "rigid"
        if self.cut_links:
            return "fractionated"
        if self.dof == 1:
            return "total"
        table = subset_dof_table(self.n, self.edges)
        sizes = subset_sizes(self.n)
        inside = joints_for(sizes, table)
        proper = np.arange(table.size) != table.size - 1
        if np.any(proper & (sizes >= 3) & (table < self.dof) & (inside >= sizes)):
            return "partial"  # a proper sub-chain with a loop and fewer DOF
        return "total"

    @property
    def common_name(self) -> str | None:
        """``four-bar``, ``Watt`` or ``Stephenson`` for the one-DOF chains of 4 and 6 links (Fig. 3-6)."""
        if self.dof != 1 or self.cut_links or self.is_degenerate:
            return None
        if self.n == 4:
            return "four-bar"
        if self.n == 6:
            ternary = [v for v, d in enumerate(self.degrees) if d == 3]
            return "Watt" if tuple(sorted(ternary)) in self.edges else "Stephenson"
        return None

    @cached_property
    def structural_number(self) -> int | None:
        """``K`` of a zero-DOF chain (Table 3-4); ``None`` for other chains."""
        if self.dof != 0 or not self.is_connected:
            return None
        return structural_number(self.n, self.edges)

    def to_dict(self) -> dict[str, Any]:
        """The properties as plain data (the ``--format json`` record)."""
        record: dict[str, Any] = {
            "links": self.links,
            "joints": self.joints,
            "loops": self.loops,
            "dof": self.dof,
            "graph6": self.graph6,
            "edges": [list(e) for e in self.edges],
            "assortment": {str(d): k for d, k in self.assortment.items()},
            "contracted_graph": [
                {"ends": list(b.ends), "binary_links": list(b.binaries)} for b in self.contracted_graph
            ],
            "dof_type": self.dof_type,
            "automorphism_group_order": self.automorphisms.order,
            "link_orbits": self.link_orbits,
            "cut_links": self.cut_links,
            "graph_planar": self.graph_planar,
            "degenerate": self.is_degenerate,
            "rigid_subchain": self.rigid_subchain,
        }
        if self.dof == 0:
            record["structural_number"] = self.structural_number
        return record

    def _repr_svg_(self) -> str | None:
        """The chain drawn as a mechanism skeleton, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "svg")


def chain_properties(graph: nx.Graph | Chain | str | Iterable[Edge]) -> dict[str, Any]:
    """Structural properties of one chain, from a networkx graph, graph6 text or edge list.

    >>> chain_properties("Cr")["dof"]
    1
    >>> chain_properties([(0, 1), (1, 2), (0, 2), (2, 3), (3, 4), (4, 5), (5, 0)])["rigid_subchain"]
    [0, 1, 2]
    """
    if isinstance(graph, Chain):
        chain = graph
    elif isinstance(graph, str):
        chain = Chain.from_graph6(graph)
    elif isinstance(graph, nx.Graph):
        chain = Chain.from_networkx(graph)
    else:
        edges = [tuple(e) for e in graph]
        n = 1 + max((max(e) for e in edges), default=-1)
        chain = Chain(n, tuple(edges))
    return chain.to_dict()
