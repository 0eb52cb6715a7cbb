"""The case base: where it is, its schema check, and the knowledge base of criterion frames in it.

By default the user's case base, or the embedded ``casebase.db`` until the
user first writes (:mod:`domes.io.resources`); the ``--db`` option or the
``DOMES_DB`` environment variable selects any SQLAlchemy URL (or a path to
an SQLite file) instead. The readable sources are the shipped knowledge, or
``DOMES_KNOWLEDGE``. Every edit is one transaction, in one session: an edit
that is refused changes nothing.

>>> import tempfile, os
>>> from domes.knowledge.frames import CriterionFrame
>>> path = os.path.join(tempfile.mkdtemp(), "kb.db")
>>> kb = KnowledgeBase(path, create=True)
>>> kb.add(CriterionFrame.create("c1", "every vertex must have degree at most 4"))
>>> [f.id for f in kb.frames()]
['c1']
>>> kb.add(CriterionFrame.create("c1", "every vertex must have degree at most 3"))
Traceback (most recent call last):
...
domes.errors.InputError: a criterion with id 'c1' is already in the knowledge base (use edit to change it)
>>> kb.close()
"""

from __future__ import annotations

import copy
import dataclasses
import datetime as _dt
import json
import os
import random
import sqlite3
import time
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable, Iterator

from sqlalchemy import create_engine, event, func, inspect, select, text
from sqlalchemy.engine import Engine, make_url
from sqlalchemy.exc import ArgumentError, IntegrityError, SQLAlchemyError
from sqlalchemy.orm import Session

from domes.errors import DomesError, InputError
from domes.io.criteria import check_unique, read_cases, read_knowledge
from domes.io.files import missing_folder, why_not_made
from domes.io.resources import DB_ENV, default_casebase, knowledge_dir, shipped_casebase, user_casebase
from domes.knowledge.frames import CriterionFrame
from domes.knowledge.problems import ProblemFrame
from domes.store.models import (
    ADDED_COMPONENTS,
    SCHEMA_VERSIONS,
    Base,
    CriterionRow,
    HistoryRow,
    ProblemRow,
    SchemaVersion,
)


def database_url(db: str | None = None, write: bool = False) -> str:
    """The case base URL: ``db``, else ``$DOMES_DB``, else the default case base; a path means SQLite.

    The default (:func:`~domes.io.resources.default_casebase`) is the user's
    case base, or the embedded one opened read-only until something is
    written (``write``), which makes the user's case base.

    >>> database_url("sqlite:///x.db")
    'sqlite:///x.db'
    """
    chosen = db or os.environ.get(DB_ENV)
    if not chosen:
        path = default_casebase(write)
        if path == shipped_casebase():
            return f"sqlite:///file:{path}?mode=ro&uri=true"
        return f"sqlite:///{path}"
    if "://" in chosen:
        return chosen
    return f"sqlite:///{Path(chosen).resolve()}"


def sqlite_path(url: str) -> Path | None:
    """The file of an SQLite URL (None for another database or an in-memory one)."""
    try:
        parsed = make_url(url)
    except ArgumentError:
        raise InputError(f"{url!r} is not a database URL (e.g. sqlite:///casebase.db) nor a file path") from None
    if parsed.get_backend_name() != "sqlite" or parsed.database in (None, "", ":memory:"):
        return None
    if parsed.query.get("uri") == "true" and parsed.database.startswith("file:"):
        return Path(parsed.database[len("file:"):])
    return Path(parsed.database)


def shown(url: str) -> str:
    """A case base URL as messages show it: a password in it is hidden.

    >>> shown("postgresql+psycopg://me:secret@db.example/cases")
    'postgresql+psycopg://me:***@db.example/cases'
    >>> shown("sqlite:///x.db")
    'sqlite:///x.db'
    """
    try:
        parsed = make_url(url)
    except ArgumentError:
        return url
    return url if parsed.password is None else parsed.render_as_string(hide_password=True)


#: The execution option of a unit of work that writes: on SQLite it starts with ``BEGIN IMMEDIATE``.
IMMEDIATE = "domes_immediate"


