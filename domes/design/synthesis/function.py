"""Function generation by a planar four-bar (seed 002 §2-3, digest A.3.4 and F.3).

The crank turns by ``θ`` as ``x`` runs over its range and the rocker by
``φ`` as ``y = f(x)`` does, in proportion (scaling (2-100)–(2-105) as
corrected). Precision points ``x_1 .. x_n`` (Chebyshev spacing (2-97) by
default) must be met exactly. With the frame ``a0 = (0, 0)``,
``b0 = (d, 0)``, crank ``a`` at angle ``θ``, rocker ``c`` at angle ``φ``
about ``b0`` and coupler ``b``, Freudenstein's equation

    K1 cos φ − K2 cos θ + K3 = cos(θ − φ),  K1 = d/a, K2 = d/c, K3 = (a² − b² + c² + d²)/(2ac)

is linear in ``K``. With the start angles ``θ0, φ0`` (at ``x0`` and
``f(x0)``) as free choices, ``n = 3`` is a 3 × 3 linear solve; with
``n = 4`` the output start ``φ0`` is an unknown and the 4 × 4 determinant
is a quadratic form in ``(cos φ0, sin φ0)``: every real root in closed form;
with ``n = 5`` both start angles are unknown, and the resultant of the two
determinants is a polynomial of degree 8 in ``tan θ0``: every real root.
The inversion (2-109) is the same problem as guidance of the inverted
crank, and for three positions gives the crank pin as a circumcentre
(:func:`inversion_three`, Example 4).

>>> fractions = chebyshev(3)
>>> [round(float(x), 5) for x in fractions]                  # (2-98), digest S-01
[0.06699, 0.5, 0.93301]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.polynomial import polynomial as P
from scipy.optimize import least_squares, minimize_scalar

from domes.design.synthesis.displacement import circumcentre, moved, rotation_about
from domes.errors import InputError

#: Samples of the range used for the structural error.
ERROR_SAMPLES = 4001


def chebyshev(n: int) -> np.ndarray:
    """Chebyshev spacing (2-97): the precision points as fractions of the range, ``(1 − cos((2j − 1)π/2n))/2``."""
    if n < 2:
        raise InputError(f"function generation needs at least 2 precision points, got {n}")
    j = np.arange(1, n + 1)
    return (1.0 - np.cos((2 * j - 1) * math.pi / (2 * n))) / 2.0


@dataclass(frozen=True)
class FunctionTask:
    """``y = f(x)`` on ``[x0, xf]`` by a crank turning ``input_range`` and a rocker ``output_range`` (rad).

    ``points`` are the precision points (in ``x``); ``start`` the free
    choices ``(θ0, φ0)``: the crank and rocker angles at ``x0`` (None where
    the synthesis solves for them); ``frame`` the length ``d``.
    """

    f: object
    x0: float
    xf: float
    input_range: float
    output_range: float
    points: tuple[float, ...]
    start: tuple[float | None, float | None] = (None, None)
    frame: float = 1.0
    name: str = "function"
    respace: bool = False
    min_transmission_deg: float | None = None
    tolerance: float | None = None
    max_link_ratio: float | None = None

    @property
    def y0(self) -> float:
        return float(self.f(self.x0))

    @property
    def k_theta(self) -> float:
        """(2-100): crank rotation per unit of ``x``."""
        return self.input_range / (self.xf - self.x0)

    @property
    def k_phi(self) -> float:
        """(2-101) as corrected: rocker rotation per unit of ``y``."""
        return self.output_range / (float(self.f(self.xf)) - self.y0)

    def angles(self, x) -> tuple[np.ndarray, np.ndarray]:
        """(2-102), (2-103): the crank and rocker rotations from the start of the range at ``x``."""
        x = np.asarray(x, dtype=float)
        return self.k_theta * (x - self.x0), self.k_phi * (np.asarray(self.f(x), dtype=float) - self.y0)


def check_function(task: FunctionTask) -> None:
    """An InputError that names the entry when the task cannot be synthesised as given."""
    if not (math.isfinite(task.x0) and math.isfinite(task.xf) and task.xf > task.x0):
        raise InputError(f"{task.name}: the range must be x0 < xf, got [{task.x0}, {task.xf}]")
    for label, value in (("input_range", task.input_range), ("output_range", task.output_range)):
        if not (math.isfinite(value) and value != 0 and abs(value) < 2 * math.pi):
            raise InputError(f"{task.name}: {label} must be a non-zero rotation below 360°, got "
                             f"{math.degrees(value) if math.isfinite(value) else value}°")
    xs = np.linspace(task.x0, task.xf, 1001)
    with np.errstate(all="ignore"):
        ys = np.asarray(task.f(xs), dtype=float)
    bad = ~np.isfinite(ys)
    if bad.any():
        raise InputError(f"{task.name}: the function is not defined at x = {xs[bad][0]:g} in its range "
                         f"[{task.x0:g}, {task.xf:g}]")
    if float(task.f(task.xf)) == task.y0:
        raise InputError(f"{task.name}: f(x0) = f(xf): the rocker's rotation cannot be scaled to the function")
    pts = np.asarray(task.points, dtype=float)
    if not 3 <= pts.size <= 5:
        raise InputError(f"{task.name}: a four-bar function generator meets 3 to 5 precision points, got {pts.size}")
    if np.any(pts < task.x0) or np.any(pts > task.xf):
        raise InputError(f"{task.name}: precision points must lie in [{task.x0:g}, {task.xf:g}], got {pts.tolist()}")
    if np.any(np.diff(np.sort(pts)) <= 1e-12 * (task.xf - task.x0)):
        raise InputError(f"{task.name}: two precision points coincide: {pts.tolist()}")
    given = tuple(s is not None for s in task.start)
    need = {3: (True, True), 4: (True, False), 5: (False, False)}[pts.size]
    if given != need:
        words = {(True, True): "both start angles θ0 and φ0", (True, False): "the input start angle θ0 only",
                 (False, False): "no start angle (both are solved for)"}
        raise InputError(f"{task.name}: with {pts.size} precision points give {words[need]}; the task gives "
                         f"{words.get(given, 'the output start angle φ0 only')}")


@dataclass(frozen=True)
class FunctionGenerator:
    """A four-bar for a function: Freudenstein's ``K``, the start angles, and the lengths it gives.

    ``crank``, ``coupler``, ``rocker``, ``frame`` are lengths; ``theta0``
    and ``phi0`` the crank and rocker angles at ``x0`` (rad; a negative
    ``d/K`` is a link pointing the other way, folded into its angle).
    """

    K: tuple[float, float, float]
    theta0: float
    phi0: float
    crank: float
    coupler: float
    rocker: float
    frame: float

    def output(self, theta, branch: float) -> np.ndarray:
        """The rocker angle at crank angle ``theta`` on the assembly ``branch`` (+1 or −1); NaN where it
        does not assemble."""
        th = np.asarray(theta, dtype=float)
        a, b, c, d = self.crank, self.coupler, self.rocker, self.frame
        # |A + a e^{iθ} − (D + c e^{iφ})| = b, A = 0, D = d: a linear form in cos φ, sin φ
        px, py = a * np.cos(th) - d, a * np.sin(th)
        Acoef, Bcoef = -2 * c * px, -2 * c * py
        Ccoef = px * px + py * py + c * c - b * b
        R = np.hypot(Acoef, Bcoef)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.arctan2(Bcoef, Acoef) + branch * np.arccos(-Ccoef / R)

    def branch_at(self, theta: float, phi: float) -> float:
        """The assembly branch (+1 or −1) whose rocker angle at ``theta`` is ``phi``."""
        errs = [abs(_wrap(float(self.output(theta, s)) - phi)) for s in (1.0, -1.0)]
        return 1.0 if errs[0] <= errs[1] else -1.0


def freudenstein(theta, phi, d: float = 1.0) -> FunctionGenerator:
    """The four-bar whose crank and rocker angles pass through ``(theta_j, phi_j)``, ``j = 1..3`` (rad)."""
    theta, phi = np.asarray(theta, dtype=float), np.asarray(phi, dtype=float)
    M = np.c_[np.cos(phi), -np.cos(theta), np.ones_like(theta)]
    rhs = np.cos(theta - phi)
    if abs(np.linalg.det(M[:3])) < 1e-12:
        raise InputError("the precision positions give a singular Freudenstein system (repeated angles)")
    K = np.linalg.solve(M[:3], rhs[:3])
    return from_k(K, float(theta[0]), float(phi[0]), d, reference=(float(theta[0]), float(phi[0])))


def from_k(K, theta1: float, phi1: float, d: float = 1.0, reference=None) -> FunctionGenerator:
    """The linkage of Freudenstein's ``K`` with its start angles (``reference`` = the angles at ``x0``)."""
    K1, K2, K3 = (float(k) for k in K)
    if K1 == 0 or K2 == 0:
        raise InputError("Freudenstein's K1 or K2 is zero: the crank or rocker would be infinitely long")
    a, c = d / K1, d / K2
    b2 = a * a + c * c + d * d - 2 * a * c * K3
    if not b2 > 0:
        raise InputError(f"no coupler length: b² = {b2:.3g} (the precision positions need an impossible coupler)")
    th0, ph0 = reference if reference is not None else (theta1, phi1)
    th0 += math.pi if a < 0 else 0.0
    ph0 += math.pi if c < 0 else 0.0
    a, c = abs(a), abs(c)
    K = (d / a, d / c, (a * a - b2 + c * c + d * d) / (2 * a * c))     # of the links as they point
    return FunctionGenerator(K, _wrap(th0), _wrap(ph0), a, math.sqrt(b2), c, d)


