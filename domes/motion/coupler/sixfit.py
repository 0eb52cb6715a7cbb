"""Fit a Watt or Stephenson six-bar to a wanted closed path, from an atlas candidate, by least squares.

As for four-bars (:mod:`domes.motion.coupler.fit`): the candidate's curve
and the path are overlaid (FFT correspondence) to give each wanted point a
crank angle, coupler angle and tracer-link angle on the candidate; least
squares then moves the twelve dimensions of
:class:`~domes.motion.coupler.sixbar.SixBar`, the placement and every
point's three angles, with the two loop closures as residuals of their own,
until the tracing point passes through the wanted points. That model
trades the points' distance against the closures' (on a short tracer link
a closure's error moves the point many times as far) and is drawn to
collapsed links, so the fit goes on with both loops closed
(:class:`ClosedModel`: each point only its crank angle, each loop its mode),
minimising the distance the kernel measures; every link is kept at least
2% of the path's size throughout (a collapsed link fits anything). The fitted
linkage is placed in the path's frame and verified by the kinematics
kernel at every point's crank angle (each point in the assembly modes
nearest it): the reported error comes from the kernel, not from the model.

>>> from domes.motion.coupler.sixbar import SixBar
>>> s = SixBar("stephenson", (0.3, 1.2, 1.0, 1.0, 0.5, 0.4, 1.2, 1.3, 1.5, 1.2, 0.6, 0.3), (1, 1))
>>> path = s.curve(np.linspace(0, 2 * np.pi, 40, endpoint=False))
>>> f = sixfit(np.c_[path.real, path.imag], s)
>>> f.success, f.kind
(True, 'Stephenson III six-bar')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.coupler.fit import MAX_POINTS, MIN_LINK, Fit, _correspond, _spread, check_wanted
from domes.motion.coupler.sixbar import KINDS, SixBar, circle_meet, drawn_mechanism
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import Kinematics
from domes.results import Status

#: Crank angles a candidate is traced at, to correspond it with the path.
TRACE = 720
#: Global unknowns: a, b, c, d, p, q, e, f, g, h, u, v and the placement tx, ty, φ.
GLOBAL = 15
METHOD = "lm"
#: Evaluations per round of the refinement (it stops between rounds once it fits or stalls).
ROUND = 40
#: A round that leaves the largest residual above this share of the last ends the refinement (it has stalled).
STALL = 0.97
#: Evaluations of the refinement with both loops closed (:class:`ClosedModel`), after the first stops short.
CLOSED = 300
#: Where the link lengths ``a, b, c, d, e, f`` are among the unknowns.
LENGTHS = [0, 1, 2, 3, 6, 7]


@dataclass(frozen=True, eq=False)
class SixFit(Fit):
    """A six-bar fitted to a wanted path: the linkage placed in the path's frame (joints ``A``-``G``, the
    tracing point ``P`` on link ``E F``), its ``kind``, its link lengths ``(a, b, c, d, e, f)``, ``E``'s place
    ``ternary = (p, q)`` on its link and ``P``'s ``coupler = (u, v)`` on ``E F`` (the path's units); the rest as
    for a four-bar's :class:`~domes.motion.coupler.fit.Fit`."""

    kind: str = ""
    ternary: tuple = ()

    @property
    def message(self) -> str:
        text = (f"{self.status}: {self.kind}, largest distance {self.after[0]:.3g} (RMS {self.after[1]:.3g}) after "
                f"refinement, {self.before[0]:.3g} before; path size {self.size:.4g}")
        return text + (f"; {self.note}" if self.note else "")