def _engine(url: str) -> Engine:
    try:
        engine = create_engine(url)
    except (ArgumentError, SQLAlchemyError, ImportError) as exc:
        raise InputError(f"cannot open the case base {shown(url)}: {exc}") from None
    if engine.dialect.name == "sqlite":
        # SQLite lets two writers read the same largest number and then collide; a unit of work that writes
        # takes the write lock when it begins (BEGIN IMMEDIATE), so writers queue instead (the driver waits
        # for the lock up to its timeout). pysqlite's own transaction handling is turned off for that.
        @event.listens_for(engine, "connect")
        def _connect(dbapi_connection, record):
            dbapi_connection.isolation_level = None

        @event.listens_for(engine, "begin")
        def _begin(connection):
            write = connection.get_execution_options().get(IMMEDIATE)
            connection.exec_driver_sql("BEGIN IMMEDIATE" if write else "BEGIN")
    return engine


def _now() -> str:
    """The time of a change, UTC, to the second (ISO 8601)."""
    return _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0).isoformat()


def open_engine(url: str, create: bool = False) -> Engine:
    """An engine on a case base of the right schema version.

    With ``create`` an empty (or missing) database gets the schema;
    otherwise it is an error. A database of another version, or one that
    is not a case base, is refused with a message saying what to do.
    """
    path = sqlite_path(url)
    if path is not None and not path.exists() and not create:
        raise InputError(f"no case base at {path}: build it with `domes kb build` (or choose one with --db / {DB_ENV})")
    if path is not None and path.is_dir():
        raise InputError(f"{path} is a folder, not a case base: give the case base's file (e.g. {path / 'casebase.db'})")
    engine = _engine(url)
    try:
        tables = set(inspect(engine).get_table_names())
        if SchemaVersion.__tablename__ not in tables:
            if tables:
                raise InputError(f"{shown(url)} is not a DOMES-py case base (it has tables {sorted(tables)} but no schema_version)")
            if not create:
                raise InputError(f"the case base {shown(url)} is empty: build it with `domes kb build` or fill it with `domes kb import`")
            with engine.begin() as conn:
                Base.metadata.create_all(conn)
                conn.execute(SchemaVersion.__table__.insert(), [{"component": c, "version": v} for c, v in SCHEMA_VERSIONS.items()])
            return engine
        with Session(engine) as session:
            found = {row.component: row.version for row in session.scalars(select(SchemaVersion))}
    except SQLAlchemyError as exc:
        engine.dispose()
        reason = str(getattr(exc, "orig", None) or exc).splitlines()[0]
        if path is not None:
            raise InputError(f"{path} is not a DOMES-py case base, or it is damaged: {reason}") from None
        raise InputError(f"cannot read the case base {shown(url)}: {reason}") from None
    except DomesError:
        engine.dispose()
        raise
    for component, version in SCHEMA_VERSIONS.items():
        if component in ADDED_COMPONENTS and component not in found:
            continue  # added on the first write (KnowledgeBase._ensure_history)
        if found.get(component) != version:
            engine.dispose()
            have = "no" if component not in found else f"version {found[component]} of the"
            raise InputError(
                f"the case base {shown(url)} has {have} '{component}' schema; this DOMES-py reads version {version}: "
                "rebuild it with `domes kb build` (first export your own criteria with the DOMES-py that made it)"
            )
    return engine


def _columns(row) -> dict:
    """A row as plain data: every column's value (JSON columns deep-copied, so later edits leave it alone)."""
    return {c.key: copy.deepcopy(getattr(row, c.key)) for c in row.__table__.columns}


#: The tables whose rows a history entry records, by name.
TABLES = {CriterionRow.__tablename__: CriterionRow, ProblemRow.__tablename__: ProblemRow}
#: How often a unit of work that met another writer's change is run again (SQLite serialises writers; another
#: database may report a conflict at commit).
ATTEMPTS = 8


class _Conflict(Exception):
    """Another writer changed what this unit of work read; run it again."""


class _Changes:
    """The rows one unit of work touches, with their columns before it; after it, the changes it made."""

    def __init__(self, session: Session):
        self.session = session
        self.before: dict[tuple[str, str], dict | None] = {}

    def touch(self, model, key: str) -> None:
        """Note a row about to change (or to be made): its columns now, once per unit of work."""
        slot = (model.__tablename__, key)
        if slot not in self.before:
            row = self.session.get(model, key)
            self.before[slot] = None if row is None else _columns(row)

    def made(self) -> list[dict]:
        """``{"table", "key", "before", "after"}`` for each row that changed, in the order touched."""
        self.session.flush()
        out = []
        for (table, key), before in self.before.items():
            row = self.session.get(TABLES[table], key)
            after = None if row is None else _columns(row)
            if before != after:
                out.append({"table": table, "key": key, "before": before, "after": after})
        return out


