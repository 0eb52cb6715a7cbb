"""No traceback, ever (issue 11): every command's arguments, and a damaged case base.

Each command starts from a valid call; one argument at a time gets a hostile
value (empty, NaN, huge, a folder, a missing file, a file of the wrong kind,
...). Every call must end as the command line ends: an exit status with a
message, or argparse's usage error. Any other exception is a traceback a user
would have seen. The case-base tests damage the stored rows and the file
itself; every command that reads them must say so, and never crash.
"""

import argparse
import io
import json
import random
import shutil
import sqlite3
from pathlib import Path

import pytest

from domes.cli import build_parser, main
from domes.io.atlas import save_atlas
from domes.motion.coupler.atlas import AtlasSpec, build
from tests.sampling import FULL

ROOT = Path(__file__).resolve().parents[1]

#: A valid call of every command (DB is the scratch case base).
BASE = {
    "design": ["design", "--db", "DB", "--answers", "examples/design/quickstart.answers", "--dry-run"],
    "cases list": ["cases", "--db", "DB", "list"],
    "cases show": ["cases", "--db", "DB", "show", "hinge-clamp-1"],
    "cases replay": ["cases", "--db", "DB", "replay", "gripper"],
    "synthesis": ["synthesis", "--dof", "1", "--loops", "2"],
    "chains": ["chains", "--links", "8", "--dof", "1", "--count"],
    "chain": ["chain", "ErOg"],
    "regenerate": ["regenerate", "motorcycle"],
    "generalize": ["generalize", "knowledge/mechanisms/suzuki-rm250x.toml"],
    "kb parse": ["kb", "parse", "every vertex must have degree at most 3"],
    "kb list": ["kb", "list", "--db", "DB"],
    "kb show": ["kb", "show", "--db", "DB", "--id", "book-i"],
    "kb add": ["kb", "add", "--db", "DB", "--id", "fuzz-1", "--text", "every vertex must have degree at most 4"],
    "kb edit": ["kb", "edit", "--db", "DB", "--id", "book-i", "--explanation", "changed"],
    "kb enable": ["kb", "enable", "--db", "DB", "--id", "book-i"],
    "kb disable": ["kb", "disable", "--db", "DB", "--id", "book-i"],
    "kb remove": ["kb", "remove", "--db", "DB", "--id", "book-vi"],
    "kb history": ["kb", "history", "--db", "DB", "--changes"],
    "kb undo": ["kb", "undo", "--db", "DB"],
    "kb export": ["kb", "export", "--db", "DB", "-o", "out.toml"],
    "kb import": ["kb", "import", "--db", "DB", "EXTRA.toml"],
    "kb check": ["kb", "check", "--db", "DB"],
    "kb build": ["kb", "build", "--db", "built.db"],
    "kb screen": ["kb", "screen", "--db", "DB", "examples/knowledge/graphs.json"],
    "kb relevance": ["kb", "relevance", "--db", "DB", '{"dof": 1}'],
    "kinematics": ["kinematics", "examples/mechanisms/four-bar.json", "--at", "30"],
    "tolerance": ["tolerance", "examples/mechanisms/four-bar.json", "--output", "angle:rocker", "--relative", "1e-4",
                  "--sweep", "0:90:45", "--samples", "200"],
    "dynamics": ["dynamics", "examples/dynamics/slider-crank-engine.json", "--sweep", "0:90:45"],
    "draw": ["draw", "ErOg"],
    "cases record": ["cases", "--db", "DB", "record", "examples/design/gripper.answers", "--name", "fuzzed"],
    "cases remove": ["cases", "--db", "DB", "remove", "robot-gripper-1"],
    "synthesize": ["synthesize", "examples/synthesis/ch2-example-4.json"],
    "cam": ["cam", "--segment", "cycloidal", "180", "10", "--segment", "cycloidal", "180", "-10", "--roller", "5",
            "--base-radius", "30", "--points", "32"],
    "catalogue": ["catalogue", "--motion", "rotation -> intermittent rotation", "--require", "dwell >= 90"],
    "curves classify": ["curves", "classify", "0.4", "1.2", "1.0", "1.4"],
    "curves trace": ["curves", "trace", "--four-bar", "0.4", "1.2", "1.0", "1.4", "1.3", "0.2", "--samples", "90"],
    "curves describe": ["curves", "describe", "--four-bar", "1", "3.5", "3", "2", "0", "-2"],
    "curves atlas": ["curves", "atlas", "info", "--file", "ATLAS.h5"],
    "curves match": ["curves", "match", "examples/curves/figure-eight.csv", "--atlas", "ATLAS.h5", "--candidates", "2",
                     "--results", "1"],
    "drum": ["drum", "knowledge/mechanisms/tyre-drum-fig5-1.json"],
    "studio": ["studio", "--home", "DIR", "--db", "DB"],        # binds its socket; the serving loop is not run
}

