"""A path drawn by hand: noisy, unevenly spaced, perhaps with corners, matched against the user's own points.

:func:`drawn` reads a sketch: repeated points dropped, closed or open (the
ends within :data:`CLOSING` of its size, unless said), its corners (where
the direction turns by more than :data:`CORNER` degrees over a short
stretch), and a smoothing spline over arc length fitted to each stretch
between corners, its weight chosen by generalised cross-validation; the RMS
distance of the points from it is the sketch's scatter (``noise``).

:func:`match_drawn` looks the smoothed sketch up in the atlas (evenly spread
by arc length, so that uneven spacing does not bias the look-up), fits each
candidate by least squares to the user's own points, and measures every fit
the same way: the distance of each of the user's points from the linkage's
coupler curve traced by the kinematics kernel (the nearest point of one
circuit; no correspondence assumed). Every candidate is fitted (a sketch's
first good fit is seldom its best), and the best are refined further. A fit
succeeds within ``tol`` of the sketch's size, by default four times the
scatter (at least :data:`FLOOR`): a sketch is matched as well as it was
drawn, not to its tremor.

With a ``timing`` (the crank's angle, or the time, at each point:
:class:`~domes.motion.coupler.timing.Timing`), the crank angles are fixed by
it and each fit is measured at it: :mod:`domes.motion.coupler.timing`.

>>> import numpy as np
>>> t = np.linspace(0, 2 * np.pi, 90, endpoint=False)
>>> ring = np.c_[np.cos(t), np.sin(t)] + np.random.default_rng(1).normal(0, 0.01, (90, 2))
>>> d = drawn(ring)
>>> d.closed, d.corners, round(d.noise / 0.01, 1)
(True, (), 0.8)
>>> drawn([[0, 2], [0, 1.5], [0, 1], [0, 0.5], [0, 0], [0.5, 0], [1, 0], [1.5, 0], [2, 0]]).corners
(4,)
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace

import numpy as np

from domes.errors import InputError
from domes.motion.coupler.atlas import Atlas, OpenAtlas
from domes.motion.coupler.curves import trace
from domes.motion.coupler.fit import Fit, check_wanted, fit
from domes.motion.coupler.match import Matching, _merge, _same
from domes.motion.coupler.timing import Schedule, TimedFit, Timing, schedule, timed_fits
from domes.results import Progress, Status, Ticker

#: The ends of a sketch closer than this share of its size make it closed (unless the caller says).
CLOSING = 0.05
#: A corner: the direction turns by more than this many degrees over :data:`REACH` of the length each side.
CORNER = 55.0
#: The stretch each side of a point over which its turn is measured, as a share of the sketch's length.
REACH = 0.03
#: The least tolerance of a sketch's fit, as a share of its size.
FLOOR = 1e-3
#: Candidates fitted, least-squares evaluations per candidate, and fits refined further (with :data:`POLISH`).
CANDIDATES, EVALUATIONS, REFINED, POLISH = 10, 60, 2, 300
#: Samples per turn of the traced curve the user's points are measured against.
TRACED = 1440
#: A timed sketch places this many times ``candidates`` atlas curves on its points as starts of its timed fit.
TIMED_LOOKUP = 5


@dataclass(frozen=True, eq=False)
class Drawn:
    """A sketch as read: the user's ``points`` (repeats dropped), whether ``closed`` (and why, ``said``), the
    indices of its ``corners``, the ``smooth`` curve at each point, the ``noise`` (RMS distance of the points from
    it), the ``size`` (the larger side of the bounding box) and ``spread``, points evenly spaced by arc length
    along the smooth curve (corners among them) for the atlas look-up; ``kept`` the index of each point among
    those given."""

    points: np.ndarray
    closed: bool
    said: str
    corners: tuple[int, ...]
    smooth: np.ndarray
    noise: float
    size: float
    spread: np.ndarray
    kept: np.ndarray | None = None


def drawn(points, closed: bool | None = None, count: int = 64) -> Drawn:
    """Read a sketch (see the module's doc); ``closed`` None: decided by its ends."""
    raw = check_wanted(points)
    keep = np.r_[True, np.any(np.abs(np.diff(raw, axis=0)) > 0, axis=1)]
    p, kept = raw[keep], np.flatnonzero(keep)
    if len(p) >= 2 and np.all(p[-1] == p[0]):
        p, kept = p[:-1], kept[:-1]
    if len(p) < 9:
        raise InputError(f"the sketch has {len(p)} distinct points; at least 9 are needed to fit a four-bar")
    size = float(np.max(np.ptp(p, axis=0)))
    if not size > 0:
        raise InputError("the sketch's points are all one point")
    gap = float(np.hypot(*(p[-1] - p[0])))
    if closed is None:
        closed = gap <= CLOSING * size
        said = (f"closed: its ends are {gap / size:.1%} of its size apart" if closed else
                f"open: its ends are {gap / size:.1%} of its size apart (more than {CLOSING:.0%})")
    else:
        said = "closed, as said" if closed else "open, as said"
    s = _arc(p, closed)
    corners = _corners(p, s, closed)
    smooth = _smoothed(p, s, corners, closed)
    noise = float(np.sqrt(np.mean(np.sum((p - smooth) ** 2, axis=1))))
    return Drawn(p, closed, said, corners, smooth, noise, size, _spread(smooth, s, corners, closed, count), kept)


def _arc(p: np.ndarray, closed: bool) -> np.ndarray:
    """The arc length at each point (a closed sketch's last entry is its whole length, back to the first point)."""
    q = np.vstack([p, p[:1]]) if closed else p
    return np.r_[0.0, np.cumsum(np.hypot(*np.diff(q, axis=0).T))]


def _at(p: np.ndarray, s: np.ndarray, t: np.ndarray, closed: bool) -> np.ndarray:
    """The polyline through ``p`` at arc lengths ``t`` (wrapped round a closed sketch)."""
    q = np.vstack([p, p[:1]]) if closed else p
    t = np.mod(t, s[-1]) if closed else np.clip(t, 0.0, s[-1])
    return np.c_[np.interp(t, s, q[:, 0]), np.interp(t, s, q[:, 1])]


def _corners(p: np.ndarray, s: np.ndarray, closed: bool) -> tuple[int, ...]:
    """The points where the direction turns by more than :data:`CORNER` over :data:`REACH` of the length each side,
    each the sharpest of its neighbourhood."""
    here = s[: len(p)]
    w = REACH * s[-1]
    before, after = _at(p, s, here - w, closed), _at(p, s, here + w, closed)
    u, v = p - before, after - p
    turn = np.degrees(np.abs(np.arctan2(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0], np.einsum("ij,ij->i", u, v))))
    if not closed:
        turn[(here < w) | (here > s[-1] - w)] = 0.0              # no whole stretch before the first point
    out = []
    for k in np.argsort(-turn, kind="stable"):
        if turn[k] <= CORNER:
            break
        gap = np.abs(here[k] - here[out]) if out else np.array([math.inf])
        if closed and out:
            gap = np.minimum(gap, s[-1] - gap)
        if np.all(gap > 2 * w):
            out.append(int(k))
    return tuple(sorted(out))


