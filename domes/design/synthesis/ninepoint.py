"""Every four-bar whose coupler curve passes through nine given points (Wampler, Morgan & Sommese 1992).

Nine points fix a four-bar's coupler curve up to finitely many linkages: in isotropic coordinates
(:mod:`~domes.design.synthesis.isotropic`) 8 dyad-pair equations in the linkage's eight coordinates after the
coupler rotations are eliminated, with 8,652 nonsingular solutions for generic points, 1,442 classes of six: the
three Roberts-Chebyshev cognates (one coupler curve) and the two labellings of each (which dyad is ``a``). A
parameter homotopy (:mod:`~domes.design.synthesis.homotopy`) tracks one member of each class from a stored
generic solution set (``ninepoint.npz``, made by ``benchmarks/make_ninepoint_start.py``: one planted four-bar,
then monodromy loops) to the given points; every end point is refined by Newton (a solution far out, which double
coordinates cannot carry, in extended precision: :func:`refine_extended`), its residual and condition number
kept, its five other class members made by :func:`orbit`, and each real one checked as a mechanism by the
project's checks and kinematics kernel (branch, order and dead-point defects; the kernel driving the crank
through its nine angles must put the coupler point on the points).

>>> import numpy as np
>>> from domes.design.synthesis.isotropic import DyadSystem, plant
>>> z, p = plant(DyadSystem(8), np.random.default_rng(1))
>>> keys = np.concatenate([class_key(w, p) for w in orbit(z, p)])
>>> float(np.abs(keys - keys[0]).max()) < 1e-12          # the six members of a class share the three pivots
True
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

import numpy as np

from domes.design.synthesis import homotopy as hc
from domes.design.synthesis.fourbars import Checks, FourBar, check
from domes.design.synthesis.isotropic import DyadSystem
from domes.design.synthesis.verify import Claim
from domes.design.synthesis.verify import check as replay_check
from domes.errors import InputError
from domes.results import Result, Status

#: Classes of nonsingular solutions for generic points (Wampler, Morgan & Sommese 1992: 8,652 in classes of six).
CLASSES = 1442
#: Solutions of five points with both fixed pivots given, generic points (Morgan & Wampler 1990).
FIVE_POINT_COUNT = 36
#: The stored generic solution sets.
START = Path(__file__).with_name("ninepoint.npz")
#: A refined end point is a solution when its residual, as a distance (:meth:`DyadSystem.point_error`), is within
#: this (the points scaled to size 1; issue 27 asks every curve through the nine points within 1e-8 of the size).
RESIDUAL = 1e-8
#: An end point whose residual is over this after Newton is refined again on an extended-precision residual (a
#: solution far out, 10⁶ sizes, stops at double round-off near 1e-9).
POLISH = 1e-10
#: The affine first pass's predictor tolerance (relative to ``1 + |z|``): looser than the retries' (a path that
#: jumps ends on another's class and is tracked again).
FIRST_TOL = 3e-4
#: A solution is real when its coordinates equal the conjugates of their partners within this (relative).
REAL = 1e-7
#: Digits of the extended precision (mpmath) in which a solution far out is refined, certified and kept.
EXTENDED_DPS = 40
#: :data:`REAL` for extended-precision coordinates: their last Newton step is 10⁻²⁵ or less, relative.
REAL_EXTENDED = 1e-20
#: A path's end point within this of a solution (residual as a distance) is tried in extended precision.
NEAR = 1e-4


def relabel(z):
    """The same linkage with its two dyads swapped (``x, a`` with ``y, b``)."""
    w = np.array(z)
    w[:, 0:4], w[:, 4:8] = z[:, 4:8], z[:, 0:4]
    return w


def cognate(z, p):
    """A Roberts-Chebyshev cognate: fixed pivots ``a`` and ``c = (a y − b x)/(y − x)``, its first crank the old
    coupler's parallel (``x' = a − x``) turning with the old coupler, its coupler turning with the old crank."""
    n = (z.shape[1] - 8) // 2
    x, xb, a, ab, y, yb, b, bb = (z[:, k:k + 1] for k in range(8))
    th, thb = z[:, 8:8 + n], z[:, 8 + n:]
    d, db = p[:, :n], p[:, n:2 * n]
    return np.concatenate([a - x, ab - xb, a, ab, (a - x) * y / (y - x), (ab - xb) * yb / (yb - xb),
                           (a * y - b * x) / (y - x), (ab * yb - bb * xb) / (yb - xb),
                           (d + th * x - a) / (x - a), (db + thb * xb - ab) / (xb - ab)], axis=1)


def orbit(z, p) -> list:
    """The six members of each row's class: itself, relabelled, its two cognates, and theirs relabelled."""
    c = cognate(z, p)
    other = cognate(relabel(z), p)
    return [z, relabel(z), c, relabel(c), other, relabel(other)]


