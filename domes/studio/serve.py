"""Start the studio's server: bound to the loopback address unless told otherwise, on a free port, its address said.

>>> bound = listening("127.0.0.1", 0)
>>> bound.getsockname()[0], bound.getsockname()[1] > 0
('127.0.0.1', True)
>>> bound.close()
"""

from __future__ import annotations

import socket
from typing import Callable

from domes.errors import InputError
from domes.studio.app import Studio, make_app

LOOPBACK = ("127.0.0.1", "localhost", "::1")


def listening(host: str, port: int) -> socket.socket:
    """A socket bound to ``host``:``port`` (0: a free port), listening; a clear error when it cannot be."""
    try:
        family = socket.AF_INET6 if ":" in host else socket.AF_INET
        sock = socket.socket(family, socket.SOCK_STREAM)
        sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
        sock.bind((host, port))
        sock.listen(64)
    except OSError as exc:
        raise InputError(f"cannot listen on {host}:{port}: {exc.strerror}") from None
    return sock


def serve(studio: Studio, say: Callable[[str], None] = print) -> None:
    """Serve the studio until interrupted (Ctrl-C); says its address first."""
    import uvicorn

    sock = listening(studio.host, studio.port)
    studio.port = sock.getsockname()[1]
    shown = f"[{studio.host}]" if ":" in studio.host else studio.host
    if studio.host not in LOOPBACK:
        say(f"warning: the studio answers on {studio.host}, not only on this machine's loopback address: anyone "
            "who can reach it can use your case base")
    say(f"DOMES Studio at http://{shown}:{studio.port}/ (data folder {studio.home}; Ctrl-C stops it)")
    server = uvicorn.Server(uvicorn.Config(make_app(studio), log_level="warning", access_log=False))
    server.run(sockets=[sock])


__all__ = ["listening", "serve"]
