"""Wanted paths on file: points ``x, y`` in CSV (``#`` comments and one header line allowed) or JSON.

JSON is either a list of ``[x, y]`` pairs or an object with ``"points"``
(and optionally ``"closed"``, true by default). Every value must be a finite
number, at most 1e50 in size; an error names the file, the line (CSV) or the
entry (JSON). A drawn path's timing (:func:`read_timing`) is a third CSV
column headed ``angle`` (the crank's angle, degrees) or ``time``, or a JSON
object's ``"angles"`` or ``"times"`` list (with ``"speed"``, degrees per
unit of time, optional for times).

>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "path.csv")
>>> _ = open(path, "w").write("x,y\\n0,0\\n1,0\\n1,1\\n")
>>> read_points(path).tolist()
[[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]
"""

from __future__ import annotations

import csv
import io
import math
from pathlib import Path

import numpy as np

from domes.errors import InputError, shown
from domes.io.files import read_json, read_text
from domes.model.fields import LARGEST, read_list, read_number, read_xy


def read_points(path: str | Path) -> np.ndarray:
    """The ``(n, 2)`` points of a wanted path (CSV or JSON, chosen by the file's suffix or its first character)."""
    return read_path(path)[0]


def read_path(path: str | Path) -> tuple[np.ndarray, bool | None]:
    """The points of a wanted path and whether the file says it is closed (JSON ``"closed"``; else None)."""
    path = Path(path)
    text = read_text(path)
    if path.suffix.lower() == ".json" or text.lstrip().startswith(("[", "{")):
        return _from_json(path, text)
    return _from_csv(path, text), None


def _from_csv(path, text):
    rows = []
    header = False
    for number, row in enumerate(csv.reader(io.StringIO(text)), 1):
        cells = [c.strip() for c in row if c.strip()]
        if not cells or cells[0].startswith("#"):
            continue
        if len(cells) < 2:
            raise InputError(f"{path}, line {number}: expected two numbers x, y, got {row!r}")
        try:
            x, y = float(cells[0]), float(cells[1])
        except ValueError:
            if not rows and not header:
                header = True
                continue  # the header line
            raise InputError(f"{path}, line {number}: {cells[0]!r}, {cells[1]!r} are not numbers") from None
        if not (math.isfinite(x) and math.isfinite(y)):
            raise InputError(f"{path}, line {number}: the point ({x}, {y}) is not finite")
        if max(abs(x), abs(y)) > LARGEST:
            raise InputError(f"{path}, line {number}: the point ({x:g}, {y:g}) is too far out (coordinates at most "
                             f"{LARGEST:g} in size)")
        rows.append((x, y))
    if not rows:
        raise InputError(f"{path}: no points (expected lines of x, y)")
    return np.array(rows)


def _from_json(path, text):
    doc = read_json(path, text)
    pts = doc.get("points") if isinstance(doc, dict) else doc
    closed = doc.get("closed") if isinstance(doc, dict) else None
    if closed is not None and not isinstance(closed, bool):
        raise InputError(f"{path}: \"closed\" must be true or false, got {closed!r}")
    if not isinstance(pts, list) or not pts:
        raise InputError(f"{path}: expected a list of [x, y] points (or an object with \"points\")")
    out = []
    for k, p in enumerate(pts):
        if not (isinstance(p, (list, tuple)) and len(p) == 2):
            raise InputError(f"{path}: point {k} must be [x, y] with two numbers, got {shown(p)}")
        out.append(read_xy(p, f"{path}: point {k}"))
    return np.array(out), closed


#: A CSV column's heading that makes it a timing: crank angles (degrees) or times.
TIMING_COLUMNS = {"angle": "angle", "angle_deg": "angle", "crank_deg": "angle", "time": "time", "t": "time"}


def read_timing(path: str | Path) -> tuple[str, list[float], float | None] | None:
    """``(kind, values, speed)``: the timing a path's file gives (``kind`` "angle" or "time", one value per point,
    the crank's speed in degrees per unit of time or None), or None when it gives none.

    >>> import tempfile, os
    >>> path = os.path.join(tempfile.mkdtemp(), "path.csv")
    >>> _ = open(path, "w").write("x,y,time\\n0,0,0\\n1,0,0.5\\n")
    >>> read_timing(path)
    ('time', [0.0, 0.5], None)
    """
    path = Path(path)
    text = read_text(path)
    if path.suffix.lower() == ".json" or text.lstrip().startswith(("[", "{")):
        doc = read_json(path, text)
        if not isinstance(doc, dict):
            return None
        given = [k for k in ("angles", "times") if k in doc]
        if len(given) > 1:
            raise InputError(f"{path}: give \"angles\" or \"times\", not both")
        if not given:
            if "speed" in doc:
                raise InputError(f"{path}: \"speed\" goes with \"times\", which the file does not give")
            return None
        values = read_list(doc[given[0]], f"{path}: \"{given[0]}\"")
        values = [read_number(v, f"{path}: {given[0]}[{k}]", LARGEST) for k, v in enumerate(values)]
        speed = doc.get("speed")
        if speed is not None:
            if given[0] != "times":
                raise InputError(f"{path}: \"speed\" goes with \"times\", not with \"angles\"")
            speed = read_number(speed, f"{path}: \"speed\"", LARGEST)
        return ("angle" if given[0] == "angles" else "time"), values, speed
    kind, values = None, []
    for number, row in enumerate(csv.reader(io.StringIO(text)), 1):
        cells = [c.strip() for c in row if c.strip()]
        if not cells or cells[0].startswith("#"):
            continue
        if kind is None and not values:
            if _numbers(cells[:2]):
                return None                                     # no heading: no timing
            if len(cells) < 3 or cells[2].lower() not in TIMING_COLUMNS:
                return None
            kind = TIMING_COLUMNS[cells[2].lower()]
            continue
        if len(cells) < 3:
            raise InputError(f"{path}, line {number}: no {kind} (the third column) for the point {row!r}")
        try:
            v = float(cells[2])
        except ValueError:
            raise InputError(f"{path}, line {number}: the {kind} {cells[2]!r} is not a number") from None
        if not math.isfinite(v) or abs(v) > LARGEST:
            raise InputError(f"{path}, line {number}: the {kind} {cells[2]} is not a finite number at most "
                             f"{LARGEST:g} in size")
        values.append(v)
    return (kind, values, None) if kind else None


def _numbers(cells) -> bool:
    try:
        [float(c) for c in cells]
    except ValueError:
        return False
    return True


def points_csv(points, header: str = "x,y") -> str:
    """Points as CSV text (full precision)."""
    lines = [header] + [f"{x!r},{y!r}" for x, y in np.asarray(points, dtype=float).tolist()]
    return "\n".join(lines) + "\n"
