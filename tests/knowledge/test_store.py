"""The case base and `domes kb`: build, list, edits as transactions, export/import, schema versions.

The tests that take a ``db`` or an ``empty`` database run twice: on an SQLite
file and on PostgreSQL (a throw-away local server, :mod:`tests.postgres`;
skipped with a note where it cannot start).
"""

import dataclasses
import itertools
import json
from pathlib import Path

import pytest
from sqlalchemy import create_engine, inspect, update
from sqlalchemy import text as sql

from domes.cli import main
from domes.errors import DomesError
from domes.io.criteria import read_cases, read_file, read_knowledge
from domes.knowledge.frames import CriterionFrame
from domes.language.tree import to_json
from domes.store.casebase import KnowledgeBase, build, sqlite_path
from domes.store.models import SCHEMA_VERSIONS, CriterionRow, SchemaVersion
from tests.postgres import contents, postgres_casebase_fixture, postgres_server_fixture  # noqa: F401 (fixtures)

ROOT = Path(__file__).resolve().parents[2]  # the checkout

SHIPPED = ROOT / "knowledge"


def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


@pytest.fixture(params=["sqlite", "postgresql"])
def backend(request):
    """Where the case base is: an SQLite file, or a PostgreSQL database."""
    return request.param


@pytest.fixture
def db(backend, tmp_path, request):
    """URL of a case base built from the shipped knowledge (on PostgreSQL, a copy of one built once)."""
    if backend == "postgresql":
        return request.getfixturevalue("postgres_casebase")
    path = tmp_path / "casebase.db"
    build(SHIPPED, str(path))
    return f"sqlite:///{path}"


@pytest.fixture(scope="module", params=["sqlite", "postgresql"])
def shared_db(request, tmp_path_factory):
    """Like ``db``, one per module: for the tests of refused changes, which must each leave it as it was."""
    if request.param == "postgresql":
        return request.getfixturevalue("postgres_server").casebase()
    path = tmp_path_factory.mktemp("shared") / "casebase.db"
    build(SHIPPED, str(path))
    return f"sqlite:///{path}"


@pytest.fixture
def empty(backend, tmp_path, request):
    """A function that gives the URL of a new empty database (an SQLite file that does not exist yet)."""
    if backend == "postgresql":
        return request.getfixturevalue("postgres_server").create_database
    names = itertools.count(1)
    return lambda: f"sqlite:///{tmp_path / f'empty-{next(names)}.db'}"


def execute(url, statement):
    """Run one statement in its own transaction, beside DOMES-py (e.g. to damage a case base)."""
    engine = create_engine(url)
    try:
        with engine.begin() as conn:
            conn.execute(statement)
    finally:
        engine.dispose()



def state(url):
    """What a refused change must leave as it was: the rows of every table and, for SQLite, the file's bytes."""
    path = sqlite_path(url)
    return contents(url), (path.read_bytes() if path is not None else None)


def tables(url):
    engine = create_engine(url)
    try:
        return inspect(engine).get_table_names()
    finally:
        engine.dispose()


def test_build_then_list_shows_the_shipped_criteria(db, capsys):
    status, out, _ = run(capsys, "kb", "list", "--db", db)
    assert status == 0
    shipped = read_knowledge(SHIPPED)
    for frame in shipped:
        assert f" {frame.id} " in out
    assert f"# {len(shipped)} criteria" in out
    # The six book examples, one per category (i)-(vi), are shipped.
    assert [f.category for f in shipped if f.id.startswith("book-")] == ["i", "ii", "iii", "iv", "v", "vi"]


