"""Lower a fitted four-bar's worst point: Lawson's iteratively reweighted least squares towards the minimax fit.

A least-squares fit (:mod:`domes.motion.coupler.fit`) makes the sum of the
squared distances small; a designer, and the path-synthesis literature, judge
a linkage by its worst point. :func:`polish` starts from a fitted four-bar
(any placement, either assembly mode), gives every wanted point the crank
and coupler angle of its nearest position on the linkage's curve, and
re-solves the least squares with weights that grow, round by round, on the
points that stay far (Lawson: ``w ← w · e / Σ w e``), the loop closure
weighted fully throughout. The linkage kept is the one whose largest
distance, measured on its own curve, is smallest; it is never worse than
the start.

>>> from domes.motion.coupler.fourbar import four_bar
>>> from domes.motion.coupler.curves import trace
>>> m = four_bar(1, 3.5, 3, 2, 0, 2)
>>> pts = trace(m, "P", 48).circuits[0].points
>>> polished, (worst, rms) = polish(m, pts)
>>> worst < 1e-6                  # the points of its own curve: met to the chords of the search
True
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import least_squares

from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism
from domes.motion.coupler.fourbar import LINKS

#: Reweighting rounds, and least-squares evaluations in each.
ROUNDS, EVALUATIONS = 10, 30
#: Crank angles per turn at which each point's nearest position is looked for.
GRID = 1024
#: The shortest link a polish may make, relative to the path's size (as the fit's MIN_LINK).
MIN_LINK = 0.02


def _start(mech):
    at = {j.name: complex(*j.at) for j in mech.joints}
    A, B, C, D = (at[k] for k in "ABCD")
    P = complex(*mech.point("P")[1])
    e = (C - B) / abs(C - B)
    uv = (P - B) / e
    return A, D, abs(B - A), abs(C - B), abs(D - C), uv


def _positions(g, theta, sign):
    """Coupler point, coupler angle and closure of the linkage ``g`` at crank angles ``theta`` on mode ``sign``."""
    ax, ay, dx, dy, a, b, c, u, v = g
    A, D = complex(ax, ay), complex(dx, dy)
    B = A + a * np.exp(1j * theta)
    r = D - B
    rr = np.abs(r)
    along = (b * b + rr * rr - c * c) / (2 * np.maximum(rr, 1e-300))
    h = np.sqrt(np.maximum(b * b - along ** 2, 0.0)) * sign
    C = B + (along + 1j * h) * r / np.maximum(rr, 1e-300)
    ok = b * b - along ** 2 >= 0
    psi = np.angle(C - B)
    P = B + (u + 1j * v) * np.exp(1j * psi)
    return np.where(ok, P, np.nan), psi


def _angles(g, T):
    """Each wanted point's crank and coupler angle at its nearest position on the curve (either mode)."""
    _, theta, sign = _nearest(g, T)
    psi = np.zeros(len(T))
    for s in (1.0, -1.0):
        on = sign == s
        if on.any():
            psi[on] = _positions(g, theta[on], s)[1]
    return theta, psi


def _nearest(g, T):
    """``(distance, theta, sign)`` of each point's nearest position on the curve of ``g``: the nearest of
    :data:`GRID` crank angles per turn on either mode, then the chords between 65 angles across the two steps
    about it."""
    theta = np.linspace(-math.pi, math.pi, GRID, endpoint=False)
    h = theta[1] - theta[0]
    d, at, sign = np.full(len(T), np.inf), np.zeros(len(T)), np.ones(len(T))
    for s in (1.0, -1.0):
        P, _ = _positions(g, theta, s)
        dd = np.abs(T[:, None] - P[None, :])
        k = np.argmin(np.where(np.isfinite(dd), dd, np.inf), axis=1)
        local = theta[k][:, None] + np.linspace(-h, h, 65)[None, :]
        Q = _positions(g, local.ravel(), s)[0].reshape(local.shape)
        a, b = Q[:, :-1], Q[:, 1:]                      # the chords between the local positions
        ab = b - a
        t = np.clip(np.real((T[:, None] - a) * np.conj(ab)) / np.maximum(np.abs(ab) ** 2, 1e-300), 0.0, 1.0)
        dq = np.abs(a + t * ab - T[:, None])
        dq = np.where(np.isfinite(dq), dq, np.inf)
        j = np.argmin(dq, axis=1)
        rows = np.arange(len(T))
        dj = dq[rows, j]
        better = dj < d
        d = np.where(better, dj, d)
        at = np.where(better, local[rows, j] + t[rows, j] * (local[rows, j + 1] - local[rows, j]), at)
        sign = np.where(better, s, sign)
    return d, at, sign


