"""Tables built once in a test run and shared by every test (and every ``pytest -n`` worker) that needs them."""

from __future__ import annotations

import fcntl
import os
from pathlib import Path


def shared_file(tmp_path_factory, name: str, write) -> Path:
    """The file ``name`` that ``write(path)`` makes: under ``pytest -n`` the first worker to need it writes it to
    the folder the workers' temporary folders share, and the others find it there."""
    shared = tmp_path_factory.getbasetemp()
    if os.environ.get("PYTEST_XDIST_WORKER"):
        shared = shared.parent
    path = shared / name
    with open(shared / f"{name}.lock", "w") as lock:
        fcntl.flock(lock, fcntl.LOCK_EX)
        if not path.is_file():
            write(path)
    return path


def small_atlas_file(tmp_path_factory, kind: str = "closed") -> Path:
    """The small atlas of coupler curves (``open``: its window index) as ``domes curves match`` builds it, saved."""
    from domes.io.atlas import save_atlas
    from domes.motion.coupler.atlas import SIZES, build, build_windows

    make = build if kind == "closed" else build_windows
    name = "fourbar-small.h5" if kind == "closed" else "fourbar-small-open.h5"
    return shared_file(tmp_path_factory, name, lambda path: save_atlas(make(SIZES["small"]), path))
