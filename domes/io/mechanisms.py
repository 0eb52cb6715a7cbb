"""Mechanism files: a dimensioned planar mechanism as JSON (format in ``docs/kinematics.md``).

>>> import json, os, tempfile
>>> from domes.motion.planar.examples import four_bar
>>> path = os.path.join(tempfile.mkdtemp(), "four-bar.json")
>>> save_mechanism(four_bar(), path)
>>> load_mechanism(path).to_dict() == four_bar().to_dict()
True
"""

from __future__ import annotations

import json
from pathlib import Path

from domes.design.scriber import ScriberTask
from domes.errors import InputError
from domes.io.files import read_json, write_atomic
from domes.model.mechanism import Mechanism
from domes.model.spatial import SpatialMechanism


def load_mechanism(path: str | Path) -> Mechanism:
    """Read a planar mechanism file (JSON). Errors name the file, line and field."""
    data = read_json(path)
    if isinstance(data, dict) and data.get("space") == "spatial":
        raise InputError(f"{path}: a spatial mechanism; this command takes planar ones (spatial files: domes "
                         "kinematics, docs/spatial.md)")
    return Mechanism.from_dict(data, str(path))


def is_spatial(path: str | Path) -> bool:
    """Whether a mechanism file is spatial (it says ``"space": "spatial"``)."""
    data = read_json(path)
    return isinstance(data, dict) and data.get("space") == "spatial"


def load_spatial(path: str | Path) -> SpatialMechanism:
    """Read a spatial mechanism file (JSON, ``docs/spatial.md``). Errors name the file, line and field."""
    return SpatialMechanism.from_dict(read_json(path), str(path))


def save_spatial(mechanism: SpatialMechanism, path: str | Path) -> None:
    """Write a spatial mechanism file (JSON, angles in degrees) atomically."""
    write_atomic(path, json.dumps(mechanism.to_dict(), indent=1) + "\n")


def load_scriber_task(path: str | Path):
    """Read a scriber task file (JSON: a 2-RPR scriber, a contour, a speed; see ``docs/dynamics.md``)."""
    return ScriberTask.from_dict(read_json(path), str(path))


def is_scriber_task(path: str | Path) -> bool:
    """Whether a JSON file is a scriber task (it has a ``contour``) rather than a mechanism."""
    data = read_json(path)
    return isinstance(data, dict) and "contour" in data


def save_mechanism(mechanism: Mechanism, path: str | Path) -> None:
    """Write a mechanism file (JSON, angles in degrees) atomically."""
    write_atomic(path, json.dumps(mechanism.to_dict(), indent=1) + "\n")
