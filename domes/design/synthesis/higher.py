"""Guidance through infinitesimally and mixed separated positions (seed 002 §2-3; digest A.3, A.3.1, A.3.2).

"Fewer positions may be used if velocity and acceleration are also
prescribed" (digest A.3): a precision position (:class:`State`) may carry
the body's velocity state (``omega`` and the ``velocity`` of its reference
point), its acceleration state (``alpha``, ``acceleration``) and here also
its jerk (``angular_jerk``, ``jerk``): the derivatives of the displacement
``D(t)`` with respect to any input parameter. A task is a list of states,
e.g. P-P-PP (two positions, then one with its velocity), PPP (one position
with velocity and acceleration: three infinitesimally separated positions)
or PPP-PP.

A crank ``a0``–``a`` keeps its length: ``|a_j − a0|² = |a_1 − a0|²``
between positions (2-49), and at a state with rates the derivatives of
``g(t) = |a(t) − a0|²`` vanish:

    ȧ·(a − a0) = 0                         (2-50)
    ä·(a − a0) + |ȧ|² = 0                  (2-51)
    a⃛·(a − a0) + 3 ȧ·ä = 0                 (jerk, added here)

with ``a(t) = P(t) + R(θ(t)) b`` (``ȧ = V a``, ``ä = A a`` in homogeneous
form). Since ``|a|² = |P|² + 2 P·R b + |b|²``, the ``|a1|²`` terms cancel in
every derivative as in (2-49): each condition is *bilinear* in the fixed
pivot ``a0`` and the moving pivot ``a1`` (in position 1),
``c(a0, a1) = [a1; 1]ᵀ K [a0; 1]``. Counting a position after the first,
a velocity, an acceleration and a jerk as one condition each: two
conditions (three "positions") pair centre and circle points one to one
(:func:`circle_point`, :func:`centre_point`; for PPP this is the
Euler–Savary equation), three give the circle-point cubic
(:func:`circle_points_at`; for four infinitesimally separated positions
the cubic of stationary curvature), four give the Burmester points
(:func:`burmester_points`). A slider's pin (a circle point at infinity,
(2-54), (2-55)) has ``n·(a_j − a_1) = 0`` and ``n·a⁽ᵏ⁾ = 0`` for the
slide's normal ``n``: linear in ``a1`` (:func:`slider_for_direction` for
two conditions, :func:`slider_points` for three: for PPPP Ball's point).
The S-S link of spatial guidance has the same conditions in space, (2-57)–
(2-59) (:mod:`~domes.design.synthesis.higherspatial`: six conditions, e.g.
PPP-PPP-P in place of seven positions). As the digest
corrects them: (2-54)/(2-55) are ``tan α = ḃ_y/ḃ_x = b̈_y/b̈_x`` (the OCR
lost the dots) and (2-58)/(2-59) read ``ȧ_j = V_j a_j``, ``ä_j = A_j a_j``
(the OCR's ``ȧ_j = D1j ȧ1`` is wrong).

Five infinitesimally separated positions (the Burmester points of one
instant: paths with five-point contact with a circle) need a fourth
derivative, which a state does not carry: mixed tasks reach four
conditions with finite positions (PPPP-P, PPP-PP, ...).

The motion state of a four-bar's coupler (seed 000 kernel, input A at 0):
the centre of curvature of B's path is the fixed pivot A, that of C's is D.

>>> s = State((1.0, 0.0), 0.7751933733103613, velocity=(0.0, 1.0), omega=-0.5, acceleration=(-1.0, 0.0),
...           alpha=0.1530931089239487)
>>> [round(float(v), 9) + 0.0 for v in centre_point([s], (1.0, 0.0))]
[0.0, 0.0]
>>> [round(float(v), 9) + 0.0 for v in centre_point([s], (3.5, math.sqrt(6.0)))]
[3.0, 0.0]
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass
from math import comb

import numpy as np
import scipy.linalg

from domes.design.synthesis.guidance import Dyad, Position
from domes.design.synthesis.sliders import SliderDyad
from domes.errors import InputError
from domes.results import Listing, Status

#: The rates a state may carry, in order: (point field, angle field).
RATES = (("velocity", "omega"), ("acceleration", "alpha"), ("jerk", "angular_jerk"))
#: The frames (turned by these angles, rad) the Burmester points are searched in; the answers are merged.
TURNS = (0.37, 1.61)


@dataclass(frozen=True)
class State:
    """A precision position of the guided body: its reference point and angle (rad), and optionally the
    derivatives of both with respect to the input parameter: ``velocity`` and ``omega``, ``acceleration`` and
    ``alpha``, ``jerk`` and ``angular_jerk`` (each needs the one before)."""

    point: tuple[float, float]
    angle: float
    velocity: tuple[float, float] | None = None
    omega: float | None = None
    acceleration: tuple[float, float] | None = None
    alpha: float | None = None
    jerk: tuple[float, float] | None = None
    angular_jerk: float | None = None

    @property
    def order(self) -> int:
        """How many derivatives the state carries (0 to 3)."""
        return sum(getattr(self, p) is not None for p, _ in RATES)

    def rates(self) -> list[tuple[complex, float]]:
        """The derivatives ``(dᵏP as a complex number, dᵏθ)``, k = 1 .. order."""
        out = []
        for p, a in RATES[: self.order]:
            v = getattr(self, p)
            out.append((complex(v[0], v[1]), float(getattr(self, a))))
        return out


def states(task) -> list[State]:
    """The task as checked :class:`State` s (a :class:`~domes.design.synthesis.guidance.Position` is a state
    without rates); an InputError names the entry that is wrong."""
    if isinstance(task, (State, Position)) or not hasattr(task, "__len__") or len(task) == 0:
        raise InputError("a task is a non-empty list of positions (State or Position)")
    out = []
    for j, p in enumerate(task, 1):
        if isinstance(p, Position):
            p = State(tuple(p.point), p.angle)
        if not isinstance(p, State):
            raise InputError(f"position {j}: expected a State or a Position, got {type(p).__name__}")
        _check_state(p, j)
        out.append(p)
    for j in range(len(out)):
        for k in range(j):
            same_point = math.dist(out[j].point, out[k].point) <= 1e-12 * max(1.0, _spread(out))
            same_angle = abs(math.remainder(out[j].angle - out[k].angle, 2 * math.pi)) <= 1e-12
            if same_point and same_angle:
                raise InputError(f"positions {k + 1} and {j + 1} coincide: the body does not move between them "
                                 "(give one position with its rates instead)")
    return out


def _check_state(p: State, j: int) -> None:
    if len(p.point) != 2 or not (np.all(np.isfinite(p.point)) and math.isfinite(p.angle)):
        raise InputError(f"position {j}: the point must be two finite numbers and the angle finite")
    gap = False
    for k, (vec, ang) in enumerate(RATES):
        v, a = getattr(p, vec), getattr(p, ang)
        if (v is None) != (a is None):
            have, need = (vec, ang) if a is None else (ang, vec)
            raise InputError(f"position {j}: '{have}' is given without '{need}': a rate of the body needs both "
                             "the reference point's and the angle's")
        if v is None:
            gap = True
            continue
        if gap:
            raise InputError(f"position {j}: '{vec}' needs '{RATES[k - 1][0]}' and '{RATES[k - 1][1]}' too (a "
                             "derivative is a condition only with the lower ones)")
        if len(v) != 2 or not (np.all(np.isfinite(v)) and math.isfinite(a)):
            raise InputError(f"position {j}: '{vec}' must be two finite numbers and '{ang}' finite")
    if p.order and math.hypot(*p.velocity) == 0 and p.omega == 0:
        raise InputError(f"position {j}: the velocity is zero (the body is at rest): a velocity condition needs "
                         "a moving body")


def count(task) -> int:
    """The number of conditions on a crank: one per position after the first, per velocity, per acceleration
    and per jerk (three is the count of four finitely separated positions)."""
    ss = states(task)
    return len(ss) - 1 + sum(s.order for s in ss)


def _spread(ss) -> float:
    pts = np.array([s.point for s in ss], dtype=float)
    return float(np.ptp(pts, axis=0).max())


def _scale(ss) -> float:
    """The task's length: the spread of its points, or (when they are close) the distance to its poles."""
    spread = _spread(ss)
    dists = []
    for s in ss:
        if s.order and s.omega:
            dists.append(math.hypot(*s.velocity) / abs(s.omega))
    p1, t1 = ss[0].point, ss[0].angle
    for s in ss[1:]:
        half = abs(math.sin((s.angle - t1) / 2))
        if half > 1e-12:
            dists.append(math.dist(s.point, p1) / (2 * half))
    far = float(np.median(dists)) if dists else 0.0
    length = max(spread, min(far, 100 * spread) if spread else far)
    return length if length > 0 else 1.0


