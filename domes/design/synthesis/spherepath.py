"""Spherical four-bar path generation (seed 002 §2-3, Table 2-2, (2-115)-(2-118); digest A.3.5).

The coupler point passes through path points ``p_1..p_n`` on the unit sphere
(n ≤ 9). The coupler's displacement from position 1 to ``j`` is a spin
``β_1j`` about ``u0 = p1`` followed by the great-circle turn ``α_1j`` about
``u_j = p1 × p_j / |p1 × p_j|`` that carries ``p1`` to ``p_j``:

    cos α_1j = p1 · p_j,   D1j = Rot(u_j, α_1j) · Rot(u0, β_1j)      (2-115)-(2-118)

(the rotation about an axis by :func:`~domes.design.synthesis.sphere.rot`,
digest F.4). Both cranks ``(a0, a1)``, ``(b0, b1)`` are spherical cranks,
(2-90)-(2-91): unit vectors with ``|D1j a1 − a0| = |a1 − a0|``, which for unit
vectors is the bilinear ``a0 · (D1j a1) = a0 · a1``. Equations ``2n + 2``,
unknowns ``n + 11`` (a0, a1, b0, b1 and ``β12..β1n``), so Table 2-2 gives
``9 − n`` of them (``fixed=``: ``a0x``..``b1z``, ``beta12``..).

- **All spins given** (n ≤ 5): each crank is a spherical guidance problem
  of its own and needs ``5 − n`` given coordinates (the book's n = 4 example
  row, ``a0x, a0y, β12, β13, β14``, fixes crank a twice and crank b not at
  all: generically no solution; it is refused with that reason, as is the
  n = 2 row, whose four coordinates of crank a leave its one length
  equation a mere check, as the digest notes for Table 2-1). n = 5:
  every crank is a real root of the four bilinear equations in P² × P²
  (six complex roots): found all, by the resultant of the two centre-point
  cubics (1234 and 1235), ``method="exhaustive"``; every pair of distinct
  cranks is a four-bar. Fewer points: seeded least squares on the crank.
- **Some spins unknown**: the cranks interact; the whole square system by
  damped Newton from many seeded starts at once (``method="seeded"``, the
  starts said in the result; each start's moving pivots already meet the
  positions whose spins are given, its unknown spins where the two cranks'
  conditions meet); every distinct root reached is returned. It is not
  exhaustive: measured on planted linkages, 1200 starts found the planted
  one in 20 of 20 seven-point cases (β12, β13 given) and 2000 starts in 30
  of 30; six points (β12..β14) 20 of 20, eight points (β12) 19 of 20.

The book's remark that above six points the result "depends strongly on
the initial estimate" is this: many real roots (4 to 31 for seven points,
19 to 91 for eight, in the planted cases), some with small basins.

A crank's axis is a line: ``a0`` and ``−a0`` (and ``a1``, ``−a1``) are the
same linkage, as are the two cranks swapped; solutions are told apart as
linkages. Each is built as a :class:`~domes.model.spatial.SpatialMechanism`
(joints ``A0, A, B, B0``, coupler point ``P``) and moved by the spatial
solver to every path point (:func:`verify`).

>>> import numpy as np
>>> P = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, 0.8], [0.0, 0.6, 0.8]])
>>> D = displacements(P, [0.0, 0.3, -0.2])
>>> bool(np.allclose(D[1] @ P[0], P[1])), bool(np.allclose(D[2] @ D[2].T, np.eye(3)))
(True, True)
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field

import numpy as np

from domes.design.synthesis.sphere import rot
from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism, SpatialPoint
from domes.results import Result, Status

#: Path points further than this from the unit sphere are refused (normalise them first, (2-87)-(2-89)).
ON_SPHERE = 1e-6
#: A root is accepted when every equation is met to this.
TOL = 1e-10
#: Seeded starts by default (all iterated together).
STARTS = 2000
#: Damped Newton: iterations, step halvings per iteration, and the longest step (in the unknowns' units).
ITERATIONS, HALVINGS, LONGEST = 60, 4, 0.5
#: The pivot names whose coordinates may be given, in the unknowns' order.
PIVOTS = ("a0", "a1", "b0", "b1")


@dataclass(frozen=True)
class Check:
    """A solution moved by the spatial solver: the worst distance of the coupler point from a path point
    (``math.inf`` where one is not reached), the crank input at each point (rad), and the defects found
    (``"branch"``: a point lies on the other assembly branch or beyond a limit; ``"order"``: the input does not
    meet the points in their order)."""

    error: float
    inputs: tuple[float, ...]
    defects: tuple[str, ...]


@dataclass(frozen=True)
class SphericalPathSolution:
    """A spherical four-bar through the path: pivots (unit vectors, position 1), the spins ``β1j`` (rad,
    j = 1..n, the first 0), the largest residual of the ``2n + 2`` equations, and the spatial check."""

    a0: np.ndarray
    a1: np.ndarray
    b0: np.ndarray
    b1: np.ndarray
    spins: tuple[float, ...]
    residual: float
    check: Check | None = None

    def mechanism(self, p1, name: str = "spherical path generator") -> SpatialMechanism:
        """The linkage as a spatial mechanism: axes through the centre, input ``A0``, coupler point ``P``."""
        return mechanism(self.a0, self.a1, self.b0, self.b1, p1, name)


@dataclass(frozen=True, eq=False)
class SphericalPathResult(Result):
    """What :func:`spherical_path` found: ``solutions``, the ``method`` (``exhaustive`` or ``seeded``), the
    ``starts`` used, and the count check of Table 2-2 (``equations``, ``unknowns``, ``given``)."""

    status: Status
    solutions: tuple[SphericalPathSolution, ...]
    method: str
    starts: int
    equations: int
    unknowns: int
    given: tuple[str, ...]
    notes: tuple[str, ...] = field(default=())

    @property
    def message(self) -> str:
        worst = max((s.residual for s in self.solutions), default=0.0)
        checked = [s.check.error for s in self.solutions if s.check is not None]
        how = self.method if self.method == "exhaustive" else f"{self.method}, {self.starts} starts"
        text = (f"{self.status}: {len(self.solutions)} spherical four-bar(s) through {self.equations // 2 - 1} "
                f"points ({how}), largest residual {worst:.1e}")
        if checked:
            text += f", coupler point off the path by at most {max(checked):.1e} (spatial solver)"
        return text

    @property
    def worst(self) -> float:
        return max((s.check.error if s.check else s.residual for s in self.solutions), default=0.0)


# -- the data -------------------------------------------------------------------------------------

def check_points(points) -> np.ndarray:
    """The path points as an (n, 3) array on the unit sphere; an InputError says what is wrong and where."""
    try:
        P = np.asarray(points, dtype=float)
    except (TypeError, ValueError):
        raise InputError("path points: a list of (x, y, z), each on the unit sphere") from None
    if P.ndim != 2 or P.shape[1] != 3 or not 2 <= P.shape[0] <= 9:
        raise InputError(f"path points: 2 to 9 points (x, y, z) (Table 2-2), got an array of shape {P.shape}")
    if not np.all(np.isfinite(P)):
        raise InputError("path points must be finite numbers")
    off = np.abs(np.linalg.norm(P, axis=1) - 1.0)
    k = int(np.argmax(off))
    if off[k] > ON_SPHERE:
        raise InputError(f"path point {k + 1} is off the unit sphere: |p| − 1 = {np.linalg.norm(P[k]) - 1:.3g}; "
                         "normalise the points to the unit sphere about the centre first ((2-87)-(2-89))")
    P = P / np.linalg.norm(P, axis=1)[:, None]
    for j in range(len(P)):
        for k in range(j):
            if np.linalg.norm(P[j] - P[k]) <= 1e-9:
                raise InputError(f"path points {k + 1} and {j + 1} coincide")
        if j and np.linalg.norm(P[j] + P[0]) <= 1e-9:
            raise InputError(f"path point {j + 1} is opposite point 1: the great circle (2-116) is not defined")
    return P


def displacements(points, spins) -> np.ndarray:
    """``D1j = Rot(u_j, α_1j) Rot(p1, β_1j)`` (2-115)-(2-118), j = 1..n (the first the identity), shape (n, 3, 3)."""
    P = check_points(points)
    spins = [float(b) for b in spins]
    if len(spins) != len(P):
        raise InputError(f"one spin per path point (the first 0): {len(P)} points, {len(spins)} spins")
    return np.array([_turn(P, j) @ rot(P[0], b) for j, b in enumerate(spins)])


def _turn(P, j) -> np.ndarray:
    """The great-circle rotation carrying ``p1`` to ``p_j`` (2-115)-(2-116)."""
    if j == 0:
        return np.eye(3)
    axis = np.cross(P[0], P[j])
    alpha = math.atan2(float(np.linalg.norm(axis)), float(P[0] @ P[j]))
    return rot(axis / np.linalg.norm(axis), alpha)


def counts(n: int) -> tuple[int, int, int]:
    """Table 2-2: ``(equations, unknowns, given) = (2n + 2, n + 11, 9 − n)``.

    >>> [counts(n) for n in (2, 5, 9)]
    [(6, 13, 7), (12, 16, 4), (20, 20, 0)]
    """
    return 2 * n + 2, n + 11, 9 - n


def names(n: int) -> list[str]:
    """The unknowns' names: ``a0x .. b1z`` then ``beta12 .. beta1n``."""
    return [f"{p}{c}" for p in PIVOTS for c in "xyz"] + [f"beta1{j}" for j in range(2, n + 1)]


