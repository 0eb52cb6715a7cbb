"""What the rules of the design expert act on: the case base, the design run, the messages.

>>> world = World(url=None, say=print)
>>> world.criterion_id("the swing arm must be adjacent to the ground")
'designer-e6fb6ac8'
"""

from __future__ import annotations

import dataclasses
import datetime as _dt
import hashlib
import re
import uuid
from typing import Callable

from domes.design.catalogue import propose
from domes.design.verify import verify as verify_mechanism
from domes.errors import DomesError
from domes.expert.dimensions import dimension_candidate
from domes.expert.facts import STRUCTURAL, Phase, Relation
from domes.expert.feasible import DesignKnobs, feasibility_text, feasible_designs
from domes.expert.paths import coupler_path_text
from domes.expert.reasoner import recognise
from domes.expert.report import report_folder, write_report
from domes.expert.run import DesignRun, design, scene_roles
from domes.io.catalogue import load_catalogue, load_heuristics
from domes.io.scenes import load_scene, scene_names
from domes.knowledge.frames import CriterionFrame
from domes.knowledge.problems import ProblemFrame
from domes.knowledge.relevance import is_relevant, relevance_vector, unavailable_names
from domes.language.render import render_relevance
from domes.language.tree import AnyOf, ClassIs, Relevance, names_used
from domes.model.mobility import SPATIAL
from domes.results import Progress
from domes.store.casebase import KnowledgeBase
from domes.typesynth.number import number_synthesis
from domes.typesynth.spatial import spatial_phrase


