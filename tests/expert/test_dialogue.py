"""The design dialogue of DOMES (seed 002, §7-2, Fig. 7-8; digest part 4.4), branch by branch.

Each test drives the dialogue with recorded answers against a scratch copy
of the shipped case base, and checks the stored frames and relevance vectors.
"""

from pathlib import Path

import pytest

from domes.errors import DomesError
from domes.expert.dialogue import Dialogue
from domes.expert.replay import replay
from domes.io.resources import knowledge_dir
from domes.io.transcripts import parse_answers
from domes.store.casebase import KnowledgeBase

ROOT = Path(__file__).resolve().parents[2]  # the checkout
MOTORCYCLE = (ROOT / "examples" / "design" / "motorcycle.answers").read_text()
CASE = "motorcycle-rear-suspension-1"


def run(casebase, text, **kwargs):
    messages = []
    outcome = Dialogue(casebase, parse_answers(text), interactive=False, out=messages.append, **kwargs).run()
    return outcome, "\n".join(messages)


def asked(outcome):
    return [e["question"] for e in outcome.exchanges]


@pytest.mark.parametrize("name", sorted(p.stem for p in (knowledge_dir() / "cases").glob("*.json")))
def test_every_shipped_case_replays_identically(name):
    result = replay(name)
    assert result.differences == []


def test_same_problem_is_answered_from_the_case_base(casebase):
    with KnowledgeBase(casebase) as kb:
        before = kb.problems()
    outcome, said = run(casebase, f"class: motorcycle rear suspension\nrelation: same {CASE}\n")
    assert outcome.relation == "same" and outcome.case == CASE
    assert asked(outcome) == ["class", "relation"]  # nothing else asked, nothing designed
    assert "from the case base" in said and "Designing" not in said
    with KnowledgeBase(casebase) as kb:
        assert kb.problems() == before  # nothing retained
        assert outcome.frame == kb.get_problem(CASE)


def test_identical_attributes_are_recognised_as_the_same_problem(casebase):
    # The designer says "different", but the case-based reasoner finds a solved problem
    # with the same class, structure and representative attributes.
    text = MOTORCYCLE.replace("class: motorcycle rear suspension\n", "class: motorcycle rear suspension\nrelation: different\n")
    text = text.split("scene:")[0]
    outcome, said = run(casebase, text)
    assert outcome.relation == "same" and outcome.case == CASE
    assert "same class, structure and attributes" in said


def test_similar_problem_takes_over_the_structure_and_merges_the_vectors(casebase):
    text = (
        "class: motorcycle rear suspension\n"
        f"relation: similar {CASE}\n"
        "names: ground, swing arm, shock absorber, rocker\n"
        "scene: motorcycle\n"
        "relevance_overrides: -book-ii +input-on-ground\n"
        "more_criteria: yes\n"
        "criterion: the swing arm must be ternary\n"
        "more_criteria: no\n"
        "verify: none\n"
        "satisfied: yes\n"
    )
    outcome, said = run(casebase, text)
    assert outcome.relation == "similar"
    assert "dof" not in asked(outcome) and "loops" not in asked(outcome)  # taken over, not asked
    with KnowledgeBase(casebase) as kb:
        new = kb.get_problem("motorcycle-rear-suspension-2")
        old = kb.get_problem(CASE)
        criteria = [f.id for f in kb.frames()]
    assert (new.dof, new.loops, new.slider_pairs, new.links, new.joints) == (old.dof, old.loops, old.slider_pairs, 6, 7)
    assert "rocker" in new.names
    added = new.criteria_added[0]
    assert added in criteria and added.startswith("designer-")
    # merged vector: element-wise OR of the new one and the stored one, over every criterion
    bits = dict(zip(new.relevance.ids, new.relevance.bits))
    old_bits = dict(zip(old.relevance.ids, old.relevance.bits))
    assert bits[added] == 1 and bits["input-on-ground"] == 1
    assert all(bits[i] >= b for i, b in old_bits.items())
    assert bits["book-ii"] == max(0, old_bits["book-ii"])
    # the added criterion (a ternary swing arm) keeps the designs whose swing arm is a plate
    assert 0 < len(new.results) < len(old.results)


