"""The design panel: the dialogue driven through the routes, compared with :class:`Dialogue` run directly; a bad
answer, a cancel, a replay; and a whole new problem answered in the page, from the first question to the report."""

from __future__ import annotations

import tempfile
import threading
import time
from pathlib import Path

import pytest

from domes.errors import InputError
from domes.expert.dialogue import Dialogue
from domes.expert.feasible import DesignKnobs
from domes.expert.questions import STATIC
from domes.expert.replay import frame_differences, scratch_casebase
from domes.io.transcripts import load_session, load_transcript, read_answers
from domes.sketch.report import funnel
from domes.store.casebase import KnowledgeBase
from tests.expert.shared_designs import designs_once_fixture  # noqa: F401 (a fixture)

EXAMPLES = Path(__file__).resolve().parents[2] / "examples" / "design"
ENDED = ("done", "failed", "cancelled")


def events(client, sid: str, since: int = 0) -> dict:
    r = client.get("/api/design/events", params={"session": sid, "since": since})
    assert r.status_code == 200, r.text
    return r.json()


def wait(client, sid: str, until, since: int = 0, limit: float = 120.0) -> tuple[dict, list]:
    """Poll the session until ``until(view, lines)``; the last view and every event seen."""
    seen, stop = [], time.monotonic() + limit
    while True:
        view = events(client, sid, since)
        seen += view["events"]
        since = view["next"]
        if until(view, seen) or view["status"] in ENDED:
            return view, seen
        assert time.monotonic() < stop, f"the session did not get there: {seen[-5:]}"
        time.sleep(0.05)


def drive(client, sid: str, script: list[tuple[str, str]]) -> tuple[dict, list, int]:
    """Answer every question the page would be asked with the script's answer for it, in order; a question the
    script leaves out gets the empty answer (its default). The end view, the events, the answers used."""
    used, since, seen = 0, 0, []
    while True:
        view, got = wait(client, sid, lambda v, _: v["status"] == "asking", since)
        seen += got
        since = view["next"]
        if view["status"] in ENDED:
            return view, seen, used
        q = view["question"]
        text = ""
        if used < len(script) and script[used][0] == q["id"]:
            text, used = script[used][1], used + 1
        r = client.post("/api/design/answer", json={"session": sid, "text": text})
        assert r.status_code == 200, r.text


def casebase_state() -> tuple:
    """What a session could change in the user's case base: its problems, criteria and history."""
    with KnowledgeBase(None) as kb:
        return ([p.to_dict() for p in kb.problems()], sorted(c.id for c in kb.frames()), len(kb.history()))


@pytest.mark.usefixtures("designs_once")
def test_quickstart_through_the_routes_ends_as_the_dialogue_run_directly(client, home):
    # the routes' session runs in a process of its own; the one run directly here takes its feasibility level as
    # computed once per test run for these inputs (tests/expert/shared_designs.py)
    script = read_answers(EXAMPLES / "quickstart.answers")
    before = casebase_state()
    direct = {}

    def run_directly():  # the same answers, the library's dialogue, the same case base (while the worker runs)
        with tempfile.TemporaryDirectory() as tmp:
            direct["outcome"] = Dialogue(scratch_casebase(None, None, Path(tmp)), script, interactive=False,
                                         out=lambda text: None, knobs=DesignKnobs(report=None)).run()

    beside = threading.Thread(target=run_directly)
    beside.start()
    start = client.post("/api/design/start", json={})
    assert start.status_code == 200, start.text
    sid = start.json()["session"]
    assert start.json()["dry_run"] is True
    view, seen, used = drive(client, sid, script)
    assert view["status"] == "done", view["error"]
    assert used == len(script)
    assert any(e["kind"] == "line" and e["text"].startswith("Dimensioning and verifying") for e in seen)
    beside.join()
    assert "outcome" in direct, "the dialogue run directly stopped (its exception is shown above)"
    direct = direct["outcome"]
    recorded = load_transcript(home / "sessions" / f"{sid}.json")  # written as `domes design --record` does
    assert (recorded["relation"], recorded["case"]) == (direct.relation, direct.case)
    assert frame_differences(direct.frame.to_dict(), recorded["frame"]) == []
    assert [(e["question"], e["answer"]) for e in recorded["exchanges"]] == \
        [(e["question"], e["answer"]) for e in direct.exchanges]
    assert view["outcome"]["retained"] == direct.frame.id
    assert view["outcome"]["feasible"] == sum(d.get("status") == "feasible" for d in direct.frame.designs)

    rows = [(r["stage"], r["count"]) for r in view["funnel"]["rows"]]
    assert rows == [(r.stage, r.count) for r in funnel(direct.frame)]
    assert [(r["candidate"], r["criterion"]) for r in view["funnel"]["rejected"]] == \
        [(r["candidate"], r["criterion"]) for r in direct.frame.rejected]

    page = client.get(f"/api/design/report/{sid}/{view['outcome']['report']}")
    assert page.status_code == 200 and page.headers["content-type"].startswith("text/html")
    assert f"case {direct.frame.id}" in page.text
    atlas = client.get(f"/api/design/report/{sid}/{view['funnel']['atlas']}")
    assert atlas.text.count('data-id="') == view["funnel"]["generated"]
    assert client.get(f"/api/design/report/{sid}/..%2F..%2Fcasebase.db").status_code == 403
    assert casebase_state() == before  # a dry run