class World:
    """The design expert's access to the case base (one transaction per change) and the designer."""

    def __init__(self, url: str | None, say: Callable[[str], None], vary: bool = True, progress: Progress | None = None,
                 knobs: DesignKnobs | None = None):
        self.url = url
        self.say = say
        self.vary = vary
        self.progress = progress
        self.knobs = knobs or DesignKnobs()
        self.pending_requirements: list = []
        self.answered_requirements: dict = {}
        self.run_result: DesignRun | None = None
        self.shown: ProblemFrame | None = None
        self.retained: ProblemFrame | None = None
        self.added: list[str] = []
        self.relation: tuple[str, str | None] = ("different", None)
        #: Names this session in the case base's history.
        self.session_id = f"design session {uuid.uuid4().hex[:8]}"
        self.pending_criterion: str | None = None
        self.catalogue = None

    # -- the case base ---------------------------------------------------------------

    def kb(self, write: bool = False) -> KnowledgeBase:
        """The case base, for one unit of work (``write``: it will be changed); its history names this session."""
        return KnowledgeBase(self.url, write=write, actor=self.session_id)

    def solved(self) -> list[ProblemFrame]:
        with self.kb() as kb:
            return kb.problems()

    def solved_in_class(self, problem_class: str) -> list[ProblemFrame]:
        return [p for p in self.solved() if p.problem_class == problem_class]

    def case(self, case_id: str) -> ProblemFrame:
        with self.kb() as kb:
            return kb.get_problem(case_id)

    def criteria(self) -> list[CriterionFrame]:
        with self.kb() as kb:
            return kb.frames()

    def known_names(self) -> list[str]:
        """The role and loop names the knowledge base's criteria and the shipped scenes talk about."""
        names: set[str] = set()
        for frame in self.criteria():
            roles, loops = names_used(frame.tree)
            names |= set(roles) | set(loops)
        for scene in scene_names():
            names |= set(load_scene(scene).roles)
        return sorted(n.replace("_", " ") for n in names)

    def structure_of(self, case_id: str) -> dict:
        case = self.case(case_id)
        self.say(f"Taking over the structure of {case_id}: " + ", ".join(f"{k} {getattr(case, k)}" for k in STRUCTURAL))
        return {k: getattr(case, k) for k in STRUCTURAL}

    # -- answers -----------------------------------------------------------------------

    def answered(self, engine, question: str, value) -> None:
        """Turn a validated answer into facts (or a change of phase)."""
        if question == "relation":
            relation, case = value
            self.relation = (relation, case)
            engine.declare(Relation(value=relation, case=case))
        elif question == "relevance_overrides":
            vector = engine.attr("relevance_default")
            for criterion_id, bit in value:
                vector = vector.set(criterion_id, bit)
            engine.set_attr("relevance", vector)
        elif question == "more_criteria":
            if value:
                engine.ask("criterion")
            else:
                self._leave_phase(engine, "criteria")
                engine.declare(Phase(name="run"))
        elif question == "function":
            engine.set_attr("function", value)
            if value is not None:
                engine.ask("function_requirements")
        elif question == "function_requirements":
            self.propose_from_catalogue(engine.attr("function"), value)
        elif question == "requirements":
            if value:
                self.pending_requirements = list(load_scene(engine.attr("scene")).requirements)
                self.answered_requirements = {}
                self._next_requirement(engine)
            else:
                engine.set_attr("requirements", ())
        elif question.startswith("req."):
            self.answered_requirements[value.id] = value
            self._next_requirement(engine)
        elif question == "weights":
            engine.set_attr("weights", value)
            engine.set_attr("requirements", tuple(self.answered_requirements.values()))
        elif question == "criterion":
            self.pending_criterion = value
            engine.ask("criterion_scope")
        elif question == "criterion_scope":
            text, self.pending_criterion = self.pending_criterion, None
            self.add_criterion(engine, text, value)
        elif question == "verify":
            if value is None:
                self._leave_phase(engine, "verify")
                engine.declare(Phase(name="review"))
            else:
                if value[0] == "path":
                    self.match_path(value[1])
                elif value[0] == "dimension":
                    self.dimension(*value[1:])
                else:
                    self.verify(*value)
                engine.ask("verify")
        elif question == "satisfied":
            self._leave_phase(engine, "review")
            if isinstance(value, list):  # criteria relaxed (-ID) or added back (+ID): design again
                self.relax(engine, value)
                engine.declare(Phase(name="run"))
            else:
                engine.declare(Phase(name="retain" if value else "criteria"))
        else:
            engine.set_attr(question, value)

    def propose_from_catalogue(self, motion, requirements) -> None:
        """The catalogue's mechanisms for ``motion`` (seed 002 §5-1, the second class of problems), measured and
        checked against ``requirements``, ordered by the §6-1 heuristic they imply (a dwell: an exact law), said
        with the reasons; type synthesis follows for new structures."""
        found = propose(load_catalogue(), motion, requirements, heuristics=load_heuristics())
        self.catalogue = found
        self.say(f"Catalogue: {found.message}")
        for p in found:
            props = "; ".join(f"{name} {value}" for name, value in p.properties.items())
            why = f" ({'; '.join(p.reasons)})" if p.reasons else ""
            self.say(f"  {'proposed' if p.kept else 'left out'}: {p.entry.name}: {props}{why}")
            if p.advice:
                self.say(f"    why here: {p.advice}")
        if not found.proposals:
            self.say("  (no catalogue mechanism converts this motion: type synthesis below looks for new ones)")
        else:
            self.say("Type synthesis follows: new structures for the same function (answer the questions below).")

    def ask_requirements(self, engine, scene: str | None) -> None:
        """Ask whether to dimension for requirements when the scene says how (else: no requirements)."""
        found = load_scene(scene) if scene else None
        if found is not None and found.requirements and found.design:
            engine.ask("requirements")
        else:
            engine.set_attr("requirements", ())

    def _next_requirement(self, engine) -> None:
        if self.pending_requirements:
            engine.ask("req." + self.pending_requirements.pop(0).id)
        else:
            engine.ask("weights")

    def requirement_default(self, engine, spec) -> str:
        """The default answer to a requirement: a similar solved problem's, else the scene's."""
        relation, case = self.relation
        if relation == "similar" and case:
            for r in self.case(case).requirements:
                if r.id == spec.id and r.text:
                    return r.text
        return spec.default

    @staticmethod
    def _leave_phase(engine, name: str) -> None:
        for fact_id, fact in list(engine.facts.items()):
            if isinstance(fact, Phase) and fact["name"] == name:
                engine.retract(fact_id)

    # -- actions of the rules ------------------------------------------------------------

    def number_synthesis(self, engine, dof: int, loops: int, space: int, gears: int) -> None:
        try:
            numbers = number_synthesis(dof, loops, space, gears)
        except DomesError as exc:
            self.say(f"Cannot synthesize: {exc}. Please give the gear pairs again.")
            engine.retract(next(i for i, f in engine.facts.items() if f.get("name") == "gear_pairs"))
            return
        self.say(
            f"Structure rule: W = {dof}, L = {loops}, λ = {space}, j_G = {gears} "
            f"-> {numbers.links} links, {numbers.joints} joints."
        )
        engine.set_attr("links", numbers.links)
        engine.set_attr("joints", numbers.joints)

    def problem(self, engine) -> ProblemFrame:
        """The problem frame from the attributes known so far."""
        a = engine.attr
        return ProblemFrame(
            id="current",
            problem_class=a("class") or "unknown",
            outputs=a("outputs"), dof=a("dof"), space=a("space") or 3, loops=a("loops"),
            gear_pairs=a("gear_pairs"), slider_pairs=a("slider_pairs"), links=a("links"), joints=a("joints"),
            names=a("names") or frozenset(), scene=a("scene"), relevance=a("relevance"),
            requirements=tuple(a("requirements") or ()),
        )

    def recognise(self, engine) -> str | None:
        """The id of a solved problem with the same class, structure and attributes, if any."""
        problem = self.problem(engine)
        match = recognise(problem, self.solved())
        if match is not None:
            self.relation = ("same", match.id)
            self.say(f"The case base holds {match.id} with the same class, structure and attributes.")
            return match.id
        return None

    def build_relevance(self, engine) -> None:
        frames = self.criteria()
        problem = self.problem(engine)
        roles = scene_roles(problem)
        vector = relevance_vector(frames, problem, roles)
        engine.set_attr("relevance_default", vector)
        off = [f for f, bit in zip(frames, vector.bits) if not bit]
        on = [f.id for f, bit in zip(frames, vector.bits) if bit]
        self.say(f"Relevant criteria ({len(on)} of {len(frames)}): {', '.join(on) or 'none'}")
        if off:
            self.say("Irrelevant by default (you may declare them relevant with +ID, or others irrelevant with -ID):")
            for f in off:
                missing = unavailable_names(f, roles) if is_relevant(f.relevance, problem) else ()
                why = (f" [not applicable: no link or loop is given the role {', '.join(missing)}"
                       + (f" by the scene {problem.scene}]" if problem.scene else " without a scene]")) if missing else ""
                self.say(f"  {f.id}: {f.explanation}{why}")

    @staticmethod
    def criterion_id(text: str) -> str:
        """A stable id for a criterion the designer adds (the same sentence gets the same id)."""
        normal = re.sub(r"\s+", " ", text.strip().lower())
        return "designer-" + hashlib.sha1(normal.encode("utf-8")).hexdigest()[:8]

    def add_criterion(self, engine, text: str, scope: Relevance | None = None) -> None:
        """Add the designer's criterion to the knowledge base (one transaction) and to the relevance vector.

        ``scope`` is its relevance condition (default: the problem's class), so that a criterion added for one
        problem never changes the answers of another class. The same sentence added again for a problem its
        condition does not cover has its condition widened to cover it (kept in the history).
        """
        problem = self.problem(engine)
        scope = scope or ClassIs(problem.problem_class)
        frame = CriterionFrame.create(
            self.criterion_id(text), text, explanation=f"added in a design session: {text}",
            relevance=render_relevance(scope), source="design session", date=_dt.date.today().isoformat(),
        )
        why = f"added in a design session of class {problem.problem_class.replace('_', ' ')!r}"
        with self.kb(write=True) as kb:
            known = {f.id: f for f in kb.frames()}
            if frame.id not in known:
                kb.add(frame, why=why)
                self.say(f"Criterion {frame.id} added to the knowledge base, relevant when {frame.relevance_text}.")
            elif is_relevant(known[frame.id].relevance, problem):
                self.say(f"Criterion {frame.id} is already in the knowledge base, relevant when "
                         f"{known[frame.id].relevance_text}.")
            else:
                old = known[frame.id]
                wider = render_relevance(AnyOf((old.relevance, scope)))
                kb.update(old.edited(relevance=wider), why=f"used in a design session of class "
                          f"{problem.problem_class.replace('_', ' ')!r} too", action="widen relevance")
                self.say(f"Criterion {frame.id} is already in the knowledge base; its relevance is widened to: {wider}.")
        self.added.append(frame.id)
        vector = engine.attr("relevance")
        ids = list(vector.ids) + ([frame.id] if frame.id not in vector.ids else [])
        engine.set_attr("relevance", vector.aligned(ids).set(frame.id, 1))

    def run(self, engine) -> None:
        problem = self.problem(engine)
        size = (f"spatial single loops of 3 to {problem.links} links" if problem.space == SPATIAL
                else f"{problem.links} links, {problem.joints} joints")
        self.say(f"Designing: {size}, DOF {problem.dof}"
                 + (f", scene {problem.scene}" if problem.scene else "") + " ...")
        criteria = self.criteria()
        self.run_result = design(problem, criteria, problem.relevance, vary=self.vary, progress=self.progress)
        for note in self.run_result.notes:
            self.say(note)
        self.say(result_text(self.run_result, criteria))
        if problem.requirements and self.run_result.kept:
            self.feasibility(engine)
        elif self.run_result.kept:
            self.report(self.frame_of_run(engine, "not retained"))

    def feasibility(self, engine) -> None:
        """The last screening level: the kept (quasi-feasible) candidates dimensioned for the requirements,
        verified and ranked; the records join the design run."""
        run = self.run_result
        self.say(f"Dimensioning and verifying {len(run.kept)} quasi-feasible candidate(s) for the requirements "
                 f"({self.knobs.method}, {self.knobs.seeds} seeds"
                 + (f", a time budget of {self.knobs.time_budget:g} s" if self.knobs.time_budget else "") + ") ...")
        try:
            result, ranking, records = feasible_designs(run.problem.scene, run.problem.requirements,
                                                        engine.attr("weights") or {}, run.kept, self.knobs,
                                                        self.progress)
        except DomesError as exc:
            self.say(f"The candidates could not be dimensioned: {exc}")
            return
        self.say(feasibility_text(result, ranking))
        note = (f"feasibility: {len(result.feasible)} of {len(result.designs)} quasi-feasible candidate(s) feasible"
                + (f"; not finished: {', '.join(map(str, result.unfinished))}" if result.unfinished else ""))
        self.run_result = dataclasses.replace(run, designs=records, notes=run.notes + (note,))
        self.report(self.frame_of_run(engine, "not retained"))

    def frame_of_run(self, engine, case_id: str) -> ProblemFrame:
        """The problem frame of the latest design run (what :meth:`retain` keeps), under ``case_id``."""
        run = self.run_result
        vector = engine.attr("relevance")
        relation, case = self.relation
        if relation == "similar" and case:
            old = self.case(case).relevance
            if old is not None:
                vector = vector.merge(old.aligned(vector.ids))
        return dataclasses.replace(
            run.problem, id=case_id, relevance=vector, results=run.kept, rejected=run.rejected,
            mechanisms=run.mechanisms, notes=run.notes, criteria_added=tuple(self.added), designs=run.designs,
            source="design session", date=_dt.date.today().isoformat(), title=engine.attr("class") or "",
        )

    def report(self, frame: ProblemFrame) -> None:
        """Write the session's report (when asked for and candidates were kept) and say where."""
        if self.knobs.report is None or not frame.results:
            return
        folder = report_folder(self.knobs.report, frame.problem_class)
        words = {c.id: c.explanation for c in self.criteria()}
        title = load_scene(frame.scene).title if frame.scene else ""
        try:
            page = write_report(folder, frame, words, title)
        except DomesError as exc:
            self.say(f"The report could not be written: {exc}")
            return
        files = sum(d.get("status") == "feasible" for d in frame.designs)
        kept = " (the kept loops, by their joints)." if frame.space == SPATIAL else " (the kept candidates, sketched)."
        self.say(f"Report: {page}" + (f" (and a mechanism file for each of the {files} feasible designs beside it)."
                                     if files else kept))

    def verify(self, candidate: int, mech, check, path: str) -> None:
        """Run a dimensional check on a kept candidate; the result joins the design's notes."""
        try:
            text = f"verified candidate {candidate} with {path}: {verify_mechanism(mech, check).message}"
        except DomesError as exc:
            text = f"verification of candidate {candidate} with {path} failed: {exc}"
        self.say(text)
        self.run_result = dataclasses.replace(self.run_result, notes=self.run_result.notes + (text,))

    def match_path(self, path: str) -> None:
        """Which four-bars trace the wanted path in ``path``: atlas look-up, refinement, check by the backend.

        The answer joins the design's notes; the matches are drawn in ``PATH.matches.html``.
        """
        try:
            text = coupler_path_text(path, self.progress)
        except DomesError as exc:
            text = f"the wanted path {path} could not be matched: {exc}"
        self.say(text)
        self.run_result = dataclasses.replace(self.run_result, notes=self.run_result.notes + (text,))

    def dimension(self, candidate: int, chain, path: str) -> None:
        """Dimension a kept candidate for the curve task in ``path``; the best verified layout joins the case."""
        record = None
        try:
            text, record = dimension_candidate(candidate, chain, path, self.progress)
        except DomesError as exc:
            text = f"candidate {candidate} could not be dimensioned for {path}: {exc}"
        self.say(text)
        self.run_result = dataclasses.replace(
            self.run_result, notes=self.run_result.notes + (text.splitlines()[0],),
            mechanisms=self.run_result.mechanisms + ((record,) if record else ()))

    def show_stored(self, case_id: str) -> None:
        frame = self.case(case_id)
        self.shown = frame
        self.say(f"The same problem as {case_id}, solved before: its result, from the case base.")
        self.say(frame_text(frame))
        self.report(frame)

    def relax(self, engine, overrides) -> None:
        """The designer relaxes (``-ID``) or adds back (``+ID``) criteria after a run: design again."""
        vector = engine.attr("relevance")
        for criterion_id, bit in overrides:
            vector = vector.set(criterion_id, bit)
        engine.set_attr("relevance", vector)
        self.say("Designing again with " + ", ".join(f"{c} {'relevant' if b else 'irrelevant'}" for c, b in overrides) + ".")

    def retain(self, engine) -> None:
        run = self.run_result
        if not run.kept:
            self.say("Nothing was kept, so the problem is not retained as a solved case.")
            return
        frame = self.frame_of_run(engine, run.problem.problem_class.replace("_", "-"))
        with self.kb(write=True) as kb:  # the id (CLASS-N) is chosen inside the transaction that stores it
            frame = kb.retain_new(frame, why="the designer found the result satisfactory")
        self.retained = frame
        self.say(f"Retained as case {frame.id}.")
        self.report(frame)