def _key(name: str) -> str:
    m = re.fullmatch(r"(?:beta|β)_?1_?(\d)", str(name).strip())
    return f"beta1{m.group(1)}" if m else str(name).strip()


def check_fixed(n: int, fixed) -> dict[str, float]:
    """The given variables by name, checked against Table 2-2 and against each crank's own count."""
    if fixed is None:
        fixed = {}
    if not isinstance(fixed, dict):
        raise InputError("fixed: a dict of given variables, e.g. {'beta12': 0.3, 'a0x': 0.2}")
    allowed = names(n)
    out: dict[str, float] = {}
    for raw, value in fixed.items():
        key = _key(raw)
        if key not in allowed:
            raise InputError(f"fixed: {raw!r} is not a variable of {n}-point spherical path generation "
                             f"({', '.join(allowed)})")
        try:
            v = float(value)
        except (TypeError, ValueError):
            raise InputError(f"fixed: {raw} must be a number, got {value!r}") from None
        if not math.isfinite(v):
            raise InputError(f"fixed: {raw} must be finite")
        if not key.startswith("beta") and not -1.0 <= v <= 1.0:
            raise InputError(f"fixed: {raw} = {v:g} is a coordinate of a unit vector: it must lie in [−1, 1]")
        out[key] = v
    _, _, given = counts(n)
    if len(out) != given:
        example = ", ".join(TABLE_2_2[n])
        raise InputError(f"{n} path points: Table 2-2 needs {given} given variable(s) (equations 2n + 2 = "
                         f"{2 * n + 2}, unknowns n + 11 = {n + 11}), got {len(out)} ({', '.join(out) or 'none'}); "
                         f"give {'more' if len(out) < given else 'fewer'}, e.g. {example or 'none'}")
    for p in PIVOTS:
        mine = [c for c in "xyz" if f"{p}{c}" in out]
        if len(mine) == 3:
            raise InputError(f"fixed: all three coordinates of {p} are given; give at most two (the third "
                             "follows from the unit sphere)")
        if sum(out[f"{p}{c}"] ** 2 for c in mine) > 1.0 + 1e-12:
            raise InputError(f"fixed: the given coordinates of {p} put it outside the unit sphere")
    free_spins = sum(1 for j in range(2, n + 1) if f"beta1{j}" not in out)
    for crank in "ab":
        g = sum(1 for k in out if k[0] == crank and not k.startswith("beta"))
        most = 5 - n + free_spins
        if g > most:
            raise InputError(f"crank {crank}: {g} given coordinate(s), but with {n - 1 - free_spins} of the "
                             f"{n - 1} spins given its {n + 1} equations leave room for at most {max(most, 0)}: "
                             "generically no solution (the other crank is left a family); with all spins given "
                             f"each crank takes exactly 5 − n = {5 - n} (e.g. "
                             f"{', '.join(TABLE_2_2_SPLIT.get(n, ())) or 'none'} and the spins)")
    return out


