"""RSSR function generation, up to seven precision points (seed 002 §2-3, digest A.3.4; RSSR of seed 001).

**The problem.** The input R axis (point ``pa``, direction ``ua``) and the
output R axis (``pb``, ``ub``) are fixed in space; the input crank carries the
sphere centre ``a1``, the output crank ``b1`` (both in position 1), the S-S
coupler joins them. Precision pairs ``(θ_j, φ_j)``, j = 1..n, of input and
output rotation (right-handed about ``ua``, ``ub``) are to be met; only the
turns from position 1, ``θ1j = θ_j − θ_1`` and ``φ1j = φ_j − φ_1`` (2-104),
(2-105), matter. By kinematic inversion (digest A.3.4) the input crank moves
relative to the output link by the spatial displacement
``D_R,j = Rot(output axis, −φ1j) · Rot(input axis, θ1j)`` (a screw when the
axes are skew), and the coupler keeps its length (the RSSR form of (2-109)):

    |D_R,j a1 − b1|² = |a1 − b1|²,   j = 2..n.

The unknowns are the six coordinates of ``a1`` and ``b1``: **seven precision
points** at most (digest A.3.4). There is no gauge on the sphere centres: a
centre moved along its axis changes its distance from the other crank's
circle differently at each position. The only free choice is the point that
stands for each fixed axis in the mechanism file; it is put at the foot of the
perpendicular from ``a1`` (``b1``) to its axis, so each crank lies in a plane
normal to its axis. Parallel axes make the motion planar (at most five
points: the planar four-bar generator) and meeting axes spherical (every
solution scales about the meeting point): both are refused.

**Exact method (seven points).** In the frame of the axes' common normal
(origin the foot on the input axis, ``z = ua``, ``x`` along the common normal
of length ``d``, ``ub = (0, sin α, cos α)``) put ``a1`` at radius ``r_a``,
height ``z_a``, phase ``ψ_a`` and ``b1`` at ``r_b``, ``z_b``, ``ψ_b``.
Dividing the coupler condition by ``−2 r_a r_b`` gives, with
``θ' = θ1j + ψ_a``, ``φ' = φ1j + ψ_b`` (checked numerically in the tests):

    cθ' cφ' + cos α sθ' sφ' + k1 cθ' + k2 sθ' + k3 cφ' + k4 sφ' + k5 = 0,
    k1 = d/r_b, k2 = z_b sin α / r_b, k3 = −d/r_a, k4 = −z_a sin α / r_a,
    k5 = −(r_a² + z_a² + d² + r_b² + z_b² − 2 z_a z_b cos α − L²) / (2 r_a r_b).

The four columns ``cθ', sθ', cφ', sφ'`` span the same space as
``cos θ1j, sin θ1j, cos φ1j, sin φ1j`` whatever the phases, so with ``Q``
(7 × 2) spanning the orthogonal complement of those four and the ones the
first column ``g_j = xᵀ M_j y`` (``x = (cos ψ_a, sin ψ_a)``,
``y = (cos ψ_b, sin ψ_b)``) must satisfy ``Qᵀ g = 0``: two bilinear
equations. For given ``x`` they are a 2 × 2 homogeneous system in ``y``,
solvable iff its determinant, a quadratic form in ``x``, vanishes: **at most
two solutions**, in closed form (the quadratic form's isotropic directions),
then ``y`` by its null vector and ``k`` by linear least squares. A radius
``d/k`` with ``k`` = 0 is a crank of infinite length (no solution); the
degenerate "cranks" of radius 0 on both axes (which satisfy the equations
trivially) never appear, since the division by ``r_a r_b`` removed them.

**Seeded method (any n ≤ 7, with ``fixed``).** With fewer points the user
fixes ``7 − n`` coordinates of ``a1``, ``b1`` (``fixed={"b1x": ..}``, world
coordinates, as :func:`~domes.design.synthesis.links.guiding_links`). The
equations are bilinear in ``(a1, b1)``; they are solved by Levenberg–Marquardt
from ``starts`` seeded random starts at once (numpy, batched over the starts;
each centre started within ``3d`` of its axis's common-normal foot along the
axis, at a radius of ``0.1d`` to ``3d``), each converged start polished by
Newton's method; starts that end on the trivial family (both centres on their
axes) are dropped. It returns every distinct solution the starts reach, which
is not proven to be all (the exact method is, for seven points).

**Check.** Every solution becomes a :class:`~domes.model.spatial.SpatialMechanism`
(drawn in position 1) and is moved by the spatial backend: the RSSR closed
form of the file (:class:`~domes.motion.spatial.rssr.RSSR`) gives the output
at each precision input on either assembly mode (``error``: the worst miss),
and :func:`~domes.motion.spatial.sweep.spatial_sweep` walks from position 1 to
each precision input by continuity (``swept_error``); ``defect`` names a
lock-up (the walk stops) or a branch defect (the point is met only on the
other assembly mode, or the walk passes a branch point).

>>> from domes.motion.spatial.rssr import RSSR
>>> planted = RSSR.make((1, 0, 0), (0, 0, 0), (0.3, 0.9, 0.2), (0, 0.6, 0.8), (0.2, 1.0, 0.0), (1.1, 1.4, -0.3))
>>> thetas = [0.2 * j for j in range(7)]
>>> phis = [float(planted.beta(t)) for t in thetas]
>>> r = rssr_function(((0, 0, 0), (1, 0, 0)), ((0.2, 1.0, 0.0), (0, 0.6, 0.8)), thetas, phis)
>>> r.message
'complete: 2 RSSR(s) for 7 precision points (exact), output error up to ... rad; 1 with a branch or lock-up defect'
>>> [(bool(np.allclose(s.a1, planted.A1) and np.allclose(s.b1, planted.B1)), s.defect) for s in r.solutions]
[(True, ''), (False, '...')]
>>> r.worst < 1e-9
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.design.synthesis.sphere import rot
from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism
from domes.results import Result, Status

#: The unknowns, by name (world coordinates of the sphere centres in position 1).
NAMES = ("a1x", "a1y", "a1z", "b1x", "b1y", "b1z")
#: The most precision points (six unknowns, one equation per point after the first).
MOST = 7
#: Axes this close to parallel (sine of their angle) or to meeting (distance over their points' spread) are refused.
DEGENERATE = 1e-9
METHODS = ("auto", "exact", "seeded")


@dataclass(frozen=True)
class RSSRSolution:
    """An RSSR function generator: sphere centres ``a1``, ``b1`` (position 1), axis points ``a0``, ``b0`` (the
    feet of the perpendiculars from them), axes ``ua``, ``ub``; ``residual``: the largest change of the coupler's
    length over the precision points over ``d``; ``error``: the largest miss (rad) of the output at the precision
    inputs by the backend's closed form (either mode), ``swept_error`` by the sweep from position 1 (inf where a
    point is not reached), ``defect``: ``""``, ``"branch"`` or ``"lock-up"``; ``mechanism``: the file."""

    a1: np.ndarray
    b1: np.ndarray
    a0: np.ndarray
    b0: np.ndarray
    ua: np.ndarray
    ub: np.ndarray
    residual: float
    error: float = math.nan
    swept_error: float = math.nan
    defect: str = ""
    mechanism: SpatialMechanism | None = field(default=None, repr=False)

    @property
    def crank(self) -> float:
        """The input crank's radius ``|a1 − a0|``."""
        return float(np.linalg.norm(self.a1 - self.a0))

    @property
    def rocker(self) -> float:
        """The output crank's radius ``|b1 − b0|``."""
        return float(np.linalg.norm(self.b1 - self.b0))

    @property
    def coupler(self) -> float:
        return float(np.linalg.norm(self.a1 - self.b1))

    def to_dict(self) -> dict:
        return {"a1": self.a1.tolist(), "b1": self.b1.tolist(), "a0": self.a0.tolist(), "b0": self.b0.tolist(),
                "crank": self.crank, "coupler": self.coupler, "rocker": self.rocker, "residual": self.residual,
                "error": self.error, "swept_error": self.swept_error, "defect": self.defect}