def _roles(candidate: dict) -> str:
    """A candidate told apart from the others: its roles and special joints, then its chain (link assortment,
    joints with their types, graph6), so that two candidates with the same roles on other chains differ.

    >>> _roles({"links": [{"id": 0, "roles": ["ground"]}, {"id": 1}, {"id": 2}],
    ...         "joints": [{"links": [0, 1]}, {"links": [1, 2], "type": "P"}, {"links": [0, 2]}]})
    '0:ground 1-2:P; chain [2^3], joints 0-1 1-2P 0-2, graph6 Bw'
    """
    parts = []
    for link in candidate.get("links", []):
        if isinstance(link, dict) and link.get("roles"):
            parts.append(f"{link['id']}:{'+'.join(link['roles'])}")
    joints = candidate.get("joints", [])
    special = [f"{j['links'][0]}-{j['links'][1]}:{j['type']}" for j in joints if j.get("type", "R") != "R"]
    head = " ".join(parts + special)
    if not joints:
        return head
    links = len(candidate.get("links", [])) or 1 + max(max(j["links"]) for j in joints)
    degree = [0] * links
    for j in joints:
        for v in j["links"]:
            degree[v] += 1
    assortment = " ".join(f"{d}^{degree.count(d)}" for d in sorted(set(degree)))
    listed = " ".join(f"{j['links'][0]}-{j['links'][1]}{'' if j.get('type', 'R') == 'R' else j['type']}" for j in joints)
    return f"{head}; chain [{assortment}], joints {listed}, graph6 {_graph6(links, joints)}".lstrip("; ")


