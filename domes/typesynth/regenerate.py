"""Specialization stage by stage, particularization, and recognition of existing designs.

Each stage of a scene gives one role to one link (or a pair of links) of
every partly labelled chain, in every way that keeps the stage's rules
true; a chain with no admissible choice is dropped, which is the
backtracking of Fig. 5-11 done breadth-first. Duplicates are removed
exactly: only one choice per orbit of the label-preserving automorphism
group is tried (the book's "similar links", §3-3-III.1; the rules are
invariant under those automorphisms), and the nauty certificate of every
result is checked once more.

``raw`` counts are what the same stages give without the similarity
analysis (every choice on the numbered links of each chain): the book's
divergence product ``S_i = Π n_j`` (§3-3-II), with ``n_i = raw_i / raw_{i−1}``.

>>> from domes.io.scenes import load_scene
>>> result = regenerate(load_scene("motorcycle"))
>>> [(s.name, s.count) for s in result.stages]
[('ground', 5), ('shock absorber', 4), ('swing arm', 10), ('swing arm adjacent to ground', 6)]
>>> [c.id for c in result.candidates if c.existing]
[2]
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import combinations

from domes.errors import InputError, NothingToPropose
from domes.language.evaluate import graph_features
from domes.model.chain import Chain
from domes.model.labelled import LabelledChain
from domes.results import Progress, Result, Status
from domes.typesynth.atlas import ChainGenerator, Graph
from domes.typesynth.scene import Scene, Stage


class EmptyStage(NothingToPropose):
    """A stage whose rules leave no choice on any chain (its rules cannot hold there)."""


@dataclass(frozen=True)
class StageResult:
    """Counts after one stage: non-isomorphic, and raw (numbered links, ``S_i``)."""

    name: str
    count: int
    raw: int
    book: int | None = None


@dataclass(frozen=True)
class Candidate:
    """A regenerated mechanism: the particularized labelled chain and where it came from."""

    id: int
    labelled: LabelledChain
    chain_index: int  # 1-based position of its chain in the atlas
    existing: tuple[str, ...]  # names of the existing designs it equals

    def to_dict(self) -> dict:
        return {
            "id": self.id,
            "existing": bool(self.existing),
            "existing_designs": list(self.existing),
            "chain": self.chain_index,
            **self.labelled.to_dict(),
        }


@dataclass(frozen=True)
class Regeneration(Result):
    """The result of a scene: stage counts, the final candidates, and the chains they came from.

    ``status`` is :attr:`~domes.results.Status.COMPLETE` when some candidate
    is left, :attr:`~domes.results.Status.EMPTY` when a screen removed them all.
    """

    scene: Scene
    stages: tuple[StageResult, ...]
    candidates: tuple[Candidate, ...]
    chains: tuple[Chain, ...] = ()

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.candidates else Status.EMPTY

    @property
    def message(self) -> str:
        existing = sum(1 for c in self.candidates if c.existing)
        if not self.candidates:
            last = next((s.name for s in self.stages if s.count == 0), self.stages[-1].name if self.stages else "")
            return f"no candidate left: stage {last!r} removed the last ones"
        return (f"{len(self.candidates)} candidates ({existing} existing, {len(self.candidates) - existing} new) "
                f"from {len(self.chains)} chains of {self.scene.links} links")

    def chain_name(self, index: int) -> str | None:
        """The common name (four-bar, Watt, Stephenson) of chain ``index`` (1-based), if it has one."""
        return self.chains[index - 1].common_name if 0 < index <= len(self.chains) else None

    def per_chain(self) -> dict[int, int]:
        """How many candidates each chain gave (chain index -> count)."""
        out: dict[int, int] = {}
        for c in self.candidates:
            out[c.chain_index] = out.get(c.chain_index, 0) + 1
        return dict(sorted(out.items()))

    def divergence_numbers(self) -> list[float]:
        """``n_i = S_i / S_{i−1}`` per stage (``S_0`` = the number of chains)."""
        out, previous = [], None
        for s in self.stages:
            out.append(s.raw / previous if previous else float(s.raw))
            previous = s.raw
        return out

    def to_dict(self, new_only: bool = False) -> dict:
        return {
            "scene": self.scene.name,
            "title": self.scene.title,
            "source": self.scene.source,
            "chains": {"links": self.scene.links, "dof": self.scene.dof},
            "stages": [
                {"name": s.name, "count": s.count, "raw": s.raw, **({"book": s.book} if s.book is not None else {})}
                for s in self.stages
            ],
            "candidates": [c.to_dict() for c in self.candidates if not (new_only and c.existing)],
        }


def _choices(chain: LabelledChain, stage: Stage) -> list[tuple[int, ...]]:
    """Every selection (a link, or a pair of links) ``stage`` could make on ``chain``."""
    if stage.select == "link":
        return [(x,) for x in range(chain.n)]
    if stage.select == "adjacent pair":
        return list(chain.edges)
    return list(combinations(range(chain.n), 2))


def _keeps(chain: LabelledChain, stage: Stage) -> bool:
    """Whether the stage's rules hold on ``chain``."""
    if not stage.tests:
        return True
    features = graph_features(chain)
    return all(test(features) for test in stage.tests)


