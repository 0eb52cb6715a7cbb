"""Five path points and both fixed pivots by the nine-point solver's homotopy (Morgan & Wampler 1990).

With the fixed pivots ``a0``, ``b0`` given, five coupler points leave the moving pivots ``x, x̄, y, ȳ`` and four
coupler rotations: 12 equations (:class:`~domes.design.synthesis.isotropic.DyadSystem` with ``pivots_given``),
36 solutions for generic data. The 36 stored generic solutions (``ninepoint.npz``) are tracked to the task by
:func:`~domes.design.synthesis.homotopy.track`; paths that run to infinity (special data: points in line) are
counted, not listed. Morgan & Wampler's Problem 7 (points on a line, pivots (0, 0) and (1, 0)) has 33 finite
solutions, 15 of them real.

>>> r = five_point_pivots(PROBLEM_7, (0.0, 0.0), (1.0, 0.0))      # doctest: +SKIP
>>> len(r.solutions), len(r.real), r.infinite                       # doctest: +SKIP
(33, 15, 3)
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from domes.design.synthesis import homotopy as hc
from domes.design.synthesis.isotropic import DyadSystem
from domes.design.synthesis.ninepoint import (
    FIVE_POINT_COUNT,
    RESIDUAL,
    NinePointSolution,
    Solutions,
    certify,
    check_points,
    solution,
    start_set,
)
from domes.errors import InputError
from domes.results import Result, Status

#: Morgan & Wampler (1990), Problem 7: five points on a line, the fixed pivots at (0, 0) and (1, 0) (the points as
#: printed in the phcpy documentation's use case of that paper).
PROBLEM_7 = ((0.50, 1.06), (-0.83, -0.27), (-0.34, 0.22), (-0.13, 0.43), (0.22, 0.78))


@dataclass(frozen=True, eq=False)
class FivePointPivots(Solutions, Result):
    """The finite solutions (``solutions``), the paths gone to infinity or failed (``infinite``), the time."""

    solutions: tuple[NinePointSolution, ...]
    infinite: int
    seconds: float

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.solutions else Status.EMPTY

    @property
    def message(self) -> str:
        return (f"{self.status}: five points, two pivots: {len(self.solutions)} finite solution(s) of "
                f"{FIVE_POINT_COUNT}, {len(self.real)} real, {len(self.usable)} usable; {self.infinite} path(s) "
                f"to infinity; {self.seconds:.2f} s")


def five_point_pivots(points, a0, b0, seed: int = 0, check_mechanisms: bool = True) -> FivePointPivots:
    """Every four-bar with fixed pivots ``a0``, ``b0`` whose coupler point passes through the five ``points``."""
    t0 = time.perf_counter()
    P = check_points(points, 5)
    piv = np.asarray([a0, b0], dtype=float)
    if piv.shape != (2, 2) or not np.isfinite(piv).all():
        raise InputError(f"a0, b0: expected two finite points (x, y), got {a0!r} and {b0!r}")
    size = float(np.ptp(P, axis=0).max())
    rel = (P - P[0]) / size
    d = rel[1:, 0] + 1j * rel[1:, 1]
    g = (piv - P[0]) / size
    a, b = complex(*g[0]), complex(*g[1])
    p1 = np.concatenate([d, d.conj(), [a, a.conjugate(), b, b.conjugate()]])[None]
    data = start_set()
    system = DyadSystem(4, pivots_given=True)
    rng = np.random.default_rng(seed)
    end = hc.track(system, data["five_z"], data["five_p"][None], p1, gamma=np.exp(1j * rng.uniform(-np.pi, np.pi)))
    z = hc.refine(system, end.z, p1)[0]
    ok = np.flatnonzero((end.status == hc.DONE) & (system.point_error(z, np.broadcast_to(p1, z.shape[:1] + p1.shape[1:]))
                                                   < RESIDUAL))
    ok = ok[hc.distinct(z[ok])] if len(ok) else ok
    res, cond = certify(system, z[ok], p1)
    sols = []
    for k, i in enumerate(ok):
        w = z[i]
        full = np.concatenate([[w[0], w[1], a, a.conjugate(), w[2], w[3], b, b.conjugate()], w[4:]])
        sols.append(solution(k, 0, full, res[k], cond[k], P, size, check_mechanisms))
    return FivePointPivots(tuple(sols), FIVE_POINT_COUNT - len(sols), time.perf_counter() - t0)
