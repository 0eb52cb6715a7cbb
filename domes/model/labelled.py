"""Labelled chains: joints carry a type, links carry roles (DOMES's labelled graphs).

A :class:`LabelledChain` is the common currency of regeneration, screening
and the design expert. Links are ``0..n−1``; each joint is a link pair with
a joint type (see :data:`JOINT_TYPES`); each link has a set of role names
(``ground``, ``input``, ``swing_arm``, ...); loops may be named
(``drive`` → the links of that loop, in order).

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

from domes.model.canon import Automorphisms
from domes.errors import DomesError, InputError

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
}


@dataclass(frozen=True, eq=False)
class LabelledChain:
    """A chain with typed joints, link roles and named loops (immutable).

    ``edges[i]`` has type ``joint_types[i]``; ``roles[v]`` is a frozenset of
    role names of link ``v``; ``named_loops`` maps a loop name to its links
    in loop order. Build one with :meth:`build`.
    """

    n: int
    edges: tuple[Edge, ...]
    joint_types: tuple[str, ...]
    roles: tuple[frozenset[str], ...]
    named_loops: tuple[tuple[str, tuple[int, ...]], ...] = ()

    @classmethod
    def build(
        cls,
        n: int,
        edges: Iterable[Edge],
        joint_types: Iterable[str] | Mapping[Edge, str] | None = None,
        roles: Mapping[int, Iterable[str]] | None = None,
        named_loops: Mapping[str, Iterable[int]] | None = None,
    ) -> "LabelledChain":
        """Validate and normalise: edges sorted, all joints ``R`` unless given."""
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
        for name, links in sorted((named_loops or {}).items()):
            links = tuple(int(x) for x in links)
            ring = list(zip(links, links[1:] + links[:1]))
            missing = [p for p in ring if (min(p), max(p)) not in seen]
            if len(links) < 3 or missing:
                raise InputError(f"named loop {name!r}: {list(links)} is not a closed loop of the chain (missing joints {missing})")
            loops.append((str(name), links))
        return cls(
            n,
            tuple((min(edges[i]), max(edges[i])) for i in order),
            tuple(types[i] for i in order),
            tuple(role_sets),
            tuple(loops),
        )

    # -- views ---------------------------------------------------------------

    def joint_type(self, u: int, v: int) -> str:
        """The type of the joint between links ``u`` and ``v``."""
        return self._types[(min(u, v), max(u, v))]

    @cached_property
    def _types(self) -> dict[Edge, str]:
        return dict(zip(self.edges, self.joint_types))

    @cached_property
    def neighbours(self) -> tuple[tuple[int, ...], ...]:
        """The links jointed to each link."""
        adjacency: list[list[int]] = [[] for _ in range(self.n)]
        for u, v in self.edges:
            adjacency[u].append(v)
            adjacency[v].append(u)
        return tuple(tuple(a) for a in adjacency)

    @property
    def degrees(self) -> tuple[int, ...]:
        """Joints on each link."""
        return tuple(len(a) for a in self.neighbours)

    def automorphisms(self) -> Automorphisms:
        """Label-preserving automorphisms (roles and joint types kept), acting on the links."""
        graph, _ = self._coloured()
        generators, mantissa, exponent, orbits, _ = pynauty.autgrp(graph)
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

    def with_roles(self, roles: Mapping[int, Iterable[str]]) -> "LabelledChain":
        """The same chain and joint types with other link roles."""
        return LabelledChain.build(self.n, self.edges, self.joint_types, roles, dict(self.named_loops))

    def to_networkx(self) -> nx.Graph:
        """Links as nodes with a ``roles`` attribute; joints as edges with a ``type`` attribute."""
        graph = nx.Graph(named_loops=dict(self.named_loops))
        for v in range(self.n):
            graph.add_node(v, roles=self.roles[v])
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
        """Plain data: ``{"links": [{"id", "roles"}], "joints": [{"links", "type"}], "loops"}``.

        >>> LabelledChain.build(3, [(0, 1), (1, 2), (0, 2)], roles={0: {"ground"}}).to_dict()["links"][0]
        {'id': 0, 'roles': ['ground']}
        """
        data = {
            "links": [{"id": v, "roles": sorted(self.roles[v])} for v in range(self.n)],
            "joints": [{"links": [u, v], "type": t} for (u, v), t in zip(self.edges, self.joint_types)],
        }
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
        unknown = set(data) - {"links", "joints", "roles", "loops", "id", "existing", "existing_designs", "chain"}
        if unknown:
            raise InputError(f"{where}: unknown field(s) {', '.join(sorted(unknown))}")
        links, joints = data.get("links"), data.get("joints")
        roles = dict(data.get("roles") or {})
        if isinstance(links, list):
            try:
                roles = {int(item["id"]): item.get("roles", []) for item in links}
            except (TypeError, KeyError, ValueError):
                raise InputError(f"{where}: each link must be an object with an 'id' and optional 'roles'") from None
            n = len(links)
        elif isinstance(links, int):
            n = links
        else:
            raise InputError(f"{where}: 'links' must be a number or a list of links")
        if not isinstance(joints, list):
            raise InputError(f"{where}: 'joints' must be a list")
        edges, types = [], []
        for j in joints:
            pair, kind = None, "R"
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
            return cls.build(n, edges, types, role_map, loops)
        except DomesError as exc:
            raise InputError(f"{where}: {exc}") from None

    # -- identity --------------------------------------------------------------

    @cached_property
    def certificate(self) -> tuple:
        """Equal for two labelled chains exactly when a label-preserving isomorphism exists.

        Named loops are not part of the identity.
        """
        graph, key = self._coloured()
        return key, pynauty.certificate(graph)

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
