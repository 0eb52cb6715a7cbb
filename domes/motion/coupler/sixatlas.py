"""An atlas of Watt and Stephenson six-bar coupler curves, for starting six-bar fits.

Six-bars are drawn from the design space of
:func:`~domes.motion.coupler.sixbar.sample` (a seeded stream, the same atlas
on every machine), each in its four assembly modes; every one is traced
once at :data:`STEPS` crank angles, and the curves of a grid of tracing
points ``(u, v)`` on its link ``E F`` follow from ``E`` and ``F`` without
tracing again (``P = E + (u + iv)(F − E)/e``). Each curve's normalised
Fourier descriptor (as in the four-bar atlas) goes into a k-d tree.

>>> atlas = SixAtlas.build(per_kind=4)
>>> atlas.count <= 2 * 4 * len(MODES) * GRID_U.size * GRID_V.size     # two types, four modes, 25 points each
True
>>> z = atlas.sixbar(0).curve(np.linspace(0, 2 * np.pi, 64, endpoint=False))
>>> best = atlas.lookup(np.c_[z.real, z.imag], k=3)[0]     # its own row, up to the 64 points' resampling
>>> best.index, best.distance < 1e-3
(0, True)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.spatial import cKDTree

from domes.motion.coupler.atlas import RESAMPLE, descriptors, resample_closed
from domes.motion.coupler.fourier import HARMONICS, describe, variants
from domes.motion.coupler.sixbar import KINDS, SixBar, sample

#: Six-bars of each type in the atlas the look-up builds by default.
PER_KIND = 1500
#: Crank angles each six-bar is traced at.
STEPS = 256
#: The tracing points on ``E F``, in units of ``e``: ``u/e`` and ``v/e`` on this grid.
GRID_U = np.linspace(-0.5, 1.5, 5)
GRID_V = np.linspace(-1.0, 1.0, 5)
MODES = ((1, 1), (1, -1), (-1, 1), (-1, -1))
SEED = 20261129


@dataclass(frozen=True)
class SixCandidate:
    """An atlas curve near the wanted path: its row, descriptor distance, and the six-bar it is."""

    index: int
    distance: float
    sixbar: SixBar


class SixAtlas:
    """Rows ``(six-bar, modes, tracing point)`` with their descriptors and a k-d tree over them."""

    def __init__(self, kinds, lengths, row_bar, row_mode, row_point, features):
        self.kinds, self.lengths = np.asarray(kinds), np.asarray(lengths, dtype=float)
        self.row_bar, self.row_mode = np.asarray(row_bar), np.asarray(row_mode)
        self.row_point, self.features = np.asarray(row_point, dtype=float), np.asarray(features, dtype=float)
        self.count = len(self.row_bar)
        self.tree = cKDTree(self.features)

    @classmethod
    def build(cls, per_kind: int = PER_KIND, seed: int = SEED) -> "SixAtlas":
        """Draw ``per_kind`` six-bars of each type and describe the curves of their tracing-point grid."""
        rng = np.random.default_rng(seed)
        theta = np.linspace(0.0, 2 * np.pi, STEPS, endpoint=False)
        grid = (GRID_U[:, None] + 1j * GRID_V[None, :]).ravel()
        kinds, lengths, bars, modes, points, feats = [], [], [], [], [], []
        for kind in sorted(KINDS):
            for _ in range(per_kind):
                base = sample(kind, rng)
                k = len(lengths)
                kinds.append(kind)
                lengths.append(base.lengths)
                e = base.lengths[6]
                for m, mode in enumerate(MODES):
                    at, ok = SixBar(kind, base.lengths, mode).joints(theta)
                    if not ok.all():
                        continue
                    Z = at["E"][None, :] + (grid * e)[:, None] * ((at["F"] - at["E"]) / e)[None, :]
                    with np.errstate(invalid="ignore", divide="ignore"):
                        f = descriptors(resample_closed(Z, RESAMPLE), HARMONICS)
                    good = np.all(np.isfinite(f), axis=1)
                    bars += [k] * int(good.sum())
                    modes += [m] * int(good.sum())
                    points += list(grid[good] * e)
                    feats.append(f[good])
        pts = np.array(points)
        return cls(kinds, lengths, bars, modes, np.c_[pts.real, pts.imag], np.concatenate(feats))

    def sixbar(self, row: int) -> SixBar:
        """The six-bar of an atlas row (its modes and tracing point)."""
        k = int(self.row_bar[row])
        lengths = tuple(self.lengths[k][:10]) + tuple(self.row_point[row])
        return SixBar(str(self.kinds[k]), lengths, MODES[int(self.row_mode[row])])

    def lookup(self, points, k: int = 30) -> list[SixCandidate]:
        """The ``k`` rows nearest the closed path through ``points`` (all readings), at most one per six-bar and
        modes (the nearest of its tracing points)."""
        wanted = describe(points, HARMONICS, RESAMPLE)
        best: dict[tuple, tuple[float, int]] = {}
        for vector in variants(wanted):
            dist, idx = self.tree.query(vector, k=min(self.count, 16 * k))
            for dd, ii in zip(np.atleast_1d(dist), np.atleast_1d(idx)):
                key = (int(self.row_bar[ii]), int(self.row_mode[ii]))
                if key not in best or dd < best[key][0]:
                    best[key] = (float(dd), int(ii))
        rows = sorted(best.values())[:k]
        return [SixCandidate(i, d, self.sixbar(i)) for d, i in rows]


_CACHE: dict[int, SixAtlas] = {}


def built(per_kind: int = PER_KIND) -> SixAtlas:
    """The atlas of ``per_kind`` six-bars of each type, built once per process (``domes.io.sixatlas`` keeps it in
    the user's data folder)."""
    if per_kind not in _CACHE:
        _CACHE[per_kind] = SixAtlas.build(per_kind)
    return _CACHE[per_kind]
