"""Every shell command of README.md and docs/*.md runs as written (issue 11).

The commands of each page run in order, in a scratch folder holding copies of
examples/, knowledge/ and casebase.db, with a scratch DOMES_HOME and
DOMES_KNOWLEDGE, so that nothing of the checkout is changed. A command fails
the test when it exits with a status the page does not show; the few that are
not run say why in SKIPPED.

A command that is the command line alone (``domes ARGS``, no shell syntax)
runs through the console script's entry point, ``domes.cli.main``, in a
child forked from the test process, the package already imported; any other
command runs in bash.

The pages of BLOCKWISE run block by block, each block a test of its own in its
own scratch folder (their blocks are independent: each starts from the shipped
state), so that ``pytest -n auto`` spreads them over the workers. A command
that does not depend on what earlier commands did (PURE) runs once, where it
first appears; a read-only command written twice in a row runs once; and a
command another test runs and checks more closely (ELSEWHERE) is left to it.
A ``--dry-run`` design session (DRY_RUN) is left to an earlier run of it, or to
another test, only when what it reads is still as shipped (checked when it
comes: else it runs here).

The scratch data folder holds the small coupler-curve atlas and its index of
open paths, built once per test run (tests/shared.py), as after a first
``domes curves match``: that the first match builds the atlas there is
tested by tests/motion/test_curves_cli.py, and that the first ``--open`` match
builds the index there, by the parts of OPEN_INDEX_BUILT_HERE.
"""

import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import pytest

from tests.shared import forked_main

ROOT = Path(__file__).resolve().parents[1]
PAGES = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs").glob("*.md"))]

#: Commands not run here, and why.
SKIPPED = {
    "pip install": "the quick start's install: .ci/run runs it on a fresh clone",
    "python -m pytest": "the test suite itself",
    "DOMES_FULL_TESTS=1 python -m pytest": "the test suite itself, in full",
    "python benchmarks/": "the benchmarks: tests/test_benchmarks.py starts each one",
    "chromium ": "the screenshots of docs/images (a maintainer's step)",
    "domes cases replay --all": ".ci/run replays every shipped case with the installed wheel (exit 0 required)",
    "domes studio": "a server that runs until stopped: tests/studio start it (the server fixture) and drive it in Chromium",
}
#: Commands that read answers on the terminal: here stdin is empty, so they end at the first question (exit 1).
INTERACTIVE = ("domes design", "domes design --record my-session.json")
#: Pages whose shell blocks are independent of each other: each block runs as a test of its own (README.md: its
#: only change to the case base, `kb add` in the design block, is taken back there by `kb undo`).
BLOCKWISE = ("README.md",)
#: Commands whose run reads nothing an earlier command may have changed (no case base, no files of the scratch
#: folder but the shipped examples and knowledge): the same command on another page is not run again.
PURE = ("domes kinematics ", "domes synthesize ", "domes tolerance ", "domes dynamics ", "domes cam ", "domes chain ",
        "domes curves classify ", "domes curves trace ", "domes curves describe ", "domes generalize ",
        "domes catalogue ", "domes synthesis ", "domes draw ", "domes chains --links 12 --dof 1 --count ",
        "domes chains --links 10 --dof 1 --format html ",
        # it goes on from what atlas12/ holds: no command writes atlas12/ before it on its page (checked below)
        "domes chains --links 12 --dof 1 --workers 2 --out atlas12")
#: A design session on a scratch copy of the case base: it reads the answers, the knowledge, the case base and the
#: data folder, and keeps nothing. Written again, or run by another test (ELSEWHERE), it is left to that run only
#: when the scratch folder's examples/, knowledge/, casebase.db and data folder are still as the test made them
#: (else it runs here); the run of a page that others are left to checks the same before it runs.
DRY_RUN = re.compile(r"domes design --answers examples/design/[\w-]+\.answers --dry-run")
#: Commands that change nothing: written twice in a row, they run once.
READ_ONLY = (*PURE, "domes kb screen ", "python -m domes kb screen ", "domes kb list", "python -m domes kb list",
             "domes kb parse ", "python -m domes kb parse ", "domes cases list", "domes cases show ")
#: Commands another test runs as written and checks more closely (the same arguments, its output read).
ELSEWHERE = {
    "domes curves match examples/curves/figure-eight.csv --format html -o eight.html":
        ("tests/motion/test_curves_cli.py", "test_documented_match_builds_the_small_atlas",
         '"curves", "match", str(ROOT / "examples/curves/figure-eight.csv"), "--format", "html", "-o"'),
    # the quick start's session, on the shipped case base (exit 0 required; it asks for no coupler path, so the
    # atlas files of the data folder here are not read)
    "domes design --answers examples/design/quickstart.answers --dry-run":
        (".ci/run", None, "&& domes design --answers examples/design/quickstart.answers --dry-run\n"),
}
#: Parts whose data folder gets the small atlas but not its index of open paths: their first ``--open`` match
#: builds it there.
OPEN_INDEX_BUILT_HERE = ("README.md#14",)