@dataclass(frozen=True, eq=False)
class RSSRFunction(Result):
    """What :func:`rssr_function` found: ``solutions`` (every distinct one), the ``method`` used, ``starts``
    (0 for the exact method), ``worst``: the largest ``error`` of the solutions."""

    status: Status
    solutions: tuple[RSSRSolution, ...]
    method: str
    starts: int
    points: int
    worst: float

    @property
    def message(self) -> str:
        if not self.solutions:
            return (f"{self.status}: no real RSSR meets the {self.points} precision points "
                    f"({self.method}{'' if not self.starts else f', {self.starts} starts'})")
        defects = sum(1 for s in self.solutions if s.defect)
        return (f"{self.status}: {len(self.solutions)} RSSR(s) for {self.points} precision points ({self.method}"
                f"{'' if not self.starts else f', {self.starts} starts'}), output error up to {self.worst:.2g} rad"
                + (f"; {defects} with a branch or lock-up defect" if defects else ""))

    def to_dict(self) -> dict:
        return {"status": str(self.status), "message": self.message, "method": self.method, "starts": self.starts,
                "points": self.points, "worst": self.worst, "solutions": [s.to_dict() for s in self.solutions],
                "mechanisms": [s.mechanism.to_dict() for s in self.solutions if s.mechanism is not None]}


