"""Parallel runs on Dask give the in-process results, byte for byte (issue 17).

A two-worker LocalCluster (worker processes on this machine) builds the 10-
bar and the 11-link DOF-2 atlases, regenerates the 8-link motorcycle scene,
dimensions candidates of a scene and builds a small coupler-curve atlas; each
is compared with the in-process run. The command
line takes --workers and --scheduler (or DOMES_SCHEDULER) and prints the
same.
"""

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from domes.errors import InputError
from domes.execution import InProcess, executor
from domes.io.scenes import load_scene
from domes.motion.coupler.atlas import AtlasSpec, build
from domes.typesynth.atlas import chains
from domes.typesynth.regenerate import regenerate

pytest.importorskip("distributed")

DOMES = [sys.executable, "-m", "domes"]
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def cluster():
    with executor(workers=2) as run:
        yield run


@pytest.mark.parametrize("links, dof", [(10, 1), (11, 2)])
def test_chain_atlas_is_the_same_on_two_workers(cluster, monkeypatch, links, dof):
    # Levels of 16 parents and more go to the workers (the product sends those of 256 and more, first met at 12
    # links): each level of these two atlases' ears is cut into slices, as the 12-link atlas's large ones are.
    monkeypatch.setattr("domes.typesynth.atlas.PARALLEL_PARENTS", 16)
    sent = []
    run = cluster._run
    monkeypatch.setattr(cluster, "_run", lambda fn, items, progress: sent.append(fn) or run(fn, items, progress))
    here = chains(links, dof)
    there = chains(links, dof, executor=cluster)
    assert sent                                                      # the workers built part of it
    assert there.chains == here.chains
    assert [c.graph6 for c in there] == [c.graph6 for c in here]


def test_regeneration_is_the_same_on_two_workers(cluster):
    # The 8-link motorcycle scene (seed 002 §4-1's eight-bar variant): every chain a task, stages merged in order.
    scene = load_scene("motorcycle-8bar")
    here, there = regenerate(scene), regenerate(scene, executor=cluster)
    assert there.to_dict() == here.to_dict()
    assert [s.count for s in there.stages] == [s.count for s in here.stages]


def test_coupler_atlas_is_the_same_on_two_workers(cluster):
    spec = AtlasSpec("test", 40, 1.0)
    here, there = build(spec), build(spec, executor=cluster)
    assert here.count == there.count > 0
    for name in ("linkages", "link", "point", "circuit", "features"):
        assert np.array_equal(getattr(here, name), getattr(there, name)), name


def test_the_command_line_on_workers_and_on_a_scheduler(tmp_path):
    # --workers 2 starts (and stops) a local cluster; DOMES_SCHEDULER points the same command at a running one.
    from distributed import LocalCluster

    alone = subprocess.run(DOMES + ["chains", "--links", "10", "--dof", "1", "--format", "graph6"],
                           capture_output=True, text=True, check=True, cwd=ROOT).stdout
    two = subprocess.run(DOMES + ["chains", "--links", "10", "--dof", "1", "--format", "graph6", "--workers", "2"],
                         capture_output=True, text=True, check=True, cwd=ROOT).stdout
    assert two == alone and len(alone.split()) == 230
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=":0") as running:
        env = {**os.environ, "DOMES_SCHEDULER": running.scheduler_address}
        there = subprocess.run(DOMES + ["chains", "--links", "10", "--dof", "1", "--format", "graph6"],
                               capture_output=True, text=True, check=True, cwd=ROOT, env=env).stdout
    assert there == alone


def test_the_default_runs_here_and_bad_knobs_are_refused():
    with executor() as run:
        assert isinstance(run, InProcess) and run.map(len, ["ab", "c"]) == [2, 1]
    with pytest.raises(InputError, match="at least 1"):
        with executor(workers=0):
            pass
    with pytest.raises(InputError, match="cannot reach the Dask scheduler at 'nonsense'"):
        with executor(scheduler="nonsense"):
            pass


@pytest.mark.parametrize("answer, message", [(b"", "says nothing within 1 s"),
                                             (b"\xff" * 64 + b"HTTP/1.1 200 OK\r\n\r\n", "")], ids=["silent", "junk"])
def test_a_scheduler_that_never_answers_or_answers_junk_is_named(monkeypatch, capfd, answer, message):
    # issue 31, items 6 and 8: an address that accepts and never answers left a run waiting for ever; one that
    # answers junk ended in "Unable to allocate 3.07 EiB".
    import socket
    import threading

    import domes.execution

    monkeypatch.setattr(domes.execution, "SCHEDULER_TIMEOUT", 1)
    server = socket.create_server(("127.0.0.1", 0))
    held = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                held.append(server.accept()[0])
                held[-1].sendall(answer)
            except OSError:
                pass

    listener = threading.Thread(target=accept, daemon=True)
    listener.start()
    address = f"tcp://127.0.0.1:{server.getsockname()[1]}"
    try:
        with pytest.raises(InputError, match=f"cannot reach the Dask scheduler at '{address}'.*{message}"):
            with executor(scheduler=address):
                pass
    finally:
        stop.set()
        listener.join()
        server.close()
        for c in held:
            c.close()
    err = capfd.readouterr().err
    assert "Traceback" not in err and "WARNING" not in err


def test_seeded_monte_carlo_is_the_same_on_two_workers(cluster):
    # Tolerance sampling by seeded batches (one SeedSequence child per batch), merged in batch order.
    from domes.design.tolerance import Tolerancing, monte_carlo
    from domes.io.mechanisms import load_mechanism

    tol = Tolerancing(load_mechanism(ROOT / "examples/mechanisms/slider-crank.json"), "point:M",
                      np.radians(np.arange(0.0, 360.0, 15.0)), relative=1e-3)
    here = monte_carlo(tol, samples=60_000, seed=11, batch_size=7_000)
    there = monte_carlo(tol, samples=60_000, seed=11, batch_size=7_000, executor=cluster)
    assert here.batches == there.batches == 9
    for name in ("mean", "std", "largest"):
        assert np.array_equal(getattr(here, name), getattr(there, name)), name


def test_scene_candidates_are_dimensioned_the_same_on_two_workers(cluster):
    # Batch verification of a scene's candidates: the rising-rate suspension task (issue 13) over three of the six
    # candidates of the motorcycle scene (more tasks than workers), each candidate a task with its own child of the
    # seed.
    import dataclasses

    from domes.design.synthesis import synthesize
    from domes.io.tasks import load_task

    task = load_task(ROOT / "examples/synthesis/rising-rate.json")
    task = dataclasses.replace(task, candidates=tuple(c for c in task.candidates if c[0] in (1, 4, 6)))
    assert len(task.candidates) == 3
    here = synthesize(task, "fast", seeds=1)
    there = synthesize(task, "fast", seeds=1, executor=cluster)
    assert len(here.solutions) == len(there.solutions) > 0
    assert [(s.candidate, s.error, s.mechanism.to_dict()) for s in here.solutions] == \
        [(s.candidate, s.error, s.mechanism.to_dict()) for s in there.solutions]
