"""A bad scene file gets an error naming the file, the line and the problem."""

import re

import pytest

from domes.cli import main
from domes.errors import DomesError
from domes.io.resources import knowledge_dir
from domes.io.scenes import load_scene
from domes.typesynth import regenerate

BASE = (knowledge_dir() / "scenes" / "motorcycle.toml").read_text()


def broken(tmp_path, old, new):
    assert old in BASE
    text = BASE.replace(old, new, 1).replace('"../mechanisms/', f'"{knowledge_dir() / "mechanisms"}/')
    path = tmp_path / "scene.toml"
    path.write_text(text)
    line = next(i for i, row in enumerate(text.splitlines(), 1) if new.splitlines()[0] in row)
    return path, line


RULE = 'rules = ["the shock absorber must be binary and must not be the ground"]'
SWING = 'rules = ["the swing arm must not be the ground and must not represent a shock absorber"]'


@pytest.mark.parametrize(
    "old, new, problem",
    [
        (SWING, 'rules = ["the swing arm must not represent a shock absorbr"]', "unknown role 'shock_absorbr'"),
        (RULE, 'rules = ["the shock absorber must not be the swing arm"]', "cannot hold yet: role 'swing_arm' is given out only at stage 3"),
        (RULE, 'rules = ["the shock absorber must be binary and be ternary"]', "cannot hold: no link can have such a number of joints (every link of the 6-link chains of DOF 1 has 2 to 3 joints)"),
        (RULE, 'rules = ["the shock absorber must have degree 9"]', "cannot hold"),
        (RULE, 'rules = ["the shock absorber must be binary or"]', "column"),
        ('select = "adjacent pair"', 'select = "triple"', "select must be one of"),
        ('rules = ["the swing arm must be adjacent to the ground"]', 'rules = ["the swingarm must be adjacent to the ground"]', "unknown role 'swingarm'"),
        ('joint = "P"', 'joint = "Q"', "unknown joint type 'Q'"),
        ('role = "swing arm"', 'rolle = "swing arm"', "unknown key 'rolle'"),
        # issue 11: the rules a six-bar can never meet, and the keys of [chains], are checked when the file is read
        (RULE, 'rules = ["the shock absorber must be quinary"]', "(every link of the 6-link chains of DOF 1 has 2 to 3 joints)"),
        (RULE, 'rules = ["the shock absorber must be binary", "the shock absorber must be ternary"]',
         "cannot hold together: no link can have such a number of joints"),
        ("dof = 1", "include_fractionatd = true\ndof = 1", "[chains]: unknown key 'include_fractionatd'"),
        ("dof = 1", 'include_fractionated = "no"\ndof = 1', "include_fractionated must be true or false, got 'no'"),
        ("dof = 1", "dof = true", "links and dof must be whole numbers"),
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


def test_rules_that_admit_nothing_are_reported(tmp_path):
    # a rule no link can satisfy on any chain: the stage that empties the set is named, with its line
    path, line = broken(tmp_path, RULE, 'rules = ["the shock absorber must be binary and must be adjacent to the ground and must be the ground"]')
    with pytest.raises(DomesError, match=rf"{path}:\d+: stage 2 \(shock absorber\): its rules cannot hold"):
        regenerate(load_scene(path))


def test_cli_reports_and_exits_2(tmp_path, capsys):
    path, line = broken(tmp_path, SWING, 'rules = ["the swing arm must not be the groundd"]')
    assert main(["regenerate", str(path)]) == 2
    err = capsys.readouterr().err
    assert f"{path}:{line}" in err
    assert main(["regenerate", "no-such-scene"]) == 2
    assert "motorcycle" in capsys.readouterr().err  # lists the scenes there are