def test_build_from_the_cli_with_environment_variables(empty, capsys, monkeypatch):
    target = empty()
    monkeypatch.setenv("DOMES_DB", target)
    monkeypatch.setenv("DOMES_KNOWLEDGE", str(SHIPPED))
    status, out, _ = run(capsys, "kb", "build")
    assert status == 0
    assert sqlite_path(target) is None or sqlite_path(target).exists()
    with KnowledgeBase() as kb:
        assert [f.id for f in kb.frames()] == [f.id for f in read_knowledge(SHIPPED)]
        kb.add(CriterionFrame.create("extra", "every vertex must have degree at most 3"))
        kb.remove_problem(read_cases(SHIPPED)[0].id)
    # Building again makes the case base anew from the sources, but not by losing the user's own work (issue 25,
    # item 11): an SQLite case base is first copied beside itself, another database is kept unless forced.
    status, out, err = run(capsys, "kb", "build")
    if sqlite_path(target) is None:
        assert status == 2 and "holds 1 criterion(s) added or changed (extra)" in err and "--force" in err
        with KnowledgeBase() as kb:
            assert "extra" in [f.id for f in kb.frames()]
        status, out, err = run(capsys, "kb", "build", "--force")
    else:
        (kept,) = sqlite_path(target).parent.glob(sqlite_path(target).name + ".*.bak")
        assert f"a copy is kept at {kept}" in out and "1 criterion(s) added or changed (extra)" in out
        with KnowledgeBase(f"sqlite:///{kept}") as kb:
            assert "extra" in [f.id for f in kb.frames()]
            assert len(kb.history()) == 2
    assert status == 0
    with KnowledgeBase() as kb:
        assert kb.frames() == read_knowledge(SHIPPED)
        assert kb.problems() == read_cases(SHIPPED)


def test_export_then_import_into_an_empty_database_gives_the_same_knowledge_base(db, empty, tmp_path, capsys):
    run(capsys, "kb", "disable", "--db", db, "--id", "book-iii")
    for suffix in (".toml", ".json"):
        exported = tmp_path / f"kb{suffix}"
        target = empty()
        assert run(capsys, "kb", "export", "--db", db, "-o", str(exported))[0] == 0
        assert run(capsys, "kb", "import", "--db", target, str(exported))[0] == 0
        with KnowledgeBase(target) as new, KnowledgeBase(db) as old:
            assert new.frames() == old.frames()
            assert [f.enabled for f in new.frames() if f.id == "book-iii"] == [False]


def test_parse_prints_json_and_refuses_bad_text(capsys):
    status, out, _ = run(capsys, "kb", "parse", "THE VERTEX REPRESENTING “PISTON” MUST HAVE ITS “TYPE” PROPERTY-VALUE AS (P R)")
    assert status == 0
    data = json.loads(out)
    assert data["category"] == "v"
    assert data["criterion"]["domain"] == {"node": "Domain", "kind": "vertex", "name": "piston"}
    for bad in ["", "nonsense words", "every vertex must have type (P R", "the value of property “weight” should be 2 for any vertex",
                "os.system('rm -rf /')", "lambda: __import__('os')"]:
        status, out, err = run(capsys, "kb", "parse", bad)
        assert status == 2 and out == ""
        assert err.startswith("domes kb: error: column ")


REFUSED_EDITS = [
    ("add", "--id", "book-i", "--text", "every vertex must have degree 2"),  # duplicate id
    ("add", "--id", "new", "--text", "every vertex must have type (P R"),  # unterminated list
    ("add", "--id", "new", "--text", "print(open('/etc/passwd').read())"),  # looks like code
    ("add", "--id", "new", "--text", ""),  # empty
    ("add", "--id", "new", "--text", "the value of property “colour” should be 2 for any vertex"),  # unknown property
    ("add", "--id", "bad id!", "--text", "every vertex must have degree 2"),
    ("add", "--id", "new", "--text", "every vertex must have degree 2", "--relevance", "sometimes"),
    ("add", "--id", "new", "--text", "every independent loop must have length 4", "--level", "1"),  # below its cost
    ("edit", "--id", "book-i", "--text", "nonsense"),
    ("edit", "--id", "missing", "--text", "every vertex must have degree 2"),
    ("edit", "--id", "book-i"),
    ("enable", "--id", "missing"),
    ("disable", "--id", "missing"),
    ("remove", "--id", "missing"),
]


@pytest.mark.parametrize("argv", REFUSED_EDITS)
def test_a_refused_edit_leaves_the_database_unchanged(shared_db, capsys, argv):
    # unchanged: the same rows in every table and, for SQLite, the same bytes
    before = state(shared_db)
    status, out, err = run(capsys, "kb", *argv, "--db", shared_db)
    assert status == 2
    assert err.startswith("domes kb: error: ")
    assert state(shared_db) == before


