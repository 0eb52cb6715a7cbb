"""How many random cases the large round-trip tests draw.

The acceptance tests of the synthesis and the coupler-curve look-up draw 200 random four-bars each (issues 13
and 14); at about 1.5 s a case, two of them took ten minutes of every test run. By default they draw the first
:data:`SAMPLE` of the same seeded stream, with the same share allowed to miss; ``DOMES_FULL_TESTS=1`` draws all
200, as a nightly run does (README, "Tests and benchmarks").

>>> allowed_misses(200, 0.01), allowed_misses(40, 0.01), allowed_misses(40, 0.05)
(2, 1, 2)
"""

import math
import os

#: Cases drawn when the full run is not asked for.
SAMPLE = 40
FULL = os.environ.get("DOMES_FULL_TESTS", "") == "1"


def cases(full: int) -> int:
    """The number of cases to draw: ``full`` in a full run, else :data:`SAMPLE` (never more than ``full``)."""
    return full if FULL else min(full, SAMPLE)


def allowed_misses(count: int, share: float) -> int:
    """How many of ``count`` cases may miss when at most ``share`` of them may: the share rounded down, at least
    one when the share is above zero."""
    return max(1, math.floor(share * count + 1e-9)) if share > 0 else 0