def _wrap(angle: float) -> float:
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _rows(theta, phi):
    """Rows of the Freudenstein system ``[cos φ, −cos θ, 1 | cos(θ − φ)]`` as a 4-column matrix."""
    return np.c_[np.cos(phi), -np.cos(theta), np.ones_like(theta), -np.cos(theta - phi)]


def _quad_coefficients(fn):
    """``(α, β, γ)`` of the quadratic form ``q(c, s) = α c² + β c s + γ s²`` evaluated by ``fn(c, s)``."""
    alpha, gamma = fn(1.0, 0.0), fn(0.0, 1.0)
    return alpha, fn(1.0, 1.0) - alpha - gamma, gamma


def _unit_roots(alpha, beta, gamma, scale):
    """Angles ``ψ`` in [−π, π) with ``α cos² ψ + β cos ψ sin ψ + γ sin² ψ = 0`` (both of each antipodal pair)."""
    out = []
    if abs(gamma) > 1e-14 * scale:
        disc = beta * beta - 4 * alpha * gamma
        if disc >= -1e-14 * scale * scale:
            r = math.sqrt(max(disc, 0.0))
            ts = {(-beta + r) / (2 * gamma), (-beta - r) / (2 * gamma)}
            out += [math.atan(t) for t in ts]
    else:  # cos ψ = 0 is a root, and α c + β s = 0 gives the other
        out.append(math.pi / 2)
        if abs(beta) > 1e-14 * scale:
            out.append(math.atan(-alpha / beta))
    return sorted({round(_wrap(x), 15) for psi in out for x in (psi, psi + math.pi)})


