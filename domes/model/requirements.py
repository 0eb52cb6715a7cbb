"""Requirements of a design problem, each with its unit: the requirement list of seed 002, ch. 1 (§5.5 of the
digest: stroke, force or torque, speed, dimensions, accuracy...), as asked in a design session.

A scene declares what it asks (:class:`RequirementSpec`: an id, what it is, its kind, its unit and a
default); the designer answers in any unit of the same dimension, and the answer is kept as a
:class:`Requirement` in the spec's unit, beside the text as written. Kinds:

* ``quantity``: one number, e.g. ``0.3 m``, ``300 mm``, ``60 N/mm``, ``1500 rpm``, ``2 %``;
* ``range``: ``LOW .. HIGH`` (or ``LOW to HIGH``), e.g. ``250 .. 450 mm``;
* ``point``: ``X, Y``, e.g. ``0.55, -0.06 m``;
* ``box``: ``X0 .. X1, Y0 .. Y1``, e.g. ``-0.15 .. 0.45, -0.2 .. 0.4 m``;
* ``function``: an expression of ``x`` (checked by the stage that uses it), e.g. ``3.1 - 2.8*x``.

A number without a unit is in the spec's unit; a unit may follow each number or only the last. Units are
parsed and converted by pint (imported when first needed), never guessed: a force where a length is
wanted is refused with both named.

:func:`fill` puts answers into a template (a scene's synthesis task): a string ``"{ID}"`` becomes the
value of requirement ``ID`` in its spec's unit, ``"{ID:UNIT}"`` in ``UNIT``.

>>> spec = RequirementSpec("travel", "wheel travel", "quantity", "m", "0.3 m")
>>> r = spec.parse("283 mm")
>>> r.value, r.shown
(0.283, '0.283 m')
>>> fill({"stroke": "{travel:mm}", "ratio": 2}, {"travel": r})
{'stroke': 283.0, 'ratio': 2}
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import Any, Mapping

from domes.errors import InputError

KINDS = ("quantity", "range", "point", "box", "function")
#: How many numbers each kind holds (a function holds text).
_COUNTS = {"quantity": 1, "range": 2, "point": 2, "box": 4}
_NUMBER = r"[-+]?(?:\d+(?:\.\d*)?|\.\d+)(?:[eE][-+]?\d{1,3})?"
_PIECE = re.compile(rf"^\s*({_NUMBER})\s*(.*?)\s*$")
_UNIT = re.compile(r"^[A-Za-z°µ%][A-Za-z0-9°µ%/*·^ _\-()]{0,39}$")
_ID = re.compile(r"^[a-z][a-z0-9_]{0,39}$")
_PLACEHOLDER = re.compile(r"^\{([a-z][a-z0-9_]*)(?::([^{}]+))?\}$")


@lru_cache(maxsize=1)
def _registry():
    import pint

    return pint.UnitRegistry(cache_folder=None)


def _unit(text: str, where: str):
    """A pint unit from its name, refused with a message when it is not one."""
    text = text.strip().replace("·", "*")
    if text in ("", "1"):
        return _registry().dimensionless
    if not _UNIT.match(text):
        raise InputError(f"{where}: {text!r} is not a unit (e.g. m, mm, deg, N, N*m, N/mm, rpm, s, %)")
    try:
        return _registry().Unit(text)
    except Exception:  # noqa: BLE001 - pint raises several kinds (UndefinedUnitError, DefinitionSyntaxError, ...)
        raise InputError(f"{where}: unknown unit {text!r} (e.g. m, mm, deg, N, N*m, N/mm, rpm, s, %)") from None


#: Units of angle: pint counts them as plain numbers, an answer may not mix them with percentages or counts.
ANGLES = {"radian", "degree", "arcminute", "arcsecond", "turn", "revolution", "grade"}


def _is_angle(unit) -> bool:
    return str(unit) in ANGLES


def convert(value: float, unit: str, to: str, where: str = "requirement") -> float:
    """``value`` in ``unit`` expressed in ``to`` (both unit names); different dimensions are refused.

    >>> convert(60, "N/mm", "N/m")
    60000.0
    """
    source, target = _unit(unit, where), _unit(to, where)
    if _is_angle(source) != _is_angle(target) and unit.strip() not in ("", "1"):
        raise InputError(f"{where}: {unit} cannot be expressed in {to} (expected {_dimension(to)})")
    try:
        out = float(_registry().Quantity(value, source).to(target).magnitude)
    except Exception:  # noqa: BLE001 - pint's DimensionalityError
        raise InputError(f"{where}: {unit or 'a plain number'} cannot be expressed in {to or 'a plain number'} "
                         f"(expected {_dimension(to)})") from None
    if not math.isfinite(out):
        raise InputError(f"{where}: {value:g} {unit} is too large to use")
    return float(f"{out:.15g}")  # 283 mm is 0.283 m, not 0.28300000000000003


def _dimension(unit: str) -> str:
    """What a unit measures, in words: ``a length (like m)``."""
    names = {"[length]": "a length", "[force]": "a force", "[length] * [force]": "a torque",
             "[force] / [length]": "a stiffness", "1 / [time]": "a speed", "[time]": "a time",
             "dimensionless": "a plain number or a percentage", "[mass]": "a mass"}
    if unit not in ("", "1") and _is_angle(_unit(unit, "unit")):
        return f"an angle (like {unit})"
    dim = _registry().get_dimensionality(_unit(unit, "unit")) if unit not in ("", "1") else None
    text = "dimensionless" if not dim else str(dim)
    aliases = {"[length] * [mass] / [time] ** 2": "[force]", "[length] ** 2 * [mass] / [time] ** 2": "[length] * [force]",
               "[mass] / [time] ** 2": "[force] / [length]"}
    text = aliases.get(text, text)
    return f"{names.get(text, 'a quantity in ' + text)} (like {unit or 'a plain number'})"


@dataclass(frozen=True)
class Requirement:
    """One requirement as answered: its ``value`` in ``unit`` (a number, numbers, or the text of a function),
    the ``text`` as the designer wrote it, and what it is (``label``)."""

    id: str
    kind: str
    value: Any
    unit: str = ""
    text: str = ""
    label: str = ""

    @property
    def shown(self) -> str:
        """The value with its unit, as a report shows it: ``0.25 .. 0.45 m``."""
        if self.kind == "function":
            return str(self.value)
        g = lambda v: f"{v:.6g}"  # noqa: E731
        v = self.value
        text = {"quantity": lambda: g(v), "range": lambda: f"{g(v[0])} .. {g(v[1])}",
                "point": lambda: f"{g(v[0])}, {g(v[1])}",
                "box": lambda: f"{g(v[0][0])} .. {g(v[0][1])}, {g(v[1][0])} .. {g(v[1][1])}"}[self.kind]()
        return f"{text} {self.unit if self.unit != '1' else ''}".strip()

    def value_in(self, unit: str | None = None):
        """The value in ``unit`` (None: its own): a number, a pair, or ``((x0, x1), (y0, y1))`` for a box."""
        if self.kind == "function" or unit is None or unit == self.unit:
            return self.value
        c = lambda x: convert(x, self.unit, unit, f"requirement {self.id}")  # noqa: E731
        if self.kind == "quantity":
            return c(self.value)
        if self.kind == "box":
            return tuple(tuple(c(x) for x in side) for side in self.value)
        return tuple(c(x) for x in self.value)

    def to_dict(self) -> dict:
        value = [list(side) for side in self.value] if self.kind == "box" else (
            list(self.value) if isinstance(self.value, tuple) else self.value)
        return {"id": self.id, "kind": self.kind, "value": value, "unit": self.unit, "text": self.text,
                "label": self.label}

    @classmethod
    def from_dict(cls, data: Mapping, where: str = "requirement") -> "Requirement":
        """From plain data (a stored problem frame); errors name the field."""
        if not isinstance(data, Mapping) or not isinstance(data.get("id"), str) or data.get("kind") not in KINDS:
            raise InputError(f"{where}: expected {{'id', 'kind' (one of {', '.join(KINDS)}), 'value', 'unit'}}")
        kind, value = data["kind"], data.get("value")
        try:
            if kind == "function":
                value = str(value)
            elif kind == "quantity":
                value = float(value)
            elif kind == "box":
                value = tuple(tuple(float(x) for x in side) for side in value)
                if len(value) != 2 or any(len(side) != 2 for side in value):
                    raise ValueError
            else:
                value = tuple(float(x) for x in value)
                if len(value) != 2:
                    raise ValueError
        except (TypeError, ValueError):
            raise InputError(f"{where} {data['id']!r}: the value {value!r} is not a {kind}") from None
        return cls(data["id"], kind, value, str(data.get("unit", "")), str(data.get("text", "")),
                   str(data.get("label", "")))


@dataclass(frozen=True)
class RequirementSpec:
    """A requirement a scene asks for: ``id``, what it is (``label``), ``kind`` (:data:`KINDS`), the ``unit``
    its value is kept in, the ``default`` answer and a ``help`` text."""

    id: str
    label: str
    kind: str
    unit: str = ""
    default: str = ""
    help: str = ""

    def __post_init__(self):
        if not _ID.match(self.id):
            raise InputError(f"requirement id {self.id!r}: lower-case letters, digits and '_', starting with a letter")
        if self.kind not in KINDS:
            raise InputError(f"requirement {self.id!r}: kind must be one of {', '.join(KINDS)}, got {self.kind!r}")
        if self.kind != "function":
            _unit(self.unit, f"requirement {self.id!r}")
        if self.default:
            self.parse(self.default)

    def parse(self, text: str) -> Requirement:
        """The designer's answer as a :class:`Requirement` in this spec's unit; a bad one says what is expected.

        >>> RequirementSpec("box", "envelope", "box", "m").parse("-150 .. 450, -200 .. 400 mm").value
        ((-0.15, 0.45), (-0.2, 0.4))
        """
        text = str(text).strip()
        where = f"{self.label or self.id}"
        if len(text) > 200:
            raise InputError(f"{where}: an answer of {len(text)} characters; at most 200")
        if self.kind == "function":
            if not text:
                raise InputError(f"{where}: give a function of x, e.g. {self.default or '3.1 - 2.8*x'}")
            return Requirement(self.id, self.kind, text, "", text, self.label)
        pieces = _split(text, self.kind)
        count = _COUNTS[self.kind]
        if len(pieces) != count:
            raise InputError(f"{where}: expected {self.example()}, got {text!r}")
        parsed = []
        for piece in pieces:
            match = _PIECE.match(piece)
            if not match:
                raise InputError(f"{where}: {piece.strip()!r} is not a number with an optional unit; expected "
                                 f"{self.example()}")
            parsed.append((float(match.group(1)), match.group(2)))
        last = next((u for _, u in reversed(parsed) if u), "")
        values = []
        for number, unit in parsed:
            if not math.isfinite(number):
                raise InputError(f"{where}: {number} is not a finite number")
            values.append(convert(number, unit or last or self.unit, self.unit, where))
        if self.kind == "range" and not values[0] < values[1]:
            raise InputError(f"{where}: the range {text!r} must go from a lower to a higher value")
        if self.kind == "box":
            if not (values[0] < values[1] and values[2] < values[3]):
                raise InputError(f"{where}: the box {text!r} must give X0 < X1 and Y0 < Y1")
            value = ((values[0], values[1]), (values[2], values[3]))
        else:
            value = values[0] if count == 1 else tuple(values)
        return Requirement(self.id, self.kind, value, self.unit, text, self.label)

    def example(self) -> str:
        """What an answer looks like, from the default or the kind."""
        shape = {"quantity": "a number", "range": "LOW .. HIGH", "point": "X, Y", "box": "X0 .. X1, Y0 .. Y1",
                 "function": "a function of x"}[self.kind]
        unit = f" with a unit like {self.unit}" if self.unit and self.kind != "function" else ""
        return f"{shape}{unit}" + (f" (e.g. {self.default})" if self.default else "")

    def to_dict(self) -> dict:
        return {"id": self.id, "label": self.label, "kind": self.kind, "unit": self.unit, "default": self.default,
                "help": self.help}


def _split(text: str, kind: str) -> list[str]:
    """The pieces of an answer: numbers with their units, split at ',', '..', ' to ' and ':'."""
    if kind == "quantity":
        return [text]
    if kind == "point":
        return [p for p in text.split(",")]
    if kind == "range":
        return [p for p in re.split(r"\.\.|\bto\b|:", text)]
    sides = text.split(",")
    return [p for side in sides for p in re.split(r"\.\.|\bto\b|:", side)]


_INSIDE = re.compile(r"\{([a-z][a-z0-9_]*)(?::([^{}]+))?\}")


def placeholders(template) -> set[tuple[str, str | None]]:
    """Every ``("ID", "UNIT" or None)`` a template's strings name (``{ID}`` or ``{ID:UNIT}``, whole or inside)."""
    found = set()
    if isinstance(template, str):
        found |= {(m.group(1), m.group(2)) for m in _INSIDE.finditer(template)}
    elif isinstance(template, Mapping):
        for v in template.values():
            found |= placeholders(v)
    elif isinstance(template, (list, tuple)):
        for v in template:
            found |= placeholders(v)
    return found