@dataclass(frozen=True)
class HistoryEntry:
    """One change of the case base (see :class:`~domes.store.models.HistoryRow`)."""

    number: int
    time: str
    session: str
    action: str
    target: str
    why: str
    changes: tuple[dict, ...]

    def to_dict(self) -> dict:
        return {"number": self.number, "time": self.time, "session": self.session, "action": self.action,
                "target": self.target, "why": self.why, "changes": [dict(c) for c in self.changes]}

    @property
    def summary(self) -> str:
        """What changed, in a few words: ``criterion designer-1a2b3c4d added``."""
        words = []
        for c in self.changes:
            what = "criterion" if c["table"] == "criteria" else "case"
            verb = "added" if c["before"] is None else ("removed" if c["after"] is None else "changed")
            words.append(f"{what} {c['key']} {verb}")
        return "; ".join(words) or "nothing"


class KnowledgeBase:
    """The criterion frames of a case base; every method is one unit of work (one session, one transaction).

    ``url`` is a SQLAlchemy URL or an SQLite path (None: :func:`database_url`);
    ``write`` says the caller will change it (without a ``url``, the user's case
    base is then made if there is none). ``actor`` names who changes it (a
    command, a design session): every change keeps a history entry (what,
    when, who, why) that :meth:`undo` takes back.
    """

    def __init__(self, url: str | None = None, create: bool = False, write: bool = False, actor: str = ""):
        self.url = database_url(url, write=write or create)
        self.engine = open_engine(self.url, create=create)
        self.actor = actor or "python"

    def close(self) -> None:
        self.engine.dispose()

    @contextmanager
    def _unit(self, action: str | None = None, target: str = "", why: str = "") -> Iterator[Session]:
        """One unit of work that changes the case base: one session, one transaction, all or nothing.

        With ``action``, the rows the work touched (``session.info["changes"]``)
        are kept as one history entry in the same transaction.
        """
        self._ensure_history()
        try:
            with Session(self.engine) as session, session.begin():
                session.connection(execution_options={IMMEDIATE: True})
                changes = session.info["changes"] = _Changes(session)
                yield session
                if action:
                    made = changes.made()
                    if made:
                        session.add(HistoryRow(time=_now(), session=self.actor, action=action,
                                               target=session.info.get("target", target), why=why, changes=made))
        except IntegrityError as exc:
            raise _Conflict(str(exc)) from None
        except SQLAlchemyError as exc:
            reason = str(getattr(exc, "orig", None) or exc).splitlines()[0]
            hint = ("the embedded case base is read-only: open it with write=True to change your own copy, "
                    "or give --db / DOMES_DB") if "readonly" in reason else "nothing was changed"
            raise InputError(f"cannot change the case base {shown(self.url)}: {reason}; {hint}") from None

    def _transact(self, work, action: str | None = None, target: str = "", why: str = ""):
        """Run ``work(session)`` as one unit of work (:meth:`_unit`); run it again when another writer got in
        first (a number or id taken meanwhile), up to :data:`ATTEMPTS` times."""
        for attempt in range(ATTEMPTS):
            try:
                with self._unit(action, target, why) as session:
                    return work(session)
            except _Conflict as exc:
                if attempt == ATTEMPTS - 1:
                    reason = str(exc).splitlines()[0]
                    raise InputError(f"cannot change the case base {shown(self.url)}: other writers kept changing "
                                     f"it ({reason}); nothing was changed, try again") from None
                time.sleep(0.01 * (attempt + 1) * (1 + random.random()))

    def _ensure_history(self) -> None:
        """A case base made before the history component gets it (one transaction), before its first change."""
        if self._has_history():
            return
        try:
            with self.engine.begin() as conn:
                Base.metadata.create_all(conn, tables=[HistoryRow.__table__])
                if conn.execute(select(SchemaVersion).where(SchemaVersion.component == "history")).first() is None:
                    conn.execute(SchemaVersion.__table__.insert(), [{"component": "history",
                                                                     "version": SCHEMA_VERSIONS["history"]}])
        except SQLAlchemyError:
            pass  # a read-only case base: the change itself says so

    def _has_history(self) -> bool:
        return HistoryRow.__tablename__ in set(inspect(self.engine).get_table_names())

    def __enter__(self) -> "KnowledgeBase":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- reading -----------------------------------------------------------------------

    @contextmanager
    def _reading(self) -> Iterator[Session]:
        """One session that reads; a stored value that cannot be read (not JSON, nested beyond reason, a
        missing table) says the case base is damaged instead of ending in a traceback."""
        try:
            with Session(self.engine) as session:
                yield session
        except (SQLAlchemyError, ValueError, TypeError, RecursionError) as exc:
            reason = str(getattr(exc, "orig", None) or exc).splitlines()[0] if not isinstance(exc, RecursionError) \
                else "a stored value is nested too deeply to read"
            raise InputError(f"the case base {shown(self.url)} is damaged: {reason}; `domes kb check` names the "
                             "damaged criteria; rebuild it with `domes kb build` (export your own criteria first)") from None

    def frames(self) -> list[CriterionFrame]:
        """Every criterion frame, in knowledge-base order (the order of relevance vectors)."""
        with self._reading() as session:
            rows = session.scalars(select(CriterionRow).order_by(CriterionRow.number)).all()
            return [self._frame(row) for row in rows]

    def get(self, criterion_id: str) -> CriterionFrame:
        with self._reading() as session:
            return self._frame(self._row(session, criterion_id))

    @staticmethod
    def _frame(row: CriterionRow) -> CriterionFrame:
        try:
            return row.frame()
        except (DomesError, TypeError, ValueError, KeyError, RecursionError) as exc:
            reason = "nested too deeply" if isinstance(exc, RecursionError) else str(exc)
            raise InputError(f"stored criterion {row.id!r} is damaged: {reason}; run `domes kb check`") from None

    @staticmethod
    def _row(session: Session, criterion_id: str) -> CriterionRow:
        row = session.get(CriterionRow, criterion_id)
        if row is None:
            raise InputError(f"no criterion with id {criterion_id!r} in the knowledge base (see `domes kb list`)")
        return row

    def damaged(self) -> list[str]:
        """The stored criteria that cannot be read at all, each with the reason (read row by row, raw)."""
        out = []
        with self._reading() as session:
            rows = session.execute(text("SELECT id, tree, relevance, keywords FROM criteria ORDER BY number")).all()
        for criterion_id, *values in rows:
            try:
                decoded = [json.loads(v) if isinstance(v, str) else v for v in values]
                row = CriterionRow(id=criterion_id, tree=decoded[0], relevance=decoded[1], keywords=decoded[2],
                                   text="", category="", explanation="", relevance_text="", level=1, source="",
                                   date="", enabled=True)
                row.frame()
            except (DomesError, TypeError, ValueError, KeyError, RecursionError) as exc:
                reason = "nested too deeply to read" if isinstance(exc, RecursionError) else str(exc).splitlines()[0]
                out.append(f"{criterion_id}: damaged: {reason}")
        return out

    def check(self) -> list[str]:
        """What is wrong with the stored criteria: each one readable, and re-parsed from its text giving the stored trees."""
        problems = self.damaged()
        if problems:
            return problems
        for frame in self.frames():
            try:
                fresh = CriterionFrame.create(
                    frame.id, frame.text, frame.explanation, frame.keywords, frame.relevance_text, frame.level,
                    frame.source, frame.date, frame.enabled,
                )
            except DomesError as exc:
                problems.append(f"{frame.id}: {exc}")
                continue
            if fresh.tree != frame.tree:
                problems.append(f"{frame.id}: the stored tree differs from the parse of its text")
            if fresh.relevance != frame.relevance:
                problems.append(f"{frame.id}: the stored relevance differs from the parse of its relevance text")
        return problems

    # -- editing: each method one transaction, kept in the history --------------------------

    @staticmethod
    def _insert(session: Session, frames: list[CriterionFrame]) -> None:
        changes = session.info.get("changes")
        for frame in frames:
            if session.get(CriterionRow, frame.id) is not None:
                raise InputError(f"a criterion with id {frame.id!r} is already in the knowledge base (use edit to change it)")
        number = session.scalar(select(func.max(CriterionRow.number))) or 0
        for frame in frames:
            number += 1
            if changes is not None:
                changes.touch(CriterionRow, frame.id)
            session.add(CriterionRow(number=number, **CriterionRow.columns_of(frame)))

    def add(self, frame: CriterionFrame, why: str = "") -> None:
        """Add one frame; a duplicate id is refused."""
        self._transact(lambda session: self._insert(session, [frame]), "add criterion", frame.id, why)

    def import_frames(self, frames: Iterable[CriterionFrame], why: str = "") -> None:
        """Add frames, all or none: duplicate ids (among them or with the knowledge base) are refused."""
        frames = list(frames)
        check_unique(frames, "import")
        self._transact(lambda session: self._insert(session, frames), "import criteria",
                       ", ".join(f.id for f in frames), why)

    def update(self, frame: CriterionFrame, why: str = "", action: str = "edit criterion") -> None:
        """Replace the stored frame that has ``frame.id`` (its position is kept)."""
        def work(session):
            row = self._row(session, frame.id)
            session.info["changes"].touch(CriterionRow, frame.id)
            for column, value in CriterionRow.columns_of(frame).items():
                setattr(row, column, value)

        self._transact(work, action, frame.id, why)

    def remove(self, criterion_id: str, why: str = "") -> None:
        def work(session):
            row = self._row(session, criterion_id)
            session.info["changes"].touch(CriterionRow, criterion_id)
            session.delete(row)

        self._transact(work, "remove criterion", criterion_id, why)

    # -- solved-problem frames (Table 7-1) -----------------------------------------------

    def problems(self, problem_class: str | None = None) -> list[ProblemFrame]:
        """Every stored problem frame (of one class, if given), in the order they were solved."""
        with self._reading() as session:
            query = select(ProblemRow).order_by(ProblemRow.number)
            if problem_class is not None:
                query = query.where(ProblemRow.problem_class == problem_class)
            return [self._problem(row) for row in session.scalars(query)]

    def get_problem(self, problem_id: str) -> ProblemFrame:
        with self._reading() as session:
            row = session.get(ProblemRow, problem_id)
            if row is None:
                raise InputError(f"no case {problem_id!r} in the case base (see `domes cases list`)")
            return self._problem(row)

    @staticmethod
    def _problem(row: ProblemRow) -> ProblemFrame:
        try:
            return ProblemFrame.from_dict(row.frame)
        except (DomesError, TypeError, ValueError, KeyError) as exc:
            raise InputError(f"stored case {row.id!r} is damaged: {exc}; rebuild with `domes kb build`") from None

    @staticmethod
    def _stored(frame: ProblemFrame) -> dict:
        """The stored form of a problem frame, refused unless it reads back and fits its columns.

        SQLite ignores the lengths of the columns; PostgreSQL enforces them.
        """
        data = frame.to_dict()
        ProblemFrame.from_dict(data)  # e.g. an id too long (or not an id) could not be read back
        limit = ProblemRow.__table__.c.problem_class.type.length
        if len(frame.problem_class) > limit:
            raise InputError(f"case {frame.id!r}: the problem class has more than {limit} characters")
        return data

    @staticmethod
    def _insert_problems(session: Session, frames: list[ProblemFrame], replace: bool = False) -> None:
        changes = session.info.get("changes")
        number = session.scalar(select(func.max(ProblemRow.number))) or 0
        for frame in frames:
            data = KnowledgeBase._stored(frame)
            row = session.get(ProblemRow, frame.id)
            if row is not None and not replace:
                raise InputError(f"a case with id {frame.id!r} is already in the case base")
            if changes is not None:
                changes.touch(ProblemRow, frame.id)
            if row is None:
                number += 1
                session.add(ProblemRow(id=frame.id, number=number, problem_class=frame.problem_class, frame=data))
            else:
                row.problem_class, row.frame = frame.problem_class, data

    def retain(self, frame: ProblemFrame, replace: bool = False, why: str = "") -> None:
        """Store a solved problem (one transaction); an existing id is refused unless ``replace``."""
        self._transact(lambda session: self._insert_problems(session, [frame], replace), "retain case", frame.id, why)

    def retain_new(self, frame: ProblemFrame, why: str = "") -> ProblemFrame:
        """Store a solved problem under the first free id ``BASE-N`` (``BASE`` its id), chosen inside the
        transaction, so that writers at the same time never take one id twice; returns the frame as stored."""
        def work(session):
            taken = set(session.scalars(select(ProblemRow.id).where(ProblemRow.id.startswith(f"{frame.id}-", autoescape=True))))
            number = 1
            while f"{frame.id}-{number}" in taken:
                number += 1
            stored = dataclasses.replace(frame, id=f"{frame.id}-{number}")
            self._insert_problems(session, [stored])
            session.info["target"] = stored.id
            return stored

        return self._transact(work, "retain case", frame.id, why)

    def remove_problem(self, problem_id: str, why: str = "") -> None:
        def work(session):
            row = session.get(ProblemRow, problem_id)
            if row is None:
                raise InputError(f"no case {problem_id!r} in the case base (see `domes cases list`)")
            session.info["changes"].touch(ProblemRow, problem_id)
            session.delete(row)

        self._transact(work, "remove case", problem_id, why)

    # -- the history ----------------------------------------------------------------------

    def history(self) -> list[HistoryEntry]:
        """Every recorded change, oldest first (none for a case base made before the history was kept)."""
        if not self._has_history():
            return []
        with self._reading() as session:
            rows = session.scalars(select(HistoryRow).order_by(HistoryRow.number)).all()
            return [HistoryEntry(r.number, r.time, r.session, r.action, r.target, r.why, tuple(r.changes))
                    for r in rows]

    def undo(self, number: int | None = None) -> list[HistoryEntry]:
        """Take back the last change (or every change from entry ``number`` on), newest first, in one
        transaction: each row touched gets back its columns from before, and the entries are removed, so the
        case base is as it was. Returns the entries taken back."""
        entries = self.history()
        if not entries:
            raise InputError(f"nothing to undo: the case base {shown(self.url)} has no recorded change")
        numbers = [e.number for e in entries]
        if number is None:
            number = numbers[-1]
        if number not in numbers:
            raise InputError(f"no history entry {number} (entries {numbers[0]} to {numbers[-1]}; see `domes kb history`)")
        undone = [e for e in reversed(entries) if e.number >= number]

        def work(session):
            for entry in undone:
                for change in reversed(entry.changes):
                    model = TABLES[change["table"]]
                    row = session.get(model, change["key"])
                    if row is not None:
                        session.delete(row)
                        session.flush()
                    if change["before"] is not None:
                        session.add(model(**change["before"]))
                        session.flush()
                session.delete(session.get(HistoryRow, entry.number))

        self._transact(work)
        return undone