def _smoothed(p: np.ndarray, s: np.ndarray, corners: tuple[int, ...], closed: bool) -> np.ndarray:
    """A smoothing spline over arc length through each stretch between corners (GCV weight); a closed sketch
    without corners wraps round."""
    from scipy.interpolate import make_smoothing_spline

    n = len(p)
    out = p.astype(float).copy()
    here = s[:n]
    if closed and not corners:
        pad = n // 3
        idx = np.r_[np.arange(n - pad, n), np.arange(n), np.arange(pad)]
        t = np.r_[here[n - pad:] - s[-1], here, here[:pad] + s[-1]]
        for k in range(2):
            out[:, k] = make_smoothing_spline(t, p[idx, k])(here)
        return out
    cuts = list(corners)
    if closed:
        order = np.r_[np.arange(cuts[0], n), np.arange(0, cuts[0] + 1)]
        t = np.r_[here[cuts[0]:], here[: cuts[0] + 1] + s[-1]]
        cuts = [c - cuts[0] if c >= cuts[0] else c - cuts[0] + n for c in cuts] + [n]
    else:
        order, t = np.arange(n), here
        cuts = [0, *cuts, n - 1]
    for a, b in zip(cuts[:-1], cuts[1:]):
        seg = order[a:b + 1]
        if len(seg) >= 6:                                       # fewer: too short to tell the drawing from its tremor
            for k in range(2):
                out[seg[1:-1], k] = make_smoothing_spline(t[a:b + 1], p[seg, k])(t[a + 1:b])
    return out


