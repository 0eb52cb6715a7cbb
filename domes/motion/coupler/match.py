"""Which four-bar traces this path? Atlas look-up, then refinement, best first.

:func:`match` looks the wanted closed path up in an
:class:`~domes.motion.coupler.atlas.Atlas` (a k-d tree over normalised
Fourier descriptors, distinct linkages) and refines the candidates in turn
(:func:`~domes.motion.coupler.fit.fit`) until ``results`` different
linkages fit within ``tol`` of the path's size, or the candidates run out
(a linkage found again from another candidate counts once). The result lists the
fits, best first, with the times of the look-up and of the refinement.

Fits that are one linkage are merged into the first of them, and the result
says so (``merged``): the same linkage driven from its other pivot (crank
and rocker swapped), its Roberts-Chebyshev cognates (the three four-bars
that trace one coupler curve: the third pivot ``O = A + z (D − A)`` with
``z = (P − B)/(C − B)``, digest B.4), and its mirror image or another
placement when the path is symmetric.

Points on one straight line have no exact match: a coupler curve is a
closed sextic, never straight. The fits are then curves that pass near the
line (approximate straight-line four-bars), and the message says so.
"""

from __future__ import annotations

import math
import time
from dataclasses import KW_ONLY, dataclass

import numpy as np

from domes.errors import InputError
from domes.motion.coupler.atlas import Atlas, OpenAtlas
from domes.motion.coupler.fit import Fit, check_wanted, fit, resampled_note
from domes.results import Listing, Progress, Status, Ticker

#: Candidates refined at most (distinct linkages, nearest descriptors first).
CANDIDATES = 30
#: The default tolerance, relative to the path's size: a closed path is matched exactly (to round-off of the
#: fit); an open stretch constrains a four-bar weakly (a near-degenerate family of linkages passes close to a
#: short arc), so its refinement converges slowly past about 1e-4 and the default asks 1e-3 (docs/curves.md).
#: A six-bar's twelve dimensions converge slowly near a fit too: unless a tolerance is given, six-bars are judged at
#: 1e-4, the level the six-bar round trip measures (a fit to 1e-6 would refine every candidate, a minute or more).
TOL = {"closed": 1e-6, "open": 1e-3, "six-bar": 1e-4}
#: When six-bars are tried too: never, when no four-bar fits within the tolerance, or always (closed paths only;
#: :mod:`domes.motion.coupler.sixmatch`).
SIXBARS = ("no", "auto", "yes")
#: With ``sixbars="auto"``, four-bar candidates refined at most before six-bars are tried: a four-bar curve is
#: matched by one of its first candidates, and refining all of them for a curve no four-bar makes costs tens of
#: seconds.
AUTO_FOURBARS = 5


@dataclass(frozen=True, eq=False)
class Matching(Listing):
    """The fits of a wanted path, best first (``fits``), the candidates tried, and the times taken."""

    fits: tuple[Fit, ...]
    tried: int
    lookup_seconds: float
    refine_seconds: float
    size: float
    tol: float
    _: KW_ONLY                                                # the rest by name: subclasses add fields of their own
    note: str = ""
    merged: tuple[tuple[tuple[Fit, str], ...], ...] = ()     # per fit: the fits merged into it, and how they relate
    six_tol: float | None = None                              # six-bars' tolerance, when they were fitted to another
    items_field = "fits"

    @property
    def status(self) -> Status:
        return Status.COMPLETE if any(f.success for f in self.fits) else Status.EMPTY if not self.fits else Status.STOPPED

    @property
    def message(self) -> str:
        good = sum(f.success for f in self.fits) + sum(g.success for m in self.merged for g, _ in m)
        best = f"best: largest distance {self.fits[0].after[0]:.3g}" if self.fits else "none could be refined"
        if any(kind_of(f) != "four-bar" for f in self.fits):
            best = f"best: {kind_of(self.fits[0])}, largest distance {self.fits[0].after[0]:.3g}"
        same = sum(len(m) for m in self.merged)
        same = f"; {same} merged into the linkage they repeat (same linkage, cognate or mirror)" if same else ""
        within = f"{self.tol:g}" + (f" (six-bars {self.six_tol:g})" if self.six_tol not in (None, self.tol) else "")
        return (f"{self.status}: {good} of {self.tried} candidates fit within {within} of the path's size "
                f"{self.size:.4g} ({best}{same}); look-up {self.lookup_seconds * 1e3:.1f} ms, "
                f"refinement {self.refine_seconds:.2f} s" + (f"; {self.note}" if self.note else ""))


