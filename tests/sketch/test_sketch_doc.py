"""The Python examples in docs/sketch.md run as written."""

import doctest
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_examples_in_the_sketch_doc(monkeypatch):
    monkeypatch.chdir(ROOT)  # the examples read examples/mechanisms/*.json
    result = doctest.testfile(str(ROOT / "docs" / "sketch.md"), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.attempted > 0 and result.failed == 0
