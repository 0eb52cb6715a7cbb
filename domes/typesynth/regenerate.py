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

A stage may also change the chain's elements (§3-3-II stages 3 and 4): a
``joint type`` stage turns one revolute into ``P`` (or ``O``); a ``higher pair`` or
``force member`` stage marks a binary link (or a dyad) with its role, and
particularization turns the marked links into a joint of their neighbours,
the inverse of :func:`~domes.typesynth.generalize.generalize`. Marked links
take no roles and their joints no other type, so each mechanism comes from
one labelled chain, and the same orbit analysis holds.

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
    """Counts after one stage: non-isomorphic, and raw (numbered links, ``S_i``); ``change``: what a stage of
    another kind than ``role`` changes (:attr:`~domes.typesynth.scene.Stage.tag`, e.g. ``R→P``)."""

    name: str
    count: int
    raw: int
    book: int | None = None
    change: str = ""


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
                {"name": s.name, "count": s.count, "raw": s.raw, **({"book": s.book} if s.book is not None else {}),
                 **({"change": s.change} if s.change else {})}
                for s in self.stages
            ],
            "candidates": [c.to_dict() for c in self.candidates if not (new_only and c.existing)],
        }


def _choices(chain: LabelledChain, stage: Stage, converted: frozenset[int] = frozenset()) -> list[tuple[int, ...]]:
    """Every selection (a link, a pair of links, or a joint as its two links) ``stage`` could make on ``chain``;
    ``converted``: the links marked to become joints, which no other stage may select."""
    if stage.kind == "joint type":
        return [e for e, t in zip(chain.edges, chain.joint_types) if t == "R" and not converted.intersection(e)]
    if stage.is_conversion:
        return _convertible(chain, stage.select, converted)
    if stage.select == "link":
        options = [(x,) for x in range(chain.n)]
    elif stage.select == "adjacent pair":
        options = list(chain.edges)
    else:
        options = list(combinations(range(chain.n), 2))
    return [c for c in options if not converted.intersection(c)] if converted else options


def _convertible(chain: LabelledChain, select: str, converted: frozenset[int]) -> list[tuple[int, ...]]:
    """Binary links (``select`` "link") or dyads of binary links ("adjacent pair") that can become a joint between
    their two outer neighbours: revolute joints, no role yet, and outer neighbours that are links of the mechanism
    and not yet joined (the mechanism has one joint between two links).

    >>> five_bar = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (0, 4)], roles={0: {"ground"}})
    >>> _convertible(five_bar, "link", frozenset()), _convertible(five_bar, "adjacent pair", frozenset())
    ([(1,), (2,), (3,), (4,)], [(1, 2), (2, 3), (3, 4)])
    >>> _convertible(five_bar.with_roles({0: {"ground"}, 1: {"hs"}}), "link", frozenset({1}))
    [(3,), (4,)]

    (In a four-bar the two ends of a dyad are jointed already: no dyad of it can become a spring.)
    """
    free = [not chain.roles[v] and chain.degrees[v] == 2 and v not in converted
            and all(chain.joint_type(v, w) == "R" for w in chain.neighbours[v]) for v in range(chain.n)]
    if select == "link":
        options = [((v,), tuple(chain.neighbours[v])) for v in range(chain.n) if free[v]]
    else:
        options = [((u, w), (_other(chain, u, w), _other(chain, w, u))) for u, w in chain.edges if free[u] and free[w]]
    joined = _joined(chain, converted)
    return [links for links, (a, b) in options
            if a != b and a not in converted and b not in converted and (min(a, b), max(a, b)) not in joined]


def _other(chain: LabelledChain, link: int, partner: int) -> int:
    """The neighbour of the binary ``link`` that is not ``partner``."""
    return next(x for x in chain.neighbours[link] if x != partner)


def _joined(chain: LabelledChain, converted: frozenset[int]) -> set[tuple[int, int]]:
    """The pairs of links of the mechanism that share a joint, the marked links already turned into joints."""
    out = {e for e in chain.edges if not converted.intersection(e)}
    for v in converted:
        ends = [x for x in chain.neighbours[v] if x not in converted]
        if len(ends) == 1:  # one end of a dyad: its other end is the partner's outer neighbour
            partner = next(x for x in chain.neighbours[v] if x in converted)
            ends.append(_other(chain, partner, v))
        out.add((min(ends), max(ends)))
    return out


def _converted(chain: LabelledChain, scene: Scene) -> frozenset[int]:
    """The links that carry a role of a higher pair or force member stage."""
    marks = set(scene.conversions)
    return frozenset(v for v, roles in enumerate(chain.roles) if roles & marks) if marks else frozenset()


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


def _apply(chain: LabelledChain, choice: tuple[int, ...], stage: Stage) -> LabelledChain:
    """The chain after ``stage`` made ``choice``: a role given, or a joint's type changed."""
    if stage.kind == "joint type":
        return chain.with_joint_types(stage.joint if e == choice else t for e, t in zip(chain.edges, chain.joint_types))
    return _assign(chain, choice, stage.role)


def _ruled_joints(chain: LabelledChain, scene: Scene) -> dict[int, str]:
    """The joints a ``[[particularize]]`` rule gives a type, by the roles of their links: index -> type (the
    last rule that applies)."""
    out = {}
    for i, (u, v) in enumerate(chain.edges):
        for rule in scene.particularize:
            a, b = rule.between
            if (a in chain.roles[u] and b in chain.roles[v]) or (b in chain.roles[u] and a in chain.roles[v]):
                out[i] = rule.joint
    return out