def _at(g, theta, sign):
    """The coupler point of ``g`` at each crank angle ``theta`` on each point's mode ``sign``."""
    P = np.empty(len(theta), dtype=complex)
    for s in (1.0, -1.0):
        on = sign == s
        if on.any():
            P[on] = _positions(g, theta[on], s)[0]
    return P


class _Distances:
    """Each point's distance from the curve of the linkage ``g`` (weighted), and its Jacobian: by the envelope
    theorem, the coupler point's motion at the nearest crank angle along the unit normal."""

    def __init__(self, T, w):
        self.T, self.w = T, np.sqrt(w)
        self.g = None
        self.far = 10 * float(np.max(np.abs(T))) + 1.0

    def _update(self, g):
        if self.g is None or not np.array_equal(g, self.g):
            self.g = np.array(g)
            self.d, self.theta, self.sign = _nearest(g, self.T)

    def residuals(self, g):
        self._update(g)
        return self.w * np.where(np.isfinite(self.d), self.d, self.far)

    def jacobian(self, g):
        self._update(g)
        P = _at(g, self.theta, self.sign)
        normal = (self.T - P) / np.maximum(np.abs(self.T - P), 1e-300)
        J = np.zeros((len(self.T), 9))
        for i in range(9):
            h = 1e-7 * max(1.0, abs(g[i]))
            y = np.array(g)
            y[i] += h
            dP = (_at(y, self.theta, self.sign) - P) / h
            J[:, i] = -self.w * np.real(np.conj(normal) * dP)
        return np.where(np.isfinite(J), J, 0.0)


def polish(mech: Mechanism, points, rounds: int = ROUNDS, evaluations: int = EVALUATIONS):
    """``(mechanism, (worst, rms))``: ``mech`` (a four-bar, joints ``A B C D``, coupler point ``P``) moved towards
    the smallest largest distance from ``points``; the distances are those of each point from its nearest
    position on the returned linkage's curve (1,024 crank angles per turn on either mode, refined about the
    nearest)."""
    T = np.asarray(points, dtype=float)
    T = T[:, 0] + 1j * T[:, 1]
    n = len(T)
    size = float(max(np.ptp(T.real), np.ptp(T.imag), 1e-300))
    A, D, a, b, c, uv = _start(mech)
    g = np.array([A.real, A.imag, D.real, D.imag, a, b, c, uv.real, uv.imag])
    best = (_worst(g, T), g)
    w = np.full(n, 1.0 / n)
    lower = np.full(9, -np.inf)
    lower[4:7] = MIN_LINK * size
    for _ in range(rounds):
        model = _Distances(T, w)
        g0 = np.maximum(g, np.where(np.isfinite(lower), lower * 1.01, -np.inf))
        with np.errstate(all="ignore"):
            g = least_squares(model.residuals, g0, jac=model.jacobian, method="trf", bounds=(lower, np.inf),
                              max_nfev=evaluations, x_scale="jac").x
        e, _, _ = _nearest(g, T)
        if not np.all(np.isfinite(e)) or not e.max() > 0:
            break
        score = (float(np.max(e)), float(np.sqrt(np.mean(e ** 2))))
        if score[0] < best[0][0]:
            best = (score, g)
        w = w * e / np.sum(w * e)
        w = np.maximum(w, 1e-6 / n)
    (worst, rms), g = best
    return _mechanism(g, T), (worst, rms)


def _worst(g, T):
    """``(largest, RMS)`` distance of the points from their nearest positions on the curve of ``g``."""
    d, _, _ = _nearest(g, T)
    return float(np.max(d)), float(np.sqrt(np.mean(d ** 2)))