def solve(task: FunctionTask, method: str = "exact", seeds: int = 64, seed: int = 0) -> list[FunctionGenerator]:
    """Every real four-bar through the task's 3, 4 or 5 precision points (closed form or resultant roots).

    With five points, ``method="fast"`` polishes ``seeds`` random start angles
    instead of taking the resultant's roots (three and four points are
    closed forms: the methods agree).
    """
    if method not in ("exact", "fast"):
        raise InputError(f"method must be 'exact' or 'fast', got {method!r}")
    check_function(task)
    xs = np.sort(np.asarray(task.points, dtype=float))
    dth, dph = task.angles(xs)
    th0, ph0 = task.start
    d = task.frame
    sols = []
    if xs.size == 3:
        sols = [_solution(dth, dph, th0, ph0, d)]
    elif xs.size == 4:
        def det(c, s, th0=th0):
            M = _rows(th0 + dth, dph)
            # φ = φ0 + Δφ: cos φ and cos(θ − φ) are linear in (cos φ0, sin φ0)
            M[:, 0] = c * np.cos(dph) - s * np.sin(dph)
            M[:, 3] = -(np.cos(th0 + dth - dph) * c + np.sin(th0 + dth - dph) * s)
            return np.linalg.det(M)
        a, b, g = _quad_coefficients(det)
        for ph in _unit_roots(a, b, g, max(abs(a), abs(b), abs(g), 1e-300)):
            sols.append(_solution(dth, dph, th0, ph, d))
    elif method == "fast":
        starts = [_polish(dth, dph, t, p) for t, p in
                  np.random.default_rng(seed).uniform(-math.pi, math.pi, (seeds, 2))]
        sols = [_solution(dth, dph, *st, d) for st in starts if st is not None]
    else:
        sols = [_solution(dth, dph, t, p, d) for t, p in _five_point_starts(dth, dph)]
    out = []
    for s in sols:
        if s is not None and not any(np.allclose(s.K, o.K, rtol=1e-9, atol=1e-12) and
                                     abs(_wrap(s.theta0 - o.theta0)) < 1e-9 for o in out):
            out.append(s)
    return out