def _spread(smooth: np.ndarray, s: np.ndarray, corners: tuple[int, ...], closed: bool, count: int) -> np.ndarray:
    """``count`` points evenly spread by arc length along the smooth curve, each corner moved onto its nearest."""
    total = _arc(smooth, closed)
    t = np.linspace(0.0, total[-1], count, endpoint=not closed)
    out = _at(smooth, total, t, closed)
    for c in corners:
        out[int(np.argmin(np.abs(t - total[c])))] = smooth[c]
    return out


# -- measuring a linkage against the user's points ------------------------------------------------------------


def distances(mech, points, samples: int = TRACED) -> np.ndarray:
    """The distance of each point from the coupler curve of ``mech`` (its point ``P``) traced by the kernel: of the
    circuits, the one the points lie nearest (RMS); inf where the linkage has no curve.

    >>> from domes.motion.coupler.fourbar import four_bar
    >>> mech = four_bar(1, 3.5, 3, 2, 0, 2)
    >>> c = trace(mech, "P", 360).circuits[0].points
    >>> float(np.max(distances(mech, c[::7]))) < 1e-12
    True
    """
    pts = np.asarray(points, dtype=float)
    try:
        circuits = trace(mech, "P", samples).circuits
    except InputError:
        circuits = ()
    best = np.full(len(pts), math.inf)
    for circuit in circuits:
        d = polyline_distances(circuit.points, pts)
        if np.sqrt(np.mean(d ** 2)) < np.sqrt(np.mean(best ** 2)):
            best = d
    return best


def polyline_distances(poly: np.ndarray, points: np.ndarray, closed: bool = True) -> np.ndarray:
    """The distance of each point from the polyline ``poly`` (segments with a non-finite end left out).

    >>> square = np.array([[0.0, 0], [1, 0], [1, 1], [0, 1]])
    >>> polyline_distances(square, np.array([[0.5, 0.2], [2.0, 0.5]])).tolist()
    [0.2, 1.0]
    """
    a = poly if closed else poly[:-1]
    b = np.roll(poly, -1, axis=0) if closed else poly[1:]
    ok = np.all(np.isfinite(a) & np.isfinite(b), axis=1)
    a, b = a[ok], b[ok]
    out = np.full(len(points), math.inf)
    if not len(a):
        return out
    d = b - a
    dd = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    for lo in range(0, len(points), 256):                    # 256 points × the segments at a time
        p = points[lo:lo + 256]
        t = np.clip(np.einsum("kij,ij->ki", p[:, None, :] - a[None], d) / dd, 0.0, 1.0)
        near = a[None] + t[..., None] * d[None]
        out[lo:lo + 256] = np.sqrt(np.min(np.sum((near - p[:, None, :]) ** 2, axis=2), axis=1))
    return out


# -- matching -------------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class DrawnMatching(Matching):
    """The fits of a sketch, best first (``fits``; each one's ``after`` is the largest and RMS distance of the
    user's points from its traced curve), the sketch as read (``sketch``), the candidates tried and the times taken;
    ``note`` says how the sketch was read."""

    sketch: Drawn | None = None

    @property
    def message(self) -> str:
        good = sum(f.success for f in self.fits) + sum(g.success for m in self.merged for g, _ in m)
        best = (f"best: largest distance {self.fits[0].after[0]:.3g} ({self.fits[0].after[0] / self.size:.2%} of "
                f"the size), RMS {self.fits[0].after[1]:.3g}") if self.fits else "none could be placed"
        return (f"{self.status}: {good} of {self.tried} candidates fit within {self.tol:g} of the sketch's size "
                f"{self.size:.4g} ({best}); look-up {self.lookup_seconds * 1e3:.1f} ms, refinement "
                f"{self.refine_seconds:.2f} s; {self.note}")


