"""The two inner tests of the walk by canonical augmentation, compiled (numba): is a branch removable, and
how little freedom can a set of links holding an ear's ends have.

Both are loops over bitmasks of at most 64 links that Python runs slowly
and a compiled loop runs in microseconds. :mod:`domes.typesynth.augment`
calls them through :func:`load`, which imports numba (and loads the loops
from numba's on-disk cache) only when the walk first needs them, and
returns None when numba is not installed: the walk then runs its
pure-Python tests, which give the same answers (``tests/typesynth/
test_augment_kernel.py`` compares both on every branch and ear of the
10- and 11-link walks).

>>> import numpy as np
>>> kernels = load()
>>> square = np.array([0b1010, 0b0101, 0b1010, 0b0101], dtype=np.int64)     # a four-bar: links 0-1-2-3-0
>>> kernels is None or list(kernels.removable(np.array([*square, 0, 1, 0]), 4)) == [0]    # the joint 0-1
True
"""

from __future__ import annotations

import importlib.util
import os
from types import SimpleNamespace

#: The environment variable that turns the compiled tests off (``python``) or on (``numba``, the default when
#: numba is installed).
VARIABLE = "DOMES_ATLAS_KERNEL"

_loaded: list = []


def load():
    """The compiled tests (an object with ``removable`` and ``least_freedom``), or None: numba is not installed,
    or ``$DOMES_ATLAS_KERNEL`` is ``python`` (read once a process)."""
    if not _loaded:
        off = os.environ.get(VARIABLE, "").strip().lower() == "python" or importlib.util.find_spec("numba") is None
        _loaded.append(None if off else _compile())
    return _loaded[0]


def _compile():
    from domes.typesynth import _earloops

    return SimpleNamespace(removable=_earloops.removable, least_freedom=_earloops.least_freedom)
