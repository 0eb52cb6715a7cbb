"""Relevance: which criteria apply to a problem, and the problem's relevance vector (§7-2).

A criterion's relevance condition is evaluated on a problem's attributes
(Table 7-1): structural attributes (DOF, independent loops, outputs, gear
and slider pairs, links, joints), its class, and its representative
attributes and named vertices and loops (piston, crank, drive loop, ...).
Any object with these attribute names will do, e.g. the design expert's
problem frame; :class:`Problem` is the minimal one. An attribute the
problem does not state (``None``) satisfies no comparison.

The relevance vector has one 0/1 element per criterion of the knowledge
base, in the order of the knowledge base (DOMES: element k stands for
criterion k). It carries the criterion ids, so that vectors made when the
knowledge base was smaller can be aligned and merged (element-wise OR).

>>> from domes.language.parse import parse_relevance
>>> p = Problem(dof=1, loops=2, slider_pairs=1, names=frozenset({"piston"}))
>>> is_relevant(parse_relevance("the problem has “piston” and the number of slider pairs is at least 1"), p)
True
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Mapping

from domes.errors import InputError
from domes.language.parse import normalise_name
from domes.language.tree import (
    PROBLEM_ATTRIBUTES,
    AllOf,
    Always,
    AnyOf,
    Attribute,
    ClassIs,
    HasName,
    NoneOf,
    Relevance,
    names_used,
)


@dataclass(frozen=True)
class Problem:
    """The problem attributes relevance conditions look at (a subset of the Table 7-1 frame).

    ``names`` holds the representative attributes (crank, piston, control
    loop, ...) and the names of the problem's special vertices and loops.
    """

    dof: int | None = None
    loops: int | None = None
    outputs: int | None = None
    gear_pairs: int | None = None
    slider_pairs: int | None = None
    links: int | None = None
    joints: int | None = None
    problem_class: str | None = None
    names: frozenset[str] = frozenset()

    def __post_init__(self) -> None:
        object.__setattr__(self, "names", frozenset(normalise_name(n) for n in self.names))
        if self.problem_class is not None:
            object.__setattr__(self, "problem_class", normalise_name(self.problem_class))

    @classmethod
    def from_dict(cls, data: Mapping, where: str = "problem") -> "Problem":
        """A problem from plain data (JSON/TOML), with errors naming the bad field.

        >>> Problem.from_dict({"dof": 1, "names": ["Swing arm"]}).names
        frozenset({'swing_arm'})
        """
        known = set(PROBLEM_ATTRIBUTES) | {"problem_class", "names"}
        unknown = set(data) - known
        if unknown:
            raise InputError(f"{where}: unknown field(s) {sorted(unknown)}; known: {sorted(known)}")
        kwargs = {}
        for key in PROBLEM_ATTRIBUTES:
            value = data.get(key)
            if value is not None and (not isinstance(value, int) or isinstance(value, bool) or value < 0):
                raise InputError(f"{where}.{key}: expected a whole number >= 0, got {value!r}")
            kwargs[key] = value
        cls_name = data.get("problem_class")
        if cls_name is not None and not isinstance(cls_name, str):
            raise InputError(f"{where}.problem_class: expected a string, got {cls_name!r}")
        names = data.get("names", ())
        if isinstance(names, str) or not all(isinstance(n, str) for n in names):
            raise InputError(f"{where}.names: expected a list of names")
        return cls(**kwargs, problem_class=cls_name or None, names=frozenset(names))


def is_relevant(condition: Relevance, problem) -> bool:
    """Whether a relevance condition holds for a problem (any object with :class:`Problem`'s attributes)."""
    if isinstance(condition, Always):
        return True
    if isinstance(condition, HasName):
        return condition.name in (getattr(problem, "names", None) or ())
    if isinstance(condition, ClassIs):
        return getattr(problem, "problem_class", None) == condition.name
    if isinstance(condition, Attribute):
        value = getattr(problem, condition.attribute, None)
        return value is not None and condition.comparison(value)
    if isinstance(condition, NoneOf):
        return not is_relevant(condition.item, problem)
    if isinstance(condition, AllOf):
        return all(is_relevant(c, problem) for c in condition.items)
    if isinstance(condition, AnyOf):
        return any(is_relevant(c, problem) for c in condition.items)
    raise InputError(f"not a relevance condition: {condition!r}")


@dataclass(frozen=True)
class RelevanceVector:
    """0/1 per criterion: ``bits[k]`` is 1 when criterion ``ids[k]`` is relevant."""

    ids: tuple[str, ...]
    bits: tuple[int, ...]

    def __post_init__(self) -> None:
        if len(self.ids) != len(self.bits) or len(set(self.ids)) != len(self.ids):
            raise InputError("a relevance vector needs one bit per criterion id, ids distinct")
        if any(b not in (0, 1) for b in self.bits):
            raise InputError("relevance bits are 0 or 1")

    def __len__(self) -> int:
        return len(self.bits)

    def relevant_ids(self) -> tuple[str, ...]:
        return tuple(i for i, b in zip(self.ids, self.bits) if b)

    def set(self, criterion_id: str, bit: int) -> "RelevanceVector":
        """The vector with one element overridden (the designer declares a criterion relevant or not)."""
        if criterion_id not in self.ids:
            raise InputError(f"no criterion {criterion_id!r} in the relevance vector")
        return RelevanceVector(self.ids, tuple(bit if i == criterion_id else b for i, b in zip(self.ids, self.bits)))

    def aligned(self, ids: Iterable[str]) -> "RelevanceVector":
        """The vector over ``ids`` (the current knowledge base): unknown criteria get 0.

        >>> RelevanceVector(("a", "b"), (1, 0)).aligned(["a", "b", "c"]).bits
        (1, 0, 0)
        """
        bit = dict(zip(self.ids, self.bits))
        ids = tuple(ids)
        return RelevanceVector(ids, tuple(bit.get(i, 0) for i in ids))

    def merge(self, other: "RelevanceVector") -> "RelevanceVector":
        """Element-wise OR of two vectors, over the ids of both (this vector's order first).

        DOMES merges the original and the new vector of a similar problem
        (§7-2, Fig. 7-8); the book does not say how, OR keeps every criterion
        either found relevant.

        >>> RelevanceVector(("a", "b"), (1, 0)).merge(RelevanceVector(("b", "c"), (1, 0))).bits
        (1, 1, 0)
        """
        ids = self.ids + tuple(i for i in other.ids if i not in self.ids)
        a, b = dict(zip(self.ids, self.bits)), dict(zip(other.ids, other.bits))
        return RelevanceVector(ids, tuple(a.get(i, 0) | b.get(i, 0) for i in ids))


def unavailable_names(frame, roles: Iterable[str] | None) -> tuple[str, ...]:
    """The role and loop names ``frame``'s criterion talks about that no candidate can carry.

    ``roles`` are the names the candidates' links and loops can be given (a
    scene's roles; nothing without a scene); None means any.

    >>> from domes.knowledge.frames import CriterionFrame
    >>> unavailable_names(CriterionFrame.create("g", "the number of vertices representing “ground” must be equal to 1"), [])
    ('ground',)
    """
    if roles is None:
        return ()
    given = {normalise_name(r) for r in roles}
    used_roles, used_loops = names_used(frame.tree)
    return tuple(n for n in sorted(set(used_roles) | set(used_loops)) if n not in given)


def relevance_vector(frames, problem, roles: Iterable[str] | None = None) -> RelevanceVector:
    """The relevance vector of a problem over criterion frames (in knowledge-base order).

    A criterion is relevant when its relevance condition holds for the
    problem and, when ``roles`` is given (the role and loop names the
    candidates can carry: a scene's roles, or none without a scene), every
    name it talks about can be carried: a criterion about the ground of a
    problem whose candidates have no ground would reject them all, or none,
    without meaning anything.

    >>> from domes.knowledge.frames import CriterionFrame
    >>> frames = [CriterionFrame.create("c1", "every vertex must have degree at most 3"),
    ...           CriterionFrame.create("c2", "the vertex representing “piston” must have type (P R)")]
    >>> relevance_vector(frames, Problem(dof=1)).bits
    (1, 0)
    >>> relevance_vector(frames, Problem(dof=1, names=frozenset({"piston"})), roles=[]).bits
    (1, 0)
    """
    frames = list(frames)
    bits = tuple(int(is_relevant(f.relevance, problem) and not unavailable_names(f, roles)) for f in frames)
    return RelevanceVector(tuple(f.id for f in frames), bits)
