"""The typed tree of a parsed criterion (and of a relevance condition), with JSON.

A criterion is a *requirement* on a labelled graph: a graph that does not
meet it is rejected. Two statement forms cover the six categories of the
knowledge-engineer module (seed 002, §7-2, Table 7-3):

* :class:`ForAll` -- every element of a domain (every vertex, every vertex
  representing a role, every independent loop, every loop, the named loop)
  satisfies a condition: categories (i), (iii), (v), (vi);
* :class:`Count` -- the number of vertices or loops satisfying a condition
  compares with a number: categories (ii), (iv);
* :class:`ActivePairs` -- the joints between the ground and the links of a
  role can drive the chain together (the active-pair criterion, seed 002
  §3-2-I.5), optionally with a DOF type: a statement about named vertices,
  category (v).

Conditions are trees of :class:`TypeIs`, :class:`JointCount`,
:class:`Adjacent`, :class:`Distance`, :class:`Represents`, :class:`InLoop`,
:class:`HasMember`, :class:`SharesJoint` joined by :class:`Not`,
:class:`And`, :class:`Or`. Every node is a frozen dataclass;
:func:`to_json` / :func:`from_json` convert a tree to and from plain JSON
data (``{"node": "ForAll", ...}``), validating every field on the way in.

>>> tree = ForAll(Domain("vertex"), Not(TypeIs("=", ("G", "P", "R"))))
>>> from_json(to_json(tree)) == tree
True
>>> category(tree)
'i'
"""

from __future__ import annotations

import re
from dataclasses import MISSING, dataclass, fields
from typing import Any, Union

from domes.errors import InputError
from domes.model.labelled import JOINT_TYPES

#: Names of roles (named vertices), loops and problem classes: lower case words joined by "_".
NAME_PATTERN = re.compile(r"^[a-z0-9]+(_[a-z0-9]+)*$")

#: Comparison operators of the language, and the operator of the negated comparison.
NEGATED_OP = {"<": ">=", "<=": ">", "=": "!=", "!=": "=", ">=": "<", ">": "<="}

#: Relations between a TYPE property (a set of joint types) and a given set.
TYPE_RELATIONS = ("=", "!=", "contains", "within")

#: Domains of a statement: vertices, independent loops (a cycle basis), loops (every simple cycle).
DOMAIN_KINDS = ("vertex", "independent_loop", "loop")

#: DOF types an active-pair statement may require (seed 002 §3-2-I.5 (2)); "total" is read as "full".
DOF_TYPES = ("full", "partial", "fractionated")

#: Problem attributes a relevance condition may compare (names of :class:`~domes.knowledge.relevance.Problem` fields).
PROBLEM_ATTRIBUTES = ("dof", "loops", "outputs", "gear_pairs", "slider_pairs", "links", "joints")


@dataclass(frozen=True)
class Comparison:
    """``value op number``, with ``op`` one of ``< <= = != >= >``."""

    op: str
    value: int

    def __call__(self, x: int) -> bool:
        """Whether ``x`` satisfies the comparison.

        >>> Comparison("<=", 1)(2)
        False
        """
        op, v = self.op, self.value
        if op == "<":
            return x < v
        if op == "<=":
            return x <= v
        if op == "=":
            return x == v
        if op == "!=":
            return x != v
        if op == ">=":
            return x >= v
        return x > v

    def negated(self) -> "Comparison":
        return Comparison(NEGATED_OP[self.op], self.value)


# -- conditions on one vertex or one loop -------------------------------------


@dataclass(frozen=True)
class TypeIs:
    """The TYPE property (the set of joint types of a vertex's joints, or of a loop's joints) related to a set.

    ``relation`` is ``=``, ``!=``, ``contains`` (a superset of ``joints``) or ``within`` (a subset).
    """

    relation: str
    joints: tuple[str, ...]


