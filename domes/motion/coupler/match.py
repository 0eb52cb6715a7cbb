"""Which four-bar traces this path? Atlas look-up, then refinement, best first.

:func:`match` looks the wanted closed path up in an
:class:`~domes.motion.coupler.atlas.Atlas` (a k-d tree over normalised
Fourier descriptors, distinct linkages) and refines the candidates in turn
(:func:`~domes.motion.coupler.fit.fit`) until ``results`` different
linkages fit within ``tol`` of the path's size, or the candidates run out
(a linkage found again from another candidate counts once). The result lists the
fits, best first, with the times of the look-up and of the refinement.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.motion.coupler.atlas import Atlas, OpenAtlas
from domes.motion.coupler.fit import Fit, fit
from domes.results import Listing, Progress, Status, Ticker

#: Candidates refined at most (distinct linkages, nearest descriptors first).
CANDIDATES = 30
#: The default tolerance, relative to the path's size: a closed path is matched exactly (to round-off of the
#: fit); an open stretch constrains a four-bar weakly (a near-degenerate family of linkages passes close to a
#: short arc), so its refinement converges slowly past about 1e-4 and the default asks 1e-3 (docs/curves.md).
TOL = {"closed": 1e-6, "open": 1e-3}


@dataclass(frozen=True, eq=False)
class Matching(Listing):
    """The fits of a wanted path, best first (``fits``), the candidates tried, and the times taken."""

    fits: tuple[Fit, ...]
    tried: int
    lookup_seconds: float
    refine_seconds: float
    size: float
    tol: float
    items_field = "fits"

    @property
    def status(self) -> Status:
        return Status.COMPLETE if any(f.success for f in self.fits) else Status.EMPTY if not self.fits else Status.STOPPED

    @property
    def message(self) -> str:
        good = sum(f.success for f in self.fits)
        best = self.fits[0].after[0] if self.fits else float("nan")
        return (f"{self.status}: {good} of {self.tried} candidates fit within {self.tol:g} of the path's size "
                f"{self.size:.4g} (best: largest distance {best:.3g}); look-up {self.lookup_seconds * 1e3:.1f} ms, "
                f"refinement {self.refine_seconds:.2f} s")


def match(points, atlas: Atlas | OpenAtlas, results: int = 3, candidates: int = CANDIDATES, tol: float | None = None,
          max_nfev: int = 200, progress: Progress | None = None) -> Matching:
    """Refine atlas candidates for the path through ``points`` until ``results`` fit within ``tol``.

    With an :class:`~domes.motion.coupler.atlas.Atlas` the path is closed;
    with an :class:`~domes.motion.coupler.atlas.OpenAtlas` it is an open
    stretch, looked up among windows of the atlas's curves. ``tol`` is
    relative to the path's size (default :data:`TOL` of its kind).
    """
    if tol is None:
        tol = TOL["open" if isinstance(atlas, OpenAtlas) else "closed"]
    if not tol > 0:
        raise InputError(f"tol {tol}: give a positive tolerance (relative to the path's size)")
    target = np.asarray(points, dtype=float)
    if target.ndim != 2 or target.shape[1] != 2:
        raise InputError(f"a wanted path is an array of points (x, y), got shape {target.shape}")
    if results < 1 or candidates < 1:
        raise InputError("results and candidates must be at least 1")
    size = float(np.max(np.ptp(target, axis=0)) or 1.0)
    t0 = time.perf_counter()
    found = atlas.lookup(target, k=candidates)
    t1 = time.perf_counter()
    fits: list[Fit] = []
    clock = Ticker(progress)
    tried = 0
    for cand in found:
        tried += 1
        clock.tick(lambda: f"refining candidate {tried}/{len(found)}; {sum(f.success for f in fits)} fit so far")
        try:
            f = fit(target, atlas.table.entry(cand.index), tol, max_nfev, cand.window)
        except InputError:
            continue
        if not any(_same(f, g, size) for g in fits):
            fits.append(f)
        if sum(f.success for f in fits) >= results:
            break
    fits.sort(key=lambda f: (not f.success, f.after[0]))
    return Matching(tuple(fits[:max(results, 1)]), tried, t1 - t0, time.perf_counter() - t1, size, tol)


def _same(f: Fit, g: Fit, size: float) -> bool:
    """Whether two fits found one linkage (the same lengths, coupler point and frame pivots, to 1e-6 of the size)."""
    if f.mechanism is None or g.mechanism is None:
        return False
    key = lambda x: np.array([*x.lengths, abs(x.coupler[1]), x.coupler[0], *x.mechanism.joint("A").at,  # noqa: E731
                              *x.mechanism.joint("D").at])
    return bool(np.max(np.abs(key(f) - key(g))) <= 1e-6 * size)
