"""Synthesis task files (JSON; examples in ``examples/synthesis/``, format in ``docs/synthesis.md``).

>>> import os, tempfile
>>> path = os.path.join(tempfile.mkdtemp(), "t.json")
>>> _ = open(path, "w").write('{"kind": "function", "rotations_deg": [[-30, 15], [-60, 45]], "rocker_pin": [0.375, 0.1875]}')
>>> load_task(path).rocker_pin
(0.375, 0.1875)
"""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

from domes.design.synthesis.candidate import CurveTask
from domes.design.synthesis.spatialtask import KINDS as SPATIAL_KINDS
from domes.design.synthesis.spatialtask import spatial_task_from_dict
from domes.design.synthesis.task import task_from_dict
from domes.errors import InputError
from domes.io.files import read_text
from domes.io.scenes import load_scene
from domes.typesynth.regenerate import regenerate


def load_spatial_task(path: str | Path):
    """A spatial synthesis task (``kind`` spherical-guidance, spherical-function or rccc), or None for a planar one."""
    text = read_text(path)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from None
    if not (isinstance(data, dict) and data.get("kind") in SPATIAL_KINDS):
        return None
    if "name" not in data:
        data = {**data, "name": Path(path).stem}
    return spatial_task_from_dict(data, str(path))


def load_task(path: str | Path, candidates=None):
    """Read a task file; errors name the file and the entry.

    A ``curve`` task gets its candidates: ``candidates`` (``(id, labelled
    chain)`` pairs, e.g. a design case's kept ones) or else those of its
    ``scene``, regenerated, narrowed to the ids its ``candidates`` entry lists.
    """
    text = read_text(path)
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from None
    if isinstance(data, dict) and "name" not in data:
        data = {**data, "name": Path(path).stem}
    task = task_from_dict(data, str(path))
    if isinstance(task, CurveTask):
        task = dataclasses.replace(task, candidates=tuple(candidates) if candidates is not None
                                   else _scene_candidates(task, data.get("candidates", "all"), path))
    return task


def _scene_candidates(task: CurveTask, wanted, path) -> tuple:
    if task.scene is None:
        raise InputError(f"{path}: a curve task names the 'scene' whose candidates it dimensions")
    scene = Path(path).parent / task.scene
    result = regenerate(load_scene(scene if task.scene.endswith(".toml") and scene.is_file() else task.scene))
    found = tuple((c.id, c.labelled) for c in result.candidates)
    if wanted == "all":
        return found
    ids = {cid for cid, _ in found}
    if (not isinstance(wanted, list) or not wanted
            or not all(isinstance(k, int) and not isinstance(k, bool) and k in ids for k in wanted)):
        raise InputError(f"{path}: 'candidates' must be \"all\" or a list of the scene's candidate numbers "
                         f"{sorted(ids)}, got {wanted!r}")
    return tuple((cid, c) for cid, c in found if cid in wanted)
