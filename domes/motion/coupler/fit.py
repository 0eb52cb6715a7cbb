"""Fit a four-bar to a wanted path: from an atlas candidate to an exact fit by least squares.

The wanted path is a sequence of points (a closed curve, in the user's
units and frame). A candidate from the atlas gives a four-bar of the right
shape; :func:`fit` then

1. *corresponds* the two curves: both resampled by arc length, the cyclic
   shift, direction and mirror that best overlay them under a similarity
   (scale and rotation, found for every shift at once by FFT cross-
   correlation) give each wanted point a crank angle and an assembly mode
   on the candidate's circuit, and the candidate's placement;
2. *refines* by least squares (:func:`scipy.optimize.least_squares`) the
   lengths ``a, b, c, d``, the coupler point ``(u, v)``, the placement
   (frame pivot ``A`` and the frame's angle) and every point's crank angle,
   until the linkage's coupler point passes through the wanted points;
3. *places* the result in the user's frame as a
   :class:`~domes.model.mechanism.Mechanism` and *verifies* it: its curve,
   traced again with the backend, is measured against every wanted point.

The result reports the fit error (largest and RMS distance from the wanted
points to the traced curve, in the user's units) before and after the
refinement, in the style of :class:`scipy.optimize.OptimizeResult`.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from domes.errors import InputError
from domes.model.fields import LARGEST
from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism
from domes.motion.coupler.atlas import resample_closed
from domes.motion.coupler.curves import trace
from domes.motion.coupler.fourbar import LINKS, four_bar
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import Kinematics
from domes.results import Result, Status

#: Samples of each curve used to correspond them (by arc length).
MATCH_SAMPLES = 256
#: The shortest link a fit may make, relative to the path's size.
MIN_LINK = 0.02
#: The most wanted points a refinement follows: each point adds two unknowns, and the dense least-squares step grows
#: with their square, so of a longer path this many of its points, spread by arc length, are followed (the fit says
#: so in its note).
MAX_POINTS = 64


@dataclass(frozen=True, eq=False)
class Fit(Result):
    """A four-bar fitted to a wanted path.

    ``mechanism`` is the linkage placed in the user's frame (its coupler
    point ``P`` traces the path); ``lengths`` its ``a, b, c, d`` and
    ``coupler`` its ``(u, v)`` in the user's units; ``before`` and ``after``
    the (largest, RMS) distance from the wanted points to the curve, before
    the refinement (the candidate as placed) and after it (the traced
    curve); ``size`` the path's size, the scale of ``tol``.
    """

    mechanism: Mechanism | None
    lengths: tuple[float, float, float, float]
    coupler: tuple[float, float]
    before: tuple[float, float]
    after: tuple[float, float]
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
        text = (f"{self.status}: largest distance {self.after[0]:.3g} (RMS {self.after[1]:.3g}) after refinement, "
                f"{self.before[0]:.3g} (RMS {self.before[1]:.3g}) before; path size {self.size:.4g}")
        return text + (f"; {self.note}" if self.note else "")


def check_wanted(points) -> np.ndarray:
    """The wanted path as an ``(n, 2)`` array; an InputError when it has fewer than 9 points or a non-finite one."""
    target = np.asarray(points, dtype=float)
    if target.ndim != 2 or target.shape[1] != 2:
        raise InputError(f"a wanted path is a list of points (x, y), got an array of shape {target.shape}")
    if target.shape[0] < 9:
        raise InputError(f"a wanted path needs at least 9 points to fit a four-bar's nine dimensions, got "
                         f"{target.shape[0]}")
    if not np.all(np.isfinite(target)):
        raise InputError("every point of the wanted path must be a finite number")
    if np.max(np.abs(target)) > LARGEST:
        raise InputError(f"the wanted path reaches {np.max(np.abs(target)):g}; its coordinates must be at most "
                         f"{LARGEST:g} in size (scale the path)")
    return target


def fit(points, candidate, tol: float = 1e-6, max_nfev: int = 400, window=None) -> Fit:
    """Fit the four-bar ``candidate`` (a :class:`~domes.model.mechanism.Mechanism` from
    :func:`~domes.motion.coupler.fourbar.four_bar`, coupler point ``P``) to the path through ``points``.

    A closed path by default; for an open path (a stretch), ``window`` says
    where on the candidate's curve it lies: ``(circuit, start, fraction,
    backwards, mirror)`` as an atlas look-up of open paths gives it. ``tol``
    is the largest distance accepted, relative to the path's size.
    """
    target = check_wanted(points)
    size = float(np.max(np.ptp(target, axis=0)) or 1.0)
    resampled = resampled_note(target.shape[0])
    if resampled:
        target = _spread(target, MAX_POINTS, closed=window is None)
    a, b, c, d = _lengths(candidate)
    u, v = _coupler(candidate)
    curve = trace(candidate, "P", 720, extra=("B", "C"))
    if window is None:
        best = min((_correspond(target, circuit) + (circuit,) for circuit in curve.circuits), key=lambda r: r[0])
        _, sc, mirror, circuit = best
    else:
        k, start, fraction, backwards, mirror = window
        if k >= len(curve.circuits):
            raise InputError(f"the candidate has {len(curve.circuits)} circuits, not {k + 1}")
        circuit = curve.circuits[k]
        sc = (start + _path_params(target, closed=False) * fraction * (-1 if backwards else 1)
              + (fraction if backwards else 0.0)) % 1.0
    w, shift, thetas, psis = _placement(target, circuit, sc, mirror)
    x0 = np.concatenate([[a, b, c, d, u, v, shift.real, shift.imag, math.atan2(w.imag, w.real)], thetas, psis])
    x0[:6] *= abs(w)
    model = _Model(target, mirror)
    before = _errors(model.residuals(x0))
    # Links may not shrink to nothing: a zero coupler or frame would let the point reach anywhere (a 2-DOF chain).
    lower = np.full(x0.size, -np.inf)
    lower[:4] = MIN_LINK * size
    x0[:4] = np.maximum(x0[:4], lower[:4] * 1.01)
    result = least_squares(model.residuals, x0, jac=model.jacobian, method="trf", bounds=(lower, np.inf),
                           xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=max_nfev, x_scale="jac")
    x = result.x
    lengths = tuple(float(abs(t)) for t in x[:4])
    mech, note = None, ""
    try:
        mech = model.mechanism(x)
        after = _verify(mech, target, x, model.signs(x), mirror)
        status = Status.COMPLETE
    except InputError as exc:
        after = _errors(model.residuals(x))
        status, note = Status.STOPPED, f"the fitted linkage could not be placed: {exc}"
    note = "; ".join(n for n in (resampled, note) if n)
    return Fit(mech, lengths, (float(x[4]), float(x[5])), before, after, size, tol, int(result.nfev), status, note)


def resampled_note(count: int) -> str:
    """What a fit says of a path of ``count`` points when it follows fewer (empty when it follows them all)."""
    if count <= MAX_POINTS:
        return ""
    return f"{MAX_POINTS} of the path's {count:,} points, spread by arc length, followed in the refinement"


def _spread(target, count: int, closed: bool) -> np.ndarray:
    """``count`` of the path's own points spread evenly by arc length (the first kept, and an open path's last)."""
    n = len(target)
    T = target[:, 0] + 1j * target[:, 1]
    s = np.concatenate(([0.0], np.cumsum(np.abs(np.diff(np.append(T, T[0]) if closed else T)))))
    if not s[-1] > 0:
        return target[np.linspace(0, n - 1, count).astype(int)]
    want = np.arange(count) / count * s[-1] if closed else np.linspace(0.0, s[-1], count)
    return target[np.unique(np.clip(np.searchsorted(s, want), 0, n - 1))]


def _lengths(mech):
    at = {j.name: j.at for j in mech.joints}
    return (math.dist(at["A"], at["B"]), math.dist(at["B"], at["C"]), math.dist(at["C"], at["D"]),
            math.dist(at["A"], at["D"]))


def _coupler(mech):
    from domes.motion.coupler.fourbar import to_coupler
    at = {j.name: j.at for j in mech.joints}
    return to_coupler(at["B"], at["C"], mech.point("P")[1])


def _path_params(target, closed: bool = True) -> np.ndarray:
    """Each point's arc-length parameter along the path, in ``[0, 1)`` (closed) or ``[0, 1]`` (open)."""
    T = target[:, 0] + 1j * target[:, 1]
    pts = np.append(T, T[0]) if closed else T
    s = np.concatenate(([0.0], np.cumsum(np.abs(np.diff(pts)))))
    return (s[:-1] if closed else s) / s[-1]


