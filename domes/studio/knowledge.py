"""The knowledge panel's routes: the criteria, their edits and history, the scenes and the solved problems.

Thin wrappers over what ``domes kb`` and ``domes cases`` call: the case base is the studio's ``db`` or, when it is
None, the user's case base as the command line chooses it (made from the embedded one on the first edit). Every
edit is one transaction of :class:`~domes.store.casebase.KnowledgeBase` with its history entry; a refused edit
changes nothing. An edit or parse refused for its text answers 400 with the field and the column of the fault, so
the page can mark the place.

>>> from starlette.testclient import TestClient
>>> from domes.studio.app import Studio, make_app
>>> import tempfile
>>> client = TestClient(make_app(Studio(tempfile.mkdtemp())), base_url="http://127.0.0.1:8765")
>>> client.post("/api/kb/parse", json={"text": "every vertex must have degree at most 3"}).json()["reading"]
'every vertex must have degree at most 3'
>>> bad = client.post("/api/kb/parse", json={"text": "every vertex must have type (G P R"}).json()
>>> bad["column"], bad["error"][:10]
(35, 'column 35:')
"""

from __future__ import annotations

from starlette.responses import JSONResponse

from domes.errors import DomesError, InputError
from domes.knowledge.frames import CriterionFrame
from domes.language.parse import CriterionSyntaxError, parse_criterion, parse_relevance
from domes.language.render import render_criterion, render_relevance
from domes.language.tree import category, to_json
from domes.store.casebase import KnowledgeBase, shown
from domes.studio.app import api

#: The fields of a criterion the editor may set (``domes kb add`` / ``edit`` options, without the dashes).
FIELDS = ("text", "explanation", "keywords", "relevance", "level", "source", "date")


def _base(studio, command: str | None = None) -> KnowledgeBase:
    """The case base, for reading (``command`` None) or for a change that ``command`` makes (kept in its
    history as ``domes studio kb COMMAND``, as ``domes kb COMMAND`` would)."""
    if command is None:
        return KnowledgeBase(studio.db)
    return KnowledgeBase(studio.db, write=True, actor=f"domes studio kb {command}")


def _only(body: dict, allowed: tuple[str, ...], route: str) -> None:
    unknown = sorted(set(body) - set(allowed))
    if unknown:
        raise InputError(f"{route}: unknown field(s) {', '.join(unknown)}; it takes {', '.join(allowed)}")


def _text(body: dict, key: str, required: bool = False) -> str | None:
    value = body.get(key)
    if value is None:
        if required:
            raise InputError(f"{key}: required")
        return None
    if not isinstance(value, str):
        raise InputError(f"{key}: expected text, got {type(value).__name__}")
    return value


def _flag(body: dict, key: str) -> bool:
    value = body.get(key, False)
    if not isinstance(value, bool):
        raise InputError(f"{key}: expected true or false, got {value!r}")
    return value


def _criterion_id(body: dict) -> str:
    value = _text(body, "id")
    if not value:
        raise InputError('id: say which criterion, e.g. {"id": "swing-arm-on-ground"}')
    return value


def _changes(body: dict) -> dict:
    """The frame fields ``body`` sets, checked as the command line's options are (None or absent: not set)."""
    changes = {}
    for key in ("text", "explanation", "relevance", "source", "date"):
        value = _text(body, key)
        if value is not None:
            changes[key] = value
    keywords = body.get("keywords")
    if isinstance(keywords, str):  # as --keywords: comma-separated
        changes["keywords"] = [w.strip() for w in keywords.split(",") if w.strip()]
    elif isinstance(keywords, list):
        changes["keywords"] = keywords
    elif keywords is not None:
        raise InputError(f"keywords: expected a list of keywords or comma-separated text, got {keywords!r}")
    level = body.get("level")
    if isinstance(level, str) and level.strip():
        if not level.strip().isdigit():
            raise InputError(f"level: expected a whole number, got {level!r}")
        changes["level"] = int(level)
    elif level is not None and level != "":
        changes["level"] = level  # CriterionFrame checks it is a whole number in range
    return changes


def syntax_error(field: str, exc: CriterionSyntaxError) -> JSONResponse:
    """A 400 answer naming the field and the place (0-based ``position``, 1-based ``column``) of a parse error."""
    prefix = f"{field}: " if field != "parse" else ""
    return JSONResponse({"error": f"{prefix}{exc}", "field": field if field != "parse" else "text",
                         "position": exc.position, "column": exc.position + 1, "expected": exc.expected}, 400)