#: Table 2-2's example given variables (the book's n = 4 row over-fixes crank a: see the module's note).
TABLE_2_2 = {2: ("a0x", "a0y", "a1x", "a1y", "b0x", "b0y", "beta12"),
             3: ("a0x", "a0y", "b0x", "b0y", "beta12", "beta13"),
             4: ("a0x", "a0y", "beta12", "beta13", "beta14"),
             5: ("beta12", "beta13", "beta14", "beta15"), 6: ("beta12", "beta13", "beta14"),
             7: ("beta12", "beta13"), 8: ("beta12",), 9: ()}
#: Given coordinates that make each crank square when all spins are given.
TABLE_2_2_SPLIT = {2: ("a0x", "a0y", "a1x", "b0x", "b0y", "b1x"), 3: ("a0x", "a0y", "b0x", "b0y"),
                   4: ("a0x", "b0x"), 5: ()}


# -- the equations, many starts at once ------------------------------------------------------------

class _System:
    """The equations of one or both cranks, vectorised over starts ``x`` of shape (S, m) (the free unknowns)."""

    def __init__(self, P, fixed: dict[str, float], cranks: str = "ab"):
        self.P = P
        self.n = len(P)
        self.turns = np.array([_turn(P, j) for j in range(1, self.n)])       # (n−1, 3, 3)
        self.cranks = cranks
        allnames = [f"{c}{k}{x}" for c in cranks for k in "01" for x in "xyz"] + [f"beta1{j}" for j in range(2, self.n + 1)]
        self.allnames = allnames
        self.fixed = fixed
        self.free = [k for k, nm in enumerate(allnames) if nm not in fixed]
        self.base = np.array([fixed.get(nm, 0.0) for nm in allnames])

    def full(self, x):
        X = np.repeat(self.base[None], x.shape[0], axis=0)
        X[:, self.free] = x
        return X

    def evaluate(self, x, jacobian: bool = True):
        X = self.full(x)
        S, c = X.shape[0], len(self.cranks)
        p1 = self.P[0]
        beta = X[:, 6 * c:]
        cb, sb = np.cos(beta)[..., None], np.sin(beta)[..., None]                  # (S, n−1, 1)
        res, jac = [], []
        width = X.shape[1]
        for k in range(c):
            o = 6 * k
            g0, g1 = X[:, o:o + 3], X[:, o + 3:o + 6]
            along = (g1 @ p1)[:, None, None] * p1                                  # (S, 1, 3)
            spun = along + cb * (g1[:, None, :] - along) + sb * np.cross(p1, g1)[:, None, :]   # R(p1, β) g1
            gj = np.einsum("jkl,sjl->sjk", self.turns, spun)                      # D1j g1
            res.append(np.einsum("sk,sjk->sj", g0, gj) - np.sum(g0 * g1, axis=1)[:, None])
            res.append(np.stack([np.sum(g0 * g0, axis=1) - 1.0, np.sum(g1 * g1, axis=1) - 1.0], axis=1))
            if not jacobian:
                continue
            J = np.zeros((S, self.n - 1, width))
            J[:, :, o:o + 3] = gj - g1[:, None, :]
            w = np.einsum("jlk,sl->sjk", self.turns, g0)                           # A_jᵀ g0
            wp = (w @ p1)[..., None] * p1
            J[:, :, o + 3:o + 6] = wp + cb * (w - wp) - sb * np.cross(p1, w) - g0[:, None, :]
            dbeta = np.einsum("sjk,sjk->sj", w, np.cross(p1, spun))
            J[:, np.arange(self.n - 1), 6 * c + np.arange(self.n - 1)] = dbeta
            U = np.zeros((S, 2, width))
            U[:, 0, o:o + 3] = 2 * g0
            U[:, 1, o + 3:o + 6] = 2 * g1
            jac += [J, U]
        r = np.concatenate(res, axis=1)
        if not jacobian:
            return r, None
        return r, np.concatenate(jac, axis=1)[:, :, self.free]

    def starts(self, count: int, rng) -> np.ndarray:
        """Random unit pivots (given coordinates kept, the rest on the sphere) and spins."""
        X = np.repeat(self.base[None], count, axis=0)
        for k in range(2 * len(self.cranks)):
            o = 3 * k
            v = rng.normal(size=(count, 3))
            v /= np.linalg.norm(v, axis=1)[:, None]
            given = [i for i in range(3) if self.allnames[o + i] in self.fixed]
            if given:
                rest = [i for i in range(3) if i not in given]
                left = max(0.0, 1.0 - sum(self.fixed[self.allnames[o + i]] ** 2 for i in given))
                scale = math.sqrt(left) / np.maximum(np.linalg.norm(v[:, rest], axis=1), 1e-12)
                v[:, rest] *= scale[:, None]
                for i in given:
                    v[:, i] = self.fixed[self.allnames[o + i]]
            X[:, o:o + 3] = v
        spins = 6 * len(self.cranks)
        X[:, spins:] = rng.uniform(-math.pi, math.pi, size=(count, self.n - 1))
        given = [k for k in range(X.shape[1]) if self.allnames[k] in self.fixed]
        X[:, given] = self.base[given]
        self._fit(X, rng)
        return X[:, self.free]

    def _fit(self, X, rng) -> None:
        """Starts on the equations of the positions whose spins are given: each moving pivot (where none of its
        coordinates is given) orthogonal to ``(D1jᵀ − I) g0`` for those positions (its fixed pivot drawn at
        random), and each unknown spin where the two cranks' conditions, affine in ``(cos β, sin β)``, meet."""
        c = len(self.cranks)
        if c < 2:
            return                            # one crank, all spins given: plain random starts reach every root
        known = [j for j in range(1, self.n) if f"beta1{j + 1}" in self.fixed]
        p1 = self.P[0]
        for k in range(c):
            o = 6 * k
            if not known or any(self.allnames[o + 3 + i] in self.fixed for i in range(3)):
                continue
            Ds = np.array([self.turns[j - 1] @ rot(p1, self.fixed[f"beta1{j + 1}"]) for j in known])
            g0 = X[:, o:o + 3]
            rows = np.einsum("jlk,sl->sjk", Ds, g0) - g0[:, None, :]
            if len(known) == 1:
                g1 = np.cross(rows[:, 0], rng.normal(size=(len(X), 3)))
            elif len(known) == 2:
                g1 = np.cross(rows[:, 0], rows[:, 1])
            else:
                g1 = np.linalg.svd(rows)[2][:, -1]
            size = np.linalg.norm(g1, axis=1)
            ok = size > 1e-12
            X[ok, o + 3:o + 6] = g1[ok] / size[ok, None]
        self.meet(X, [j for j in range(1, self.n) if f"beta1{j + 1}" not in self.fixed])

    def meet(self, X, which) -> None:
        """Set the spins of the positions ``which`` (1-based after the first) where the two cranks' conditions
        meet: each is affine in ``(cos β, sin β)``, a line; the point where the lines cross, put on the circle."""
        p1 = self.P[0]
        for j in which:
            lines = []
            for k in range(2):
                g0, g1 = X[:, 6 * k:6 * k + 3], X[:, 6 * k + 3:6 * k + 6]
                w = g0 @ self.turns[j - 1]                                   # T_jᵀ g0
                along = (g1 @ p1)[:, None] * p1
                lines.append((np.sum(w * (g1 - along), axis=1), np.sum(w * np.cross(p1, g1), axis=1),
                              np.sum(g0 * g1, axis=1) - (w @ p1) * (g1 @ p1)))
            (ca, sa, ea), (cb, sb, eb) = lines
            det = ca * sb - sa * cb
            with np.errstate(all="ignore"):
                cos, sin = (ea * sb - sa * eb) / det, (ca * eb - ea * cb) / det
            ok = np.isfinite(cos) & np.isfinite(sin) & (np.hypot(cos, sin) > 1e-12)
            X[ok, 12 + j - 1] = np.arctan2(sin[ok], cos[ok])


