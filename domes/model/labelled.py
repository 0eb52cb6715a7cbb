"""Labelled chains: joints carry a type, links carry roles (DOMES's labelled graphs, a mechanism's topology).

A :class:`LabelledChain` is the common currency of regeneration, screening
and the design expert. Links are ``0..n−1``; each joint is a link pair with
a joint type (see :data:`JOINT_TYPES`); each link has a set of role names
(``ground``, ``input``, ``swing_arm``, ...); loops may be named
(``drive`` → the links of that loop, in order). A chain drawn by a designer
also names itself, its links and its joints (Yan's mechanism topology
matrix, seed 002 §4-1): :meth:`LabelledChain.from_named`. Names are not part
of the identity.

Two labelled chains are the same design exactly when a label-preserving
isomorphism maps one onto the other: :attr:`LabelledChain.certificate` is
nauty's canonical form of the graph with links coloured by their roles and
each joint subdivided by a vertex coloured by its type.

>>> four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)],
...                                roles={0: {"ground"}, 1: {"input"}})
>>> four_bar.joint_types
('R', 'R', 'R', 'R')
>>> four_bar.with_roles({0: {"ground"}, 3: {"input"}}).certificate == four_bar.certificate
True
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Iterable, Mapping

import networkx as nx
import pynauty

from domes.errors import DomesError, InputError
from domes.model.canon import Automorphisms, nauty
from domes.model.topology import Topology

Edge = tuple[int, int]

#: Joint types of a labelled chain: symbol -> name (Table 3-5 of seed 002).
JOINT_TYPES: dict[str, str] = {
    "R": "revolute",
    "P": "prismatic (slider)",
    "G": "gear pair",
    "C": "cam / higher pair",
    "O": "rolling contact",
    "S": "spring",
    "H": "hydraulic cylinder",
    "F": "force",
    "Fp": "driving force",
    "Fr": "resisting force",
    # the lower pairs of spatial mechanisms (``domes.model.spatial``), apart from the table's C, S, H
    "Cyl": "cylindric pair",
    "Sph": "spherical pair",
    "Hel": "helical pair",
}


@dataclass(frozen=True, eq=False)
class LabelledChain:
    """A chain with typed joints, link roles and named loops (immutable).

    ``edges[i]`` has type ``joint_types[i]``; ``roles[v]`` is a frozenset of
    role names of link ``v``; ``named_loops`` maps a loop name to its links
    in loop order. ``name``, ``source``, ``link_names`` and ``joint_names``
    (empty: unnamed) say what a designer called them. Build one with
    :meth:`build` or :meth:`from_named`.
    """

    n: int
    edges: tuple[Edge, ...]
    joint_types: tuple[str, ...]
    roles: tuple[frozenset[str], ...]
    named_loops: tuple[tuple[str, tuple[int, ...]], ...] = ()
    name: str = ""
    source: str = ""
    link_names: tuple[str, ...] = ()
    joint_names: tuple[str, ...] = ()

    @classmethod
    def build(
        cls,
        n: int,
        edges: Iterable[Edge],
        joint_types: Iterable[str] | Mapping[Edge, str] | None = None,
        roles: Mapping[int, Iterable[str]] | None = None,
        named_loops: Mapping[str, Iterable[int]] | None = None,
        *,
        name: str = "",
        source: str = "",
        link_names: Iterable[str] | None = None,
        joint_names: Iterable[str] | None = None,
    ) -> "LabelledChain":
        """Validate and normalise: edges sorted, all joints ``R`` unless given; names optional."""
        edges = [tuple(int(x) for x in e) for e in edges]
        if isinstance(joint_types, Mapping):
            lookup = {tuple(sorted(k)): t for k, t in joint_types.items()}
            types = [lookup.get(tuple(sorted(e)), "R") for e in edges]
        elif joint_types is None:
            types = ["R"] * len(edges)
        else:
            types = list(joint_types)
            if len(types) != len(edges):
                raise InputError(f"{len(types)} joint types given for {len(edges)} joints")
        seen: dict[Edge, int] = {}
        for i, ((u, v), t) in enumerate(zip(edges, types)):
            if not (0 <= u < n and 0 <= v < n) or u == v:
                raise InputError(f"joint {i}: ({u}, {v}) must join two different links of 0..{n - 1}")
            if t not in JOINT_TYPES:
                raise InputError(f"joint {i} ({u}-{v}): unknown joint type {t!r}; known: {', '.join(JOINT_TYPES)}")
            key = (min(u, v), max(u, v))
            if key in seen:
                raise InputError(f"joint {i}: links {key[0]} and {key[1]} are already jointed by joint {seen[key]}")
            seen[key] = i
        order = sorted(range(len(edges)), key=lambda i: (min(edges[i]), max(edges[i])))
        role_sets = [frozenset() for _ in range(n)]
        for v, names in (roles or {}).items():
            if not 0 <= int(v) < n:
                raise InputError(f"role(s) {sorted(names)} given to link {v}, which is not in 0..{n - 1}")
            role_sets[int(v)] = frozenset(str(r) for r in names)
        loops = []
        for loop_name, links in sorted((named_loops or {}).items()):
            links = tuple(int(x) for x in links)
            ring = list(zip(links, links[1:] + links[:1]))
            missing = [p for p in ring if (min(p), max(p)) not in seen]
            if len(links) < 3 or missing:
                raise InputError(f"named loop {loop_name!r}: {list(links)} is not a closed loop of the chain (missing joints {missing})")
            loops.append((str(loop_name), links))
        link_names = tuple(str(x) for x in link_names or ())
        if link_names and len(link_names) != n:
            raise InputError(f"{len(link_names)} link names given for {n} links")
        joint_names = tuple(str(x) for x in joint_names or ())
        if joint_names and len(joint_names) != len(edges):
            raise InputError(f"{len(joint_names)} joint names given for {len(edges)} joints")
        return cls(
            n,
            tuple((min(edges[i]), max(edges[i])) for i in order),
            tuple(types[i] for i in order),
            tuple(role_sets),
            tuple(loops),
            str(name),
            str(source),
            link_names,
            tuple(joint_names[i] for i in order) if joint_names else (),
        )

    # -- views ---------------------------------------------------------------

    def joint_type(self, u: int, v: int) -> str:
        """The type of the joint between links ``u`` and ``v``."""
        return self._types[(min(u, v), max(u, v))]

    @cached_property
    def _types(self) -> dict[Edge, str]:
        return dict(zip(self.edges, self.joint_types))

    @property
    def neighbours(self) -> tuple[tuple[int, ...], ...]:
        """The links jointed to each link."""
        return self.topology.adjacency

    @property
    def degrees(self) -> tuple[int, ...]:
        """Joints on each link."""
        return tuple(len(a) for a in self.neighbours)

    @cached_property
    def topology(self) -> Topology:
        """Loops, cycle space and distances of the chain's graph (shared with chains derived from this one)."""
        return Topology(self.n, self.edges)

    @cached_property
    def automorphisms(self) -> Automorphisms:
        """Label-preserving automorphisms (roles and joint types kept), acting on the links."""
        graph, _ = self._coloured()
        generators, mantissa, exponent, orbits, _ = nauty(pynauty.autgrp, graph)
        first: dict[int, int] = {}
        for v, o in enumerate(orbits[: self.n]):
            first.setdefault(o, v)
        return Automorphisms(
            round(mantissa * 10**exponent),
            tuple(tuple(g[: self.n]) for g in generators),
            tuple(first[o] for o in orbits[: self.n]),
        )

    def links_with_role(self, role: str) -> list[int]:
        """Links that carry ``role``."""
        return [v for v, r in enumerate(self.roles) if role in r]

    def link_name(self, v: int) -> str:
        """What the designer called link ``v`` (its number when the links are not named)."""
        return self.link_names[v] if self.link_names else str(v)

    def joint_name(self, i: int) -> str:
        """What the designer called joint ``i`` (``a-b`` by link names when the joints are not named)."""
        if self.joint_names and self.joint_names[i]:
            return self.joint_names[i]
        u, v = self.edges[i]
        return f"{self.link_name(u)}-{self.link_name(v)}"

    def with_roles(self, roles: Mapping[int, Iterable[str]]) -> "LabelledChain":
        """The same chain, joint types and names with other link roles (sharing the topology)."""
        return self.with_labels(roles=roles)

    def with_joint_types(self, joint_types: Iterable[str]) -> "LabelledChain":
        """The same chain, roles and names with other joint types (in the order of :attr:`edges`)."""
        return self.with_labels(joint_types=joint_types)

    def with_labels(self, joint_types: Iterable[str] | None = None,
                    roles: Mapping[int, Iterable[str]] | None = None) -> "LabelledChain":
        """The same chain and names with other joint types and/or roles, sharing the topology."""
        child = LabelledChain.build(
            self.n, self.edges, self.joint_types if joint_types is None else joint_types,
            dict(enumerate(self.roles)) if roles is None else roles, dict(self.named_loops),
            name=self.name, source=self.source, link_names=self.link_names, joint_names=self.joint_names,
        )
        if "topology" in self.__dict__:
            child.__dict__["topology"] = self.__dict__["topology"]
        return child

    @classmethod
    def from_chain(cls, chain) -> "LabelledChain":
        """The chain (a :class:`~domes.model.Chain`) with every joint revolute and no roles, sharing its topology."""
        labelled = cls.build(chain.n, chain.edges)
        labelled.__dict__["topology"] = chain.topology
        return labelled

    @classmethod
    def from_named(
        cls,
        name: str,
        links: Iterable[tuple[str, Iterable[str]]],
        joints: Iterable[tuple[str, str, str, str]],
        source: str = "",
    ) -> "LabelledChain":
        """A chain as a designer names it: ``(link name, roles)`` and ``(joint name, link a, link b, type)``.

        >>> pair = LabelledChain.from_named("pair", [("1", ["ground"]), ("2", [])], [("a", "1", "2", "R")])
        >>> pair.edges, pair.joint_names, pair.link_name(0)
        (((0, 1),), ('a',), '1')
        """
        names: list[str] = []
        roles: dict[int, frozenset[str]] = {}
        for link_name, link_roles in links:
            link_name = str(link_name)
            if link_name in names:
                raise InputError(f"mechanism {name!r}: link {link_name!r} is defined twice")
            roles[len(names)] = frozenset(str(r) for r in link_roles)
            names.append(link_name)
        index = {n: i for i, n in enumerate(names)}
        edges, types, joint_names, seen = [], [], [], {}
        for joint_name, a, b, kind in joints:
            label = joint_name or f"{a}-{b}"
            for end in (a, b):
                if str(end) not in index:
                    raise InputError(f"mechanism {name!r}, joint {label!r}: unknown link {end!r} (links: {', '.join(names)})")
            if str(a) == str(b):
                raise InputError(f"mechanism {name!r}, joint {label!r}: a joint needs two different links")
            if kind not in JOINT_TYPES:
                raise InputError(f"mechanism {name!r}, joint {label!r}: unknown type {kind!r}; known: {', '.join(JOINT_TYPES)}")
            pair = tuple(sorted((index[str(a)], index[str(b)])))
            if pair in seen:
                raise InputError(f"mechanism {name!r}, joint {label!r}: links {a} and {b} are already joined by {seen[pair]!r}")
            seen[pair] = label
            edges.append(pair)
            types.append(kind)
            joint_names.append(str(joint_name))
        return cls.build(len(names), edges, types, roles, name=name, source=source, link_names=names,
                         joint_names=joint_names if any(joint_names) else None)

    def to_networkx(self) -> nx.Graph:
        """Links as nodes with a ``roles`` attribute; joints as edges with a ``type`` attribute."""
        graph = nx.Graph(named_loops=dict(self.named_loops))
        for v in range(self.n):
            graph.add_node(v, roles=self.roles[v], name=self.link_name(v))
        for (u, v), t in zip(self.edges, self.joint_types):
            graph.add_edge(u, v, type=t)
        return graph

    @classmethod
    def from_networkx(cls, graph: nx.Graph) -> "LabelledChain":
        """Inverse of :meth:`to_networkx` (nodes must be ``0..n−1``)."""
        n = graph.number_of_nodes()
        if sorted(graph.nodes) != list(range(n)):
            raise InputError("nodes of a labelled chain must be 0..n-1; relabel with nx.convert_node_labels_to_integers")
        return cls.build(
            n,
            list(graph.edges),
            {(u, v): d.get("type", "R") for u, v, d in graph.edges(data=True)},
            {v: d.get("roles", ()) for v, d in graph.nodes(data=True)},
            graph.graph.get("named_loops"),
        )

    def to_dict(self) -> dict:
        """Plain data: ``{"links": [{"id", "roles"}], "joints": [{"links", "type"}], "loops"}``, names where given.

        >>> LabelledChain.build(3, [(0, 1), (1, 2), (0, 2)], roles={0: {"ground"}}).to_dict()["links"][0]
        {'id': 0, 'roles': ['ground']}
        """
        data: dict = {}
        if self.name:
            data["name"] = self.name
        if self.source:
            data["source"] = self.source
        data["links"] = [{"id": v, "roles": sorted(self.roles[v])} for v in range(self.n)]
        data["joints"] = [{"links": [u, v], "type": t} for (u, v), t in zip(self.edges, self.joint_types)]
        for v, item in enumerate(data["links"]):
            if self.link_names:
                item["name"] = self.link_names[v]
        for i, item in enumerate(data["joints"]):
            if self.joint_names and self.joint_names[i]:
                item["name"] = self.joint_names[i]
        if self.named_loops:
            data["loops"] = {name: list(links) for name, links in self.named_loops}
        return data

    @classmethod
    def from_dict(cls, data: object, where: str = "labelled chain") -> "LabelledChain":
        """Inverse of :meth:`to_dict`; also the compact form ``{"links": n, "joints": [[u, v(, type)]],
        "roles": {link: [names]}, "loops": {name: [links]}}``. Errors say where.

        >>> LabelledChain.from_dict({"links": 3, "joints": [[0, 1, "P"], [1, 2], [0, 2]]}).joint_types
        ('P', 'R', 'R')
        """
        if not isinstance(data, dict):
            raise InputError(f"{where}: expected an object with links and joints")
        unknown = set(data) - {"name", "source", "links", "joints", "roles", "loops", "id", "existing", "existing_designs", "chain"}
        if unknown:
            raise InputError(f"{where}: unknown field(s) {', '.join(sorted(unknown))}")
        links, joints = data.get("links"), data.get("joints")
        roles = dict(data.get("roles") or {})
        link_names = None
        if isinstance(links, list):
            try:
                roles = {int(item["id"]): item.get("roles", []) for item in links}
                if any("name" in item for item in links):
                    link_names = [str(item.get("name", item["id"])) for item in links]
            except (TypeError, KeyError, ValueError):
                raise InputError(f"{where}: each link must be an object with an 'id' and optional 'roles'") from None
            n = len(links)
        elif isinstance(links, int):
            n = links
        else:
            raise InputError(f"{where}: 'links' must be a number or a list of links")
        if not isinstance(joints, list):
            raise InputError(f"{where}: 'joints' must be a list")
        edges, types, joint_names = [], [], []
        for j in joints:
            pair, kind = None, "R"
            joint_names.append(str(j.get("name", "")) if isinstance(j, dict) else "")
            if isinstance(j, dict):
                pair, kind = j.get("links"), j.get("type", "R")
            elif isinstance(j, list) and len(j) in (2, 3):
                pair, kind = j[:2], (j[2] if len(j) == 3 else "R")
            if not (isinstance(pair, list) and len(pair) == 2 and all(isinstance(x, int) for x in pair)):
                raise InputError(f"{where}: joint {j!r} is not [u, v], [u, v, type] or {{'links': [u, v], 'type': T}}")
            edges.append(tuple(pair))
            types.append(kind)
        try:
            role_map = {int(v): [str(r) for r in names] for v, names in roles.items()}
        except (TypeError, ValueError):
            raise InputError(f"{where}: 'roles' must map a link number to a list of role names") from None
        loops = data.get("loops") or {}
        if not isinstance(loops, dict):
            raise InputError(f"{where}: 'loops' must map a loop name to its links in order")
        try:
            return cls.build(n, edges, types, role_map, loops, name=str(data.get("name", "")),
                             source=str(data.get("source", "")), link_names=link_names,
                             joint_names=joint_names if any(joint_names) else None)
        except DomesError as exc:
            raise InputError(f"{where}: {exc}") from None

    # -- identity --------------------------------------------------------------

    @cached_property
    def certificate(self) -> tuple:
        """Equal for two labelled chains exactly when a label-preserving isomorphism exists.

        Named loops are not part of the identity.
        """
        graph, key = self._coloured()
        return key, nauty(pynauty.certificate, graph)

    def _coloured(self) -> tuple[pynauty.Graph, tuple]:
        """The nauty graph: links coloured by role set, joints as vertices coloured by type."""
        colour_of: dict[tuple, list[int]] = {}
        for v, r in enumerate(self.roles):
            colour_of.setdefault(("link", tuple(sorted(r))), []).append(v)
        adjacency: dict[int, list[int]] = {}
        for i, ((u, v), t) in enumerate(zip(self.edges, self.joint_types)):
            w = self.n + i  # the joint, as a vertex of its own
            adjacency.setdefault(w, []).extend((u, v))
            colour_of.setdefault(("joint", t), []).append(w)
        keys = sorted(colour_of)
        graph = pynauty.Graph(
            self.n + len(self.edges),
            adjacency_dict=adjacency,
            vertex_coloring=[set(colour_of[k]) for k in keys],
        )
        return graph, tuple((k, len(colour_of[k])) for k in keys)

    def __eq__(self, other: object) -> bool:
        return isinstance(other, LabelledChain) and self.certificate == other.certificate

    def __hash__(self) -> int:
        return hash(self.certificate)

    def _repr_svg_(self) -> str | None:
        """The chain drawn as a mechanism sketch, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "svg")


def share_topologies(chains: Iterable[LabelledChain]) -> None:
    """Let labelled chains on the same graph share one :class:`~domes.model.topology.Topology`.

    Each labelled chain caches its topology on first use; among chains built
    separately on the same links and joints (e.g. read from a file), this
    makes the first one's serve all, so loops are enumerated once per graph.

    >>> a = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
    >>> b = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(0, 1): "P"})
    >>> share_topologies([a, b]); a.topology is b.topology
    True
    """
    shared: dict[tuple, Topology] = {}
    for chain in chains:
        known = shared.get((chain.n, chain.edges))
        if known is None:
            shared[(chain.n, chain.edges)] = chain.topology
        elif "topology" not in chain.__dict__:
            chain.__dict__["topology"] = known