class _System:
    """The conditions of a task in a normalised frame (centred on its points, scaled by its length; turned by
    :meth:`turned`).

    ``K``: one 3 × 3 bilinear form per condition, ``c = [a1; 1]ᵀ K [a0; 1]``;
    ``W``: the 2 × 3 affine map ``w(a1)`` of each (the direction a slider's
    normal must be square to); ``kind``: its name; ``moving``: whether a zero
    ``w`` makes it vacuous (a position's or a velocity's: a pole).
    """

    def __init__(self, task):
        ss = states(task)
        self.count = len(ss) - 1 + sum(s.order for s in ss)
        self.centre = np.mean([s.point for s in ss], axis=0)
        self.length = _scale(ss)
        self.turn = 0.0
        c0 = complex(*self.centre)
        L = self.length
        pose, rates = [], []
        for s in ss:
            pts = (complex(*s.point) - c0) / L
            rs = s.rates()
            tau = 1.0
            if rs:
                tau = 1.0 / max(abs(rs[0][1]), abs(rs[0][0]) / L)
            pose.append((pts, s.angle))
            rates.append([(v * tau ** (k + 1) / L, w * tau ** (k + 1)) for k, (v, w) in enumerate(rs)])
        self.pose, self.rates = pose, rates
        # a_j^(k)(z) = m[j][k] z + c[j][k], z the body point in position 1 (normalised, complex)
        P1, t1 = pose[0]
        self.maps = []
        for (P, t), rs in zip(pose, rates):
            E = complex(math.cos(t - t1), math.sin(t - t1))
            F = _exp_rates([w for _, w in rs])
            m = [f * E for f in F]
            c = [P - m[0] * P1] + [v - mk * P1 for (v, _), mk in zip(rs, m[1:])]
            self.maps.append(list(zip(m, c)))
        funcs, self.kind, self.moving = [], [], []
        for j in range(1, len(ss)):
            funcs.append(self._position(j))
            self.kind.append(f"position {j + 1}")
            self.moving.append(True)
        for j, rs in enumerate(rates):
            for k in range(1, len(rs) + 1):
                funcs.append(self._rate(j, k))
                self.kind.append(f"{RATES[k - 1][0]} at position {j + 1}")
                self.moving.append(k == 1)
        basis = (0j, 1 + 0j, 1j)
        self.K = np.zeros((len(funcs), 3, 3))
        self.W = np.zeros((len(funcs), 2, 3))
        for i, f in enumerate(funcs):
            (w0, h0), (wx, hx), (wy, hy) = (f(z) for z in basis)
            W = np.array([[wx.real - w0.real, wy.real - w0.real, w0.real], [wx.imag - w0.imag, wy.imag - w0.imag,
                                                                          w0.imag]])
            self.W[i] = W
            self.K[i, :, :2] = -W.T
            self.K[i, :, 2] = (hx - h0, hy - h0, h0)

    def turned(self, turn: float) -> "_System":
        """The same conditions in the frame turned by ``turn`` (rad) more: ``K' = Tᵀ K T``, ``W' = R W T`` with
        ``T`` the turn back in homogeneous form."""
        c, s = math.cos(turn), math.sin(turn)
        R = np.array([[c, -s], [s, c]])
        T = np.eye(3)
        T[:2, :2] = R.T
        out = copy.copy(self)
        out.turn = self.turn + turn
        out.K = np.einsum("ai,kab,bj->kij", T, self.K, T)
        out.W = np.einsum("ab,kbc,cj->kaj", R, self.W, T)
        return out

    def at(self, j, k, z):
        m, c = self.maps[j][k]
        return m * z + c

    def _position(self, j):
        def f(z):
            a = self.at(j, 0, z)
            return a - z, (abs(a) ** 2 - abs(z) ** 2) / 2
        return f

    def _rate(self, j, k):
        def f(z):
            d = [self.at(j, m, z) for m in range(k + 1)]
            h = _dot(d[k], d[0]) + sum(comb(k, m) * _dot(d[m], d[k - m]) for m in range(1, k)) / 2
            return d[k], h
        return f

    # -- frames ------------------------------------------------------------------------------------------------
    def inward(self, p) -> np.ndarray:
        z = complex(math.cos(self.turn), math.sin(self.turn)) * (complex(*p) - complex(*self.centre)) / self.length
        return np.array([z.real, z.imag])

    def outward(self, q) -> np.ndarray:
        z = complex(math.cos(-self.turn), math.sin(-self.turn)) * complex(*q) * self.length
        return self.centre + np.array([z.real, z.imag])

    # -- the bilinear conditions -------------------------------------------------------------------------------
    def rows_for_a0(self, a1) -> np.ndarray:
        """The rows ``q`` of ``q · [a0; 1] = 0`` for the circle point ``a1`` (normalised)."""
        return np.einsum("i,kij->kj", np.array([a1[0], a1[1], 1.0]), self.K)

    def rows_for_a1(self, a0) -> np.ndarray:
        """The rows ``r`` of ``r · [a1; 1] = 0`` for the centre point ``a0`` (normalised)."""
        return np.einsum("kij,j->ki", self.K, np.array([a0[0], a0[1], 1.0]))

    def values(self, a0, a1) -> np.ndarray:
        return self.rows_for_a0(a1) @ np.array([a0[0], a0[1], 1.0])

    def pole(self, a1, tol: float = 1e-8) -> str:
        """The condition that leaves ``a1`` where it was (a position's: a pole; a velocity's: the instant
        centre), or "": that condition is then empty and the crank undetermined."""
        x1 = np.array([a1[0], a1[1], 1.0])
        w = np.einsum("kij,j->ki", self.W, x1)
        size = np.linalg.norm(self.W, axis=(1, 2)) * np.linalg.norm(x1)
        still = (np.linalg.norm(w, axis=1) <= tol * size) & np.array(self.moving)
        return self.kind[int(np.argmax(still))] if still.any() else ""

    def residual(self, a0, a1) -> float:
        """The largest condition error as a length (original units)."""
        r = max(float(np.linalg.norm(np.subtract(a1, a0))), 1.0)
        return float(np.abs(self.values(a0, a1)).max()) / r * self.length