def _orbit_representatives(chain: LabelledChain, choices: list[tuple[int, ...]]) -> list[tuple[int, ...]]:
    if len(choices) <= 1:
        return choices
    group = chain.automorphisms
    if len(choices[0]) == 2:
        return [tuple(p) for p in group.pair_orbit_representatives(choices)]
    seen, reps = set(), []
    for (x,) in choices:
        if group.orbit_of[x] not in seen:
            seen.add(group.orbit_of[x])
            reps.append((x,))
    return reps


def _assign(chain: LabelledChain, links: tuple[int, ...], role: str) -> LabelledChain:
    roles = {v: set(r) for v, r in enumerate(chain.roles)}
    for v in links:
        roles[v].add(role)
    return chain.with_roles(roles)


def particularize(chain: LabelledChain, scene: Scene) -> LabelledChain:
    """Restore joint types from roles (e.g. the joint inside the shock absorber becomes ``P``)."""
    types = list(chain.joint_types)
    for rule in scene.particularize:
        a, b = rule.between
        for i, (u, v) in enumerate(chain.edges):
            if (a in chain.roles[u] and b in chain.roles[v]) or (b in chain.roles[u] and a in chain.roles[v]):
                types[i] = rule.joint
    return chain.with_joint_types(types)


def chain_stages(task: tuple[Scene, Graph, int]) -> list[list[tuple[LabelledChain, int, int]]]:
    """Every stage of the scene on one chain: per stage, the labelled chains kept, as ``(labelled chain, chain
    index, |Aut| of the chain)``; the unit of work a worker runs. Two labelled chains of different chains are
    never isomorphic, so duplicates are removed chain by chain."""
    scene, (n, edges), index = task
    chain = LabelledChain.build(n, edges)
    current = [(chain, index, chain.automorphisms.order)]
    out = []
    for stage in scene.stages:
        following = []
        seen: set = set()
        for labelled, _, group_order in current:
            if stage.is_screen:
                if _keeps(labelled, stage):
                    following.append((labelled, index, group_order))
                continue
            for links in _orbit_representatives(labelled, _choices(labelled, stage)):
                child = _assign(labelled, links, stage.role)
                if _keeps(child, stage) and child.certificate not in seen:
                    seen.add(child.certificate)
                    following.append((child, index, group_order))
        out.append(following)
        current = following
    return out


def regenerate(scene: Scene, progress: Progress | None = None, generator: ChainGenerator | None = None,
               executor=None) -> Regeneration:
    """Run every stage of ``scene`` (see the module doc).

    ``generator`` is the :class:`~domes.typesynth.atlas.ChainGenerator` whose
    atlas the scene's chains come from (default: a new one); ``executor``
    (:mod:`domes.execution`) runs the chains in parallel, one task each; the
    result is the same.
    """
    graphs = (generator or ChainGenerator()).chains(scene.links, scene.dof, scene.include_fractionated)
    if not graphs:
        raise InputError(f"scene {scene.name!r}: there are no chains with {scene.links} links and DOF {scene.dof}")
    chains = tuple(Chain(n, edges) for n, edges in graphs)
    tasks = [(scene, graph, index) for index, graph in enumerate(graphs, 1)]
    per_chain = executor.map(chain_stages, tasks) if executor is not None else [chain_stages(t) for t in tasks]
    results = []
    current: list = list(graphs)
    for number, stage in enumerate(scene.stages):
        following = [item for stages in per_chain for item in stages[number]]
        if not following and current and not stage.is_screen:
            raise EmptyStage(
                f"{scene.path}:{stage.line}: stage {number + 1} ({stage.name}): its rules cannot hold: "
                f"no link of any of the {len(current)} chains so far can be given the role {stage.role!r}"
            )
        current = following
        # Each class stands for |Aut(chain)| / |Aut(labelled)| numbered assignments.
        raw = sum(order // chain.automorphisms.order for chain, _, order in current)
        book = scene.book_counts[number] if scene.book_counts else None
        results.append(StageResult(stage.name, len(current), raw, book))
        if progress:
            progress(f"stage {number + 1}/{len(scene.stages)} {stage.name}: {len(current)} (raw {raw})")
    scene_roles = set(scene.roles)
    known = [(m.name, m.with_roles({v: r & scene_roles for v, r in enumerate(m.roles)}).certificate)
             for m in scene.existing]
    candidates = []
    ordered = sorted(current, key=lambda item: (item[1], item[0].certificate))
    for number, (chain, index, _) in enumerate(ordered, 1):
        mechanism = particularize(chain, scene)
        existing = tuple(name for name, cert in known if cert == mechanism.certificate)
        candidates.append(Candidate(number, mechanism, index, existing))
    return Regeneration(scene, tuple(results), tuple(candidates), chains)