def test_everything_eliminated_varies_loops_and_gears(casebase):
    # Criterion (ii) of the book, left relevant, rejects every suspension (piston and
    # cylinder are both slider-and-revolute links): the design varies the loops, then the
    # gear pairs, and says so (§7-2, structure determination step 3).
    text = MOTORCYCLE.replace("relevance_overrides: -book-ii", "relevance_overrides: none").replace(
        "class: motorcycle rear suspension\n", "class: motorcycle rear suspension\nrelation: different\n"
    ).replace("names: ground, swing arm, shock absorber", "names: ground, swing arm, shock absorber, damper")
    text = "\n".join(line for line in text.splitlines() if not line.startswith("verify:"))  # nothing kept to verify
    outcome, said = run(casebase, text)
    assert "criterion 'book-ii' eliminated the last candidate; trying 3 loops" in said
    assert "every variation was eliminated too" in said
    frame = outcome.frame
    assert frame.results == () and frame.rejected and all(r["criterion"] == "book-ii" for r in frame.rejected)
    assert any("trying 3 loops" in note for note in frame.notes)


def test_bad_answers_are_asked_again_with_the_reason(casebase):
    text = (
        "class: gear box\noutputs: 1\ndof: two\ndof: 1\nspace: spatial\nspace: planar\nloops: 1\n"
        "gear_pairs: 0\nslider_pairs: 1\nnames: none\nscene: nowhere\nscene: none\n"
        "relevance_overrides: +no-such-criterion\nrelevance_overrides: none\n"
        "more_criteria: maybe\nmore_criteria: yes\ncriterion: the swing arm must be adjacent to\n"
        "criterion: every vertex must have at most 2 joints\nmore_criteria: no\nverify: 2 nowhere.json rotatability\n"
        "verify: 1 examples/mechanisms/four-bar.json rotatability\nverify: none\nsatisfied: rejected\nsatisfied: yes\n"
    )
    outcome, said = run(casebase, text)
    rejected = {e["answer"]: e["rejected"] for e in outcome.exchanges if "rejected" in e}
    assert "expected a whole number" in rejected["two"]
    assert "planar" in rejected["spatial"]
    assert "no scene 'nowhere'" in rejected["nowhere"]
    assert "no criterion 'no-such-criterion'" in rejected["+no-such-criterion"]
    assert "yes or no" in rejected["maybe"]
    assert "column" in rejected["the swing arm must be adjacent to"]
    assert "not among those kept" in rejected["2 nowhere.json rotatability"]
    assert "is not this candidate" in rejected["1 examples/mechanisms/four-bar.json rotatability"]
    assert outcome.frame is not None and len(outcome.frame.results) == 1  # the slider-crank four-bar


def test_scripted_answers_must_fit_the_questions(casebase):
    with pytest.raises(DomesError, match="answer 2 is for 'dof', but the question is 'relation'"):
        run(casebase, "class: motorcycle rear suspension\ndof: 1\n")
    with pytest.raises(DomesError, match="the answers ended before the question 'relation'"):
        run(casebase, "class: motorcycle rear suspension\n")


def test_pump_structure_rule(casebase):
    # MECXPRT (seed 002 §7-1): W = 1, three loops, R and P joints only -> 8 links, 10 joints.
    with KnowledgeBase(casebase) as kb:
        pump = kb.get_problem("double-acting-pump-1")
    assert (pump.links, pump.joints) == (8, 10)


def test_verification_of_a_candidate(casebase):
    # The dimensioned Suzuki RM-250X is candidate 2 of the motorcycle design; the check's
    # result (shock stroke for a swing-arm travel) joins the frame's notes, and equals the
    # kinematics backend's own answer.
    import math

    from domes.io.mechanisms import load_mechanism
    from domes.motion.planar import checks

    outcome, said = run(casebase, MOTORCYCLE.replace("class: motorcycle rear suspension\n", "class: test suspension\n"))
    note = next(n for n in outcome.frame.notes if n.startswith("verified candidate 2"))
    mech = load_mechanism(knowledge_dir() / "mechanisms" / "suzuki-rm250x.json")
    r = checks.output_range(mech, "slide:g", math.radians(-10), math.radians(10))
    assert f"travel {r.travel:.6g}" in note
