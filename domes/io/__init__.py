"""Files and package data: where the shipped knowledge is, and the file formats read and written.

The rest of the package works on values; this layer turns files into values
and values into files (always written atomically, :mod:`domes.io.files`):

- :mod:`domes.io.resources` -- the shipped knowledge and case base, the user's case base;
- :mod:`domes.io.mechanisms` -- dimensioned mechanisms (JSON);
- :mod:`domes.io.topology` -- mechanism topologies (TOML, Yan's MTM, the TYPE matrix);
- :mod:`domes.io.scenes` -- design scenes (TOML);
- :mod:`domes.io.criteria` -- criterion frames and solved cases (TOML, JSON);
- :mod:`domes.io.graphs` -- labelled graphs (JSON);
- :mod:`domes.io.transcripts` -- answers files and design transcripts.

The names below are loaded on first use (PEP 562): ``from domes.io.files import ...`` does not load the scenes'
design stack.

>>> from domes.io import load_scene
>>> load_scene("motorcycle").links
6
"""

from __future__ import annotations

from domes.io.lazy import exports

#: Each re-exported name and the module it comes from, imported on first use.
_LAZY = {
    "from_mtm": "domes.io.topology",
    "load_mechanism": "domes.io.mechanisms",
    "load_scene": "domes.io.scenes",
    "parse_scene": "domes.io.scenes",
    "read_topology": "domes.io.topology",
    "save_mechanism": "domes.io.mechanisms",
    "scene_names": "domes.io.scenes",
    "to_mtm": "domes.io.topology",
    "write_topology": "domes.io.topology",
}

__all__ = [
    "from_mtm", "load_mechanism", "load_scene", "parse_scene", "read_topology", "save_mechanism", "scene_names",
    "to_mtm", "write_topology",
]


__getattr__, __dir__ = exports(globals(), _LAZY)
