"""Design scenes as data: the rules of a regeneration, read from TOML.

A scene names the chains to start from, the stages that assign roles (each
stage gives its role to a link, or a pair of links, in every way that keeps
its ``rules`` true), the stages that change the chain's elements (§3-3-II
stages 3 and 4: a revolute becomes prismatic, a binary link becomes a gear
or cam pair, a binary link or a dyad becomes a force member; see
:data:`KINDS`), screens (stages without a role: their rules filter),
how to particularize the chosen roles back into joints (e.g. the joint
inside the shock absorber becomes prismatic), the existing designs to
recognise, and the book's counts to print beside ours. Rules are sentences
of the criterion language (:mod:`domes.language.parse`), the same
language as the knowledge base's screening criteria. The shipped scenes are
in ``knowledge/scenes/``; the format is documented in ``docs/regeneration.md``.

Scenes are read from files by :mod:`domes.io.scenes`.

>>> from domes.io.scenes import load_scene
>>> scene = load_scene("motorcycle")
>>> [s.name for s in scene.stages]
['ground', 'shock absorber', 'swing arm', 'swing arm adjacent to ground']
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterable

from domes.language.evaluate import compile_criterion
from domes.language.tree import And, Criterion, ForAll, JointCount, Not
from domes.model.labelled import JOINT_TYPES, LabelledChain
from domes.model.requirements import RequirementSpec
from domes.typesynth.generalize import ELEMENTS, HIGHER_PAIRS

SELECTIONS = ("link", "adjacent pair", "pair")

#: The kinds of divergence stage (seed 002 §3-3-II): what a stage may select and what its ``joint`` may be.
#: ``role`` gives a role (stages 1, 2, 5-9); ``joint type`` turns a revolute into ``P`` (or rolling ``O``),
#: stage 3; ``higher pair`` marks a binary link that becomes a gear or cam pair between its two neighbours,
#: and ``force member`` a binary link (the book's ``Fp`` link) or a dyad (the equivalent chain of
#: :mod:`domes.typesynth.generalize`) that becomes a spring, cylinder or force, stage 4.
KINDS: dict[str, tuple[tuple[str, ...], tuple[str, ...]]] = {
    "role": (SELECTIONS, ()),
    "joint type": (("joint",), ("P", "O")),
    "higher pair": (("link",), tuple(t for t in JOINT_TYPES if t in HIGHER_PAIRS)),
    "force member": (("link", "adjacent pair"), tuple(t for t in JOINT_TYPES if t in ELEMENTS)),
}
#: The kinds whose links leave the chain when it is particularized (they become a joint of their neighbours).
CONVERSIONS = ("higher pair", "force member")


@dataclass(frozen=True)
class Stage:
    """One divergence stage (``role`` is given out, or a joint or link is changed) or, without a role, one screen.

    ``kind`` is one of :data:`KINDS`; a stage of another kind than ``role``
    changes the chain into ``joint`` (a joint type), and if it is ``optional``
    leaving the chain unchanged is one more choice.

    >>> Stage("cam pair", "cam", "link", (), (), (), 1, "higher pair", "C").removes
    1
    """

    name: str
    role: str  # "" for a screen and for a joint type stage
    select: str  # one of the selections of its kind (KINDS), or "screen"
    rules: tuple[Criterion, ...]
    rule_text: tuple[str, ...]
    tests: tuple[Callable, ...]  # the compiled rules (features -> bool)
    line: int
    kind: str = "role"
    joint: str = ""  # what a joint type, higher pair or force member stage makes
    optional: bool = False

    @property
    def is_screen(self) -> bool:
        return self.select == "screen"

    @property
    def is_conversion(self) -> bool:
        """Whether the links it marks become a joint of their neighbours (a higher pair or a force member)."""
        return self.kind in CONVERSIONS

    @property
    def removes(self) -> int:
        """How many links of the chain each of its choices takes out of the mechanism (0, 1 or 2)."""
        return (2 if self.select == "adjacent pair" else 1) if self.is_conversion else 0

    @property
    def tag(self) -> str:
        """What the stage changes, in short (``""`` for a role stage or a screen).

        >>> Stage("slider", "", "joint", (), (), (), 1, "joint type", "P").tag
        'R→P'
        """
        if self.kind == "role":
            return ""
        source = {"joint": "R", "link": "link", "adjacent pair": "dyad"}[self.select]
        return f"{source}→{self.joint}" + (" or none" if self.optional else "")

    def __reduce__(self):
        """Pickled without its compiled tests (closures), compiled again from the rules where it is unpickled:
        a scene can go to a worker process or machine."""
        return (_stage, (self.name, self.role, self.select, self.rules, self.rule_text, self.line, self.kind,
                         self.joint, self.optional))


def _stage(name, role, select, rules, rule_text, line, kind="role", joint="", optional=False) -> Stage:
    return Stage(name, role, select, rules, rule_text, tuple(compile_criterion(t) for t in rules), line, kind, joint,
                 optional)


@dataclass(frozen=True)
class Particularization:
    """The joint between a link of role ``between[0]`` and one of ``between[1]`` becomes ``joint``."""

    between: tuple[str, str]
    joint: str


@dataclass(frozen=True)
class SceneCheck:
    """A dimensional check the scene asks of a verified candidate: its ``usage`` (a verify check, e.g.
    ``force-ratio OUTPUT FROM:TO [RATIO]``) and ``why`` the design needs it."""

    usage: str
    why: str


@dataclass(frozen=True)
class Scene:
    """A regeneration scene (see the module doc)."""

    name: str
    title: str
    source: str
    path: str
    links: int
    dof: int
    include_fractionated: bool
    stages: tuple[Stage, ...]
    particularize: tuple[Particularization, ...]
    existing: tuple[LabelledChain, ...]
    book_counts: tuple[int | None, ...]
    book_note: str
    checks: tuple[SceneCheck, ...] = ()
    #: What a design session asks when the candidates are to be dimensioned (docs/expert.md).
    requirements: tuple[RequirementSpec, ...] = ()
    #: How the candidates are dimensioned and checked: ``{"task": ..., "checks": [...], "weights": {...}}``
    #: (a task template whose strings ``"{ID}"`` name requirements; :mod:`domes.design.brief`), or None.
    design: dict | None = None
    #: The chains are the clamping atlas's (seed 002 §3-3-I (4): immobile sub-chains admitted, any DOF).
    clamping: bool = False

    @property
    def roles(self) -> list[str]:
        """The roles the stages give out, in stage order."""
        return [s.role for s in self.stages if s.role]

    @property
    def conversions(self) -> dict[str, Stage]:
        """The roles that mark links to become a joint (higher pairs, force members), with their first stage."""
        out: dict[str, Stage] = {}
        for s in self.stages:
            if s.is_conversion:
                out.setdefault(s.role, s)
        return out

    @property
    def mechanism_links(self) -> tuple[int, int]:
        """The fewest and the most links a particularized candidate can have (:func:`mechanism_links`)."""
        return mechanism_links(self.links, self.stages)


def mechanism_links(links: int, stages: Iterable[Stage]) -> tuple[int, int]:
    """The fewest and the most links of the mechanisms that ``stages`` make of chains of ``links`` links: the
    chains' links less those turned into joints (an optional stage may turn none).

    >>> cam = Stage("cam pair", "hs", "link", (), (), (), 1, "higher pair", "C")
    >>> spring = Stage("spring", "spring", "adjacent pair", (), (), (), 1, "force member", "S", optional=True)
    >>> mechanism_links(8, [cam, spring])
    (5, 7)
    """
    stages = list(stages)
    fewest = links - sum(s.removes for s in stages)
    return fewest, fewest + sum(s.removes for s in stages if s.optional)


@dataclass(frozen=True)
class Degrees:
    """The numbers of joints the links of a scene's chains can have, and a sentence that says so."""

    values: frozenset[int]
    text: str


