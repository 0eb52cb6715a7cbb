"""The rules of the house (docs/architecture.md): the import contracts of pyproject.toml hold,
and a planted arrow against the flow of the pipeline breaks them."""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LINT = Path(sys.executable).with_name("lint-imports")
needs_lint = pytest.mark.skipif(not LINT.exists(), reason="import-linter is not installed (pip install -e '.[test]')")

#: What times a test: a clock read for a duration, or a duration compared with a number. (A deadline that only
#: ends a wait which would otherwise hang, ``time.monotonic() < deadline``, and a file's time set with
#: ``os.utime``, are not timings.)
TIMING = re.compile(r"perf_counter|process_time|\btime\.time\(\)|\btimeit\b"
                    r"|assert .*\b(elapsed|duration|wall|seconds)\w*\s*[<>]=?\s*(?!0\b)[\d.]+")


def lint(folder: Path) -> subprocess.CompletedProcess:
    env = {**os.environ, "PYTHONPATH": str(folder)}
    return subprocess.run([str(LINT), "--no-cache", "--no-logo"], cwd=folder, env=env, capture_output=True, text=True)


@needs_lint
def test_the_package_keeps_its_import_contracts():
    result = lint(ROOT)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "1 kept, 0 broken" in result.stdout


@needs_lint
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


@needs_lint
def test_sibling_stages_are_independent(tmp_path):
    # regeneration (typesynth) and screening (knowledge) share the criterion language, not each other
    shutil.copytree(ROOT / "domes", tmp_path / "domes", symlinks=True, ignore=shutil.ignore_patterns("__pycache__"))
    shutil.copy(ROOT / "pyproject.toml", tmp_path)
    target = tmp_path / "domes" / "typesynth" / "regenerate.py"
    target.write_text(target.read_text() + "\nimport domes.knowledge.screening  # planted: sibling stages\n")
    result = lint(tmp_path)
    assert result.returncode == 1 and "domes.typesynth.regenerate -> domes.knowledge.screening" in result.stdout, result.stdout


def timings(text: str) -> list[str]:
    """The lines of a test module that time something (:data:`TIMING`)."""
    return [line.strip() for line in text.splitlines() if TIMING.search(line) and "utime(" not in line]


def test_no_test_asserts_a_time():
    # issue 25, item 5: a test that expects seconds fails on a slow or busy machine; timings go in benchmarks/.
    assert timings("t0 = time.perf_counter()\nassert elapsed < 2.5\nassert result.seconds <= 10") == [
        "t0 = time.perf_counter()", "assert elapsed < 2.5", "assert result.seconds <= 10"]
    assert timings("deadline = time.monotonic() + 120\nassert f.seconds > 0 and f.memory > 0\n"
                   "os.utime(old, (time.time() - 3600, time.time() - 3600))") == []
    found = {str(path.relative_to(ROOT)): timings(path.read_text())
             for path in sorted((ROOT / "tests").rglob("*.py")) if path.name != "test_architecture.py"}
    assert {path: lines for path, lines in found.items() if lines} == {}
