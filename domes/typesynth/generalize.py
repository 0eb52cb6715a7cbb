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

>>> cam = LabelledChain.from_named("cam", [("0", ["ground"]), ("1", ["input"]), ("2", [])],
...                                [("", "0", "1", "R"), ("", "1", "2", "C"), ("", "2", "0", "P")])
>>> g = generalize(cam)
>>> g.chain.n, g.chain.joint_types, g.link_names[-1]
(4, ('R', 'P', 'R', 'R'), 'HS(1-2)')
"""

from __future__ import annotations

from dataclasses import dataclass

from domes.model.chain import Chain
from domes.model.labelled import LabelledChain
from domes.results import Result, Status
from domes.typesynth.atlas import ChainGenerator, atlas_position

#: Joint types replaced by a binary ``HS`` link (higher pairs).
HIGHER_PAIRS = {"G", "C"}
#: Two-point elements replaced by a dyad whose middle joint carries the mark.
ELEMENTS = {"S", "H", "F", "Fp", "Fr"}
#: Joint types that become a revolute with a mark of the same name.
MARKED_REVOLUTES = {"P"}


@dataclass(frozen=True)
class Generalization(Result):
    """A mechanism (``original``) and its generalized chain (``chain``, whose links are named); always COMPLETE."""

    original: LabelledChain
    chain: LabelledChain

    status = Status.COMPLETE

    @property
    def message(self) -> str:
        c = self.unlabelled
        name = f": the {c.common_name} chain" if c.common_name else (": degenerate" if c.is_degenerate else "")
        return f"{self.original.name or 'mechanism'}: {c.n} links, {c.joints} joints, DOF {c.dof}, {c.loops} loops{name}"

    @property
    def link_names(self) -> tuple[str, ...]:
        """The names of the generalized chain's links (the original's, then the links added)."""
        return tuple(self.chain.link_name(v) for v in range(self.chain.n))

    @property
    def unlabelled(self) -> Chain:
        """The chain without marks (for lookup in the atlas)."""
        return Chain(self.chain.n, self.chain.edges)

    def to_dict(self, generator: ChainGenerator | None = None) -> dict:
        """The generalized chain as plain data, with its position in the atlas (``atlas_position``)."""
        chain = self.unlabelled
        return {
            "mechanism": self.original.name,
            "links": chain.n,
            "joints": chain.joints,
            "dof": chain.dof,
            "loops": chain.loops,
            "link_names": list(self.link_names),
            "edges": [list(e) for e in self.chain.edges],
            "marks": self.marks,
            "chain": chain.common_name,
            "atlas_position": atlas_position(chain, generator),
            "degenerate": chain.is_degenerate,
            "graph6": chain.graph6,
        }

    @property
    def marks(self) -> dict[str, list[str]]:
        """Marked joints (``"a-b"`` by link names) and marked links, by mark."""
        names = self.link_names
        out: dict[str, list[str]] = {}
        for (u, v), t in zip(self.chain.edges, self.chain.joint_types):
            if t != "R":
                out.setdefault(t, []).append(f"{names[u]}-{names[v]}")
        for v, roles in enumerate(self.chain.roles):
            for r in roles:
                out.setdefault(r, []).append(names[v])
        return out


def generalize(mechanism: LabelledChain) -> Generalization:
    """The generalized chain of revolute joints (see the module doc)."""
    names = [mechanism.link_name(v) for v in range(mechanism.n)]
    roles: dict[int, set[str]] = {}
    edges: list[tuple[int, int]] = []
    marks: list[str] = []

    def new_link(name: str) -> int:
        names.append(name)
        return len(names) - 1

    for i, ((a, b), kind) in enumerate(zip(mechanism.edges, mechanism.joint_types)):
        label = mechanism.joint_name(i)
        if kind in HIGHER_PAIRS:
            hs = new_link(f"HS({label})")
            roles[hs] = {"HS"}
            edges += [(a, hs), (hs, b)]
            marks += ["R", "R"]
        elif kind in ELEMENTS:
            first, second = new_link(f"{kind}({label}).1"), new_link(f"{kind}({label}).2")
            edges += [(a, first), (first, second), (second, b)]
            marks += ["R", kind, "R"]
        else:
            edges.append((a, b))
            marks.append(kind if kind in MARKED_REVOLUTES else "R")
    chain = LabelledChain.build(len(names), edges, marks, roles, name=mechanism.name, link_names=names)
    return Generalization(mechanism, chain)
