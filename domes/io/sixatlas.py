"""The six-bar atlas in the user's data folder (``$DOMES_HOME/atlas/sixbar-N.npz``), built there the first time.

>>> default_sixatlas.__name__
'default_sixatlas'
"""

from __future__ import annotations

from domes.io.resources import user_dir
from domes.motion.coupler.sixatlas import _CACHE, PER_KIND, SixAtlas


def default_sixatlas(per_kind: int = PER_KIND) -> SixAtlas:
    """The six-bar atlas of ``per_kind`` six-bars of each type, read from the data folder or built and saved there."""
    if per_kind not in _CACHE:
        path = user_dir() / "atlas" / f"sixbar-{per_kind}.npz"
        if path.is_file():
            _CACHE[per_kind] = SixAtlas.load(path)
        else:
            _CACHE[per_kind] = SixAtlas.build(per_kind)
            path.parent.mkdir(parents=True, exist_ok=True)
            _CACHE[per_kind].save(path)
    return _CACHE[per_kind]
