"""The Python examples of docs/knowledge.md run as written (on a freshly built case base)."""

import doctest

from domes.io.resources import repo_root
from domes.store.casebase import build


def test_docs_examples(tmp_path, monkeypatch):
    db = tmp_path / "casebase.db"
    build(repo_root() / "knowledge", str(db))
    monkeypatch.setenv("DOMES_DB", str(db))
    result = doctest.testfile(str(repo_root() / "docs" / "knowledge.md"), module_relative=False, verbose=False)
    assert result.attempted > 5
    assert result.failed == 0