class SixModel:
    """The tracing point of a placed six-bar at each point's crank, coupler and tracer-link angles.

    Each wanted point has three unknown angles and four residuals: its two
    coordinates and the two loop closures (``|C − D| = c``, ``|F − G| = f``).
    """

    blocks = 3

    def __init__(self, target, kind: str, mirror: bool):
        self.target, self.kind, self.mirror = np.asarray(target, dtype=float), kind, mirror
        self.n = len(self.target)

    def joints(self, x):
        a, b, c, d, p, q, e, f, g, h, u, v, tx, ty, phi = x[:GLOBAL]
        n = self.n
        theta, psi, chi = x[GLOBAL:GLOBAL + n], x[GLOBAL + n:GLOBAL + 2 * n], x[GLOBAL + 2 * n:]
        B = a * np.exp(1j * theta)
        C = B + b * np.exp(1j * psi)
        if self.kind == "stephenson":
            E = B + (p + 1j * q) * np.exp(1j * psi)
        else:
            E = d + (p + 1j * q) * (C - d) / np.abs(C - d)
        t = np.exp(1j * chi)
        return {"A": 0 * B, "B": B, "C": C, "D": d + 0 * B, "E": E, "F": E + e * t, "G": g + 1j * h + 0 * B,
                "P": E + (u + 1j * v) * t}

    def place(self, x, z):
        tx, ty, phi = x[12:15]
        return (np.conj(z) if self.mirror else z) * np.exp(1j * phi) + (tx + 1j * ty)

    def residuals(self, x):
        at = self.joints(x)
        P = self.place(x, at["P"])
        return np.concatenate([P.real - self.target[:, 0], P.imag - self.target[:, 1],
                               np.abs(at["C"] - at["D"]) - x[2], np.abs(at["F"] - at["G"]) - x[7]])

    def jacobian(self, x):
        """Forward differences: one evaluation per global unknown and one per kind of angle (all points at once)."""
        f0, n = self.residuals(x), self.n
        J = np.zeros((4 * n, x.size))
        for i in range(GLOBAL):
            h = 1e-7 * max(1.0, abs(x[i]))
            y = x.copy()
            y[i] += h
            J[:, i] = (self.residuals(y) - f0) / h
        idx = np.arange(n)
        for block in range(self.blocks):
            y = x.copy()
            y[GLOBAL + block * n:GLOBAL + (block + 1) * n] += 1e-7
            df = (self.residuals(y) - f0) / 1e-7
            for k in range(4):
                J[k * n + idx, GLOBAL + block * n + idx] = df[k * n:(k + 1) * n]
        return J


class ClosedModel(SixModel):
    """The tracing point with both loops closed: each point has only its crank angle, each loop its assembly mode
    (kept from a fit of :class:`SixModel`), and the residuals are the point's two coordinates and how far each loop is
    from assembling (0 where it does). The distance it minimises is the one the kernel measures, where a
    :class:`SixModel` fit trades the points' distance against the closures' (amplified on a long tracer)."""

    blocks = 1

    def __init__(self, target, kind: str, mirror: bool, modes):
        super().__init__(target, kind, mirror)
        self.modes = modes

    @classmethod
    def closing(cls, model: SixModel, x):
        """The closed model and its start from a fit ``x`` of ``model``: signs of lengths folded into the angles."""
        at = model.joints(x)
        m1 = np.where(np.imag((at["C"] - at["B"]) * np.conj(at["D"] - at["B"])) < 0, -1.0, 1.0)
        m2 = np.where(np.imag((at["F"] - at["E"]) * np.conj(at["G"] - at["E"])) < 0, -1.0, 1.0)
        y = np.concatenate([x[:GLOBAL], x[GLOBAL:GLOBAL + model.n]])
        for i, ij in ((1, (4, 5)), (6, (10, 11))):         # E = B + (p + iq)(C - B)/b, P = E + (u + iv)(F - E)/e
            if y[i] < 0:
                y[i], y[list(ij)] = -y[i], -y[list(ij)]
        if y[0] < 0:
            y[0], y[GLOBAL:] = -y[0], y[GLOBAL:] + np.pi
        y[[2, 7]] = np.abs(y[[2, 7]])
        return cls(model.target, model.kind, model.mirror, (m1, m2)), y

    def _closed(self, x):
        a, b, c, d, p, q, e, f, g, h, u, v = x[:12]
        B = a * np.exp(1j * x[GLOBAL:])
        D = d + 0 * B
        C, _ = circle_meet(B, D, b, c, self.modes[0])
        if self.kind == "stephenson":
            E = B + (p + 1j * q) * (C - B) / b
        else:
            E = D + (p + 1j * q) * (C - D) / np.abs(C - D)
        G = g + 1j * h + 0 * B
        F, _ = circle_meet(E, G, e, f, self.modes[1])
        return {"A": 0 * B, "B": B, "C": C, "D": D, "E": E, "F": F, "G": G, "P": E + (u + 1j * v) * (F - E) / e}

    def joints(self, x):
        return self._closed(x)

    def residuals(self, x):
        at = self._closed(x)
        P = self.place(x, at["P"])
        gaps = [np.maximum.reduce([np.abs(Y - X) - abs(r1) - abs(r2), np.abs(abs(r1) - abs(r2)) - np.abs(Y - X),
                                   0 * X.real])
                for X, Y, r1, r2 in ((at["B"], at["D"], x[1], x[2]), (at["E"], at["G"], x[6], x[7]))]
        return np.concatenate([P.real - self.target[:, 0], P.imag - self.target[:, 1], *gaps])


