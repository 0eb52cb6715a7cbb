"""Seed 002 §6-1's functional heuristics (digest seed-002-ch2-ch6.md, B.1) ordering the catalogue's proposals.

The source's rules: a precise continuous law with exact dwells -> rigid mechanisms, the cam the simplest; only
start and end positions accurate -> hydraulic or pneumatic cylinders; an approximate law -> cams, linkages,
gear-linkage combinations; transmission (constant ratio) -> gears; rotary speed regulation -> variators, linear
-> hydraulics.
"""

import json
import shutil

import pytest

from domes.cli import main
from domes.design.catalogue import propose
from domes.errors import InputError
from domes.io.catalogue import load_catalogue, load_heuristics
from domes.io.resources import knowledge_dir
from domes.knowledge.catalogue import FUNCTIONS, requirement

ENTRIES = load_catalogue()
RULES = load_heuristics()


def families(found):
    return [p.entry.family for p in found]


def test_every_function_of_the_source_has_its_heuristic():
    assert {h.function for h in RULES} == set(FUNCTIONS)
    assert all(h.source.startswith("seed 002 §6-1") for h in RULES)
    exact = next(h for h in RULES if h.function == "exact")
    assert exact.prefer[0] == "cam" and "cam is the simplest" in exact.reason
    assert next(h for h in RULES if h.function == "end positions").prefer[0] == "cylinder"
    assert next(h for h in RULES if h.function == "constant ratio").prefer[0] == "gears"


def test_a_dwell_requirement_means_an_exact_law_the_cam_first():
    found = propose(ENTRIES, "rotation -> reciprocation", ["dwell >= 90"], heuristics=RULES)
    assert found.heuristic.function == "exact" and "ordered for the function 'exact' (seed 002 §6-1)" in found.message
    assert [p.entry.name for p in found if p.kept] == ["dwell-rise-dwell-return cam"]
    assert found[0].advice.startswith("exact: cam is choice 1 of cam, intermittent") and "(seed 002 §6-1)" in found[0].advice
    # without the requirement nothing implies a function: the catalogue's order, no advice
    plain = propose(ENTRIES, "rotation -> reciprocation", heuristics=RULES)
    assert plain.heuristic is None and plain[0].entry.name == "slider-crank" and plain[0].advice == ""
    exact = propose(ENTRIES, "rotation -> reciprocation", [], "exact", RULES)
    assert families(exact) == ["cam", "linkage", "linkage", "gears"]


def test_intermittent_motion_with_a_dwell_finds_geneva_wheels_and_the_ratchet():
    found = propose(ENTRIES, "rotation -> intermittent rotation", ["dwell >= 90"], heuristics=RULES)
    assert [p.entry.name for p in found if p.kept] == ["Geneva wheel, 4 slots", "Geneva wheel, 6 slots",
                                                      "ratchet, 24 teeth"]
    assert all("intermittent is choice 2 of" in p.advice for p in found)


@pytest.mark.parametrize("function, motion, order", [
    ("constant ratio", "rotation -> reciprocation", ["gears", "linkage", "linkage", "cam"]),
    ("end positions", "rotation -> reciprocation", ["linkage", "linkage", "cam", "gears"]),
    ("approximate", "rotation -> rotation", ["gears", "gears"]),
])
def test_the_kept_mechanisms_follow_the_heuristics_families(function, motion, order):
    found = propose(ENTRIES, motion, [], function, RULES)
    assert families(found) == order
    rule = found.heuristic
    assert [rule.rank(f) for f in families(found)] == sorted(rule.rank(f) for f in families(found))


def test_requirements_imply_the_function():
    ratio = propose(ENTRIES, "rotation -> reciprocation", ["ratio variation <= 1e-6"], heuristics=RULES)
    assert ratio.heuristic.function == "constant ratio" and ratio[0].entry.name == "rack and pinion"
    straight = propose(ENTRIES, "oscillation -> straight line", ["straight-line deviation <= 1"], heuristics=RULES)
    assert straight.heuristic.function == "approximate"
    assert "cams, linkages and gear-linkage combinations" in straight[0].advice


def test_speed_regulation_by_the_output_motion():
    rotary = propose(ENTRIES, "rotation -> rotation", [], "speed regulation", RULES).heuristic
    linear = propose(ENTRIES, "rotation -> reciprocation", [], "speed regulation", RULES).heuristic
    assert rotary.prefer[0] == "variator" and linear.prefer == ("cylinder",) and "hydraulics" in linear.reason
    gears = propose(ENTRIES, "rotation -> rotation", [], "speed regulation", RULES)
    assert all(p.advice.startswith("speed regulation: gears is choice 2 of variator, gears") for p in gears)


def test_bad_functions_and_heuristic_files_say_what_is_wrong(tmp_path):
    with pytest.raises(InputError, match="unknown function 'precise': use exact, approximate"):
        propose(ENTRIES, "rotation -> reciprocation", [], "precise", RULES)
    with pytest.raises(InputError, match="no heuristic for the function 'exact'"):
        propose(ENTRIES, "rotation -> reciprocation", [], "exact", ())
    folder = tmp_path / "knowledge"
    shutil.copytree(knowledge_dir(), folder)
    text = (folder / "heuristics.toml").read_text()
    (folder / "heuristics.toml").unlink()
    assert load_heuristics(folder) == []                     # a knowledge folder without heuristics orders nothing
    for old, new, message in [
        ('prefer = ["gears", "gear-linkage"]', 'prefer = ["gears", "belts"]', r"heuristics.toml:\d+: .*'belts'"),
        ('function = "end positions"', 'function = "end points"', r"heuristics.toml:\d+: function must be one of"),
        ('implied_by = ["dwell", "index"]', 'implied_by = "dwell"', r"heuristics.toml:\d+: .*'implied_by' must be a list"),
        ('function = "exact"\n', 'function = "exact"\ncolour = "red"\n', r"heuristics.toml:\d+: unknown key\(s\) colour"),
    ]:
        assert old in text
        (folder / "heuristics.toml").write_text(text.replace(old, new, 1))
        with pytest.raises(InputError, match=message):
            load_heuristics(folder)
    catalogue = (folder / "catalogue.toml").read_text()
    (folder / "catalogue.toml").write_text(catalogue.replace('family = "intermittent"', 'family = "clockwork"'))
    with pytest.raises(InputError, match=r"catalogue.toml:\d+: ratchet, 24 teeth: family must be one of"):
        load_catalogue(folder)


def test_cli_orders_by_the_function_and_says_why(capsys):
    assert main(["catalogue", "--motion", "rotation -> reciprocation", "--function", "exact"]) == 0
    out = capsys.readouterr().out
    assert out.index("dwell-rise-dwell-return cam") < out.index("slider-crank")
    assert "why here: exact: cam is choice 1 of" in out
    assert main(["catalogue", "--motion", "rotation -> intermittent rotation", "--require", "dwell >= 90",
                 "--format", "json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["heuristic"]["function"] == "exact" and doc["heuristic"]["source"] == "seed 002 §6-1"
    assert [m["family"] for m in doc["mechanisms"]] == ["intermittent"] * 3
    assert all("(seed 002 §6-1)" in m["advice"] for m in doc["mechanisms"])
    assert str(requirement("dwell >= 90")) in doc["requirements"]