def _levenberg(system: _System, x, iterations: int = 80):
    """Levenberg–Marquardt on every start at once; the roots' free unknowns and their residuals."""
    S, m = x.shape
    lam = np.full(S, 1e-3)
    r, J = system.evaluate(x)
    cost = np.sum(r * r, axis=1)
    eye = np.eye(m)
    for _ in range(iterations):
        A = np.einsum("sij,sik->sjk", J, J)
        g = np.einsum("sij,si->sj", J, r)
        diag = np.einsum("sii->si", A)
        with np.errstate(all="ignore"):
            step = _solve(A + lam[:, None, None] * (eye * (diag[:, None, :] + 1e-12)), g)
        trial = x + np.where(np.isfinite(step), step, 0.0)
        r2, J2 = system.evaluate(trial)
        cost2 = np.sum(r2 * r2, axis=1)
        ok = cost2 < cost
        x = np.where(ok[:, None], trial, x)
        r = np.where(ok[:, None], r2, r)
        J = np.where(ok[:, None, None], J2, J)
        cost = np.where(ok, cost2, cost)
        lam = np.where(ok, np.maximum(lam / 5, 1e-12), np.minimum(lam * 4, 1e8))
        if np.all(cost < 1e-28):
            break
    for _ in range(3):                                   # Newton to the last digits (square system)
        with np.errstate(all="ignore"):
            dx = _solve(J, r)
        trial = x + np.where(np.isfinite(dx), dx, 0.0)
        r2, J2 = system.evaluate(trial)
        better = np.sum(r2 * r2, axis=1) < np.sum(r * r, axis=1)
        x = np.where(better[:, None], trial, x)
        r = np.where(better[:, None], r2, r)
        J = np.where(better[:, None, None], J2, J)
    return x, np.max(np.abs(r), axis=1)


def _newton(system: _System, x):
    """Newton's method on every start at once (the system is square), each step at most :data:`LONGEST` long
    and halved up to :data:`HALVINGS` times until the residual falls; a start whose step does not lower it
    even then has stalled (a local minimum of the residual) and is dropped. The starts' end points and
    residuals. (On this system it reaches more of the roots than Levenberg–Marquardt from the same starts.)"""
    r, J = system.evaluate(x)
    cost = np.sum(r * r, axis=1)
    alive = np.ones(len(x), bool)
    for _ in range(ITERATIONS):
        live = np.flatnonzero(alive & (cost > 1e-28))
        if not live.size:
            break
        with np.errstate(all="ignore"):
            dx = _solve(J[live], r[live])
        dx = np.where(np.isfinite(dx), dx, 0.0)
        dx *= np.minimum(1.0, LONGEST / np.maximum(np.linalg.norm(dx, axis=1), 1e-300))[:, None]
        pending, t = np.arange(live.size), 1.0
        for _ in range(HALVINGS):
            k = live[pending]
            trial = x[k] + t * dx[pending]
            r2, J2 = system.evaluate(trial)
            c2 = np.sum(r2 * r2, axis=1)
            ok = c2 < cost[k]
            x[k[ok]], r[k[ok]], J[k[ok]], cost[k[ok]] = trial[ok], r2[ok], J2[ok], c2[ok]
            pending = pending[~ok]
            if not pending.size:
                break
            t /= 2
        alive[live[pending]] = False
    return x, np.max(np.abs(r), axis=1)


