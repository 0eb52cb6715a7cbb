"""Coupler-curve atlas files: HDF5, chunked and compressed, written atomically.

An atlas is a large numeric table (one row per curve: linkage, coupler
point, circuit, descriptor); HDF5 stores it in compressed chunks, so that a
large atlas stays small on disk and is read column by column. A file is
written to a temporary file beside the target and renamed over it, so a
reader never sees half an atlas; the temporary files of writes that were
killed are removed at the next write in that folder (:func:`clean_stale`).
The atlases a user builds by name live in
the user's data folder (``$DOMES_HOME/atlas/``, see
:mod:`domes.io.resources`); :func:`default_atlas` builds the small one there
the first time it is needed (about ten seconds).

>>> import tempfile, os
>>> from domes.motion.coupler.atlas import AtlasSpec, build
>>> path = os.path.join(tempfile.mkdtemp(), "tiny.h5")
>>> save_atlas(build(AtlasSpec("tiny", 3, 2.0)), path)
>>> load_atlas(path).meta["name"]
'tiny'
"""

from __future__ import annotations

import dataclasses
import json
import logging
import math
import os
import re
import tempfile
import time
from pathlib import Path

import numpy as np

from domes.errors import InputError, shown
from domes.io.files import check_target, read_json
from domes.io.resources import user_dir
from domes.model.fields import read_number
from domes.motion.coupler.atlas import SIZES, VERSION, AtlasTable, WindowTable, build, build_windows, open_features
from domes.motion.coupler.fourier import features
from domes.results import Progress

TABLES = {"closed": AtlasTable, "open": WindowTable}
#: The temporary file of an atlas being written, beside it: ``.atlas-PID-RANDOM.h5`` (PID: the writer's process,
#: RANDOM: the letters mkstemp chose; files of older versions have no PID: ``.atlas-RANDOM.h5``).
TEMPORARY = re.compile(r"^\.atlas-(?:(\d+)-)?[A-Za-z0-9_]+\.h5$")
log = logging.getLogger("domes")
#: Rows per compressed chunk.
CHUNK_ROWS = 1 << 16


def _columns(kind) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(TABLES[kind]) if f.name != "meta")


def save_atlas(table: AtlasTable | WindowTable, path: str | Path) -> None:
    """Write ``table`` to the HDF5 file ``path`` (atomically: a temporary file renamed over it)."""
    import h5py

    target = check_target(path)
    clean_stale(target.parent, time.time() - float(table.meta.get("seconds", 0.0)))
    fd, tmp = tempfile.mkstemp(prefix=f".atlas-{os.getpid()}-", suffix=".h5", dir=target.parent)
    os.close(fd)
    try:
        with h5py.File(tmp, "w") as f:
            for name in _columns(table.meta.get("kind", "closed")):
                data = getattr(table, name)
                chunks = (min(CHUNK_ROWS, max(1, len(data))),) + data.shape[1:]
                f.create_dataset(name, data=data, chunks=chunks, compression="gzip", compression_opts=4, shuffle=True)
            f.attrs["meta"] = json.dumps(table.meta)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, target)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def clean_stale(folder: str | Path, started: float) -> list[Path]:
    """Remove the temporary files that atlas writes killed mid-write left in ``folder``: those of processes no
    longer alive, and those that name no process and were last written before ``started`` (the build's start,
    seconds since the epoch). A file of a live process is another write under way and is kept. Returns those
    removed.

    >>> import tempfile
    >>> folder = Path(tempfile.mkdtemp())
    >>> _ = (folder / ".atlas-k3j_x9q2.h5").write_bytes(b"half")
    >>> [p.name for p in clean_stale(folder, time.time() + 1)], list(folder.iterdir())
    (['.atlas-k3j_x9q2.h5'], [])
    """
    removed = []
    for path in Path(folder).iterdir():
        match = TEMPORARY.match(path.name)
        if not match or not path.is_file():
            continue
        try:
            stale = not _alive(int(match[1])) if match[1] else path.stat().st_mtime < started
            if stale:
                path.unlink()
        except OSError:          # gone meanwhile, or not ours to remove: left as it is
            continue
        if stale:
            removed.append(path)
            log.info(f"removed {path}: the temporary file of an atlas write that did not finish")
    return removed


