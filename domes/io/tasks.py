"""Synthesis task files (JSON; examples in ``examples/synthesis/``, format in ``docs/synthesis.md``).

>>> import os, tempfile
>>> path = os.path.join(tempfile.mkdtemp(), "t.json")
>>> _ = open(path, "w").write('{"kind": "function", "rotations_deg": [[-30, 15], [-60, 45]], "rocker_pin": [0.375, 0.1875]}')
>>> load_task(path).rocker_pin
(0.375, 0.1875)
"""

from __future__ import annotations

import json
from pathlib import Path

from domes.design.synthesis.task import task_from_dict
from domes.errors import InputError
from domes.io.files import read_text


def load_task(path: str | Path):
    """Read a task file; errors name the file and the entry."""
    text = read_text(path)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from None
    if isinstance(data, dict) and "name" not in data:
        data = {**data, "name": Path(path).stem}
    return task_from_dict(data, str(path))
