"""Recorded cases as regression tests: replay a transcript and show what changed.

A shipped case (``knowledge/cases/NAME.json``) is a design transcript: the
answers of the session and the problem frame it retained. Replaying runs the
same answers against a temporary copy of the current case base (the case
itself left out, unless the session was answered from it) and compares the
new frame with the recorded one.

>>> frame_differences({"results": [{"id": 1}], "date": "x"}, {"results": [{"id": 1}], "date": "y"})
[]
"""

from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass
from pathlib import Path

from domes.design.methods import METHODS
from domes.errors import DomesError, InputError
from domes.expert.dialogue import Dialogue, Outcome
from domes.expert.feasible import DesignKnobs
from domes.io.resources import knowledge_dir
from domes.io.transcripts import exchanges_answers, load_transcript, write_transcript
from domes.knowledge.frames import ID_PATTERN
from domes.store.casebase import KnowledgeBase, copy_casebase, database_url, sqlite_path

#: Frame fields that may differ between runs without the result changing.
IGNORED = ("date",)


def frame_differences(recorded: dict, replayed: dict) -> list[str]:
    """Human-readable differences between two problem frames (as plain data)."""
    out = []
    for key in sorted(set(recorded) | set(replayed)):
        if key in IGNORED:
            continue
        a, b = recorded.get(key), replayed.get(key)
        if a == b:
            continue
        if key in ("results", "rejected") and isinstance(a, list) and isinstance(b, list):
            ids = lambda rows: [r.get("id", r.get("candidate")) for r in rows]  # noqa: E731
            out.append(f"{key}: recorded {len(a)} {ids(a)}, now {len(b)} {ids(b)}")
            for old, new in zip(a, b):
                if old != new:
                    out.append(f"  first difference: recorded {old}, now {new}")
                    break
        elif key == "relevance" and isinstance(a, dict) and isinstance(b, dict):
            # criteria added to the knowledge base since, and irrelevant here, are no difference
            on = lambda v: {i for i, bit in zip(v.get("ids", []), v.get("bits", [])) if bit}  # noqa: E731
            if on(a) != on(b):
                out.append(f"relevance: recorded relevant {sorted(on(a))}, now {sorted(on(b))}")
        elif key == "designs" and isinstance(a, list) and isinstance(b, list):
            out += design_differences(a, b)
        elif key == "mechanisms" and isinstance(a, list) and isinstance(b, list):
            # dimensions come from a seeded least-squares fit: the same candidates and tasks, verified, is a match
            which = lambda rows: [(m.get("candidate"), m.get("task")) for m in rows]  # noqa: E731
            if which(a) != which(b):
                out.append(f"mechanisms: recorded {which(a)}, now {which(b)}")
        else:
            out.append(f"{key}: recorded {a!r}, now {b!r}")
    return out


#: Relative difference of a design's numbers (scores, the checks' values) that counts as a change.
RELATIVE = 1e-6


def design_differences(recorded: list, replayed: list) -> list[str]:
    """How the designs of a replay differ: another candidate, status, rank or failed check, or a number (a score,
    a check's value) off by more than :data:`RELATIVE`. The fitted coordinates are not compared: the checks on
    them are."""
    def shape(d):
        return (d.get("candidate"), d.get("status"), d.get("rank"),
                tuple(c.get("name") for c in d.get("checks", []) if not c.get("passed")))

    if [shape(d) for d in recorded] != [shape(d) for d in replayed]:
        return [f"designs: recorded {[shape(d)[:3] for d in recorded]}, now {[shape(d)[:3] for d in replayed]}"]
    for old, new in zip(recorded, replayed):
        pairs = [("score", old.get("score"), new.get("score"))]
        pairs += [(c.get("name"), c.get("value"), n.get("value"))
                  for c, n in zip(old.get("checks", []), new.get("checks", []))]
        for what, x, y in pairs:
            if (x is None) != (y is None) or (x is not None and abs(x - y) > RELATIVE * max(abs(x), abs(y), 1e-300)):
                return [f"designs: candidate {old.get('candidate')}: {what} recorded {x!r}, now {y!r}"]
    return []


@dataclass
class Replay:
    """A replayed case: the session's outcome (None when it stopped) and every difference from the recording."""

    name: str
    outcome: Outcome | None
    differences: list[str]


def shipped_cases() -> list[str]:
    """The names of the shipped cases (``cases/NAME.json`` of the knowledge folder)."""
    return sorted(p.stem for p in (knowledge_dir() / "cases").glob("*.json"))