def _dot(p: complex, q: complex) -> float:
    return p.real * q.real + p.imag * q.imag


def _exp_rates(dtheta) -> list[complex]:
    """``F_k`` with ``dᵏ/dtᵏ e^{iθ} = F_k e^{iθ}``, k = 0 .. len(dtheta): by Leibniz on ``f' = iθ' f``."""
    F = [1 + 0j]
    for k in range(len(dtheta)):
        F.append(sum(comb(k, m) * 1j * dtheta[m] * F[k - m] for m in range(k + 1)))
    return F


def _need(system: _System, wanted, what: str) -> None:
    if system.count not in wanted:
        want = " or ".join(str(w) for w in wanted)
        raise InputError(f"{what} takes {want} conditions (a position after the first, a velocity, an acceleration "
                         f"and a jerk count one each), got {system.count}")


def circle_point(task, a0) -> np.ndarray:
    """The moving pivot (in position 1) of the crank pivoted at ``a0``, for two conditions (PPP, PP-P, P-PP,
    P-P-P)."""
    sy = _System(task)
    _need(sy, (2,), "a circle point from a centre point")
    r = sy.rows_for_a1(sy.inward(a0))
    if abs(np.linalg.det(r[:, :2])) <= 1e-12 * max(np.abs(r[:, :2]).max() ** 2, 1e-300):
        raise InputError(f"no circle point for the centre point {tuple(a0)}: it is a pole or the task is "
                         "degenerate there")
    return sy.outward(np.linalg.solve(r[:, :2], -r[:, 2]))