def _correspond(target, circuit):
    """``(residual, params, mirror)``: where on the circuit each wanted point lies, by the best overlay.

    Both curves are resampled by arc length; the cyclic shift, direction and
    mirror that best overlay them under a similarity are found for every
    shift at once by FFT cross-correlation.
    """
    T = target[:, 0] + 1j * target[:, 1]
    Tr = resample_closed(T[None, :], MATCH_SAMPLES)[0]
    C = circuit.points[:, 0] + 1j * circuit.points[:, 1]
    Cr = resample_closed(C[None, :], MATCH_SAMPLES)[0]
    tc = Tr - Tr.mean()
    best = None
    for mirror in (False, True):
        base = np.conj(Cr) if mirror else Cr
        for backwards in (False, True):
            cand = base[::-1] if backwards else base
            cc = cand - cand.mean()
            norm = float(np.sum(np.abs(cc) ** 2))
            r = np.fft.ifft(np.fft.fft(tc) * np.conj(np.fft.fft(cc)))     # r[k] = Σ_j tc[j + k] conj(cc[j])
            res = float(np.sum(np.abs(tc) ** 2)) - np.abs(r) ** 2 / norm
            k = int(np.argmin(res))
            if best is None or res[k] < best[0]:
                best = (res[k], k, mirror, backwards)
    res, k, mirror, backwards = best
    j = (_path_params(target) * MATCH_SAMPLES - k) % MATCH_SAMPLES   # the index in ``cand`` of each wanted point
    sc = ((MATCH_SAMPLES - 1 - j) % MATCH_SAMPLES if backwards else j) / MATCH_SAMPLES
    return res, sc, mirror