def class_key(z, p):
    """The elementary symmetric functions of the three fixed pivots ``a, b, c`` (and of ``ā, b̄, c̄``): the same
    for the six members of a class."""
    x, xb, a, ab, y, yb, b, bb = (z[:, k] for k in range(8))
    c = (a * y - b * x) / (y - x)
    cb = (ab * yb - bb * xb) / (yb - xb)
    return np.stack([a + b + c, a * b + b * c + c * a, a * b * c, ab + bb + cb, ab * bb + bb * cb + cb * ab,
                     ab * bb * cb], axis=1)


@lru_cache(maxsize=1)
def start_set() -> dict:
    """The stored generic solutions and their parameters (``nine_z``, ``nine_p``, ``five_z``, ``five_p``)."""
    with np.load(START) as data:
        return {k: data[k] for k in data.files}


@dataclass(frozen=True)
class NinePointSolution:
    """One solution: ``fourbar`` (pivots in the first position, coupler point at point 1; None when complex), its
    class and member (0: the tracked one), the isotropic coordinates ``z`` (in the points' units), the Newton
    ``residual`` as a distance over the points' size (how far a dyad's length is off) and the scaled Jacobian's
    ``condition``; for a real one its ``checks`` (defects), the kernel's
    distance from each point (``distances``, in length units) and whether it is ``usable``. A solution far out,
    whose double coordinates cannot carry it (its residual in double over :data:`POLISH`), or whose class's
    members disagree on being real, also has ``extended``: its coordinates refined by Newton in mpmath
    (:data:`EXTENDED_DPS` digits; ``mpc``, the same units as ``z``), from which its ``residual``, its being real
    and its four-bar are taken (``z`` is then ``extended`` rounded to double)."""

    cls: int
    member: int
    z: np.ndarray = field(repr=False)
    real: bool
    residual: float
    condition: float
    fourbar: FourBar | None = None
    checks: Checks | None = None
    distances: tuple[float, ...] = ()
    defects: tuple[str, ...] = ()
    extended: tuple | None = field(default=None, repr=False)

    @property
    def usable(self) -> bool:
        """Real, with no branch, order or dead-point defect, the kernel on every point."""
        return self.real and self.checks is not None and not self.defects


class Solutions:
    """The real and the usable ones among a result's ``solutions``."""

    @property
    def real(self) -> tuple[NinePointSolution, ...]:
        return tuple(s for s in self.solutions if s.real)

    @property
    def usable(self) -> tuple[NinePointSolution, ...]:
        return tuple(s for s in self.solutions if s.usable)


@dataclass(frozen=True, eq=False)
class NinePointPath(Solutions, Result):
    """Every solution through nine points, grouped by class (``classes[k]``: the six members of class ``k``)."""

    points: tuple
    size: float
    classes: tuple[tuple[NinePointSolution, ...], ...]
    tracked: int
    failed: int
    retracked: int
    seconds: float
    notes: tuple[str, ...] = ()

    @property
    def solutions(self) -> tuple[NinePointSolution, ...]:
        return tuple(s for c in self.classes for s in c)

    @property
    def status(self) -> Status:
        return Status.COMPLETE if len(self.classes) == CLASSES else Status.STOPPED

    @property
    def message(self) -> str:
        real = sum(1 for c in self.classes if c[0].real)
        found = (f"all {CLASSES} classes" if len(self.classes) == CLASSES else
                 f"{len(self.classes)} of the {CLASSES} classes")
        return (f"{self.status}: nine points: {found} ({len(self.solutions)} solutions), {real} real classes, "
                f"{len(self.usable)} usable linkage(s) (no branch, order or dead-point defect); "
                f"{self.failed} path(s) failed; {self.seconds:.1f} s")


