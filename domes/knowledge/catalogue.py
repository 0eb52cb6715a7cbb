"""The catalogue of standard mechanisms as knowledge: what each converts, and requirements on what it does.

Seed 002's system search (ch. 1: every mechanism for a motion conversion,
e.g. rotation → reciprocation by slider-crank, sine, tangent and cam
mechanisms) and the second class of problems of §5-1 (a function by motion
mode: constant ratio → gears, straight line → linkage, intermittent →
Geneva) look mechanisms up by the motion they turn one into another and by
what they must do. An :class:`Entry` says the first; a
:class:`Requirement` (``"dwell >= 90"``) the second, checked against the
properties measured on the entry's model (:mod:`domes.design.catalogue`).
A :class:`Heuristic` (§6-1) says which families of mechanisms suit a
function best (an exact law: rigid mechanisms, the cam the simplest), and
:func:`choose` picks the one a problem states or its requirements imply.

>>> r = requirement("dwell >= 90°")
>>> r.name, r.op, r.value, r.met(270.0)
('dwell', '>=', 90.0, True)
>>> motion_pair("rotation -> intermittent rotation")
('rotation', 'intermittent rotation')
>>> h = Heuristic("exact", ("cam", "intermittent"), "only rigid mechanisms hold it", "seed 002 §6-1", ("dwell",))
>>> choose([h], None, ("rotation", "reciprocation"), [r]) is h, h.rank("intermittent"), h.rank("linkage")
(True, 1, 2)
"""

from __future__ import annotations

import math
import operator
import re
from dataclasses import dataclass, field

from domes.errors import InputError

#: The motions an entry converts (in → out).
MOTIONS = ("rotation", "oscillation", "reciprocation", "intermittent rotation", "straight line")
#: The models the catalogue measures: a mechanism file, or a closed form.
MODELS = ("mechanism", "geneva", "cam")
#: The families of mechanisms §6-1's heuristics rank (an entry's ``family``).
FAMILIES = ("cam", "linkage", "gears", "gear-linkage", "intermittent", "cylinder", "variator")
#: The functions §6-1 tells apart (:class:`Heuristic`).
FUNCTIONS = ("exact", "approximate", "end positions", "constant ratio", "speed regulation")
OPS = {">=": operator.ge, "<=": operator.le, ">": operator.gt, "<": operator.lt, "=": lambda a, b: math.isclose(a, b)}


@dataclass(frozen=True)
class Entry:
    """A standard mechanism: ``name``, ``motion`` (in, out), its ``model`` (a kind, a mechanism or parameters),
    the ``measure`` that shows its property, its ``source`` and a one-line ``description``."""

    name: str
    motion: tuple[str, str]
    model: str
    measure: dict
    source: str = ""
    description: str = ""
    mechanism: object = None
    parameters: dict = field(default_factory=dict)
    family: str = "linkage"

    def __post_init__(self):
        if len(self.motion) != 2 or any(m not in MOTIONS for m in self.motion):
            raise InputError(f"{self.name}: motion must be [input, output] from {', '.join(MOTIONS)}, got "
                             f"{list(self.motion)!r}")
        if self.model not in MODELS:
            raise InputError(f"{self.name}: model must be one of {', '.join(MODELS)}, got {self.model!r}")
        if self.model == "mechanism" and self.mechanism is None:
            raise InputError(f"{self.name}: a mechanism model needs its mechanism")
        if self.family not in FAMILIES:
            raise InputError(f"{self.name}: family must be one of {', '.join(FAMILIES)}, got {self.family!r}")


def motion_pair(text: str) -> tuple[str, str]:
    """``(input, output)`` from ``"rotation -> straight line"`` (or ``→``, ``to``); an InputError lists the motions."""
    parts = [p.strip().lower() for p in re.split(r"\s*(?:->|→|\bto\b)\s*", str(text)) if p.strip()]
    if len(parts) != 2:
        raise InputError(f"a motion conversion reads 'INPUT -> OUTPUT' (e.g. 'rotation -> straight line'), got {text!r}")
    for p in parts:
        if p not in MOTIONS:
            raise InputError(f"unknown motion {p!r}: use {', '.join(MOTIONS)}")
    return parts[0], parts[1]