@dataclass(frozen=True)
class _Frame:
    """The axes' common-normal frame: origin ``o`` (the foot on the input axis), columns ``E = [x, y, z]``
    (``z = ua``, ``x`` along the common normal), its length ``d``, ``ca``, ``sa`` (``ub = (0, sa, ca)``)."""

    pa: np.ndarray
    ua: np.ndarray
    pb: np.ndarray
    ub: np.ndarray
    o: np.ndarray
    E: np.ndarray
    d: float
    ca: float
    sa: float


def _axis(value, where: str):
    try:
        point, direction = (np.asarray(v, dtype=float) for v in value)
    except (TypeError, ValueError):
        raise InputError(f"{where}: give (point, direction), each three numbers") from None
    if point.shape != (3,) or direction.shape != (3,):
        raise InputError(f"{where}: give (point, direction), each three numbers")
    if not (np.all(np.isfinite(point)) and np.all(np.isfinite(direction))):
        raise InputError(f"{where}: the point and direction must be finite numbers")
    norm = float(np.linalg.norm(direction))
    if norm == 0:
        raise InputError(f"{where}: the direction (0, 0, 0) has no direction")
    return point, direction / norm


def _frame(input_axis, output_axis) -> _Frame:
    pa, ua = _axis(input_axis, "input axis")
    pb, ub = _axis(output_axis, "output axis")
    n = np.cross(ua, ub)
    sine = float(np.linalg.norm(n))
    spread = max(1.0, float(np.linalg.norm(pa)), float(np.linalg.norm(pb)))
    if sine <= DEGENERATE:
        raise InputError("the input and output axes are parallel: the motion is planar and an RSSR meets at most "
                         "five precision points there (use the planar four-bar function generator)")
    w = pb - pa
    c = float(ua @ ub)
    s = (float(ua @ w) - c * float(ub @ w)) / (sine * sine)   # feet of the common normal
    t = (c * float(ua @ w) - float(ub @ w)) / (sine * sine)
    fa, fb = pa + s * ua, pb + t * ub
    d = float(np.linalg.norm(fb - fa))
    if d <= DEGENERATE * spread:
        raise InputError("the input and output axes meet: the linkage is spherical and every solution scales about "
                         "the meeting point (use the spherical function generator, domes.design.synthesis.sphere)")
    x = (fb - fa) / d
    y = np.cross(ua, x)
    return _Frame(pa, ua, pb, ub, fa, np.column_stack([x, y, ua]), d, c, float(ub @ y))


def _displacements(fr: _Frame, th, ph):
    """``D_R,j`` as ``(R_j, t_j)`` in world coordinates (j over the given relative turns)."""
    Rs, ts = [], []
    for t, f in zip(th, ph):
        Ra, Rb = rot(fr.ua, t), rot(fr.ub, -f)
        Rs.append(Rb @ Ra)
        ts.append(Rb @ (fr.pa - Ra @ fr.pa - fr.pb) + fr.pb)
    return np.array(Rs), np.array(ts)


