"""Lost workers on a two-worker LocalCluster: their tasks run again, or the run ends with a ClusterError (issue 31).

Workers are killed with SIGKILL from here (their process ids asked of the
cluster), or by the task itself; the cluster's nannies start new ones. A
run with no worker left ends after ``DOMES_WORKER_TIMEOUT`` seconds; a
task's own error reaches the caller as it was, whatever its type.
"""

import os
import signal
import sys
import time

import cloudpickle
import pytest

from domes.errors import InputError
from domes.execution import ClusterError, check_workers, executor

pytest.importorskip("distributed")

cloudpickle.register_pickle_by_value(sys.modules[__name__])      # the workers need not import this file


def slow_length(item):
    data, k = item
    time.sleep(0.3)
    return len(data) * 1000 + k


def second_kills_its_worker(k):
    if k == 2:
        os.kill(os.getpid(), signal.SIGKILL)
    return k


def wrong(kind):
    if kind == "input":
        raise InputError("a task's own input error")
    raise TimeoutError("a task's own timeout")


def kill_workers(client) -> int:
    pids = client.run(os.getpid)
    for pid in pids.values():
        os.kill(pid, signal.SIGKILL)
    return len(pids)


def test_tasks_run_again_when_every_worker_dies_and_the_shared_data_is_sent_again():
    # Killing both workers loses the data `share` sent them (every copy): Dask cancels the tasks that need it, and
    # the executor sends the data again and runs them on the new workers.
    with executor(workers=2) as run:
        shared = run.share(b"x" * 5000)
        seen = {}
        killed = 0
        for k, result in run.completed(slow_length, [(shared, k) for k in range(12)]):
            seen[k] = result
            if not killed:
                killed = kill_workers(run.client)
        assert killed == 2 and shared.status != "finished"               # the data first sent died with them
        assert run.map(slow_length, [(shared, 7)]) == [5_000_007]      # the data sent again serves later maps
    assert seen == {k: 5_000_000 + k for k in range(12)}


def test_a_task_that_kills_every_worker_it_runs_on_is_named():
    import dask

    with dask.config.set({"distributed.scheduler.allowed-failures": 0}):     # Dask gives up at the first death
        with executor(workers=2) as run:
            with pytest.raises(ClusterError) as caught:
                run.map(second_kills_its_worker, [1, 2, 3])
    message = str(caught.value)
    assert message.startswith("lost the workers of a local Dask cluster of 2 workers: task 2 of 3 "
                              "(second_kills_its_worker) was lost with every worker Dask ran it on")
    assert "3 times" in message and "Run the command again" in message and "\n" not in message


def test_a_cluster_without_workers_gives_up_after_the_timeout(monkeypatch):
    monkeypatch.setenv("DOMES_WORKER_TIMEOUT", "1")
    with executor(workers=2) as run:
        run.client.cluster.scale(0)
        for _ in range(300):
            if not run.client.scheduler_info()["workers"]:
                break
            time.sleep(0.1)
        with pytest.raises(ClusterError, match=r"lost the workers of a local Dask cluster of 2 workers: it has no "
                           r"worker, and none has run for 1 s; 0 of 3 tasks done\. Run the command again .*"
                           r"DOMES_WORKER_TIMEOUT=SECONDS to wait longer than 1 s"):
            run.map(abs, [1, -2, 3])


@pytest.fixture(scope="module")
def cluster():
    """A two-worker cluster for the tests that kill no worker."""
    with executor(workers=2) as run:
        yield run


@pytest.mark.parametrize("kind, error", [("input", InputError), ("timeout", TimeoutError)])
def test_a_tasks_own_error_is_raised_as_it_was(cluster, kind, error):
    # A TimeoutError raised by the task is the task's, not a lost connection: it is not run again nor renamed.
    with pytest.raises(error, match="a task's own"):
        cluster.map(wrong, [kind])
    assert cluster.map(abs, [-1]) == [1]


def test_the_timeout_knob_is_checked_before_a_run(monkeypatch):
    for bad in ("soon", "0", "-5", "inf", "nan"):
        monkeypatch.setenv("DOMES_WORKER_TIMEOUT", bad)
        with pytest.raises(InputError, match=f"DOMES_WORKER_TIMEOUT must be a number of seconds above 0, got '{bad}'"):
            check_workers(2)
    monkeypatch.setenv("DOMES_WORKER_TIMEOUT", "90")
    assert check_workers(2) is None
