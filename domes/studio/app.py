"""The studio's web application: one Starlette app over the library, its routes collected from the panels' modules.

Every route is a plain function ``fn(studio, body) -> dict`` wrapped by :func:`api`: the body is a JSON
object (a POST) or the query's parameters (a GET); the answer is JSON; an error in the input is a 400 with
``{"error": "..."}`` saying what was wrong, as the command line would. The routes run one at a time in the
server's own thread (no thread pool): a long stage, the design dialogue's, runs in a worker process of its
own that the page can cancel.

>>> from starlette.testclient import TestClient
>>> import tempfile
>>> client = TestClient(make_app(Studio(tempfile.mkdtemp())), base_url="http://127.0.0.1:8765")
>>> client.get("/api/about").json()["name"]
'DOMES Studio'
>>> client.post("/api/about", content=b"{", headers={"content-type": "application/json"}).json()["error"]
'request body: line 1, column 2: invalid JSON: Expecting property name enclosed in double quotes'
"""

from __future__ import annotations

import importlib
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

from starlette.applications import Starlette
from starlette.requests import Request
from starlette.responses import FileResponse, JSONResponse, Response
from starlette.routing import Mount, Route
from starlette.staticfiles import StaticFiles

from domes import __version__
from domes.errors import DomesError, InputError
from domes.io.files import read_json
from domes.studio.security import CHANGES, MAX_BODY, Refused, allowed_hosts, check_request, confine

#: Where the page's assets are (shipped with the package).
STATIC = Path(__file__).parent / "static"

#: The modules whose ``routes`` the app serves, one per panel.
PANELS = ("domes.studio.mechanism", "domes.studio.synthesis", "domes.studio.knowledge", "domes.studio.dialogue")


@dataclass
class Studio:
    """What the server knows: the user's data folder, the case base, the files opened, the live sessions."""

    home: str | Path
    db: str | None = None
    opened: set[Path] = field(default_factory=set)
    host: str = "127.0.0.1"
    port: int = 8765
    #: Per-panel state (the dialogue's sessions, ...), by the panel's name.
    state: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        self.home = Path(self.home)
        self.opened = {Path(p).resolve() for p in self.opened}

    def path(self, name: str | Path) -> Path:
        """The file ``name`` if the studio may read or write it (:func:`~domes.studio.security.confine`)."""
        return confine(self.home, name, self.opened)


def finite(value):
    """``value`` with every float that is not finite turned into None (JSON has no NaN or infinity)."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: finite(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [finite(v) for v in value]
    return value


def answer(value, status: int = 200) -> JSONResponse:
    """A JSON answer (non-finite numbers as null)."""
    return JSONResponse(finite(value), status)


def error(message: str, status: int = 400) -> JSONResponse:
    return JSONResponse({"error": message}, status)


async def body_of(request: Request) -> dict:
    """The request's JSON object, read at most :data:`~domes.studio.security.MAX_BODY` bytes far."""
    data = bytearray()
    async for chunk in request.stream():
        data += chunk
        if len(data) > MAX_BODY:
            raise Refused(f"the request body is larger than the {MAX_BODY:,} bytes taken", 413)
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"request body: not UTF-8 text (byte {exc.start})") from None
    value = read_json("request body", text or "{}")
    if not isinstance(value, dict):
        raise InputError(f"request body: a JSON object is needed, got {type(value).__name__}")
    return value


def api(path: str, fn: Callable[[Studio, dict], Any], methods: tuple[str, ...] = ("POST",)) -> Route:
    """A route that calls ``fn(studio, body)`` and answers its value as JSON (a Response as it is)."""

    async def endpoint(request: Request) -> Response:
        studio = request.app.state.studio
        try:
            body = await body_of(request) if request.method in CHANGES else dict(request.query_params)
            value = fn(studio, body)
        except Refused as exc:
            return error(str(exc), exc.status)
        except DomesError as exc:
            return error(str(exc))
        return value if isinstance(value, Response) else answer(value)

    endpoint.__name__ = fn.__name__
    return Route(path, endpoint, methods=list(methods))


class Guard:
    """ASGI middleware: every request passes :func:`~domes.studio.security.check_request` first; every answer
    carries headers that keep the pages from loading anything from elsewhere or being framed."""

    HEADERS = [(b"content-security-policy", b"default-src 'self'; img-src 'self' data:; style-src 'self' "
                b"'unsafe-inline'; frame-ancestors 'none'; form-action 'self'"),
               (b"x-content-type-options", b"nosniff"), (b"referrer-policy", b"no-referrer")]

    def __init__(self, app, hosts: frozenset[str]):
        self.app, self.hosts = app, hosts

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            return await self.app(scope, receive, send)
        headers = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in scope["headers"]}
        try:
            check_request(scope["method"], headers, self.hosts)
        except Refused as exc:
            return await error(str(exc), exc.status)(scope, receive, send)

        async def secured(message):
            if message["type"] == "http.response.start":
                message = {**message, "headers": [*message.get("headers", []), *self.HEADERS]}
            await send(message)

        await self.app(scope, receive, secured)


def about(studio: Studio, body: dict) -> dict:
    """The server's name, version, data folder and case base."""
    return {"name": "DOMES Studio", "version": __version__, "home": str(studio.home),
            "db": studio.db or "your case base (or the embedded one until you change something)"}


def files(studio: Studio, body: dict) -> dict:
    """The JSON files the studio may open: those in the data folder (``mechanisms/`` first) and those opened."""
    home = Path(studio.home)
    found = sorted(str(p.relative_to(home)) for p in home.rglob("*.json") if p.is_file() and not
                   any(part.startswith(".") for part in p.relative_to(home).parts))[:1000]
    return {"home": str(home), "files": found, "opened": sorted(str(p) for p in studio.opened)}


def open_file(studio: Studio, body: dict) -> dict:
    """The JSON value of the file ``name`` (in the data folder, or one the user opened)."""
    name = body.get("name")
    if not isinstance(name, str):
        raise InputError("say which file to open: {\"name\": \"mechanisms/linkage.json\"}")
    path = studio.path(name)
    if not path.is_file():
        raise Refused(f"{name}: no such file in the data folder {studio.home}", 404)
    if path.stat().st_size > MAX_BODY:
        raise Refused(f"{name}: {path.stat().st_size:,} bytes, more than the {MAX_BODY:,} the studio opens", 413)
    return {"name": name, "path": str(path), "content": read_json(path)}


def make_app(studio: Studio) -> Starlette:
    """The studio's application over ``studio`` (its folder, case base and address)."""
    routes = [Route("/", lambda request: FileResponse(STATIC / "index.html")),
              api("/api/about", about, ("GET", "POST")), api("/api/files", files, ("GET",)),
              api("/api/open", open_file, ("GET", "POST"))]
    for name in PANELS:
        routes += importlib.import_module(name).routes
    routes.append(Mount("/static", StaticFiles(directory=STATIC), name="static"))
    app = Starlette(routes=routes)
    app.state.studio = studio
    app.add_middleware(Guard, hosts=allowed_hosts(studio.host, studio.port))
    return app


__all__ = ["PANELS", "Studio", "answer", "api", "body_of", "error", "finite", "make_app"]
