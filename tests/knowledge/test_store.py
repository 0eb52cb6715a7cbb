"""The case base and `domes kb`: build, list, edits as transactions, export/import, schema versions."""

import json
import sqlite3
from pathlib import Path

import pytest

from domes.cli import main
from domes.errors import DomesError
from domes.io.criteria import read_cases, read_file, read_knowledge
from domes.knowledge.frames import CriterionFrame
from domes.language.tree import to_json
from domes.store.casebase import KnowledgeBase, build
from domes.store.models import SCHEMA_VERSIONS

ROOT = Path(__file__).resolve().parents[2]  # the checkout

SHIPPED = ROOT / "knowledge"


def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err


@pytest.fixture
def db(tmp_path):
    path = tmp_path / "casebase.db"
    build(SHIPPED, str(path))
    return path


def test_build_then_list_shows_the_shipped_criteria(db, capsys):
    status, out, _ = run(capsys, "kb", "list", "--db", str(db))
    assert status == 0
    shipped = read_knowledge(SHIPPED)
    for frame in shipped:
        assert f" {frame.id} " in out
    assert f"# {len(shipped)} criteria" in out
    # The six book examples, one per category (i)-(vi), are shipped.
    assert [f.category for f in shipped if f.id.startswith("book-")] == ["i", "ii", "iii", "iv", "v", "vi"]


def test_build_from_the_cli_with_environment_variables(tmp_path, capsys, monkeypatch):
    target = tmp_path / "env.db"
    monkeypatch.setenv("DOMES_DB", str(target))
    monkeypatch.setenv("DOMES_KNOWLEDGE", str(SHIPPED))
    status, out, _ = run(capsys, "kb", "build")
    assert status == 0 and target.exists()
    assert [f.id for f in KnowledgeBase().frames()] == [f.id for f in read_knowledge(SHIPPED)]


def test_export_then_import_into_an_empty_database_gives_the_same_knowledge_base(db, tmp_path, capsys):
    run(capsys, "kb", "disable", "--db", str(db), "--id", "book-iii")
    for suffix in (".toml", ".json"):
        exported = tmp_path / f"kb{suffix}"
        empty = tmp_path / f"empty{suffix}.db"
        assert run(capsys, "kb", "export", "--db", str(db), "-o", str(exported))[0] == 0
        assert run(capsys, "kb", "import", "--db", str(empty), str(exported))[0] == 0
        assert KnowledgeBase(str(empty)).frames() == KnowledgeBase(str(db)).frames()


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
def test_a_refused_edit_leaves_the_database_byte_identical(db, capsys, argv):
    before = db.read_bytes()
    status, out, err = run(capsys, "kb", *argv, "--db", str(db))
    assert status == 2
    assert err.startswith("domes kb: error: ")
    assert db.read_bytes() == before


def test_a_refused_import_writes_nothing(db, tmp_path, capsys):
    good = '[[criterion]]\nid = "fresh-1"\ntext = "every vertex must have degree at most 4"\n'
    cases = {
        "bad-text.toml": good + '\n[[criterion]]\nid = "fresh-2"\ntext = "every vertex must"\n',
        "duplicate.toml": good + '\n[[criterion]]\nid = "book-ii"\ntext = "every vertex must have degree 2"\n',
        "twice.toml": good + "\n" + good,
        "not-toml.toml": good + "\n[[criterion]\n",
        "unknown-field.toml": good + 'colour = "red"\n',
    }
    before = db.read_bytes()
    for name, text in cases.items():
        path = tmp_path / name
        path.write_text(text)
        status, _, err = run(capsys, "kb", "import", "--db", str(db), str(path))
        assert status == 2, name
        assert str(path) in err
        assert db.read_bytes() == before, name


def test_a_refused_import_creates_no_database(tmp_path, capsys):
    path = tmp_path / "twice.toml"
    path.write_text('[[criterion]]\nid = "a"\ntext = "every vertex must have degree 2"\n' * 2)
    target = tmp_path / "new.db"
    status, _, err = run(capsys, "kb", "import", "--db", str(target), str(path))
    assert status == 2 and "given twice" in err
    assert not target.exists()


