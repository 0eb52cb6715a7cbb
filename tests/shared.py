"""Tables built once in a test run and shared by every test (and every ``pytest -n`` worker) that needs them."""

from __future__ import annotations

import fcntl
import os
from pathlib import Path


def shared_file(tmp_path_factory, name: str, write) -> Path:
    """The file ``name`` that ``write(path)`` makes: under ``pytest -n`` the first worker to need it writes it to
    the folder the workers' temporary folders share, and the others find it there."""
    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent
    path = shared / name
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not path.is_file():
            write(path)
    return path


def small_atlas_file(tmp_path_factory, kind: str = "closed") -> Path:
    """The small atlas of coupler curves (``open``: its window index) as ``domes curves match`` builds it, saved."""
    from domes.io.atlas import save_atlas
    from domes.motion.coupler.atlas import SIZES, build, build_windows

    make = build if kind == "closed" else build_windows
    name = "fourbar-small.h5" if kind == "closed" else "fourbar-small-open.h5"
    return shared_file(tmp_path_factory, name, lambda path: save_atlas(make(SIZES["small"]), path))


#: The exit status of a forked command that raised.
TRACEBACK = 99


def forked_main(argv: list[str], folder: Path, out: Path | str, err: Path | str, *, env: dict[str, str] | None = None,
                alarm: int = 300, limits=None) -> int:
    """``domes ARGV`` run by the console script's entry point (:func:`domes.cli.main`) in a child forked from this
    process (the package already imported, so a run costs only its own work): in ``folder``, with an empty stdin,
    stdout and stderr to the files ``out`` and ``err``, ``env`` as its environment (None: this one's), ended by
    SIGALRM after ``alarm`` s; ``limits()`` runs first in the child (resource limits). Returns the wait status
    (:func:`os.waitpid`); a child that raised exits with :data:`TRACEBACK`, the trace on stderr."""
    import contextlib
    import io
    import signal
    import sys
    import traceback

    from domes.cli import main

    sys.stdout.flush()
    sys.stderr.flush()
    pid = os.fork()
    if pid == 0:  # the child: never returns
        status = TRACEBACK
        try:
            signal.signal(signal.SIGALRM, signal.SIG_DFL)
            signal.signal(signal.SIGINT, signal.SIG_DFL)
            signal.alarm(alarm)
            if limits is not None:
                limits()
            if env is not None:
                os.environ.clear()
                os.environ.update(env)
            os.chdir(folder)
            os.dup2(os.open(os.devnull, os.O_RDONLY), 0)
            for fd, name in ((1, out), (2, err)):
                os.dup2(os.open(name, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600), fd)
            sys.stdin = io.StringIO("")
            sys.stdout = open(1, "w", encoding="utf-8", closefd=False)
            sys.stderr = open(2, "w", encoding="utf-8", closefd=False)
            import logging

            logging.getLogger("domes").handlers.clear()
            try:
                status = main(argv)
            except SystemExit as stop:
                status = stop.code if isinstance(stop.code, int) else 2
        except BaseException:  # noqa: BLE001 - what the tests look for
            traceback.print_exc()
            status = TRACEBACK
        finally:
            with contextlib.suppress(BaseException):
                sys.stdout.flush()
                sys.stderr.flush()
            os._exit(status if isinstance(status, int) and 0 <= status < 256 else TRACEBACK)
    return os.waitpid(pid, 0)[1]


def studio_server(home: Path):
    """``domes studio`` in a process of its own on the data folder ``home`` (its case base copied from the embedded
    one if it has none), on a free port: yields its address (``http://127.0.0.1:PORT``), then stops it."""
    import re
    import shutil
    import subprocess
    import sys

    from domes.io.resources import shipped_casebase

    if not (home / "casebase.db").is_file():
        shutil.copyfile(shipped_casebase(), home / "casebase.db")
    env = {name: value for name, value in os.environ.items() if name != "DOMES_DB"}
    env.update(DOMES_HOME=str(home), PYTHONUNBUFFERED="1")
    proc = subprocess.Popen([sys.executable, "-m", "domes", "studio", "--home", str(home)], env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    line = proc.stdout.readline()
    found = re.search(r"http://127\.0\.0\.1:\d+", line)
    if not found:
        proc.kill()
        raise AssertionError(f"domes studio did not say its address: {line}{proc.stdout.read()}")
    yield found.group()
    proc.terminate()
    try:
        proc.wait(10)
    except subprocess.TimeoutExpired:
        proc.kill()