@dataclass(frozen=True)
class JointCount:
    """The number of joints of type ``joint`` (of any type when ``None``) of a vertex or in a loop.

    With ``joint=None`` this is a vertex's degree or a loop's length.
    """

    joint: str | None
    comparison: Comparison


@dataclass(frozen=True)
class Adjacent:
    """The vertex is jointed (by a joint of type ``joint``, any when ``None``) to a vertex representing ``role``."""

    role: str
    joint: str | None = None


@dataclass(frozen=True)
class Distance:
    """The distance (joints on a shortest path) from the vertex to the nearest vertex representing ``role``."""

    role: str
    comparison: Comparison


@dataclass(frozen=True)
class Represents:
    """The vertex carries the role ``role`` (ground, input, piston, ...)."""

    role: str


@dataclass(frozen=True)
class InLoop:
    """The vertex is a member of the named loop ``loop``."""

    loop: str


@dataclass(frozen=True)
class HasMember:
    """The loop has a vertex representing ``role`` among its members."""

    role: str


@dataclass(frozen=True)
class SharesJoint:
    """The loop shares at least one joint with the named loop ``loop``."""

    loop: str


@dataclass(frozen=True)
class Not:
    item: "Condition"


@dataclass(frozen=True)
class And:
    items: tuple["Condition", ...]


@dataclass(frozen=True)
class Or:
    items: tuple["Condition", ...]


Condition = Union[TypeIs, JointCount, Adjacent, Distance, Represents, InLoop, HasMember, SharesJoint, Not, And, Or]

#: Conditions that make sense on a vertex and on a loop respectively.
VERTEX_CONDITIONS = (TypeIs, JointCount, Adjacent, Distance, Represents, InLoop)
LOOP_CONDITIONS = (TypeIs, JointCount, HasMember, SharesJoint)


# -- statements ------------------------------------------------------------------


@dataclass(frozen=True)
class Domain:
    """What a statement ranges over: ``kind`` in :data:`DOMAIN_KINDS`, optionally only the element(s) named ``name``.

    A named vertex domain is every vertex representing that role; a named
    loop domain is the loop of that name.
    """

    kind: str
    name: str | None = None


@dataclass(frozen=True)
class ForAll:
    """Every element of ``domain`` satisfies ``condition``."""

    domain: Domain
    condition: Condition


@dataclass(frozen=True)
class Count:
    """The number of elements of ``domain`` satisfying ``condition`` (all when ``None``) satisfies ``comparison``."""

    domain: Domain
    condition: Condition | None
    comparison: Comparison


@dataclass(frozen=True)
class ActivePairs:
    """The joints between the ground and the links representing ``role`` can be active pairs together.

    Each takes exactly one DOF away and together they leave none (the
    active-pair criterion, seed 002 §3-2-I.5 (1); see
    :func:`domes.model.active.active_pairs`); with ``dof_type``, they also
    give that type of DOF (:data:`DOF_TYPES`, §3-2-I.5 (2)).
    """

    role: str = "input"
    dof_type: str | None = None


Criterion = Union[ForAll, Count, ActivePairs]


# -- relevance conditions (on problem attributes) ----------------------------------


@dataclass(frozen=True)
class Always:
    """Relevant to every problem."""


@dataclass(frozen=True)
class HasName:
    """The problem has a representative attribute, named vertex or named loop called ``name``."""

    name: str


@dataclass(frozen=True)
class ClassIs:
    """The problem belongs to the class ``name``."""

    name: str


@dataclass(frozen=True)
class Attribute:
    """A structural attribute of the problem (one of :data:`PROBLEM_ATTRIBUTES`) compares with a number."""

    attribute: str
    comparison: Comparison


@dataclass(frozen=True)
class AllOf:
    items: tuple["Relevance", ...]


@dataclass(frozen=True)
class AnyOf:
    items: tuple["Relevance", ...]


@dataclass(frozen=True)
class NoneOf:
    item: "Relevance"


