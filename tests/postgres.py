"""A throw-away PostgreSQL server for the tests that run the case base on PostgreSQL.

The server is Debian's (``apt-get install postgresql``: ``initdb``, ``pg_ctl``
and ``postgres`` under ``/usr/lib/postgresql/VERSION/bin``), started once per
test session in a temporary folder, listening only on a Unix socket in that
folder (no TCP port), and stopped and removed at the end. initdb refuses to
run as root: as root, the server runs as Debian's ``postgres`` system user.
Each test gets its own database. Where the server cannot start (no binaries,
no driver, no ``postgres`` user), the tests that need it are skipped and say
what is missing.

Use it by importing the fixtures into a test module::

    from tests.postgres import postgres_casebase_fixture, postgres_server_fixture  # noqa: F401

(the fixtures are named ``postgres_server`` and ``postgres_casebase``).
"""

from __future__ import annotations

import atexit
import glob
import itertools
import os
import pwd
import re
import shutil
import stat
import subprocess
import tempfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]  # the checkout

INSTALL = "apt-get install postgresql (Debian's PostgreSQL server)"
SUPERUSER = "domes"  # the role initdb makes; local connections are trusted
TIMEOUT = 60  # seconds for initdb, start and stop


def find_bindir() -> Path | None:
    """A folder with ``initdb``, ``pg_ctl`` and ``postgres``: Debian's newest, else the PATH's."""
    def version(folder: str) -> tuple[int, ...]:
        return tuple(int(n) for n in re.findall(r"\d+", Path(folder).parent.name))

    folders = sorted(glob.glob("/usr/lib/postgresql/*/bin"), key=version, reverse=True)
    initdb = shutil.which("initdb")
    if initdb:
        folders.append(str(Path(initdb).parent))
    for folder in folders:
        if all(os.access(Path(folder) / tool, os.X_OK) for tool in ("initdb", "pg_ctl", "postgres")):
            return Path(folder)
    return None


def _reachable_by_others(folder: Path) -> bool:
    """Whether another user can reach ``folder`` (every folder on the way is searchable by others)."""
    return all(os.stat(p).st_mode & stat.S_IXOTH for p in [folder, *folder.parents])