def _equations(x, R, t):
    """``|D_j a − b|² − |a − b|²`` (rows over the starts ``x = (a, b)``, shape (N, 6)) and the Jacobian."""
    a, b = x[:, :3], x[:, 3:]
    Da = np.einsum("mij,nj->nmi", R, a) + t[None]
    rel = Da - b[:, None]
    f = np.einsum("nmi,nmi->nm", rel, rel) - np.sum((a - b) ** 2, axis=1)[:, None]
    da = 2 * np.einsum("mji,nmj->nmi", R, rel) - 2 * (a - b)[:, None]
    db = -2 * (Da - a[:, None])
    return f, np.concatenate([da, db], axis=2)


def _exact(fr: _Frame, th: np.ndarray, ph: np.ndarray) -> list[np.ndarray]:
    """The (at most two) real solutions ``(a1, b1)`` for seven points, world coordinates (module docstring)."""
    ct, st, cp, sp = np.cos(th), np.sin(th), np.cos(ph), np.sin(ph)
    F = np.column_stack([ct, st, cp, sp, np.ones_like(th)])
    U, sv, _ = np.linalg.svd(F)
    if sv[-1] <= 1e-9 * sv[0]:
        raise InputError("the precision points are not independent (two of them coincide, or the input or output "
                         "turns repeat in a pattern): seven distinct points are needed")
    Q = U[:, 5:]
    ca = fr.ca
    M = np.array([[ct * cp + ca * st * sp, -ct * sp + ca * st * cp],
                  [-st * cp + ca * ct * sp, st * sp + ca * ct * cp]]).transpose(2, 0, 1)
    P = np.einsum("jk,jab->kab", Q, M)
    S = np.outer(P[0][:, 0], P[1][:, 1]) - np.outer(P[0][:, 1], P[1][:, 0])
    S = 0.5 * (S + S.T)
    lam, V = np.linalg.eigh(S)
    scale = max(abs(lam).max(), 1e-300)
    if abs(lam).max() <= 1e-14:
        raise InputError("the precision points leave the crank phases undetermined (a degenerate set)")
    xs = []
    if lam[0] * lam[1] <= 0:
        for sign in ((1.0, -1.0) if abs(lam[0] * lam[1]) > 1e-24 * scale ** 2 else (1.0,)):
            x = math.sqrt(abs(lam[1])) * V[:, 0] + sign * math.sqrt(abs(lam[0])) * V[:, 1]
            xs.append(x / np.linalg.norm(x))
    out = []
    for x in xs:
        N = np.array([x @ P[0], x @ P[1]])
        y = np.linalg.svd(N)[2][-1]
        psa, psb = math.atan2(x[1], x[0]), math.atan2(y[1], y[0])
        g = np.einsum("a,jab,b->j", x, M, y)
        G = np.column_stack([np.cos(th + psa), np.sin(th + psa), np.cos(ph + psb), np.sin(ph + psb), np.ones_like(th)])
        k = np.linalg.lstsq(G, -g, rcond=None)[0]
        if abs(k[0]) <= 1e-9 or abs(k[2]) <= 1e-9:
            continue                                   # a crank of (nearly) infinite length
        ra, rb = -fr.d / k[2], fr.d / k[0]
        za, zb = -k[3] * ra / fr.sa, k[1] * rb / fr.sa
        a = np.array([ra * math.cos(psa), ra * math.sin(psa), za])
        b = np.array([fr.d + rb * math.cos(psb), zb * fr.sa + rb * math.sin(psb) * fr.ca,
                      zb * fr.ca - rb * math.sin(psb) * fr.sa])
        out.append(np.concatenate([fr.o + fr.E @ a, fr.o + fr.E @ b]))
    return out