def _graph6(links: int, joints) -> str:
    """The graph6 string of the chain's graph (links as vertices, joints as edges)."""
    import networkx as nx

    graph = nx.empty_graph(links)
    graph.add_edges_from(tuple(j["links"]) for j in joints)
    return nx.to_graph6_bytes(graph, header=False).decode().strip()


def result_text(run: DesignRun, criteria=()) -> str:
    """The candidates kept, how many each criterion removed (in the designer's words), and, when every
    candidate was eliminated, which criterion to relax."""
    words = {c.id: c.explanation for c in criteria}

    def named(criterion_id: str) -> str:
        return f"{criterion_id} ({words[criterion_id]})" if words.get(criterion_id) else criterion_id

    spatial = run.problem.space == SPATIAL
    lines = [f"{len(run.kept)} of {len(run.candidates)} candidates kept ({_size(run)})."]
    for c in run.kept:
        flag = "  EXISTING" if c.get("existing") else ""
        lines.append(f"  candidate {c['id']}: {spatial_phrase(c) if spatial else _roles(c)}{flag}")
    removed: dict[str, int] = {}
    for r in run.rejected:
        removed[r["criterion"]] = removed.get(r["criterion"], 0) + 1
    for criterion, count in removed.items():
        lines.append(f"  {count} removed by {named(criterion)}")
    if run.emptied_by:
        lines.append(f"  every candidate was eliminated; {run.emptied_by} removed the last ones")
    if run.relax:
        best = ", ".join(f"without {named(c)} {k} would be kept" for c, k in run.relax[:3])
        lines.append(f"  to keep candidates, relax a criterion: {best}; answer -{run.relax[0][0]} to the question "
                     "whether the result is satisfactory, to design again without it")
    elif not run.kept and run.candidates:
        lines.append("  no single criterion left out would keep a candidate: change the loops, sliders or gear pairs")
    return "\n".join(lines)


