"""The knowledge panel (issue 30, item 4): its routes against the case base read with the library, and the page.

The case base is the one the ``home`` fixture copies (``$DOMES_HOME/casebase.db``); every check reads it with
:class:`~domes.store.casebase.KnowledgeBase`, never through the routes.
"""

import json

import pytest

from domes.cli import main
from domes.knowledge.frames import CriterionFrame
from domes.language.parse import CriterionSyntaxError, parse_criterion, parse_relevance
from domes.store.casebase import KnowledgeBase

THREE_PINS = "every vertex must have degree at most 3"
#: Mistyped: the joint types' bracket is never closed (the parser's fault is at the end of the text).
MISTYPED = "every vertex must have type (G P R"


def stored(home):
    """The criteria (every field, in knowledge-base order) and the history of the case base, read by the library."""
    with KnowledgeBase(str(home / "casebase.db")) as kb:
        return [f.to_dict() for f in kb.frames()], [e.to_dict() for e in kb.history()]


def fault(text):
    """Where the library's parser finds the fault in ``text`` (0-based)."""
    with pytest.raises(CriterionSyntaxError) as caught:
        parse_criterion(text)
    return caught.value.position


def test_add_keeps_the_frame_the_library_makes_and_undo_takes_it_back(client, home):
    before = stored(home)
    r = client.post("/api/kb/add", json={"id": "three-pins", "text": THREE_PINS, "keywords": "pins, plates",
                                         "explanation": "no plates of four pins", "why": "a test"})
    assert r.status_code == 200, r.text
    frames, history = stored(home)
    assert [f["id"] for f in frames] == [f["id"] for f in before[0]] + ["three-pins"]
    expected = CriterionFrame.create("three-pins", THREE_PINS, "no plates of four pins", ["pins", "plates"]).to_dict()
    assert frames[-1] == expected
    assert r.json()["message"] == f"added three-pins: category ({expected['category']}), level {expected['level']}: " \
                                  f"{expected['reading']}"
    last = history[-1]
    assert (last["action"], last["target"], last["why"], last["session"]) == \
        ("add criterion", "three-pins", "a test", "domes studio kb add")
    assert [e["number"] for e in client.get("/api/kb/history").json()["history"]] == [e["number"] for e in history]

    r = client.post("/api/kb/undo", json={})
    assert r.status_code == 200 and r.json()["undone"][0]["target"] == "three-pins"
    assert stored(home) == before


def test_a_parse_error_names_its_column_and_a_refused_add_changes_nothing(client, home):
    text = "every  vertex must have type (G P R"              # two spaces: the column is in the text as typed
    r = client.post("/api/kb/parse", json={"text": text})
    assert r.status_code == 400
    answer = r.json()
    assert answer["position"] == fault(text) == len(text) and answer["column"] == fault(text) + 1
    assert answer["error"].startswith(f"column {fault(text) + 1}: expected a joint type letter")

    database = (home / "casebase.db").read_bytes()
    before = stored(home)
    r = client.post("/api/kb/add", json={"id": "typo", "text": text})
    assert r.status_code == 400
    assert (r.json()["field"], r.json()["position"]) == ("text", fault(text))
    assert r.json()["error"].startswith("text: column")
    r = client.post("/api/kb/add", json={"id": "book-i", "text": THREE_PINS})       # an id already there
    assert r.status_code == 400 and "already in the knowledge base" in r.json()["error"]
    r = client.post("/api/kb/edit", json={"id": "book-i", "relevance": "the problem has"})
    assert r.status_code == 400 and r.json()["field"] == "relevance"
    with pytest.raises(CriterionSyntaxError) as caught:
        parse_relevance("the problem has")
    assert r.json()["position"] == caught.value.position
    r = client.post("/api/kb/add", json={"id": "typo", "text": THREE_PINS, "disabled": "no"})
    assert r.status_code == 400 and r.json()["error"] == "disabled: expected true or false, got 'no'"
    r = client.post("/api/kb/remove", json={"id": "no-such"})
    assert r.status_code == 400 and "no criterion with id 'no-such'" in r.json()["error"]
    assert stored(home) == before
    assert (home / "casebase.db").read_bytes() == database


def test_parse_answers_what_the_command_line_prints(client, capsys):
    for body, argv in (({"text": THREE_PINS}, ["kb", "parse", THREE_PINS]),
                       ({"text": "the problem has “piston”", "relevance": True},
                        ["kb", "parse", "--relevance", "the problem has “piston”"])):
        assert main(argv) == 0
        assert client.post("/api/kb/parse", json=body).json() == json.loads(capsys.readouterr().out)