def _mechanism(g, T) -> Mechanism:
    """The four-bar ``g`` drawn where its coupler point is nearest the first wanted point."""
    th, ps = _angles(g, T[:1])
    ax, ay, dx, dy, a, b, c, u, v = g
    A, D = complex(ax, ay), complex(dx, dy)
    B = A + a * complex(math.cos(th[0]), math.sin(th[0]))
    e = complex(math.cos(ps[0]), math.sin(ps[0]))
    C, P = B + b * e, B + complex(u, v) * e
    joints = [Joint("A", "R", ("frame", "crank"), (A.real, A.imag)), Joint("B", "R", ("crank", "coupler"), (B.real, B.imag)),
              Joint("C", "R", ("coupler", "rocker"), (C.real, C.imag)), Joint("D", "R", ("rocker", "frame"), (D.real, D.imag))]
    return Mechanism.build("fitted four-bar", list(LINKS), "frame", joints, [Input("A")],
                           points=[CouplerPoint("P", "coupler", (P.real, P.imag))])


#: Random starts of :func:`timed_fit`, and least-squares evaluations from each.
TIMED_STARTS, TIMED_EVALUATIONS = 60, 200
#: The box of :func:`timed_fit` (times the points' size): pivots and coupler point within BOX of the points'
#: centre, links between MIN_LINK and LONGEST.
BOX, LONGEST = 5.0, 10.0
#: The nine dimensions' names, in the order of a linkage vector ``g``.
DIMENSIONS = ("ax", "ay", "dx", "dy", "a", "b", "c", "u", "v")


def timed_fit(points, rotations, fixed: dict | None = None, starts: int = TIMED_STARTS, seed: int = 0):
    """``(mechanism, first, worst)``: a four-bar whose coupler point meets ``points`` at prescribed crank angles,
    the crank turning by ``rotations`` (rad) from the first point to each later one, by bounded least squares
    from ``starts`` random starts (either assembly mode) in a box of the points' size (links from 2% to 10 times
    it), so that no minimum runs off to infinite links; ``first`` is the crank's angle (world, rad) at the first
    point and ``worst`` the largest distance. ``fixed`` holds dimensions of :data:`DIMENSIONS` given (``{"ax": 0,
    "ay": 0, "dy": 0}``: the crank pivot at the origin, the rocker pivot on the x axis). None when no start closes.

    >>> from domes.motion.coupler.fourbar import four_bar
    >>> m = four_bar(1, 3.5, 3, 2, 0, 2, theta=0.3)
    >>> import numpy as np
    >>> from domes.motion.planar.batch import batch
    >>> b = batch(m, inputs=0.3 + np.radians(np.arange(0, 150, 25)), outputs=["point:P"])
    >>> pts = np.c_[b.values["point:P.x"][0], b.values["point:P.y"][0]]
    >>> mech, first, worst = timed_fit(pts, np.radians(np.arange(25, 150, 25)), starts=4)
    >>> worst < 1e-3                  # a few starts: near the planted linkage (60, the default: 1e-14)
    True
    """
    problem = TimedProblem(points, rotations, fixed)
    size, centre = problem.size, problem.centre
    rng = np.random.default_rng(seed)
    best = None
    for k in range(starts):
        x0 = np.concatenate([centre[:4] + size * rng.uniform(-2, 2, 4), size * rng.uniform(0.1, 2, 3),
                             size * rng.uniform(-2, 2, 2), rng.uniform(-math.pi, math.pi, 1)])
        found = problem.solve(x0, 1.0 if k % 2 else -1.0)
        if best is None or found[0] < best[0]:
            best = found
    worst, x, sign = best
    if not problem.closes(x, sign):
        return None
    return _drawn(x[:9], x[9], sign), float(x[9]), worst


