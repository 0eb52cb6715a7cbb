import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]  # the checkout


@pytest.fixture(autouse=True)
def designs_once(tmp_path_factory):
    """A session's feasibility level computed once per test run for the same inputs (tests/expert/shared_designs.py)."""
    from tests.expert.shared_designs import designs_computed_once

    with designs_computed_once(tmp_path_factory):
        yield


@pytest.fixture
def casebase(tmp_path):
    """A scratch copy of the shipped case base (the six seed cases and the shipped criteria)."""
    target = tmp_path / "casebase.db"
    shutil.copyfile(ROOT / "casebase.db", target)
    return f"sqlite:///{target}"