def blocks(page: Path) -> list[list[str]]:
    """The commands of each shell block of a page: '$ ' lines where the block shows output, else every line."""
    out = []
    for block in re.findall(r"```(?:sh|bash|shell|console)\n(.*?)```", page.read_text(), re.S):
        out.append([])
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
            out[-1].append(line)
    return out


def commands(page: Path) -> list[str]:
    """The commands of the shell blocks of a page, in order."""
    return [command for block in blocks(page) for command in block]


def _strip_comment(command: str) -> str:
    return re.sub(r"\s+#\s.*$", "", command) if "'" not in command.split("#")[-1] else command


def _plain(command: str) -> str:
    """The command without its comment and with single spaces, to find the same command written elsewhere."""
    return " ".join(_strip_comment(command).split())


#: Per part, the steps not run only while the scratch folder is as made (DRY_RUN: else they run), and the steps
#: whose run others are left to (the folder must be as made when they come).
UNLESS_CHANGED: dict[str, set[int]] = {}
RELIED_ON: dict[str, set[int]] = {}


def _elsewhere(plain: str) -> str:
    file, name, _ = ELSEWHERE[plain]
    return f"run and checked by {file}::{name}" if name else f"run by {file}"


def plan() -> dict[str, list[tuple[str, str | None]]]:
    """Every part (a page, or a block of a BLOCKWISE page) with each of its commands and why it is not run here
    (None: run)."""
    parts, first = {}, {}
    UNLESS_CHANGED.clear()
    RELIED_ON.clear()
    for page in PAGES:
        chunks = blocks(ROOT / page)
        named = [(f"{page}#{k + 1}", c) for k, c in enumerate(chunks)] if page in BLOCKWISE else [(page, commands(ROOT / page))]
        for name, chunk in named:
            steps, before = [], None
            for command in chunk:
                plain, why = _plain(command), None
                skipped = next((prefix for prefix in SKIPPED if command.startswith(prefix)), None)
                if skipped is not None:
                    why = SKIPPED[skipped]
                elif plain in ELSEWHERE:
                    why = _elsewhere(plain)
                    if DRY_RUN.fullmatch(plain):
                        why += ", with what it reads as shipped (if so here)"
                        UNLESS_CHANGED.setdefault(name, set()).add(len(steps))
                elif DRY_RUN.fullmatch(plain) and plain in first:
                    why = f"the same session ran in {first[plain][0]}, with what it reads as shipped (if so here)"
                    UNLESS_CHANGED.setdefault(name, set()).add(len(steps))
                    RELIED_ON.setdefault(first[plain][0], set()).add(first[plain][1])
                elif plain.startswith(PURE) and plain in first:
                    why = f"the same command ran in {first[plain][0]}"
                elif plain == before and plain.startswith(READ_ONLY):
                    why = "the same command ran just before"
                if why is None:
                    first.setdefault(plain, (name, len(steps)))
                    before = plain
                steps.append((command, why))
            parts[name] = steps
    return parts


PLAN = plan()
#: The parts with a command to run.
RUN = [name for name, steps in PLAN.items() if any(why is None for _, why in steps)]


def _inputs(folder: Path) -> list[tuple[str, int, int]]:
    """What a design session reads of the scratch folder, as each file's name, size and time of change."""
    paths = [folder / "casebase.db", *(p for name in ("examples", "knowledge", "home") for p in (folder / name).rglob("*"))]
    return sorted((str(p.relative_to(folder)), p.stat().st_size, p.stat().st_mtime_ns) for p in paths if p.is_file())


def _seed_atlas(home: Path, tmp_path_factory, kinds) -> None:
    """The small atlas files (built once per run) in the data folder where the commands look for them."""
    from domes.io.atlas import atlas_path
    from tests.shared import small_atlas_file

    for kind in kinds:
        source = small_atlas_file(tmp_path_factory, kind)
        target = home / "atlas" / atlas_path("small", kind).name
        target.parent.mkdir(parents=True, exist_ok=True)
        try:
            os.link(source, target)  # read only by the commands (a new build is written beside and renamed)
        except OSError:
            shutil.copyfile(source, target)


#: Seconds a command may take.
TIMEOUT = 300
#: Characters of shell syntax (a pipe, a redirection, a substitution, a glob, a second command): a command with
#: any of them, even quoted, runs in bash.
SHELL = re.compile(r"[|&;<>()$`*?\[\]{}~!\\]")


def domes_argv(command: str) -> list[str] | None:
    """The arguments of a command that is ``domes ARGS`` (or ``python -m domes ARGS``) and nothing else; None for
    anything the shell must run.

    >>> domes_argv("domes kb add --id x --text 'a b'   # a comment")
    ['kb', 'add', '--id', 'x', '--text', 'a b']
    >>> domes_argv("domes chains --links 10 --dof 1 --format html > atlas.html") is None
    True
    """
    try:
        words = shlex.split(command, comments=True)
    except ValueError:  # not for this reading: the shell's
        return None
    if any(SHELL.search(word) for word in words):  # shell syntax (or the like, quoted: the shell runs it)
        return None
    if words[:1] == ["domes"]:
        return words[1:]
    if words[:3] == ["python", "-m", "domes"]:
        return words[3:]
    return None


