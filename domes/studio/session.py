"""A design session of the studio: the terminal's :class:`~domes.expert.dialogue.Dialogue` in a worker process.

The worker (:func:`work`) runs the dialogue and sends on a pipe what it says (``line``), how a long stage
advances (``progress``), each exchange (``exchange``), the question it waits on (``question``: id, prompt,
default, help, and the reason the last answer was not accepted), the funnel of every design run (``funnel``)
and how it ended (``done`` or ``failed``). It reads the page's answers from the same pipe. The server's side
(:class:`Session`) reads the pipe only when the page asks (no thread), and kills the worker on cancel: a long
stage stops at once, and a transaction under way never reaches the case base.

>>> from domes.knowledge.problems import ProblemFrame
>>> frame = ProblemFrame("demo-1", "demo", dof=1, loops=1, results=({"id": 2},),
...                      rejected=({"candidate": 1, "criterion": "one-ground", "level": 1, "reason": "two frames"},))
>>> shown = Funnel.of(frame, (), {"one-ground": "exactly one fixed link"}, None)
>>> [(r["stage"], r["count"]) for r in shown["rows"]]
[('generated', 2), ('screening level 1', 1), ('quasi-feasible (after the screening levels)', 1)]
>>> shown["rejected"][0]["explanation"], shown["kept"]
('exactly one fixed link', [2])
"""

from __future__ import annotations

import multiprocessing
import shutil
import time
from dataclasses import dataclass, field
from pathlib import Path

from domes.errors import InputError
from domes.io.transcripts import save_session

#: The start method of the workers: a fresh interpreter, safe in a server or a test runner with threads.
CONTEXT = multiprocessing.get_context("spawn")
#: How long a worker waits for an answer before it gives up (s).
IDLE = 4 * 3600.0
#: At most one progress message per this many seconds.
PROGRESS_EVERY = 0.25
#: The states a session ends in.
ENDED = ("done", "failed", "cancelled")


class Funnel:
    """The funnel of a design run as plain data (:func:`domes.sketch.report.funnel`), its rejected candidates with
    criterion and reason, and an atlas page of the candidates' sketches (``candidates.html``)."""

    #: Candidates drawn in the atlas at most.
    cap = 120

    @staticmethod
    def of(frame, candidates, words: dict, folder: Path | None) -> dict:
        """The funnel of ``frame``, whose generated ``candidates`` (plain data with ids) are drawn into ``folder``."""
        from domes.errors import DomesError
        from domes.sketch.report import funnel

        rows = [{"stage": r.stage, "count": r.count, "removed": [[what, k] for what, k in r.removed]}
                for r in funnel(frame, words)]
        rejected = [{**r, "explanation": words.get(r.get("criterion"), "")} for r in frame.rejected]
        try:
            atlas = Funnel.atlas(frame, candidates, rejected, folder) if folder is not None and candidates else None
        except DomesError:  # the funnel is shown all the same, without its sketches
            atlas = None
        return {"rows": rows, "kept": [c.get("id") for c in frame.results], "rejected": rejected,
                "generated": len(frame.results) + len(frame.rejected), "atlas": atlas}

    @staticmethod
    def atlas(frame, candidates, rejected, folder: Path) -> str | None:
        """Write ``candidates.html`` (every candidate sketched, a rejected one marked with its criterion)."""
        from domes.errors import DomesError
        from domes.io.files import write_atomic
        from domes.model.labelled import LabelledChain
        from domes.sketch.atlas import Card, atlas_html, mechanism_card, not_drawn_svg

        why = {r.get("candidate"): r for r in rejected}
        cards = []
        for c in list(candidates)[:Funnel.cap]:
            r = why.get(c.get("id"))
            verdict = (f"rejected by {r['criterion']} (level {r.get('level')}): {r.get('reason') or ''}" if r
                       else "kept")
            props = (("screening", verdict),) + ((("existing", "; ".join(c["existing"])),) if c.get("existing") else ())
            title = f"Candidate {c.get('id')}"
            badge = f"rejected by {r['criterion']}" if r else None
            try:
                cards.append(mechanism_card(c.get("id"), LabelledChain.from_dict(c), title=title, properties=props,
                                            badge=badge, size=220.0))
            except DomesError as exc:
                cards.append(Card(str(c.get("id")), title, not_drawn_svg(str(exc), 220.0), props, badge))
        generated = len(frame.results) + len(frame.rejected)
        summary = (f"{generated} candidates generated, {len(frame.results)} kept"
                   + (f"; {len(cards)} of them drawn" if len(cards) < generated else "") + ".")
        title = f"Candidates: {(frame.title or frame.problem_class).replace('_', ' ')}"
        folder.mkdir(parents=True, exist_ok=True)
        write_atomic(folder / "candidates.html", atlas_html(cards, title, summary))
        return "candidates.html"