def _solution(dth, dph, th0, ph0, d):
    """The linkage through every precision point from the start angles, or None when there is none."""
    M = _rows(th0 + dth, ph0 + dph)
    K, *_ = np.linalg.lstsq(M[:, :3], -M[:, 3], rcond=None)
    try:
        return from_k(K, th0 + dth[0], ph0 + dph[0], d, reference=(th0, ph0))
    except InputError:
        return None


def _bilinear(fn):
    """The 3 × 3 coefficients ``C[i, k]`` of a form quadratic in ``(c1, s1)`` and in ``(c2, s2)``:
    ``Σ C[i, k] m_i(c1, s1) m_k(c2, s2)``, ``m = (c², c s, s²)``."""
    C = np.empty((3, 3))
    for k, fixed in enumerate(((1.0, 0.0), None, (0.0, 1.0))):
        if fixed is not None:
            C[:, k] = _quad_coefficients(lambda c, s: fn(c, s, *fixed))
    both = np.array(_quad_coefficients(lambda c, s: fn(c, s, 1.0, 1.0)))
    C[:, 1] = both - C[:, 0] - C[:, 2]
    return C


def _five_point_starts(dth, dph):
    """Every real ``(θ0, φ0)`` making rows 1-4 and rows 1, 2, 3, 5 of the Freudenstein system dependent.

    Each condition is quadratic in ``tan φ0`` with coefficients quadratic in
    ``tan θ0``; their resultant is a polynomial of degree 8 in ``tan θ0``.
    """
    def condition(rows):
        def fn(cp, sp, ct, st):
            M = np.empty((4, 4))
            cd, sd = np.cos(dph[rows]), np.sin(dph[rows])
            ca, sa = np.cos(dth[rows]), np.sin(dth[rows])
            M[:, 0] = cp * cd - sp * sd                           # cos(φ0 + Δφ)
            M[:, 1] = -(ct * ca - st * sa)                        # −cos(θ0 + Δθ)
            M[:, 2] = 1.0
            cw, sw = np.cos(dth[rows] - dph[rows]), np.sin(dth[rows] - dph[rows])
            cth, sth = ct * cw - st * sw, st * cw + ct * sw       # θ0 + Δθ − Δφ, then minus φ0
            M[:, 3] = -(cth * cp + sth * sp)
            return np.linalg.det(M)
        return _bilinear(fn)

    F, G = condition([0, 1, 2, 3]), condition([0, 1, 2, 4])
    # in t = tan φ0 (row index i: power i) and u = tan θ0 (column k: power k)
    fa, fb, fc = F[2], F[1], F[0]
    ga, gb, gc = G[2], G[1], G[0]
    res = P.polysub(P.polymul(P.polysub(P.polymul(fa, gc), P.polymul(fc, ga)),
                              P.polysub(P.polymul(fa, gc), P.polymul(fc, ga))),
                    P.polymul(P.polysub(P.polymul(fa, gb), P.polymul(fb, ga)),
                              P.polysub(P.polymul(fb, gc), P.polymul(fc, gb))))
    res = np.trim_zeros(res, "b")
    starts = []
    scale = np.max(np.abs(res)) if res.size else 0.0
    if res.size > 1 and scale > 0:
        roots = P.polyroots(res)
        us = [r.real for r in roots if abs(r.imag) <= 1e-7 * max(1.0, abs(r))]
        if res.size - 1 < 8:   # a lost degree: the root at infinity, θ0 = 90°
            us.append(math.inf)
        for u in us:
            base = math.atan(u) if math.isfinite(u) else math.pi / 2
            for th0 in (base, _wrap(base + math.pi)):
                ct, st = math.cos(th0), math.sin(th0)
                a, b, g = F @ np.array([ct * ct, ct * st, st * st])
                for ph0 in _unit_roots(a, b, g, max(abs(a), abs(b), abs(g), 1e-300)):
                    starts.append(_polish(dth, dph, th0, ph0))
    return [s for s in starts if s is not None]