def test_a_refused_import_writes_nothing(shared_db, tmp_path, capsys):
    good = '[[criterion]]\nid = "fresh-1"\ntext = "every vertex must have degree at most 4"\n'
    cases = {
        "bad-text.toml": good + '\n[[criterion]]\nid = "fresh-2"\ntext = "every vertex must"\n',
        "duplicate.toml": good + '\n[[criterion]]\nid = "book-ii"\ntext = "every vertex must have degree 2"\n',
        "twice.toml": good + "\n" + good,
        "not-toml.toml": good + "\n[[criterion]\n",
        "unknown-field.toml": good + 'colour = "red"\n',
    }
    before = state(shared_db)
    for name, text in cases.items():
        path = tmp_path / name
        path.write_text(text)
        status, _, err = run(capsys, "kb", "import", "--db", shared_db, str(path))
        assert status == 2, name
        assert str(path) in err
        assert state(shared_db) == before, name


def test_a_refused_import_creates_no_database(empty, tmp_path, capsys):
    path = tmp_path / "twice.toml"
    path.write_text('[[criterion]]\nid = "a"\ntext = "every vertex must have degree 2"\n' * 2)
    target = empty()
    status, _, err = run(capsys, "kb", "import", "--db", target, str(path))
    assert status == 2 and "given twice" in err
    if sqlite_path(target) is not None:
        assert not sqlite_path(target).exists()
    else:
        assert tables(target) == []


