"""Groups solved by Newton's method, on arrays: class-III and class-IV Assur groups for many inputs at once.

A :class:`Loops` compiles a group's loop equations (seed 000, eq. 15: the
segments of :mod:`~domes.motion.planar.structure`) into matrices. Each loop
is ``Σ c_s·exp(iθ_s)`` with ``θ = C·v + θ₀`` linear in the variables and
``c_s`` a link's length or a slide's signed travel, so the residuals and
Jacobians of a whole array of configurations cost a few array operations.

:func:`follow` solves the group along a path of configurations (a sweep's
inputs) from a solved one, as continuation does step by step: Newton's
method walks a coarse subset of the path in order (each step predicted from
the last solutions, its stride doubled while the predictions hold and
halved where they fail, down to single steps), then every configuration in
between is solved at once from cubics through the coarse solutions. A
configuration whose solution strays from its prediction is walked again
step by step; the first one that cannot be solved ends the path (the sweep
hands it to the scalar code, which locates the dead point). Every
configuration is converged to rounding, so the path is the step-by-step
route of :meth:`~domes.motion.planar.query.Kinematics.positions` to
rounding.

>>> import numpy as np
>>> from domes.motion.planar.examples import four_bar
>>> from domes.motion.planar.query import Kinematics
>>> kin = Kinematics(four_bar(), method="newton")
>>> loops = Loops(kin, kin.groups[0])
>>> loops.unknowns, loops.external
(('rot:coupler', 'rot:rocker'), ('q:A',))
"""

from __future__ import annotations

import math

import numpy as np

#: Newton stops when its last correction (rad; slides over the size) is below this: the error left is of the
#: order of its square times the condition number, rounding (as the ``default`` preset's ``tol``).
CONVERGED = 1e-9
#: A correction below this that no longer halves is rounding near a singular point: converged.
STALL = 1e-8
#: The coarse walk stops here: its solutions are predictions, polished with the others (to :data:`CONVERGED`).
COARSE = 1e-6
#: Iterations allowed from a prediction.
ITERATIONS = 16
#: The farthest a coarse solution may be from its prediction (rad; slides over the size) for the stride to hold.
ACCEPT = 0.05
#: Below this the stride doubles.
WIDEN = 2e-3
#: The largest change of a variable between two coarse solutions (as continuation's ``JUMP``, halved).
COARSE_CHANGE = 0.3
#: The most steps that bridge two neighbours of a path too far apart for one Newton step.
BRIDGE = 64
#: A configuration solved from the cubics may stray this far from it (rad; slides over the size).
STRAY = 1e-2


