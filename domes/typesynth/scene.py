"""Design scenes as data: the rules of a regeneration, read from TOML.

A scene names the chains to start from, the stages that assign roles (each
stage gives its role to a link, or a pair of links, in every way that keeps
its ``rules`` true), screens (stages without a role: their rules filter),
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
from domes.model.labelled import LabelledChain
from domes.model.requirements import RequirementSpec

SELECTIONS = ("link", "adjacent pair", "pair")


@dataclass(frozen=True)
class Stage:
    """One divergence stage (``role`` is given out) or, without a role, one screen."""

    name: str
    role: str  # "" for a screen
    select: str  # one of SELECTIONS, or "screen"
    rules: tuple[Criterion, ...]
    rule_text: tuple[str, ...]
    tests: tuple[Callable, ...]  # the compiled rules (features -> bool)
    line: int

    @property
    def is_screen(self) -> bool:
        return self.select == "screen"

    def __reduce__(self):
        """Pickled without its compiled tests (closures), compiled again from the rules where it is unpickled:
        a scene can go to a worker process or machine."""
        return (_stage, (self.name, self.role, self.select, self.rules, self.rule_text, self.line))


def _stage(name, role, select, rules, rule_text, line) -> Stage:
    return Stage(name, role, select, rules, rule_text, tuple(compile_criterion(t) for t in rules), line)


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

    @property
    def roles(self) -> list[str]:
        """The roles the stages give out, in stage order."""
        return [s.role for s in self.stages if not s.is_screen]


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
