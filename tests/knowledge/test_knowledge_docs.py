"""The Python examples of docs/knowledge.md run as written (on a freshly built case base)."""

import doctest
from pathlib import Path

from domes.store.casebase import build

ROOT = Path(__file__).resolve().parents[2]  # the checkout


def test_docs_examples(tmp_path, monkeypatch):
    db = tmp_path / "casebase.db"
    build(ROOT / "knowledge", str(db))
    monkeypatch.setenv("DOMES_DB", str(db))
    result = doctest.testfile(str(ROOT / "docs" / "knowledge.md"), module_relative=False, verbose=False)
    assert result.attempted > 5
    assert result.failed == 0