def test_edits_and_undo_from_an_entry(client, home):
    before = stored(home)
    assert client.post("/api/kb/disable", json={"id": "book-ii", "why": "one slider"}).status_code == 200
    assert client.post("/api/kb/edit", json={"id": "one-ground", "level": 3}).status_code == 200
    assert client.post("/api/kb/remove", json={"id": "book-iv"}).status_code == 200
    frames, history = stored(home)
    by_id = {f["id"]: f for f in frames}
    assert by_id["book-ii"]["enabled"] is False and by_id["one-ground"]["level"] == 3 and "book-iv" not in by_id
    assert [e["action"] for e in history[-3:]] == ["disable criterion", "edit criterion", "remove criterion"]
    listed = client.get("/api/kb/criteria").json()["criteria"]
    assert [(c["number"], c["id"], c["enabled"]) for c in listed] == [(n, f["id"], f["enabled"])
                                                                       for n, f in enumerate(frames, 1)]
    r = client.post("/api/kb/undo", json={"entry": history[-3]["number"]})
    assert [e["action"] for e in r.json()["undone"]] == ["remove criterion", "edit criterion", "disable criterion"]
    assert stored(home) == before
    assert client.post("/api/kb/undo", json={"entry": "x"}).status_code == 400


def test_scenes_and_cases_as_the_library_reads_them(client):
    from domes.io.scenes import load_scene, scene_names

    listed = client.get("/api/kb/scenes").json()["scenes"]
    assert [s["name"] for s in listed] == scene_names()
    scene = client.get("/api/kb/scenes", params={"name": "motorcycle"}).json()["scene"]
    read = load_scene("motorcycle")
    assert [s["name"] for s in scene["stages"]] == [s.name for s in read.stages]
    assert [[r["text"] for r in s["rules"]] for s in scene["stages"]] == [list(s.rule_text) for s in read.stages]
    assert [r["id"] for r in scene["requirements"]] == [r.id for r in read.requirements]
    assert client.get("/api/kb/scenes", params={"name": "nowhere"}).status_code == 400

    with KnowledgeBase() as kb:
        problems = kb.problems()
    cases = client.get("/api/kb/cases").json()["cases"]
    assert [c["id"] for c in cases] == [p.id for p in problems]
    one = client.get("/api/kb/cases", params={"id": problems[0].id}).json()
    assert one["case"] == problems[0].to_dict() and one["text"].startswith(f"case {problems[0].id} ")


# ---- the page ------------------------------------------------------------------------------------------------


def open_panel(page):
    page.click("#tabs button[data-panel=knowledge]")
    page.wait_for_selector("#kb-criteria tbody tr")


def test_page_marks_a_mistyped_criterion_and_add_changes_nothing(page, home):
    before = stored(home)
    open_panel(page)
    page.fill("#kb-id", "typo")
    page.type("#kb-text", MISTYPED, delay=5)
    page.wait_for_selector("#kb-text-parse .kb-fault")
    column = fault(MISTYPED) + 1
    assert f"column {column}:" in page.inner_text("#kb-text-parse .kb-parse-error")
    assert page.get_attribute("#kb-text-parse .kb-fault", "title") == f"column {column}"
    assert page.get_attribute("#kb-text", "aria-invalid") == "true"
    page.click("#kb-add")
    page.wait_for_selector("#kb-form-status.error")                     # the server's answer to Add
    assert page.inner_text("#kb-form-status").startswith(f"text: column {column}:")
    assert page.input_value("#kb-text") == MISTYPED                    # the input is kept
    assert stored(home) == before
    page.fill("#kb-text", THREE_PINS)                                   # fixed: the fault goes, the reading comes
    page.wait_for_selector("#kb-text-parse .kb-reading")
    assert page.get_attribute("#kb-text", "aria-invalid") is None


def test_page_adds_a_criterion_and_undo_restores_the_case_base(page, home):
    before = stored(home)
    open_panel(page)
    page.fill("#kb-id", "three-pins")
    page.fill("#kb-text", THREE_PINS)
    page.fill("#kb-why", "no plates of four pins")
    page.click("#kb-add")
    page.wait_for_selector("#kb-criteria tr[data-id='three-pins']")
    page.wait_for_selector("#kb-history li[data-entry]")
    frames, history = stored(home)
    assert [f["id"] for f in frames] == [f["id"] for f in before[0]] + ["three-pins"]
    assert history[-1]["why"] == "no plates of four pins"
    page.click("#kb-undo")
    page.wait_for_selector("#kb-no-history")
    assert page.query_selector("#kb-criteria tr[data-id='three-pins']") is None
    assert stored(home) == before
