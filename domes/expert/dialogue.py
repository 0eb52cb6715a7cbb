"""The design session: asks the engine's questions, validates every answer, records the dialogue.

Answers come from the terminal, from a scripted list (an answers file or a
transcript), or from a scripted list and then the terminal (resuming an
interrupted session). A bad answer is never fatal: the reason is shown and
the question asked again (in a script, the next line must answer it).

The answers files and transcripts are read and written by
:mod:`domes.io.transcripts`.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable

from domes.errors import DomesError, InputError
from domes.expert.engine import DesignExpert
from domes.expert.feasible import DesignKnobs
from domes.expert.questions import (
    HELP,
    STATIC,
    Question,
    names_help,
    overrides_parser,
    parse_names,
    parse_scene_answer,
    parse_weights,
    parse_yes_no,
    relation_parser,
    requirement_parser,
    satisfied_parser,
    scope_parser,
    verify_parser,
)
from domes.expert.world import World
from domes.io.scenes import load_scene, scene_names
from domes.io.transcripts import TRANSCRIPT_FORMAT
from domes.knowledge.problems import ProblemFrame
from domes.model.labelled import LabelledChain
from domes.model.mobility import SPATIAL
from domes.results import Progress
from domes.typesynth.spatial import loop_reading


@dataclass
class Outcome:
    """How a session ended: the relation, the frame shown or retained, and every exchange."""

    relation: str
    case: str | None
    frame: ProblemFrame | None
    exchanges: list[dict] = field(default_factory=list)
    #: The dimensioning's knobs the session ran with (a replay runs with the same).
    knobs: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        """The transcript: answers, outcome and frame, as plain data (:func:`domes.io.transcripts.write_transcript`)."""
        out = {
            "format": TRANSCRIPT_FORMAT,
            "relation": self.relation,
            "case": self.case,
            "exchanges": self.exchanges,
            "frame": self.frame.to_dict() if self.frame else None,
        }
        if self.knobs:
            out["knobs"] = dict(self.knobs)
        return out


class Dialogue:
    """One design dialogue against a case base (``url``: SQLAlchemy URL or path; None: the default)."""

    def __init__(
        self,
        url: str | None = None,
        answers: list[tuple[str, str]] | None = None,
        interactive: bool = True,
        out: Callable[[str], None] | None = None,
        read: Callable[[str], str] = input,
        vary: bool = True,
        progress: Progress | None = None,
        knobs: DesignKnobs | None = None,
    ):
        self.say = out or (lambda text: print(text, flush=True))
        self.script = list(answers or [])
        self.used = 0
        self.interactive = interactive
        self.read = read
        self.world = World(url, self.say, vary=vary, progress=progress, knobs=knobs)
        self.exchanges: list[dict] = []

    # -- questions -----------------------------------------------------------------------

    def question(self, engine: DesignExpert, qid: str) -> Question:
        if qid in STATIC:
            return STATIC[qid]
        if qid == "names":
            return Question("names", "Representative attributes and special links, comma separated (or none; '?' lists "
                            "the names the criteria know)", parse_names, "none", names_help(self.world.known_names()))
        if qid == "satisfied":
            ids = list(engine.attr("relevance").ids)
            return Question("satisfied", "Is the result satisfactory? (yes/no; 'rejected' lists the rejected candidates; "
                            "-ID relaxes a criterion and designs again)", satisfied_parser(ids), "yes", HELP["satisfied"])
        if qid == "relation":
            cases = self.world.solved_in_class(engine.attr("class"))
            self.say(f"Solved problems of class {engine.attr('class')!r}:")
            for c in cases:
                if c.space == SPATIAL:
                    self.say(f"  {c.id}: {spatial_case_text(c)}; attributes {', '.join(sorted(c.names)) or 'none'}")
                    continue
                self.say(f"  {c.id}: DOF {c.dof}, {c.loops} loops, {c.links} links, {c.joints} joints, "
                         f"{c.slider_pairs or 0} sliders, {c.gear_pairs or 0} gear pairs; "
                         f"attributes {', '.join(sorted(c.names)) or 'none'}")
            ids = [c.id for c in cases]
            return Question("relation", "Is your problem the same as, similar to, or different from one of these? "
                            "(same ID / similar ID / different)", relation_parser(ids), f"same {ids[-1]}", HELP["relation"])
        if qid == "scene":
            problem_class = engine.attr("class") or ""
            _, case = self.world.relation
            default = self.world.case(case).scene if case else None
            slug = problem_class.replace("_", "-")
            known = scene_names()
            default = default or next((s for s in known if slug == s or slug.startswith(s)), None)
            return Question("scene", f"Scene whose rules give the links their roles ({', '.join(known)}, a FILE.toml, or none)",
                            parse_scene_answer, default or "none", HELP["scene"])
        if qid == "verify":
            kept = {c["id"]: LabelledChain.from_dict(c) for c in self.world.run_result.kept}
            asks = _scene_checks(engine.attr("scene"))
            if self.world.run_result.problem.space == SPATIAL:
                asks += (" The checks are of planar mechanisms: a spatial candidate is dimensioned by domes synthesize "
                         "(an RSSR or RCCC task, docs/spatial.md).")
            return Question("verify", "Verify dimensions? (none; CANDIDATE FILE.json CHECK, CHECK is rotatability, "
                            "range OUTPUT FROM:TO, force-ratio OUTPUT FROM:TO [RATIO], wheel-rate POINT SPRING FROM:TO "
                            "or drive FROM:TO; path POINTS.csv: which four-bar traces it?; or dimension CANDIDATE "
                            "TASK.json: dimensions for a wanted curve)" + asks,
                            verify_parser(kept), "none", HELP["verify"])
        if qid == "requirements":
            scene = load_scene(engine.attr("scene"))
            asked = ", ".join(r.label for r in scene.requirements)
            return Question("requirements", f"Dimension, verify and rank the candidates for your requirements? (yes/no; "
                            f"the {scene.name} scene asks: {asked})", parse_yes_no, "yes", HELP["requirements"],
                            optional_in_scripts=True, script_default="no")
        if qid.startswith("req."):
            spec = next(r for r in load_scene(engine.attr("scene")).requirements if r.id == qid[4:])
            unit = f" ({spec.unit})" if spec.unit and spec.unit != "1" else ""
            return Question(qid, f"Requirement: {spec.label}{unit}", requirement_parser(spec),
                            self.world.requirement_default(engine, spec),
                            (spec.help + " " if spec.help else "") + f"Answer {spec.example()}; any unit of the same "
                            "kind is taken (mm or m, deg or rad, N/mm or N/m).", optional_in_scripts=True)
        if qid == "weights":
            return Question("weights", "Weights of the ranking (default, or e.g. 'transmission 2, force 3')",
                            parse_weights, "default", HELP["weights"], optional_in_scripts=True)
        if qid == "criterion_scope":
            problem_class = engine.attr("class") or ""
            shown = problem_class.replace("_", " ")
            return Question("criterion_scope", f"Relevant to which problems? class (the problem class is “{shown}”), "
                            "always, or a relevance condition", scope_parser(problem_class), "class",
                            HELP["criterion_scope"], optional_in_scripts=True)
        if qid == "relevance_overrides":
            ids = list(engine.attr("relevance_default").ids)
            return Question("relevance_overrides", "Override relevance? (none, or criterion ids: ID or +ID relevant, -ID irrelevant)",
                            overrides_parser(ids), "none", HELP["relevance_overrides"])
        raise InputError(f"the engine asked an unknown question {qid!r}")

    def answer(self, engine: DesignExpert, q: Question):
        """Ask until an answer is valid; return its value."""
        while True:
            text = self._next(q)
            if text == "" and q.default is not None:
                text = q.default
            if q.id == "satisfied" and text.strip().lower() == "rejected":
                self._record(q, text, True)
                self.say(rejected_text(self.world))
                continue
            if text.strip().lower() in ("?", "help"):
                self._record(q, text, True)
                self.say(q.help or f"Answer: {q.prompt}")
                continue
            try:
                value = q.parse(text)
            except DomesError as exc:
                self._record(q, text, False, str(exc))
                self.say(f"  not accepted: {exc}")
                continue
            self._record(q, text, True)
            return value

    def _next(self, q: Question) -> str:
        prompt = f"{q.prompt}" + (f" [{q.default}]" if q.default is not None else "") + ": "
        if self.used < len(self.script) and self.script[self.used][0] == "relation" and q.id != "relation":
            # answers that say how the problem relates to solved ones, run where its class is new: not needed
            self.used += 1
            self.say(f"  (the answers say 'relation: {self.script[self.used - 1][1]}', but the class is new: not needed)")
        if self.used < len(self.script) or (not self.interactive and q.optional_in_scripts):
            question, text = self.script[self.used] if self.used < len(self.script) else ("", "")
            if question != q.id and q.id == "relation":
                # answers written for a new problem, run where its class is known: a different problem
                self.say(prompt + "different")
                self.say("  (the answers do not say how the problem relates to the solved ones: a different problem)")
                return "different"
            if question != q.id and q.optional_in_scripts:
                taken = q.default if q.script_default is None else q.script_default
                self.say(prompt + (taken or ""))
                self.say(f"  (the answers do not answer {q.id!r}: {taken!r})")
                return taken or ""
            self.used += 1
            if question != q.id:
                raise InputError(f"answer {self.used} is for {question!r}, but the question is {q.id!r} ({q.prompt})")
            self.say(prompt + text)
            return text
        if not self.interactive:
            raise InputError(f"the answers ended before the question {q.id!r} ({q.prompt})")
        return self.read(prompt)

    def _record(self, q: Question, text: str, accepted: bool, reason: str = "") -> None:
        entry = {"question": q.id, "prompt": q.prompt, "answer": text}
        if not accepted:
            entry["rejected"] = reason
        self.exchanges.append(entry)

    # -- the dialogue ------------------------------------------------------------------

    def run(self) -> Outcome:
        engine = DesignExpert(self.world)
        engine.reset()
        engine.run()
        while engine.pending:
            q = self.question(engine, engine.pending)
            engine.answer(q.id, self.answer(engine, q))
            engine.run()
        relation, case = self.world.relation
        frame = self.world.retained or self.world.shown
        if frame is None and (self.world.run_result is None or self.world.run_result.kept):
            known = sorted(str(f.get("name", f.get("id", ""))) for f in engine.facts.values() if hasattr(f, "get"))
            raise InputError(f"the design dialogue stopped without a result (known: {', '.join(known)})")
        if self.world.shown is not None:
            relation, case = "same", self.world.shown.id
        left = self.script[self.used:]
        if left:
            first = f"{left[0][0]}: {left[0][1]}"
            self.say(f"({len(left)} answer(s) not needed, from '{first}' on: the dialogue ended before those questions)")
        knobs = {}
        if frame is not None and frame.designs:
            knobs = {"method": self.world.knobs.method, "seeds": self.world.knobs.seeds}
        return Outcome(relation, case, frame, self.exchanges, knobs)


def rejected_text(world: World) -> str:
    run = world.run_result
    if run is None or not run.rejected:
        return "No candidate was rejected."
    words = {f.id: f.explanation for f in world.criteria()}
    lines = [f"{len(run.rejected)} rejected candidates:"]
    spatial = {c["id"]: _joints(c) for c in run.candidates} if run.problem.space == SPATIAL else {}
    for r in run.rejected:
        why = f" ({words[r['criterion']]})" if words.get(r["criterion"]) else ""
        shown = f" ({spatial[r['candidate']]})" if r["candidate"] in spatial else ""
        lines.append(f"  candidate {r['candidate']}{shown}: rejected by {r['criterion']}{why} (level {r['level']}): "
                     f"{r['reason']}")
    return "\n".join(lines)


def _joints(candidate: dict) -> str:
    """``4 links: R-S-S-R``: a spatial candidate's links and joints, read from the input joint."""
    joints = loop_reading(candidate)
    n = len(candidate.get("links", ()))
    return f"{n} links: " + ("-".join(joints) if joints else "not a single loop with a frame, input and output")