def _solve(J, r):
    """Newton steps of every start (zero where the Jacobian is singular)."""
    try:
        return np.linalg.solve(J, -r[..., None])[..., 0]
    except np.linalg.LinAlgError:
        out = np.zeros_like(r)
        for k in range(len(r)):
            try:
                out[k] = np.linalg.solve(J[k], -r[k])
            except np.linalg.LinAlgError:
                pass
        return out


def _crank_roots(system: _System, starts: int, rng, tol: float) -> tuple[np.ndarray, int]:
    """One crank's roots (all spins given) from seeded starts: the full unknowns of those that converged."""
    x, worst = _levenberg(system, system.starts(starts, rng))
    return system.full(x[worst <= tol]), starts


# -- five positions: every crank, by the resultant of two centre-point cubics -------------------------

def burmester(Ds) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every real crank ``(a0, a1)`` for five positions ``Ds`` (rotations, the first the identity): the real
    common zeros of the cubic cones ``det[D1jᵀ a0 − a0]_{j=2,3,4} = 0`` and ``_{j=2,3,5}`` (the 1234 and 1235
    centre-point curves, (2-90)), less the three where rows 2 and 3 are parallel; found as the roots of the
    two cubics' resultant (degree 9) in random projective coordinates (two frames, merged), each polished by
    Newton on the crank's equations and kept when it meets them."""
    Ds = np.asarray(Ds, dtype=float)
    if Ds.shape != (5, 3, 3):
        raise InputError(f"five positions (rotations), got an array of shape {Ds.shape}")
    out: list[tuple[np.ndarray, np.ndarray]] = []
    for frame in (7, 8):
        for a0 in _centre_points(Ds, np.linalg.qr(np.random.default_rng(frame).normal(size=(3, 3)))[0]):
            rows = np.array([D.T @ a0 - a0 for D in Ds[1:]])
            crank = _polish_crank(Ds, a0, np.linalg.svd(rows)[2][-1])
            if crank is None or _crank_residual(Ds, *crank) > 1e-11:
                continue
            if not any(_same_line(crank[0], h0, 1e-7) and _same_line(crank[1], h1, 1e-7) for h0, h1 in out):
                out.append(crank)
    return out


def _exact_kind(n: int, given: dict, c: str) -> str:
    """How crank ``c`` is found exactly when all spins are given: ``"five"`` (:func:`burmester`), ``"four"``
    (one coordinate of a pivot given: :func:`~domes.design.synthesis.sphere.crank_with`), ``"three"`` (two
    coordinates of one pivot: that pivot in closed form, the other normal to two rows), or ``""``."""
    mine = sorted(k for k in given if k[0] == c and not k.startswith("beta"))
    if n == 5 and not mine:
        return "five"
    if n == 4 and len(mine) == 1:
        return "four"
    if n == 3 and len(mine) == 2 and mine[0][:2] == mine[1][:2]:
        return "three"
    return ""


def _crank_exact(Ds, given: dict, c: str) -> list[tuple[np.ndarray, np.ndarray]]:
    """Every crank ``c`` for the rotations ``Ds`` (all spins given) by the route :func:`_exact_kind` names. A
    given coordinate of the moving pivot is handled by the inverse motion: ``(a1, a0)`` is a crank of the
    rotations ``D1jᵀ`` exactly when ``(a0, a1)`` is one of ``D1j``."""
    from domes.design.synthesis.sphere import crank_with

    kind = _exact_kind(len(Ds), given, c)
    if kind == "five":
        return burmester(Ds)
    mine = sorted(k for k in given if k[0] == c and not k.startswith("beta"))
    moving = mine[0][1] == "1"
    R = np.array([D.T for D in Ds]) if moving else np.asarray(Ds)
    out = []
    if kind == "four":
        axis = mine[0][2]
        value = given[mine[0]]
        if abs(value) >= 1.0:
            return []
        out = [(k.a0, k.a1) for k in crank_with(list(R), axis, value)]
    else:
        fixed = {k[2]: given[k] for k in mine}
        free = next(x for x in "xyz" if x not in fixed)
        left = 1.0 - sum(v * v for v in fixed.values())
        for sign in (1.0, -1.0) if left > 1e-15 else (1.0,):
            g0 = np.array([fixed.get(x, sign * math.sqrt(max(left, 0.0))) if x == free else fixed[x] for x in "xyz"])
            rows = [D.T @ g0 - g0 for D in R[1:]]
            g1 = np.cross(rows[0], rows[1])
            if np.linalg.norm(g1) > 1e-12:
                out.append((g0, g1 / np.linalg.norm(g1)))
    return [(b, a) for a, b in out] if moving else out


def _crank_residual(Ds, a0, a1) -> float:
    return max([abs(float(a0 @ (D @ a1) - a0 @ a1)) for D in Ds[1:]] + [abs(float(a0 @ a0) - 1),
                                                                        abs(float(a1 @ a1) - 1)])