def copy_casebase(source: str, target: str) -> None:
    """Copy the criteria and solved cases of one case base into another, new one (e.g. PostgreSQL into SQLite)."""
    with KnowledgeBase(source) as kb:
        frames, problems = kb.frames(), kb.problems()
    with KnowledgeBase(target, create=True) as kb:
        with kb._unit() as session:
            KnowledgeBase._insert(session, frames)
            KnowledgeBase._insert_problems(session, problems)


def replaceable(url: str) -> str | None:
    """Why building over ``url`` would destroy something that is not a case base (None: safe).

    A missing file, an empty database and a DOMES-py case base (of any
    schema version) may be built over; anything else is kept unless forced.
    """
    path = sqlite_path(url)
    if path is not None and not path.exists():
        return None
    if path is not None and path.is_dir():
        return f"{path} is a folder"
    engine = _engine(url)
    try:
        tables = set(inspect(engine).get_table_names())
    except SQLAlchemyError as exc:
        return f"{shown(url)} is not a database DOMES-py can read ({str(getattr(exc, 'orig', None) or exc).splitlines()[0]})"
    finally:
        engine.dispose()
    if tables and SchemaVersion.__tablename__ not in tables:
        return f"{shown(url)} is not a DOMES-py case base (it has tables {', '.join(sorted(tables))})"
    return None