Relevance = Union[Always, HasName, ClassIs, Attribute, AllOf, AnyOf, NoneOf]

_NODES = {
    cls.__name__: cls
    for cls in (
        Comparison, TypeIs, JointCount, Adjacent, Distance, Represents, InLoop, HasMember, SharesJoint,
        Not, And, Or, Domain, ForAll, Count, ActivePairs, Always, HasName, ClassIs, Attribute, AllOf, AnyOf, NoneOf,
    )
}


# -- JSON ------------------------------------------------------------------------------


def to_json(node: Any) -> Any:
    """Plain JSON data (dicts, lists, strings, numbers, null) for a tree.

    >>> to_json(JointCount("G", Comparison("<=", 1)))
    {'node': 'JointCount', 'joint': 'G', 'comparison': {'node': 'Comparison', 'op': '<=', 'value': 1}}
    """
    if isinstance(node, tuple):
        return [to_json(x) for x in node]
    if type(node).__name__ in _NODES and type(node) is _NODES[type(node).__name__]:
        out = {"node": type(node).__name__}
        for f in fields(node):
            out[f.name] = to_json(getattr(node, f.name))
        return out
    return node


def from_json(data: Any, where: str = "tree", expect: str | None = None) -> Any:
    """The tree for JSON data made by :func:`to_json`; any malformed part raises DomesError naming where it is.

    ``expect`` is ``"criterion"`` or ``"relevance"`` to accept only that kind of tree.

    >>> from_json({"node": "ForAll", "domain": {"node": "Domain", "kind": "vertex", "name": "input"},
    ...            "condition": {"node": "Adjacent", "role": "ground"}})
    ForAll(domain=Domain(kind='vertex', name='input'), condition=Adjacent(role='ground', joint=None))
    >>> from_json({"node": "Eval", "code": "1"})
    Traceback (most recent call last):
    ...
    domes.errors.InputError: tree: unknown node 'Eval'
    """
    node = _decode(data, where)
    kinds = {"criterion": (ForAll, Count, ActivePairs), "relevance": (Always, HasName, ClassIs, Attribute, AllOf, AnyOf, NoneOf)}
    allowed = kinds[expect] if expect else kinds["criterion"] + kinds["relevance"]
    if not isinstance(node, allowed):
        raise InputError(f"{where}: {type(node).__name__} is not a {expect or 'criterion or relevance condition'}")
    _validate(node, where)
    return node


def _decode(data: Any, where: str) -> Any:
    if not isinstance(data, dict):
        raise InputError(f"{where}: expected an object with a 'node' field, got {type(data).__name__}")
    name = data.get("node")
    cls = _NODES.get(name) if isinstance(name, str) else None
    if cls is None:
        raise InputError(f"{where}: unknown node {name!r}")
    names = {f.name for f in fields(cls)}
    extra = set(data) - names - {"node"}
    if extra:
        raise InputError(f"{where}: {name} has no field(s) {sorted(extra)}")
    kwargs = {}
    for f in fields(cls):
        if f.name not in data:
            if f.default is not MISSING:
                continue
            raise InputError(f"{where}: {name} is missing the field {f.name!r}")
        value = data[f.name]
        here = f"{where}.{f.name}"
        if f.name in ("items",):
            if not isinstance(value, list) or len(value) < 2:
                raise InputError(f"{here}: expected a list of at least two conditions")
            value = tuple(_decode(x, f"{here}[{i}]") for i, x in enumerate(value))
        elif f.name == "joints":
            if not isinstance(value, list) or not all(isinstance(x, str) for x in value):
                raise InputError(f"{here}: expected a list of joint-type letters")
            value = tuple(value)
        elif isinstance(value, dict):
            value = _decode(value, here)
        kwargs[f.name] = value
    return cls(**kwargs)