def _lm(x, R, t, free, iterations: int):
    """Levenberg–Marquardt on the ``free`` columns of every start at once; the points and their costs."""
    f, J = _equations(x, R, t)
    J = J[:, :, free]
    cost = np.sum(f * f, axis=1)
    lam = np.full(len(x), 1e-3)
    eye = np.eye(len(free))
    for _ in range(iterations):
        JTJ = np.einsum("nmi,nmj->nij", J, J)
        g = np.einsum("nmi,nm->ni", J, f)
        dg = np.einsum("nii->ni", JTJ) + 1e-12
        A = JTJ + lam[:, None, None] * (eye * dg[:, :, None])
        try:
            step = -np.linalg.solve(A, g[..., None])[..., 0]
        except np.linalg.LinAlgError:                 # a start where the equations vanish identically
            step = -np.einsum("nij,nj->ni", np.linalg.pinv(A), g)
        xn = x.copy()
        xn[:, free] += step
        fn, Jn = _equations(xn, R, t)
        cn = np.sum(fn * fn, axis=1)
        ok = cn < cost
        x = np.where(ok[:, None], xn, x)
        f = np.where(ok[:, None], fn, f)
        J = np.where(ok[:, None, None], Jn[:, :, free], J)
        cost = np.where(ok, cn, cost)
        lam = np.clip(np.where(ok, lam / 4, lam * 4), 1e-12, 1e12)
    return x, cost


def _newton(x, R, t, free, steps: int = 6):
    """Newton (least-squares, by the pseudo-inverse) steps on every row of ``x`` at once."""
    x = x.copy()
    for _ in range(steps):
        f, J = _equations(x, R, t)
        x[:, free] -= np.einsum("nij,nj->ni", np.linalg.pinv(J[:, :, free]), f)
    return x


def _seeded(fr: _Frame, th, ph, fixed: dict, starts: int, seed: int, tol: float) -> list[np.ndarray]:
    """Every distinct non-trivial solution the seeded starts reach, world coordinates."""
    c = 0.5 * (fr.o + fr.o + fr.d * fr.E[:, 0])                # work about the common normal's middle, in units d
    R, t = _displacements(fr, th, ph)
    tu = (np.einsum("mij,j->mi", R, c) + t - c) / fr.d
    rng = np.random.default_rng(seed)
    n = starts

    def around(foot, u):
        e1 = np.cross(u, fr.E[:, 0] if abs(u @ fr.E[:, 0]) < 0.9 else fr.E[:, 1])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(u, e1)
        psi = rng.uniform(0, 2 * math.pi, n)
        r = rng.uniform(0.1, 3.0, n)
        z = rng.uniform(-3.0, 3.0, n)
        return foot + z[:, None] * u + r[:, None] * (np.cos(psi)[:, None] * e1 + np.sin(psi)[:, None] * e2)

    fa = (fr.o - c) / fr.d
    fb = (fr.o + fr.d * fr.E[:, 0] - c) / fr.d
    x0 = np.hstack([around(fa, fr.ua), around(fb, fr.ub)])
    for name, value in fixed.items():
        k = NAMES.index(name)
        x0[:, k] = (value - c[k % 3]) / fr.d
    free = [k for k, nm in enumerate(NAMES) if nm not in fixed]
    x, cost = _lm(x0, R, tu, free, 40)
    x = _newton(x[cost <= 1e-6], R, tu, free)
    f, _ = _equations(x, R, tu)
    ra = np.linalg.norm(np.cross(x[:, :3] - fa, fr.ua), axis=1)
    rb = np.linalg.norm(np.cross(x[:, 3:] - fb, fr.ub), axis=1)
    with np.errstate(invalid="ignore"):
        good = (np.max(np.abs(f), axis=1) <= tol) & (np.max(np.abs(x), axis=1) <= 1e4) & (ra > 1e-6) & (rb > 1e-6)
    out: list[np.ndarray] = []                         # the trivial family (both centres on their axes) left out
    for y in x[good][np.argsort(np.max(np.abs(f[good]), axis=1))]:
        if not any(np.max(np.abs(y - z)) <= 1e-7 for z in out):
            out.append(y)
    found = [np.concatenate([c, c]) + fr.d * y for y in out]
    for x in found:                                    # the fixed coordinates exactly as given
        for name, value in fixed.items():
            x[NAMES.index(name)] = value
    return found


def _foot(p, u, q):
    return p + float(u @ (q - p)) * u