class Loops:
    """A group's loop equations compiled for arrays: ``unknowns``, ``external`` (the variables it reads).

    Segments turning with the same rotation share one ``exp(iΔ)``: a loop
    is ``Σ_k exp(iΔ_k)·Z_k`` plus its slides' ``exp(iΔ_k)·w·(s − s₀)``.
    :meth:`system` gives the residuals and Jacobians of configurations whose
    variables are the rows of a matrix (unknowns first, then the external ones).
    """

    def __init__(self, kin, g):
        segs = [(i, seg) for i, loop in enumerate(g.loops) for seg in loop]
        names: list[str] = []
        for _, seg in segs:
            names += [v for v, _ in seg.rotation.terms] + ([seg.slide] if seg.kind == "slide" else [])
        for x in g.links:
            names += [v for v, _ in kin.structure.rotations[x].terms]
        self.unknowns = tuple(g.unknowns)
        self.external = tuple(sorted(set(names) - set(g.unknowns)))
        order = list(self.unknowns) + list(self.external)
        col = {v: k for k, v in enumerate(order)}
        L, V = len(g.loops), len(order)
        rots: dict = {}
        for _, seg in segs:
            rots.setdefault(tuple(sorted(seg.rotation.terms)), len(rots))
        K = len(rots)
        self.C = np.zeros((K, V))
        for terms, k in rots.items():
            for v, c in terms:
                self.C[k, col[v]] += c
        self.Z = np.zeros((K, L), dtype=complex)
        self.slides = []                                      # (rotation, loop, weight, variable, s0)
        for i, seg in segs:
            k = rots[tuple(sorted(seg.rotation.terms))]
            turn = complex(math.cos(seg.rotation.const + seg.alpha), math.sin(seg.rotation.const + seg.alpha))
            if seg.kind == "link":
                self.Z[k, i] += seg.length * turn
            else:
                self.slides.append((k, i, seg.sign * turn, col[seg.slide], seg.s0))
        # Jacobian blocks, variable-major: column ``v·L + l`` is ∂(loop l)/∂v.
        self.Zd = np.ascontiguousarray((1j * self.C[:, :, None] * self.Z[:, None, :]).reshape(K, V * L))
        self._CT = np.ascontiguousarray(self.C.T)
        self.loops, self.count = L, V
        self.scale = np.array([1.0 if v.startswith("rot:") else 1.0 / kin.size for v in self.unknowns])
        self.turning = self.scale == 1.0
        self.size = kin.size
        self._blocks: dict = {}

    def _block(self, columns):
        """The Jacobian block of the first ``columns`` variables, contiguous (a BLAS product)."""
        if columns not in self._blocks:
            self._blocks[columns] = np.ascontiguousarray(self.Zd[:, :columns * self.loops])
        return self._blocks[columns]

    def turns(self, X):
        """``exp(iΔ_k)`` of every rotation for the configurations ``X`` (rows of variables): ``(n, K)``."""
        return np.exp(1j * (X @ self._CT))

    def system(self, X, columns: int | None = None):
        """Residuals ``(n, 2L)`` (rows ``x, y`` of each loop) and the Jacobians ``(n, 2L, columns)`` (the first
        ``columns`` variables; all by default; none when 0)."""
        E = self.turns(X)
        F = _product(E, self.Z)
        n = X.shape[0]
        columns = self.count if columns is None else columns
        L = self.loops
        dF = _product(E, self._block(columns)) if columns else None
        for k, i, w, j, s0 in self.slides:
            unit = E[:, k] * w
            term = unit * (X[:, j] - s0)
            F[:, i] += term
            if columns:
                for v in np.flatnonzero(self.C[k, :columns]):
                    dF[:, v * L + i] += 1j * self.C[k, v] * term
                if j < columns:
                    dF[:, j * L + i] += unit
        res = np.ascontiguousarray(F).view(np.float64)
        if not columns:
            return res, None
        return res, dF.reshape(n, columns, L).view(np.float64).transpose(0, 2, 1)

    def second(self, X, Xd):
        """The loops' second derivatives with every variable's acceleration zero, ``(n, 2L)``: the centripetal
        (``−Δ̇²``) and Coriolis (``2iṡΔ̇``) terms, at the configurations ``X`` with rates ``Xd``."""
        E = self.turns(X)
        w = Xd @ self._CT
        F = _product(-(w * w) * E, self.Z)
        for k, i, c, j, s0 in self.slides:
            F[:, i] += E[:, k] * c * (2j * Xd[:, j] * w[:, k] - (X[:, j] - s0) * w[:, k] ** 2)
        return np.ascontiguousarray(F).view(np.float64)

    def newton(self, X, iterations: int = ITERATIONS):
        """Newton's method on every row of ``X`` at once (unknown columns updated in place): the converged mask.

        Rotations move at most 0.5 rad per iteration, as in the scalar method.
        """
        U = len(self.unknowns)
        n = X.shape[0]
        ok = np.zeros(n, dtype=bool)
        last = np.full(n, np.inf)
        rows = np.arange(n)
        for _ in range(iterations):
            if rows.size == 0:
                break
            whole = rows.size == n
            sub = X if whole else X[rows]
            res, J = self.system(sub, U)
            dx = solve(J, -res)
            dx[~res.any(axis=1)] = 0.0                        # closed exactly (the drawn pose): nothing to correct
            bad = ~np.isfinite(dx).all(axis=1)
            cap = np.max(np.abs(dx) * self.turning, axis=1)
            big = cap > 0.5
            if big.any():
                dx[big] *= (0.5 / cap[big])[:, None]
            dx[bad] = 0.0
            if whole:
                X[:, :U] += dx
            else:
                X[rows, :U] += dx
            size = np.max(np.abs(dx * self.scale), axis=1)
            conv = ((size <= CONVERGED) | ((size <= STALL) & (size >= 0.5 * last[rows]))) & ~bad
            ok[rows[conv]] = True
            last[rows] = size
            rows = rows[~(conv | bad)]
        return ok

    def newton_one(self, x, ext, tol: float = CONVERGED):
        """:meth:`newton` for one configuration (unknowns ``x`` from a prediction, ``ext`` the variables it reads),
        stopping at a correction below ``tol``: ``(solution, converged)``, with the least array overhead (the
        coarse walk is sequential)."""
        U = x.size
        X = np.concatenate((x, ext))[None, :]
        last = math.inf
        for _ in range(ITERATIONS):
            res, J = self.system(X, U)
            if not res.any():
                return X[0, :U], True
            try:
                dx = np.linalg.solve(J[0], -res[0])
            except np.linalg.LinAlgError:
                return X[0, :U], False
            cap = float(np.max(np.abs(dx) * self.turning))
            if cap > 0.5:
                dx *= 0.5 / cap
            X[0, :U] += dx
            size = float(np.max(np.abs(dx) * self.scale))
            if not math.isfinite(size):
                return X[0, :U], False
            if size <= tol or (size <= STALL and size >= 0.5 * last):
                return X[0, :U], True
            last = size
        return X[0, :U], False

    def closure(self, X):
        """Each configuration's largest loop-closure error (a length)."""
        res, _ = self.system(X, 0)
        return np.max(np.abs(res), axis=1)


