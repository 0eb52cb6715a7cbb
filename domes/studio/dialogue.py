"""The design dialogue's routes: the terminal's ``domes design`` session, asked and answered in the page.

Each session runs :class:`~domes.expert.dialogue.Dialogue` in a worker process of its own
(:mod:`domes.studio.session`). It writes its report as ``domes design --report DIR`` does, into
``reports/ID/`` of the data folder, and records its transcript as ``--record`` does, into ``sessions/ID.json``:
started again with ``answers`` naming that transcript, it replays. A dry run (the default) works on a scratch
copy of the case base and keeps nothing; ``"dry_run": false`` keeps the solved problem and the criteria added.

* ``POST /api/design/start`` ``{dry_run?, answers?, method?, seeds?, time_budget?, vary?}``
* ``GET /api/design/events?session=ID&since=N``: the lines said from the N-th on, the pending question, the
  progress of a long stage, the funnel, and how the session ended
* ``POST /api/design/answer`` ``{session, text}``; ``POST /api/design/cancel`` ``{session}``
* ``GET /api/design/sessions``: the transcripts, saved sessions and answers files to replay, and the shipped cases
* ``GET /api/design/report/ID/NAME``: a file of the session's report folder

>>> session_id("20261129-043700-0a1b2c")
'20261129-043700-0a1b2c'
"""

from __future__ import annotations

import math
import re
import secrets
import tempfile
import time
from pathlib import Path

from starlette.requests import Request
from starlette.responses import FileResponse, Response
from starlette.routing import Route

from domes.errors import DomesError, InputError
from domes.io.files import read_json
from domes.studio.app import Studio, api, error
from domes.studio.security import Refused, confine
from domes.studio.session import Session

#: Sessions whose workers may run at once.
MAX_LIVE = 4
#: Where a session's report and transcript go, in the data folder.
REPORTS, SESSIONS = "reports", "sessions"
#: The prefix of a shipped case's name in ``answers`` (``case:pump``: ``knowledge/cases/pump.json``).
CASE = "case:"
ID = re.compile(r"^[A-Za-z0-9][A-Za-z0-9._-]{0,80}$")
#: At most this many files of each kind are listed.
LISTED = 200


def session_id(text) -> str:
    """``text`` if it can name a session (letters, digits, '.', '_', '-'); otherwise an InputError."""
    if not isinstance(text, str) or not ID.match(text) or ".." in text:
        raise InputError(f"'session' must name a session (as /api/design/start answered), got {text!r:.60}")
    return text


def sessions_of(studio: Studio) -> dict[str, Session]:
    return studio.state.setdefault("design", {})


def session_of(studio: Studio, body: dict) -> Session:
    name = session_id(body.get("session"))
    found = sessions_of(studio).get(name)
    if found is None:
        raise Refused(f"no session {name} on this server (it was started before the server was, or never)", 404)
    return found


def _flag(body: dict, key: str, default: bool) -> bool:
    value = body.get(key, default)
    if not isinstance(value, bool):
        raise InputError(f"{key!r} must be true or false, got {value!r:.40}")
    return value


def knobs_of(body: dict, recorded: dict | None) -> tuple[str, int, float | None]:
    """The dimensioning's method and seeds and the time budget, as ``domes design`` takes them (``--method``,
    ``--seeds``, ``--time-budget``); a replayed transcript's own knobs unless the body says otherwise."""
    from domes.design.methods import METHODS

    recorded = recorded if isinstance(recorded, dict) else {}
    method = body.get("method", recorded.get("method", "fast"))
    seeds = body.get("seeds", recorded.get("seeds", 16))
    budget = body.get("time_budget")
    if method not in METHODS:
        raise InputError(f"'method' must be one of {', '.join(METHODS)}, got {method!r:.40}")
    if isinstance(seeds, bool) or not isinstance(seeds, int) or not 1 <= seeds <= 4096:
        raise InputError(f"'seeds' must be a whole number from 1 to 4096, got {seeds!r:.40}")
    if budget is not None and (isinstance(budget, bool) or not isinstance(budget, (int, float))
                               or not (math.isfinite(budget) and budget > 0)):
        raise InputError(f"'time_budget' must be a positive number of seconds, got {budget!r:.40}")
    return method, seeds, None if budget is None else float(budget)


def answers_of(studio: Studio, name) -> tuple[list[tuple[str, str]], dict | None]:
    """The answers to replay from ``name`` (a file in the data folder: an answers file, a transcript or a saved
    session; or ``case:NAME``, a shipped case) and the knobs a transcript was recorded with."""
    from domes.io.transcripts import exchanges_answers, load_transcript, read_answers

    if not isinstance(name, str) or not name:
        raise InputError(f"'answers' must name an answers file or a transcript, got {name!r:.60}")
    if name.startswith(CASE):
        from domes.expert.replay import shipped_cases
        from domes.io.resources import knowledge_dir

        if name[len(CASE):] not in shipped_cases():
            raise InputError(f"{name}: no such shipped case (the cases are {', '.join(shipped_cases())})")
        path = knowledge_dir() / "cases" / f"{name[len(CASE):]}.json"
    else:
        path = studio.path(name)
        if not path.is_file():
            raise Refused(f"{name}: no such file in the data folder {studio.home}", 404)
    if path.suffix != ".json":
        return read_answers(path), None
    data = read_json(path)
    if isinstance(data, dict) and "format" not in data and "exchanges" in data:  # a saved (interrupted) session
        return exchanges_answers(data["exchanges"], name), None
    transcript = load_transcript(path)
    return exchanges_answers(transcript["exchanges"], name), transcript.get("knobs")