def start(target, candidate: SixBar):
    """``(x0, mirror)``: the candidate overlaid on the path (each point's angles and the placement)."""
    theta = np.linspace(0.0, 2 * np.pi, TRACE, endpoint=False)
    at, ok = candidate.joints(theta)
    if not ok.all():
        raise InputError("the candidate does not assemble all round")

    class Circuit:
        points = np.c_[at["P"].real, at["P"].imag]

    _, sc, mirror = _correspond(target, Circuit)
    closed = np.append(at["P"], at["P"][0])
    s = np.concatenate(([0.0], np.cumsum(np.abs(np.diff(closed)))))
    s /= s[-1]

    def angle(z):
        w = np.unwrap(np.angle(z))
        return np.interp(sc, s, np.append(w, w[-1] + math.remainder(w[0] - w[-1], 2 * np.pi)))

    Pc = np.interp(sc, s, closed.real) + 1j * np.interp(sc, s, closed.imag)
    Pc = np.conj(Pc) if mirror else Pc
    T = target[:, 0] + 1j * target[:, 1]
    p0, t0 = Pc - Pc.mean(), T - T.mean()
    w = np.sum(np.conj(p0) * t0) / np.sum(np.abs(p0) ** 2)
    shift = T.mean() - w * Pc.mean()
    thetas = np.interp(sc, s, np.append(theta, 2 * np.pi))
    psis = angle(at["C"] - at["B"])
    chis = angle(at["F"] - at["E"])
    x0 = np.concatenate([np.asarray(candidate.lengths) * abs(w), [shift.real, shift.imag, np.angle(w)],
                         thetas, psis, chis])
    return x0, mirror


def sixfit(points, candidate: SixBar, tol: float = 1e-6, max_nfev: int = 400, quick: int = 0) -> SixFit:
    """Fit the six-bar type of ``candidate`` to the closed path through ``points``, starting from ``candidate``.

    ``quick`` > 0 stops after that many evaluations and skips the kernel's
    verification (the model's error is reported): a first pass over many
    candidates, to refine the best of them fully.
    """
    target = check_wanted(points)
    size = float(np.max(np.ptp(target, axis=0)) or 1.0)
    if len(target) > MAX_POINTS:
        target = _spread(target, MAX_POINTS, closed=True)
    centre = target.mean(axis=0)
    unit = (target - centre) / size                       # fitted at size 1, placed back in the path's frame
    if isinstance(candidate, tuple):                      # a short fit's (x, mirror, kind), to go on from
        x0, mirror, kind = candidate
    else:
        (x0, mirror), kind = start(unit, candidate), candidate.kind
    model = SixModel(unit, kind, mirror)
    before = _errors(model.residuals(x0), size)
    x, fun, nfev = _solve(model, _bounded(x0), quick or max_nfev, 0.0 if quick else 0.3 * tol)
    if not quick:                                         # then the loops closed: the distance the kernel measures
        model, x = ClosedModel.closing(model, x)
        x, fun, used = _solve(model, _bounded(x), CLOSED, 0.3 * tol)
        nfev += used
    a, b, c, d, p, q, e, f, g, h, u, v = (float(t) * size for t in x[:12])
    if kind == "stephenson" and b < 0:                     # a length's sign is a half turn of its link
        p, q = -p, -q
    if e < 0:
        u, v = -u, -v
    a, b, c, d, e, f = (abs(t) for t in (a, b, c, d, e, f))
    mech, note, status = None, "", Status.COMPLETE
    if quick:
        after, status = _errors(fun, size), Status.STOPPED
        mech = (x, mirror, kind)
    else:
        try:
            mech = _mechanism(model, x, size, centre)
            after = _verify(mech, model, x, size, centre, target)
        except InputError as exc:
            after, status = _errors(fun, size), Status.STOPPED
            note = f"the fitted linkage could not be placed: {exc}"
    return SixFit(mech, (a, b, c, d, e, f), (u, v), before, after, size, tol, nfev, status, note,
                  kind=KINDS[kind], ternary=(p, q))