def timed_scatter(sketch: Drawn, plan: Schedule) -> float:
    """The RMS distance of a timed sketch's points from a smoothing spline over their timing (GCV weight, wrapped
    round a closed sketch, no corners: a coupler point moves smoothly with its crank even through a cusp); the
    sketch's scatter over arc length when its timing does not run one way."""
    u = np.r_[0.0, plan.rotations]
    u = -u if u[-1] < 0 else u
    if not np.all(np.diff(u) > 0):
        return sketch.noise
    period = (2 * math.pi if not plan.free else u[-1] + u[-1] / (len(u) - 1)) if sketch.closed else u[-1]
    smooth = _smoothed(sketch.points, np.r_[u, period], (), sketch.closed)
    return float(np.sqrt(np.mean(np.sum((sketch.points - smooth) ** 2, axis=1))))


def _reading(d: Drawn, timing: Timing | None = None, noise: float | None = None) -> str:
    """How a sketch was read, for the answer's message."""
    corners = f"{len(d.corners)} corner{'' if len(d.corners) == 1 else 's'}" if d.corners else "no corner"
    text = (f"a drawn path of {len(d.points)} points, {d.said}; {corners}; the points scatter "
            f"{d.noise / d.size:.2%} of its size about a smooth curve; errors are the distances of your points from ")
    if timing is None:
        return text + "each linkage's traced curve"
    given = ("crank angles" if timing.kind == "angle" else "times, the crank's speed " +
             ("found by the fit" if timing.speed is None else f"{timing.speed:g}°/unit"))
    return (text + f"each linkage's coupler point at their timing ({given}), about which they scatter "
            f"{noise / d.size:.2%} of its size")


def _curve(mech, sketch: Drawn) -> tuple[float, float]:
    """The largest and RMS distance of the sketch's points from the traced curve of ``mech``."""
    d = distances(mech, sketch.points)
    return float(np.max(d)), float(np.sqrt(np.mean(d ** 2)))


def match_drawn(points, atlas: Atlas | OpenAtlas, results: int = 3, candidates: int = CANDIDATES,
                tol: float | None = None, closed: bool | None = None, progress: Progress | None = None,
                timing: Timing | None = None) -> DrawnMatching:
    """The four-bars whose coupler curves pass nearest a drawn path (see the module's doc), best first.

    ``atlas`` an :class:`~domes.motion.coupler.atlas.Atlas` for a closed sketch, an
    :class:`~domes.motion.coupler.atlas.OpenAtlas` for an open one (``closed`` None: the sketch's ends decide, and
    must agree with the atlas). ``tol`` relative to the sketch's size (default: four times its scatter, at least
    :data:`FLOOR`). ``timing`` (a :class:`~domes.motion.coupler.timing.Timing`, or a list of crank angles in
    degrees, one per point): the crank's angle at each point is fixed by it, up to the crank's zero (and its speed,
    for times without one), and each fit (a :class:`~domes.motion.coupler.timing.TimedFit`) is measured at it.
    """
    sketch = drawn(points, closed)
    plan = None if timing is None else schedule(timing, len(np.asarray(points)), sketch.kept, sketch.closed)
    if sketch.closed != (not isinstance(atlas, OpenAtlas)):
        kind = "closed" if sketch.closed else "open"
        raise InputError(f"the sketch is {sketch.said.split(':')[0]}, but the atlas is of "
                         f"{'open' if isinstance(atlas, OpenAtlas) else 'closed'} paths: give the atlas of {kind} "
                         "paths (or say closed/open)")
    if results < 1 or candidates < 1:
        raise InputError("results and candidates must be at least 1")
    noise = sketch.noise if plan is None else timed_scatter(sketch, plan)
    if tol is None:
        tol = max(FLOOR, 4.0 * noise / sketch.size)
    if not tol > 0:
        raise InputError(f"tol {tol}: give a positive tolerance (relative to the sketch's size)")
    t0 = time.perf_counter()
    found = atlas.lookup(sketch.spread, k=candidates if plan is None else TIMED_LOOKUP * candidates)
    t1 = time.perf_counter()
    clock = Ticker(progress)
    if plan is not None:
        timed = _timed(sketch, plan, atlas, found, tol, clock)
        return DrawnMatching(tuple(timed[:results]), len(found), t1 - t0, time.perf_counter() - t1, sketch.size, tol,
                             note=_reading(sketch, plan.timing, noise), sketch=sketch)
    fits: list[Fit] = []
    tried = 0
    for cand in found:
        tried += 1
        clock.tick(lambda: f"fitting candidate {tried}/{len(found)}; {sum(f.success for f in fits)} fit so far")
        f = _measured(sketch, _fit(sketch, atlas.table.entry(cand.index), tol, EVALUATIONS, cand.window), tol)
        if f is not None and not any(_same(f, g, sketch.size) for g in fits):
            fits.append(f)
    fits.sort(key=lambda f: f.after[1])
    for k, f in enumerate(fits[:REFINED]):
        clock.tick(lambda: f"refining fit {k + 1}/{min(REFINED, len(fits))}")
        better = _measured(sketch, _fit(sketch, f.mechanism, tol, POLISH, None, f), tol)
        if better is not None and better.after[1] < f.after[1]:
            fits[k] = better
    fits.sort(key=lambda f: (not f.success, f.after[1]))
    kept, merged = _merge(fits, sketch.size)
    shown, count = 0, 0
    while shown < len(kept) and count < results:
        count += 1 + len(merged[shown])
        shown += 1
    return DrawnMatching(tuple(kept[:max(shown, 1)]), tried, t1 - t0, time.perf_counter() - t1, sketch.size, tol,
                         note=_reading(sketch), merged=tuple(tuple(m) for m in merged[:max(shown, 1)]),
                         sketch=sketch)


