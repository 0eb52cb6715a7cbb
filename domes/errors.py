"""Errors raised by DOMES-py: one hierarchy, three kinds of failure.

* :class:`InputError` -- the input is wrong (a file, an argument, a value):
  the message says what and where, and what to do instead;
* :class:`NumericalError` -- the input is fine but the numbers cannot be
  trusted or found (a dead point, a singular Jacobian, no convergence): the
  message names the place, and the exception carries the diagnostics
  (``kind``, ``residual``, ``condition``, ``where``);
* :class:`NothingToPropose` -- a stage ran correctly and found no candidate
  (a scene stage whose rules hold on no chain).

None of them is a :class:`ValueError`: a dead point is not bad input. The
command line prints the message of any :class:`DomesError` and exits with
status 2.

>>> raise InputError("links must be >= 2, got 1")
Traceback (most recent call last):
...
domes.errors.InputError: links must be >= 2, got 1
>>> issubclass(NumericalError, ValueError), issubclass(NumericalError, DomesError)
(False, True)

A message never echoes a whole long value: :func:`shown` cuts a value short
where a message names it, and a line longer than :data:`MAX_LINE` characters
is cut in its middle, its start (what and where) and end kept.

>>> shown("x" * 1000)
"'xxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxxx... (1,002 characters)"
>>> len(str(InputError("names: " + "y" * 100_000)))
400
"""

from __future__ import annotations

import math
from typing import Any, Mapping

#: The longest line of an error message; a longer one is cut in its middle.
MAX_LINE = 400
#: The most lines of an error message; the lines past them are left out.
MAX_LINES = 40


def shown(value: Any, limit: int = 60) -> str:
    """``repr(value)`` for a message, cut to about ``limit`` characters with its length said."""
    text = repr(value)
    if len(text) <= limit:
        return text
    return f"{text[:max(limit - 6, 10)]}... ({len(text):,} characters)"


def _cut(message: str) -> str:
    lines = message.split("\n")
    if len(lines) > MAX_LINES:
        lines = lines[:MAX_LINES - 1] + [f"... ({len(lines) - MAX_LINES + 1:,} more lines)"]
    out = []
    for line in lines:
        if len(line) > MAX_LINE:
            left = f" ... ({len(line):,} characters; cut) ... "
            tail = MAX_LINE // 5
            line = line[:MAX_LINE - tail - len(left)] + left + line[-tail:]
        out.append(line)
    return "\n".join(out)


class DomesError(Exception):
    """Every error DOMES-py raises on purpose; the message says what and where (cut to a readable length)."""

    def __init__(self, message: Any = "", *args: Any):
        super().__init__(_cut(message) if isinstance(message, str) else message, *args)


class InputError(DomesError):
    """Bad input to DOMES-py: the message says what was wrong, where, and what to do."""


class NumericalError(DomesError):
    """A numerical failure, with the numbers that show it.

    ``kind`` names the failure (e.g. ``limit``, ``undetermined``, ``newton``,
    ``jump``); ``residual`` and ``condition`` are the last loop-closure
    residual and condition number known (NaN when not known); ``where`` holds
    what locates it (a group, joints, an input value).

    >>> e = NumericalError("Jacobian singular", kind="newton", condition=math.inf, where={"joints": ("B", "C")})
    >>> e.kind, e.condition, e.where["joints"]
    ('newton', inf, ('B', 'C'))
    """

    def __init__(
        self,
        message: str,
        *,
        kind: str = "numerical",
        residual: float = math.nan,
        condition: float = math.nan,
        where: Mapping[str, Any] | None = None,
    ):
        super().__init__(message)
        self.kind = kind
        self.residual = residual
        self.condition = condition
        self.where = dict(where or {})


class NothingToPropose(DomesError):
    """A stage found no candidate to propose; the message says which rule or criterion left none."""
