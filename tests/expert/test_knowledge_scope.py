"""Knowledge that stays where it belongs: scoped designer criteria, the history of the case base and undo,
replays that list every difference.

The leakage sequence of the design-loop issue: a criterion added in a pump session (seed 002, §7-1) used to
apply to every later problem, so that a motorcycle session (§4-1) kept none of its six candidates.
"""

from pathlib import Path

import pytest

from domes.cli import main
from domes.expert.dialogue import Dialogue
from domes.expert.replay import replay, shipped_cases
from domes.io.resources import knowledge_dir
from domes.io.transcripts import load_transcript
from domes.language.tree import Always, AnyOf, ClassIs, HasName
from domes.store.casebase import KnowledgeBase
from tests.postgres import contents


def answers(name):
    """The answers of a shipped case's recorded session."""
    data = load_transcript(knowledge_dir() / "cases" / f"{name}.json")
    return [(e["question"], e["answer"]) for e in data["exchanges"]]


def recorded(name):
    return load_transcript(knowledge_dir() / "cases" / f"{name}.json")["frame"]


def session(url, script):
    messages = []
    outcome = Dialogue(url, script, interactive=False, out=messages.append).run()
    return outcome, "\n".join(messages)



@pytest.fixture
def without_shipped_cases(casebase):
    """The shipped case base without its cases: every shipped session then meets a new class, as recorded."""
    with KnowledgeBase(casebase) as kb:
        for p in kb.problems():
            kb.remove_problem(p.id)
    return casebase


def test_a_pump_criterion_does_not_change_the_motorcycle(without_shipped_cases):
    pump, _ = session(without_shipped_cases, answers("pump"))
    with KnowledgeBase(without_shipped_cases) as kb:
        added = [kb.get(c) for c in pump.frame.criteria_added]
    assert added and all(c.relevance == ClassIs("double_acting_pump") for c in added)
    moto, said = session(without_shipped_cases, answers("motorcycle"))
    assert moto.relation == "different" and "Designing" in said
    assert [c["id"] for c in moto.frame.results] == [c["id"] for c in recorded("motorcycle")["results"]]
    assert len(moto.frame.results) == 6
    assert not set(pump.frame.criteria_added) & set(moto.frame.relevance.relevant_ids())


@pytest.mark.parametrize("order", ["sorted", "reversed", "pump first"])
def test_every_shipped_case_replays_after_any_sequence_of_the_shipped_sessions(without_shipped_cases, order):
    names = shipped_cases()
    names = {"sorted": names, "reversed": names[::-1],
             "pump first": ["pump"] + [n for n in names if n != "pump"]}[order]
    for name in names:
        session(without_shipped_cases, answers(name))
    for name in shipped_cases():
        result = replay(name, without_shipped_cases)
        assert result.differences == [], name


def test_undo_restores_the_case_base_after_a_session(without_shipped_cases):
    casebase = without_shipped_cases
    before = contents(casebase)
    outcome, _ = session(casebase, answers("pump"))
    with KnowledgeBase(casebase) as kb:
        entries = kb.history()[len(before["history"]):]
        assert [e.action for e in entries] == ["add criterion"] * 3 + ["retain case"]
        assert {e.session for e in entries} == {entries[0].session} and entries[0].session.startswith("design session")
        assert entries[-1].target == outcome.frame.id and entries[-1].why
        undone = kb.undo(entries[0].number)
    assert [e.number for e in undone] == [e.number for e in reversed(entries)]
    assert contents(casebase) == before  # every row of every table, the history included


def test_undo_one_entry_at_a_time_and_history_on_the_command_line(casebase, capsys):
    db = casebase
    before = contents(db)
    assert main(["kb", "add", "--db", db, "--id", "deg3", "--text", "every vertex must have degree at most 3",
                 "--why", "no quaternary links in this shop"]) == 0
    mid = contents(db)
    assert main(["kb", "edit", "--db", db, "--id", "deg3", "--text", "every vertex must have degree at most 2"]) == 0
    capsys.readouterr()
    assert main(["kb", "history", "--db", db]) == 0
    out = capsys.readouterr().out
    assert "domes kb add: add criterion deg3  (why: no quaternary links in this shop)" in out
    assert "criterion deg3 changed" in out
    assert main(["kb", "undo", "--db", db]) == 0
    assert contents(db) == mid
    assert main(["kb", "undo", "--db", db]) == 0
    assert contents(db) == before
    capsys.readouterr()
    assert main(["kb", "undo", "--db", db]) == 2
    assert "nothing to undo" in capsys.readouterr().err


def test_the_scope_is_shown_and_may_be_changed(without_shipped_cases):
    casebase = without_shipped_cases
    script = answers("pump")
    k = next(i for i, (q, _) in enumerate(script) if q == "criterion")
    # the first added criterion: a bad condition is refused with the column, then 'the problem has “piston”'
    script[k + 1:k + 1] = [("criterion_scope", "the problem has"),
                           ("criterion_scope", "the problem has “piston”")]
    outcome, said = session(casebase, script)
    assert "Relevant to which problems? class (the problem class is “double acting pump”)" in said
    assert "not accepted: " in said and "column" in said
    with KnowledgeBase(casebase) as kb:
        first, *rest = (kb.get(c) for c in outcome.frame.criteria_added)
    assert first.relevance == HasName("piston")
    assert all(c.relevance == ClassIs("double_acting_pump") for c in rest)  # the script's default