def spatial_case_text(case: ProblemFrame) -> str:
    """A solved spatial problem in one line: its DOF, its loop and its kept candidates' joints.

    >>> from domes.typesynth.spatial import FunctionGenerator, SpatialLoop
    >>> rssr = FunctionGenerator("RSSR", SpatialLoop("RRSS")).labelled().to_dict()
    >>> frame = ProblemFrame("s-1", "s", dof=1, space=6, loops=1, links=7, joints=7, results=({"id": 4, **rssr},))
    >>> spatial_case_text(frame)
    'DOF 1, spatial (λ = 6), 1 loop, 0 sliders; 1 candidate kept: R-S-S-R'
    """
    kept = [_joints(c).split(": ")[-1] for c in case.results]
    loops = f"{case.loops} loop{'' if case.loops == 1 else 's'}"
    return (f"DOF {case.dof}, spatial (λ = 6), {loops}, {case.slider_pairs or 0} sliders; "
            f"{len(kept)} candidate{'' if len(kept) == 1 else 's'} kept" + (f": {', '.join(kept)}" if kept else ""))


def _scene_checks(scene: str | None) -> str:
    """The checks the scene asks for, as a sentence for the verify question ('' without a scene or checks)."""
    if not scene or scene == "none":
        return ""
    try:
        checks = load_scene(scene).checks
    except DomesError:
        return ""
    if not checks:
        return ""
    return " The scene asks for: " + "; ".join(f"{c.usage} ({c.why})" for c in checks) + "."