def match(points, atlas: Atlas | OpenAtlas, results: int = 3, candidates: int = CANDIDATES, tol: float | None = None,
          max_nfev: int = 200, progress: Progress | None = None, sixbars: str = "no", sixatlas=None) -> Matching:
    """Refine atlas candidates for the path through ``points`` until ``results`` fit within ``tol``.

    With an :class:`~domes.motion.coupler.atlas.Atlas` the path is closed;
    with an :class:`~domes.motion.coupler.atlas.OpenAtlas` it is an open
    stretch, looked up among windows of the atlas's curves. ``tol`` is
    relative to the path's size (default :data:`TOL` of its kind).
    ``sixbars`` (:data:`SIXBARS`) says when Watt and Stephenson six-bars
    are fitted too (from ``sixatlas``, by default one built in memory;
    the command line keeps it in the data folder); the
    fits are then listed together, those within ``tol`` first (four-bars
    before six-bars), then by their largest distance.
    """
    if sixbars not in SIXBARS:
        raise InputError(f"sixbars {sixbars!r}: one of {', '.join(SIXBARS)}")
    if sixbars != "no" and isinstance(atlas, OpenAtlas):
        raise InputError("six-bars are matched to closed paths only; leave out the six-bars or the open path")
    if sixbars == "auto":
        candidates = min(candidates, AUTO_FOURBARS)
    six_tol = TOL["six-bar"] if tol is None else tol
    if tol is None:
        tol = TOL["open" if isinstance(atlas, OpenAtlas) else "closed"]
    if not tol > 0:
        raise InputError(f"tol {tol}: give a positive tolerance (relative to the path's size)")
    target = np.asarray(points, dtype=float)
    if target.ndim != 2 or target.shape[1] != 2:
        raise InputError(f"a wanted path is an array of points (x, y), got shape {target.shape}")
    if results < 1 or candidates < 1:
        raise InputError("results and candidates must be at least 1")
    check_wanted(target)
    size = float(np.max(np.ptp(target, axis=0)) or 1.0)
    line = ""
    if _on_one_line(target, size):
        line = ("the points lie on one straight line: a coupler curve is never straight (a closed sextic), so no "
                "four-bar traces them exactly; the fits are curves passing near the line (approximate straight-line "
                "four-bars)" + ("" if isinstance(atlas, OpenAtlas) else
                                "; a straight stretch is matched better as an open path (--open)"))
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
    fits.sort(key=lambda f: (not f.success, f.mechanism is None, f.after[0]))     # a fit never placed last
    kept, merged = _merge(fits, size)
    shown, count = 0, 0
    while shown < len(kept) and count < results:        # a fit merged into another counts as one of the results
        count += 1 + len(merged[shown])
        shown += 1
    note = "; ".join(n for n in (resampled_note(len(target)), line) if n)
    kept, merged = kept[:max(shown, 1)], [tuple(m) for m in merged[:max(shown, 1)]]
    six_fitted = sixbars == "yes" or (sixbars == "auto" and not any(f.success for f in kept))
    if six_fitted:
        from domes.motion.coupler.sixatlas import built
        from domes.motion.coupler.sixmatch import match_sixbars

        clock.tick(lambda: "fitting six-bars")
        six, six_merged, six_tried = match_sixbars(target, sixatlas or built(), results, six_tol)
        tried += six_tried
        order = sorted(range(len(kept) + len(six)), key=lambda k: _rank((kept + six)[k]))
        kept, merged = [(kept + six)[k] for k in order], [(merged + [tuple(m) for m in six_merged])[k] for k in order]
    return Matching(tuple(kept), tried, t1 - t0, time.perf_counter() - t1, size, tol, note=note,
                    merged=tuple(merged), six_tol=six_tol if six_fitted else None)


def kind_of(f) -> str:
    """The type of a fitted linkage: ``four-bar`` or the six-bar's type."""
    return getattr(f, "kind", "four-bar")


def _rank(f):
    """Fits within the tolerance first, four-bars (the simpler linkage) before six-bars; then the nearest."""
    return (not f.success, f.success and kind_of(f) != "four-bar", f.mechanism is None, f.after[0])


def _on_one_line(target, size: float) -> bool:
    """Whether the points lie on one straight line (to 1e-9 of their size)."""
    centred = target - target.mean(axis=0)
    return bool(np.linalg.svd(centred, compute_uv=False)[-1] <= 1e-9 * size * math.sqrt(len(target)))


#: Fits whose pivots and lengths agree to this fraction of the path's size are one linkage (merged).
SAME = 1e-3