def start(studio: Studio, body: dict) -> dict:
    """Start a design session: a new problem, or the answers of ``answers`` replayed (then asked in the page)."""
    dry_run = _flag(body, "dry_run", True)
    vary = _flag(body, "vary", True)
    answers, recorded = answers_of(studio, body["answers"]) if body.get("answers") is not None else ([], None)
    method, seeds, budget = knobs_of(body, recorded)
    for s in sessions_of(studio).values():
        s.pump()
    live = [s for s in sessions_of(studio).values() if s.live]
    if len(live) >= MAX_LIVE:
        raise Refused(f"{len(live)} design sessions are running ({', '.join(s.id for s in live)}): end or cancel "
                      "one first", 429)
    sid = f"{time.strftime('%Y%m%d-%H%M%S')}-{secrets.token_hex(3)}"
    home = Path(studio.home)
    (home / SESSIONS).mkdir(parents=True, exist_ok=True)
    spec = {"db": studio.db, "answers": answers, "vary": vary, "method": method, "seeds": seeds,
            "time_budget": budget, "report": str(home / REPORTS / sid), "transcript": str(home / SESSIONS / f"{sid}.json"),
            "scratch": tempfile.mkdtemp(prefix="domes-dry-run-") if dry_run else None}
    session = Session(sid, home, spec, dry_run, body.get("answers")).start()
    sessions_of(studio)[sid] = session
    return session.view(0)


def events(studio: Studio, body: dict) -> dict:
    """What the session said from event ``since`` on, its pending question, progress, funnel and end."""
    session = session_of(studio, body)
    since = body.get("since", "0")
    try:
        since = int(since)
    except (TypeError, ValueError):
        raise InputError(f"'since' must be a whole number (the 'next' of the last answer), got {since!r:.40}") from None
    if since < 0:
        raise InputError(f"'since' must be 0 or more, got {since}")
    session.pump()
    return session.view(since)


def answer(studio: Studio, body: dict) -> dict:
    """Answer the session's pending question (an empty text takes the default, '?' asks for its help)."""
    session = session_of(studio, body)
    text = body.get("text")
    if not isinstance(text, str):
        raise InputError(f"'text' must be the answer's text, got {text!r:.40}")
    if "\n" in text.rstrip("\r\n") or len(text) > 10_000:
        raise InputError("an answer is one line of at most 10,000 characters")
    session.answer(text.rstrip("\r\n"))
    return session.view(len(session.events))


def cancel(studio: Studio, body: dict) -> dict:
    """Stop the session's worker at once (a dry run's scratch copy is removed; the case base is not touched)."""
    session = session_of(studio, body)
    session.cancel()
    return session.view(len(session.events))


def _listed(home: Path, pattern: str) -> list[Path]:
    found = [p for p in home.rglob(pattern) if p.is_file()
             and not any(part.startswith(".") for part in p.relative_to(home).parts)]
    return sorted(found, key=lambda p: p.stat().st_mtime, reverse=True)[:LISTED]


def recorded(studio: Studio, body: dict) -> dict:
    """The sessions to replay: transcripts and saved sessions (``sessions/``), answers files of the data folder,
    and the shipped cases."""
    from domes.expert.replay import shipped_cases

    home = Path(studio.home)
    out = []
    for path in _listed(home / SESSIONS, "*.json") if (home / SESSIONS).is_dir() else []:
        name = str(path.relative_to(home))
        try:
            data = read_json(path)
        except DomesError:
            continue
        if not isinstance(data, dict) or not isinstance(data.get("exchanges"), list):
            continue
        frame = data.get("frame") if isinstance(data.get("frame"), dict) else {}
        asked = {e.get("question"): e.get("answer") for e in data["exchanges"] if isinstance(e, dict)}
        problem = str(frame.get("title") or frame.get("problem_class") or asked.get("class") or "?")
        kind = "transcript" if "format" in data else "interrupted"
        out.append({"name": name, "kind": kind, "problem": problem.replace("_", " "), "relation": data.get("relation"),
                    "answers": len(data["exchanges"]), "date": time.strftime("%Y-%m-%d %H:%M", time.localtime(path.stat().st_mtime))})
    for path in _listed(home, "*.answers"):
        out.append({"name": str(path.relative_to(home)), "kind": "answers", "problem": path.stem.replace("-", " ")})
    for case in shipped_cases():
        out.append({"name": CASE + case, "kind": "case", "problem": case.replace("-", " ")})
    live = [s.id for s in sessions_of(studio).values() if s.live]
    return {"sessions": out, "live": live}


async def report_file(request: Request) -> Response:
    """A file of a session's report folder (``reports/ID/``), and nothing outside it."""
    studio = request.app.state.studio
    try:
        sid = session_id(request.path_params["session"])
        folder = Path(studio.home) / REPORTS / sid
        if not folder.is_dir():
            raise Refused(f"session {sid} wrote no report", 404)
        path = confine(folder, request.path_params["name"])
        if not path.is_file():
            raise Refused(f"{request.path_params['name']}: no such file in the report of session {sid}", 404)
    except Refused as exc:
        return error(str(exc), exc.status)
    except DomesError as exc:
        return error(str(exc))
    return FileResponse(path)


routes = [
    api("/api/design/start", start),
    api("/api/design/events", events, ("GET",)),
    api("/api/design/answer", answer),
    api("/api/design/cancel", cancel),
    api("/api/design/sessions", recorded, ("GET",)),
    Route("/api/design/report/{session}/{name:path}", report_file, methods=["GET"]),
]