def check_points(points, count: int = 9) -> np.ndarray:
    """The points as an array, or an :class:`InputError` saying what is wrong with them."""
    try:
        P = np.asarray(points, dtype=float)
    except (TypeError, ValueError) as exc:
        raise InputError(f"points: expected {count} pairs of numbers ({exc})") from None
    if P.shape != (count, 2):
        raise InputError(f"points: expected {count} points (x, y), got an array of shape {P.shape}")
    if not np.isfinite(P).all():
        raise InputError(f"points: point {int(np.flatnonzero(~np.isfinite(P).all(axis=1))[0]) + 1} is not finite")
    size = float(np.ptp(P, axis=0).max())
    for j in range(count):
        for k in range(j):
            if math.dist(P[j], P[k]) <= 1e-9 * max(size, 1e-300):
                raise InputError(f"points: points {k + 1} and {j + 1} coincide")
    return P


def _ends(system, z0, p0, p1, gamma, tol, chart=None):
    """Track the rows of ``z0`` (affine, or on the projective ``chart``) and refine their end points: the end
    points and whether each is certified."""
    if chart is None:
        end = hc.track(system, z0, p0, p1, gamma=gamma, tol=tol)
        z = end.z
    else:
        end = hc.track(chart, chart.lift(z0), p0, p1, gamma=gamma, tol=tol)
        z = chart.drop(end.z)
    return _polished(system, z, p1, end.status == hc.DONE)


def _polished(system, z, p1, done=True):
    """Newton from the rows of ``z``, again on an extended residual for those over :data:`POLISH`: the points and
    whether each (of those ``done``) is a solution within :data:`RESIDUAL`."""
    pp = np.broadcast_to(p1, (len(z), system.q))
    z = hc.refine(system, z, pp)[0]
    rough = np.flatnonzero(~(system.point_error(z, pp) < POLISH) & done)
    if len(rough):
        z[rough] = hc.refine(system, z[rough], pp[rough], iterations=4, extended=True)[0]
    error = system.point_error(z, pp)
    # a solution far out whose double residual cannot reach RESIDUAL: certified in extended precision
    for k in np.flatnonzero(done & (error >= RESIDUAL) & (error < NEAR)):
        w, error[k] = refine_extended(system, z[k], pp[k])
        z[k] = w.astype(complex)
    return z, done & (error < RESIDUAL)


def refine_extended(system, z, p):
    """The row ``z`` refined at ``p`` by Newton in extended precision (:func:`~.homotopy.refine_mp`,
    :data:`EXTENDED_DPS` digits): the coordinates (``mpc``) and their residual as a distance, measured in the
    same precision (infinite when Newton has not settled)."""
    import mpmath

    w, step = hc.refine_mp(system, z, p, EXTENDED_DPS)
    with mpmath.workdps(EXTENDED_DPS):
        error = float(system.point_error(w[None], hc.mp_array(p)[None])[0])
    return w, error if step < 1e-12 else math.inf


def _track(system, z0, p0, p1, gamma, key, rng, tries: int = 3):
    """Track every row (affine), then on a random projective chart (the same γ, so the same end points; smaller
    steps each try) those that failed and those that ended on the class of another (of two such, the one tracked
    last, or both: jumped paths), then from its cognates each still failing: every certified end point met, how
    many paths were tracked again and how many failed in the end. A path that passes near infinity, where the
    affine tracker fails, stays bounded on the chart."""
    pp = np.broadcast_to(p1, (len(z0), system.q))
    chart = hc.Projective(system, rng)
    z = np.zeros_like(z0)
    good = np.zeros(len(z0), bool)
    todo = np.arange(len(z0))
    ends, retracked = [], 0
    for attempt in range(tries):
        z[todo], good[todo] = _ends(system, z0[todo], p0, p1, gamma, hc.TRACK_TOL / 4 ** (attempt - 1) if attempt
                                    else FIRST_TOL, chart if attempt else None)
        ends.append(z[todo][good[todo]])
        retracked += len(todo) if attempt else 0
        ok = np.flatnonzero(good)
        now = set(todo.tolist())
        suspect = set()
        for i, j in hc.twins(key(z[ok], pp[:len(ok)])):
            pair = [int(ok[i]), int(ok[j])]
            suspect |= {k for k in pair if k in now} or set(pair)
        todo = np.array(sorted(set(np.flatnonzero(~good).tolist()) | suspect), int)
        good[todo] = False
        if not len(todo):
            break
    failed = np.flatnonzero(~good)
    if len(failed):
        # the same class from a cognate: a path to a solution far out may be one to a cognate near by
        for member in (2, 4):
            p0s = np.broadcast_to(p0, (len(failed), system.q))
            zz, done = _ends(system, orbit(z0[failed], p0s)[member], p0s, p1, gamma, hc.TRACK_TOL / 4, chart)
            ends.append(zz[done])
            good[failed[done]] = True
            retracked += len(failed)
            failed = failed[~done]
            if not len(failed):
                break
    return np.concatenate(ends), retracked, len(failed)


