"""Files a user hands to DOMES-py, and files it writes: one rule, nothing lost (issue 11)."""

import io
import os
import stat
from pathlib import Path

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