def _located(exc: InputError, changes: dict):
    """A frame refused for its text or relevance: the error at its place in the text as typed (the frame
    parses the text with its spaces folded); any other refusal is raised as it is."""
    field = str(exc).split(":", 1)[0]
    if field in ("text", "relevance") and isinstance(changes.get(field), str):
        try:
            (parse_criterion if field == "text" else parse_relevance)(changes[field])
        except CriterionSyntaxError as located:
            return syntax_error(field, located)
    raise exc


def criterion(frame: CriterionFrame, number: int | None = None) -> dict:
    """A frame as the page shows it: its fields, its reading and (``number``) its place in the order."""
    out = frame.to_dict()
    out["relevance_reading"] = render_relevance(frame.relevance)
    if number is not None:
        out["number"] = number
    return out


def criteria(studio, body: dict) -> dict:
    """Every criterion, in knowledge-base order (the order of the relevance vector), as ``domes kb list``."""
    with _base(studio) as kb:
        frames, where = kb.frames(), shown(kb.url)
    return {"db": where, "criteria": [criterion(f, n) for n, f in enumerate(frames, 1)],
            "enabled": sum(f.enabled for f in frames)}


def parse(studio, body: dict):
    """``domes kb parse``: the tree, category and reading of a criterion (or, ``relevance``, a relevance
    condition); a text that does not parse answers 400 with the column."""
    _only(body, ("text", "relevance"), "parse")
    text = _text(body, "text", required=True)
    try:
        if _flag(body, "relevance"):
            tree = parse_relevance(text)
            return {"relevance": to_json(tree), "reading": render_relevance(tree)}
        tree = parse_criterion(text)
    except CriterionSyntaxError as exc:
        return syntax_error("parse", exc)
    return {"criterion": to_json(tree), "category": category(tree), "reading": render_criterion(tree)}


def add(studio, body: dict):
    """``domes kb add``: a new criterion at the end of the order."""
    _only(body, ("id", *FIELDS, "disabled", "why"), "add")
    changes = _changes(body)
    if "text" not in changes:
        raise InputError("text: a criterion needs its text, e.g. 'every vertex must have degree at most 3'")
    try:
        frame = CriterionFrame.create(_criterion_id(body), enabled=not _flag(body, "disabled"), **changes)
    except InputError as exc:
        return _located(exc, changes)
    with _base(studio, "add") as kb:
        kb.add(frame, why=_text(body, "why") or "")
    return {"message": f"added {frame.id}: category ({frame.category}), level {frame.level}: "
                       f"{render_criterion(frame.tree)}", "criterion": criterion(frame)}


def edit(studio, body: dict):
    """``domes kb edit``: change fields of a criterion (its place in the order is kept)."""
    _only(body, ("id", *FIELDS, "why"), "edit")
    criterion_id, changes = _criterion_id(body), _changes(body)
    if not changes:
        raise InputError("nothing to change: give text, explanation, keywords, relevance, level, source or date")
    with _base(studio, "edit") as kb:
        try:
            frame = kb.get(criterion_id).edited(**changes)
        except InputError as exc:
            return _located(exc, changes)
        kb.update(frame, why=_text(body, "why") or "")
    return {"message": f"edited {frame.id}: category ({frame.category}), level {frame.level}: "
                       f"{render_criterion(frame.tree)}", "criterion": criterion(frame)}


def _switch(enable: bool):
    command = "enable" if enable else "disable"

    def switch(studio, body: dict) -> dict:
        _only(body, ("id", "why"), command)
        criterion_id = _criterion_id(body)
        with _base(studio, command) as kb:
            kb.update(kb.get(criterion_id).with_enabled(enable), why=_text(body, "why") or "",
                      action=f"{command} criterion")
        return {"message": f"{command}d {criterion_id}"}

    switch.__name__ = command
    switch.__doc__ = f"``domes kb {command}``: {command} a criterion (a disabled one is kept, not applied)."
    return switch


def remove(studio, body: dict) -> dict:
    """``domes kb remove``: remove a criterion (``undo`` brings it back at its place)."""
    _only(body, ("id", "why"), "remove")
    criterion_id = _criterion_id(body)
    with _base(studio, "remove") as kb:
        kb.remove(criterion_id, why=_text(body, "why") or "")
    return {"message": f"removed {criterion_id}"}