def _check_str(value: Any, where: str, allowed: tuple | None = None, optional: bool = False) -> None:
    if value is None and optional:
        return
    if not isinstance(value, str) or not value:
        raise InputError(f"{where}: expected a non-empty string, got {value!r}")
    if allowed is not None and value not in allowed:
        raise InputError(f"{where}: {value!r} is not one of {', '.join(map(str, allowed))}")
    if allowed is None and not NAME_PATTERN.match(value):
        raise InputError(f"{where}: {value!r} is not a name (lower-case letters and digits joined by '_')")


def _validate(node: Any, where: str, context: str | None = None) -> None:
    """Field types and the vertex/loop context of every condition."""
    if isinstance(node, Comparison):
        _check_str(node.op, f"{where}.op", tuple(NEGATED_OP))
        if not isinstance(node.value, int) or isinstance(node.value, bool) or node.value < 0:
            raise InputError(f"{where}.value: expected a whole number >= 0, got {node.value!r}")
    elif isinstance(node, (ForAll, Count)):
        if not isinstance(node.domain, Domain):
            raise InputError(f"{where}.domain: expected a Domain")
        _check_str(node.domain.kind, f"{where}.domain.kind", DOMAIN_KINDS)
        _check_str(node.domain.name, f"{where}.domain.name", optional=True)
        ctx = "vertex" if node.domain.kind == "vertex" else "loop"
        if isinstance(node, ForAll):
            _validate(node.condition, f"{where}.condition", ctx)
        else:
            if node.domain.name is not None:
                raise InputError(f"{where}.domain: a count ranges over all vertices or loops, not a named one")
            if node.condition is not None:
                _validate(node.condition, f"{where}.condition", ctx)
            _expect(node.comparison, Comparison, f"{where}.comparison")
            _validate(node.comparison, f"{where}.comparison")
    elif isinstance(node, ActivePairs):
        if context is not None:
            raise InputError(f"{where}: ActivePairs is a criterion, not a {context} condition")
        _check_str(node.role, f"{where}.role")
        _check_str(node.dof_type, f"{where}.dof_type", DOF_TYPES, optional=True)
    elif isinstance(node, (Not, NoneOf)):
        _validate(node.item, f"{where}.item", context)
    elif isinstance(node, (And, Or, AllOf, AnyOf)):
        for i, item in enumerate(node.items):
            _validate(item, f"{where}.items[{i}]", context)
    elif isinstance(node, (Always, HasName, ClassIs, Attribute)):
        if context is not None:
            raise InputError(f"{where}: {type(node).__name__} is a relevance condition, not a {context} condition")
        if isinstance(node, (HasName, ClassIs)):
            _check_str(node.name, f"{where}.name")
        elif isinstance(node, Attribute):
            _check_str(node.attribute, f"{where}.attribute", PROBLEM_ATTRIBUTES)
            _expect(node.comparison, Comparison, f"{where}.comparison")
            _validate(node.comparison, f"{where}.comparison")
    else:
        allowed = VERTEX_CONDITIONS if context == "vertex" else LOOP_CONDITIONS if context == "loop" else ()
        if not isinstance(node, allowed):
            what = f"a {context} condition" if context else "a criterion or relevance condition"
            raise InputError(f"{where}: {type(node).__name__} is not {what}")
        if isinstance(node, TypeIs):
            _check_str(node.relation, f"{where}.relation", TYPE_RELATIONS)
            if not node.joints or any(j not in JOINT_TYPES for j in node.joints) or tuple(sorted(set(node.joints))) != node.joints:
                raise InputError(f"{where}.joints: expected sorted distinct joint types from {' '.join(JOINT_TYPES)}")
        elif isinstance(node, JointCount):
            _check_str(node.joint, f"{where}.joint", tuple(JOINT_TYPES), optional=True)
            _expect(node.comparison, Comparison, f"{where}.comparison")
            _validate(node.comparison, f"{where}.comparison")
        elif isinstance(node, Adjacent):
            _check_str(node.role, f"{where}.role")
            _check_str(node.joint, f"{where}.joint", tuple(JOINT_TYPES), optional=True)
        elif isinstance(node, Distance):
            _check_str(node.role, f"{where}.role")
            _expect(node.comparison, Comparison, f"{where}.comparison")
            _validate(node.comparison, f"{where}.comparison")
        elif isinstance(node, (Represents, HasMember)):
            _check_str(node.role, f"{where}.role")
        elif isinstance(node, (InLoop, SharesJoint)):
            _check_str(node.loop, f"{where}.loop")