def _size(run: DesignRun) -> str:
    """``6 links, 7 joints``; for a spatial run the sizes of its single loops (``single loops of 4 links``)."""
    if run.problem.space != SPATIAL:
        return f"{run.links} links, {run.joints} joints"
    sizes = sorted({len(c["links"]) for c in (run.kept or run.candidates)}) or [0]
    return "spatial single loops of " + (f"{sizes[0]} to {sizes[-1]}" if len(sizes) > 1 else f"{sizes[0]}") + " links"


def frame_text(frame: ProblemFrame) -> str:
    """A stored problem frame and its result."""
    spatial = frame.space == SPATIAL
    structure = (f"DOF {frame.dof}, spatial (λ = 6), {frame.loops} loop(s), {frame.slider_pairs or 0} sliders"
                 if spatial else f"DOF {frame.dof}, {frame.loops} loops, {frame.links} links, {frame.joints} joints, "
                 f"{frame.slider_pairs or 0} sliders, {frame.gear_pairs or 0} gear pairs")
    lines = [
        f"case {frame.id} ({frame.problem_class}): {structure}",
        f"  representative attributes: {', '.join(sorted(frame.names)) or 'none'}",
        f"  {len(frame.results)} candidates:",
    ]
    lines += [f"  candidate {c.get('id')}: {spatial_phrase(c) if spatial else _roles(c)}"
              f"{'  EXISTING' if c.get('existing') else ''}" for c in frame.results]
    if frame.requirements:
        lines.append("  requirements: " + "; ".join(f"{r.label or r.id} {r.shown}" for r in frame.requirements))
    ranked = sorted((d for d in frame.designs if d.get("status") == "feasible"), key=lambda d: d.get("rank", 0))
    lines += [f"  design {d['rank']}: candidate {d['candidate']}, score {d.get('score', 0):.3f} ({d.get('grade', '')})"
              for d in ranked]
    lines += [f"  candidate {d['candidate']}: {d.get('status')}: {d.get('reason', '')}" for d in frame.designs
              if d.get("status") != "feasible"]
    lines += [f"  {note}" for note in frame.notes]
    return "\n".join(lines)
