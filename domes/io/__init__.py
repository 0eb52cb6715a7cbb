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

>>> load_scene("motorcycle").links
6
"""

from domes.io.mechanisms import load_mechanism, save_mechanism
from domes.io.scenes import load_scene, parse_scene, scene_names
from domes.io.topology import from_mtm, read_topology, to_mtm, write_topology

__all__ = [
    "from_mtm", "load_mechanism", "load_scene", "parse_scene", "read_topology", "save_mechanism", "scene_names",
    "to_mtm", "write_topology",
]