#: Rows per BLAS product with the loops' small matrices: on more, threaded BLAS spends longer starting and waiting
#: for its threads (more so on a busy machine) than the few operations take.
BLAS_ROWS = 512


def _product(E, M):
    """``E @ M`` for ``E`` of few columns, in blocks of :data:`BLAS_ROWS` rows (each on one thread)."""
    n = E.shape[0]
    if n <= BLAS_ROWS:
        return E @ M
    out = np.empty((n, M.shape[1]), dtype=np.result_type(E, M))
    for i in range(0, n, BLAS_ROWS):
        np.matmul(E[i:i + BLAS_ROWS], M, out=out[i:i + BLAS_ROWS])
    return out


def solve(J, rhs):
    """Solve a stack of small systems; NaN where one is singular (no exception)."""
    if J.shape[0] == 0:
        return np.zeros(rhs.shape)
    try:
        return np.linalg.solve(J, rhs[..., None])[..., 0]
    except np.linalg.LinAlgError:
        out = np.full(rhs.shape, np.nan)
        for k in range(J.shape[0]):
            try:
                out[k] = np.linalg.solve(J[k], rhs[k])
            except np.linalg.LinAlgError:
                pass
        return out


def _distance(loops, a, b):
    return float(np.max(np.abs((a - b) * loops.scale))) if a.size else 0.0


def _predict(ts, xs, t):
    """Extrapolate the last solutions (``ts``, ``xs``) to ``t``: quadratic, linear or constant as they allow."""
    k = len(ts)
    if k >= 3 and ts[-1] != ts[-2] and ts[-2] != ts[-3] and ts[-1] != ts[-3]:
        t0, t1, t2 = ts[-3:]
        l0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2))
        l1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2))
        l2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1))
        return l0 * xs[-3] + l1 * xs[-2] + l2 * xs[-1]
    if k >= 2 and ts[-1] != ts[-2]:
        return xs[-1] + (xs[-1] - xs[-2]) * (t - ts[-1]) / (ts[-1] - ts[-2])
    return xs[-1].copy()


def follow(loops: Loops, ext, t, x0, ext0=None, t0: float = 0.0):
    """The group's unknowns along a path: ``(x, first)``.

    ``ext`` ``(n, E)`` holds the external variables of each configuration,
    ``t`` ``(n,)`` its place on the path (nondecreasing: the input walked so
    far), ``x0`` the solved unknowns at ``t0`` (where the external variables
    are ``ext0``). ``x`` is ``(n, U)``, NaN from ``first`` on (the first
    configuration that could not be reached; ``n`` when all were). Two
    neighbours too far apart for one Newton step are bridged in up to
    :data:`BRIDGE` steps, the external variables moving linearly between them.

    >>> import numpy as np
    >>> from domes.motion.planar.examples import four_bar
    >>> from domes.motion.planar.query import Kinematics
    >>> kin = Kinematics(four_bar(), method="newton")
    >>> loops = Loops(kin, kin.groups[0])
    >>> qs = np.radians(np.arange(0.0, 361.0, 1.0))
    >>> x, first = follow(loops, qs[:, None], qs, np.zeros(2))
    >>> first, [round(float(np.degrees(x[k, 1])), 6) for k in (30, 60)]
    (361, [-7.916119, -3.234357])
    """
    n = t.size
    U = len(loops.unknowns)
    x = np.full((n, U), np.nan)
    if n == 0:
        return x, 0
    node_t, node_x, node_k = [float(t0)], [np.asarray(x0, dtype=float)], [-1]
    node_e = np.asarray(ext[0] if ext0 is None else ext0, dtype=float)
    k, stride, first = -1, 1, n
    while k < n - 1:
        j = min(k + stride, n - 1)
        pred = _predict(node_t[-3:], node_x[-3:], t[j])
        sol, ok = loops.newton_one(pred, ext[j], COARSE)
        off = _distance(loops, sol, pred) if ok else math.inf
        change = _distance(loops, sol, node_x[-1]) if ok else math.inf
        if ok and off <= ACCEPT and change <= COARSE_CHANGE:
            node_t.append(float(t[j]))
            node_x.append(sol.copy())
            node_k.append(j)
            x[j] = sol
            k = j
            if off <= WIDEN and change <= COARSE_CHANGE / 2:
                stride *= 2
            elif off > ACCEPT / 4 and stride > 1:
                stride //= 2
        elif stride > 1:
            stride //= 2
        else:
            sol = _bridge(loops, node_x[-1], node_e, ext[j])
            if sol is None:
                first = j
                break
            node_t.append(float(t[j]))
            node_x.append(sol)
            node_k.append(j)
            x[j] = sol
            k = j
        node_e = ext[k]
    _fill(loops, ext, t, x, node_t, node_x, node_k, first)
    first = min([first] + [int(i) for i in np.flatnonzero(np.isnan(x[:first, 0]))])
    x[first:] = np.nan
    return x, first


