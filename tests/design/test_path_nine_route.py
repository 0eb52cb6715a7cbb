"""Issue 27: a path task of nine points with ``"route": "exact"`` is answered by the nine-point homotopy.

The full route takes about 18 s of CPU (1,442 paths), so it runs in a full run only (``DOMES_FULL_TESTS=1``,
tests/sampling.py); the entry's checks run always.
"""

from __future__ import annotations

import numpy as np
import pytest

from domes.design.synthesis import synthesize, task_from_dict
from domes.design.synthesis.ninepoint import CLASSES
from domes.design.synthesis.verify import curve_distances
from domes.errors import InputError
from tests.design.test_path_routes_agree import planted
from tests.sampling import FULL


def _task(points, **entries):
    return task_from_dict({"kind": "path", "points": np.asarray(points).tolist(), **entries})


def test_the_route_entry_is_checked():
    P, fb = planted(np.random.default_rng(9), "crank-rocker", 9)
    assert _task(P, route="exact").route == "exact" and _task(P).route == "auto"
    with pytest.raises(InputError, match="'route' must be 'auto' or 'exact'"):
        _task(P, route="homotopy")
    with pytest.raises(InputError, match="exactly nine points.*got 8 points"):
        _task(P[:8], route="exact")
    with pytest.raises(InputError, match="pivots given"):
        _task(P, route="exact", a0=list(fb.a0))


@pytest.mark.skipif(not FULL, reason="about 18 s of CPU: full runs only (DOMES_FULL_TESTS=1)")
def test_nine_points_of_a_planted_four_bar_give_every_class_and_the_planted_curve():
    P, _ = planted(np.random.default_rng(9), "crank-rocker", 9)
    result = synthesize(_task(P, route="exact"))
    size = float(np.ptp(P, axis=0).max())
    assert f"{CLASSES} classes of {CLASSES}" in result.notes[0]
    assert result.usable and all(s.notes[0] == "route: exact, the nine-point homotopy" for s in result.solutions)
    for s in result.usable:                            # the kernel's re-trace of each usable linkage's curve
        assert max(curve_distances(s.fourbar, P)) <= 1e-8 * size