HOSTILE = ["", " ", "nan", "inf", "-1", "0", "1e309", "99999999999999999999", "🙂 ∑", "/", "/nonexistent/x.json",
           "DIR", "BINARY", "WRONG.json", "EMPTY.toml", "-x", "examples/mechanisms/four-bar.json", "knowledge"]


def leaves() -> dict[str, argparse.ArgumentParser]:
    """Every command's parser, by the words that name it."""
    out = {}

    def walk(parser, words):
        subs = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
        if not subs:
            out[" ".join(words)] = parser
            return
        for name, child in subs[0].choices.items():
            walk(child, [*words, name])

    walk(build_parser(), [])
    return out


def mutations() -> list[tuple[str, str, str]]:
    """(command, argument, value): each argument of each command with each hostile value."""
    out = []
    for command, parser in sorted(leaves().items()):
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):
                continue
            name = action.option_strings[0] if action.option_strings else f"<{action.dest}>"
            values = [""] if action.nargs == 0 else HOSTILE
            out += [(command, name, v) for v in values]
    return out


def argv(command: str, argument: str, value: str, folder: Path) -> list[str]:
    words = list(BASE[command])
    if argument.startswith("<"):  # a positional: the first one the base call gives, replaced
        parser = leaves()[command]
        positionals = [a for a in parser._actions if not a.option_strings and a.dest != "help"]
        index = [a.dest for a in positionals].index(argument[1:-1])
        fixed = [w for w in words if not w.startswith("-")][len(command.split()):]
        if index < len(fixed):
            words[words.index(fixed[index], len(command.split()))] = value
        else:
            words.append(value)
    elif value == "" and argument in words:
        pass  # a flag already given
    elif argument in words:
        words[words.index(argument) + 1] = value
    else:
        words += [argument] + ([value] if value != "" or not _is_flag(command, argument) else [])
    return [_place(w, folder) for w in words]


def _is_flag(command: str, argument: str) -> bool:
    action = next(a for a in leaves()[command]._actions if argument in a.option_strings)
    return action.nargs == 0


def _place(word: str, folder: Path) -> str:
    return {"DB": str(folder / "casebase.db"), "DIR": str(folder / "a-folder"), "BINARY": str(folder / "binary.bin"),
            "WRONG.json": str(folder / "wrong.json"), "EMPTY.toml": str(folder / "empty.toml"),
            "EXTRA.toml": str(folder / "extra.toml"), "ATLAS.h5": str(folder / "atlas.h5")}.get(word, word)


@pytest.fixture
def scratch(tmp_path, monkeypatch):
    for name in ("examples", "knowledge"):
        shutil.copytree(ROOT / name, tmp_path / name)
    shutil.copy(ROOT / "casebase.db", tmp_path / "casebase.db")
    (tmp_path / "a-folder").mkdir()
    (tmp_path / "binary.bin").write_bytes(bytes(range(256)) * 4)
    (tmp_path / "wrong.json").write_text("[1, 2, {\"links\": null}]")
    (tmp_path / "empty.toml").write_text("")
    (tmp_path / "extra.toml").write_text('[[criterion]]\nid = "extra-1"\ntext = "every vertex must have degree at most 5"\n')
    save_atlas(build(AtlasSpec("fuzz", 6, 2.0)), tmp_path / "atlas.h5")  # a tiny atlas of coupler curves
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("DOMES_KNOWLEDGE", str(tmp_path / "knowledge"))
    monkeypatch.setenv("DOMES_HOME", str(tmp_path / "home"))
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    monkeypatch.setattr("uvicorn.Server.run", lambda self, sockets=None: None)
    return tmp_path


def ends_cleanly(words: list[str], capsys) -> int:
    """The exit status of a call (its stderr in ``ends_cleanly.err``); an exception other than argparse's
    exit fails the test with the call."""
    try:
        status = main(words)
    except SystemExit as stop:  # argparse: --help (0) or a usage error (2)
        status = stop.code
    except Exception as exc:  # noqa: BLE001 - exactly what must never happen
        pytest.fail(f"domes {' '.join(words)!r} raised {type(exc).__name__}: {exc}")
    err = capsys.readouterr().err
    assert "Traceback" not in err
    ends_cleanly.err = err
    return status


#: The mutations a test run tries: a seeded sample of :data:`FUZZ_SAMPLE`, every one of them (about 4,000, some
#: minutes) with ``DOMES_FULL_TESTS=1`` (tests/sampling.py).
FUZZ_SAMPLE = 150
SEED = 11


def sampled_mutations() -> list[tuple[str, str, str]]:
    every = mutations()
    return every if FULL else random.Random(SEED).sample(every, FUZZ_SAMPLE)


