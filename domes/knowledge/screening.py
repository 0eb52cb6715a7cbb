"""Multi-level screening (seed 002, §5-2 IV and §7-2): criteria applied level by level, cheap to costly.

The relevant, enabled criteria are applied in order of level (topological
ones first, kinematic ones last; within a level in knowledge-base order),
each to the candidates that are left. Every rejected candidate records the
criterion that rejected it. When a criterion eliminates the last candidates
the remaining criteria are skipped and the result names the criterion that
emptied the set (DOMES, Fig. 7-8). ``max_level`` is the screening-depth
knob: criteria above it are not applied.

>>> from domes.model import LabelledChain
>>> from domes.knowledge.frames import CriterionFrame
>>> four_bar = [(0, 1), (1, 2), (2, 3), (0, 3)]
>>> crank_rocker = LabelledChain.build(4, four_bar, roles={0: {"ground"}, 1: {"input"}})
>>> floating_input = LabelledChain.build(4, four_bar, roles={0: {"ground"}, 2: {"input"}})
>>> rule = CriterionFrame.create("input-on-ground", "the input must be adjacent to the ground")
>>> result = screen([crank_rocker, floating_input], [rule])
>>> result.kept_indices, result.rejected_by
((0,), {1: 'input-on-ground'})
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Sequence

from domes.errors import InputError
from domes.knowledge.relevance import RelevanceVector, is_relevant
from domes.language.evaluate import compile_criterion, graph_features
from domes.language.tree import Always, Relevance
from domes.model.labelled import LabelledChain, share_topologies
from domes.results import Progress, Result, Status, Ticker


@dataclass(frozen=True)
class CostlyCriterion:
    """A criterion that is a function of the candidate (e.g. a kinematic check by a later stage).

    ``check(candidate)`` is True when the candidate is kept. It is applied at
    ``level`` (4, kinematic, by default), after every cheaper criterion.
    """

    id: str
    check: Callable[[Any], bool]
    level: int = 4
    explanation: str = ""
    enabled: bool = True
    relevance: Relevance = field(default_factory=Always)


@dataclass(frozen=True)
class Rejection:
    """Candidate ``index`` (in the input order) was rejected by ``criterion`` at ``level``."""

    index: int
    criterion: str
    level: int


@dataclass(frozen=True)
class ScreeningResult(Result):
    """The outcome of :func:`screen`.

    ``kept`` are the surviving candidates (input order) and ``kept_indices``
    their positions; ``rejections`` says which criterion rejected each of
    the others; ``applied``, ``skipped`` and ``not_relevant`` list criterion
    ids; ``emptied_by`` is the criterion that eliminated the last
    candidates (None if some survive); ``levels`` gives, per level applied,
    how many candidates were left after it.
    """

    kept: tuple
    kept_indices: tuple[int, ...]
    rejections: tuple[Rejection, ...]
    applied: tuple[str, ...]
    skipped: tuple[str, ...]
    not_relevant: tuple[str, ...]
    emptied_by: str | None
    levels: tuple[tuple[int, int], ...]

    @property
    def rejected_by(self) -> dict[int, str]:
        """Candidate index -> id of the criterion that rejected it."""
        return {r.index: r.criterion for r in self.rejections}

    @property
    def status(self) -> Status:
        """COMPLETE when some candidate is kept, EMPTY when none is (``emptied_by`` says which criterion)."""
        return Status.COMPLETE if self.kept else Status.EMPTY

    @property
    def message(self) -> str:
        """One line for the designer (DOMES prints a message when every graph is eliminated)."""
        total = len(self.kept) + len(self.rejections)
        if self.emptied_by is not None:
            text = f"all {total} candidate(s) were eliminated, the last by criterion {self.emptied_by!r}"
            if self.skipped:
                text += f"; criteria {', '.join(self.skipped)} were skipped"
            return text + ". Consider other numbers of loops or gear pairs."
        return f"{len(self.kept)} of {total} candidates kept by {len(self.applied)} criteria"


def screen(
    candidates: Sequence,
    criteria: Sequence,
    problem: Any = None,
    relevance: RelevanceVector | None = None,
    max_level: int | None = None,
    progress: Progress | None = None,
) -> ScreeningResult:
    """Screen candidates (labelled graphs) by criteria, level by level; see the module docstring.

    ``criteria`` are :class:`~domes.knowledge.frames.CriterionFrame` or
    :class:`CostlyCriterion` objects; disabled ones are not applied. A
    criterion is relevant when ``relevance`` (a vector, e.g. after the
    designer's overrides) has a 1 for it, else when its relevance condition
    holds for ``problem``; with neither, every criterion is relevant.
    """
    candidates = list(candidates)
    ids = [c.id for c in criteria]
    if len(set(ids)) != len(ids):
        raise InputError("screening criteria must have distinct ids")
    chosen, not_relevant = [], []
    for position, criterion in enumerate(criteria):
        if not criterion.enabled:
            continue
        if relevance is not None:
            relevant = criterion.id in relevance.ids and relevance.bits[relevance.ids.index(criterion.id)] == 1
        else:
            relevant = problem is None or is_relevant(criterion.relevance, problem)
        if not relevant:
            not_relevant.append(criterion.id)
        elif max_level is None or criterion.level <= max_level:
            chosen.append((criterion.level, position, criterion))
    chosen.sort(key=lambda t: (t[0], t[1]))

    share_topologies(c for c in candidates if isinstance(c, LabelledChain))
    clock = Ticker(progress)
    alive = list(range(len(candidates)))
    features: dict[int, Any] = {}
    rejections: list[Rejection] = []
    applied: list[str] = []
    levels: list[tuple[int, int]] = []
    emptied_by = None
    for lvl, _, criterion in chosen:
        if not alive:
            break
        applied.append(criterion.id)
        clock.tick(lambda: f"level {lvl}, criterion {criterion.id}: {len(alive)} candidates left")
        if isinstance(criterion, CostlyCriterion):
            keep = lambda i: bool(criterion.check(candidates[i]))  # noqa: E731
        else:
            test = compile_criterion(criterion.tree)

            def keep(i: int) -> bool:
                f = features.get(i)
                if f is None:
                    f = features[i] = graph_features(candidates[i])
                return test(f)

        survivors = []
        for i in alive:
            if keep(i):
                survivors.append(i)
            else:
                rejections.append(Rejection(i, criterion.id, lvl))
        alive = survivors
        if levels and levels[-1][0] == lvl:
            levels[-1] = (lvl, len(alive))
        else:
            levels.append((lvl, len(alive)))
        if not alive:
            emptied_by = criterion.id
    skipped = tuple(c.id for _, _, c in chosen[len(applied):])
    rejections.sort(key=lambda r: r.index)
    return ScreeningResult(
        kept=tuple(candidates[i] for i in alive),
        kept_indices=tuple(alive),
        rejections=tuple(rejections),
        applied=tuple(applied),
        skipped=skipped,
        not_relevant=tuple(not_relevant),
        emptied_by=emptied_by,
        levels=tuple(levels),
    )