class PostgresServer:
    """A PostgreSQL server in its own temporary folder: ``data/``, ``server.log`` and the socket."""

    def __init__(self, bindir: Path, folder: Path, run_as: list[str]):
        self.bindir, self.folder, self.run_as = bindir, folder, run_as
        self.data, self.log = folder / "data", folder / "server.log"
        self._names = itertools.count(1)
        self._template: str | None = None
        self.running = False

    @classmethod
    def start(cls) -> "PostgresServer":
        """Start a server, or raise :class:`RuntimeError` saying what is missing."""
        try:
            import psycopg  # noqa: F401 (the driver of the postgresql+psycopg URLs)
        except ImportError:
            raise RuntimeError("the PostgreSQL driver psycopg is not installed: pip install -e '.[postgres]'") from None
        bindir = find_bindir()
        if bindir is None:
            raise RuntimeError(f"no PostgreSQL server binaries (initdb, pg_ctl, postgres in /usr/lib/postgresql/*/bin): {INSTALL}")
        run_as, owner = [], None
        if os.geteuid() == 0:  # initdb refuses root: run the server as Debian's postgres user
            try:
                owner = pwd.getpwnam("postgres")
            except KeyError:
                raise RuntimeError(f"running as root, and no 'postgres' system user to run the server as: {INSTALL}") from None
            runuser = shutil.which("runuser")
            if runuser is None:
                raise RuntimeError("running as root, and no runuser (util-linux) to run the server as 'postgres'")
            run_as = [runuser, "-u", "postgres", "--"]
        base = Path(tempfile.gettempdir())
        # The socket path must be short (about 100 bytes) and, for the postgres user, reachable.
        if len(str(base)) > 60 or (owner is not None and not _reachable_by_others(base)):
            base = Path("/tmp")
        folder = Path(tempfile.mkdtemp(prefix="domes-pg-", dir=base))
        if owner is not None:
            os.chown(folder, owner.pw_uid, owner.pw_gid)
        server = cls(bindir, folder, run_as)
        try:
            server._init_and_start()
        except BaseException:
            server.stop()
            raise
        return server

    def _run(self, *argv: str) -> None:
        result = subprocess.run([*self.run_as, *argv], capture_output=True, text=True, timeout=TIMEOUT,
                                stdin=subprocess.DEVNULL, cwd=self.folder)
        if result.returncode != 0:
            log = self.log.read_text(errors="replace") if self.log.exists() else ""
            tail = "\n".join((result.stdout + result.stderr + log).strip().splitlines()[-8:])
            raise RuntimeError(f"{Path(argv[0]).name} failed (exit {result.returncode}): {tail}")

    def _init_and_start(self) -> None:
        self._run(str(self.bindir / "initdb"), "-D", str(self.data), "-U", SUPERUSER, "--auth=trust",
                  "--encoding=UTF8", "--no-locale", "--no-sync")
        with open(self.data / "postgresql.conf", "a") as conf:
            # Unix socket in our folder only; durability is not needed for a throw-away server.
            conf.write(f"\nlisten_addresses = ''\nunix_socket_directories = '{self.folder}'\n"
                       "fsync = off\nsynchronous_commit = off\nfull_page_writes = off\n")
        self.running = True  # from here on, stop() stops it, even if the start fails half-way
        self._run(str(self.bindir / "pg_ctl"), "-D", str(self.data), "-l", str(self.log), "-w", "-t", str(TIMEOUT), "start")

    def stop(self) -> None:
        """Stop the server and remove its folder (idempotent)."""
        if self.running:
            self.running = False
            for mode in ("fast", "immediate"):
                try:
                    self._run(str(self.bindir / "pg_ctl"), "-D", str(self.data), "-m", mode, "-w", "stop")
                    break
                except (RuntimeError, OSError, subprocess.TimeoutExpired):
                    continue
        shutil.rmtree(self.folder, ignore_errors=True)

    def url(self, database: str) -> str:
        """The SQLAlchemy URL of a database of this server (psycopg 3, through the socket)."""
        return f"postgresql+psycopg://{SUPERUSER}@/{database}?host={self.folder}"

    def execute(self, sql: str) -> None:
        """Run one statement outside a transaction, on the ``postgres`` database (e.g. CREATE DATABASE)."""
        import psycopg

        with psycopg.connect(host=str(self.folder), dbname="postgres", user=SUPERUSER, autocommit=True) as conn:
            conn.execute(sql)

    def create_database(self, template: str | None = None) -> str:
        """A new database (empty, or a copy of ``template``); returns its URL."""
        name = f"test_{next(self._names)}"
        self.execute(f'CREATE DATABASE "{name}"' + (f' TEMPLATE "{template}"' if template else ""))
        return self.url(name)

    def casebase(self) -> str:
        """A new database holding the case base built from the shipped knowledge; returns its URL.

        The case base is built once (``domes.store.build``) into a template database, then copied.
        """
        if self._template is None:
            from domes.store.casebase import build

            self.execute('CREATE DATABASE "shipped"')
            build(ROOT / "knowledge", self.url("shipped"))  # disposes its engine: the template has no connections
            self._template = "shipped"
        return self.create_database(self._template)


_server: PostgresServer | None = None
_failure: str | None = None


def shared_server() -> PostgresServer:
    """The session's server, started on first use; skips the calling test when it cannot start."""
    global _server, _failure
    if _server is None and _failure is None:
        try:
            _server = PostgresServer.start()
            atexit.register(_server.stop)
        except (RuntimeError, OSError, subprocess.TimeoutExpired) as exc:
            _failure = str(exc)
    if _server is None:
        pytest.skip(f"no PostgreSQL server for the tests: {_failure}")
    return _server


@pytest.fixture(scope="session", name="postgres_server")
def postgres_server_fixture():
    """The throw-away PostgreSQL server of this test session (one for every module that imports this fixture)."""
    yield shared_server()
    if _server is not None:
        _server.stop()


@pytest.fixture(name="postgres_casebase")
def postgres_casebase_fixture(postgres_server) -> str:
    """URL of a fresh PostgreSQL database holding the case base built from the shipped knowledge."""
    return postgres_server.casebase()


def contents(url):
    """Every row of every table of the case base, in primary-key order: what two case bases compare by."""
    from sqlalchemy import create_engine, select

    from domes.store.models import Base

    engine = create_engine(url)
    try:
        with engine.connect() as conn:
            return {t.name: conn.execute(select(t).order_by(*t.primary_key)).all() for t in Base.metadata.sorted_tables}
    finally:
        engine.dispose()