def fill(template, requirements: Mapping[str, Requirement]):
    """``template`` with its placeholders replaced by the requirements' values: a string that is one
    placeholder (``"{ID}"``, ``"{ID:UNIT}"``) becomes the value (a number, lists for pairs and boxes, the text
    of a function); a placeholder inside a longer string (a function such as ``"{travel:m} * x / 150"``)
    becomes the number written out.

    >>> r = RequirementSpec("travel", "window travel", "quantity", "m").parse("400 mm")
    >>> fill({"function": "{travel:m} * x / 150"}, {"travel": r})
    {'function': '(0.4) * x / 150'}
    """
    if isinstance(template, str):
        match = _PLACEHOLDER.match(template)
        if match:
            value = _value(match, requirements)
            if isinstance(value, tuple):
                return [list(v) if isinstance(v, tuple) else v for v in value]
            return value

        def number(m):
            value = _value(m, requirements)
            if not isinstance(value, float):
                raise InputError(f"the template writes requirement {m.group(1)!r} inside {template!r}: only a single "
                                 "quantity can be written inside text")
            return f"({value!r})"

        return _INSIDE.sub(number, template)
    if isinstance(template, Mapping):
        return {k: fill(v, requirements) for k, v in template.items()}
    if isinstance(template, (list, tuple)):
        return [fill(v, requirements) for v in template]
    return template


def _value(match, requirements):
    rid, unit = match.groups()
    if rid not in requirements:
        raise InputError(f"the template names requirement {rid!r}, which was not answered "
                         f"(answered: {', '.join(sorted(requirements)) or 'none'})")
    return requirements[rid].value_in(unit)