class TimedProblem:
    """The bounded least squares of :func:`timed_fit`, shared with the timed sketches of
    :mod:`domes.motion.coupler.freehand`: the coupler point at crank angle ``first + speed · rotation`` meets each
    point, in the box of :func:`timed_fit`. A linkage is ``x = (ax ay dx dy a b c u v, first, speed)``; ``speed``
    is 1 unless ``speed=True`` makes it free (the crank's speed unknown, ``rotations`` then its times)."""

    def __init__(self, points, rotations, fixed: dict | None = None, speed: bool = False):
        T = np.asarray(points, dtype=float)
        self.T = T[:, 0] + 1j * T[:, 1]
        self.rel = np.concatenate([[0.0], np.asarray(rotations, dtype=float)])
        if len(self.rel) != len(self.T):
            raise ValueError(f"one crank rotation per point after the first ({len(self.T) - 1}), got "
                             f"{len(self.rel) - 1}")
        fixed = dict(fixed or {})
        self.size = size = float(max(np.ptp(self.T.real), np.ptp(self.T.imag), 1e-300))
        c = self.T.mean()
        self.centre = np.array([c.real, c.imag, c.real, c.imag, 0, 0, 0, 0, 0])
        self.lo = np.concatenate([self.centre[:4] - BOX * size, np.full(3, MIN_LINK * size), np.full(2, -BOX * size),
                                  [-np.inf, -np.inf]])
        self.hi = np.concatenate([self.centre[:4] + BOX * size, np.full(3, LONGEST * size), np.full(2, BOX * size),
                                  [np.inf, np.inf]])
        self.free = [k for k, name in enumerate(DIMENSIONS) if name not in fixed] + [9] + ([10] if speed else [])
        self.full = np.zeros(11)
        self.full[10] = 1.0
        for k, name in enumerate(DIMENSIONS):
            if name in fixed:
                self.full[k] = fixed[name]
        self.evaluations = 0

    def positions(self, x, sign: float) -> np.ndarray:
        """The coupler point of the linkage ``x`` (mode ``sign``) at each point's crank angle (NaN: not closed)."""
        return _positions(x[:9], x[9] + x[10] * self.rel, sign)[0]

    def residuals(self, y, sign: float) -> np.ndarray:
        self.evaluations += 1
        x = self.full.copy()
        x[self.free] = y
        P = self.positions(x, sign)
        r = np.where(np.isfinite(P), P - self.T, 10.0 * self.size)
        return np.concatenate([r.real, r.imag]) / self.size

    def solve(self, x0, sign: float, evaluations: int = TIMED_EVALUATIONS):
        """``(worst, x, sign)``: the bounded least squares from ``x0`` (ten or eleven entries) on mode ``sign``."""
        start = self.full.copy()
        start[:len(x0)] = x0
        lo, hi = self.lo[self.free], self.hi[self.free]
        y0 = np.clip(start[self.free], lo + 1e-9 * self.size, hi - 1e-9 * self.size)
        with np.errstate(all="ignore"):
            y = least_squares(self.residuals, y0, args=(sign,), bounds=(lo, hi), method="trf",
                              max_nfev=evaluations).x
        r = self.residuals(y, sign)
        n = len(self.T)
        x = self.full.copy()
        x[self.free] = y
        return float(np.max(np.hypot(r[:n], r[n:]))) * self.size, x, sign

    def closes(self, x, sign: float) -> bool:
        """Whether the linkage ``x`` closes at the first point's crank angle."""
        return bool(np.isfinite(_positions(x[:9], x[9] + x[10] * self.rel[:1], sign)[0][0]))

    def mechanism(self, x, sign: float) -> Mechanism:
        """The linkage ``x`` drawn at the first point's crank angle."""
        return _drawn(x[:9], x[9], sign)


def _drawn(g, theta: float, sign: float) -> Mechanism:
    """The four-bar ``g`` drawn with its crank at ``theta`` on assembly mode ``sign``."""
    ax, ay, dx, dy, a, b, c, u, v = g
    A, D = complex(ax, ay), complex(dx, dy)
    B = A + a * complex(math.cos(theta), math.sin(theta))
    r = D - B
    along = (b * b + abs(r) ** 2 - c * c) / (2 * abs(r))
    C = B + complex(along, sign * math.sqrt(max(b * b - along * along, 0.0))) * r / abs(r)
    P = B + complex(u, v) * (C - B) / abs(C - B)
    joints = [Joint("A", "R", ("frame", "crank"), (A.real, A.imag)), Joint("B", "R", ("crank", "coupler"), (B.real, B.imag)),
              Joint("C", "R", ("coupler", "rocker"), (C.real, C.imag)), Joint("D", "R", ("rocker", "frame"), (D.real, D.imag))]
    return Mechanism.build("fitted four-bar", list(LINKS), "frame", joints, [Input("A")],
                           points=[CouplerPoint("P", "coupler", (P.real, P.imag))])