def test_a_bad_answer_is_rejected_with_the_reason_and_asked_again(client):
    sid = client.post("/api/design/start", json={}).json()["session"]
    script = [("class", "garden gate latch"), ("function", "none"), ("outputs", "1")]
    since = 0
    for question, text in script:
        view, seen = wait(client, sid, lambda v, _: v["status"] == "asking", since)
        since = view["next"]
        assert view["question"]["id"] == question
        client.post("/api/design/answer", json={"session": sid, "text": text})
    view, seen = wait(client, sid, lambda v, _: v["status"] == "asking", since)
    assert view["question"]["id"] == "dof" and view["question"]["default"] == STATIC["dof"].default
    with pytest.raises(InputError) as why:
        STATIC["dof"].parse("nine")
    r = client.post("/api/design/answer", json={"session": sid, "text": "nine"})
    assert r.status_code == 200
    view, seen = wait(client, sid, lambda v, _: v["status"] == "asking", view["next"])
    assert view["question"]["id"] == "dof"  # asked again
    assert view["question"]["rejected"] == str(why.value)
    assert {"kind": "line", "text": f"  not accepted: {why.value}"} in seen
    client.post("/api/design/answer", json={"session": sid, "text": "1"})
    view, _ = wait(client, sid, lambda v, _: v["status"] == "asking", view["next"])
    assert view["question"]["id"] == "space" and view["question"]["rejected"] is None
    wrong = client.post("/api/design/answer", json={"session": sid, "text": 3})
    assert wrong.status_code == 400 and "'text'" in wrong.json()["error"]
    assert client.post("/api/design/cancel", json={"session": sid}).json()["status"] == "cancelled"
    again = client.post("/api/design/answer", json={"session": sid, "text": "planar"})
    assert again.status_code == 400 and "cancelled" in again.json()["error"]


def test_cancel_kills_a_long_stage_and_leaves_the_case_base(client, studio, home):
    (home / "rising.answers").write_text((EXAMPLES / "motorcycle-rising-rate.answers").read_text())
    before = casebase_state()
    r = client.post("/api/design/start", json={"dry_run": False, "answers": "rising.answers"})
    assert r.status_code == 200, r.text
    sid = r.json()["session"]
    dimensioning = lambda v, seen: any(e["text"].startswith("Dimensioning") for e in seen if e["kind"] == "line")  # noqa: E731
    view, _ = wait(client, sid, dimensioning)
    assert view["status"] == "running"
    process = studio.state["design"][sid].process
    assert process.is_alive()
    view = client.post("/api/design/cancel", json={"session": sid}).json()
    assert view["status"] == "cancelled" and not view["alive"]
    assert not process.is_alive() and process.exitcode < 0  # killed, not finished
    assert casebase_state() == before  # the long stage's result never reached it
    saved = load_session(home / "sessions" / f"{sid}.interrupted.json")
    given = read_answers(home / "rising.answers")  # every answer up to the design run, and the defaults taken
    upto = [q for q, _ in given].index("more_criteria") + 1
    assert [a for a in saved if a in given] == given[:upto]
    assert {q for q, _ in saved} - {q for q, _ in given} == {"function"} and ("function", "none") in saved
    assert not (home / "sessions" / f"{sid}.json").exists()
    assert client.post("/api/design/cancel", json={"session": sid}).status_code == 400


