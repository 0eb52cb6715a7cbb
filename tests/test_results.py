"""Every stage entry point reports the same way: a result with status (a Status), success and message."""

import math

import pytest

from domes.design.verify import Check, verify
from domes.errors import DomesError, InputError, NothingToPropose, NumericalError
from domes.expert.run import design
from domes.io.scenes import load_scene
from domes.knowledge import CriterionFrame, ProblemFrame, screen
from domes.model import LabelledChain
from domes.motion import solve, sweep
from domes.motion.planar.examples import four_bar, triple_rocker
from domes.results import Result, Status
from domes.typesynth import chains, generalize, label_joints, number_synthesis, regenerate

FOUR_BAR = [(0, 1), (1, 2), (2, 3), (0, 3)]


def check(result, status):
    assert isinstance(result, Result)
    assert result.status is status
    assert result.success is (status is Status.COMPLETE)
    assert isinstance(result.message, str) and result.message


def test_type_synthesis_stages():
    check(number_synthesis(dof=1, loops=2), Status.COMPLETE)
    atlas = chains(links=8, dof=1)
    check(atlas, Status.COMPLETE)
    assert "16 chains" in atlas.message and len(atlas) == 16 and atlas[0] in set(atlas)
    check(label_joints(atlas, {"P": 1}), Status.COMPLETE)
    check(label_joints(chains(links=4, dof=1), {"P": 5}), Status.EMPTY)  # more sliders than joints
    check(regenerate(load_scene("motorcycle")), Status.COMPLETE)
    check(generalize(LabelledChain.build(4, FOUR_BAR, {(0, 1): "P"})), Status.COMPLETE)


def test_screening_kept_or_emptied():
    graph = LabelledChain.build(4, FOUR_BAR, roles={0: {"ground"}, 2: {"input"}})
    kept = screen([graph], [CriterionFrame.create("deg", "every vertex must have degree 2")])
    emptied = screen([graph], [CriterionFrame.create("in", "the input must be adjacent to the ground")])
    check(kept, Status.COMPLETE)
    check(emptied, Status.EMPTY)
    assert emptied.emptied_by == "in" and "'in'" in emptied.message


def test_motion_and_verification():
    check(solve(four_bar(), math.radians(30)), Status.COMPLETE)
    check(sweep(four_bar(), 0.0, math.radians(90), math.radians(30)), Status.COMPLETE)
    stopped = sweep(triple_rocker(), 0.0, math.radians(130), math.radians(5))
    check(stopped, Status.STOPPED)
    assert "cannot pass 127.1688996" in stopped.message
    check(verify(four_bar(), Check("rotatability")), Status.COMPLETE)
    check(verify(triple_rocker(), Check("rotatability")), Status.STOPPED)


def test_design_run():
    check(design(ProblemFrame("p", "slider four-bar", dof=1, loops=1, slider_pairs=1), []), Status.COMPLETE)
    never = CriterionFrame.create("never", "every vertex must have degree 3")
    check(design(ProblemFrame("p", "x", dof=1, loops=1, slider_pairs=1), [never], vary=False), Status.EMPTY)


def test_progress_reaches_the_caller():
    seen = []
    chains(links=10, dof=1, progress=seen.append)
    assert any("230 chains" in m for m in seen)


def test_failures_are_one_hierarchy_and_not_value_errors():
    for kind in (InputError, NumericalError, NothingToPropose):
        assert issubclass(kind, DomesError) and not issubclass(kind, ValueError)
    with pytest.raises(NumericalError) as caught:
        solve(triple_rocker(), math.radians(128))
    assert caught.value.kind == "limit" and caught.value.where["joints"] == ("B", "C", "D")
    with pytest.raises(InputError):
        number_synthesis(dof=-1, loops=1)
