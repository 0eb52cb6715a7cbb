"""Faults end with a clear message, never a wait without end or a traceback (issue 31, item 6).

Each case runs the command line as a subprocess under a hard deadline of
:data:`DEADLINE` seconds: a run still going then is the failure (the
deadline is the hang detector; no time is asserted otherwise). Each must
end with a one-line ``domes COMMAND: error: ...`` on stderr (or the right
answer), and no Python traceback anywhere:

- a scheduler address that accepts connections and never answers;
- the workers of a ``--workers 2`` run killed every half second (the run
  ends with the lost-worker message, or with the serial run's answer),
  and killed once (the run goes on to the serial run's answer);
- a ``**`` bomb in a task's function;
- a name that would lead a file out of its folder.
"""

import json
import os
import re
import shutil
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

psutil = pytest.importorskip("psutil")
pytest.importorskip("distributed")

ROOT = Path(__file__).resolve().parents[1]
DOMES = [sys.executable, "-m", "domes"]
#: Seconds a case may take before it counts as a hang.
DEADLINE = 60
#: The lost-worker deadline of the killed runs (the default, 60 s, is the whole of DEADLINE).
WORKER_TIMEOUT = "10"
FOUR_BAR = str(ROOT / "examples/mechanisms/four-bar.json")
TOLERANCE = ["tolerance", FOUR_BAR, "--output", "angle:rocker", "--tolerance", "0.001", "--samples", "1000000"]


def domes(args, env=None, **kw) -> subprocess.CompletedProcess:
    return subprocess.run(DOMES + list(args), capture_output=True, text=True, timeout=DEADLINE, cwd=ROOT,
                          env={**os.environ, **(env or {})}, **kw)


def assert_clear_error(proc, command: str, pattern: str = "") -> str:
    """The run failed with one line ``domes COMMAND: error: ...`` (matching ``pattern``) and no traceback."""
    assert "Traceback" not in proc.stderr + proc.stdout, proc.stderr[-3000:]
    assert proc.returncode == 2, (proc.returncode, proc.stderr[-3000:])
    errors = [line for line in proc.stderr.splitlines() if line.startswith(f"domes {command}: error: ")]
    assert len(errors) == 1, proc.stderr[-3000:]
    assert re.search(pattern, errors[0]), errors[0]
    return errors[0]


@pytest.fixture
def silent_scheduler():
    """``tcp://127.0.0.1:PORT`` of a socket that accepts connections and never says a word."""
    server = socket.create_server(("127.0.0.1", 0))
    server.settimeout(0.2)
    held, stop = [], threading.Event()

    def accept():
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
            except OSError:
                pass

    listener = threading.Thread(target=accept, daemon=True)
    listener.start()
    yield f"tcp://127.0.0.1:{server.getsockname()[1]}"
    stop.set()
    listener.join()
    server.close()
    for connection in held:
        connection.close()


def test_a_silent_scheduler_is_named(silent_scheduler):
    # --scheduler and DOMES_SCHEDULER, the two runs side by side (each waits 10 s for an answer, idle)
    runs = {"tolerance": (TOLERANCE + ["--scheduler", silent_scheduler], {}),
            "chains": (["chains", "--links", "8", "--dof", "1", "--count"], {"DOMES_SCHEDULER": silent_scheduler})}
    started = {command: subprocess.Popen(DOMES + args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                         cwd=ROOT, env={**os.environ, **env})
               for command, (args, env) in runs.items()}
    try:
        for command, run in started.items():
            out, err = run.communicate(timeout=DEADLINE)
            proc = subprocess.CompletedProcess(run.args, run.returncode, out, err)
            assert_clear_error(proc, command, f"cannot reach the Dask scheduler at '{silent_scheduler}' .*: it "
                                              "accepts connections but says nothing within 10 s")
    finally:
        for run in started.values():
            if run.poll() is None:
                run.kill()
                run.wait()


def _workers_of(process) -> list:
    """The worker processes of a local cluster the command started: its children but the resource tracker."""
    try:
        children = process.children(recursive=True)
    except psutil.Error:
        return []
    out = []
    for child in children:
        try:
            if "resource_tracker" not in " ".join(child.cmdline()):
                out.append(child)
        except psutil.Error:
            pass
    return out