def entry(e, changes: bool = False) -> dict:
    """A history entry as the page lists it (``changes``: with every row before and after)."""
    out = e.to_dict()
    out["summary"] = e.summary
    if not changes:
        del out["changes"]
    return out


def history(studio, body: dict) -> dict:
    """``domes kb history``: every change of the case base, oldest first (``changes``: the rows too)."""
    full = str(body.get("changes", "")).lower() in ("1", "true", "yes")
    with _base(studio) as kb:
        entries = kb.history()
    return {"history": [entry(e, full) for e in entries]}


def undo(studio, body: dict) -> dict:
    """``domes kb undo [N]``: take back the last change, or every change from entry N on."""
    _only(body, ("entry",), "undo")
    number = body.get("entry")
    if number is not None and (not isinstance(number, int) or isinstance(number, bool)):
        raise InputError(f"entry: expected the number of a history entry, got {number!r}")
    with _base(studio, "undo") as kb:
        undone = kb.undo(number)
    return {"undone": [entry(e) for e in undone],
            "message": "; ".join(f"undone {e.number}: {e.action} {e.target} ({e.summary})" for e in undone)}


def _scene(scene) -> dict:
    """A scene as the library reads it: its chains, stages with their rules, checks and requirements."""
    stages = [{"number": i, "name": s.name, "kind": s.kind, "role": s.role, "select": s.select, "joint": s.joint,
               "optional": s.optional, "change": s.tag, "line": s.line,
               "rules": [{"text": t, "reading": render_criterion(r)} for t, r in zip(s.rule_text, s.rules)]}
              for i, s in enumerate(scene.stages, 1)]
    counts = list(scene.book_counts) or [None] * len(stages)
    for stage, count in zip(stages, counts):
        stage["book"] = count
    return {"name": scene.name, "title": scene.title, "source": scene.source, "links": scene.links,
            "dof": scene.dof, "include_fractionated": scene.include_fractionated, "clamping": scene.clamping,
            "roles": scene.roles, "stages": stages, "book_note": scene.book_note,
            "particularize": [{"between": list(p.between), "joint": p.joint} for p in scene.particularize],
            "existing": len(scene.existing), "checks": [{"check": c.usage, "why": c.why} for c in scene.checks],
            "requirements": [r.to_dict() for r in scene.requirements], "design": scene.design}


def scenes(studio, body: dict) -> dict:
    """The shipped design scenes (``domes regenerate NAME``); with ``name``, that scene read whole."""
    from domes.io.scenes import load_scene, scene_names

    name = _text(body, "name")
    if name:
        if name not in scene_names():
            raise InputError(f"no scene {name!r}; the scenes are {', '.join(scene_names())}")
        return {"scene": _scene(load_scene(name))}
    listed = []
    for n in scene_names():
        try:
            s = load_scene(n)
        except DomesError as exc:
            listed.append({"name": n, "error": str(exc)})
            continue
        listed.append({"name": n, "title": s.title, "links": s.links, "dof": s.dof, "stages": len(s.stages)})
    return {"scenes": listed}


def cases(studio, body: dict) -> dict:
    """``domes cases list``; with ``id``, ``domes cases show ID``: the solved problem's frame and its text."""
    from domes.expert.world import frame_text

    case_id = _text(body, "id")
    with _base(studio) as kb:
        if case_id:
            frame = kb.get_problem(case_id)
            return {"case": frame.to_dict(), "text": frame_text(frame)}
        problems = kb.problems()
    return {"cases": [{"id": p.id, "title": p.title, "problem_class": p.problem_class, "dof": p.dof,
                       "loops": p.loops, "links": p.links, "joints": p.joints, "slider_pairs": p.slider_pairs or 0,
                       "gear_pairs": p.gear_pairs or 0, "kept": len(p.results), "space": p.space}
                      for p in problems]}


routes = [
    api("/api/kb/criteria", criteria, ("GET",)),
    api("/api/kb/parse", parse),
    api("/api/kb/add", add),
    api("/api/kb/edit", edit),
    api("/api/kb/enable", _switch(True)),
    api("/api/kb/disable", _switch(False)),
    api("/api/kb/remove", remove),
    api("/api/kb/history", history, ("GET",)),
    api("/api/kb/undo", undo),
    api("/api/kb/scenes", scenes, ("GET",)),
    api("/api/kb/cases", cases, ("GET",)),
]