def _centre(sy: _System, a1) -> np.ndarray:
    if still := sy.pole(a1):
        raise InputError(f"no centre point for the circle point {tuple(float(v) for v in sy.outward(a1))}: it is "
                         f"a pole of the task (the {still} leaves it in place), so the crank is undetermined")
    q = sy.rows_for_a0(a1)
    q = q / np.linalg.norm(q, axis=1)[:, None]
    s = np.linalg.svd(q[:, :2], compute_uv=False)
    if s[-1] <= 1e-10 * s[0]:
        raise InputError(f"no finite centre point for the circle point {tuple(sy.outward(a1))}: its path's centre "
                         "is at infinity there (a slider: see slider_for_direction)")
    return np.linalg.lstsq(q[:, :2], -q[:, 2], rcond=None)[0]


def centre_point(task, a1) -> np.ndarray:
    """The fixed pivot of the crank whose moving pivot is ``a1`` in position 1 (two or more conditions; with
    more, ``a1`` should be on the circle-point curve: the least-squares centre). For PPP it is the centre of
    curvature of the path of ``a1`` (Euler–Savary)."""
    sy = _System(task)
    if sy.count < 2:
        raise InputError(f"a centre point needs two or more conditions, got {sy.count}")
    return sy.outward(_centre(sy, sy.inward(a1)))


