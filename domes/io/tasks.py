"""Synthesis task files (JSON; examples in ``examples/synthesis/``, format in ``docs/synthesis.md``).

>>> import os, tempfile
>>> path = os.path.join(tempfile.mkdtemp(), "t.json")
>>> _ = open(path, "w").write('{"kind": "function", "rotations_deg": [[-30, 15], [-60, 45]], "rocker_pin": [0.375, 0.1875]}')
>>> load_task(path).rocker_pin
(0.375, 0.1875)
"""

from __future__ import annotations

import dataclasses
from pathlib import Path

from domes.design.synthesis.candidate import CurveTask
from domes.design.synthesis.spatialtask import KINDS as SPATIAL_KINDS
from domes.design.synthesis.spatialtask import spatial_task_from_dict
from domes.design.synthesis.task import task_from_dict
from domes.errors import InputError
from domes.io.files import is_file, read_json
from domes.io.scenes import load_scene
from domes.model.fields import check_keys, closest
from domes.typesynth.regenerate import regenerate

#: The entries of a planar task file by kind (docs/synthesis.md), besides ``kind``, ``name``, ``description``,
#: ``comment`` and ``min_transmission_deg``; and the entries of a curve task's sections. Guidance, function and
#: path tasks also take ``tolerance`` and ``max_link_ratio`` (what "usable" means: docs/synthesis.md).
CHECKED = {"tolerance", "max_link_ratio"}
ENTRIES = {
    "guidance": {"positions", "circle_points", "centre_points", "circle_x", "slider_directions_deg", "slider"} | CHECKED,
    "function": {"function", "range", "input_deg", "output_deg", "points", "frame", "respace", "start_deg",
                 "rotations_deg", "rocker_pin"} | CHECKED,
    "path": {"points", "crank_deg", "a0", "a1", "b0", "b1", "given", "driver", "route"} | CHECKED,
    "curve": {"scene", "candidates", "input", "point", "wanted", "box", "limits"},
}
COMMON = {"kind", "name", "description", "comment", "min_transmission_deg"}
SECTIONS = {
    "input": {"role", "pivot", "rotation_deg", "guide_deg", "overtravel_deg"},
    "point": {"name", "at"},
    "wanted": {"quantity", "of", "function", "samples", "tolerance", "bound", "over", "over_last", "guide_deg",
               "least"},
    "limits": {"min_transmission_deg", "length"},
}


def check_entries(data, where: str) -> None:
    """Refuse a planar task whose ``kind`` is missing or unknown, or with an entry its kind does not take, naming
    the entry as written and the known one closest to it."""
    if not isinstance(data, dict):
        return
    kinds = (*ENTRIES, *SPATIAL_KINDS)
    if "kind" not in data:
        near = closest("kind", [k for k in data if isinstance(k, str)])
        raise InputError(f"{where}: no 'kind'" + (f" ({near!r} is not an entry: did you mean 'kind'?)" if near else "")
                         + f"; the kinds are {', '.join(kinds)}")
    kind = data["kind"]
    if kind not in ENTRIES:
        near = closest(kind, kinds) if isinstance(kind, str) else None
        raise InputError(f"{where}: kind {kind!r} is not a task kind" + (f" (did you mean {near!r}?)" if near else "")
                         + f"; the kinds are {', '.join(kinds)}")
    check_keys(data, COMMON | ENTRIES[kind], set(), f"{where} ({kind} task)")
    if kind == "curve":
        for section, entries in SECTIONS.items():
            if isinstance(data.get(section), dict):
                check_keys(data[section], entries, set(), f"{where}: {section}")


def load_spatial_task(path: str | Path):
    """A spatial synthesis task (``kind`` spherical-guidance, spherical-function or rccc), or None for a planar one."""
    data = read_json(path)
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
    data = read_json(path)
    check_entries(data, str(path))
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
    result = regenerate(load_scene(scene if task.scene.endswith(".toml") and is_file(scene) else task.scene))
    found = tuple((c.id, c.labelled) for c in result.candidates)
    if wanted == "all":
        return found
    ids = {cid for cid, _ in found}
    if (not isinstance(wanted, list) or not wanted
            or not all(isinstance(k, int) and not isinstance(k, bool) and k in ids for k in wanted)):
        raise InputError(f"{path}: 'candidates' must be \"all\" or a list of the scene's candidate numbers "
                         f"{sorted(ids)}, got {wanted!r}")
    return tuple((cid, c) for cid, c in found if cid in wanted)