def _centre_points(Ds, Q) -> list[np.ndarray]:
    """Candidates ``a0`` (near-real common zeros of the two cubics) in the projective frame ``Q``."""
    E = np.array([D.T - np.eye(3) for D in Ds[1:]])

    def minors(x, y):
        a0 = np.stack([x, y, np.ones_like(x)], axis=-1) @ Q.T
        R = np.einsum("jkl,...l->...jk", E, a0)
        return np.linalg.det(R[..., [0, 1, 2], :]), np.linalg.det(R[..., [0, 1, 3], :])

    ys = np.array([-1.0, 0.0, 1.0, 2.0])
    V = np.vander(ys, 4)

    def coefficients(x):
        f, g = minors(np.repeat(x[:, None], 4, axis=1), np.repeat(ys[None], x.size, axis=0) + 0j)
        return np.linalg.solve(V, f.T).T, np.linalg.solve(V, g.T).T

    N = 32
    xs = np.exp(2j * np.pi * np.arange(N) / N)
    cf, cg = coefficients(xs)
    M = np.zeros((N, 6, 6), dtype=complex)
    for k in range(3):
        M[:, k, k:k + 4] = cf
        M[:, 3 + k, k:k + 4] = cg
    coef = (np.fft.fft(np.linalg.det(M)) / N)[:10]
    keep = np.flatnonzero(np.abs(coef) > 1e-13 * np.abs(coef).max())
    coef = coef[: keep.max() + 1] if keep.size else coef[:1]
    out = []
    for x in (np.roots(coef[::-1]) if coef.size > 1 else ()):
        f, g = coefficients(np.array([x]))
        ys_ = np.roots(f[0])
        if not ys_.size:
            continue
        y = ys_[np.argmin(np.abs(np.polyval(g[0], ys_)) / np.maximum(1.0, np.abs(ys_)) ** 3)]
        a0 = np.array([x, y, 1.0]) @ Q.T
        a0 = a0 / np.sqrt(np.sum(np.abs(a0) ** 2))
        a0 = a0 * np.exp(-1j * np.angle(a0[np.argmax(np.abs(a0))]))
        if np.max(np.abs(a0.imag)) > 1e-3:
            continue
        out.append(a0.real / np.linalg.norm(a0.real))
    return out


# -- the solver -----------------------------------------------------------------------------------

def spherical_path(points, fixed=None, method: str = "auto", starts: int = STARTS, seed: int = 0,
                   tol: float = TOL, verify_with_solver: bool = True) -> SphericalPathResult:
    """Every spherical four-bar whose coupler point passes through ``points`` (unit vectors, 2..9), with the
    given variables ``fixed`` (Table 2-2: ``9 − n`` of ``a0x..b1z``, ``beta12..``; spins in rad).

    ``method``: ``"auto"`` (exhaustive where it exists: all spins given and five points), ``"exhaustive"``
    (refused where it does not exist) or ``"seeded"`` (``starts`` seeded starts, iterated together: each crank
    by Levenberg–Marquardt when all spins are given, else the whole system by damped Newton). A root is kept
    when all ``2n + 2`` equations hold to ``tol``. Each solution is moved by the spatial solver
    (``verify_with_solver``, :func:`verify`).

    >>> P = [[0.0, 0.0, 1.0], [0.5, 0.0, 0.866025403784], [0.4, 0.5, 0.768114574787],
    ...      [0.0, 0.7, 0.714142842854], [-0.3, 0.6, 0.741619848710]]
    >>> r = spherical_path(P, {"beta12": 0.1, "beta13": 0.3, "beta14": 0.2, "beta15": -0.1})
    >>> r.success, r.method, all(s.check.error < 1e-9 for s in r.solutions)
    (True, 'exhaustive', True)
    """
    P = check_points(points)
    n = len(P)
    given = check_fixed(n, fixed)
    eqs, unknowns, _ = counts(n)
    if method not in ("auto", "exhaustive", "seeded"):
        raise InputError(f"method: 'auto', 'exhaustive' or 'seeded', got {method!r}")
    if not (isinstance(starts, int) and 1 <= starts <= 100_000):
        raise InputError(f"starts: an integer from 1 to 100,000, got {starts!r}")
    all_spins = all(f"beta1{j}" in given for j in range(2, n + 1))
    exhaustive = all_spins and all(_exact_kind(n, given, c) for c in "ab")
    if method == "exhaustive" and not exhaustive:
        raise InputError("method='exhaustive' needs all spins given and, for each crank, five points, or four with "
                         "one coordinate of a pivot given, or three with two of one pivot; use 'seeded'")
    chosen = "exhaustive" if exhaustive and method != "seeded" else "seeded"
    rng = np.random.default_rng(seed)
    spins = np.array([0.0] + [given.get(f"beta1{j}", 0.0) for j in range(2, n + 1)])
    found: list[SphericalPathSolution] = []
    used = 0
    notes = []
    if all_spins:
        Ds = np.array([_turn(P, j) @ rot(P[0], b) for j, b in enumerate(spins)])
        cranks = {}
        for c in "ab":
            if chosen == "exhaustive":
                cranks[c] = _crank_exact(Ds, given, c)
            else:
                mine = {k: v for k, v in given.items() if k[0] == c or k.startswith("beta")}
                X, s = _crank_roots(_System(P, mine, c), starts, rng, tol)
                used += s
                cranks[c] = _distinct([(x[0:3], x[3:6]) for x in X])
            cranks[c] = [_polish_crank(Ds, g0, g1) for g0, g1 in cranks[c]]
            cranks[c] = [g for g in cranks[c] if g is not None and _keeps(given, c, g)]
        notes.append(f"all spins given: the cranks are independent ({len(cranks['a'])} a, {len(cranks['b'])} b)")
        for ga in cranks["a"]:
            for gb in cranks["b"]:
                if _same_line(ga[0], gb[0]) and _same_line(ga[1], gb[1]):
                    continue                                      # one crank twice: no linkage
                sol = _solution(P, ga, gb, spins, given)
                if sol.residual <= tol and not any(_same(sol, f) for f in found):
                    found.append(sol)
    else:
        system = _System(P, given, "ab")
        pool = system.starts(starts, rng)
        used = starts
        x, worst = _newton(system, pool)
        notes.append(f"{starts} seeded starts, damped Newton on the {eqs} equations; the cranks interact through "
                     "the unknown spins, so the roots found are those reached (more starts may find more)")
        for X in _representatives(system.full(x[worst <= tol])):
            sp = np.concatenate([[0.0], X[12:]])
            sol = _solution(P, (X[0:3], X[3:6]), (X[6:9], X[9:12]), sp, given)
            if sol.residual <= tol and not _degenerate(sol) and not any(_same(sol, f) for f in found):
                found.append(sol)
    if verify_with_solver:
        found = [SphericalPathSolution(s.a0, s.a1, s.b0, s.b1, s.spins, s.residual, verify(P, s)) for s in found]
    status = Status.COMPLETE if found else Status.EMPTY
    return SphericalPathResult(status, tuple(found), chosen, used, eqs, unknowns, tuple(sorted(given)), tuple(notes))