def _polish(dth, dph, th0, ph0, steps: int = 8):
    """Newton on ``(θ0, φ0, K)`` over all five rows; None when it does not meet them to 1e-10."""
    x = np.array([th0, ph0, 0.0, 0.0, 0.0])
    M = _rows(th0 + dth, ph0 + dph)
    x[2:], *_ = np.linalg.lstsq(M[:, :3], -M[:, 3], rcond=None)
    for _ in range(steps):
        t, p, K1, K2, K3 = x
        th, ph = t + dth, p + dph
        r = K1 * np.cos(ph) - K2 * np.cos(th) + K3 - np.cos(th - ph)
        J = np.c_[K2 * np.sin(th) + np.sin(th - ph), -K1 * np.sin(ph) - np.sin(th - ph),
                  np.cos(ph), -np.cos(th), np.ones_like(th)]
        try:
            x = x - np.linalg.solve(J, r)
        except np.linalg.LinAlgError:
            return None
    th, ph = x[0] + dth, x[1] + dph
    r = x[2] * np.cos(ph) - x[3] * np.cos(th) + x[4] - np.cos(th - ph)
    return (_wrap(x[0]), _wrap(x[1])) if np.max(np.abs(r)) < 1e-10 * max(1.0, np.max(np.abs(x[2:]))) else None


def inversion_three(theta1j, phi1j, b1, b0=(1.0, 0.0)):
    """Example 4's route (2-108), (2-109): the crank pin ``a1`` of a three-position generator, given the
    rocker pin ``b1`` (a0 at the origin, b0 at ``b0``; rotations from position 1 in rad).

    Inverted on the rocker, the crank is a body guided through three
    positions and ``b1`` a fixed pivot: ``a1`` is the circumcentre of ``b1``
    and its images under the inverse displacements.

    >>> a1 = inversion_three([math.radians(-30), math.radians(-60)], [math.radians(15), math.radians(45)], (0.375, 0.1875))
    >>> [round(float(x), 6) for x in a1]                             # digest S-04
    [0.346046, 0.52925]
    """
    images = [np.asarray(b1, dtype=float)]
    for th, ph in zip(theta1j, phi1j):
        D_R = rotation_about(b0, -ph) @ rotation_about((0.0, 0.0), th)     # (2-108): D_−φ D_θ
        images.append(moved(np.linalg.inv(D_R), b1))
    return circumcentre(*images)


@dataclass(frozen=True)
class StructuralError:
    """The mechanism's output against the wanted one over the range (digest A.3.4).

    ``x`` samples the range and ``error`` is the rocker angle reached minus
    the one wanted there (rad; NaN where the linkage does not assemble);
    ``extrema`` the signed largest error between consecutive precision
    points and the range's ends (``n + 1`` values); ``branch`` the assembly
    mode of the first precision point, and ``defects`` the reasons the
    linkage fails the task as a mechanism (no assembly over part of the
    range, a precision point met only on the other branch).
    """

    x: np.ndarray
    error: np.ndarray
    extrema: tuple[float, ...]
    branch: float
    defects: tuple[str, ...]

    @property
    def largest(self) -> float:
        """The largest absolute structural error (rad of rocker rotation)."""
        return float(np.nanmax(np.abs(self.error))) if np.isfinite(self.error).any() else math.inf

    @property
    def spread(self) -> float:
        """How unequal the extrema are: ``max |E| / min |E| − 1`` (0 when all are equal)."""
        m = np.abs(np.asarray(self.extrema))
        return float(m.max() / m.min() - 1.0) if m.min() > 0 else math.inf


