"""Files a user hands to DOMES-py, and files it writes: one rule, nothing lost (issue 11)."""

import io
import json
import os
import stat
from pathlib import Path

import pytest

from domes.cli import main

ROOT = Path(__file__).resolve().parents[1]


def test_kb_build_keeps_a_file_that_is_not_a_case_base(tmp_path, capsys):
    notes = tmp_path / "notes.db"
    notes.write_text("my notes, not a case base\n")
    assert main(["kb", "build", "--db", str(notes)]) == 2
    assert "would destroy it; give --force" in capsys.readouterr().err
    assert notes.read_text() == "my notes, not a case base\n"  # untouched
    assert main(["kb", "build", "--db", str(notes), "--force"]) == 0
    assert main(["kb", "build", "--db", str(notes)]) == 0  # a case base now: rebuilt without asking


def test_a_damaged_file_is_named_without_database_jargon(tmp_path, capsys):
    junk = tmp_path / "junk.db"
    junk.write_bytes(b"\x00junk" * 200)
    assert main(["kb", "list", "--db", str(junk)]) == 2
    err = capsys.readouterr().err
    assert "is not a DOMES-py case base, or it is damaged" in err
    assert "sqlalche.me" not in err and "[SQL:" not in err


def test_outputs_in_a_missing_folder_are_refused_the_same_way(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    missing = tmp_path / "no" / "such" / "folder"
    calls = [
        ["draw", "ErOg", "-o", str(missing / "x.svg")],
        ["kb", "export", "-o", str(missing / "kb.toml")],
        ["design", "--answers", str(ROOT / "examples/design/quickstart.answers"), "--dry-run",
         "--record", str(missing / "t.json")],
    ]
    for words in calls:
        assert main(words) == 2, words
        assert f"folder {missing} does not exist" in capsys.readouterr().err, words
    assert not (tmp_path / "no").exists()


def test_outputs_under_a_file_say_the_parent_is_a_file(tmp_path, capsys):
    # issue 25, item 5: README.md/x.html was refused as "folder README.md does not exist"
    notes = tmp_path / "README.md"
    notes.write_text("mine\n")
    for words in (["draw", "ErOg", "-o", str(notes / "x.html")], ["kb", "build", "--db", str(notes / "deep" / "kb.db")]):
        assert main(words) == 2, words
        err = capsys.readouterr().err
        assert f"{notes} is a file, not a folder" in err and "does not exist" not in err, words
    assert notes.read_text() == "mine\n"


def test_drawings_get_the_permissions_of_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        assert main(["draw", "ErOg", "-o", str(tmp_path / "s.svg")]) == 0
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "s.svg").stat().st_mode) == 0o644  # was 0600 (the temporary file's)


def test_end_of_input_before_any_answer_leaves_no_session_file(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    monkeypatch.setattr("sys.stdin", io.StringIO(""))
    assert main(["design", "--db", str(ROOT / "casebase.db"), "--dry-run"]) == 1
    assert "end of input before any answer; nothing saved" in capsys.readouterr().err
    assert not (tmp_path / ".domes-design-session.json").exists()


def test_json_nested_too_deep_or_with_an_endless_integer_is_named_by_every_reader(tmp_path, capsys):
    # issue 25, item 18: JSON nested 1,000 deep raised RecursionError, an integer of 5,000 digits a ValueError
    from domes.errors import InputError
    from domes.io.files import read_json

    deep, endless = tmp_path / "deep.json", tmp_path / "endless.json"
    deep.write_text("[" * 1000 + "]" * 1000)
    endless.write_text('{"links": [1,\n 1' + "0" * 5000 + "]}")
    with pytest.raises(InputError, match="deep.json: line 1, column 65: lists and objects nested deeper than 64"):
        read_json(deep)
    with pytest.raises(InputError, match="endless.json: line 2, column 2: an integer of more than 4,300 digits"):
        read_json(endless)
    for command in (["kinematics"], ["tolerance", "--output", "angle:x", "--relative", "1e-4"], ["dynamics"], ["draw"], ["synthesize"],
                    ["curves", "trace"], ["curves", "describe"], ["curves", "match"]):
        for path, message in ((deep, "nested deeper than 64 levels"), (endless, "more than 4,300 digits")):
            words = [*command[:2], str(path), *command[2:]] if command[0] == "curves" else [command[0], str(path),
                                                                                             *command[1:]]
            assert main(words) == 2, words
            assert message in capsys.readouterr().err, words


def test_a_long_value_is_cut_short_in_a_message(tmp_path, capsys):
    # issue 25, item 18: messages echoed whole values, up to 200,000 characters; a name longer than the system
    # takes raised OSError
    assert main(["regenerate", "x" * 300]) == 2
    err = capsys.readouterr().err
    assert "no scene 'xxxx" in err and "(302 characters)" in err and len(err) < 400
    path = tmp_path / "long.json"
    data = json.loads((ROOT / "examples/mechanisms/four-bar.json").read_text())
    data["ground"] = "g" * 200_000
    path.write_text(json.dumps(data))
    assert main(["kinematics", str(path)]) == 2
    err = capsys.readouterr().err
    assert "ground:" in err and max(len(line) for line in err.splitlines()) <= 450
