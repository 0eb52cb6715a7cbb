"""Reading the fields of the mechanism file format: numbers, points and objects, each error naming its place.

>>> read_xy([1, 2], "joints[0].at")
(1.0, 2.0)
>>> read_number("x", "joints[0].direction")
Traceback (most recent call last):
...
domes.errors.InputError: joints[0].direction: expected a finite number, got 'x'
"""

from __future__ import annotations

import math

from domes.errors import InputError

Point2 = tuple[float, float]


def read_number(value, where: str) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        raise InputError(f"{where}: expected a finite number, got {value!r}")
    return float(value)


def read_xy(value, where: str) -> Point2:
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(f"{where}: expected [x, y], got {value!r}")
    return read_number(value[0], f"{where}[0]"), read_number(value[1], f"{where}[1]")


def check_keys(obj, allowed: set[str], required: set[str], where: str) -> None:
    if not isinstance(obj, dict):
        raise InputError(f"{where}: expected an object, got {type(obj).__name__}")
    unknown = set(obj) - allowed
    if unknown:
        raise InputError(f"{where}: unknown field(s) {sorted(unknown)}; allowed: {sorted(allowed)}")
    missing = required - set(obj)
    if missing:
        raise InputError(f"{where}: missing field(s) {sorted(missing)}")


__all__ = ["check_keys", "read_number", "read_xy"]