def case_path(name_or_path: str) -> Path:
    """A transcript by file path, or a shipped case by name (``knowledge/cases/NAME.json``)."""
    path = Path(name_or_path)
    if path.is_file():
        return path
    candidate = knowledge_dir() / "cases" / f"{name_or_path}.json"
    if candidate.is_file():
        return candidate
    raise InputError(f"no case {name_or_path!r}: not a file, and not one of: {', '.join(shipped_cases())}")


def scratch_casebase(url: str | None, leave_out: str | None, folder: Path, leave_class: str | None = None) -> str:
    """A temporary SQLite copy of the case base (an SQLite file copied; another database's criteria and cases copied),
    without the case ``leave_out`` and every case of class ``leave_class``."""
    target = folder / "casebase.db"
    source_url = database_url(url)
    source = sqlite_path(source_url)
    if source is not None:
        if not source.is_file():
            raise InputError(f"no case base at {source}: build it with `domes kb build` (or choose one with --db)")
        shutil.copyfile(source, target)
    else:
        copy_casebase(source_url, f"sqlite:///{target}")
    scratch = f"sqlite:///{target}"
    if leave_out or leave_class:
        with KnowledgeBase(scratch, actor="replay") as kb:
            for p in kb.problems():
                if p.id == leave_out or p.problem_class == leave_class:
                    kb.remove_problem(p.id)
    return scratch


def replay(name_or_path: str, url: str | None = None, say=lambda text: None) -> Replay:
    """Replay a transcript against (a copy of) the current case base; never changes it."""
    path = case_path(name_or_path)
    data = load_transcript(path)
    recorded = data.get("frame") or {}
    leave_out = None if data.get("relation") == "same" else recorded.get("id")
    answers = exchanges_answers(data["exchanges"], path)
    # a session recorded as a new class met no solved problem of its class: neither does its replay
    new_class = not any(q == "relation" for q, _ in answers) and data.get("relation") == "different"
    leave_class = recorded.get("problem_class") if new_class else None
    with tempfile.TemporaryDirectory(prefix="domes-replay-") as tmp:
        scratch = scratch_casebase(url, leave_out, Path(tmp), leave_class)
        knobs = _knobs(data.get("knobs"), path)
        try:
            outcome = Dialogue(scratch, answers, interactive=False, out=say, knobs=knobs).run()
        except DomesError as exc:
            return Replay(path.stem, None, [f"the replay stopped: {exc}"])
    now = outcome.frame.to_dict() if outcome.frame else {}
    differences = frame_differences(recorded, now)
    if data.get("relation") != outcome.relation:
        differences.insert(0, f"relation: recorded {data.get('relation')!r}, now {outcome.relation!r}")
    return Replay(path.stem, outcome, differences)


def _knobs(raw, where) -> DesignKnobs:
    """The dimensioning knobs a transcript was recorded with (no report: a replay writes nothing)."""
    if raw is None:
        return DesignKnobs()
    if not isinstance(raw, dict) or raw.get("method") not in METHODS or not isinstance(raw.get("seeds"), int):
        raise InputError(f"{where}: 'knobs' must be {{'method': one of {', '.join(METHODS)}, 'seeds': a whole number}}")
    return DesignKnobs(method=raw["method"], seeds=raw["seeds"])


def record(answers: list[tuple[str, str]], case_id: str | None, url: str | None = None, say=lambda text: None,
           knobs: DesignKnobs | None = None) -> Outcome:
    """Run answers against a scratch copy of the case base (without ``case_id``), as a replay would."""
    with tempfile.TemporaryDirectory(prefix="domes-record-") as tmp:
        scratch = scratch_casebase(url, case_id, Path(tmp))
        return Dialogue(scratch, answers, interactive=False, out=say, knobs=knobs).run()


def record_case(answers: list[tuple[str, str]], name: str, url: str | None = None, say=lambda text: None,
                knobs: DesignKnobs | None = None) -> tuple[Outcome, Path]:
    """Run answers as the shipped case ``NAME`` (``cases/NAME.json`` of the knowledge folder) and write its transcript.

    The session runs against a scratch copy of the case base without the
    case it replaces, as a replay would; a session that keeps no result is refused.
    """
    if not ID_PATTERN.match(name) or ".." in name:
        raise InputError(f"--name {name!r}: a case's name is letters, digits, '.', '_' and '-' (it names "
                         f"knowledge/cases/NAME.json, and may not leave that folder)")
    target = knowledge_dir() / "cases" / f"{name}.json"
    previous = (load_transcript(target).get("frame") or {}).get("id") if target.is_file() else None
    outcome = record(answers, previous, url, say, knobs)
    if outcome.frame is None:
        raise InputError("the session ended without a result to keep")
    write_transcript(target, outcome.to_dict())
    return outcome, target