def dyad(task, a1) -> Dyad:
    """The crank through circle point ``a1`` with its residual: the largest condition error, as a length."""
    sy = _System(task)
    if sy.count < 2:
        raise InputError(f"a crank from its circle point needs two or more conditions, got {sy.count}")
    z = sy.inward(a1)
    a0 = _centre(sy, z)
    A0 = sy.outward(a0)
    return Dyad(tuple(float(v) for v in A0), (float(a1[0]), float(a1[1])),
                float(np.linalg.norm(np.subtract(a1, A0))), sy.residual(a0, z))


def _det_y(sy: _System, rows, x: float):
    """``y ↦ det`` of the three conditions ``rows`` on the vertical line ``x`` (normalised), and its cubic."""
    def f(y):
        return float(np.linalg.det(sy.rows_for_a0((x, y))[list(rows)]))
    ys = np.array([-1.0, -1 / 3, 1 / 3, 1.0])
    return f, np.polyfit(ys, [f(y) for y in ys], 3)


def _real_roots(coef, tol=1e-9):
    coef = np.asarray(coef, dtype=float)
    top = max(np.abs(coef).max(), 1e-300)
    while len(coef) > 1 and abs(coef[0]) <= 1e-12 * top:
        coef = coef[1:]
    if len(coef) < 2:
        return []
    return [r.real for r in np.roots(coef) if abs(r.imag) <= tol * max(1.0, abs(r))]


def circle_points_at(task, x: float) -> list[float]:
    """Every ``y`` with ``(x, y)`` on the circle-point curve of three conditions (e.g. PPPP: the cubic of
    stationary curvature; PPP-P, PP-PP, P-P-PP, four positions): the real roots of a cubic, polished. Poles of
    the task lie on the curve too (see :func:`circle_point_curve`)."""
    sy = _System(task)
    _need(sy, (3,), "the circle-point curve")
    return [float(sy.centre[1] + sy.length * y) for y in _curve_at(sy, (x - sy.centre[0]) / sy.length)]


