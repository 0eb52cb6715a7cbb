"""Reading the fields of the mechanism file format: numbers, points and objects, each error naming its place.

>>> read_xy([1, 2], "joints[0].at")
(1.0, 2.0)
>>> read_number("x", "joints[0].direction")
Traceback (most recent call last):
...
domes.errors.InputError: joints[0].direction: expected a finite number, got 'x'
"""

from __future__ import annotations

import difflib
import math

from domes.errors import InputError, shown

Point2 = tuple[float, float]
#: The largest size of a coordinate or a vector's component in a file: far beyond any drawing's, and small enough
#: that the products of a few of them (lengths squared, forces times lengths) stay within a float's range.
LARGEST = 1e50
#: The values of a mechanism file's ``space``: a planar file may leave it out, a spatial one says ``spatial``.
SPACES = ("planar", "spatial")


def read_number(value, where: str, largest: float = math.inf) -> float:
    """The finite number ``value`` of the field ``where``, as a float, at most ``largest`` in size; an integer too
    large for a float is refused.

    >>> read_number(10 ** 400, "inputs[0].speed")
    Traceback (most recent call last):
    ...
    domes.errors.InputError: inputs[0].speed: expected a finite number, got an integer of 401 digits (too large)
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(f"{where}: expected a finite number, got {shown(value)}")
    try:
        number = float(value)
    except OverflowError:
        raise InputError(f"{where}: expected a finite number, got an integer of {len(str(abs(value))):,} digits "
                         "(too large)") from None
    if not math.isfinite(number):
        raise InputError(f"{where}: expected a finite number, got {value!r}")
    if abs(number) > largest:
        raise InputError(f"{where}: {number:g} is too large (at most {largest:g} in size)")
    return number


def read_list(value, where: str) -> list:
    """The list ``value`` of the field ``where`` (a JSON array)."""
    if not isinstance(value, list):
        raise InputError(f"{where}: expected a list, got {shown(value)}")
    return value


def read_xy(value, where: str) -> Point2:
    """A point or vector ``[x, y]``, each number at most :data:`LARGEST` in size."""
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(f"{where}: expected [x, y], got {shown(value)}")
    return read_number(value[0], f"{where}[0]", LARGEST), read_number(value[1], f"{where}[1]", LARGEST)


def closest(key: str, known) -> str | None:
    """The name in ``known`` closest to a misspelt ``key`` (difflib's ratio of at least 0.6), or None.

    >>> closest("joins", ["links", "joints", "inputs"]), closest("xyz", ["links"])
    ('joints', None)
    """
    found = difflib.get_close_matches(str(key), sorted(known), n=1)
    return found[0] if found else None


def check_space(data, wanted: str, where: str) -> None:
    """Refuse a mechanism file whose ``space`` is not ``wanted`` (``planar`` may be left out), naming the value
    and the spaces there are.

    >>> check_space({"space": "plane"}, "spatial", "rssr.json")
    Traceback (most recent call last):
    ...
    domes.errors.InputError: rssr.json: space: 'plane' is not a space (did you mean 'planar'?); the spaces are 'planar' and 'spatial'
    """
    if not isinstance(data, dict):
        return
    space = data.get("space", "planar")
    if space == wanted:
        return
    if space in SPACES:
        raise InputError(f"{where}: space: {wanted!r} for a {wanted} mechanism file, got {space!r} (a {space} one)")
    near = closest(space, SPACES) if isinstance(space, str) else None
    raise InputError(f"{where}: space: {space!r} is not a space" + (f" (did you mean {near!r}?)" if near else "")
                     + f"; the spaces are {' and '.join(map(repr, SPACES))}")


def check_keys(obj, allowed: set[str], required: set[str], where: str) -> None:
    """Refuse an object with a field not in ``allowed`` (naming it, and the allowed field it is closest to) or
    without one of ``required``.

    >>> check_keys({"joins": []}, {"links", "joints"}, {"links", "joints"}, "four-bar.json")
    Traceback (most recent call last):
    ...
    domes.errors.InputError: four-bar.json: unknown field(s) ['joins'] (did you mean 'joints'?); allowed: ['joints', 'links']
    """
    if not isinstance(obj, dict):
        raise InputError(f"{where}: expected an object, got {type(obj).__name__}")
    unknown = sorted(set(obj) - allowed, key=str)
    if unknown:
        unused = allowed - set(obj)
        guesses = {k: closest(k, unused) or closest(k, allowed) for k in unknown}
        guesses = {k: g for k, g in guesses.items() if g}
        hint = ""
        if len(unknown) == 1 and guesses:
            hint = f" (did you mean {guesses[unknown[0]]!r}?)"
        elif guesses:
            hint = f" (did you mean {', '.join(f'{g!r} for {k!r}' for k, g in guesses.items())}?)"
        raise InputError(f"{where}: unknown field(s) {unknown}{hint}; allowed: {sorted(allowed)}")
    missing = required - set(obj)
    if missing:
        raise InputError(f"{where}: missing field(s) {sorted(missing)}")


__all__ = ["LARGEST", "SPACES", "check_keys", "check_space", "closest", "read_list", "read_number", "read_xy"]
