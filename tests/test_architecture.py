"""The rules of the house (docs/architecture.md): the import contracts of pyproject.toml hold,
and a planted arrow against the flow of the pipeline breaks them."""

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = Path(sys.executable).with_name("lint-imports")
pytestmark = pytest.mark.skipif(not LINT.exists(), reason="import-linter is not installed (pip install -e '.[test]')")


def lint(folder: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(folder)}
    return subprocess.run([str(LINT), "--no-cache", "--no-logo"], cwd=folder, env=env, capture_output=True, text=True)


def test_the_package_keeps_its_import_contracts():
    result = lint(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 kept, 0 broken" in result.stdout


@pytest.mark.parametrize("planted, arrow", [
    ("domes/model/chain.py", "domes.model.chain -> domes.expert"),        # the data model reaching up to the expert
    ("domes/typesynth/atlas.py", "domes.typesynth.atlas -> domes.expert"),  # a stage reaching up
])
def test_a_planted_violation_breaks_the_contract(tmp_path, planted, arrow):
    shutil.copytree(ROOT / "domes", tmp_path / "domes", symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    target = tmp_path / planted
    target.write_text(target.read_text() + "\nimport domes.expert.world  # planted: against the flow\n")
    result = lint(tmp_path)
    assert result.returncode == 1, result.stdout + result.stderr
    assert "BROKEN" in result.stdout and arrow in result.stdout, result.stdout


def test_sibling_stages_are_independent(tmp_path):
    # regeneration (typesynth) and screening (knowledge) share the criterion language, not each other
    shutil.copytree(ROOT / "domes", tmp_path / "domes", symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    target = tmp_path / "domes" / "typesynth" / "regenerate.py"
    target.write_text(target.read_text() + "\nimport domes.knowledge.screening  # planted: sibling stages\n")
    result = lint(tmp_path)
    assert result.returncode == 1 and "domes.typesynth.regenerate -> domes.knowledge.screening" in result.stdout, result.stdout