def _clashes(chain: LabelledChain, scene: Scene) -> bool:
    """Whether a joint a joint type stage changed is one a ``[[particularize]]`` rule would type as well (two
    labelled chains would then give one mechanism, so such a choice is not made)."""
    return any(chain.joint_types[i] != "R" for i in _ruled_joints(chain, scene))


def particularize(chain: LabelledChain, scene: Scene) -> LabelledChain:
    """Restore joint types from roles (e.g. the joint inside the shock absorber becomes ``P``), then turn the links
    marked by higher pair and force member stages into joints between their neighbours (:func:`contract`)."""
    types = list(chain.joint_types)
    for i, joint in _ruled_joints(chain, scene).items():
        types[i] = joint
    return contract(chain.with_joint_types(types), scene)


def contract(chain: LabelledChain, scene: Scene) -> LabelledChain:
    """The mechanism of a chain whose links carry higher pair or force member roles: each marked binary link (or
    dyad) becomes a joint of its stage's type between its two outer neighbours; the other links are numbered in
    their order. The inverse of :func:`~domes.typesynth.generalize.generalize` (Table 3-5).

    The chain of Fig. 3-28c (seed 002, §3-3-III.2): five-bar 0-1-2-3-4 and, between the driver 1 and the
    follower 4, the cam contact 5 (the ``HS`` link of the ``cam-linkage`` scene):

    >>> from domes.io.scenes import load_scene
    >>> chain = LabelledChain.build(6, [(0, 1), (0, 4), (1, 2), (1, 5), (2, 3), (3, 4), (4, 5)],
    ...                             roles={0: {"ground"}, 1: {"input"}, 5: {"hs"}})
    >>> m = contract(chain, load_scene("cam-linkage"))
    >>> m.n, [(e, t) for e, t in zip(m.edges, m.joint_types) if t != "R"]
    (5, [((1, 4), 'C')])
    """
    marks = scene.conversions
    converted = _converted(chain, scene)
    if not converted:
        return chain
    keep = [v for v in range(chain.n) if v not in converted]
    number = {v: k for k, v in enumerate(keep)}
    edges = [(number[u], number[v]) for u, v in chain.edges if u in number and v in number]
    types = [t for (u, v), t in zip(chain.edges, chain.joint_types) if u in number and v in number]
    done: set[int] = set()
    for v in sorted(converted):
        if v in done:
            continue
        group = [v] + [x for x in chain.neighbours[v] if x in converted]
        done.update(group)
        ends = [x for g in group for x in chain.neighbours[g] if x not in converted]
        role = next(r for r in sorted(chain.roles[v]) if r in marks)
        edges.append((number[ends[0]], number[ends[1]]))
        types.append(marks[role].joint)
    roles = {number[v]: chain.roles[v] for v in keep}
    return LabelledChain.build(len(keep), edges, types, roles, name=chain.name, source=chain.source)


def chain_stages(task: tuple[Scene, Graph, int]) -> list[list[tuple[LabelledChain, int, int]]]:
    """Every stage of the scene on one chain: per stage, the labelled chains kept, as ``(labelled chain, chain
    index, |Aut| of the chain)``; the unit of work a worker runs. Two labelled chains of different chains are
    never isomorphic, so duplicates are removed chain by chain."""
    scene, (n, edges), index = task
    chain = LabelledChain.build(n, edges)
    current = [(chain, index, chain.automorphisms.order)]
    out = []
    clash = bool(scene.particularize) and any(s.kind == "joint type" for s in scene.stages)
    for stage in scene.stages:
        following = []
        seen: set = set()
        for labelled, _, group_order in current:
            if stage.is_screen:
                if _keeps(labelled, stage):
                    following.append((labelled, index, group_order))
                continue
            children = [labelled] if stage.optional else []
            choices = _choices(labelled, stage, _converted(labelled, scene))
            children += [_apply(labelled, c, stage) for c in _orbit_representatives(labelled, choices)]
            for child in children:
                if _keeps(child, stage) and not (clash and _clashes(child, scene)) and child.certificate not in seen:
                    seen.add(child.certificate)
                    following.append((child, index, group_order))
        out.append(following)
        current = following
    return out


def _nothing(stage: Stage, chains: int) -> str:
    """What a stage that admits no choice on ``chains`` chains could not do, in words."""
    if stage.kind == "joint type":
        return f"no revolute joint of any of the {chains} chains so far can become {stage.joint!r}"
    if stage.is_conversion:
        what = "dyad of binary links" if stage.select == "adjacent pair" else "binary link"
        return f"no {what} of any of the {chains} chains so far can become a joint {stage.joint!r} ({stage.role!r})"
    return f"no link of any of the {chains} chains so far can be given the role {stage.role!r}"


def regenerate(scene: Scene, progress: Progress | None = None, generator: ChainGenerator | None = None,
               executor=None) -> Regeneration:
    """Run every stage of ``scene`` (see the module doc).

    ``generator`` is the :class:`~domes.typesynth.atlas.ChainGenerator` whose
    atlas the scene's chains come from (default: a new one); ``executor``
    (:mod:`domes.execution`) runs the chains in parallel, one task each; the
    result is the same.
    """
    graphs = (generator or ChainGenerator()).chains(scene.links, scene.dof, scene.include_fractionated,
                                                    scene.clamping)
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
                f"{_nothing(stage, len(current))}"
            )
        current = following
        # Each class stands for |Aut(chain)| / |Aut(labelled)| numbered assignments.
        raw = sum(order // chain.automorphisms.order for chain, _, order in current)
        book = scene.book_counts[number] if scene.book_counts else None
        results.append(StageResult(stage.name, len(current), raw, book, stage.tag))
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
