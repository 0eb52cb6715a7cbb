"""`domes design` on a real terminal (pexpect): typed answers, the candidates read from the screen."""

import shutil
import signal
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]  # the checkout

pexpect = pytest.importorskip("pexpect")

ANSWERS = [
    ("Problem class", "motorcycle rear suspension"),
    ("Number of output motions", ""),  # the default, 1
    ("Degrees of freedom", "1"),
    ("Mechanism type", "planar"),
    ("Independent loops", "two"),  # refused: asked again with the reason
    ("Independent loops", "2"),
    ("Gear pairs", "0"),
    ("Slider", "1"),
    ("Representative attributes", "ground, swing arm, shock absorber"),
    ("Scene", ""),  # the proposed default: motorcycle
    ("Override relevance", "-book-ii"),
    ("Specify additional screening criteria", "no"),
]


def spawn(casebase, *extra, cwd):
    # SIGINT back to its default in the child (a runner started in the background has it ignored, and
    # Ctrl-C would then never reach the session); a generous timeout for a loaded machine
    return pexpect.spawn(
        sys.executable, ["-m", "domes", "design", "--db", casebase, *extra],
        cwd=str(cwd), encoding="utf-8", timeout=180, dimensions=(50, 200),
        preexec_fn=lambda: signal.signal(signal.SIGINT, signal.SIG_DFL),
    )


def empty_casebase(tmp_path):
    # the shipped criteria, no solved problems: the motorcycle problem is new
    target = tmp_path / "casebase.db"
    shutil.copyfile(ROOT / "casebase.db", target)
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(str(target)) as kb:
        for p in kb.problems():
            kb.remove_problem(p.id)
    return str(target)


def test_design_on_a_terminal(tmp_path):
    child = spawn(empty_casebase(tmp_path), cwd=tmp_path)
    for prompt, answer in ANSWERS:
        child.expect(prompt)
        child.sendline(answer)
        if answer == "two":
            child.expect("not accepted: expected a whole number")
    child.expect("6 of 6 candidates kept")
    child.expect(r"Verify dimensions")
    screen = child.before
    child.sendline("none")
    child.expect(r"Is the result satisfactory")
    candidates = [line for line in screen.splitlines() if line.strip().startswith("candidate ")]
    assert len(candidates) == 6
    assert sum("EXISTING" in line for line in candidates) == 1
    assert all("swing_arm" in line and "shock_absorber" in line and "ground" in line for line in candidates)
    child.sendline("yes")
    child.expect("Retained as case motorcycle-rear-suspension-1")
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 0


def test_interrupt_and_resume(tmp_path):
    casebase = empty_casebase(tmp_path)
    child = spawn(casebase, cwd=tmp_path)
    for prompt, answer in ANSWERS[:5]:
        child.expect(prompt)
        child.sendline(answer)
    child.expect("Independent loops")
    child.sendintr()  # Ctrl-C at the question about loops
    child.expect("interrupted")
    child.expect(pexpect.EOF)
    child.close()
    assert child.exitstatus == 130 and child.signalstatus is None  # 128 + SIGINT: caught, saved, reported
    state = tmp_path / ".domes-design-session.json"
    assert state.is_file()
    child = spawn(casebase, "--resume", str(state), cwd=tmp_path)
    child.expect("Resuming")
    for prompt, answer in ANSWERS[5:]:
        child.expect(prompt)
        child.sendline(answer)
    child.expect("6 of 6 candidates kept")
    child.expect("Verify dimensions")
    child.sendline("")
    child.expect("Is the result satisfactory")
    child.sendline("yes")
    child.expect("Retained as case")
    child.expect(pexpect.EOF)