def _alive(pid: int) -> bool:
    """Whether the process ``pid`` runs (signal 0 only asks; on Windows, where it would not, every one counts)."""
    if os.name == "nt" or not 0 < pid < 2 ** 31:
        return os.name == "nt"
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # it runs, as another user
        return True
    return True


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def load_atlas(path: str | Path) -> AtlasTable | WindowTable:
    """Read an atlas file; an InputError that says what is wrong with a file that is not one."""
    import h5py

    path = Path(path)
    if not path.is_file():
        raise InputError(f"{path}: no atlas file there (build one with: domes curves atlas build)")
    try:
        with h5py.File(path, "r") as f:
            text = f.attrs.get("meta", "{}")
            meta = read_json(f"{path}: the atlas's metadata", text if isinstance(text, str) else "null")
            if not isinstance(meta, dict):
                raise InputError(f"{path}: the atlas's metadata is damaged (not an object); build it again")
            kind = meta.get("kind", "closed")
            if kind not in TABLES:
                raise InputError(f"{path}: not an atlas (kind {shown(kind)})")
            columns = _columns(kind)
            missing = [c for c in columns if c not in f or not isinstance(f[c], h5py.Dataset)]
            if missing:
                raise InputError(f"{path}: not an atlas: no {', '.join(missing)} column")
            data = {c: f[c][()] for c in columns}
    except OSError as exc:
        raise InputError(f"{path}: cannot read the atlas ({exc}); build it again") from None
    if meta.get("version") != VERSION:
        raise InputError(f"{path}: atlas version {shown(meta.get('version'))} (this DOMES-py reads version {VERSION}); "
                         "build it again")
    problem = _meta_problem(meta, kind) or _column_problem(data, kind, meta)
    if problem:
        raise InputError(f"{path}: the atlas is damaged: {problem}; build it again")
    data["linkages"] = data["linkages"].astype(np.float64)
    return TABLES[kind](**data, meta=meta)


#: The entries of an atlas's metadata that a reader uses: the numbers (each with the least it may be) and the counts
#: (each with its range), by kind.
_NUMBERS = {"step": 0.0, "plane": 0.0, "seconds": 0.0}
_COUNTS = {"closed": {"harmonics": (2, 64)}, "open": {"window_points": (3, 1000)}}


def _meta_problem(meta: dict, kind: str) -> str:
    """What is wrong with an atlas's metadata (empty when nothing is)."""
    if not isinstance(meta.get("name"), str):
        return f"its name is {shown(meta.get('name'))}, not text"
    for key, least in _NUMBERS.items():
        value = meta.get(key)
        try:
            number = read_number(value, key)
        except InputError:
            number = math.nan
        if not least <= number < math.inf:
            return f"its {key!r} is {shown(value)}, not a finite number of at least {least:g}"
    for key, (low, high) in _COUNTS[kind].items():
        value = meta.get(key)
        if isinstance(value, bool) or not isinstance(value, int) or not low <= value <= high:
            return f"its {key!r} is {shown(value)}, not a whole number from {low} to {high}"
    return ""


def _column_problem(data: dict, kind: str, meta: dict) -> str:
    """What is wrong with an atlas's columns: a type, a shape (the features' width as the metadata says), a value that
    is not finite, a row of a linkage that is not there."""
    for name, values in data.items():
        if values.dtype.kind not in "iuf":
            return f"column {name} holds {values.dtype} values, not numbers"
        if values.dtype.kind == "f" and not np.all(np.isfinite(values)):
            return f"column {name} has values that are not finite"
    if data["circuit"].ndim != 1:
        return f"column circuit has the shape {data['circuit'].shape}, not one row per curve"
    rows = data["circuit"].shape
    if kind == "closed":
        width = features(np.zeros((1, 2 * meta["harmonics"] + 1))).shape[1]
    else:
        q = meta["window_points"]
        width = open_features(np.linspace(0, 1, q)[None, :].astype(complex), q).shape[1]
    shapes = {"linkages": (None, 4), "link": rows, "point": (*rows, 2), "circuit": rows, "start": rows,
              "fraction": rows, "features": (*rows, width)}
    for name, values in data.items():
        wanted = shapes[name]
        if values.ndim != len(wanted) or any(w is not None and n != w for n, w in zip(values.shape, wanted)):
            return f"column {name} has the shape {values.shape}; the atlas's rows are {rows[0]:,}"
    link = data["link"]
    if link.size and (link.dtype.kind == "f" or link.min() < 0 or link.max() >= len(data["linkages"])):
        return f"column link names linkages that are not in the linkages column (of {len(data['linkages']):,})"
    return ""


def atlas_path(name: str, kind: str = "closed") -> Path:
    """Where the atlas ``name`` (``small``, ``large``) lives in the user's data folder (``open``: its windows)."""
    if name not in SIZES:
        raise InputError(f"no atlas size {name!r}; sizes are {sorted(SIZES)}")
    return user_dir() / "atlas" / f"fourbar-{name}{'-open' if kind == 'open' else ''}.h5"


def default_atlas(name: str = "small", progress: Progress | None = None, kind: str = "closed"):
    """The atlas ``name`` (or its open-path windows) from the user's data folder, built there first if need be."""
    path = atlas_path(name, kind)
    if not path.is_file():
        path.parent.mkdir(parents=True, exist_ok=True)
        save_atlas((build if kind == "closed" else build_windows)(SIZES[name], progress), path)
    return load_atlas(path)