def _curve_at(sy: _System, x: float) -> list[float]:
    """The normalised ``y`` of the circle-point curve on the normalised line ``x``."""
    f, coef = _det_y(sy, (0, 1, 2), x)
    d = np.polyder(coef)
    out = []
    for y in _real_roots(coef):
        for _ in range(8):
            slope = np.polyval(d, y)
            if slope == 0:
                break
            step = f(y) / slope
            y -= step
            if abs(step) <= 1e-15 * max(1.0, abs(y)):
                break
        out.append(float(y))
    return out


def circle_point_curve(task, xs) -> list[Dyad]:
    """Cranks of three conditions with circle points at every abscissa in ``xs``, every branch, with their
    centre points (the centre-point curve); poles and points whose centre is at infinity are left out."""
    sy = _System(task)
    _need(sy, (3,), "the circle-point curve")
    out = []
    for x in xs:
        xn = (float(x) - sy.centre[0]) / sy.length
        for y in _curve_at(sy, xn):
            try:
                a0 = _centre(sy, (xn, y))
            except InputError:
                continue
            A0, A1 = sy.outward(a0), sy.outward((xn, y))
            out.append(Dyad(tuple(float(v) for v in A0), (float(x), float(A1[1])), float(math.dist(A1, A0)),
                            sy.residual(a0, (xn, y))))
    return out


@dataclass(frozen=True, eq=False)
class Burmester(Listing):
    """The Burmester cranks of four conditions: ``dyads`` (circle point ``a1``, centre point ``a0``), the
    ``candidates`` (curve intersections polished), the largest ``residual`` (a length) and the ``method``."""

    dyads: tuple[Dyad, ...]
    candidates: int
    residual: float
    method: str = "resultant"
    items_field = "dyads"

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.dyads else Status.EMPTY

    @property
    def message(self) -> str:
        return (f"{len(self.dyads)} Burmester crank(s) from {self.candidates} candidate intersections, largest "
                f"residual {self.residual:.2g}")


def burmester_points(task, reach: float = 1e3) -> Burmester:
    """Every real crank of four conditions (five "positions": P-P-P-P-P, PPP-PP, PP-P-PP, PPPP-P, ...) whose
    circle point is within ``reach`` × the task's length of its centre.

    The circle points lie on the cubics ``det[q_1; q_2; q_3] = 0`` and
    ``det[q_1; q_2; q_4] = 0`` (``q_i · [a0; 1] = 0`` the conditions for the
    fixed pivot). Their intersections are found from the resultant in ``y``:
    the 6 × 6 Sylvester matrix is a cubic matrix polynomial in ``x``, whose
    eigenvalues (an 18 × 18 generalized eigenproblem) are the abscissas;
    each candidate is polished by Newton on the four bilinear equations in
    ``(a0, a1)``. Intersections where the first two conditions are
    dependent (poles) fail the polish and are dropped; the search runs in
    the frames turned by :data:`TURNS` and the answers are merged.
    """
    base = _System(task)
    _need(base, (4,), "Burmester points")
    found: list[tuple[np.ndarray, np.ndarray]] = []
    tried = 0
    for turn in TURNS:
        sy = base.turned(turn)
        for z in _intersections(sy, reach):
            if any(math.dist(sy.outward(z), f1) <= 1e-6 * base.length for _, f1 in found):
                continue                     # found already (in the other frame, or a double intersection)
            tried += 1
            sol = _polish(sy, z)
            if sol is None or sy.pole(sol[1]) or np.linalg.norm(sol[1]) > reach:
                continue
            a0, a1 = sy.outward(sol[0]), sy.outward(sol[1])
            if not any(math.dist(a1, f1) <= 1e-7 * base.length for _, f1 in found):
                found.append((a0, a1))
    dyads = []
    for a0, a1 in sorted(found, key=lambda p: (p[1][0], p[1][1])):
        z0, z1 = base.inward(a0), base.inward(a1)
        dyads.append(Dyad(tuple(float(v) for v in a0), tuple(float(v) for v in a1),
                          float(math.dist(a0, a1)), base.residual(z0, z1)))
    return Burmester(tuple(dyads), tried, max((d.residual for d in dyads), default=0.0))


