"""Runs that would hang or run for minutes in silence are estimated and refused without --yes (issue 11)."""

import io
import math

import pytest

from domes.cli import main
from domes.errors import InputError
from domes.motion import sweep
from domes.motion.planar.examples import four_bar


@pytest.fixture(autouse=True)
def no_terminal(monkeypatch):
    monkeypatch.setattr("sys.stdin", io.StringIO(""))  # nobody to ask: the guards refuse


def test_too_many_link_assortments_are_refused_or_asked_for(capsys):
    assert main(["synthesis", "--dof", "1", "--loops", "400"]) == 2  # 5e27 assortments: it used to hang
    assert "too many to list; give --no-assortments" in capsys.readouterr().err
    assert main(["synthesis", "--dof", "1", "--loops", "400", "--no-assortments"]) == 0
    assert "links i = 802   joints j = 1201" in capsys.readouterr().out
    assert main(["synthesis", "--dof", "1", "--loops", "20"]) == 2
    assert "24,418 link assortments; pass --yes" in capsys.readouterr().err


def test_huge_sweeps_are_refused(capsys):
    path = "examples/mechanisms/four-bar.json"
    assert main(["kinematics", path, "--sweep", "0:1e9:1e-6"]) == 2
    assert "has 1e+15 steps, more than 10,000,000" in capsys.readouterr().err
    assert main(["kinematics", path, "--sweep", "0:1e6:1"]) == 2
    assert "1,000,001 steps takes about" in capsys.readouterr().err
    assert main(["kinematics", path, "--at", "nan"]) == 2
    assert "--at must be a finite number" in capsys.readouterr().err
    with pytest.raises(InputError, match="finite"):
        sweep(four_bar(), 0.0, math.inf, 1.0)


def test_large_atlas_pages_and_sizes_are_refused(capsys):
    assert main(["chains", "--links", "12", "--dof", "1", "--format", "html"]) == 2
    err = capsys.readouterr().err
    assert "a page of 6856 drawn chains is large: about 41 MB" in err and "pass --yes" in err
    assert main(["chains", "--links", "100000", "--dof", "1", "--count"]) == 2
    assert "more than 20 links are out of reach" in capsys.readouterr().err
    assert main(["chain", ""]) == 2
    assert "is not a graph6 string" in capsys.readouterr().err