def test_error_messages_name_the_file_line_and_field(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('[[criterion]]\nid = "a"\ntext = "every vertex must have degree 2"\n\n'
                    '[[criterion]]\nid = "b"\ntext = "every vertex must have type (P"\n')
    with pytest.raises(DomesError) as info:
        read_file(path)
    # "every vertex must have type (P" has 30 characters: the list is still open at column 31.
    assert f"{path}, line 6: criterion 2 (id 'b'): text: column 31: expected a joint type letter" in str(info.value)


def test_edits_are_applied(db, capsys):
    before = contents(db)
    assert run(capsys, "kb", "add", "--db", db, "--id", "new-1", "--text", "every vertex must have degree at most 3",
               "--keywords", "degree, Link", "--explanation", "no pentagonal links")[0] == 0
    assert contents(db) != before
    kb = KnowledgeBase(db)
    frame = kb.get("new-1")
    assert frame.keywords == ("degree", "link") and frame.category == "i" and frame.enabled
    assert kb.frames()[-1].id == "new-1"  # a new criterion extends the order (and relevance vectors)
    run(capsys, "kb", "edit", "--db", db, "--id", "new-1", "--text", "every loop must have length at most 6")
    frame = kb.get("new-1")
    assert frame.category == "iii" and frame.level == 3  # derived level follows the new text
    run(capsys, "kb", "disable", "--db", db, "--id", "new-1")
    assert not kb.get("new-1").enabled
    run(capsys, "kb", "enable", "--db", db, "--id", "new-1")
    assert kb.get("new-1").enabled
    status, out, _ = run(capsys, "kb", "show", "--db", db, "--id", "new-1")
    assert "reading:     every loop must have length at most 6" in out
    run(capsys, "kb", "remove", "--db", db, "--id", "new-1")
    with pytest.raises(DomesError, match="no criterion with id 'new-1'"):
        kb.get("new-1")
    assert run(capsys, "kb", "check", "--db", db)[0] == 0
    kb.close()
    now = contents(db)
    history = now.pop("history")
    assert now == {k: v for k, v in before.items() if k != "history"}  # added, then removed: as it was
    assert [h.action for h in history[len(before["history"]):]] == [
        "add criterion", "edit criterion", "disable criterion", "enable criterion", "remove criterion"]
    # every edit kept its history entry; undoing them all gives back the case base, history included
    first = history[len(before["history"])].number
    assert run(capsys, "kb", "undo", str(first), "--db", db)[0] == 0
    assert contents(db) == before


def test_check_finds_a_tree_that_does_not_match_its_text(db, capsys):
    frame = CriterionFrame.create("x", "every vertex must have degree 2")
    execute(db, update(CriterionRow).where(CriterionRow.id == "book-i").values(tree=to_json(frame.tree)))
    status, _, err = run(capsys, "kb", "check", "--db", db)
    assert status == 2 and "book-i: the stored tree differs" in err


def test_another_schema_version_is_refused_with_a_message(db, capsys):
    execute(db, update(SchemaVersion).where(SchemaVersion.component == "knowledge").values(version=SCHEMA_VERSIONS["knowledge"] + 1))
    status, _, err = run(capsys, "kb", "list", "--db", db)
    assert status == 2
    assert "has version 2 of the 'knowledge' schema; this DOMES-py reads version 1" in err
    assert "domes kb build" in err


def test_missing_databases_are_refused(tmp_path, capsys):
    missing = tmp_path / "none.db"
    status, _, err = run(capsys, "kb", "list", "--db", str(missing))
    assert status == 2 and "no case base at" in err and not missing.exists()
    status, _, err = run(capsys, "kb", "list", "--db", "nosuchdialect://x")
    assert status == 2 and "cannot open the case base" in err


def test_messages_hide_the_password_of_a_database_url(capsys):
    # No server listens on this socket: the connection fails, and the message shows the URL without its password.
    status, _, err = run(capsys, "kb", "list", "--db", "postgresql+psycopg://me:s3cret@/cases?host=/nonexistent")
    assert status == 2 and "postgresql+psycopg://me:***@/cases" in err
    assert "s3cret" not in err


def test_empty_and_foreign_databases_are_refused(empty, capsys):
    blank = empty()
    execute(blank, sql("SELECT 1"))  # an SQLite file is made, empty
    status, _, err = run(capsys, "kb", "list", "--db", blank)
    assert status == 2 and "is empty: build it with `domes kb build`" in err
    foreign = empty()
    execute(foreign, sql("CREATE TABLE t (x integer)"))
    status, _, err = run(capsys, "kb", "list", "--db", foreign)
    assert status == 2 and "is not a DOMES-py case base (it has tables ['t'] but no schema_version)" in err
    assert tables(blank) == [] and tables(foreign) == ["t"]  # refused, nothing made


def test_solved_problems_are_retained_and_removed(db, capsys):
    cases = read_cases(SHIPPED)
    with KnowledgeBase(db) as kb:
        assert kb.problems() == cases
        assert kb.problems(cases[0].problem_class) == [p for p in cases if p.problem_class == cases[0].problem_class]
        new = dataclasses.replace(cases[0], id="retained-1", notes=("kept by a test",))
        kb.retain(new)
        assert kb.problems()[-1] == new and kb.get_problem("retained-1") == new  # solved last, listed last
        before = state(db)
        with pytest.raises(DomesError, match="a case with id 'retained-1' is already in the case base"):
            kb.retain(dataclasses.replace(new, notes=()))
        # What would not read back, or not fit its column, is refused on every database alike.
        with pytest.raises(DomesError, match="problem frame.id: expected an id"):
            kb.retain(dataclasses.replace(new, id="x" * 65))
        with pytest.raises(DomesError, match="the problem class has more than 128 characters"):
            kb.retain(dataclasses.replace(new, id="long-class", problem_class="k" * 129))
        assert state(db) == before
        kb.retain(dataclasses.replace(new, notes=("replaced",)), replace=True)
        assert kb.get_problem("retained-1").notes == ("replaced",)
        assert [p.id for p in kb.problems()] == [p.id for p in cases] + ["retained-1"]  # its place is kept
    status, out, _ = run(capsys, "cases", "--db", db, "list")
    assert status == 0 and all(f" {p.id} " in out for p in [*cases, new])
    status, out, _ = run(capsys, "cases", "--db", db, "show", "retained-1", "--format", "json")
    assert status == 0 and json.loads(out)["notes"] == ["replaced"]
    assert run(capsys, "cases", "--db", db, "remove", "retained-1")[0] == 0
    before = state(db)
    status, _, err = run(capsys, "cases", "--db", db, "remove", "retained-1")
    assert status == 2 and "no case 'retained-1' in the case base" in err
    assert state(db) == before
    with KnowledgeBase(db) as kb:
        assert kb.problems() == cases


def test_the_shipped_casebase_matches_the_sources():
    # casebase.db at the top of the checkout is built from knowledge/ by `domes kb build`.
    with KnowledgeBase(str(ROOT / "casebase.db")) as kb:
        assert kb.frames() == read_knowledge(SHIPPED)
        assert kb.problems() == read_cases(SHIPPED)


def test_building_over_a_case_base_of_the_sources_alone_keeps_no_copy(tmp_path, capsys):
    # issue 25, item 11: a copy is kept only when there is something of the user's to keep.
    path = tmp_path / "casebase.db"
    for _ in range(2):
        status, out, _ = run(capsys, "kb", "build", "--db", str(path), "--from", str(SHIPPED))
        assert status == 0 and "copy" not in out
    assert list(tmp_path.glob("*.bak")) == []
