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

from domes.errors import InputError
from domes.io.files import read_text, write_atomic
from domes.model.mechanism import Mechanism


def load_mechanism(path: str | Path) -> Mechanism:
    """Read a mechanism file (JSON). Errors name the file, line and field."""
    text = read_text(path)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from None
    return Mechanism.from_dict(data, str(path))


def save_mechanism(mechanism: Mechanism, path: str | Path) -> None:
    """Write a mechanism file (JSON, angles in degrees) atomically."""
    write_atomic(path, json.dumps(mechanism.to_dict(), indent=1) + "\n")
