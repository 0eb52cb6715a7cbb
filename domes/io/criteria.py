"""Readable knowledge sources: criterion frames in TOML (``knowledge/criteria/*.toml``) or JSON.

A source file is a list of ``[[criterion]]`` tables with the fields of
:data:`~domes.knowledge.frames.FIELDS` (``id`` and ``text`` required).
Export writes the same format, plus the category and the canonical reading
of each criterion for the reader (both checked or ignored on import).
Reading validates every frame of every file before returning any, and every
error names the file, the criterion and the field.

>>> frames = loads_toml('[[criterion]]\\nid = "c1"\\ntext = "every vertex must have degree at most 4"\\n', "x.toml")
>>> frames[0].category
'i'
"""

from __future__ import annotations

import json
import tomllib
from pathlib import Path
from typing import Iterable

from domes.errors import DomesError, InputError
from domes.io.tomlsource import read_text
from domes.knowledge.frames import CriterionFrame
from domes.knowledge.problems import ProblemFrame

FORMATS = ("toml", "json")


def _line_of(text: str, frame_id) -> str:
    if isinstance(frame_id, str):
        for number, line in enumerate(text.splitlines(), 1):
            if line.strip().startswith("id") and f'"{frame_id}"' in line:
                return f", line {number}"
    return ""


def _frames(tables, where: str, text: str = "") -> list[CriterionFrame]:
    if not isinstance(tables, list):
        raise InputError(f"{where}: expected a list of criteria ([[criterion]] tables)")
    frames = []
    for index, table in enumerate(tables, 1):
        ident = table.get("id") if isinstance(table, dict) else None
        try:
            frames.append(CriterionFrame.from_dict(table))
        except DomesError as exc:
            label = f"criterion {index}" + (f" (id {ident!r})" if isinstance(ident, str) else "")
            raise InputError(f"{where}{_line_of(text, ident)}: {label}: {exc}") from None
    return frames


def loads_toml(text: str, where: str = "<toml>") -> list[CriterionFrame]:
    """Frames from the text of a TOML source file."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(f"{where}: not valid TOML: {exc}") from None
    unknown = set(data) - {"criterion"}
    if unknown:
        raise InputError(f"{where}: unknown top-level key(s) {sorted(unknown)}; criteria go in [[criterion]] tables")
    return _frames(data.get("criterion", []), where, text)


def loads_json(text: str, where: str = "<json>") -> list[CriterionFrame]:
    """Frames from JSON: ``{"criteria": [...]}`` as written by :func:`dumps_json`."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}: not valid JSON: {exc}") from None
    if not isinstance(data, dict) or set(data) - {"criteria"}:
        raise InputError(f"{where}: expected an object with a 'criteria' list")
    return _frames(data.get("criteria", []), where)


def read_file(path: str | Path) -> list[CriterionFrame]:
    """Frames from a ``.toml`` or ``.json`` file."""
    path = Path(path)
    text = read_text(path)
    if path.suffix == ".json":
        return loads_json(text, str(path))
    return loads_toml(text, str(path))


def check_unique(frames: Iterable[CriterionFrame], where: str) -> None:
    seen: set[str] = set()
    for frame in frames:
        if frame.id in seen:
            raise InputError(f"{where}: criterion id {frame.id!r} is given twice")
        seen.add(frame.id)


def read_knowledge(directory: str | Path) -> list[CriterionFrame]:
    """Every frame of ``directory/criteria/*.toml``, files in name order, validated whole."""
    directory = Path(directory)
    folder = directory / "criteria"
    if not folder.is_dir():
        raise InputError(f"{directory}: no criteria/ folder of knowledge sources (expected {folder})")
    frames: list[CriterionFrame] = []
    owner: dict[str, Path] = {}
    for path in sorted(folder.glob("*.toml")):
        for frame in read_file(path):
            if frame.id in owner:
                raise InputError(f"{path}: criterion id {frame.id!r} is also defined in {owner[frame.id]}")
            owner[frame.id] = path
            frames.append(frame)
    return frames


def read_cases(directory: str | Path) -> list[ProblemFrame]:
    """The solved-problem frames of ``directory/cases/*.json`` (each a design transcript with a
    ``frame``), files in name order; no cases folder means no cases."""
    folder = Path(directory) / "cases"
    frames: list[ProblemFrame] = []
    owner: dict[str, Path] = {}
    for path in sorted(folder.glob("*.json")) if folder.is_dir() else []:
        try:
            data = json.loads(path.read_text(encoding="utf-8"))
        except (OSError, UnicodeDecodeError) as exc:
            raise InputError(f"{path}: cannot read: {exc}") from None
        except json.JSONDecodeError as exc:
            raise InputError(f"{path}: not valid JSON: {exc}") from None
        if not isinstance(data, dict) or "frame" not in data:
            raise InputError(f"{path}: a case is a design transcript with a 'frame' (see docs/expert.md)")
        frame = ProblemFrame.from_dict(data["frame"], f"{path}: frame")
        if frame.id in owner:
            raise InputError(f"{path}: case id {frame.id!r} is also used by {owner[frame.id]}")
        owner[frame.id] = path
        frames.append(frame)
    return frames


def _toml_value(value) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    return "[" + ", ".join(_toml_value(v) for v in value) + "]"


def dumps_toml(frames: Iterable[CriterionFrame]) -> str:
    """TOML text of frames, readable and re-importable (``reading`` is the canonical form, for the reader)."""
    blocks = []
    for frame in frames:
        lines = ["[[criterion]]"]
        for key, value in frame.to_dict().items():
            lines.append(f"{key} = {_toml_value(value)}")
        blocks.append("\n".join(lines))
    return "# DOMES-py knowledge base: criterion frames (Table 7-2)\n\n" + "\n\n".join(blocks) + "\n"


def dumps_json(frames: Iterable[CriterionFrame]) -> str:
    return json.dumps({"criteria": [f.to_dict() for f in frames]}, ensure_ascii=False, indent=1) + "\n"