def _placement(target, circuit, sc, mirror):
    """``(w, shift, thetas, psis)``: the candidate's points at parameters ``sc``, overlaid on the wanted points.

    ``w`` (rotation and scale) and ``shift`` are the least-squares similarity
    (after mirroring when ``mirror``); ``thetas`` and ``psis`` are the crank
    and coupler angles on the circuit at those parameters.
    """
    C = circuit.points[:, 0] + 1j * circuit.points[:, 1]
    closed = np.append(C, C[0])
    s = np.concatenate(([0.0], np.cumsum(np.abs(np.diff(closed)))))
    s /= s[-1]
    at = np.interp(sc, s, closed.real) + 1j * np.interp(sc, s, closed.imag)
    if mirror:
        at = np.conj(at)
    T = target[:, 0] + 1j * target[:, 1]
    a0, t0 = at - at.mean(), T - T.mean()
    w = np.sum(np.conj(a0) * t0) / np.sum(np.abs(a0) ** 2)
    shift = T.mean() - w * at.mean()
    inputs = np.interp(sc, s, np.append(circuit.inputs, circuit.inputs[-1] + _wrap(circuit.inputs)))
    B, Cj = circuit.extra["B"], circuit.extra["C"]
    coupler = np.unwrap(np.arctan2(Cj[:, 1] - B[:, 1], Cj[:, 0] - B[:, 0]))
    psis = np.interp(sc, s, np.append(coupler, coupler[-1] + math.remainder(coupler[0] - coupler[-1], 2 * math.pi)))
    return w, shift, inputs, psis


def _wrap(inputs):
    return math.remainder(inputs[0] - inputs[-1], 2 * math.pi)


