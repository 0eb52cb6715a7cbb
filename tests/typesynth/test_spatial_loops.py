"""Single-loop spatial chains (λ = 6) with R, P, H, C, S joints, against brute force over joint assignments.

The chains of ``domes.typesynth.spatial`` are built by a pruned search keeping
the least reading of each loop; here every one of the 5^n joint assignments
is tried, its DOF counted by Kutzbach (seed 002, (7-1) with λ = 6) less the
idle spins of links held by two S joints, and the assignments grouped into
orbits of the dihedral group by their sets of readings, and counted a second
way by Burnside's lemma. The RSSR is seed 001's mechanism, the RCCC seed
004's.
"""

import json
from fractions import Fraction
from itertools import product

import pytest

from domes.errors import InputError
from domes.model.mobility import SPATIAL, mobility
from domes.typesynth import function_generators, spatial_loops
from domes.typesynth.spatial import SpatialLoop, generic_mobility

F = {"R": 1, "P": 1, "H": 1, "C": 2, "S": 3}


def dof_of(seq: tuple[str, ...]) -> int:
    """Kutzbach with n links and n joints (mobility(n, n, 6, Σf)) less the links between two S joints."""
    n = len(seq)
    idle = sum(1 for i in range(n) if seq[i] == "S" == seq[(i + 1) % n])
    return mobility(n, n, SPATIAL, freedom=sum(F[t] for t in seq)) - idle


def readings(seq: tuple[str, ...]) -> list[tuple[str, ...]]:
    n = len(seq)
    return [tuple(s[(k + i) % n] for i in range(n)) for s in (seq, seq[::-1]) for k in range(n)]


def brute_orbits(n: int, dof: int, types: str = "RPHCS") -> set[frozenset]:
    return {frozenset(readings(seq)) for seq in product(types, repeat=n) if dof_of(seq) == dof}


def burnside(n: int, dof: int, types: str = "RPHCS") -> int:
    """Orbits = the mean over the 2n symmetries of the assignments (with that DOF) each fixes."""
    fixed = 0
    for seq in product(types, repeat=n):
        if dof_of(seq) == dof:
            fixed += sum(r == seq for r in readings(seq))
    return int(Fraction(fixed, 2 * n))


@pytest.mark.parametrize("n, dof", [(3, 1), (4, 1), (5, 1), (3, 0), (4, 0), (4, 2), (5, 2), (4, 3)])
def test_count_equals_brute_force(n, dof):
    found = spatial_loops(n, dof=dof)
    orbits = brute_orbits(n, dof)
    assert len(found) == len(orbits) == burnside(n, dof)
    assert {frozenset(readings(tuple(loop.joints))) for loop in found} == orbits
    for loop in found:
        assert loop.dof == dof_of(tuple(loop.joints)) == dof
        assert len(set(readings(tuple(loop.joints)))) == 2 * n // loop.symmetry  # orbit-stabiliser


def test_four_links_dof_one_with_subsets_of_joint_types():
    for types in ("R", "RS", "RC", "RCS", "PHS", "CS"):
        assert len(spatial_loops(4, dof=1, joints=types)) == len(brute_orbits(4, 1, types)), types


def test_six_and_seven_links_by_burnside():
    assert len(spatial_loops(6, dof=1)) == burnside(6, 1)
    assert len(spatial_loops(7, dof=1)) == burnside(7, 1)
    assert spatial_loops(7, dof=1, joints="R").names == ("RRRRRRR",)  # the 7R loop: mobility(7, 7, 6) = 1


def test_rssr_and_rccc_are_one_dof_chains_of_four_links():
    found = spatial_loops(4, dof=1)
    rssr, rccc = found.get("RSSR"), found.get("RCCC")
    # seed 001: the RSSR is a one-input function generator; Kutzbach gives 2, one of them the coupler's spin
    assert (rssr.kutzbach, rssr.idle, rssr.dof, rssr.generic_dof, rssr.proper) == (2, 1, 1, 1, True)
    # seed 004: the RCCC, 1 + 2 + 2 + 2 − 6 = 1
    assert (rccc.kutzbach, rccc.idle, rccc.dof, rccc.generic_dof, rccc.proper) == (1, 0, 1, 1, True)
    assert found.get("srrs") == rssr  # read any way round, any case


def test_generic_mobility_where_the_kutzbach_count_fails():
    # a loop of P joints only translates: 3 closure equations, not 6
    for n in (4, 5, 7):
        assert generic_mobility("P" * n) == (n - 3, ())
    # three turning axes in general position alone cannot turn: the R's of 3R + 4P are still
    mobility_, locked = generic_mobility("RRRPPPP")
    assert mobility_ == 1 and locked == ((0, "turn"), (1, "turn"), (2, "turn"))
    pccc = SpatialLoop("PCCC")
    assert pccc.dof == 1 and not pccc.proper and "turn of joint 1 (C)" in pccc.note()
    # the 7R loop and the spatial four-bar of R joints: the generic count is Kutzbach's
    assert generic_mobility("RRRRRRR") == (1, ())
    assert generic_mobility("RRRR") == (0, tuple((i, "turn") for i in range(4)))  # rigid unless Bennett's


