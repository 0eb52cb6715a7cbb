"""What the studio's server lets a request do: answer on its own address, post from its own pages, stay small,
and read or write files only in the user's data folder and the files the user opened.

A page of another site open in the same browser can send requests to ``127.0.0.1``; the server therefore
answers only requests whose ``Host`` is its own address (no DNS rebinding) and takes a change (POST, PUT,
DELETE) only as JSON from its own origin (a cross-origin form or fetch carries another ``Origin``, and
cannot send ``application/json`` without the browser asking first).

>>> confine("/home/u/.local/share/domes", "mechanisms/a.json")
PosixPath('/home/u/.local/share/domes/mechanisms/a.json')
>>> confine("/home/u/.local/share/domes", "../../.ssh/id_rsa")
Traceback (most recent call last):
...
domes.studio.security.Refused: ../../.ssh/id_rsa is outside the studio's data folder /home/u/.local/share/domes
"""

from __future__ import annotations

import os
from pathlib import Path

from domes.errors import InputError

#: The largest request body taken, in bytes (a mechanism, a sketched path, a criterion: well under this).
MAX_BODY = 1 << 20

#: The methods that change something: taken only as JSON from the studio's own pages.
CHANGES = frozenset({"POST", "PUT", "PATCH", "DELETE"})


class Refused(InputError):
    """A request the studio does not serve; ``status`` is the HTTP status it answers with."""

    def __init__(self, message: str, status: int = 403):
        super().__init__(message)
        self.status = status


def confine(folder: str | Path, name: str | Path, opened: frozenset[Path] | set[Path] = frozenset()) -> Path:
    """The path ``name`` (relative to ``folder``, or absolute) if it lies inside ``folder`` or is one of the
    files the user ``opened``; otherwise :class:`Refused`. Links are followed before the test."""
    base = Path(os.path.realpath(folder))
    text = str(name)
    if not text or "\x00" in text:
        raise Refused(f"{text!r} is not a file name", 400)
    path = Path(os.path.realpath(base / name))
    if path == base or base in path.parents or path in {Path(os.path.realpath(p)) for p in opened}:
        return path
    raise Refused(f"{name} is outside the studio's data folder {folder}")


def allowed_hosts(host: str, port: int) -> frozenset[str]:
    """The ``Host`` headers of requests to a server bound to ``host``:``port``."""
    names = {host}
    if host in ("127.0.0.1", "localhost", "::1"):
        names |= {"127.0.0.1", "localhost", "[::1]"}
    if ":" in host and not host.startswith("["):
        names.add(f"[{host}]")
    return frozenset({f"{n}:{port}" for n in names} | ({f"{n}" for n in names} if port == 80 else set()))


def check_request(method: str, headers: dict[str, str], hosts: frozenset[str]) -> None:
    """Refuse a request to another host name, or a change that is not JSON from the studio's own origin.

    >>> hosts = allowed_hosts("127.0.0.1", 8000)
    >>> check_request("GET", {"host": "localhost:8000"}, hosts)
    >>> check_request("POST", {"host": "127.0.0.1:8000", "origin": "http://evil.example",
    ...                        "content-type": "application/json"}, hosts)
    Traceback (most recent call last):
    ...
    domes.studio.security.Refused: a change posted from another site (http://evil.example) is refused
    """
    host = headers.get("host", "")
    if host not in hosts:
        raise Refused(f"this server answers only as {sorted(hosts)[0]}, not as {host or 'no host'!r}", 400)
    if method not in CHANGES:
        return
    origin = headers.get("origin")
    if origin is not None and origin.split("://", 1)[-1] not in hosts:
        raise Refused(f"a change posted from another site ({origin}) is refused")
    if headers.get("sec-fetch-site", "same-origin") not in ("same-origin", "none"):
        raise Refused(f"a change posted from another site ({headers['sec-fetch-site']}) is refused")
    kind = headers.get("content-type", "").split(";")[0].strip().lower()
    if kind != "application/json":
        raise Refused(f"a change must be sent as application/json, not {kind or 'no content type'}", 415)
    size = headers.get("content-length")
    if size is not None and (not size.isdigit() or int(size) > MAX_BODY):
        raise Refused(f"the request body of {size} bytes is larger than the {MAX_BODY:,} bytes taken", 413)


__all__ = ["MAX_BODY", "Refused", "allowed_hosts", "check_request", "confine"]