def _bivariate(sy: _System, rows, nodes):
    """Coefficients ``C[p, q]`` of ``det[q_i]_{i ∈ rows} = Σ C[p, q] xᵖ y^q`` (degree ≤ 3 in each variable)
    from its values on the grid ``nodes × nodes``."""
    X, Y = np.meshgrid(nodes, nodes, indexing="ij")
    pts = np.stack([X.ravel(), Y.ravel(), np.ones(X.size)], axis=1)
    M = np.linalg.det(np.einsum("gi,kij->gkj", pts, sy.K[list(rows)])).reshape(len(nodes), len(nodes))
    Vi = np.linalg.inv(np.vander(nodes, 4, increasing=True))
    return Vi @ M @ Vi.T


def _intersections(sy: _System, reach: float) -> list[np.ndarray]:
    nodes = 2.0 * np.cos(np.pi * (np.arange(4) + 0.5) / 4)
    F, G = _bivariate(sy, (0, 1, 2), nodes), _bivariate(sy, (0, 1, 3), nodes)
    scale = max(np.abs(F).max(), 1e-300), max(np.abs(G).max(), 1e-300)
    F, G = F / scale[0], G / scale[1]
    S = np.zeros((4, 6, 6))              # S(x) = Σ xᵖ S[p]; rows: y-coefficients, highest first
    for p in range(4):
        for i in range(3):
            S[p, i, i:i + 4] = F[p, ::-1]
            S[p, 3 + i, i:i + 4] = G[p, ::-1]
    n = 6
    A = np.zeros((3 * n, 3 * n))
    B = np.eye(3 * n)
    A[:n, n:2 * n] = np.eye(n)
    A[n:2 * n, 2 * n:] = np.eye(n)
    A[2 * n:, :n], A[2 * n:, n:2 * n], A[2 * n:, 2 * n:] = -S[0], -S[1], -S[2]
    B[2 * n:, 2 * n:] = S[3]
    with np.errstate(all="ignore"):
        xs = scipy.linalg.eigvals(A, B)
    out = []
    for x in xs:
        if not np.isfinite(x) or abs(x) > reach or abs(x.imag) > 1e-3 * max(1.0, abs(x)):
            continue
        x = x.real
        powers = x ** np.arange(4)
        fy, gy = (powers @ F)[::-1], (powers @ G)[::-1]           # coefficients in y, highest power first
        for y in _real_roots(fy, 1e-3):
            g = np.polyval(gy, y)
            if abs(g) > 1e-4 * max(np.abs(gy).max(), 1e-300) * max(1.0, abs(y)) ** 3:
                continue
            q = sy.rows_for_a0((x, y))
            q = q / np.linalg.norm(q, axis=1)[:, None]
            if np.linalg.svd(q, compute_uv=False)[-1] <= 1e-4:       # all four conditions: rank 2 (not a pole)
                out.append(np.array([x, y]))
    return out


def _polish(sy: _System, a1, steps: int = 30):
    """Newton on the four bilinear conditions in ``(a0, a1)`` (normalised) from the circle point ``a1``."""
    try:
        a0 = _centre(sy, a1)
    except InputError:
        return None
    K = sy.K
    norms = np.linalg.norm(K, axis=(1, 2))
    x0, x1 = np.array([a0[0], a0[1], 1.0]), np.array([a1[0], a1[1], 1.0])
    for it in range(steps):
        q = np.einsum("i,kij->kj", x1, K)
        c = q @ x0
        scaled = np.abs(c).max() / (norms.max() * np.linalg.norm(x0) * np.linalg.norm(x1))
        if scaled <= 1e-15:
            break
        if it >= 8 and scaled > 1e-6:
            return None                      # not converging: a spurious intersection
        J = np.empty((4, 4))
        J[:, :2] = q[:, :2]
        J[:, 2:] = np.einsum("kij,j->ki", K, x0)[:, :2]
        try:
            step = np.linalg.solve(J, -c)
        except np.linalg.LinAlgError:
            return None
        x0[:2] += step[:2]
        x1[:2] += step[2:]
        if not (np.all(np.isfinite(x0)) and np.all(np.isfinite(x1))):
            return None
        if abs(step).max() <= 1e-15 * max(1.0, abs(x0).max(), abs(x1).max()):
            break
    c = np.einsum("i,kij,j->k", x1, K, x0) / (norms * np.linalg.norm(x0) * np.linalg.norm(x1))
    return (x0[:2], x1[:2]) if np.abs(c).max() <= 1e-11 else None