def _classes(system, z0, p0, p1, rng, progress=None, passes: int = 1):
    """One certified end point of every class reached: a first pass of every path on a random γ arc, and while
    classes are missing another on another arc (its end points joined to the first's)."""
    reps = np.zeros((0, z0.shape[1]), complex)
    retracked = failed = 0
    for k in range(passes):
        if k and progress:
            progress(f"{len(reps)} classes after pass {k}: tracking again on another arc")
        ends, again, failed = _track(system, z0, p0, p1, np.exp(1j * rng.uniform(-np.pi, np.pi)), class_key, rng)
        retracked += again + (len(z0) if k else 0)
        both = np.concatenate([reps, ends])
        reps = both[hc.distinct(class_key(both, np.broadcast_to(p1, (len(both), system.q))))]
        if len(reps) >= len(z0):
            break
    return reps, retracked, failed


def nine_point_path(points, seed: int = 0, check_mechanisms: bool = True, passes: int = 1,
                    progress=None) -> NinePointPath:
    """Every four-bar whose coupler point passes through the nine ``points`` (in that order along the curve when
    ``usable``), grouped by class; ``seed`` draws the γ of the homotopy's arc; while classes are missing, up to
    ``passes`` arcs are tracked. About 15 s of one core a pass (docs/synthesis.md, "Nine points").
    """
    t0 = time.perf_counter()
    P = check_points(points)
    size = float(np.ptp(P, axis=0).max())
    rel = (P - P[0]) / size
    d = rel[1:, 0] + 1j * rel[1:, 1]
    p1 = np.concatenate([d, d.conj()])[None]
    data = start_set()
    system = DyadSystem(8)
    rng = np.random.default_rng(seed)
    if progress:
        progress(f"tracking {len(data['nine_z'])} paths")
    reps, retracked, failed = _classes(system, data["nine_z"], data["nine_p"][None], p1, rng, progress, passes)
    pp = np.broadcast_to(p1, (len(reps), system.q))
    # a member made by `orbit` far out may stop at double round-off: Newton again on an extended residual
    members = [_polished(system, w, p1)[0] for w in orbit(reps, pp)]
    if progress:
        progress(f"{len(reps)} classes; checking the real ones")
    quality = [certify(system, w, p1) for w in members]
    far = far_out(members, quality)
    fine = {(k, m): refine_extended(system, members[m][k], p1[0]) for k in far for m in range(6)}
    classes = [tuple(solution(k, m, members[m][k], quality[m][0][k], quality[m][1][k], P, size, check_mechanisms,
                              fine.get((k, m))) for m in range(6)) for k in range(len(reps))]
    notes = []
    if len(reps) < CLASSES:
        notes.append(f"{CLASSES - len(reps)} class(es) not found: their paths failed or the points are not generic")
    return NinePointPath(tuple(map(tuple, P)), size, tuple(classes), len(data["nine_z"]), failed, retracked,
                         time.perf_counter() - t0, tuple(notes))