def _bounded(x):
    """``x`` with every link length (``a, b, c, d, e, f``) at least :data:`MIN_LINK` of the size, its sign kept (a
    negative length is a half turn of its link): a collapsed link fits anything."""
    x = x.copy()
    x[LENGTHS] = np.where(x[LENGTHS] < 0, -1.0, 1.0) * np.maximum(np.abs(x[LENGTHS]), MIN_LINK)
    return x


def _solve(model, x, budget: int, enough: float):
    """Least squares in rounds of :data:`ROUND` evaluations, each ending with the links bounded (:func:`_bounded`),
    until the largest residual is ``enough`` (of the unit size), the budget is spent, or a round gains less than
    :data:`STALL` asks."""
    used, last = 0, np.inf
    while True:
        r = least_squares(model.residuals, x, jac=model.jacobian, method=METHOD, xtol=1e-15,
                          ftol=1e-15, gtol=1e-15, max_nfev=min(ROUND, budget - used), x_scale="jac")
        x, used, fun = _bounded(r.x), used + r.nfev, r.fun
        if np.any(x != r.x):
            fun = model.residuals(x)
        worst = float(np.max(np.abs(fun)))
        if worst <= enough or used >= budget or r.status != 0 or worst > STALL * last:
            return x, fun, used
        last = worst


def _errors(residuals, size: float) -> tuple[float, float]:
    n = residuals.size // 4
    dist = np.hypot(residuals[:n], residuals[n:2 * n]) * size
    return float(np.max(dist)), float(np.sqrt(np.mean(dist ** 2)))


def _world(model, x, size, centre, z):
    return model.place(x, z) * size + (centre[0] + 1j * centre[1])


def _mechanism(model: SixModel, x, size, centre) -> Mechanism:
    """The fitted six-bar in the path's frame, drawn at the first point's pose (its loops closed by the kernel)."""
    return drawn_mechanism(model.kind, {k: complex(_world(model, x, size, centre, z)[0])
                                        for k, z in model.joints(x).items()})


def _verify(mech, model, x, size, centre, target) -> tuple[float, float]:
    """Largest and RMS distance from the wanted points to the kernel's tracing point at their crank angles, each
    point in the assembly modes (of the four-bar and of the dyad) nearest it."""
    at = model.joints(x)
    crank = _world(model, x, size, centre, at["B"]) - _world(model, x, size, centre, at["A"])
    q = np.angle(crank)
    prog = Program(Kinematics(mech, ["point:P"]))
    geom = prog.geometry()
    groups = sorted(geom.sign)
    best = np.full(len(target), np.inf)
    for combo in range(2 ** len(groups)):
        signs = {g: geom.sign[g] * (-1.0 if combo >> k & 1 else 1.0) * np.ones(len(q)) for k, g in enumerate(groups)}
        pose = prog.poses(geom, q, signs=signs)
        out = prog.outputs(geom, pose)
        dist = np.hypot(out["point:P.x"] - target[:, 0], out["point:P.y"] - target[:, 1])
        dist = np.where(np.asarray(pose.failed) | ~np.isfinite(dist), np.inf, dist)
        best = np.minimum(best, dist)
    return float(np.max(best)), float(np.sqrt(np.mean(best ** 2)))