def test_generic_mobility_does_not_depend_on_the_placement():
    for loop in spatial_loops(5, dof=1):
        first = generic_mobility(loop.joints)
        assert all(generic_mobility(loop.joints, seed=seed) == first for seed in (1, 2, 3)), loop.joints


def test_function_generators_against_brute_force():
    # a function generator reads the loop from its input joint (R, P or H, frame-input) to its output joint
    # (R, P, H or C, output-frame): every such string of a proper 1-DOF loop, each once
    for n in (3, 4, 5):
        strings = {
            "".join(seq) for seq in product("RPHCS", repeat=n)
            if seq[0] in "RPH" and seq[-1] in "RPHC" and dof_of(seq) == 1 and SpatialLoop("".join(seq)).proper
        }
        found = function_generators(spatial_loops(n, dof=1))
        assert sorted(g.joints for g in found) == sorted(strings)
    names = {g.joints for g in function_generators(spatial_loops(4, dof=1))}
    assert {"RSSR", "RCCC"} <= names and "PCCC" not in names
    rssr = next(g for g in function_generators(spatial_loops(4, dof=1)) if g.joints == "RSSR").labelled()
    assert rssr.joint_types.count("Sph") == 2 and rssr.links_with_role("input") == [1]


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"links": 2}, "a single loop has 3 to"),
        ({"links": 13}, "a single loop has 3 to"),
        ({"links": 4, "joints": "RX"}, "unknown joint type"),
        ({"links": 4, "joints": ""}, "a string of R, P, H, C, S"),
        ({"links": 4, "dof": -1}, "dof"),
        ({"links": "4"}, "links"),
    ],
)
def test_bad_input_is_named(kwargs, message):
    with pytest.raises(InputError, match=message):
        spatial_loops(**kwargs)


def test_bad_loops_are_named():
    from domes.typesynth.spatial import canonical_loop, kutzbach

    for call in (lambda: SpatialLoop("RSQR"), lambda: kutzbach("RZ"), lambda: canonical_loop(7),
                 lambda: generic_mobility("")):
        with pytest.raises(InputError, match=r"R, P, H, C, S|R \(revolute\), P \(prismatic\)"):
            call()
    with pytest.raises(InputError, match="3 links or more"):
        SpatialLoop("SS")
    with pytest.raises(InputError, match="is not among the 24 chains"):
        spatial_loops(4).get("RRRR")


def test_command_line(capsys):
    from domes.cli import main

    assert main(["chains", "--spatial", "--links", "4", "--dof", "1", "--count"]) == 0
    assert capsys.readouterr().out == f"{len(brute_orbits(4, 1))}\n"
    assert main(["chains", "--spatial", "--links", "4", "--dof", "1", "--format", "json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert data["count"] == len(data["chains"]) == len(brute_orbits(4, 1)) and data["space"] == "spatial"
    assert {"RRSS", "RCCC"} <= {c["joints"] for c in data["chains"]}
    assert main(["chains", "--spatial", "RC", "--links", "4", "--dof", "1"]) == 0
    out = capsys.readouterr().out
    assert "1 single-loop spatial chain of 4 links, DOF 1" in out and "RCCC" in out
    for argv, message in (
        (["--spatial", "--loops", "1"], "--loops is for the planar atlas"),
        (["--spatial", "--links", "4", "--active"], "--active is for the planar atlas"),
        (["--spatial", "--links", "4", "--format", "graph6"], "--format graph6"),
        (["--spatial", "RX", "--links", "4"], "unknown joint type"),
        (["--spatial", "--links", "2"], "a single loop has 3 to"),
    ):
        assert main(["chains", *argv, "--dof", "1"]) == 2, argv
        assert message in capsys.readouterr().err, argv


def test_the_counts_table_of_the_docs():
    from pathlib import Path

    page = (Path(__file__).resolve().parents[2] / "docs" / "spatial.md").read_text()
    rows = [line for line in page.splitlines() if line.startswith("| ") and line[2:3].isdigit()]
    assert len(rows) == 4
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        dof = int(cells[0])
        for links, cell in zip(range(3, 10), cells[1:]):
            if cell == "–":
                assert links > dof + 6
                continue
            found = spatial_loops(links, dof=dof)
            proper = sum(loop.proper for loop in found)
            assert cell == (str(len(found)) if proper == len(found) else f"{len(found)} ({proper})"), (dof, links)