class _Model:
    """The coupler point of a placed four-bar at each point's crank and coupler angles, and its Jacobian.

    Each wanted point has two unknowns, the crank angle ``θ`` and the
    coupler angle ``ψ``, and three residuals: the point's two coordinates
    and the loop closure ``|C − D| − c``. No assembly mode is fixed, so a
    fit may pass from one mode to the other (at a limit) as the shape needs.
    """

    def __init__(self, target, mirror):
        self.target = np.asarray(target, dtype=float)
        self.mirror = mirror
        self.n = self.target.shape[0]

    def parts(self, x):
        a, b, c, d, u, v, tx, ty, phi = x[:9]
        theta, psi = x[9:9 + self.n], x[9 + self.n:]
        B = a * np.exp(1j * theta)
        e = np.exp(1j * psi)
        C = B + b * e
        P = B + (u + 1j * v) * e
        if self.mirror:
            P = np.conj(P)
        return P * np.exp(1j * phi) + (tx + 1j * ty), np.abs(C - d) - c

    def points(self, x):
        return self.parts(x)[0]

    def residuals(self, x):
        P, closure = self.parts(x)
        return np.concatenate([P.real - self.target[:, 0], P.imag - self.target[:, 1], closure])

    def jacobian(self, x):
        """Forward differences: one evaluation per global parameter, one for all crank and one for all coupler angles."""
        f0 = self.residuals(x)
        n = self.n
        J = np.zeros((3 * n, x.size))
        for i in range(9):
            h = 1e-7 * max(1.0, abs(x[i]))
            y = x.copy()
            y[i] += h
            J[:, i] = (self.residuals(y) - f0) / h
        idx = np.arange(n)
        for block in (0, 1):
            y = x.copy()
            y[9 + block * n:9 + (block + 1) * n] += 1e-7
            df = (self.residuals(y) - f0) / 1e-7
            for k in range(3):
                J[k * n + idx, 9 + block * n + idx] = df[k * n:(k + 1) * n]
        return J

    def signs(self, x):
        """Each point's assembly mode in the solution: which side of ``B → D`` its ``C`` lies on."""
        a, b, c, d = x[:4]
        theta, psi = x[9:9 + self.n], x[9 + self.n:]
        B = a * np.exp(1j * theta)
        C = B + b * np.exp(1j * psi)
        side = np.imag(np.conj(d - B) * (C - B))
        return np.where(side >= 0, 1.0, -1.0)

    def mechanism(self, x) -> Mechanism:
        """The fitted four-bar placed in the user's frame, drawn at the first point's crank angle."""
        a, b, c, d, u, v, tx, ty, phi = x[:9]
        a, b, c, d = abs(a), abs(b), abs(c), abs(d)
        link = four_bar(a, b, c, d, u, v, theta=float(x[9]), crossed=self.signs(x)[0] < 0)

        def place(p):
            z = complex(p[0], p[1])
            if self.mirror:
                z = z.conjugate()
            z = z * complex(math.cos(phi), math.sin(phi)) + complex(tx, ty)
            return (z.real, z.imag)

        joints = [Joint(j.name, j.kind, j.links, place(j.at)) for j in link.joints]
        return Mechanism.build("fitted four-bar", list(LINKS), "frame", joints, [Input("A")],
                               points=[CouplerPoint("P", "coupler", place(link.point("P")[1]))])


def _errors(residuals) -> tuple[float, float]:
    n = residuals.size // 3
    dist = np.hypot(residuals[:n], residuals[n:2 * n])
    return float(np.max(dist)), float(np.sqrt(np.mean(dist ** 2)))


def _verify(mech, target, x, signs, mirror) -> tuple[float, float]:
    """Largest and RMS distance from the wanted points to the placed mechanism's point at their crank angles.

    The positions come from the kinematics kernel on the placed mechanism
    (not from the model that was fitted), each point in its assembly mode.
    """
    kin = Kinematics(mech, ["point:P"])
    prog = Program(kin)
    geom = prog.geometry()
    thetas = np.asarray(x[9:9 + len(target)], dtype=float)
    q = x[8] + (-thetas if mirror else thetas)
    relative = np.asarray(signs, dtype=float) * signs[0]
    overrides = {g: geom.sign[g] * relative for g in geom.sign}
    pose = prog.poses(geom, q, signs=overrides)
    out = prog.outputs(geom, pose)
    P = np.c_[out["point:P.x"], out["point:P.y"]]
    dist = np.hypot(*(P - target).T)
    dist = np.where(np.asarray(pose.failed) | ~np.isfinite(dist), np.inf, dist)
    return float(np.max(dist)), float(np.sqrt(np.mean(dist ** 2)))
