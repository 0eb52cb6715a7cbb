"""Every shell command of README.md and docs/*.md runs as written (issue 11).

The commands of each page run in order, in a scratch folder holding copies of
examples/, knowledge/ and casebase.db, with a scratch DOMES_HOME and
DOMES_KNOWLEDGE, so that nothing of the checkout is changed. A command fails
the test when it exits with a status the page does not show; the few that are
not run say why in SKIPPED.
"""

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))]

#: Commands not run here, and why.
SKIPPED = {
    "pip install": "the quick start's install: .ci/run runs it on a fresh clone",
    "python -m pytest": "the test suite itself",
    "DOMES_FULL_TESTS=1 python -m pytest": "the test suite itself, in full",
    "python benchmarks/": "the benchmarks: tests/test_benchmarks.py starts each one",
    "chromium ": "the screenshots of docs/images (a maintainer's step)",
}
#: Commands that read answers on the terminal: here stdin is empty, so they end at the first question (exit 1).
INTERACTIVE = ("domes design", "domes design --record my-session.json")


def commands(page: Path) -> list[str]:
    """The commands of the shell blocks of a page: '$ ' lines where the block shows output, else every line."""
    out = []
    for block in re.findall(r"```(?:sh|bash|shell|console)\n(.*?)```", page.read_text(), re.S):
        lines = block.splitlines()
        prompted = any(line.startswith("$ ") for line in lines)
        i = 0
        while i < len(lines):
            line = lines[i]
            i += 1
            if prompted:
                if not line.startswith("$ "):
                    continue
                line = line[2:]
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            while line.rstrip().endswith("\\") and i < len(lines):  # continued on the next line
                line = line.rstrip()[:-1] + " " + lines[i].strip()
                i += 1
            if line.lstrip().startswith("(") and line.count("(") > line.count(")"):  # a ( ... ) group
                while i < len(lines) and line.count("(") > line.count(")"):
                    line += "\n" + lines[i]
                    i += 1
            out.append(line)
    return out


def _strip_comment(command: str) -> str:
    return re.sub(r"\s+#\s.*$", "", command) if "'" not in command.split("#")[-1] else command


@pytest.fixture
def scratch(tmp_path):
    for name in ("examples", "knowledge"):
        shutil.copytree(ROOT / name, tmp_path / name)
    shutil.copy(ROOT / "casebase.db", tmp_path / "casebase.db")
    env = {**os.environ, "DOMES_HOME": str(tmp_path / "home"), "DOMES_KNOWLEDGE": str(tmp_path / "knowledge"),
           "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ.get('PATH', '')}"}
    env.pop("DOMES_DB", None)
    return tmp_path, env


@pytest.mark.slow
@pytest.mark.parametrize("page", PAGES)
def test_documented_commands_run(page, scratch):
    folder, env = scratch
    ran = 0
    for command in commands(ROOT / page):
        if any(command.startswith(prefix) for prefix in SKIPPED):
            continue
        expected = 1 if _strip_comment(command).strip() in INTERACTIVE else 0
        result = subprocess.run(["bash", "-c", command], cwd=folder, env=env, stdin=subprocess.DEVNULL,
                                capture_output=True, text=True, timeout=300)
        assert result.returncode == expected, f"{page}: {command}\nexit {result.returncode}\n{result.stderr[-2000:]}"
        assert "Traceback" not in result.stderr, f"{page}: {command}\n{result.stderr[-2000:]}"
        ran += 1
    assert ran or not commands(ROOT / page), page


def test_the_pages_have_commands():
    # the extraction itself: the README's quick start and a continued command of docs/knowledge.md are read whole
    readme = commands(ROOT / "README.md")
    assert readme[0].startswith("pip install -e '.[test]' && domes design --answers")
    knowledge = commands(ROOT / "docs" / "knowledge.md")
    assert any("--explanation 'the swing arm pivots on the frame'" in c and c.startswith("python -m domes kb add")
               for c in knowledge)