def _representatives(X) -> np.ndarray:
    """One row of each group of roots that agree to 1e-6 as linkages (axes up to sign, cranks in either
    order, spins by their cosine and sine): fewer rows for the exact comparison (:func:`_same`)."""
    if not len(X):
        return X
    axes = X[:, :12].reshape(len(X), 4, 3)
    axes = axes * np.sign(np.take_along_axis(axes, np.argmax(np.abs(axes), axis=2)[..., None], axis=2))
    cranks = axes.reshape(len(X), 2, 6)
    first = np.round(cranks[:, 0], 6)
    second = np.round(cranks[:, 1], 6)
    order = np.array([tuple(a) <= tuple(b) for a, b in zip(first, second)])
    lo = np.where(order[:, None], first, second)
    hi = np.where(order[:, None], second, first)
    key = np.hstack([lo, hi, np.round(np.cos(X[:, 12:]), 6), np.round(np.sin(X[:, 12:]), 6)])
    _, keep = np.unique(key, axis=0, return_index=True)
    return X[np.sort(keep)]


def _keeps(given, c, crank) -> bool:
    """Whether a crank (up to the signs of its axes) keeps the given coordinates."""
    for k, g in zip("01", crank):
        for i, x in enumerate("xyz"):
            v = given.get(f"{c}{k}{x}")
            if v is not None and abs(abs(g[i]) - abs(v)) > 1e-9:
                return False
    return True


def _polish_crank(Ds, a0, a1):
    """Newton on one crank's equations (2-90)-(2-91), all of its unknowns free, from a root found otherwise."""
    a0, a1 = np.asarray(a0, float), np.asarray(a1, float)
    for _ in range(6):
        r = [a0 @ (D @ a1) - a0 @ a1 for D in Ds[1:]] + [a0 @ a0 - 1, a1 @ a1 - 1]
        J = [np.concatenate([D @ a1 - a1, D.T @ a0 - a0]) for D in Ds[1:]]
        J += [np.concatenate([2 * a0, np.zeros(3)]), np.concatenate([np.zeros(3), 2 * a1])]
        dx = np.linalg.lstsq(np.array(J), -np.array(r), rcond=None)[0]
        a0, a1 = a0 + dx[:3], a1 + dx[3:]
    a0, a1 = a0 / np.linalg.norm(a0), a1 / np.linalg.norm(a1)
    if not np.all(np.isfinite(a0)) or np.linalg.norm(np.cross(a0, a1)) < 1e-8:
        return None                                                        # no crank: a1 on the fixed axis
    return a0, a1


def _canonical(g0, g1, c, given):
    """A crank's axes with signs chosen: a given coordinate keeps its sign; otherwise the arc ``a0 a1`` is at
    most 90° and ``a1`` is on the side of ``p1``'s hemisphere chosen by the caller."""
    g0, g1 = np.array(g0, float), np.array(g1, float)
    for k, g in (("0", g0), ("1", g1)):
        for i, x in enumerate("xyz"):
            v = given.get(f"{c}{k}{x}")
            if v is not None and v != 0 and np.sign(g[i]) != np.sign(v):
                g *= -1
                break
    pinned0 = any(given.get(f"{c}0{x}") not in (None, 0.0) for x in "xyz")
    pinned1 = any(given.get(f"{c}1{x}") not in (None, 0.0) for x in "xyz")
    if g0 @ g1 < 0:
        if not pinned1:
            g1 = -g1
        elif not pinned0:
            g0 = -g0
    return g0, g1


def _solution(P, ga, gb, spins, given) -> SphericalPathSolution:
    a0, a1 = _canonical(*ga, "a", given)
    b0, b1 = _canonical(*gb, "b", given)
    spins = tuple(float(math.remainder(s, 2 * math.pi)) for s in spins)
    return SphericalPathSolution(a0, a1, b0, b1, spins, residuals(P, a0, a1, b0, b1, spins))


def residuals(P, a0, a1, b0, b1, spins) -> float:
    """The largest error of the ``2n + 2`` equations: crank lengths ``|D1j g1 − g0| − |g1 − g0|`` (chords,
    (2-90)) and unit norms (2-91), with ``D1j`` rebuilt from (2-118)."""
    worst = max(abs(float(np.linalg.norm(v)) - 1) for v in (a0, a1, b0, b1))
    for j in range(1, len(P)):
        D = _turn(P, j) @ rot(P[0], spins[j])
        for g0, g1 in ((a0, a1), (b0, b1)):
            worst = max(worst, abs(float(np.linalg.norm(D @ g1 - g0) - np.linalg.norm(g1 - g0))))
    return worst


def _same_line(u, v, tol: float = 1e-7) -> bool:
    return bool(np.linalg.norm(np.cross(u, v)) <= tol)


def _same(s: SphericalPathSolution, t: SphericalPathSolution) -> bool:
    """One linkage: the same axes (up to sign), cranks possibly swapped, the same spins."""
    if max(abs(math.remainder(x - y, 2 * math.pi)) for x, y in zip(s.spins, t.spins)) > 1e-6:
        return False
    pairs = ((s.a0, s.a1, s.b0, s.b1), (s.b0, s.b1, s.a0, s.a1))
    return any(all(_same_line(u, v) for u, v in zip(p, (t.a0, t.a1, t.b0, t.b1))) for p in pairs)