def test_the_same_sentence_in_another_class_widens_its_scope(casebase):
    text = "every vertex must have degree at most 3"
    first = [("class", "crusher"), ("outputs", "1"), ("dof", "1"), ("space", "planar"), ("loops", "2"),
             ("gear_pairs", "0"), ("slider_pairs", "0"), ("names", "none"), ("scene", "none"),
             ("relevance_overrides", "none"), ("more_criteria", "yes"), ("criterion", text),
             ("criterion_scope", "class"), ("more_criteria", "no"), ("verify", "none"), ("satisfied", "yes")]
    one, _ = session(casebase, first)
    second = [(q, "stamping press" if q == "class" else a) for q, a in first]
    two, said = session(casebase, second)
    assert one.frame.criteria_added == two.frame.criteria_added
    with KnowledgeBase(casebase) as kb:
        frame = kb.get(one.frame.criteria_added[0])
        assert frame.relevance == AnyOf((ClassIs("crusher"), ClassIs("stamping_press")))
        assert kb.history()[-2].action == "widen relevance"
    assert "its relevance is widened" in said
    third = [(q, "always" if q == "criterion_scope" else ("press" if q == "class" else a)) for q, a in first]
    session(casebase, third)
    with KnowledgeBase(casebase) as kb:
        assert kb.get(one.frame.criteria_added[0]).relevance == AnyOf(
            (AnyOf((ClassIs("crusher"), ClassIs("stamping_press"))), Always()))


def test_replay_all_lists_every_difference_and_exits_1(casebase, capsys):
    # a criterion relevant to every problem changes every case (its relevance vector): each is listed
    assert main(["kb", "add", "--db", casebase, "--id", "six", "--text", "every vertex must have degree at most 6"]) == 0
    capsys.readouterr()
    assert main(["cases", "--db", casebase, "replay", "--all"]) == 1
    out = capsys.readouterr().out
    lines = [line for line in out.splitlines() if not line.startswith("  ")]
    assert [line.split(":")[0] for line in lines[:-1]] == shipped_cases()
    assert sum("DIFFERENT" in line for line in lines) == len(shipped_cases())
    assert lines[-1].endswith(f"of {len(shipped_cases())} case(s) differ")


def _kb_add(item):
    """``domes kb add`` in a process of its own: its exit status."""
    url, k = item
    return main(["kb", "add", "--db", url, "--id", f"c{k}", "--text", "every vertex must have degree at most 4",
                 "--why", f"writer {k}"])


def test_concurrent_writers_queue_instead_of_colliding(casebase):
    # issue 25, item 19: 5 of 50 concurrent pairs of `kb add` failed on the criterion number; numbers are
    # allocated inside the transaction, which waits for the other writer (SQLite BEGIN IMMEDIATE) or retries
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(2) as pool:                     # 40 pairs: two writers at a time
        assert list(pool.map(_kb_add, [(casebase, k) for k in range(80)])) == [0] * 80
    with KnowledgeBase(casebase) as kb:
        ids = [f.id for f in kb.frames()]
        entries = kb.history()
    assert {f"c{k}" for k in range(80)} <= set(ids)  # every addition kept, each in the order of the base
    assert sorted(e.target for e in entries) == sorted(f"c{k}" for k in range(80))


def _one_session(item):
    """A small problem designed and retained (a process of its own); ``k`` makes it differ from the others."""
    url, k = item
    script = [("class", "crank slider"), ("outputs", "1"), ("dof", "1"), ("space", "planar"), ("loops", "1"),
              ("gear_pairs", "0"), ("slider_pairs", "1"), ("names", f"part {k}"), ("scene", "none"),
              ("relevance_overrides", "none"), ("more_criteria", "no"), ("verify", "none"), ("satisfied", "yes")]
    outcome = Dialogue(url, script, interactive=False, out=lambda text: None).run()
    return outcome.frame.id


def test_design_sessions_at_the_same_time_each_keep_their_case(without_shipped_cases):
    # issue 25, item 19: sessions finishing together used to collide on the case id CLASS-N
    from concurrent.futures import ProcessPoolExecutor

    with ProcessPoolExecutor(4) as pool:
        ids = list(pool.map(_one_session, [(without_shipped_cases, k) for k in range(40)]))
    assert sorted(ids, key=lambda i: int(i.rsplit("-", 1)[1])) == [f"crank-slider-{k}" for k in range(1, 41)]
    with KnowledgeBase(without_shipped_cases) as kb:
        assert len([p for p in kb.problems() if p.problem_class == "crank_slider"]) == 40


@pytest.mark.parametrize("name", ["../../x", "..", "a/b", "/tmp/x", ".hidden/../../y"])
def test_a_recorded_case_name_never_leaves_the_cases_folder(casebase, capsys, name):
    # issue 31, item 7: `domes cases record ANSWERS --name ../../x` wrote outside the cases folder.
    root = Path(__file__).resolve().parents[2]
    before = set(root.rglob("*.json"))
    answers = str(root / "examples" / "design" / "gripper.answers")
    status = main(["cases", "--db", casebase, "record", answers, "--name", name])
    assert status == 2 and "a case's name is letters, digits" in capsys.readouterr().err
    assert set(root.rglob("*.json")) == before
