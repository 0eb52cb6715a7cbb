"""Coupler-curve atlas files: HDF5, chunked and compressed, written atomically.

An atlas is a large numeric table (one row per curve: linkage, coupler
point, circuit, descriptor); HDF5 stores it in compressed chunks, so that a
large atlas stays small on disk and is read column by column. A file is
written to a temporary file beside the target and renamed over it, so a
reader never sees half an atlas. The atlases a user builds by name live in
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
import os
import tempfile
from pathlib import Path

import numpy as np

from domes.errors import InputError
from domes.io.files import check_target
from domes.io.resources import user_dir
from domes.motion.coupler.atlas import SIZES, VERSION, AtlasTable, WindowTable, build, build_windows
from domes.results import Progress

TABLES = {"closed": AtlasTable, "open": WindowTable}
#: Rows per compressed chunk.
CHUNK_ROWS = 1 << 16


def _columns(kind) -> tuple[str, ...]:
    return tuple(f.name for f in dataclasses.fields(TABLES[kind]) if f.name != "meta")


def save_atlas(table: AtlasTable | WindowTable, path: str | Path) -> None:
    """Write ``table`` to the HDF5 file ``path`` (atomically: a temporary file renamed over it)."""
    import h5py

    target = check_target(path)
    fd, tmp = tempfile.mkstemp(prefix=".atlas-", suffix=".h5", dir=target.parent)
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
            meta = json.loads(f.attrs.get("meta", "{}"))
            kind = meta.get("kind", "closed")
            if kind not in TABLES:
                raise InputError(f"{path}: not an atlas (kind {kind!r})")
            columns = _columns(kind)
            missing = [c for c in columns if c not in f]
            if missing:
                raise InputError(f"{path}: not an atlas: no {', '.join(missing)} column")
            data = {c: f[c][()] for c in columns}
    except OSError as exc:
        raise InputError(f"{path}: cannot read the atlas ({exc}); build it again") from None
    if meta.get("version") != VERSION:
        raise InputError(f"{path}: atlas version {meta.get('version')} (this DOMES-py reads version {VERSION}); "
                         "build it again")
    rows = {len(data[c]) for c in columns[1:]}
    if len(rows) != 1 or (data["link"].size and int(data["link"].max()) >= len(data["linkages"])):
        raise InputError(f"{path}: the atlas's columns do not agree (lengths {sorted(rows)}): the file is damaged")
    data["linkages"] = data["linkages"].astype(np.float64)
    return TABLES[kind](**data, meta=meta)


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
