"""Fit a Watt or Stephenson six-bar to a wanted closed path, from an atlas candidate, by least squares.

As for four-bars (:mod:`domes.motion.coupler.fit`): the candidate's curve
and the path are overlaid (FFT correspondence) to give each wanted point a
crank angle, coupler angle and tracer-link angle on the candidate; least
squares then moves the twelve dimensions of
:class:`~domes.motion.coupler.sixbar.SixBar`, the placement and every
point's three angles, with the two loop closures as residuals of their own,
until the tracing point passes through the wanted points. The fitted
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
from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism
from domes.motion.coupler.fit import MAX_POINTS, MIN_LINK, _correspond, _spread, check_wanted
from domes.motion.coupler.sixbar import KINDS, LINKS, SixBar
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import Kinematics
from domes.results import Result, Status

#: Crank angles a candidate is traced at, to correspond it with the path.
TRACE = 720
#: Global unknowns: a, b, c, d, p, q, e, f, g, h, u, v and the placement tx, ty, φ.
GLOBAL = 15
METHOD = "lm"
#: Evaluations per round of the refinement (it stops between rounds once it fits or stalls).
ROUND = 40
#: A round that leaves the largest residual above this share of the last ends the refinement (it has stalled).
STALL = 0.97


@dataclass(frozen=True, eq=False)
class SixFit(Result):
    """A six-bar fitted to a wanted path: the linkage placed in the path's frame (joints ``A``-``G``, the
    tracing point ``P`` on link ``E F``), its type, its link lengths ``(a, b, c, d, e, f)``, ``E``'s place ``(p, q)``
    on its link and ``P``'s ``(u, v)`` on ``E F`` (the path's units), and the (largest, RMS) distance from the
    wanted points to its curve before and after refinement."""

    mechanism: Mechanism | None
    kind: str
    lengths: tuple
    ternary: tuple
    coupler: tuple
    before: tuple
    after: tuple
    size: float
    tol: float
    evaluations: int
    status: Status
    note: str = ""

    @property
    def success(self) -> bool:
        return self.status is Status.COMPLETE and self.after[0] <= self.tol * self.size

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
        for block in range(3):
            y = x.copy()
            y[GLOBAL + block * n:GLOBAL + (block + 1) * n] += 1e-7
            df = (self.residuals(y) - f0) / 1e-7
            for k in range(4):
                J[k * n + idx, GLOBAL + block * n + idx] = df[k * n:(k + 1) * n]
        return J


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
    lower = np.full(x0.size, -np.inf)
    for i in (0, 1, 2, 3, 6, 7):
        lower[i] = MIN_LINK
        x0[i] = max(x0[i], MIN_LINK * 1.01)
    x, fun, nfev = _solve(model, x0, lower, quick or max_nfev, 0.0 if quick else 0.3 * tol)
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
    return SixFit(mech, KINDS[kind], (a, b, c, d, e, f), (p, q), (u, v), before, after, size, tol,
                  nfev, status, note)


def _solve(model, x, lower, budget: int, enough: float):
    """Least squares in rounds of :data:`ROUND` evaluations, until the largest residual is ``enough`` (of the unit
    size), the budget is spent, or a round gains less than :data:`STALL` asks."""
    bounds = (lower, np.inf) if METHOD == "trf" else (-np.inf, np.inf)
    used, last = 0, np.inf
    while True:
        r = least_squares(model.residuals, x, jac=model.jacobian, method=METHOD, bounds=bounds, xtol=1e-15,
                          ftol=1e-15, gtol=1e-15, max_nfev=min(ROUND, budget - used), x_scale="jac")
        x, used = r.x, used + r.nfev
        worst = float(np.max(np.abs(r.fun)))
        if worst <= enough or used >= budget or r.status != 0 or worst > STALL * last:
            return x, r.fun, used
        last = worst


def _errors(residuals, size: float) -> tuple[float, float]:
    n = residuals.size // 4
    dist = np.hypot(residuals[:n], residuals[n:2 * n]) * size
    return float(np.max(dist)), float(np.sqrt(np.mean(dist ** 2)))


def _world(model, x, size, centre, z):
    return model.place(x, z) * size + (centre[0] + 1j * centre[1])


def _mechanism(model: SixModel, x, size, centre) -> Mechanism:
    """The fitted six-bar in the path's frame, drawn at the first point's pose (its loops closed by the kernel)."""
    at = {k: complex(_world(model, x, size, centre, z)[0]) for k, z in model.joints(x).items()}
    xy = {k: (z.real, z.imag) for k, z in at.items()}
    carrier = "coupler" if model.kind == "stephenson" else "rocker"
    joints = [Joint("A", "R", ("frame", "crank"), xy["A"]), Joint("B", "R", ("crank", "coupler"), xy["B"]),
              Joint("C", "R", ("coupler", "rocker"), xy["C"]), Joint("D", "R", ("rocker", "frame"), xy["D"]),
              Joint("E", "R", (carrier, "tracer"), xy["E"]), Joint("F", "R", ("tracer", "link"), xy["F"]),
              Joint("G", "R", ("link", "frame"), xy["G"])]
    return Mechanism.build(f"fitted {KINDS[model.kind]}", list(LINKS), "frame", joints, [Input("A")],
                           points=[CouplerPoint("P", "tracer", xy["P"])])


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