def structural_error(task: FunctionTask, gen: FunctionGenerator, points=None, samples: int = ERROR_SAMPLES):
    """The structural error of ``gen`` over the task's range, split at the precision ``points``."""
    pts = np.sort(np.asarray(task.points if points is None else points, dtype=float))
    x = np.union1d(np.linspace(task.x0, task.xf, samples), pts)
    dth, dph = task.angles(x)
    theta, wanted = gen.theta0 + dth, gen.phi0 + dph
    p1 = np.searchsorted(x, pts[0])
    branch = gen.branch_at(float(theta[p1]), float(wanted[p1]))
    got = gen.output(theta, branch)
    error = np.array([_wrap(e) if np.isfinite(e) else np.nan for e in got - wanted])
    defects = []
    if not np.isfinite(error).all():
        bad = x[~np.isfinite(error)]
        defects.append(f"does not assemble for x in [{bad.min():.6g}, {bad.max():.6g}] (a dead point in the range)")
    at = np.searchsorted(x, pts)
    missed = [float(pts[k]) for k, i in enumerate(at) if not abs(error[i]) <= 1e-7]
    if missed and not defects:
        defects.append(f"branch defect: precision points {', '.join(f'{m:.6g}' for m in missed)} are met only "
                       "in the other assembly mode")
    edges = np.concatenate(([0], at, [x.size - 1]))

    def signed(xx):
        dt, dp = task.angles(xx)
        return _wrap(float(gen.output(gen.theta0 + dt, branch)) - float(gen.phi0 + dp))

    extrema = []
    for lo, hi in zip(edges[:-1], edges[1:]):
        seg = error[lo:hi + 1]
        k = lo + (int(np.nanargmax(np.abs(seg))) if np.isfinite(seg).any() else 0)
        extrema.append(_peak(signed, x, k, lo, hi) if not defects else float(error[k]))
    return StructuralError(x, error, tuple(extrema), branch, tuple(defects))


def _peak(signed, x, k, lo, hi):
    """The extremum of the error near sample ``k`` (between samples ``lo`` and ``hi``), located by Brent's method."""
    a, b = x[max(k - 1, lo)], x[min(k + 1, hi)]
    if b <= a:
        return signed(x[k])
    sign = 1.0 if signed(x[k]) >= 0 else -1.0
    found = minimize_scalar(lambda t: -sign * signed(t), bounds=(a, b), method="bounded",
                            options={"xatol": 1e-12 * max(1.0, abs(b))})
    return max((signed(t) for t in (found.x, x[k])), key=lambda v: sign * v)


@dataclass(frozen=True)
class Respacing:
    """Precision points moved until the structural error's extrema are equal (Freudenstein's method)."""

    points: tuple[float, ...]
    generator: FunctionGenerator
    before: StructuralError
    after: StructuralError
    iterations: int


def respace(task: FunctionTask, gen: FunctionGenerator, max_nfev: int = 200) -> Respacing:
    """Move the precision points until the extrema of the structural error are equal.

    The book gives the method in words only; here the ``n`` points are the
    unknowns of a least-squares problem (:func:`scipy.optimize.least_squares`)
    on the ``n`` equations ``log |E_i| − log |E_{i+1}| = 0``, the points
    written as shares of the range (so they stay ordered and inside it); each
    evaluation re-synthesises the linkage with the task's free choices held
    and keeps the solution nearest the previous one. With the free choices
    held, equal extrema need not exist: :attr:`StructuralError.spread` of
    ``after`` says how far from equal they ended.
    """
    pts = np.sort(np.asarray(task.points, dtype=float))
    before = structural_error(task, gen, pts)
    span = task.xf - task.x0
    state = {"g": gen, "err": before, "pts": pts}
    penalty = np.full(pts.size, 10.0)

    def to_points(z):
        w = np.exp(z - z.max())
        return task.x0 + span * np.cumsum(w / w.sum())[:-1]

    def residuals(z):
        p = to_points(z)
        t = FunctionTask(task.f, task.x0, task.xf, task.input_range, task.output_range, tuple(p), task.start,
                         task.frame, task.name)
        try:
            sols = solve(t)
        except InputError:
            return penalty
        if not sols:
            return penalty
        near = state["g"]
        g = min(sols, key=lambda s: np.linalg.norm(np.subtract(s.K, near.K)) + abs(_wrap(s.theta0 - near.theta0)))
        err = structural_error(t, g, p)
        if err.defects or min(np.abs(err.extrema)) == 0:
            return penalty
        ext = np.abs(np.asarray(err.extrema))
        r = np.log(ext[:-1]) - np.log(ext[1:])
        if np.linalg.norm(r) <= np.linalg.norm(state.get("r", penalty)):
            state.update(g=g, err=err, pts=p, r=r)
        return r

    z0 = np.log(np.diff(np.concatenate(([task.x0], pts, [task.xf]))) / span)
    found = least_squares(residuals, z0, diff_step=1e-7, xtol=1e-12, ftol=1e-12, max_nfev=max_nfev)
    return Respacing(tuple(float(x) for x in state["pts"]), state["g"], before, state["err"], int(found.nfev))