# -- sliders: the circle point at infinity (2-52)–(2-55) ---------------------------------------------------------

def _slider_rows(sy: _System, angle: float) -> np.ndarray:
    """Rows ``l`` of ``l · [a1; 1] = 0``: the slide's normal square to every ``w`` (normalised frame)."""
    t = angle + sy.turn
    n = np.array([-math.sin(t), math.cos(t)])
    return np.einsum("i,kij->kj", n, sy.W)


def _slider(sy: _System, a1, angle: float) -> SliderDyad:
    rows = _slider_rows(sy, angle)
    x1 = np.r_[a1, 1.0]
    res = float(np.abs(rows @ x1).max()) * sy.length
    direction = math.remainder(angle, math.pi)
    A1 = sy.outward(a1)
    return SliderDyad((float(A1[0]), float(A1[1])), direction, res)


def slider_for_direction(task, angle: float) -> SliderDyad:
    """The slider pin (in position 1) whose path has direction ``angle`` (rad) to the task's order, for two
    conditions: PPP (the point of the inflection circle whose velocity has that direction), PP-P, P-P-P."""
    sy = _System(task)
    _need(sy, (2,), "a slider chosen by its direction")
    rows = _slider_rows(sy, angle)
    if abs(np.linalg.det(rows[:, :2])) <= 1e-12 * max(np.abs(rows[:, :2]).max() ** 2, 1e-300):
        raise InputError(f"no slider along {math.degrees(angle):.6g}°: the task leaves that direction free or "
                         "impossible")
    a1 = np.linalg.solve(rows[:, :2], -rows[:, 2])
    if sy.pole(a1):
        raise InputError(f"the slider along {math.degrees(angle):.6g}° is at a pole of the task: its pin does not "
                         "move")
    return _slider(sy, a1, angle)


def slider_points(task) -> list[SliderDyad]:
    """The sliders of three conditions (PPPP: Ball's point; PPP-P, PP-PP, P-P-PP, P-P-P-P), every real one:
    the slide directions are the real roots of a cubic in ``tan``; poles are left out."""
    sy = _System(task)
    _need(sy, (3,), "slider points")

    def det(angle):
        return float(np.linalg.det(_slider_rows(sy, angle)))

    ts = np.array([-2.0, -0.5, 0.5, 2.0])
    coef = np.polyfit(ts, [det(math.atan(t)) / math.cos(math.atan(t)) ** 3 for t in ts], 3)
    angles = [math.atan(t) for t in _real_roots(coef, 1e-7)]
    if abs(coef[0]) <= 1e-9 * max(np.abs(coef).max(), 1e-300):
        angles.append(math.pi / 2)                   # the cubic lost its leading term: a root at tan = ∞
    out: list[SliderDyad] = []
    for angle in angles:
        for _ in range(4):                            # polish the root on the determinant itself
            slope = (det(angle + 1e-7) - det(angle - 1e-7)) / 2e-7
            if slope == 0 or not math.isfinite(det(angle) / slope):
                break
            angle -= det(angle) / slope
        rows = _slider_rows(sy, angle)
        rows = rows / np.maximum(np.linalg.norm(rows, axis=1), 1e-300)[:, None]   # a zero row: met by every pin
        a1 = np.linalg.lstsq(rows[:, :2], -rows[:, 2], rcond=None)[0]
        if sy.pole(a1):
            continue
        s = _slider(sy, a1, angle)
        if s.residual <= 1e-8 * sy.length and not any(math.dist(s.a1, o.a1) <= 1e-8 * sy.length for o in out):
            out.append(s)
    return out
