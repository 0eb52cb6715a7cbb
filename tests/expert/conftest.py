import shutil
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]  # the checkout



@pytest.fixture
def casebase(tmp_path):
    """A scratch copy of the shipped case base (the six seed cases and the shipped criteria)."""
    target = tmp_path / "casebase.db"
    shutil.copyfile(ROOT / "casebase.db", target)
    return f"sqlite:///{target}"