def far_out(members, quality) -> list[int]:
    """The classes to refine in extended precision: a member's double residual over :data:`POLISH` (a solution
    far out, whose double coordinates cannot carry it), or members that disagree on being real (a far-out one's
    coordinates off by 10⁻⁷ of themselves: the solution is ill-conditioned along a long link)."""
    rough = np.any([q[0] > POLISH for q in quality], axis=0)
    real = np.array([real_rows(w) for w in members])
    return np.flatnonzero(rough | (real.any(axis=0) & ~real.all(axis=0))).tolist()


def real_rows(z, tol: float = REAL):
    """:func:`is_real` of each row of ``z`` (double), vectorised."""
    n = (z.shape[1] - 8) // 2
    u = z[:, [0, 2, 4, 6, *range(8, 8 + n)]]
    v = z[:, [1, 3, 5, 7, *range(8 + n, 8 + 2 * n)]]
    return (np.abs(u.conj() - v) <= tol * (1 + np.abs(u))).all(axis=1)


def is_real(z, tol: float = REAL) -> bool:
    """Whether the isotropic coordinates are those of a real linkage (each ``z̄`` the conjugate of ``z`` within
    ``tol`` of ``1 + |z|``; double or ``mpc`` values)."""
    n = (len(z) - 8) // 2
    pairs = [(z[k], z[k + 1]) for k in range(0, 8, 2)] + [(z[8 + j], z[8 + n + j]) for j in range(n)]
    return all(abs(u.conjugate() - v) <= tol * (1 + abs(u)) for u, v in pairs)


def certify(system, z, p):
    """Residual norms and Jacobian condition numbers of the rows of ``z`` at ``p``."""
    p = np.broadcast_to(p, (len(z), system.q))
    return system.point_error(z, p), hc.condition(system, z, p)


def solution(k, m, z, res, cond, P, size, check_mechanisms, fine=None) -> NinePointSolution:
    """The solution ``z`` (eight linkage coordinates and the rotations, points scaled to size 1) with its
    residual and condition; a real one as a four-bar, checked for defects (the kernel replays the defect-free).
    ``fine``: its extended-precision coordinates and residual (:func:`refine_extended`), which then decide."""
    ext = None
    if fine is None:
        real = is_real(z)
        linkage = real_fourbar(z, P, size) if real else None
    else:
        import mpmath

        with mpmath.workdps(EXTENDED_DPS):                  # mpc arithmetic rounds to the working precision
            w, res = fine
            real = is_real(w, REAL_EXTENDED)
            linkage = real_fourbar(w, P, size) if real else None
            ext = tuple(c * size if i < 8 else c for i, c in enumerate(w))
            z = w.astype(complex)
    scaled = np.array(z)
    scaled[:8] *= size
    head = (k, m, scaled, real, float(res), float(cond))
    if not real:
        return NinePointSolution(*head, extended=ext)
    fb, A, B = linkage
    if not check_mechanisms:
        return NinePointSolution(*head, fb, extended=ext)
    checks = check(fb, A, B)
    if checks.defects:
        return NinePointSolution(*head, fb, checks, (), checks.defects, extended=ext)
    dist, defects = replay_check(fb, Claim(angles=tuple(math.radians(a) for a in checks.crank_angles_deg),
                                           points=tuple(map(tuple, P))), 1e-8, size)
    return NinePointSolution(*head, fb, checks, dist, defects, extended=ext)


def real_fourbar(z, P, size):
    """The real linkage of ``z`` (points' units; double or ``mpc`` values, these rounded once their real parts are
    taken): the four-bar and its moving pivots at every point."""
    n = (len(z) - 8) // 2
    x, a, y, b = ((z[k] + z[k + 1].conjugate()) / 2 for k in (0, 2, 4, 6))
    th = np.concatenate([[1.0], z[8:8 + n]])
    th = th / np.abs(th)
    if z.dtype == object:                                   # the four-bar holds doubles
        x, a, y, b = (complex(v) for v in (x, a, y, b))
        th = th.astype(complex)
    c = P[:, 0] + 1j * P[:, 1]
    A = c + size * th * x
    B = c + size * th * y
    a0, b0 = c[0] + size * a, c[0] + size * b

    def xy(w):
        return (float(w.real), float(w.imag))

    fb = FourBar(xy(a0), xy(A[0]), xy(B[0]), xy(b0), xy(c[0]))
    return fb, [xy(w) for w in A], [xy(w) for w in B]