@pytest.mark.slow
def test_no_argument_ends_in_a_traceback(scratch, capsys):
    for command, argument, value in sampled_mutations():
        status = ends_cleanly(argv(command, argument, value, scratch), capsys)
        assert status in (0, 1, 2, 130), (command, argument, value)


#: Hostile values each argument of the coupler-curve and synthesis commands gets (a seeded sample of
#: :data:`HOSTILE`; every one with ``DOMES_FULL_TESTS=1``).
VALUES_EACH = 6


def every_argument(command: str) -> list[tuple[str, str, str]]:
    """Every argument of ``command``, each with :data:`VALUES_EACH` hostile values (all in a full run)."""
    rng = random.Random(f"{SEED}{command}")
    by_argument: dict[str, list] = {}
    for mutation in mutations():
        if mutation[0] == command:
            by_argument.setdefault(mutation[1], []).append(mutation)
    return [m for found in by_argument.values()
            for m in (found if FULL or len(found) <= VALUES_EACH else rng.sample(found, VALUES_EACH))]


@pytest.mark.slow
@pytest.mark.parametrize("command", sorted(c for c in BASE if c.startswith(("curves", "synthesize", "dynamics"))))
def test_every_curves_argument_ends_cleanly(scratch, capsys, command):
    # every argument of the coupler-curve and synthesis commands, with a sample of the hostile values
    for cmd, argument, value in every_argument(command):
        status = ends_cleanly(argv(cmd, argument, value, scratch), capsys)
        assert status in (0, 1, 2, 130), (argument, value)


def test_every_base_call_runs(scratch, capsys):
    for command, words in BASE.items():
        status = ends_cleanly([_place(w, scratch) for w in words], capsys)
        assert status == 0, command


# -- a damaged case base ---------------------------------------------------------------------

READERS = [["kb", "list"], ["kb", "check"], ["kb", "show", "--id", "book-i"], ["kb", "relevance", '{"dof": 1}'],
           ["kb", "export"], ["cases", "list"], ["cases", "show", "hinge-clamp-1"],
           ["kb", "add", "--id", "x-1", "--text", "every vertex must have degree at most 4"],
           ["design", "--answers", "examples/design/quickstart.answers", "--dry-run"]]


def damage(path: Path, how: str) -> None:
    if how == "not a database":
        path.write_bytes(b"this is not SQLite " * 100)
        return
    if how == "empty file":
        path.write_bytes(b"")
        return
    with sqlite3.connect(path) as db:
        if how == "tree not JSON":
            db.execute("UPDATE criteria SET tree = 'not json' WHERE id = 'book-i'")
        elif how == "tree nested deep":
            db.execute("UPDATE criteria SET tree = ? WHERE id = 'book-i'", ("[" * 200000 + "]" * 200000,))
        elif how == "tree of an unknown node":
            db.execute("UPDATE criteria SET tree = ? WHERE id = 'book-i'", (json.dumps({"node": "Eval", "code": "1"}),))
        elif how == "tree nested deep in JSON":
            db.execute("UPDATE criteria SET tree = ? WHERE id = 'book-i'", (_deep_json(3000),))
        elif how == "frame not JSON":
            db.execute("UPDATE problems SET frame = '{broken' WHERE id = 'hinge-clamp-1'")
        elif how == "keywords not a list":
            db.execute("UPDATE criteria SET keywords = '42' WHERE id = 'book-i'")
        elif how == "no schema version":
            db.execute("DROP TABLE schema_version")
        elif how == "no criteria table":
            db.execute("DROP TABLE criteria")


def _deep_json(depth: int) -> str:
    return '{"node": "Not", "item": ' * depth + '{"node": "Represents", "role": "x"}' + "}" * depth


@pytest.mark.parametrize("how", ["not a database", "empty file", "tree not JSON", "tree nested deep",
                                 "tree of an unknown node", "tree nested deep in JSON", "frame not JSON",
                                 "keywords not a list", "no schema version", "no criteria table"])
def test_a_damaged_case_base_is_named_never_a_traceback(scratch, capsys, how):
    db = scratch / "casebase.db"
    damage(db, how)
    for words in READERS:
        status = ends_cleanly([*words[:1], *(["--db", str(db)] if words[0] == "cases" else []), *words[1:],
                               *(["--db", str(db)] if words[0] != "cases" else [])], capsys)
        assert status in (0, 2), (how, words)
        if status == 2:
            assert any(w in ends_cleanly.err for w in ("damaged", "not a DOMES-py case base", "schema", "is empty")), \
                ends_cleanly.err
            assert "sqlalche.me" not in ends_cleanly.err and "[SQL:" not in ends_cleanly.err  # no raw SQLAlchemy text
