"""The case base on PostgreSQL, end to end through the CLI: design sessions, `domes cases`, replay.

The knowledge-base operations (build, list, edits, import/export, solved
problems) run on SQLite and on PostgreSQL in test_store.py; these tests run
the design expert on a PostgreSQL case base and compare it with the same
session on SQLite. The server is a throw-away local one (:mod:`tests.postgres`);
without Debian's postgresql package the tests are skipped with a note.
"""

import json
from pathlib import Path

import pytest

from domes.cli import main
from domes.io.criteria import read_cases
from domes.store.casebase import KnowledgeBase, build
from tests.expert.shared_designs import designs_once_fixture  # noqa: F401 (a fixture)
from tests.postgres import contents, postgres_casebase_fixture, postgres_server_fixture  # noqa: F401 (fixtures)

ROOT = Path(__file__).resolve().parents[2]  # the checkout
SHIPPED = ROOT / "knowledge"
QUICKSTART = ROOT / "examples" / "design" / "quickstart.answers"
NEW_CASE = "motorcycle-rear-suspension-2"  # what the quick start's session retains


def run(capsys, *argv):
    status = main(list(argv))
    out, err = capsys.readouterr()
    return status, out, err



@pytest.mark.usefixtures("designs_once")
def test_a_design_session_retains_the_same_case_in_postgresql_as_in_sqlite(postgres_casebase, tmp_path, capsys):
    # the three sessions' feasibility level (the same inputs: the case base does not change it) is computed once
    # per test run (tests/expert/shared_designs.py); this test is about what the case base keeps
    pg = postgres_casebase
    before = contents(pg)
    status, out, _ = run(capsys, "design", "--answers", str(QUICKSTART), "--dry-run", "--db", pg)
    assert status == 0 and f"Retained as case {NEW_CASE}." in out
    assert contents(pg) == before  # a dry run keeps nothing
    lite = f"sqlite:///{tmp_path / 'casebase.db'}"
    build(SHIPPED, lite)
    for url in (lite, pg):
        status, out, _ = run(capsys, "design", "--answers", str(QUICKSTART), "--db", url)
        assert status == 0 and f"Retained as case {NEW_CASE}." in out
    with KnowledgeBase(lite) as sqlite_kb, KnowledgeBase(pg) as pg_kb:
        new = pg_kb.get_problem(NEW_CASE)
        assert [p.id for p in pg_kb.problems()] == [p.id for p in read_cases(SHIPPED)] + [NEW_CASE]
        # the designer's criterion ("the swing arm must be ternary") is stored with the case
        assert len(new.criteria_added) == 1 and pg_kb.get(new.criteria_added[0]).text == "the swing arm must be ternary"
        assert new.results and new.rejected
        # the same session on SQLite keeps the same frames, criteria and case
        assert pg_kb.problems() == sqlite_kb.problems()
        assert pg_kb.frames() == sqlite_kb.frames()
    assert contents(pg) != before


def test_cases_commands_on_postgresql(postgres_casebase, tmp_path, capsys, monkeypatch):
    pg, case = postgres_casebase, "motorcycle-rear-suspension-1"
    with KnowledgeBase(pg) as kb:
        stored = kb.get_problem(case)
    before = contents(pg)
    # The same problem again is answered from the PostgreSQL case base: nothing designed, nothing retained.
    same = tmp_path / "same.answers"
    same.write_text(f"class: motorcycle rear suspension\nrelation: same {case}\n")
    status, out, _ = run(capsys, "design", "--answers", str(same), "--db", pg)
    assert status == 0 and "from the case base" in out and "Designing" not in out
    # DOMES_DB selects a PostgreSQL case base as --db does.
    monkeypatch.setenv("DOMES_DB", pg)
    status, out, _ = run(capsys, "cases", "list")
    assert status == 0 and all(f" {p.id} " in out for p in read_cases(SHIPPED))
    status, out, _ = run(capsys, "cases", "show", case, "--format", "json")
    assert status == 0 and json.loads(out) == stored.to_dict()
    monkeypatch.delenv("DOMES_DB")
    # Recorded sessions replay with a PostgreSQL --db (on a scratch copy): same results.
    status, out, _ = run(capsys, "cases", "--db", pg, "replay", "motorcycle", "tyre-drum")
    assert status == 0 and out.splitlines() == [
        "motorcycle: same result (different, 6 candidates)", "tyre-drum: same result (different, 20 candidates)"]
    assert contents(pg) == before
    assert run(capsys, "cases", "--db", pg, "remove", case)[0] == 0
    with KnowledgeBase(pg) as kb:
        assert [p.id for p in kb.problems()] == [p.id for p in read_cases(SHIPPED) if p.id != case]


def test_a_database_that_does_not_exist_is_refused_with_the_reason(postgres_server, capsys):
    status, out, err = run(capsys, "kb", "list", "--db", postgres_server.url("nosuch"))
    assert status == 2 and out == ""
    assert "cannot read the case base" in err and 'database "nosuch" does not exist' in err
