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
from typing import Callable

from domes.language.tree import And, Criterion, ForAll, JointCount, Not
from domes.model.labelled import LabelledChain

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


@dataclass(frozen=True)
class Particularization:
    """The joint between a link of role ``between[0]`` and one of ``between[1]`` becomes ``joint``."""

    between: tuple[str, str]
    joint: str


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

    @property
    def roles(self) -> list[str]:
        """The roles the stages give out, in stage order."""
        return [s.role for s in self.stages if not s.is_screen]


def impossible_degree(tree: Criterion, links: int) -> str | None:
    """Why a rule's joint-count tests on its links can never all hold on ``links``-link chains."""
    if not isinstance(tree, ForAll) or tree.domain.kind != "vertex":
        return None
    terms = list(tree.condition.items) if isinstance(tree.condition, And) else [tree.condition]
    allowed = set(range(2, links))
    for term in terms:
        negated = isinstance(term, Not)
        inner = term.item if negated else term
        if isinstance(inner, JointCount) and inner.joint is None:
            allowed &= {d for d in range(2, links) if inner.comparison(d) != negated}
    if not allowed:
        return f"no link of a {links}-link chain has such a number of joints (every link has 2 to {links - 1})"
    return None