def _merge(fits: list[Fit], size: float, related=None):
    """The fits that are distinct linkages, and per each the fits merged into it with how they relate
    (``related(kept, fit, tol)``: why ``fit`` repeats ``kept``, or ""; four-bars' :func:`relation` by default)."""
    related = related or relation
    kept: list[Fit] = []
    merged: list[list[tuple[Fit, str]]] = []
    for f in fits:
        for k, g in enumerate(kept):
            why = related(g, f, SAME * size)
            if why:
                merged[k].append((f, why))
                break
        else:
            kept.append(f)
            merged.append([])
    return kept, merged


def _sides(A, B, C, D, P):
    """The linkage as two frame pivots, each with its link's length and its moving joint's distance from ``P``,
    and the coupler's length: what does not change as it moves or is driven from the other pivot."""
    return ((complex(A), abs(B - A), abs(P - B)), (complex(D), abs(C - D), abs(P - C)), abs(C - B))


def _joints(f: Fit):
    m = f.mechanism
    A, B, C, D = (complex(*m.joint(n).at) for n in "ABCD")
    return A, B, C, D, complex(*m.point("P")[1])


def cognates(A, B, C, D, P) -> list[tuple]:
    """The two Roberts-Chebyshev cognates of a four-bar (complex joint positions at one pose), each as
    ``(A, B, C, D, P)``: on the pivots ``A`` and ``O``, and on ``D`` and ``O``; ``O = A + z (D − A)`` with
    ``z = (P − B)/(C − B)``. Each cognate's links are the original's scaled by ``|z|`` or ``|1 − z|``.

    >>> A, B, C, D, P = 0j, 1j, 3 + 1.5j, 3 + 0j, 1.5 + 2.5j
    >>> (a2, b2, c2, o2, p2), (d3, c3, b3, o3, p3) = cognates(A, B, C, D, P)
    >>> z = (P - B) / (C - B)
    >>> [round(x, 12) for x in (abs(o2 - o3), abs(b2 - a2) - abs(z) * abs(C - B), abs(c2 - o2) - abs(z) * abs(C - D))]
    [0.0, 0.0, 0.0]
    """
    z = (P - B) / (C - B)
    O = A + z * (D - A)
    w = 1 - z                                   # the same construction driven from D: P = C + w (B − C)
    return [(A, A + (P - B), A + z * (C - A), O, P), (D, D + (P - C), D + w * (B - D), O, P)]


def relation(f: Fit, g: Fit, tol: float) -> str:
    """How ``g`` repeats ``f`` (one linkage, a cognate, a mirror image), or "" when it is another linkage."""
    if f.mechanism is None or g.mechanism is None:
        return ""
    mine, other = _joints(f), _joints(g)
    p, q, coupler = _sides(*other)

    def close(x, y) -> bool:
        return abs(x[0] - y[0]) <= tol and max(abs(x[1] - y[1]), abs(x[2] - y[2])) <= tol

    def same(sides) -> bool:
        s1, s2, b = sides
        return abs(b - coupler) <= tol and ((close(s1, p) and close(s2, q)) or (close(s1, q) and close(s2, p)))

    if same(_sides(*mine)):
        if abs(other[0] - mine[3]) <= tol:
            return "the same linkage driven from its other frame pivot (crank and rocker swapped)"
        return "the same linkage (the other assembly mode or coupler side)"
    for k, cog in enumerate(cognates(*mine)):
        if same(_sides(*cog)):
            return f"a Roberts-Chebyshev cognate (the same curve; it shares frame pivot {'AD'[k]})"
    s1, s2, b = _sides(*mine)
    shape = sorted([(s1[1], s1[2]), (s2[1], s2[2])])
    other_shape = sorted([(p[1], p[2]), (q[1], q[2])])
    if abs(b - coupler) <= tol and abs(abs(s1[0] - s2[0]) - abs(p[0] - q[0])) <= tol and \
            all(abs(x - y) <= tol for u, v in zip(shape, other_shape) for x, y in zip(u, v)):
        return "the same linkage placed otherwise (its mirror image or a turned copy: the path is symmetric)"
    return ""


def _same(f: Fit, g: Fit, size: float) -> bool:
    """Whether two fits found one linkage (the same lengths, coupler point and frame pivots, to 1e-6 of the size)."""
    if f.mechanism is None or g.mechanism is None:
        return False
    key = lambda x: np.array([*x.lengths, abs(x.coupler[1]), x.coupler[0], *x.mechanism.joint("A").at,  # noqa: E731
                              *x.mechanism.joint("D").at])
    return bool(np.max(np.abs(key(f) - key(g))) <= 1e-6 * size)
