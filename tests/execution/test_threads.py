"""Numerical threads: every command holds BLAS/OpenMP to one thread (or DOMES_THREADS), whatever the caller set.

On a busy 2-core machine a thread per core per fit made `domes curves match` take 33 minutes instead of 58 s
(the design-loop issue's companion, item 1); the limit is set in one place, around every command.
"""

import numpy  # noqa: F401 - loads the BLAS whose threads are limited
import pytest
from threadpoolctl import threadpool_info, threadpool_limits

import domes.cli.synthesis
from domes.cli import main
from domes.errors import DomesError
from domes.execution.threads import THREADS_VARIABLE, limited_threads, thread_limit


def threads_seen_by_a_command(monkeypatch):
    seen = {}

    def spy(args):
        seen["threads"] = {i["num_threads"] for i in threadpool_info()}
        return 0

    monkeypatch.setattr(domes.cli.synthesis, "run", spy)
    with threadpool_limits(limits=4):  # what a caller (or the libraries' default) may have set
        assert main(["synthesis", "--dof", "1", "--loops", "1"]) == 0
    return seen["threads"]


@pytest.mark.skipif(not threadpool_info(), reason="no BLAS thread pool loaded")
def test_a_command_runs_with_one_numerical_thread(monkeypatch):
    monkeypatch.delenv(THREADS_VARIABLE, raising=False)
    assert threads_seen_by_a_command(monkeypatch) == {1}


@pytest.mark.skipif(not threadpool_info(), reason="no BLAS thread pool loaded")
def test_domes_threads_sets_the_limit(monkeypatch):
    monkeypatch.setenv(THREADS_VARIABLE, "2")
    assert threads_seen_by_a_command(monkeypatch) == {2}


def test_a_bad_limit_is_refused_with_its_name(monkeypatch, capsys):
    for bad in ("0", "-1", "many", "1.5"):
        monkeypatch.setenv(THREADS_VARIABLE, bad)
        with pytest.raises(DomesError, match=THREADS_VARIABLE):
            thread_limit()
    monkeypatch.setenv(THREADS_VARIABLE, "all")
    assert thread_limit() is None
    with limited_threads() as n:
        assert n is None
