"""Test session setup: the checkout's own ``domes`` first on sys.path (pytest puts this folder there),
a scratch DOMES_HOME so that no test ever reads or writes the user's own case base, and the numerical
libraries held to one thread, as every command holds them (domes.execution.threads)."""

import os
import tempfile

import pytest

os.environ["DOMES_HOME"] = tempfile.mkdtemp(prefix="domes-test-home-")
for _name in ("DOMES_DB", "DOMES_KNOWLEDGE"):
    os.environ.pop(_name, None)


@pytest.fixture(autouse=True, scope="session")
def _one_thread():
    from domes.execution.threads import limited_threads

    with limited_threads(1):
        yield
