"""``domes studio``: the design dialogue, a mechanism editor, synthesis and the knowledge base in the browser."""

from __future__ import annotations

import argparse

from domes.errors import InputError

#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "studio": "DOMES Studio: the design dialogue, a mechanism editor, path sketching and the knowledge base in "
              "the browser (a local web application)",
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "studio",
        help=COMMANDS["studio"],
        description="Start DOMES Studio, a local web application over the same library as the commands: the "
        "design dialogue, a mechanism editor (drag joints, see the coupler curves, dead and branch points), "
        "path sketching and precision positions, and the knowledge base. It answers only on the loopback "
        "address unless --host says otherwise, on a free port, and prints its address; it reads and writes "
        "files only in the data folder and the files named here. Ctrl-C stops it.",
    )
    p.add_argument("files", nargs="*", metavar="FILE", help="mechanism files (JSON) the editor may open and save")
    p.add_argument("--host", default="127.0.0.1", help="the address to answer on (default 127.0.0.1: this "
                   "machine only)")
    p.add_argument("--port", type=int, default=0, help="the port (default 0: a free one)")
    p.add_argument("--home", default=None, metavar="DIR",
                   help="the data folder the studio reads and writes (default: your DOMES data folder, "
                   "$DOMES_HOME or ~/.local/share/domes)")
    p.add_argument("--db", default=None, help="case base: SQLAlchemy URL or path (default: your case base)")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from pathlib import Path

    from domes.io.resources import user_dir
    from domes.studio.app import Studio
    from domes.studio.serve import serve

    if not 0 <= args.port <= 65535:
        raise InputError(f"--port must be 0 (a free port) to 65535, got {args.port}")
    if args.home is not None and not Path(args.home).is_dir():
        raise InputError(f"--home {args.home}: no such folder")
    home = Path(args.home) if args.home is not None else user_dir()
    try:
        home.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot make the data folder {home}: {exc.strerror}") from None
    for name in args.files:
        if not Path(name).is_file():
            raise InputError(f"{name}: no such file")
    studio = Studio(home, args.db, set(args.files), args.host, args.port)
    try:
        serve(studio)
    except KeyboardInterrupt:
        pass
    return 0