def _distinct(cranks):
    out = []
    for g0, g1 in cranks:
        if not any(_same_line(g0, h0, 1e-6) and _same_line(g1, h1, 1e-6) for h0, h1 in out):
            out.append((g0, g1))
    return out


def _degenerate(s: SphericalPathSolution) -> bool:
    """A crank of no length (``a1`` on its fixed axis) or both cranks one: not a four-bar."""
    return bool(_same_line(s.a0, s.a1, 1e-8) or _same_line(s.b0, s.b1, 1e-8)
                or (_same_line(s.a0, s.b0, 1e-8) and _same_line(s.a1, s.b1, 1e-8)))


# -- the linkage, moved by the spatial solver ------------------------------------------------------

def mechanism(a0, a1, b0, b1, p1, name: str = "spherical path generator") -> SpatialMechanism:
    """The spherical four-bar as a spatial mechanism: R joints ``A0`` (frame–input), ``A`` (input–coupler),
    ``B`` (coupler–output), ``B0`` (frame–output), each on its axis through the centre, driven at ``A0``;
    the coupler point ``P`` at ``p1``."""
    t = lambda v: tuple(float(x) for x in v)  # noqa: E731
    joints = (SpatialJoint("A0", "R", ("frame", "input"), t(a0), t(a0)),
              SpatialJoint("A", "R", ("input", "coupler"), t(a1), t(a1)),
              SpatialJoint("B", "R", ("coupler", "output"), t(b1), t(b1)),
              SpatialJoint("B0", "R", ("frame", "output"), t(b0), t(b0)))
    return SpatialMechanism.build(name, ("frame", "input", "coupler", "output"), "frame", joints,
                                  (SpatialInput("A0"),), (SpatialPoint("P", "coupler", t(p1)),))


def crank_inputs(P, s: SphericalPathSolution) -> np.ndarray:
    """The input crank's turn about ``a0`` (rad, in (−π, π]) from position 1 to each path point."""
    out = []
    for j in range(len(P)):
        D = _turn(P, j) @ rot(P[0], s.spins[j])
        aj = D @ s.a1
        u, v = s.a1 - (s.a1 @ s.a0) * s.a0, aj - (aj @ s.a0) * s.a0
        out.append(math.atan2(float(s.a0 @ np.cross(u, v)), float(u @ v)))
    return np.array(out)


def verify(points, s: SphericalPathSolution) -> Check:
    """Move the linkage with the spatial backend: at each path point's input the closed form of the spherical
    four-bar (:class:`~domes.motion.spatial.spherical.SphericalFourBar`, read off the mechanism) gives the
    pose on the drawn assembly branch; the spatial position solve (:class:`~domes.motion.spatial.loops.Loops`)
    closes every joint there and gives the coupler point, whose distance from the path point is measured.
    A point met only on the other branch, or past a range where the linkage does not assemble (both ways
    round from position 1), is a ``branch`` defect; inputs not met in the points' order an ``order`` one."""
    from domes.motion.spatial.limits import closed_form
    from domes.motion.spatial.loops import Loops, State

    P = np.asarray(points, dtype=float)
    mech = mechanism(s.a0, s.a1, s.b0, s.b1, P[0])
    thetas = crank_inputs(P, s)
    kin = Loops(mech, ["point:P"])
    closed = closed_form(mech)
    form = closed.form
    drawn = form.drawn_branch()
    gaps = form.gaps()
    F1 = np.column_stack([s.a1, s.b1, np.cross(s.a1, s.b1)])
    centres = kin.drawn().o

    def point(theta, branch):
        psi = float(form.psi(theta, branch))
        if not math.isfinite(psi):
            return math.inf
        Ri = rot(form.v, theta)
        aj, bj = Ri @ s.a1, rot(form.vs, psi) @ s.b1
        Rc = np.column_stack([aj, bj, np.cross(aj, bj)]) @ np.linalg.inv(F1)
        R = np.array([Ri, Rc, rot(form.vs, psi)])
        guess = State(np.einsum("kij,kj->ki", R, centres), R)
        try:
            state, _ = kin.positions({"A0": float(theta)}, guess)
        except NumericalError:
            return math.inf
        out = kin.output_values(state)
        return np.array([out["point:P.x"], out["point:P.y"], out["point:P.z"]])

    errors, reached, defects = [], [], set()
    tau = 2 * math.pi
    for j, th in enumerate(thetas):
        got = point(th, drawn)
        err = float(np.linalg.norm(got - P[j])) if isinstance(got, np.ndarray) else math.inf
        if not err <= 1e-6:
            other = point(th, -drawn)
            alt = float(np.linalg.norm(other - P[j])) if isinstance(other, np.ndarray) else math.inf
            defects.add("branch")
            err = min(err, alt)
        ways = [q for q in (th % tau, th % tau - tau) if not closed.crosses_gap(0.0, q, gaps)]
        if not ways:
            defects.add("branch")
        reached.append(ways[0] if ways else th)
        errors.append(err)
    if not _in_order(reached, thetas):
        defects.add("order")
    return Check(max(errors), tuple(float(t) for t in thetas), tuple(sorted(defects)))


def _in_order(reached, thetas) -> bool:
    """Whether the input meets the points in their order: the inputs reached rise or fall along the sweep, or
    (a crank turning fully) the turns from position 1 do, taken all one way round."""
    tau = 2 * math.pi
    for seq in (np.array(reached), np.mod(thetas, tau), -np.mod(-np.asarray(thetas), tau)):
        steps = np.diff(seq)
        if np.all(steps > 0) or np.all(steps < 0):
            return True
    return False


__all__ = ["Check", "SphericalPathResult", "SphericalPathSolution", "burmester", "check_fixed", "check_points",
           "counts", "crank_inputs", "displacements", "mechanism", "names", "residuals", "spherical_path",
           "verify"]