def test_error_messages_name_the_file_line_and_field(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('[[criterion]]\nid = "a"\ntext = "every vertex must have degree 2"\n\n'
                    '[[criterion]]\nid = "b"\ntext = "every vertex must have type (P"\n')
    with pytest.raises(DomesError) as info:
        read_file(path)
    # "every vertex must have type (P" has 30 characters: the list is still open at column 31.
    assert f"{path}, line 6: criterion 2 (id 'b'): text: column 31: expected a joint type letter" in str(info.value)


def test_edits_are_applied(db, capsys):
    assert run(capsys, "kb", "add", "--db", str(db), "--id", "new-1", "--text", "every vertex must have degree at most 3",
               "--keywords", "degree, Link", "--explanation", "no pentagonal links")[0] == 0
    kb = KnowledgeBase(str(db))
    frame = kb.get("new-1")
    assert frame.keywords == ("degree", "link") and frame.category == "i" and frame.enabled
    assert kb.frames()[-1].id == "new-1"  # a new criterion extends the order (and relevance vectors)
    run(capsys, "kb", "edit", "--db", str(db), "--id", "new-1", "--text", "every loop must have length at most 6")
    frame = kb.get("new-1")
    assert frame.category == "iii" and frame.level == 3  # derived level follows the new text
    run(capsys, "kb", "disable", "--db", str(db), "--id", "new-1")
    assert not kb.get("new-1").enabled
    run(capsys, "kb", "enable", "--db", str(db), "--id", "new-1")
    assert kb.get("new-1").enabled
    status, out, _ = run(capsys, "kb", "show", "--db", str(db), "--id", "new-1")
    assert "reading:     every loop must have length at most 6" in out
    run(capsys, "kb", "remove", "--db", str(db), "--id", "new-1")
    with pytest.raises(DomesError, match="no criterion with id 'new-1'"):
        kb.get("new-1")
    assert run(capsys, "kb", "check", "--db", str(db))[0] == 0
    kb.close()


def test_check_finds_a_tree_that_does_not_match_its_text(db, capsys):
    frame = CriterionFrame.create("x", "every vertex must have degree 2")
    with sqlite3.connect(db) as conn:
        conn.execute("UPDATE criteria SET tree = ? WHERE id = 'book-i'", (json.dumps(to_json(frame.tree)),))
    status, _, err = run(capsys, "kb", "check", "--db", str(db))
    assert status == 2 and "book-i: the stored tree differs" in err


def test_another_schema_version_is_refused_with_a_message(db, capsys):
    with sqlite3.connect(db) as conn:
        conn.execute("UPDATE schema_version SET version = ? WHERE component = 'knowledge'", (SCHEMA_VERSIONS["knowledge"] + 1,))
    status, _, err = run(capsys, "kb", "list", "--db", str(db))
    assert status == 2
    assert "has version 2 of the 'knowledge' schema; this DOMES-py reads version 1" in err
    assert "domes kb build" in err


def test_missing_empty_and_foreign_databases_are_refused(tmp_path, capsys):
    missing = tmp_path / "none.db"
    status, _, err = run(capsys, "kb", "list", "--db", str(missing))
    assert status == 2 and "no case base at" in err and not missing.exists()
    foreign = tmp_path / "foreign.db"
    with sqlite3.connect(foreign) as conn:
        conn.execute("CREATE TABLE t (x)")
    status, _, err = run(capsys, "kb", "list", "--db", str(foreign))
    assert status == 2 and "is not a DOMES-py case base" in err
    status, _, err = run(capsys, "kb", "list", "--db", "nosuchdialect://x")
    assert status == 2 and "cannot open the case base" in err


def test_the_shipped_casebase_matches_the_sources():
    # casebase.db at the top of the checkout is built from knowledge/ by `domes kb build`.
    with KnowledgeBase(str(ROOT / "casebase.db")) as kb:
        assert kb.frames() == read_knowledge(SHIPPED)
        assert kb.problems() == read_cases(SHIPPED)
