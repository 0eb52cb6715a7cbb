import shutil

import pytest

from domes.io.resources import repo_root


@pytest.fixture
def casebase(tmp_path):
    """A scratch copy of the shipped case base (the six seed cases and the shipped criteria)."""
    target = tmp_path / "casebase.db"
    shutil.copyfile(repo_root() / "casebase.db", target)
    return f"sqlite:///{target}"
