"""Answers files, design transcripts and saved sessions of the design dialogue.

* An **answers file** has one ``question: answer`` per line (``#`` comments);
  see ``examples/design/*.answers``.
* A **transcript** (JSON, format :data:`TRANSCRIPT_FORMAT`) records every
  exchange of a session, how it ended and the problem frame it kept; the
  shipped cases (``knowledge/cases/*.json``) are transcripts.
* A **saved session** (``.domes-design-session.json``) keeps the exchanges of
  an interrupted session, to be resumed.

>>> parse_answers("# motorcycle\\nclass: motorcycle rear suspension\\ndof: 1\\n")
[('class', 'motorcycle rear suspension'), ('dof', '1')]
"""

from __future__ import annotations

import json
from pathlib import Path

from domes.errors import InputError
from domes.io.files import read_text, write_atomic

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
    text = read_text(path)
    if path.suffix == ".json":
        return exchanges_answers(load_transcript(path, text)["exchanges"], path)
    return parse_answers(text, str(path))


def _json(path: Path, text: str | None) -> object:
    try:
        return json.loads(read_text(path) if text is None else text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: not valid JSON: {exc}") from None


def load_transcript(path: str | Path, text: str | None = None) -> dict:
    """A design transcript as plain data, checked to be one."""
    path = Path(path)
    data = _json(path, text)
    if not isinstance(data, dict) or data.get("format") != TRANSCRIPT_FORMAT or not isinstance(data.get("exchanges"), list):
        raise InputError(f"{path}: not a design transcript (format {TRANSCRIPT_FORMAT})")
    exchanges_answers(data["exchanges"], path)
    return data


def exchanges_answers(exchanges: object, where: str | Path) -> list[tuple[str, str]]:
    """The ``(question, answer)`` pairs of recorded exchanges; an error names the first malformed one."""
    if not isinstance(exchanges, list):
        raise InputError(f"{where}: 'exchanges' must be a list of {{'question': ..., 'answer': ...}}")
    out = []
    for number, e in enumerate(exchanges, 1):
        if not (isinstance(e, dict) and isinstance(e.get("question"), str) and isinstance(e.get("answer"), str)):
            raise InputError(f"{where}: exchange {number} is not {{'question': TEXT, 'answer': TEXT}}: {e!r:.80}")
        out.append((e["question"], e["answer"]))
    return out


def write_transcript(path: str | Path, transcript: dict) -> None:
    """A session's transcript (answers, outcome, frame) as JSON, written atomically."""
    write_atomic(path, json.dumps(transcript, indent=1, ensure_ascii=False) + "\n")


def save_session(path: str | Path, exchanges: list[dict]) -> None:
    """The exchanges of an interrupted session, to resume it later."""
    write_atomic(path, json.dumps({"exchanges": exchanges}, indent=1, ensure_ascii=False) + "\n")


def load_session(path: str | Path) -> list[tuple[str, str]]:
    """The answers of a saved session; an error says what is wrong with the file."""
    path = Path(path)
    if not path.is_file():
        raise InputError(f"no saved session at {path}")
    data = _json(path, None)
    if not isinstance(data, dict) or "exchanges" not in data:
        raise InputError(f"{path}: not a saved design session (expected {{'exchanges': [...]}})")
    return exchanges_answers(data["exchanges"], path)