@dataclass(frozen=True)
class Requirement:
    """``name op value``: a property the mechanism must have (its unit is the property's own)."""

    name: str
    op: str
    value: float

    def met(self, measured: float) -> bool:
        return bool(OPS[self.op](measured, self.value))

    def __str__(self) -> str:
        return f"{self.name} {self.op} {self.value:g}"


def requirement(text: str) -> Requirement:
    """A requirement from ``"NAME OP NUMBER [UNIT]"`` (``>=``, ``<=``, ``>``, ``<``, ``=``, ``≥``, ``≤``).

    >>> str(requirement("time ratio ≥ 1.5"))
    'time ratio >= 1.5'
    """
    t = str(text).replace("≥", ">=").replace("≤", "<=")
    m = re.fullmatch(r"\s*([A-Za-z][A-Za-z -]*?)\s*(>=|<=|>|<|=)\s*([-+0-9.eE]+)\s*(°|deg|degrees|%)?\s*", t)
    if not m:
        raise InputError(f"a requirement reads 'NAME OP NUMBER' (e.g. 'dwell >= 90', 'straight-line deviation <= "
                         f"0.5%'), got {text!r}")
    try:
        value = float(m.group(3))
    except ValueError:
        raise InputError(f"requirement {text!r}: {m.group(3)!r} is not a number") from None
    if not math.isfinite(value):
        raise InputError(f"requirement {text!r}: the number must be finite")
    return Requirement(" ".join(m.group(1).lower().split()), m.group(2), value)


@dataclass(frozen=True)
class Heuristic:
    """Seed 002 §6-1: for a ``function`` (one of :data:`FUNCTIONS`), the families to ``prefer``, in order, and
    why; it applies to the ``outputs`` motions only (empty: any) and is implied by requirements on the
    properties named in ``implied_by`` (a dwell: an exact law)."""

    function: str
    prefer: tuple[str, ...]
    reason: str
    source: str = ""
    implied_by: tuple[str, ...] = ()
    outputs: tuple[str, ...] = ()

    def __post_init__(self):
        if self.function not in FUNCTIONS:
            raise InputError(f"function must be one of {', '.join(FUNCTIONS)}, got {self.function!r}")
        bad = [f for f in self.prefer if f not in FAMILIES] or [m for m in self.outputs if m not in MOTIONS]
        if bad or not self.prefer:
            raise InputError(f"{self.function}: prefer lists families of {', '.join(FAMILIES)} (at least one) and "
                             f"outputs motions of {', '.join(MOTIONS)}, got {bad[0] if bad else 'no family'!r}")

    def applies(self, motion) -> bool:
        return not self.outputs or motion[1] == "any" or motion[1] in self.outputs

    def rank(self, family: str) -> int:
        """The place of ``family`` in :attr:`prefer` (0 first); families not listed come after them all."""
        return self.prefer.index(family) if family in self.prefer else len(self.prefer)

    def advice(self, family: str) -> str:
        """Where ``family`` stands for this function and why, with the source."""
        k = self.rank(family)
        place = f"choice {k + 1} of" if k < len(self.prefer) else "not among"
        return f"{self.function}: {family} is {place} {', '.join(self.prefer)}; {self.reason} ({self.source})"


def choose(heuristics, function, motion, requirements=()) -> Heuristic | None:
    """The heuristic for ``function`` (None: the first implied by a requirement's name) that applies to
    ``motion``; None when there is none."""
    if function is not None and function not in FUNCTIONS:
        raise InputError(f"unknown function {function!r}: use {', '.join(FUNCTIONS)}")
    fits = [h for h in heuristics if h.applies(motion)]
    if function is not None:
        return next((h for h in fits if h.function == function), None)
    for r in requirements:
        found = next((h for h in fits if r.name in h.implied_by), None)
        if found is not None:
            return found
    return None
