"""The catalogue files: ``catalogue.toml`` and ``heuristics.toml`` of the knowledge folder, the mechanism files of ``catalogue/``.

Format in ``docs/catalogue.md``; every error names the file and the line.

>>> entries = load_catalogue()
>>> sorted({e.motion[1] for e in entries})[:2]
['intermittent rotation', 'oscillation']
>>> sorted({e.family for e in entries})
['cam', 'gears', 'intermittent', 'linkage']
>>> [h.function for h in load_heuristics()][:2]
['exact', 'approximate']
"""

from __future__ import annotations

from pathlib import Path

from domes.errors import DomesError, InputError
from domes.io.mechanisms import load_mechanism
from domes.io.resources import knowledge_dir
from domes.io.tomlsource import TomlSource
from domes.knowledge.catalogue import Entry, Heuristic

_KEYS = {"name", "motion", "model", "measure", "source", "description", "parameters", "family"}
_HEURISTIC_KEYS = {"function", "prefer", "reason", "source", "implied_by", "outputs"}


def load_catalogue(folder: str | Path | None = None) -> list[Entry]:
    """The entries of ``catalogue.toml`` in the knowledge folder (``folder``, else the shipped one)."""
    root = knowledge_dir(folder)
    path = root / "catalogue.toml"
    src = TomlSource.read(path)
    items = src.data.get("mechanism", [])
    if not isinstance(items, list) or not items:
        raise src.error("expected [[mechanism]] tables")
    unknown = set(src.data) - {"mechanism"}
    if unknown:
        raise src.error(f"unknown key(s) {', '.join(sorted(unknown))}: only [[mechanism]] tables", src.line_of(
            sorted(unknown)[0]))
    out, names = [], set()
    for line, raw in _tables(src, "mechanism", _KEYS, ("name", "motion", "model", "measure"), "name"):
        name = raw["name"]
        if not isinstance(name, str) or not name.strip() or name in names:
            raise src.error(f"a mechanism's name must be a new, non-empty text, got {name!r}", line)
        names.add(name)
        model, mechanism = raw["model"], None
        if not isinstance(model, str) or not model:
            raise src.error(f"{name}: 'model' must be a mechanism file's name or geneva or cam", line)
        if model.endswith(".json"):
            file = root / "catalogue" / model
            if Path(model).name != model:
                raise src.error(f"{name}: the model file {model!r} must be a name in catalogue/", line)
            mechanism = load_mechanism(file)
            model = "mechanism"
        if not isinstance(raw["measure"], dict) or not isinstance(raw.get("parameters", {}), dict):
            raise src.error(f"{name}: 'measure' and 'parameters' must be tables", line)
        motion = raw["motion"]
        if not isinstance(motion, list):
            raise src.error(f"{name}: 'motion' must be [input, output]", line)
        try:
            out.append(Entry(name, tuple(motion), model, dict(raw["measure"]), str(raw.get("source", "")),
                             str(raw.get("description", "")), mechanism, dict(raw.get("parameters", {})),
                             raw.get("family", _family(model, mechanism))))
        except DomesError as exc:
            raise InputError(f"{path}:{line}: {exc}") from None
    return out


def _family(model: str, mechanism) -> str:
    """An entry's family when its table gives none: a cam or Geneva model's, gears when its mechanism meshes."""
    if model != "mechanism":
        return {"cam": "cam", "geneva": "intermittent"}[model]
    return "gears" if mechanism.gears else "cam" if mechanism.cams else "linkage"


def load_heuristics(folder: str | Path | None = None) -> list[Heuristic]:
    """The §6-1 heuristics of ``heuristics.toml`` in the knowledge folder (none when the folder has no such file)."""
    path = knowledge_dir(folder) / "heuristics.toml"
    if not path.is_file():
        return []
    src = TomlSource.read(path)
    items = src.data.get("heuristic", [])
    unknown = set(src.data) - {"heuristic"}
    if unknown or not isinstance(items, list):
        raise src.error("only [[heuristic]] tables", src.line_of(sorted(unknown)[0]) if unknown else None)
    out = []
    for line, raw in _tables(src, "heuristic", _HEURISTIC_KEYS, ("function", "prefer", "reason"), "function"):
        lists = {k: raw.get(k, []) for k in ("prefer", "implied_by", "outputs")}
        for key, value in lists.items():
            if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
                raise src.error(f"[[heuristic]] {raw['function']!r}: '{key}' must be a list of texts", line)
        try:
            out.append(Heuristic(str(raw["function"]), tuple(lists["prefer"]), str(raw["reason"]),
                                 str(raw.get("source", "")), tuple(lists["implied_by"]), tuple(lists["outputs"])))
        except DomesError as exc:
            raise InputError(f"{path}:{line}: {exc}") from None
    return out


def _tables(src: TomlSource, kind: str, keys: set, required: tuple, label: str):
    """Each ``[[kind]]`` table of ``src`` with its line, checked for unknown and missing keys (errors name the
    table by its ``label`` key, else by its number)."""
    for i, raw in enumerate(src.data.get(kind, [])):
        line = src.table_line(kind, i)
        if not isinstance(raw, dict):
            raise src.error(f"a [[{kind}]] must be a table", line)
        extra = set(raw) - keys
        if extra:
            raise src.error(f"unknown key(s) {', '.join(sorted(extra))} (known: {', '.join(sorted(keys))})", line)
        for key in required:
            if key not in raw:
                raise src.error(f"[[{kind}]] {raw.get(label, i + 1)!r}: '{key}' is missing", line)
        yield line, raw
