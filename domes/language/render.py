"""The canonical text of a tree: the inverse of the parser (``parse(render(t)) == t``).

``domes kb show`` prints it beside the designer's own wording, so that what
the system understood can be read back in the same language.

>>> from domes.language.parse import parse_criterion
>>> render_criterion(parse_criterion("THE VERTEX REPRESENTING “PISTON” MUST HAVE ITS “TYPE” PROPERTY-VALUE AS (P R)"))
'the vertex representing “piston” must have type (P R)'
"""

from __future__ import annotations

from domes.errors import InputError
from domes.language.tree import (
    ActivePairs,
    Adjacent,
    AllOf,
    Always,
    And,
    AnyOf,
    Attribute,
    ClassIs,
    Comparison,
    Count,
    Criterion,
    Distance,
    HasMember,
    HasName,
    InLoop,
    JointCount,
    NoneOf,
    Not,
    Or,
    Relevance,
    Represents,
    SharesJoint,
    TypeIs,
)

JOINT_NAMES = {"R": "revolute", "P": "prismatic", "G": "gear", "C": "cam", "O": "rolling", "S": "spring", "H": "hydraulic", "F": "force"}
ATTRIBUTE_PHRASES = {
    "dof": "degrees of freedom", "loops": "independent loops", "outputs": "outputs", "gear_pairs": "gear pairs",
    "slider_pairs": "slider pairs", "links": "links", "joints": "joints",
}
TYPE_PHRASES = {"=": "", "!=": "not equal to ", "contains": "containing ", "within": "within "}


def quoted(name: str) -> str:
    return "“" + name.replace("_", " ") + "”"


def comparison_text(c: Comparison) -> str:
    """``at most 1``, ``more than 2``, ``3``, ...

    >>> comparison_text(Comparison("<=", 1))
    'at most 1'
    """
    return {
        "<": "less than {}", "<=": "at most {}", "=": "{}", "!=": "other than {}", ">=": "at least {}", ">": "more than {}",
    }[c.op].format(c.value)


def _joints(joint: str | None, count: int) -> str:
    noun = "joint" if joint is None else f"{JOINT_NAMES[joint]} pair"
    return noun if count == 1 else noun + "s"


def condition_text(c, loop: bool, be: str = "be") -> str:
    """A vertex (``loop=False``) or loop condition after a modal (``be="be"``) or in a ``that`` clause (``be="are"``)."""
    if isinstance(c, Not):
        return "not " + _grouped(c.item, loop, be)
    if isinstance(c, (And, Or)):
        word = " and " if isinstance(c, And) else " or "
        return word.join(_grouped(x, loop, be) for x in c.items)
    if isinstance(c, TypeIs):
        return f"have type {TYPE_PHRASES[c.relation]}({' '.join(c.joints)})"
    if isinstance(c, JointCount):
        if c.joint is None:
            return f"have {'length' if loop else 'degree'} {comparison_text(c.comparison)}"
        if c.comparison == Comparison("=", 0):
            return f"have no {_joints(c.joint, 2)}"
        if c.comparison == Comparison(">=", 1):
            return f"have a {_joints(c.joint, 1)}"
        return f"have {comparison_text(c.comparison)} {_joints(c.joint, c.comparison.value)}"
    if isinstance(c, Adjacent):
        via = f" by a {JOINT_NAMES[c.joint]} pair" if c.joint else ""
        return f"{be} adjacent to {quoted(c.role)}{via}"
    if isinstance(c, Distance):
        return f"{be} at distance {comparison_text(c.comparison)} from {quoted(c.role)}"
    if isinstance(c, Represents):
        return f"represent {quoted(c.role)}"
    if isinstance(c, InLoop):
        return f"{be} in the {quoted(c.loop)} loop"
    if isinstance(c, HasMember):
        return f"contain {quoted(c.role)}"
    if isinstance(c, SharesJoint):
        return f"share a joint with the {quoted(c.loop)} loop"
    raise InputError(f"not a condition: {c!r}")


def _grouped(c, loop: bool, be: str) -> str:
    text = condition_text(c, loop, be)
    return f"[{text}]" if isinstance(c, (And, Or, Not)) else text


def _after_modal(c, loop: bool) -> str:
    """``must A`` / ``must not A``; a conjunction as clauses ``must A and must not B``."""
    if isinstance(c, And):
        return " and ".join("must " + _grouped(x, loop, "be") if isinstance(x, And) else _after_modal(x, loop) for x in c.items)
    if isinstance(c, Not):
        return "must not " + condition_text(c.item, loop)
    return "must " + condition_text(c, loop)


def render_criterion(tree: Criterion) -> str:
    """The canonical sentence of a criterion.

    >>> from domes.language.tree import Domain
    >>> render_criterion(Count(Domain("vertex"), TypeIs("=", ("P", "R")), Comparison("<=", 1)))
    'the number of vertices that have type (P R) must be at most 1'
    >>> render_criterion(ActivePairs("input", "partial"))
    'the “input” pairs must be active pairs with partial DOF'
    """
    if isinstance(tree, ActivePairs):
        kind = f" with {tree.dof_type} DOF" if tree.dof_type else ""
        return f"the {quoted(tree.role)} pairs must be active pairs{kind}"
    d = tree.domain
    loop = d.kind != "vertex"
    if isinstance(tree, Count):
        noun = {"vertex": "vertices", "independent_loop": "independent loops", "loop": "loops"}[d.kind]
        that = f" that {condition_text(tree.condition, loop, 'are')}" if tree.condition is not None else ""
        return f"the number of {noun}{that} must be {comparison_text(tree.comparison)}"
    if d.name is not None:
        subject = f"the {'loop' if loop else 'vertex'} representing {quoted(d.name)}"
    else:
        subject = {"vertex": "every vertex", "independent_loop": "every independent loop", "loop": "every loop"}[d.kind]
    return f"{subject} {_after_modal(tree.condition, loop)}"


def render_relevance(r: Relevance) -> str:
    """The canonical text of a relevance condition.

    >>> render_relevance(Attribute("gear_pairs", Comparison(">=", 1)))
    'the number of gear pairs is at least 1'
    """
    if isinstance(r, Always):
        return "always"
    if isinstance(r, HasName):
        return f"the problem has {quoted(r.name)}"
    if isinstance(r, ClassIs):
        return f"the problem class is {quoted(r.name)}"
    if isinstance(r, Attribute):
        return f"the number of {ATTRIBUTE_PHRASES[r.attribute]} is {comparison_text(r.comparison)}"
    if isinstance(r, NoneOf):
        return "not " + _rgrouped(r.item)
    word = " and " if isinstance(r, AllOf) else " or "
    return word.join(_rgrouped(x) for x in r.items)


def _rgrouped(r: Relevance) -> str:
    text = render_relevance(r)
    return f"[{text}]" if isinstance(r, (AllOf, AnyOf, NoneOf)) else text
