"""Batches written to HDF5 as they run: a sink for :func:`domes.motion.planar.batch.batch`.

>>> import numpy as np, tempfile, os, h5py
>>> from domes.motion.planar.batch import batch
>>> from domes.motion.planar.examples import four_bar
>>> path = os.path.join(tempfile.mkdtemp(), "b.h5")
>>> run = batch(four_bar(), {"C": np.array([[3.5, 6 ** 0.5], [3.2, 2.0]])}, np.radians([0.0, 90.0]),
...             outputs=["angle:rocker"], sink=HDF5Sink(path))
>>> with h5py.File(run.result) as f:
...     f["values/angle:rocker"].shape, f["kinds"][:].tolist()
((2, 2), [b'complete', b'complete'])
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from domes.errors import InputError
from domes.io.files import publish, temporary_beside
from domes.motion.planar.batch import KINDS, Chunk, Plan


class HDF5Sink:
    """Write each chunk to the HDF5 file ``path`` as it finishes; the result is the path.

    The file holds ``inputs``, ``values/<column>`` ``(M, N)``,
    ``assembled``, ``kinds`` (bytes), ``transmission``, ``residual`` and the
    attributes ``mechanism``, ``joint``. It is written to a temporary file in
    the same folder and renamed over ``path`` at the end (an interrupted
    batch leaves no file and an old one as it was). ``compression`` is
    passed to ``h5py`` (e.g. ``"gzip"``). Needs ``h5py``.
    """

    def __init__(self, path, compression=None):
        self.path = Path(path)
        self.compression = compression
        self.file = None
        self.tmp = None

    def start(self, plan: Plan) -> None:
        try:
            import h5py
        except ImportError:
            raise InputError("HDF5Sink needs h5py (pip install h5py)") from None
        fd, self.tmp = temporary_beside(self.path)
        os.close(fd)
        m, n = plan.count, plan.inputs.size
        f = self.file = h5py.File(self.tmp, "w")
        f.attrs["mechanism"] = plan.mechanism
        f.attrs["joint"] = plan.joint
        f.create_dataset("inputs", data=plan.inputs)
        kw = {"compression": self.compression} if self.compression else {}
        values = f.create_group("values")
        for c in plan.columns:
            values.create_dataset(c, (m, n), dtype="f8", **kw)
        f.create_dataset("assembled", (m, n), dtype=bool, **kw)
        f.create_dataset("kinds", (m,), dtype=f"S{max(map(len, KINDS))}")
        f.create_dataset("transmission", (m,), dtype="f8")
        f.create_dataset("residual", (m,), dtype="f8")

    def accept(self, c: Chunk) -> None:
        f = self.file
        for col, val in c.values.items():
            f["values"][col][c.lo:c.hi] = val
        f["assembled"][c.lo:c.hi] = c.assembled
        f["kinds"][c.lo:c.hi] = c.kinds.astype(np.bytes_)
        f["transmission"][c.lo:c.hi] = c.transmission
        f["residual"][c.lo:c.hi] = c.residual

    def finish(self) -> str:
        self.file.close()
        self.file = None
        publish(self.tmp, self.path)
        self.tmp = None
        return str(self.path)

    def abort(self) -> None:
        if self.file is not None:
            self.file.close()
            self.file = None
        if self.tmp and os.path.exists(self.tmp):
            os.unlink(self.tmp)
        self.tmp = None


__all__ = ["HDF5Sink"]