def test_a_recorded_session_replays_without_a_question(client, home):
    (home / "same.answers").write_text("class: robot gripper\nrelation: same robot-gripper-1\n")
    first = client.post("/api/design/start", json={"answers": "same.answers"}).json()["session"]
    view, _ = wait(client, first, lambda v, _: False)
    assert view["status"] == "done" and view["outcome"]["relation"] == "same"
    listed = client.get("/api/design/sessions").json()["sessions"]
    names = {s["name"]: s["kind"] for s in listed}
    assert names[f"sessions/{first}.json"] == "transcript" and names["same.answers"] == "answers"
    assert names["case:pump"] == "case"
    again = client.post("/api/design/start", json={"answers": f"sessions/{first}.json"}).json()["session"]
    view, _ = wait(client, again, lambda v, _: False)
    assert view["status"] == "done" and view["outcome"]["case"] == "robot-gripper-1"
    one, two = (load_transcript(home / "sessions" / f"{s}.json") for s in (first, again))
    assert one["exchanges"] == two["exchanges"] and one["frame"] == two["frame"]
    bad = client.post("/api/design/start", json={"answers": "../outside.answers"})
    assert bad.status_code == 403
    assert client.post("/api/design/start", json={"dry_run": "yes"}).status_code == 400
    assert client.get("/api/design/events", params={"session": "nope"}).status_code == 404


#: A problem the case base has not met: a one-loop slider mechanism for a garden gate's latch (no scene).
NEW_PROBLEM = [("class", "garden gate latch"), ("function", None), ("outputs", None), ("dof", None), ("space", None),
               ("loops", "1"), ("gear_pairs", None), ("slider_pairs", "1"), ("names", None), ("scene", None),
               ("relevance_overrides", None), ("more_criteria", None), ("verify", None), ("satisfied", None)]


def test_a_new_problem_answered_in_the_page_ends_with_its_report(page, home):
    page.click("#panel-design .design-start")
    ask = "#panel-design .design-ask"
    for number, (question, text) in enumerate(NEW_PROBLEM):
        page.wait_for_function(f"() => {{ const f = document.querySelector('{ask}'); "
                               f"return f && !f.hidden && f.dataset.question === '{question}'; }}", timeout=60_000)
        box = page.locator("#panel-design .design-answer")
        if question in STATIC and STATIC[question].default is not None:
            assert box.input_value() == STATIC[question].default  # the default, filled in
        if question == "loops":
            page.click("#panel-design .design-help-button")
            assert page.locator("#panel-design .design-help").inner_text().strip() == STATIC["loops"].help.strip()
            box.fill("many")
            page.click("#panel-design .design-send")
            with pytest.raises(InputError) as why:
                STATIC["loops"].parse("many")
            page.wait_for_function("() => !document.querySelector('#panel-design .design-rejected').hidden",
                                   timeout=30_000)
            assert page.locator("#panel-design .design-rejected").inner_text() == f"not accepted: {why.value}"
            assert page.locator(ask).get_attribute("data-question") == "loops"
        if text is not None:
            box.fill(text)
        page.click("#panel-design .design-send")
    page.wait_for_function("() => document.querySelector('#panel-design').dataset.status === 'done'", timeout=60_000)
    page.wait_for_function("() => { const b = document.querySelector('#panel-design .design-report-body'); "
                           "return b.shadowRoot && b.shadowRoot.querySelector('h1'); }", timeout=30_000)
    sid = page.locator("#panel-design").get_attribute("data-session")
    frame = load_transcript(home / "sessions" / f"{sid}.json")["frame"]
    heading = page.evaluate("() => document.querySelector('#panel-design .design-report-body')"
                            ".shadowRoot.querySelector('h1').textContent")
    assert heading == "Design report: garden gate latch"
    assert page.locator("#panel-design .design-report-link").get_attribute("href") == \
        f"/api/design/report/{sid}/index.html"
    kept = page.locator("#panel-design .design-kept").inner_text()
    assert kept == "kept: candidate " + ", ".join(str(c["id"]) for c in frame["results"])
    assert (home / "reports" / sid / "index.html").is_file()
    page.click("#panel-design .design-atlas-box summary")  # the candidates, sketched by the library
    cards = page.evaluate("() => { const b = document.querySelector('#panel-design .design-atlas'); "
                          "return b.shadowRoot ? b.shadowRoot.querySelectorAll('.card').length : -1; }")
    assert cards == len(frame["results"]) + len(frame["rejected"]) > 0