def page_dialogue(conn, url, answers, knobs, vary: bool, folder: Path):
    """A :class:`~domes.expert.dialogue.Dialogue` whose ``read`` asks the page and whose ``out`` and progress go to
    it (``conn``: the worker's end of the pipe)."""
    from domes.expert.dialogue import Dialogue
    from domes.results import Ticker

    class PageDialogue(Dialogue):
        def __init__(self):
            ticker = Ticker(lambda text: self.send("progress", text), PROGRESS_EVERY)
            super().__init__(url, answers, interactive=True, out=lambda text: self.send("line", text), read=self.ask,
                             vary=vary, progress=lambda text: ticker.tick(lambda: text), knobs=knobs)
            self.current = None
            self.sent = 0
            self.drawn = None

        def send(self, kind: str, value) -> None:
            self.flush()  # every exchange reaches the server before what follows it
            conn.send((kind, value))

        def flush(self) -> None:
            while self.sent < len(self.exchanges):
                conn.send(("exchange", self.exchanges[self.sent]))
                self.sent += 1

        def answer(self, engine, q):
            self.current = q
            run = self.world.run_result
            if run is not None and run is not self.drawn:
                self.drawn = run
                frame = self.world.frame_of_run(engine, "not retained")
                self.send("funnel", Funnel.of(frame, run.candidates, self.words(), folder))
            return super().answer(engine, q)

        def words(self) -> dict:
            return {c.id: c.explanation for c in self.world.criteria()}

        def ask(self, prompt: str) -> str:
            q = self.current
            last = self.exchanges[-1] if self.exchanges else {}
            self.send("question", {"id": q.id, "prompt": q.prompt, "default": q.default, "help": q.help,
                                   "rejected": last.get("rejected") if last.get("question") == q.id else None})
            if not conn.poll(IDLE):
                raise EOFError(f"no answer for {IDLE / 3600:g} hours")
            return conn.recv()

    return PageDialogue()


def work(conn, spec: dict) -> None:
    """The worker process: one design dialogue against the case base (a scratch copy of it for a dry run)."""
    from domes.errors import DomesError
    from domes.expert.feasible import DesignKnobs
    from domes.expert.replay import scratch_casebase
    from domes.io.transcripts import write_transcript

    try:
        url = spec["db"]
        if spec["scratch"]:
            url = scratch_casebase(spec["db"], None, Path(spec["scratch"]))
            conn.send(("line", "Dry run: a scratch copy of the case base; nothing is kept."))
        folder = Path(spec["report"])
        knobs = DesignKnobs(spec["method"], spec["seeds"], time_budget=spec["time_budget"], report=folder)
        dialogue = page_dialogue(conn, url, spec["answers"], knobs, spec["vary"], folder)
        outcome = dialogue.run()
        dialogue.flush()
        write_transcript(spec["transcript"], outcome.to_dict())
        conn.send(("line", f"Transcript written to {spec['transcript']}."))
        if spec["scratch"]:
            conn.send(("line", "Dry run: the case base is unchanged."))
        frame = outcome.frame
        if frame is not None and dialogue.world.run_result is None:  # the same problem: the stored frame
            conn.send(("funnel", Funnel.of(frame, frame.results, dialogue.words(), folder)))
        conn.send(("done", {"relation": outcome.relation, "case": outcome.case,
                            "retained": frame.id if frame is not None and dialogue.world.retained else None,
                            "kept": len(frame.results) if frame else 0,
                            "feasible": sum(d.get("status") == "feasible" for d in frame.designs) if frame else 0,
                            "report": "index.html" if (folder / "index.html").is_file() else None}))
    except (DomesError, EOFError) as exc:
        conn.send(("failed", str(exc)))
    except Exception as exc:  # noqa: BLE001 - the page is told, not left waiting
        conn.send(("failed", f"{type(exc).__name__}: {exc}"))
    finally:
        conn.close()