def _timed(sketch: Drawn, plan: Schedule, atlas, found, tol: float, clock: Ticker) -> list[TimedFit]:
    """The timed fits of a sketch (:func:`~domes.motion.coupler.timing.timed_fits`), started from the atlas
    candidates ``found`` as placed on the user's points, each with its distances from its traced curve."""
    starts = []
    for k, cand in enumerate(found):
        clock.tick(lambda: f"placing candidate {k + 1}/{len(found)}")
        f = _fit(sketch, atlas.table.entry(cand.index), tol, 1, cand.window)
        if f is not None and f.mechanism is not None:
            starts.append(f.mechanism)
    fits = timed_fits(sketch.points, plan, starts, tol, tick=lambda what: clock.tick(lambda: what))
    return [replace(f, curve=_curve(f.mechanism, sketch)) for f in fits]


def _fit(sketch: Drawn, start, tol: float, evaluations: int, window, previous: Fit | None = None) -> Fit | None:
    """The least-squares fit of the linkage ``start`` to the user's points (None when it cannot be fitted)."""
    try:
        if previous is not None and not sketch.closed:
            return fit(sketch.points, start, tol, evaluations, _window_of(previous, sketch))
        return fit(sketch.points, start, tol, evaluations, window)
    except InputError:
        return None


def _window_of(f: Fit, sketch: Drawn):
    """Where on its own curve an open fit's points lie, as a look-up window gives it: ``(circuit, start, fraction,
    backwards, mirror)`` of the circuit the points are nearest."""
    circuits = trace(f.mechanism, "P", TRACED).circuits
    best = min(range(len(circuits)), key=lambda k: np.mean(polyline_distances(circuits[k].points, sketch.points) ** 2))
    pts = circuits[best].points
    n = len(pts)
    first, last = (int(np.argmin(np.sum((pts - q) ** 2, axis=1))) for q in (sketch.points[0], sketch.points[-1]))
    mid = int(np.argmin(np.sum((pts - sketch.points[len(sketch.points) // 2]) ** 2, axis=1)))
    ahead = (last - first) % n
    backwards = not ((mid - first) % n <= ahead)
    fraction = (n - ahead if backwards else ahead) / n
    return best, first / n, max(fraction, 1.0 / n), backwards, False


def _measured(sketch: Drawn, f: Fit | None, tol: float) -> Fit | None:
    """``f`` with its error measured against the user's points (largest and RMS distance from its traced curve)."""
    if f is None or f.mechanism is None:
        return None
    d = distances(f.mechanism, sketch.points)
    if not np.all(np.isfinite(d)):
        return None
    after = (float(np.max(d)), float(np.sqrt(np.mean(d ** 2))))
    return replace(f, after=after, size=sketch.size, tol=tol, status=Status.COMPLETE)


__all__ = ["Drawn", "DrawnMatching", "distances", "drawn", "match_drawn", "polyline_distances"]
