"""The design session: asks the engine's questions, validates every answer, records the dialogue.

Answers come from the terminal, from a scripted list (an answers file or a
transcript), or from a scripted list and then the terminal (resuming an
interrupted session). A bad answer is never fatal: the reason is shown and
the question asked again (in a script, the next line must answer it).

Answers file format: one ``question: answer`` per line (``#`` comments);
see ``examples/design/*.answers``.

>>> parse_answers("# motorcycle\\nclass: motorcycle rear suspension\\ndof: 1\\n")
[('class', 'motorcycle rear suspension'), ('dof', '1')]
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from domes.errors import DomesError, InputError
from domes.expert.engine import DesignExpert
from domes.expert.questions import STATIC, Question, overrides_parser, parse_scene, relation_parser, verify_parser
from domes.model.labelled import LabelledChain
from domes.expert.world import World
from domes.knowledge.problems import ProblemFrame
from domes.io.topology import write_atomic
from domes.typesynth.scene import scene_names

TRANSCRIPT_FORMAT = "domes-design-transcript/1"


def parse_answers(text: str, where: str = "answers") -> list[tuple[str, str]]:
    """``question: answer`` lines (comments and blank lines skipped)."""
    out = []
    for number, line in enumerate(text.splitlines(), 1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        if ":" not in stripped:
            raise InputError(f"{where}:{number}: expected 'question: answer', got {stripped!r}")
        question, answer = stripped.split(":", 1)
        out.append((question.strip(), answer.strip()))
    return out


def read_answers(path: str | Path) -> list[tuple[str, str]]:
    """Answers from an answers file or from a transcript (``.json``)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(f"cannot read {path}: {exc.strerror}") from None
    if path.suffix == ".json":
        data = load_transcript(path, text)
        return [(e["question"], e["answer"]) for e in data["exchanges"]]
    return parse_answers(text, str(path))


def load_transcript(path: str | Path, text: str | None = None) -> dict:
    path = Path(path)
    try:
        data = json.loads(text if text is not None else path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise InputError(f"cannot read {path}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not valid JSON: {exc}") from None
    if not isinstance(data, dict) or data.get("format") != TRANSCRIPT_FORMAT or not isinstance(data.get("exchanges"), list):
        raise InputError(f"{path}: not a design transcript (format {TRANSCRIPT_FORMAT})")
    return data


@dataclass
class Outcome:
    """How a session ended: the relation, the frame shown or retained, and every exchange."""

    relation: str
    case: str | None
    frame: ProblemFrame | None
    exchanges: list[dict] = field(default_factory=list)

    def transcript(self) -> dict:
        return {
            "format": TRANSCRIPT_FORMAT,
            "relation": self.relation,
            "case": self.case,
            "exchanges": self.exchanges,
            "frame": self.frame.to_mapping() if self.frame else None,
        }


class Session:
    """One design dialogue against a case base (``url``: SQLAlchemy URL or path; None: the default)."""

    def __init__(
        self,
        url: str | None = None,
        answers: list[tuple[str, str]] | None = None,
        interactive: bool = True,
        out: Callable[[str], None] | None = None,
        read: Callable[[str], str] = input,
        vary: bool = True,
    ):
        self.say = out or (lambda text: print(text, flush=True))
        self.script = list(answers or [])
        self.used = 0
        self.interactive = interactive
        self.read = read
        self.world = World(url, self.say, vary=vary)
        self.exchanges: list[dict] = []

    # -- questions -----------------------------------------------------------------------

    def question(self, engine: DesignExpert, qid: str) -> Question:
        if qid in STATIC:
            return STATIC[qid]
        if qid == "relation":
            cases = self.world.solved_in_class(engine.attr("class"))
            self.say(f"Solved problems of class {engine.attr('class')!r}:")
            for c in cases:
                self.say(f"  {c.id}: DOF {c.dof}, {c.loops} loops, {c.links} links, {c.joints} joints, "
                         f"{c.slider_pairs or 0} sliders, {c.gear_pairs or 0} gear pairs; "
                         f"attributes {', '.join(sorted(c.names)) or 'none'}")
            ids = [c.id for c in cases]
            return Question("relation", "Is your problem the same as, similar to, or different from one of these? "
                            "(same ID / similar ID / different)", relation_parser(ids), f"same {ids[-1]}")
        if qid == "scene":
            problem_class = engine.attr("class") or ""
            _, case = self.world.relation
            default = self.world.case(case).scene if case else None
            slug = problem_class.replace("_", "-")
            known = scene_names()
            default = default or next((s for s in known if slug == s or slug.startswith(s)), None)
            return Question("scene", f"Scene whose rules give the links their roles ({', '.join(known)}, or none)",
                            parse_scene, default or "none")
        if qid == "verify":
            kept = {c["id"]: LabelledChain.from_dict(c) for c in self.world.run_result.kept}
            return Question("verify", "Verify dimensions? (none, or CANDIDATE FILE.json CHECK; CHECK is rotatability "
                            "or range OUTPUT FROM:TO)", verify_parser(kept), "none")
        if qid == "relevance_overrides":
            ids = list(engine.attr("relevance_default").ids)
            return Question("relevance_overrides", "Override relevance? (none, or criterion ids: ID or +ID relevant, -ID irrelevant)",
                            overrides_parser(ids), "none")
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
        if self.used < len(self.script):
            question, text = self.script[self.used]
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
        if frame is None:
            known = sorted(str(f.get("name", f.get("id", ""))) for f in engine.facts.values() if hasattr(f, "get"))
            raise InputError(f"the design dialogue stopped without a result (known: {', '.join(known)})")
        if self.world.shown is not None:
            relation, case = "same", self.world.shown.id
        return Outcome(relation, case, frame, self.exchanges)


def rejected_text(world: World) -> str:
    run = world.run_result
    if run is None or not run.rejected:
        return "No candidate was rejected."
    lines = [f"{len(run.rejected)} rejected candidates:"]
    for r in run.rejected:
        lines.append(f"  candidate {r['candidate']}: rejected by {r['criterion']} (level {r['level']}): {r['reason']}")
    return "\n".join(lines)


def write_transcript(path: str | Path, outcome: Outcome) -> None:
    """The session's transcript (answers, outcome, frame) as JSON, written atomically."""
    write_atomic(Path(path), json.dumps(outcome.transcript(), indent=1, ensure_ascii=False) + "\n")