def _bridge(loops, x, e0, e1):
    """The solution at the external variables ``e1`` reached from ``x`` at ``e0`` in 2, 4, … :data:`BRIDGE`
    steps along the straight line between them (None when none reaches it)."""
    m = 2
    while m <= BRIDGE:
        here, prev = x, None
        for i in range(1, m + 1):
            guess = here if prev is None else 2 * here - prev
            sol, ok = loops.newton_one(guess, e0 + (e1 - e0) * (i / m), COARSE)
            if not ok or _distance(loops, sol, here) > COARSE_CHANGE:
                break
            prev, here = here, sol
        else:
            return here
        m *= 2
    return None


def _interpolate(nt, nx, t):
    """The cubic through the four solutions nearest each ``t`` (fewer where fewer are known): ``(len(t), U)``."""
    m = nt.size
    if m == 1:
        return np.repeat(nx[:1], t.size, axis=0)
    order = min(m, 4)
    lo = np.clip(np.searchsorted(nt, t) - order // 2, 0, m - order)
    idx = lo[:, None] + np.arange(order)
    ts = nt[idx]
    out = np.zeros((t.size, nx.shape[1]))
    for a in range(order):
        w = np.ones(t.size)
        for b in range(order):
            if b != a:
                w *= (t - ts[:, b]) / (ts[:, a] - ts[:, b])
        out += w[:, None] * nx[idx[:, a]]
    return out


def _fill(loops, ext, t, x, node_t, node_x, node_k, first):
    """Solve every configuration at once from cubics through the coarse solutions (these polished too); walk
    step by step where one strays."""
    U = len(loops.unknowns)
    solved = np.array(node_k[1:], dtype=int)
    if first == 0:
        return
    rest = np.arange(first)
    keep = np.concatenate(([True], np.diff(node_t) > 0))
    guess = _interpolate(np.array(node_t)[keep], np.array(node_x)[keep], t[rest])
    inside = solved < first
    guess[solved[inside]] = np.array(node_x[1:])[inside]
    X = np.concatenate((guess, ext[rest]), axis=1)
    ok = loops.newton(X)
    ok &= np.max(np.abs((X[:, :U] - guess) * loops.scale), axis=1) <= STRAY
    x[rest] = np.where(ok[:, None], X[:, :U], np.nan)
    strays = rest[~ok]
    if strays.size == 0:
        return
    # Walk again, one configuration after the other, each stretch between coarse solutions holding a stray.
    bounds = np.searchsorted(solved, strays)
    for b in np.unique(bounds):
        lo = int(solved[b - 1]) if b > 0 else -1
        hi = int(solved[b]) if b < solved.size else first
        ts = [node_t[b]] if lo >= 0 else [node_t[0]]
        xs = [x[lo] if lo >= 0 and np.isfinite(x[lo, 0]) else node_x[b]]
        for j in range(lo + 1, hi):
            sol, ok = loops.newton_one(_predict(ts[-2:], xs[-2:], t[j]), ext[j])
            if not ok or _distance(loops, sol, xs[-1]) > 2 * COARSE_CHANGE:
                x[j:] = np.nan
                return
            x[j] = sol
            ts.append(float(t[j]))
            xs.append(x[j].copy())
