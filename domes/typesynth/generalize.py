"""Generalization (seed 002 §3-3-I, Table 3-5): a mechanism becomes a revolute chain.

The rules of Table 3-5, with their marks kept on the generalized chain:

========================  =====================================  ==========
element                    becomes                                mark
========================  =====================================  ==========
revolute ``R``             revolute                               --
prismatic ``P``            revolute                               joint ``P``
rolling ``O``              revolute                               --
gear ``G``, cam ``C``      a binary link + two revolutes          link ``HS``
spring ``S``               a dyad (two binary links)              middle joint ``S``
cylinder ``H``             a dyad                                 middle joint ``H``
force ``F``/``Fp``/``Fr``  a dyad                                 middle joint ``F``/``Fp``/``Fr``
========================  =====================================  ==========

The frame and the driver are released: ``ground`` and ``input`` roles are
dropped. Other roles are not part of the chain either; the mechanism keeps
them.

>>> from domes.io.topology import Mechanism
>>> cam = Mechanism.build("cam", [("0", ["ground"]), ("1", ["input"]), ("2", [])],
...                       [("", "0", "1", "R"), ("", "1", "2", "C"), ("", "2", "0", "P")])
>>> g = generalize(cam)
>>> g.chain.n, g.chain.joint_types, g.link_names[-1]
(4, ('R', 'P', 'R', 'R'), 'HS(1-2)')
"""

from __future__ import annotations

from dataclasses import dataclass

from domes.model.chain import Chain
from domes.model.labelled import LabelledChain
from domes.io.topology import Mechanism

#: Joint types replaced by a binary ``HS`` link (higher pairs).
HIGHER_PAIRS = {"G", "C"}
#: Two-point elements replaced by a dyad whose middle joint carries the mark.
ELEMENTS = {"S", "H", "F", "Fp", "Fr"}
#: Joint types that become a revolute with a mark of the same name.
MARKED_REVOLUTES = {"P"}


@dataclass(frozen=True)
class Generalization:
    """The generalized chain of a mechanism, and the names of its links."""

    mechanism: Mechanism
    chain: LabelledChain
    link_names: tuple[str, ...]

    @property
    def unlabelled(self) -> Chain:
        """The chain without marks (for lookup in the atlas)."""
        return Chain(self.chain.n, self.chain.edges)

    @property
    def marks(self) -> dict[str, list[str]]:
        """Marked joints (``"a-b"`` by link names) and marked links, by mark."""
        out: dict[str, list[str]] = {}
        for (u, v), t in zip(self.chain.edges, self.chain.joint_types):
            if t != "R":
                out.setdefault(t, []).append(f"{self.link_names[u]}-{self.link_names[v]}")
        for v, roles in enumerate(self.chain.roles):
            for r in roles:
                out.setdefault(r, []).append(self.link_names[v])
        return out


def generalize(mechanism: Mechanism) -> Generalization:
    """The generalized chain of revolute joints (see the module doc)."""
    names = list(mechanism.link_names)
    roles: dict[int, set[str]] = {}
    edges: list[tuple[int, int]] = []
    marks: list[str] = []

    def new_link(name: str) -> int:
        names.append(name)
        return len(names) - 1

    for joint in mechanism.joints:
        a, b = joint.links
        label = joint.name or f"{mechanism.link_names[a]}-{mechanism.link_names[b]}"
        if joint.type in HIGHER_PAIRS:
            hs = new_link(f"HS({label})")
            roles[hs] = {"HS"}
            edges += [(a, hs), (hs, b)]
            marks += ["R", "R"]
        elif joint.type in ELEMENTS:
            first, second = new_link(f"{joint.type}({label}).1"), new_link(f"{joint.type}({label}).2")
            edges += [(a, first), (first, second), (second, b)]
            marks += ["R", joint.type, "R"]
        else:
            edges.append((a, b))
            marks.append(joint.type if joint.type in MARKED_REVOLUTES else "R")
    chain = LabelledChain.build(len(names), edges, marks, roles)
    return Generalization(mechanism, chain, tuple(names))