def run_killing(args, tmp_path, every: float | None) -> tuple[subprocess.CompletedProcess, int]:
    """Run ``domes ARGS --progress``; from its first 'tasks done' line on, kill its workers every ``every`` seconds
    (None: once). Returns the run and how many processes were killed."""
    out, err = tmp_path / "stdout", tmp_path / "stderr"
    env = {**os.environ, "DOMES_WORKER_TIMEOUT": WORKER_TIMEOUT}
    with open(out, "w") as stdout, open(err, "w") as stderr:
        run = subprocess.Popen(DOMES + list(args) + ["--progress"], stdout=stdout, stderr=stderr, text=True,
                               cwd=ROOT, env=env)
        me = psutil.Process(run.pid)
        started, kills, killing = time.monotonic(), 0, False
        try:
            while run.poll() is None:
                if time.monotonic() - started > DEADLINE:
                    pytest.fail(f"domes {' '.join(args)} still runs after {DEADLINE} s ({kills} workers killed): "
                                f"{err.read_text()[-2000:]}")
                killing = killing or "tasks done" in err.read_text()
                if killing and (every is not None or not kills):
                    for worker in _workers_of(me):
                        try:
                            worker.kill()
                            kills += 1
                        except psutil.Error:
                            pass
                time.sleep(every or 0.1)
        finally:
            if run.poll() is None:
                run.kill()
            run.wait()
    return subprocess.CompletedProcess(run.args, run.returncode, out.read_text(), err.read_text()), kills


def test_workers_killed_every_half_second(tmp_path):
    # The workers never come back for long: the run ends with the lost-worker message once no worker has run for
    # DOMES_WORKER_TIMEOUT seconds, or (had the last batches finished first) with the serial run's numbers.
    proc, kills = run_killing(TOLERANCE + ["--workers", "2"], tmp_path, every=0.5)
    assert kills >= 2
    if proc.returncode == 0:
        assert "Traceback" not in proc.stderr
        assert proc.stdout == domes(TOLERANCE).stdout
    else:
        assert_clear_error(proc, "tolerance", r"lost the workers of a local Dask cluster of 2 workers: .*; "
                                              r"\d+ of 50 tasks done\. Run the command again")


def test_workers_killed_once_the_run_goes_on(tmp_path, tmp_path_factory):
    # Both workers die while the 12-link atlas's first large level is half done: the data the slices share died
    # with them, and is sent again to the new workers; the atlas is the one built in one process (built once in a
    # run for the tests that read it: tests/typesynth/reference.py).
    from tests.typesynth.reference import chain_atlas

    proc, kills = run_killing(["chains", "--links", "12", "--dof", "1", "--format", "graph6", "--workers", "2"],
                              tmp_path, every=None)
    assert kills == 2
    assert proc.returncode == 0 and "Traceback" not in proc.stderr, proc.stderr[-3000:]
    assert proc.stdout.split() == chain_atlas(tmp_path_factory, 12, 1)


BOMBS = ["0*9**9**9", "2**2**2**2**2", "(9**9)**(9**9)"]


@pytest.mark.parametrize("bomb", BOMBS)
@pytest.mark.parametrize("task", ["log10", "rising-rate"])
def test_a_power_bomb_in_a_task_function_is_refused(tmp_path, task, bomb):
    # Arithmetic is in floats: the powers overflow to inf at once, and the task says where its function is not
    # defined (as integers, 9**9**9 would run for hours and 2**2**2**2**2 is a 19,729-digit number).
    data = json.loads((ROOT / f"examples/synthesis/{task}.json").read_text())
    if task == "log10":
        data["function"] = f"log10(x) + {bomb}" if bomb.startswith("0*") else bomb
    else:
        data["wanted"]["function"] = f"3.1 - 2.8*x + {bomb}" if bomb.startswith("0*") else bomb
    path = tmp_path / "task.json"
    path.write_text(json.dumps(data))
    assert_clear_error(domes(["synthesize", str(path)]), "synthesize",
                       r"the (function|wanted curve) is (not defined|undefined) at x = ")


@pytest.mark.parametrize("name", ["../../x", "a/../../x", "..", "/tmp/x", "x/y"])
def test_a_case_name_may_not_leave_its_folder(tmp_path, name):
    # `domes cases record --name NAME` writes knowledge/cases/NAME.json: the only command that makes a file's
    # name from a user's name (the others take a path, or look a name up in a folder without writing). It runs
    # on a copy of the knowledge folder two levels down, so that '../../x.json' would land in tmp_path.
    knowledge = tmp_path / "a" / "b" / "knowledge"
    shutil.copytree(ROOT / "knowledge", knowledge)
    before = sorted(p for p in tmp_path.rglob("*"))
    proc = domes(["cases", "record", "examples/design/pump.answers", "--name", name],
                 env={"DOMES_KNOWLEDGE": str(knowledge), "DOMES_HOME": str(tmp_path / "home")})
    assert_clear_error(proc, "cases", rf"--name '{name}': a case's name is letters, digits.*may not leave that folder")
    assert sorted(p for p in tmp_path.rglob("*")) == before