def own_content(url: str, frames, cases) -> list[str]:
    """What the case base at ``url`` holds that the sources (``frames``, ``cases``) lack: the user's cases,
    criteria added or changed, recorded changes. Empty for a missing file or one that is not a case base."""
    path = sqlite_path(url)
    if (path is not None and not path.is_file()) or replaceable(url):
        return []
    try:
        with KnowledgeBase(url) as kb:
            stored, problems, changes = kb.frames(), kb.problems(), kb.history()
    except (DomesError, SQLAlchemyError):
        return []
    shipped = {(f.id, f.text, f.relevance_text, f.enabled) for f in frames}
    criteria = [f.id for f in stored if (f.id, f.text, f.relevance_text, f.enabled) not in shipped]
    known = {c.id for c in cases}
    own = [c.id for c in problems if c.id not in known]
    found = []
    if own:
        found.append(f"{len(own)} case(s) of your own ({', '.join(own[:5])}{', ...' if len(own) > 5 else ''})")
    if criteria:
        found.append(f"{len(criteria)} criterion(s) added or changed ({', '.join(criteria[:5])}"
                     f"{', ...' if len(criteria) > 5 else ''})")
    if changes:
        found.append(f"{len(changes)} recorded change(s)")
    return found


def _keep_copy(path: Path) -> Path:
    """A consistent copy of the SQLite case base at ``path`` beside it (``NAME.YYYYmmdd-HHMMSS.bak``)."""
    stamp = _dt.datetime.now().strftime("%Y%m%d-%H%M%S")
    kept = path.with_name(f"{path.name}.{stamp}.bak")
    n = 1
    while kept.exists():
        n += 1
        kept = path.with_name(f"{path.name}.{stamp}-{n}.bak")
    source, target = sqlite3.connect(path), sqlite3.connect(kept)
    try:
        source.backup(target)
    finally:
        source.close()
        target.close()
    return kept


