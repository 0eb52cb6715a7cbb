"""The six-bar atlas on disk: NumPy ``.npz`` files written atomically, read with their shapes checked, and the
default atlas in the user's data folder (``$DOMES_HOME/atlas/sixbar-N.npz``), built there the first time.

>>> import tempfile, pathlib
>>> from domes.motion.coupler.sixatlas import SixAtlas
>>> atlas = SixAtlas.build(per_kind=2)
>>> path = pathlib.Path(tempfile.mkdtemp()) / "six.npz"
>>> save_sixatlas(atlas, path)
>>> load_sixatlas(path).count == atlas.count
True
"""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np

from domes.errors import InputError
from domes.io.files import write_atomic
from domes.io.resources import user_dir
from domes.motion.coupler.sixatlas import _CACHE, PER_KIND, SixAtlas

#: The arrays of a six-bar atlas file, in the order :class:`SixAtlas` takes them.
FIELDS = ("kinds", "lengths", "row_bar", "row_mode", "row_point", "features")


def save_sixatlas(atlas: SixAtlas, path: str | Path) -> None:
    """Write ``atlas`` to ``path`` (NumPy ``.npz``, compressed) through a temporary file and a rename."""
    buffer = io.BytesIO()
    np.savez_compressed(buffer, **{name: getattr(atlas, name) for name in FIELDS})
    write_atomic(path, buffer.getvalue())


def load_sixatlas(path: str | Path) -> SixAtlas:
    """The six-bar atlas in ``path``; an InputError that says what is wrong when it is not one."""
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {name: data[name] for name in FIELDS}
    except (OSError, KeyError, ValueError) as exc:
        raise InputError(f"{path}: not a six-bar atlas ({exc}); delete it to build it again") from None
    try:
        problem = _problem(arrays)
    except (TypeError, ValueError, IndexError):
        problem = "an array has the wrong type or shape"
    if problem:
        raise InputError(f"{path}: not a six-bar atlas ({problem}); delete it to build it again")
    return SixAtlas(*(arrays[name] for name in FIELDS))


def _problem(arrays) -> str | None:
    """What makes ``arrays`` no six-bar atlas, or None."""
    rows, bars = len(arrays["features"]), arrays["row_bar"]
    checks = [(f"{name} has {len(arrays[name])} rows, not {rows}", len(arrays[name]) == rows)
              for name in ("row_bar", "row_mode", "row_point")]
    checks += [("its descriptors or tracing points have the wrong shape",
                arrays["features"].ndim == 2 and arrays["row_point"].shape[1:] == (2,)),
               ("a row names a six-bar that is not there",
                not rows or 0 <= bars.min() <= bars.max() < len(arrays["lengths"])),
               ("a value is not finite", all(np.isfinite(arrays[n]).all() for n in ("lengths", "row_point", "features")))]
    return next((text for text, ok in checks if not ok), None)


def default_sixatlas(per_kind: int = PER_KIND) -> SixAtlas:
    """The six-bar atlas of ``per_kind`` six-bars of each type, read from the data folder or built and saved there."""
    if per_kind not in _CACHE:
        path = user_dir() / "atlas" / f"sixbar-{per_kind}.npz"
        if path.is_file():
            _CACHE[per_kind] = load_sixatlas(path)
        else:
            _CACHE[per_kind] = SixAtlas.build(per_kind)
            path.parent.mkdir(parents=True, exist_ok=True)
            save_sixatlas(_CACHE[per_kind], path)
    return _CACHE[per_kind]
