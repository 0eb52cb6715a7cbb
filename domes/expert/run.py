"""The design run: from a problem frame to screened candidates (DOMES §7-2, Fig. 7-8).

1. number synthesis: links and joints from W, L, λ and j_G (the MECXPRT
   structure rule, e.g. the pump of §7-1: W = 1, three loops, R and P joints
   only -> 8 links, 10 joints);
2. the unlabelled chains of that size from the atlas;
3. labelled graphs: the scene's stages give the links their roles (Yan's
   regeneration) when the problem names a scene; otherwise the sliders and
   gear pairs are placed on the joints in every non-isomorphic way (DOMES's
   labelled-graph generator);
4. multi-level screening by the relevant criteria, every rejection with its
   criterion and reason;
5. if every candidate is eliminated, the independent loops and then the gear
   pairs are varied and the run repeated, saying so (§7-2 step 3); if every
   variation fails too, the result (with its rejections) is that of the
   problem as stated.

A spatial problem (λ = 6) of one loop and DOF 1 takes its candidates from
the single-loop spatial chains instead (:func:`spatial_candidates`).

Gear pairs: the chains are the revolute atlas of DOF ``W − j_G`` with
``j_G`` joints typed ``G``; a gear pair removes one DOF where a revolute
removes two, so these chains stay non-degenerate. Chains whose only rigid
sub-chains contain gear pairs (some epicyclic trains) are not generated.

>>> from domes.knowledge.problems import ProblemFrame
>>> run = design(ProblemFrame("p", "four-bar slider", dof=1, loops=1, gear_pairs=0, slider_pairs=1), [])
>>> run.links, run.joints, len(run.kept)
(4, 4, 1)
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from domes.errors import DomesError, InputError
from domes.io.scenes import load_scene
from domes.knowledge.problems import ProblemFrame
from domes.knowledge.relevance import RelevanceVector, relevance_vector
from domes.knowledge.screening import screen
from domes.language.explain import explain
from domes.model.labelled import LabelledChain
from domes.model.mobility import SPATIAL, mobility
from domes.results import Progress, Result, Status
from domes.typesynth.atlas import ChainGenerator
from domes.typesynth.labelling import label_joints
from domes.typesynth.number import number_synthesis
from domes.typesynth.regenerate import EmptyStage, regenerate
from domes.typesynth.spatial import function_generators, spatial_loops

#: How far the design varies the problem when every candidate is eliminated: (extra loops, extra gear pairs).
VARIATIONS = ((1, 0), (2, 0), (0, 1), (1, 1))
#: Variations are not tried beyond this many links (the labelled atlases grow about 30-fold per loop).
MAX_VARIED_LINKS = 10


@dataclass(frozen=True)
class DesignRun(Result):
    """The outcome of one design: candidates kept, rejected (with criterion and reason), and what was tried.

    ``status`` is COMPLETE when some candidate is kept, EMPTY when none is.
    """

    problem: ProblemFrame  # as run (links and joints filled in; loops and gear pairs as finally used)
    links: int
    joints: int
    candidates: tuple[dict, ...]  # every candidate generated, as plain data with an "id"
    kept: tuple[dict, ...]
    rejected: tuple[dict, ...]  # {"candidate", "criterion", "level", "reason"}
    applied: tuple[str, ...]
    emptied_by: str | None
    notes: tuple[str, ...]
    #: When every candidate is eliminated: (criterion, candidates kept without it), most first.
    relax: tuple[tuple[str, int], ...] = ()
    #: Verified dimensioned mechanisms of kept candidates (``dimension`` answers), kept with the case.
    mechanisms: tuple[dict, ...] = ()
    #: The feasibility level and the ranking (:mod:`domes.expert.feasible`): one record per kept candidate.
    designs: tuple[dict, ...] = ()

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.kept else Status.EMPTY

    @property
    def message(self) -> str:
        text = f"{len(self.kept)} of {len(self.candidates)} candidates kept ({self.links} links, {self.joints} joints)"
        return text + (f"; {self.emptied_by} removed the last ones" if self.emptied_by else "")


def candidates_for(problem: ProblemFrame, links: int, joints: int, generator: ChainGenerator | None = None,
                   progress: Progress | None = None) -> list[tuple[LabelledChain, dict]]:
    """The labelled candidates of a problem and, for each, plain data about its origin.

    ``generator`` keeps the chain atlases between the attempts of one design.
    """
    generator = generator or ChainGenerator()
    chain_dof = mobility(links, joints)
    if problem.scene:
        scene = load_scene(problem.scene)
        if (scene.links, scene.dof) != (links, chain_dof):
            scene = dataclasses.replace(
                scene, links=links, dof=chain_dof, existing=tuple(m for m in scene.existing if m.n == links)
            )
        try:
            result = regenerate(scene, progress, generator)
        except EmptyStage:
            return []
        return [(c.labelled, {"chain": c.chain_index, "existing": list(c.existing)}) for c in result.candidates]
    if chain_dof < 0:
        return []
    chains = [LabelledChain.build(n, edges) for n, edges in generator.chains(links, chain_dof)]
    counts = {t: k for t, k in (("P", problem.slider_pairs or 0), ("G", problem.gear_pairs or 0)) if k}
    return [(labelled, {}) for labelled in label_joints(chains, counts, progress=progress)]


def _attempt(problem: ProblemFrame, criteria, relevance: RelevanceVector | None,
             generator: ChainGenerator, progress: Progress | None = None) -> DesignRun:
    numbers = number_synthesis(problem.dof, problem.loops, problem.space, problem.gear_pairs or 0)
    notes: tuple[str, ...] = ()
    if problem.space == SPATIAL:
        generated, note = spatial_candidates(problem)
        notes = (note,)
    else:
        generated = candidates_for(problem, numbers.links, numbers.joints, generator, progress)
    records = [{"id": i, **extra, **chain.to_dict()} for i, (chain, extra) in enumerate(generated, 1)]
    graphs = [chain for chain, _ in generated]
    result = screen(graphs, criteria, problem, relevance=relevance, progress=progress)
    by_id = {c.id: c for c in criteria}
    rejected = tuple(
        {
            "candidate": r.index + 1,
            "criterion": r.criterion,
            "level": r.level,
            "reason": explain(by_id[r.criterion].tree, generated[r.index][0]) or "",
        }
        for r in result.rejections
    )
    solved = dataclasses.replace(problem, links=numbers.links, joints=numbers.joints)
    relax = () if result.kept else _relaxations(graphs, [by_id[i] for i in result.applied + result.skipped],
                                                problem, relevance)
    return DesignRun(
        solved, numbers.links, numbers.joints, tuple(records), tuple(records[i] for i in result.kept_indices),
        rejected, result.applied, result.emptied_by, notes, relax,
    )


def spatial_candidates(problem: ProblemFrame) -> tuple[list[tuple[LabelledChain, dict]], str]:
    """The candidates of a spatial problem (λ = 6) and a note saying what they are.

    A single loop of DOF 1 (``domes.typesynth.spatial``): every loop of 3 to
    7 links with R, P, H, C and S joints, made a function generator in every
    way (a frame link, its neighbours the input, jointed by R, P or H, and the
    output, by R, P, H or C), with as many P joints as the problem's slider
    pairs. Other spatial problems get no candidate and a note saying why.

    >>> from domes.knowledge.problems import ProblemFrame
    >>> found, note = spatial_candidates(ProblemFrame("p", "spatial", dof=1, space=6, loops=1, slider_pairs=0))
    >>> len(found), {"RSSR", "RCCC"} <= {chain.name for chain, _ in found}
    (406, True)
    """
    why = None
    if problem.loops != 1 or problem.dof != 1:
        why = (f"spatial type synthesis makes single loops (L = 1) of DOF 1; W = {problem.dof}, L = {problem.loops} "
               "get no candidate (domes chains --spatial lists single loops of any DOF)")
    elif problem.gear_pairs:
        why = f"a spatial loop here has R, P, H, C and S joints, no gear pair; j_G = {problem.gear_pairs} gets no candidate"
    elif problem.scene:
        why = f"the scene {problem.scene} regenerates planar chains; a spatial problem takes no scene"
    if why:
        return [], why
    largest = problem.dof + SPATIAL
    found = []
    for links in range(3, largest + 1):
        for gen in function_generators(spatial_loops(links, problem.dof)):
            if problem.slider_pairs is None or gen.joints.count("P") == problem.slider_pairs:
                found.append((gen.labelled(), {}))
    sliders = "any number of" if problem.slider_pairs is None else str(problem.slider_pairs)
    return found, (
        f"spatial, one loop: {len(found)} function generators (a frame, the input and the output jointed to it; "
        f"input joint R, P or H, output joint R, P, H or C) of the single loops of 3 to {largest} links with R, P, "
        f"H, C and S joints and {sliders} P joint(s), DOF 1 by Kutzbach less the idle spins of links held by two S "
        f"joints, loops whose joints cannot all move left out (docs/spatial.md); the structure rule's "
        f"{largest} links hold for one-freedom joints. Screening applies the criteria to the chain's graph, roles "
        "and joint types (Cyl, Sph, Hel); the spatial criteria are those of knowledge/criteria/05-spatial.toml"
    )


def _relaxations(graphs, criteria, problem, relevance) -> tuple[tuple[str, int], ...]:
    """For each criterion that was applied, how many candidates every other one would keep (those > 0, most first)."""
    if not graphs:
        return ()
    found = []
    for criterion in criteria:
        others = [c for c in criteria if c.id != criterion.id]
        kept = len(screen(graphs, others, problem, relevance=relevance).kept)
        if kept:
            found.append((criterion.id, kept))
    return tuple(sorted(found, key=lambda item: -item[1]))


def scene_roles(problem: ProblemFrame) -> tuple[str, ...]:
    """The roles the candidates of ``problem`` can carry: its scene's; a spatial problem's function generators'
    (the frame, the input and the output); none otherwise."""
    if problem.scene:
        return tuple(load_scene(problem.scene).roles)
    return ("ground", "input", "output") if problem.space == SPATIAL else ()


def outcome_text(run: DesignRun) -> str:
    """One line: how many candidates were kept, or which criterion emptied the set."""
    if run.kept:
        return f"{len(run.kept)} of {len(run.candidates)} candidates kept"
    if not run.candidates:
        return "no candidate could be generated"
    return f"all {len(run.candidates)} candidates eliminated, the last ones by criterion {run.emptied_by!r}"


def design(
    problem: ProblemFrame,
    criteria,
    relevance: RelevanceVector | None = None,
    vary: bool = True,
    max_links: int = MAX_VARIED_LINKS,
    progress: Progress | None = None,
) -> DesignRun:
    """Generate, label and screen the candidates of ``problem`` (see the module doc).

    ``criteria`` are the knowledge base's frames; ``relevance`` the problem's
    vector (None: each criterion's own relevance condition decides). When
    everything is eliminated and ``vary`` is set, the variations of
    :data:`VARIATIONS` are tried, up to ``max_links`` links (the knob). Without
    a vector, a criterion about roles no candidate can carry (none without a
    scene) is not relevant (:func:`~domes.knowledge.relevance.relevance_vector`).
    """
    for key in ("dof", "loops"):
        if getattr(problem, key) is None:
            raise InputError(f"the problem does not state its {key}: a design needs DOF and independent loops")
    if relevance is None:
        relevance = relevance_vector(criteria, problem, scene_roles(problem))
    generator = ChainGenerator(progress=progress)
    first = run = _attempt(problem, criteria, relevance, generator, progress)
    notes = []
    if run.kept or not vary or problem.space == SPATIAL:  # spatial: single loops only, nothing to vary
        return run
    for extra_loops, extra_gears in VARIATIONS:
        why = (
            f"criterion {run.emptied_by!r} eliminated the last candidate" if run.emptied_by
            else "no candidate could be generated"
        )
        varied = dataclasses.replace(
            problem, loops=problem.loops + extra_loops, gear_pairs=(problem.gear_pairs or 0) + extra_gears
        )
        size = number_synthesis(varied.dof, varied.loops, varied.space, varied.gear_pairs).links
        if size > max_links:
            notes.append(f"{varied.loops} loops and {varied.gear_pairs} gear pairs not tried: {size} links is beyond {max_links}")
            continue
        notes.append(
            f"with {run.problem.loops} loops and {run.problem.gear_pairs or 0} gear pairs ({run.links} links, "
            f"{run.joints} joints) {why}; trying {varied.loops} loops and {varied.gear_pairs} gear pairs"
        )
        try:
            run = _attempt(varied, criteria, relevance, generator, progress)
        except DomesError as exc:
            notes.append(f"{varied.loops} loops and {varied.gear_pairs} gear pairs: {exc}")
            continue
        notes.append(f"{varied.loops} loops and {varied.gear_pairs} gear pairs ({run.links} links, "
                     f"{run.joints} joints): {outcome_text(run)}")
        if run.kept:
            break
    else:
        notes.append("every variation was eliminated too; the result is that of the problem as stated")
        run = first
    return dataclasses.replace(run, notes=tuple(notes))