@pytest.fixture(scope="module", autouse=True)
def imported():
    """What the commands import, imported once: each forked command then costs only its own work."""
    import h5py  # noqa: F401
    import scipy.optimize  # noqa: F401

    import domes.cli
    import domes.expert.dialogue  # noqa: F401
    import domes.sketch.curves  # noqa: F401

    domes.cli.build_parser()


def run_forked(argv: list[str], folder: Path, env: dict[str, str]) -> tuple[int, str]:
    """``domes ARGV`` run by its entry point in a child of this process (tests/shared.py :func:`forked_main`), in
    ``folder`` with ``env`` and an empty stdin, as the console script runs it: its exit status and its stderr."""
    with tempfile.TemporaryDirectory(prefix="domes-doc-") as tmp:
        wait = forked_main(argv, folder, os.devnull, Path(tmp) / "stderr.txt", env=env, alarm=TIMEOUT)
        stderr = (Path(tmp) / "stderr.txt").read_text(encoding="utf-8", errors="replace")
    return (128 + os.WTERMSIG(wait) if os.WIFSIGNALED(wait) else os.WEXITSTATUS(wait)), stderr


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
@pytest.mark.parametrize("part", RUN)
def test_documented_commands_run(part, scratch, tmp_path_factory):
    folder, env = scratch
    _seed_atlas(folder / "home", tmp_path_factory, ("closed",) if part in OPEN_INDEX_BUILT_HERE else ("closed", "open"))
    made = _inputs(folder)
    ran = 0
    for k, (command, why) in enumerate(PLAN[part]):
        if k in RELIED_ON.get(part, ()):
            assert _inputs(folder) == made, f"{part}: {command}: later runs of it are left to this one, but an " \
                                            "earlier command changed what it reads"
        if why is not None and not (k in UNLESS_CHANGED.get(part, ()) and _inputs(folder) != made):
            continue
        expected = 1 if _strip_comment(command).strip() in INTERACTIVE else 0
        argv = domes_argv(command)
        if argv is None:
            result = subprocess.run(["bash", "-c", command], cwd=folder, env=env, stdin=subprocess.DEVNULL,
                                    capture_output=True, text=True, timeout=TIMEOUT)
            status, stderr = result.returncode, result.stderr
        else:
            status, stderr = run_forked(argv, folder, env)
        assert status == expected, f"{part}: {command}\nexit {status}\n{stderr[-2000:]}"
        assert "Traceback" not in stderr, f"{part}: {command}\n{stderr[-2000:]}"
        ran += 1
    assert ran, part


def test_every_documented_command_is_run_or_says_why():
    # Every command of every page is in the plan, in its order; one not run says why, a repeat is run where it
    # first appears, and a command left to another test is run there as written (the same arguments).
    assert [c for steps in PLAN.values() for c, _ in steps] == [c for page in PAGES for c in commands(ROOT / page)]
    run = {_plain(c) for steps in PLAN.values() for c, why in steps if why is None}
    for steps in PLAN.values():
        for command, why in steps:
            if _plain(command) in ELSEWHERE:
                file, name, arguments = ELSEWHERE[_plain(command)]
                source = (ROOT / file).read_text()
                assert (name is None or f"def {name}(" in source) and arguments in source, (command, file, name)
            elif why is not None and not command.startswith(tuple(SKIPPED)):
                assert _plain(command) in run, command
    # a session left to an earlier run of it is left to a run that checks it reads the shipped inputs (and the same
    # data folder: both atlas files)
    assert not set(RELIED_ON) & set(OPEN_INDEX_BUILT_HERE)
    for part, steps in UNLESS_CHANGED.items():
        for k in steps:
            plain = _plain(PLAN[part][k][0])
            assert plain in ELSEWHERE or any(_plain(PLAN[p][i][0]) == plain and PLAN[p][i][1] is None
                                             for p, relied in RELIED_ON.items() for i in relied), (part, plain)
    # the atlas job that goes on from what its folder holds is the first command of its page to name that folder
    for steps in PLAN.values():
        for k, (command, _) in enumerate(steps):
            if _plain(command).startswith("domes chains --links 12 --dof 1 --workers 2 --out atlas12"):
                assert not any("atlas12" in c for c, _ in steps[:k]), command


def test_the_pages_have_commands():
    # the extraction itself: the README's quick start and a continued command of docs/knowledge.md are read whole
    readme = commands(ROOT / "README.md")
    assert readme[0].startswith("pip install -e '.[test]' && domes design --answers")
    knowledge = commands(ROOT / "docs" / "knowledge.md")
    assert any("--explanation 'the swing arm pivots on the frame'" in c and c.startswith("python -m domes kb add")
               for c in knowledge)