def build(source: str | Path | None = None, url: str | None = None, force: bool = False,
          say=None) -> list[CriterionFrame]:
    """Build the case base from the knowledge sources; returns the frames stored.

    All sources are read and validated first. An SQLite file is built
    beside its target and moved over it (the old one stays until the new
    one is complete); another database has its tables dropped and made
    anew in one transaction. A target that is not a case base (another
    SQLite file, a database with other tables) is refused unless ``force``.
    A case base that holds what the sources lack (:func:`own_content`) is
    first copied beside itself (SQLite; ``say`` is told where), or refused
    unless ``force`` (another database).
    """
    folder = knowledge_dir(source)
    frames = read_knowledge(folder)
    cases = read_cases(folder)
    if url is None and not os.environ.get(DB_ENV):  # the user's case base, made anew
        target = user_casebase()
        try:
            target.parent.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(f"cannot build {target}: {why_not_made(target.parent, exc)}") from None
        url = f"sqlite:///{target}"
    url = database_url(url)
    path = sqlite_path(url)
    why = None if force else replaceable(url)
    if why:
        raise InputError(f"{why}: building the case base there would destroy it; give --force to replace it anyway")
    own = own_content(url, frames, cases)
    if own and path is None and not force:
        raise InputError(f"the case base {shown(url)} holds {'; '.join(own)}, which the sources lack: building would "
                         "drop them; export them first (domes kb export, domes cases export) or give --force")
    if own and path is not None:
        try:
            kept = _keep_copy(path)
        except (OSError, sqlite3.Error) as exc:
            raise InputError(f"cannot keep a copy of {path} before building over it: {exc}") from None
        if say:
            say(f"the old case base held {'; '.join(own)}: a copy is kept at {kept}")
    if path is None:
        engine = _engine(url)
        try:
            with engine.begin() as conn:
                Base.metadata.drop_all(conn)
                Base.metadata.create_all(conn)
                conn.execute(SchemaVersion.__table__.insert(), [{"component": c, "version": v} for c, v in SCHEMA_VERSIONS.items()])
                with Session(bind=conn) as session:
                    KnowledgeBase._insert(session, frames)
                    KnowledgeBase._insert_problems(session, cases)
                    session.flush()
        except SQLAlchemyError as exc:
            raise InputError(f"cannot build the case base {shown(url)}: {exc}") from None
        finally:
            engine.dispose()
        return frames
    if why := missing_folder(path.parent):
        raise InputError(f"cannot build {path}: {why}")
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    if tmp.exists():
        tmp.unlink()
    try:
        kb = KnowledgeBase(f"sqlite:///{tmp}", create=True)
        try:
            check_unique(frames, "build")
            with Session(kb.engine) as session, session.begin():  # built, not changed: no history entry
                KnowledgeBase._insert(session, frames)
                KnowledgeBase._insert_problems(session, cases)
        finally:
            kb.close()
        os.replace(tmp, path)
    except (OSError, SQLAlchemyError) as exc:
        raise InputError(f"cannot build {path}: {exc}") from None
    finally:
        if tmp.exists():
            tmp.unlink()
    return frames
