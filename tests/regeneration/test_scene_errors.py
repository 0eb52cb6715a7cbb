"""A bad scene file gets an error naming the file, the line and the problem."""

import re

import pytest

from domes.cli import main
from domes.errors import DomesError
from domes.paths import knowledge_dir
from domes.regeneration import load_scene

BASE = (knowledge_dir() / "scenes" / "motorcycle.toml").read_text()


def broken(tmp_path, old, new):
    assert old in BASE
    text = BASE.replace(old, new, 1)
    path = tmp_path / "scene.toml"
    path.write_text(text)
    line = next(i for i, row in enumerate(text.splitlines(), 1) if new.splitlines()[0] in row)
    return path, line


@pytest.mark.parametrize(
    "old, new, problem",
    [
        ('where = ["not ground", "not shock_absorber"]', 'where = ["not ground", "not shock_absorbr"]', "unknown role 'shock_absorbr'"),
        ('where = ["binary", "not ground"]', 'where = ["binary", "not swing_arm"]', "cannot hold: role 'swing_arm' is assigned only at stage 3"),
        ('where = ["binary", "not ground"]', 'where = ["binary", "ternary"]', "cannot hold: no link can be binary and ternary"),
        ('where = ["binary", "not ground"]', 'where = ["degree >= 9"]', "cannot hold"),
        ('where = ["binary", "not ground"]', 'where = ["binary or"]', "expected a condition"),
        ('select = "adjacent pair"', 'select = "triple"', "select must be one of"),
        ('screen = "swing_arm"', 'screen = "swingarm"', "screen of unknown role 'swingarm'"),
        ('joint = "P"', 'joint = "Q"', "unknown joint type 'Q'"),
        ('role = "swing_arm"', 'rolle = "swing_arm"', "unknown key 'rolle'"),
    ],
)
def test_semantic_errors(tmp_path, old, new, problem):
    path, line = broken(tmp_path, old, new)
    with pytest.raises(DomesError) as info:
        load_scene(path)
    message = str(info.value)
    assert message.startswith(f"{path}:{line}:"), message
    assert problem in message


def test_syntax_error(tmp_path):
    path, line = broken(tmp_path, 'name = "ground"\nrole = "ground"', 'name = "ground\nrole = "ground"')
    with pytest.raises(DomesError) as info:
        load_scene(path)
    assert str(path) in str(info.value) and "TOML syntax error" in str(info.value)
    assert re.search(rf"line {line}\b", str(info.value))


def test_cli_reports_and_exits_2(tmp_path, capsys):
    path, line = broken(tmp_path, 'screen = "swing_arm"', 'screen = "swingarm"')
    assert main(["regenerate", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:{line}" in err
    assert main(["regenerate", "no-such-scene"]) == 2
    assert "motorcycle" in capsys.readouterr().err  # lists the scenes there are