def mechanism(a1, b1, input_axis, output_axis, name: str = "RSSR function generator") -> SpatialMechanism:
    """The spatial mechanism file of an RSSR drawn in position 1: joints ``A0`` (R, input, at the foot of ``a1``
    on the input axis), ``A``, ``B`` (S) and ``B0`` (R, output); the input drives ``A0``."""
    pa, ua = _axis(input_axis, "input axis")
    pb, ub = _axis(output_axis, "output axis")
    a1, b1 = np.asarray(a1, float), np.asarray(b1, float)
    t = lambda v: tuple(map(float, v))  # noqa: E731
    joints = (SpatialJoint("A0", "R", ("frame", "input"), t(_foot(pa, ua, a1)), t(ua)),
              SpatialJoint("A", "S", ("input", "coupler"), t(a1)),
              SpatialJoint("B", "S", ("coupler", "output"), t(b1)),
              SpatialJoint("B0", "R", ("frame", "output"), t(_foot(pb, ub, b1)), t(ub)))
    return SpatialMechanism.build(name, ("frame", "input", "coupler", "output"), "frame", joints,
                                  (SpatialInput("A0"),))


#: The sweep of :func:`check` takes steps of at most this (rad) between the precision inputs' extremes.
SWEEP_STEP = math.radians(15.0)


def check(mech: SpatialMechanism, th, ph, sweep: bool = True) -> tuple[float, float, str]:
    """``(error, swept_error, defect)`` of a mechanism from :func:`mechanism` at relative turns ``th``, ``ph``.

    ``error``: the RSSR closed form's miss on the nearer assembly mode. With ``sweep``: one
    :func:`~domes.motion.spatial.sweep.spatial_sweep` from position 1 over the precision inputs' range (steps of
    at most :data:`SWEEP_STEP`, the closed form keeping the walk on its branch), then the backend's position
    solve (Newton) at each precision input from the nearest pose of the walk: ``swept_error`` its miss (inf
    where the walk stops short: ``defect`` "lock-up"); "branch" where a point is met only on the other mode
    or the walk passes a branch point. Without: ``swept_error`` NaN, ``defect`` from the closed form alone:
    "lock-up" where a range in which the linkage does not assemble (its exact gaps) lies between the precision
    inputs, "branch" where a point is missed on the drawn mode."""
    from domes.motion.spatial.loops import Loops
    from domes.motion.spatial.rssr import RSSR
    from domes.motion.spatial.sweep import spatial_sweep

    form = RSSR.of(mech)
    drawn = form.drawn_branch()
    th, ph = np.asarray(th, dtype=float), np.asarray(ph, dtype=float)
    miss = {s: np.abs(np.remainder(form.beta(th, s) - ph + math.pi, 2 * math.pi) - math.pi) for s in (1, -1)}
    error = float(np.max(np.fmin(miss[1], miss[-1])))            # NaN only where neither mode assembles
    error = math.inf if math.isnan(error) else error
    drawn_error = float(np.max(miss[drawn]))
    drawn_error = math.inf if math.isnan(drawn_error) else drawn_error
    lo, hi = float(np.min(th)), float(np.max(th))
    if not sweep:
        blocked = any(math.floor((hi - g0) / (2 * math.pi)) >= math.ceil((lo - g1) / (2 * math.pi))
                      for g0, g1 in form.gaps("input"))          # a gap, shifted by whole turns, meets [lo, hi]
        defect = "lock-up" if blocked or not math.isfinite(drawn_error) else "branch" if drawn_error > 1e-6 else ""
        return error, math.nan, defect
    steps = max(1, math.ceil((hi - lo) / SWEEP_STEP))
    try:
        sw = spatial_sweep(mech, lo, hi, (hi - lo) / steps, outputs=["angle:B0"])
    except NumericalError:              # the walk from position 1 to the range's start stopped
        return error, math.inf, "lock-up"
    if sw.limit is not None:
        return error, math.inf, "lock-up"
    kin = Loops(mech, ["angle:B0"])
    swept = 0.0
    for t, f in zip(th, ph):
        k = int(np.argmin(np.abs(sw.inputs - t)))
        try:
            s, _ = kin.positions({"A0": float(t)}, sw.states[k])
        except NumericalError:
            return error, math.inf, "lock-up"
        got = kin.output_values(s)["angle:B0"]
        swept = max(swept, abs(math.remainder(got - f, 2 * math.pi)))
    return error, swept, "branch" if swept > 1e-6 or sw.branch_points else ""