def impossible_degree(trees: Iterable[Criterion], degrees: Degrees) -> str | None:
    """Why the joint-count tests that rules put on the same links can never all hold, or None.

    Rules over the same vertices (every vertex, or the vertices of one role)
    must allow some number of joints that the scene's chains have.

    >>> from domes.language.parse import parse_criterion
    >>> six_bar = Degrees(frozenset({2, 3}), "every link of the 6-link chains has 2 to 3 joints")
    >>> impossible_degree([parse_criterion("the ground must be quinary")], six_bar)
    'no link can have such a number of joints (every link of the 6-link chains has 2 to 3 joints)'
    >>> rules = [parse_criterion(t) for t in ("the ground must be binary", "the ground must be ternary")]
    >>> impossible_degree(rules[:1], six_bar) is None, impossible_degree(rules, six_bar) is not None
    (True, True)
    """
    allowed: dict[str | None, set[int]] = {}
    for tree in trees:
        if not isinstance(tree, ForAll) or tree.domain.kind != "vertex":
            continue
        terms = list(tree.condition.items) if isinstance(tree.condition, And) else [tree.condition]
        keep = allowed.setdefault(tree.domain.name, set(degrees.values))
        for term in terms:
            negated = isinstance(term, Not)
            inner = term.item if negated else term
            if isinstance(inner, JointCount) and inner.joint is None:
                keep &= {d for d in degrees.values if inner.comparison(d) != negated}
    if any(not keep for keep in allowed.values()):
        return f"no link can have such a number of joints ({degrees.text})"
    return None
