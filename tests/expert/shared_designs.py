"""The feasibility level of a design session computed once per test run for the same inputs.

Several tests run sessions whose last level (the kept candidates dimensioned, verified and ranked:
:func:`domes.expert.feasible.feasible_designs`) gets exactly the same inputs: the quick start in the dialogue's,
the PostgreSQL and the studio's tests, the window lifter's shipped case in every replay and in the design loop's
tests. That level is a pure function of its inputs (the scene, the requirements, the weights, the kept candidates,
the method and the seeds: each candidate draws from its own seed), so it is computed by the first test that needs
it and read back by the others, across the ``pytest -n`` workers (:func:`tests.shared.shared_file`). Its numbers are
compared with the recordings by the replays and derived again by another route in test_design_loop.py.

Knobs that change how it runs (workers, a scheduler, a time budget) are never taken from the file: the tests of
those knobs compare them with one process.
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import pickle

import pytest

from tests.shared import shared_file


def _key(scene_name, requirements, weights, kept, knobs) -> str:
    text = json.dumps([scene_name, repr(requirements), weights, kept, knobs.method, knobs.seeds],
                      sort_keys=True, default=repr)
    return hashlib.sha256(text.encode()).hexdigest()[:24]


@contextlib.contextmanager
def designs_computed_once(tmp_path_factory):
    """Within the block, a session's feasibility level with the same inputs is computed once per test run."""
    import domes.expert.world as world

    compute = world.feasible_designs

    def once(scene_name, requirements, weights, kept, knobs, progress=None):
        if knobs.workers is not None or knobs.scheduler is not None or knobs.time_budget is not None:
            return compute(scene_name, requirements, weights, kept, knobs, progress)

        def write(path):
            path.write_bytes(pickle.dumps(compute(scene_name, requirements, weights, kept, knobs, progress)))

        name = f"designs-{_key(scene_name, requirements, weights, kept, knobs)}.pickle"
        return pickle.loads(shared_file(tmp_path_factory, name, write).read_bytes())

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(world, "feasible_designs", once)
        yield


@pytest.fixture(name="designs_once")
def designs_once_fixture(tmp_path_factory):
    """:func:`designs_computed_once` for one test (in tests/expert, for every test: its conftest.py)."""
    with designs_computed_once(tmp_path_factory):
        yield
