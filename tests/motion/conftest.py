"""The small atlas of coupler curves (closed paths, and the window index of open ones), built once in a test run."""

import pytest

from domes.io.atlas import load_atlas, save_atlas
from domes.motion.coupler.atlas import SIZES, Atlas, OpenAtlas, build, build_windows


def _shared_table(tmp_path_factory, name: str, make):
    """The table ``make()`` saved as ``name``: under ``pytest -n`` the first worker to need it writes it to the folder
    the workers' temporary folders share, and the others read that file."""
    import fcntl
    import os

    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent
    path = shared / name
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not path.is_file():
            save_atlas(make(), path)
    return load_atlas(path)


@pytest.fixture(scope="module")
def small_atlas(tmp_path_factory):
    """The small atlas (600 four-bars), as ``domes curves match`` builds it."""
    return Atlas(_shared_table(tmp_path_factory, "fourbar-small.h5", lambda: build(SIZES["small"])))


@pytest.fixture(scope="module")
def small_open_atlas(tmp_path_factory):
    """The small atlas's window index of open paths, as ``domes curves match --open`` builds it."""
    return OpenAtlas(_shared_table(tmp_path_factory, "fourbar-small-open.h5", lambda: build_windows(SIZES["small"])))
