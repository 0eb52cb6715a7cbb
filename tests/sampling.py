"""How many random cases the large round-trip tests draw.

The acceptance tests of the synthesis and the coupler-curve look-up draw 200 random four-bars each (issues 13
and 14); at about 1.5 s a case, two of them took ten minutes of every test run. By default they draw the first
:data:`SAMPLE` of the same seeded stream, with the same share allowed to miss; ``DOMES_FULL_TESTS=1`` draws all
200, as a nightly run does (README, "Tests and benchmarks").

>>> allowed_misses(200, 0.01), allowed_misses(30, 0.01), allowed_misses(30, 0.05)
(2, 1, 1)

Such a test may be split into :func:`parts`, each a parametrized test of its own, so that ``pytest -n auto``
spreads the cases over the workers: the cases are dealt out in turn (the costly ones, which come at random, end
up in different parts) and the sample's allowed misses are shared out, so that the parts all pass only when the
whole sample would have.

>>> [(list(p.cases), p.allowed) for p in parts(10, 0.05, 4)]
[([0, 4, 8], 1), ([1, 5, 9], 0), ([2, 6], 0), ([3, 7], 0)]
>>> sum(p.allowed for p in parts(30, 0.05, 4)) == allowed_misses(30, 0.05)
True
"""

import math
import os
from typing import NamedTuple

#: Cases drawn when the full run is not asked for.
SAMPLE = 24
FULL = os.environ.get("DOMES_FULL_TESTS", "") == "1"


def cases(full: int) -> int:
    """The number of cases to draw: ``full`` in a full run, else :data:`SAMPLE` (never more than ``full``)."""
    return full if FULL else min(full, SAMPLE)


def allowed_misses(count: int, share: float) -> int:
    """How many of ``count`` cases may miss when at most ``share`` of them may: the share rounded down, at least
    one when the share is above zero."""
    return max(1, math.floor(share * count + 1e-9)) if share > 0 else 0


class Part(NamedTuple):
    """One part of a sample: the indices of its cases and how many of them may miss."""

    cases: range
    allowed: int


def parts(count: int, share: float, n: int) -> list[Part]:
    """``count`` cases dealt into ``n`` parts (part ``k``: cases ``k, k + n, ...``), with the misses
    :func:`allowed_misses` grants the whole sample shared out among them (the first parts get one more)."""
    total = allowed_misses(count, share)
    return [Part(range(k, count, n), total // n + (k < total % n)) for k in range(n)]