@dataclass
class Session:
    """The server's side of a design session: the worker, what it said so far, and where it writes."""

    id: str
    home: Path
    spec: dict
    dry_run: bool
    source: str | None = None
    events: list = field(default_factory=list)
    exchanges: list = field(default_factory=list)
    status: str = "running"
    question: dict | None = None
    progress: str | None = None
    funnel: dict | None = None
    outcome: dict | None = None
    error: str | None = None
    started: float = field(default_factory=time.time)

    def start(self) -> Session:
        self.conn, child = CONTEXT.Pipe()
        self.process = CONTEXT.Process(target=work, args=(child, self.spec), name=f"domes-design-{self.id}",
                                       daemon=True)
        self.process.start()
        child.close()
        return self

    @property
    def live(self) -> bool:
        return self.status not in ENDED

    def pump(self) -> None:
        """Read what the worker has sent so far (never waits)."""
        while self.live:
            try:
                if not self.conn.poll():
                    break
                kind, value = self.conn.recv()
            except (EOFError, OSError):
                self.end("failed", f"the session's process stopped (exit code {self.process.exitcode})")
                break
            self.take(kind, value)
        if self.live and not self.process.is_alive() and not self.conn.poll():
            self.end("failed", f"the session's process stopped (exit code {self.process.exitcode})")

    def take(self, kind: str, value) -> None:
        if kind == "line":
            self.events.append({"kind": "line", "text": value})
            if value:
                self.progress = None
        elif kind == "progress":
            self.progress = value
        elif kind == "exchange":
            self.exchanges.append(value)
        elif kind == "question":
            self.question, self.progress, self.status = value, None, "asking"
        elif kind == "funnel":
            self.funnel = value
        elif kind == "done":
            self.outcome = value
            self.end("done")
        elif kind == "failed":
            self.events.append({"kind": "error", "text": value})
            self.end("failed", value)

    def answer(self, text: str) -> None:
        self.pump()
        if self.status != "asking":
            raise InputError(f"session {self.id} is {self.status}: it waits for no answer")
        self.events.append({"kind": "answer", "question": self.question["id"], "text": text})
        try:
            self.conn.send(text)
        except OSError:
            self.end("failed", f"the session's process stopped (exit code {self.process.exitcode})")
            raise InputError(f"session {self.id}: {self.error}") from None
        self.question, self.status = None, "running"

    def cancel(self) -> None:
        """Kill the worker; the answers so far are saved to be resumed (``sessions/ID.interrupted.json``)."""
        self.pump()
        if not self.live:
            raise InputError(f"session {self.id} has already ended ({self.status})")
        self.process.kill()
        self.process.join(10)
        while self.conn.poll():  # what was sent before the end
            try:
                kind, value = self.conn.recv()
            except (EOFError, OSError):
                break
            if kind == "exchange":
                self.exchanges.append(value)
        self.events.append({"kind": "line", "text": "Cancelled: the session's process was stopped."})
        if self.exchanges:
            saved = Path(self.spec["transcript"]).with_suffix(".interrupted.json")
            save_session(saved, self.exchanges)
            self.events.append({"kind": "line", "text": f"{len(self.exchanges)} answers saved in sessions/"
                                f"{saved.name} (replay it to resume)."})
        self.end("cancelled")

    def end(self, status: str, error: str | None = None) -> None:
        self.status, self.error, self.question, self.progress = status, error, None, None
        self.conn.close()
        if self.spec["scratch"]:  # the worker has ended its dialogue, or been killed: its scratch copy goes
            shutil.rmtree(self.spec["scratch"], ignore_errors=True)

    def view(self, since: int) -> dict:
        """What the page shows from event ``since`` on."""
        return {"session": self.id, "status": self.status, "events": self.events[since:], "next": len(self.events),
                "question": self.question, "progress": self.progress, "funnel": self.funnel, "outcome": self.outcome,
                "error": self.error, "dry_run": self.dry_run, "source": self.source,
                "pid": self.process.pid, "alive": self.process.is_alive()}