def rssr_function(input_axis, output_axis, thetas, phis, fixed: dict | None = None, method: str = "auto",
                  starts: int = 300, seed: int = 0, tol: float = 1e-10, sweep: bool = True) -> RSSRFunction:
    """Every RSSR whose output turns ``phis`` when the input turns ``thetas`` (rad; n ≤ 7 precision pairs, the
    first the reference position), the input and output axes given as ``(point, direction)``.

    ``method``: ``"exact"`` (seven points, closed form, every real solution), ``"seeded"`` (any n, with
    ``7 − n`` coordinates ``fixed`` by name: ``a1x`` .. ``b1z``; ``starts`` seeded starts) or ``"auto"`` (exact
    for seven points, else seeded). ``tol``: the largest residual (of ``|D a − b|² − |a − b|²`` over ``d²``)
    accepted. ``sweep``: also walk each solution to its points by continuity (defects)."""
    fr = _frame(input_axis, output_axis)
    th = np.asarray(thetas, dtype=float).ravel()
    ph = np.asarray(phis, dtype=float).ravel()
    if th.size != ph.size:
        raise InputError(f"{th.size} input angles but {ph.size} output angles: give one (θ, φ) pair per point")
    n = th.size
    if not 2 <= n <= MOST:
        raise InputError(f"an RSSR function generator meets 2 to {MOST} precision points; got {n}")
    if not (np.all(np.isfinite(th)) and np.all(np.isfinite(ph))):
        raise InputError("the precision angles must be finite numbers")
    th, ph = th - th[0], ph - ph[0]
    for j in range(1, n):
        for i in range(j):
            if abs(math.remainder(th[j] - th[i], 2 * math.pi)) <= 1e-9:
                raise InputError(f"precision points {i + 1} and {j + 1} have the same input angle")
    fixed = {k: float(v) for k, v in (fixed or {}).items()}
    for key in fixed:
        if key not in NAMES:
            raise InputError(f"fixed: {key!r} is not an unknown ({', '.join(NAMES)})")
        if not math.isfinite(fixed[key]):
            raise InputError(f"fixed: {key} must be a finite number")
    if method not in METHODS:
        raise InputError(f"method: one of {', '.join(METHODS)}, got {method!r}")
    if method == "auto":
        method = "exact" if n == MOST and not fixed else "seeded"
    if method == "exact" and (n != MOST or fixed):
        raise InputError(f"the exact method solves seven precision points with nothing fixed; got {n} points"
                         + (f" and {len(fixed)} fixed" if fixed else "") + " (use method='seeded')")
    if len(fixed) != MOST - n and method == "seeded":
        raise InputError(f"{n} precision points leave {MOST - n} of the six coordinates of a1, b1 free: fix exactly "
                         f"that many ('fixed', e.g. {{'b1x': ..}}); got {len(fixed)}")
    if method == "seeded" and not (isinstance(starts, int) and 1 <= starts <= 100_000):
        raise InputError(f"starts: an integer from 1 to 100,000, got {starts!r}")
    if method == "exact":
        found, used = _exact(fr, th, ph), 0
    else:
        found, used = _seeded(fr, th, ph, fixed, starts, seed, tol), starts
    R, t = _displacements(fr, th, ph)
    solutions = []
    for k, x in enumerate(found, 1):
        a1, b1 = x[:3], x[3:]
        lengths = np.linalg.norm(np.einsum("mij,j->mi", R, a1) + t - b1, axis=1)
        residual = float(np.ptp(lengths)) / fr.d
        mech = mechanism(a1, b1, (fr.pa, fr.ua), (fr.pb, fr.ub), f"RSSR function generator {k}")
        error, swept, defect = check(mech, th, ph, sweep)
        solutions.append(RSSRSolution(a1, b1, _foot(fr.pa, fr.ua, a1), _foot(fr.pb, fr.ub, b1), fr.ua, fr.ub,
                                      residual, error, swept if sweep else math.nan, defect, mech))
    worst = max((s.error for s in solutions), default=0.0)
    return RSSRFunction(Status.COMPLETE if solutions else Status.EMPTY, tuple(solutions), method, used, n, worst)


__all__ = ["METHODS", "MOST", "NAMES", "RSSRFunction", "RSSRSolution", "check", "mechanism", "rssr_function"]
