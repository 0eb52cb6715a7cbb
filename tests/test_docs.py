"""The Python examples in the README and the docs run as written."""

import doctest
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ["README.md", "docs/chains.md", "docs/regeneration.md", "docs/dynamics.md", "docs/cams.md", "docs/catalogue.md", "docs/studio.md"]


@pytest.mark.parametrize("name", DOCS)
def test_examples_in_docs(name):
    result = doctest.testfile(str(ROOT / name), module_relative=False, optionflags=doctest.ELLIPSIS)
    assert result.failed == 0
