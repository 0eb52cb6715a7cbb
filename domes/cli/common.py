"""What the subcommands share: progress on stderr, the case-base option, writing an output.

The subcommands' modules import what their commands compute with inside the commands, not at the top: building
the parser (``domes --help``) loads no numerical library.

>>> import argparse
>>> p = argparse.ArgumentParser(parents=[db_option()])
>>> p.parse_args(["--db", "x.db"]).db
'x.db'
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import select
import sys

from domes.errors import InputError
from domes.execution import SCHEDULER_VARIABLE
from domes.execution.watch import WORKER_TIMEOUT, WORKER_TIMEOUT_VARIABLE
from domes.io.files import write_atomic
from domes.io.resources import DB_ENV
from domes.results import Progress, Ticker

#: Without a terminal (a log, a pipe), progress is one line per this many seconds at most: a long run says it is
#: alive, a short one says nothing.
LOG_EVERY = 5.0


def read_line(prompt: str = "") -> str:
    """:func:`input` that sees a Ctrl-C at once on a terminal.

    ``input`` blocks in C: a SIGINT that lands between the prompt and the blocking read is only noticed at the next
    key. Here the wait returns to Python every quarter second, where a pending KeyboardInterrupt is raised. A
    terminal in canonical mode hands over one line per read; anything else (a pipe, a file) goes to ``input``.
    """
    if not (sys.stdin.isatty() and sys.stdout.isatty()):
        return input(prompt)
    sys.stdout.write(prompt)
    sys.stdout.flush()
    fd = sys.stdin.fileno()
    while not select.select([fd], [], [], 0.25)[0]:
        pass
    line = os.read(fd, 65536)
    if not line:
        raise EOFError
    return line.decode(sys.stdin.encoding or "utf-8", errors="replace").rstrip("\r\n")


def progress_printer(enabled: bool | None = None, every: float = 0.0) -> Progress | None:
    """A progress callback printing ``... message`` on stderr: by default (None) as it comes on a terminal and one
    line every :data:`LOG_EVERY` seconds elsewhere; True: always as it comes; False: never.

    ``every``: at most one line per that many seconds (the others are dropped), for a log rather than a terminal.
    """
    if enabled is False:
        return None
    if enabled is None and not sys.stderr.isatty():
        every = max(every, LOG_EVERY)
    show = lambda message: print(f"... {message}", file=sys.stderr, flush=True)          # noqa: E731
    if every <= 0:
        return show
    clock = Ticker(show, every)
    return lambda message: clock.tick(lambda: message)


#: The help text of every --db option.
DB_HELP = (f"SQLAlchemy URL or SQLite file of the case base (default: ${DB_ENV}, else your case base, "
           "made from the embedded casebase.db when you first change something)")


def parallel_options(parser: argparse.ArgumentParser, what: str) -> None:
    """``--workers N`` and ``--scheduler ADDRESS`` (see :mod:`domes.execution`): where ``what`` runs."""
    parser.add_argument("--workers", type=int, default=None, metavar="N",
                        help=f"{what} on a local Dask cluster of N worker processes (default: in this process; the "
                        f"result is the same); a run with no worker alive for ${WORKER_TIMEOUT_VARIABLE} seconds "
                        f"(default {WORKER_TIMEOUT:g}) stops and says so")
    parser.add_argument("--scheduler", metavar="ADDRESS",
                        help=f"{what} on an existing Dask cluster, e.g. tcp://host:8786 (default: "
                        f"${SCHEDULER_VARIABLE} if set)")


def db_option() -> argparse.ArgumentParser:
    """A parent parser with ``--db URL``: the case base of a subcommand."""
    parent = argparse.ArgumentParser(add_help=False)
    parent.add_argument("--db", metavar="URL", help=DB_HELP)
    return parent


def finite_json(obj):
    """JSON without NaN/Infinity: non-finite numbers become null (e.g. derivatives at a singular point)."""
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: finite_json(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [finite_json(v) for v in obj]
    return obj


def available_memory() -> int | None:
    """The memory this machine can give a new run (``MemAvailable``), in bytes; None where it cannot be read."""
    try:
        with open("/proc/meminfo", encoding="ascii") as info:
            for line in info:
                if line.startswith("MemAvailable:"):
                    return int(line.split()[1]) * 1024
    except (OSError, ValueError, IndexError):
        pass
    return None


def confirm(command: str, message: str, yes: bool) -> None:
    """Go on with a long run only when the user agrees: ``--yes``, or 'yes' typed at a terminal.

    Without a terminal to ask on, the run is refused with the message and the hint to pass ``--yes``.
    """
    if yes:
        return
    if not sys.stdin.isatty():
        raise InputError(f"{message}; pass --yes to run it anyway")
    print(f"domes {command}: {message}.", file=sys.stderr)
    if input("Go on? [y/N] ").strip().lower() not in ("y", "yes"):
        raise InputError("not run (the answer was not 'yes')")


def write_output(text: str, path: str | None) -> None:
    """Write to standard output, or atomically to ``path``."""
    if path is None:
        sys.stdout.write(text)
    else:
        write_atomic(path, text)


def write_document(doc: dict, fmt: str, *, html, rows, text) -> None:
    """Write a command's document to standard output as ``json``, ``html`` (``html(doc)``, a page), ``csv``
    (``rows(doc)``: the header, then the rows) or ``text`` (``text(out, doc)``)."""
    out = sys.stdout
    if fmt == "json":
        json.dump(finite_json(doc), out, indent=1)
        out.write("\n")
    elif fmt == "html":
        out.write(html(doc))
    elif fmt == "csv":
        writer = csv.writer(out)
        for k, row in enumerate(rows(doc)):
            writer.writerow(row if k == 0 else [repr(v) for v in row])
    else:
        text(out, doc)
