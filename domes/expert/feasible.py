"""The design loop's last levels in a session: the quasi-feasible candidates dimensioned for the designer's
requirements and verified (feasibility, :mod:`domes.design.feasibility`), then ranked (:mod:`domes.design.ranking`).

The brief comes from the problem's scene: its ``[design]`` task and checks filled with the requirements
(:func:`scene_brief`). The knobs of a session (:class:`DesignKnobs`: the dimensioning's method and seeds,
where the candidates run, the time budget, where the report goes) are the command line's.

>>> DesignKnobs().method, DesignKnobs().seeds
('fast', 16)
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from domes.design.brief import DesignBrief, brief_from
from domes.design.feasibility import FEASIBLE, Feasibility, feasibility
from domes.design.ranking import Ranked, rank
from domes.errors import InputError
from domes.execution import executor
from domes.io.scenes import load_scene
from domes.model.labelled import LabelledChain
from domes.model.requirements import Requirement
from domes.results import Progress


@dataclass(frozen=True)
class DesignKnobs:
    """How the feasibility level runs: ``method`` and ``seeds`` of the dimensioning, ``workers`` or
    ``scheduler`` (Dask), ``time_budget`` (s), and the ``report`` folder (None: no report)."""

    method: str = "fast"
    seeds: int = 16
    workers: int | None = None
    scheduler: str | None = None
    time_budget: float | None = None
    report: Path | None = None


def scene_brief(scene_name: str, requirements: tuple[Requirement, ...], weights: dict | None = None) -> DesignBrief:
    """The brief of a problem: its scene's ``[design]`` filled with the answered requirements."""
    scene = load_scene(scene_name)
    if not scene.design:
        raise InputError(f"scene {scene_name!r} does not say how its candidates are dimensioned (no [design])")
    merged = {**scene.design.get("weights", {}), **(weights or {})}
    return brief_from(scene.title or scene.name, scene.design["task"], scene.design.get("checks", []),
                      {r.id: r for r in requirements}, merged)


def feasible_designs(scene_name: str, requirements, weights, kept, knobs: DesignKnobs,
                     progress: Progress | None = None) -> tuple[Feasibility, list[Ranked], tuple[dict, ...]]:
    """The feasibility level over the kept candidates (plain data with ids) and the ranking of the feasible
    ones; the records (feasible designs best first, then the others in candidate order) a case keeps."""
    brief = scene_brief(scene_name, requirements, weights)
    candidates = [(c["id"], LabelledChain.from_dict(c)) for c in kept]
    with executor(knobs.workers, knobs.scheduler) as run:
        result = feasibility(brief, candidates, method=knobs.method, seeds=knobs.seeds, executor=run,
                             time_budget=knobs.time_budget, progress=progress)
    ranking = rank([d for d in result.designs if d.status == FEASIBLE], brief.weights)
    by_id = {d.candidate: d for d in result.designs}
    records = []
    for r in ranking:
        records.append({**by_id[r.candidate].to_dict(), **{k: v for k, v in r.to_dict().items() if k != "candidate"}})
    records += [d.to_dict() for d in result.designs if d.status != FEASIBLE]
    return result, ranking, tuple(records)


def feasibility_text(result: Feasibility, ranking: list[Ranked]) -> str:
    """What the feasibility level found and how the feasible designs rank, for the terminal."""
    lines = [f"Feasibility: {result.message}."]
    for d in result.designs:
        if d.status != FEASIBLE:
            lines.append(f"  candidate {d.candidate}: {d.status}: {d.reason}")
    if ranking:
        w = ranking[0].weights
        lines.append("Ranked by a fuzzy comprehensive evaluation (weights " +
                     ", ".join(f"{k} {v:.2f}" for k, v in w.items()) + "; docs/expert.md):")
        for r in ranking:
            lines.append(f"  {r.rank}. candidate {r.candidate}: score {r.score:.3f} ({r.grade}); "
                         f"{r.explanation()}")
    return "\n".join(lines)


def weights_text(weights: dict) -> str:
    """Weights as the designer writes them: ``transmission 2, force 1``."""
    return ", ".join(f"{k} {v:g}" for k, v in weights.items() if math.isfinite(v))