def _expect(value: Any, cls: type, where: str) -> None:
    if not isinstance(value, cls):
        raise InputError(f"{where}: expected a {cls.__name__}")


# -- properties of a tree ---------------------------------------------------------------


def category(tree: Criterion) -> str:
    """The knowledge-engineer category (i)-(vi) of a criterion (§7-2, 4.5).

    (i) any vertex, (ii) number of vertices, (iii) any independent loop,
    (iv) number of loops, (v) a named vertex, (vi) a named loop.

    >>> category(Count(Domain("independent_loop"), JointCount("P", Comparison(">=", 1)), Comparison("<=", 1)))
    'iv'
    >>> category(ActivePairs())          # about the named vertices ground and input
    'v'
    """
    if isinstance(tree, ActivePairs):
        return "v"
    vertex = tree.domain.kind == "vertex"
    if isinstance(tree, Count):
        return "ii" if vertex else "iv"
    if tree.domain.name is not None:
        return "v" if vertex else "vi"
    return "i" if vertex else "iii"


def walk(node: Any):
    """Every node of a tree, depth first."""
    yield node
    if isinstance(node, tuple):
        for x in node:
            yield from walk(x)
        return
    if type(node).__name__ in _NODES:
        for f in fields(node):
            value = getattr(node, f.name)
            if isinstance(value, tuple) or type(value).__name__ in _NODES:
                yield from walk(value)


def names_used(tree: Criterion) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """The roles (named vertices) and the loop names a criterion refers to, sorted.

    >>> names_used(ForAll(Domain("vertex", "swing_arm"), Adjacent("ground")))
    (('ground', 'swing_arm'), ())
    """
    roles, loops = set(), set()
    for node in walk(tree):
        if isinstance(node, (Adjacent, Distance, Represents, HasMember)):
            roles.add(node.role)
        elif isinstance(node, (InLoop, SharesJoint)):
            loops.add(node.loop)
        elif isinstance(node, Domain) and node.name is not None:
            (roles if node.kind == "vertex" else loops).add(node.name)
        elif isinstance(node, ActivePairs):
            roles.update(("ground", node.role))
    return tuple(sorted(roles)), tuple(sorted(loops))


#: Cost levels of multi-level screening, cheapest first.
LEVELS = {
    1: "local: joint types, degrees and roles of single vertices",
    2: "neighbourhood: adjacency, distances, named loops",
    3: "loops: every simple cycle and the cycle space of the graph",
    4: "kinematic: needs dimensions (supplied by the kinematics backend)",
}


def level(tree: Criterion) -> int:
    """The cheapest screening level that can evaluate a criterion (see :data:`LEVELS`).

    >>> level(ForAll(Domain("vertex"), Not(TypeIs("=", ("G", "P", "R")))))
    1
    >>> level(ForAll(Domain("vertex", "swing_arm"), Adjacent("ground")))
    2
    >>> level(ActivePairs())            # the loops of the whole chain (a pebble game)
    3
    """
    if isinstance(tree, ActivePairs):
        return 3
    if tree.domain.kind != "vertex" and tree.domain.name is None:
        return 3
    if tree.domain.kind != "vertex":
        return 2
    if any(isinstance(n, (Adjacent, Distance, InLoop)) for n in walk(tree)):
        return 2
    return 1
