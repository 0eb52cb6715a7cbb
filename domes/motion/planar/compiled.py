"""The kernel's positions compiled (numba): one loop over configurations instead of whole-array numpy steps.

:meth:`~domes.motion.planar.kernel.Program.poses` places a mechanism of
drivers and dyads with a few dozen numpy operations, each a pass over every
configuration with its own temporary array. Here the same closed forms run
as a *tape*: each step of the program is a row of integers (its kind, links,
points, slides), and one compiled loop (:func:`run`) reads the tape and
places each step's links for every configuration, with no temporary arrays
(a batch's chunk is then finished and reduced by two more). The tape is built
once per program (:class:`Tape`); the compiled loop is the same for every
mechanism, so it is compiled once per machine (numba's on-disk cache) and
never per mechanism. A sweep goes on in one more compiled pass
(:mod:`~domes.motion.planar.onepass`: angles, rates, outputs).

The numpy route stays the reference: both give the same numbers to
rounding (``tests/motion/test_compiled.py``). :func:`choose` says which route
a call takes: ``DOMES_KERNEL=numpy`` forces numpy, ``DOMES_KERNEL=numba``
the compiled loop whatever the size; by default (``auto``) the compiled
loop is taken for a call of at least :data:`THRESHOLD` configurations (a
large batch: :func:`~domes.motion.planar.batch.batch` asks for the whole
batch) when numba is installed. numba is imported only when the compiled
loop is used.

>>> import numpy as np
>>> from domes.motion.planar.examples import four_bar
>>> from domes.motion.planar.query import Kinematics
>>> from domes.motion.planar.kernel import Program
>>> prog = Program(Kinematics(four_bar(), outputs=["angle:rocker"]))
>>> Tape.of(prog) is not None, choose(10, "numpy"), choose(10)
(True, False, False)
"""

from __future__ import annotations

import importlib.util
import os

import numpy as np

from domes.errors import InputError

#: Configurations from which the default route compiles: numba's import and the loop's load from its cache cost
#: about 0.5 s of CPU once per process (a cold cache: about 6 s to compile), which the loop repays from about
#: 10^7 configurations (``docs/benchmarks.md``, "Bounded batches").
THRESHOLD = 1 << 24
#: The environment variable that picks the route: ``numpy``, ``numba`` or ``auto`` (the default).
VARIABLE = "DOMES_KERNEL"
ROUTES = ("auto", "numpy", "numba")

DRIVER_R, DRIVER_P, RRR, RPR, RRP, PRP, RPP = range(7)
KINDS = {"RRR": RRR, "RPR": RPR, "RRP": RRP, "PRP": PRP, "RPP": RPP}
WIDTH = 13


def available() -> bool:
    """Whether numba is installed (without importing it)."""
    return importlib.util.find_spec("numba") is not None


def route(given: str | None = None) -> str:
    """The route asked for: ``given``, else ``$DOMES_KERNEL``, else ``auto``; an unknown name is refused."""
    name = (given if given is not None else os.environ.get(VARIABLE) or "auto").strip().lower()
    if name not in ROUTES:
        raise InputError(f"{VARIABLE}={name!r}: the kernel's route is one of {', '.join(ROUTES)}")
    return name


def choose(configurations: int, given: str | None = None) -> bool:
    """Whether ``configurations`` configurations are placed by the compiled loop (:func:`route`)."""
    name = route(given)
    if name == "numpy":
        return False
    if name == "numba":
        if not available():
            raise InputError(f"{VARIABLE}=numba: numba is not installed (pip install numba)")
        return True
    return configurations >= THRESHOLD and available()


class Tape:
    """A :class:`~domes.motion.planar.kernel.Program` of drivers and dyads as rows of integers, for :func:`run`.

    ``points`` names the geometry's points (joints, coupler points, slide
    origins), ``slides`` its P joints, ``links`` the links placed (the
    ground first), ``dyads`` the group indices of the dyads in order.
    """

    def __init__(self, prog, points, slides, links, dyads, rows, anchors, inputs):
        self.prog = prog
        self.points = points
        self.slides = slides
        self.links = links
        self.dyads = dyads
        self.rows = np.array(rows, dtype=np.int64).reshape(len(rows), WIDTH)
        self.anchors = np.array(anchors, dtype=np.int64)
        self.inputs = inputs
        self._scratch = None
        dyad = self.rows[self.rows[:, 0] >= RRR]
        self.signed = [int(r[0]) in (RRR, RPR, RRP) for r in dyad]
        placed = {int(r[6]) for r in self.rows if r[0] == DRIVER_P}
        placed |= {int(r[9]) for r in dyad if r[0] in (RPR, RRP)}
        placed |= {int(x) for r in dyad if r[0] in (PRP, RPP) for x in (r[9], r[10])}
        self.placed = sorted(placed)

    @classmethod
    def of(cls, prog) -> "Tape | None":
        """The tape of ``prog``, or None when a step is not a driver or a dyad (gear, cam or Newton groups)."""
        cached = getattr(prog, "_tape", False)
        if cached is not False:
            return cached
        tape = cls._build(prog)
        prog._tape = tape
        return tape

    @classmethod
    def _build(cls, prog):
        mech = prog.mech
        if any(kind not in ("driver", "dyad") for kind, *_ in prog.steps) or prog.reads:
            return None
        points = [j.name for j in mech.joints] + [p.name for p in mech.points]
        points += [f"origin:{j.name}" for j in mech.joints if j.kind == "P"]
        pidx = {n: k for k, n in enumerate(points)}
        slides = [j.name for j in mech.joints if j.kind == "P"]
        sidx = {n: k for k, n in enumerate(slides)}
        links = [mech.ground]
        anchors = [-1]
        inputs = list(prog.inputs)
        rows, dyads = [], []

        def link(name, anchor):
            links.append(name)
            anchors.append(pidx[anchor])
            return len(links) - 1

        lidx = {mech.ground: 0}
        for kind, g, *rest in prog.steps:
            if kind == "driver":
                j, name, known = rest
                k = inputs.index(j.name)
                if j.kind == "R":
                    a, b = j.links
                    if mech.ground in (a, b):
                        b = b if a == mech.ground else a
                    row = [DRIVER_R, 0, lidx[known], pidx[j.name], k, 1 if name == b else -1, 0]
                else:
                    row = [DRIVER_P, 0, lidx[known], pidx[j.name], k, 1 if j.links[0] == known else -1, sidx[j.name]]
                lidx[name] = row[1] = link(name, j.name)
                rows.append(row + [0] * (WIDTH - len(row)))
                continue
            plan, ka, kc = rest
            a, b, c = plan.a, plan.b, plan.c
            d = len(dyads)
            dyads.append(g.index)
            l1 = lidx[plan.l1] = link(plan.l1, a.name)
            l2 = lidx[plan.l2] = link(plan.l2, c.name)
            row = [KINDS[plan.kind], d, l1, l2, lidx[ka], lidx[kc], pidx[a.name], pidx[b.name], pidx[c.name]]
            if plan.kind == "RPR":
                row += [sidx[b.name], 1 if b.links[0] == plan.l1 else -1, 0, 0]
            elif plan.kind == "RRP":
                row += [sidx[c.name], 0, 1 if c.links[0] == kc else -1, 0]
            elif plan.kind == "PRP":
                row += [sidx[a.name], sidx[c.name], 1 if a.links[0] == ka else -1, 1 if c.links[0] == kc else -1]
            elif plan.kind == "RPP":
                row += [sidx[b.name], sidx[c.name], 1 if b.links[0] == plan.l1 else -1, 1 if c.links[0] == kc else -1]
            else:
                row += [0, 0, 0, 0]
            rows.append(row)
        return cls(prog, points, slides, links, dyads, rows, anchors, inputs)

    def tables(self, geom, others=None, signs=None) -> tuple:
        """The constant tables the compiled loops read, one row per mechanism of ``geom``: the points ``G``, the
        slides' directions ``U`` and drawn values ``S0``, the inputs' ``drawn`` and ``fixed`` values (``others``
        for the inputs not swept, else the drawn ones) and the dyads' assembly ``sign`` (``signs``, else the
        drawn ones)."""
        mg = geom.count if geom.count is not None else 1

        def table(values, fill, dtype):
            out = np.empty((mg, len(values)), dtype=dtype)
            for k, v in enumerate(values):
                out[:, k] = np.broadcast_to(np.asarray(v if v is not None else fill, dtype=dtype).reshape(-1), (mg,))
            return out

        return (table([geom.at[p] for p in self.points], 0j, complex),
                table([geom.direction[s] for s in self.slides], 1 + 0j, complex),
                table([geom.s0[s] for s in self.slides], 0.0, float),
                table([geom.drawn[j] for j in self.inputs], 0.0, float),
                table([(others or {}).get(j, geom.drawn[j]) for j in self.inputs], 0.0, float),
                table([(signs or {}).get(i, geom.sign.get(i, 1.0)) for i in self.dyads], 1.0, float))

    def poses(self, geom, q, joint, others, signs, shape):
        """The :class:`~domes.motion.planar.kernel.Poses` of :meth:`Program.poses` by the compiled loop.

        ``q`` is one row of inputs (``(N,)`` or ``(1, N)``); ``shape`` the
        broadcast shape the numpy route gives (``(N,)``, or ``(M, N)`` for a batch).
        """
        from domes.motion.planar.kernel import Poses

        prog = self.prog
        mg = geom.count if geom.count is not None else 1
        qs = np.ascontiguousarray(np.asarray(q, dtype=float).reshape(-1))
        n = qs.size

        G, U, S0, drawn, fixed, sign = self.tables(geom, others, signs)
        nl, nd, ns = len(self.links), len(self.dyads), len(self.slides)
        key = (nl, nd, ns, mg, n)
        if getattr(prog, "scratch", False) and self._scratch and self._scratch[0] == key:
            R, W, S, F, B = self._scratch[1]  # a batch's next chunk: its arrays are free again (no fresh pages)
        else:
            R = np.empty((nl, mg, n), dtype=complex)
            W = np.empty((nl, mg, n), dtype=complex)
            S = np.empty((ns, mg, n))
            F = np.empty((3, nd, mg, n))
            B = np.empty((2, nd, mg, n), dtype=np.bool_)
            if getattr(prog, "scratch", False):
                self._scratch = (key, (R, W, S, F, B))
        R[0], W[0] = 1.0, 0.0
        _kernel()(self.rows, self.anchors, G, U, S0, drawn, fixed, qs, self.inputs.index(joint), sign, R, W, S, F, B,
                  True)

        def shaped(a):
            return a.reshape(shape)

        inputs = {j: (q if j == joint else (others or {}).get(j, geom.drawn[j])) for j in self.inputs}
        pose = Poses({prog.ground: (1.0 + 0j, 0j, 0j)}, {}, inputs, shape)
        pose.raw = (G, R, W, S, F, B)
        variables = prog.kin.structure.input_vars
        pose.values = {variables[j]: np.asarray(v, dtype=float) for j, v in inputs.items()}
        for k, name in enumerate(self.links[1:], 1):
            pose.links[name] = (shaped(R[k]), shaped(W[k]), geom.at[self.points[self.anchors[k]]])
        for k in self.placed:
            pose.slides[self.slides[k]] = shaped(S[k])
        for k, index in enumerate(self.dyads):
            pose.unassembled[index] = shaped(B[0, k])
            pose.undetermined[index] = shaped(B[1, k])
            pose.closure[index] = shaped(F[2, k])
            if self.signed[k]:
                pose.root[index] = shaped(F[0, k])
                pose.margin[index] = shaped(F[1, k])
        return pose


    def finish(self, pose, outputs, ambiguous, size):
        """A batch chunk's ``(values, assembled, kinds, transmission, residual)`` from a compiled pose, as
        :func:`~domes.motion.planar.batch._evaluate` makes them; None when an output is not a point or a slide
        (angles are unwrapped by numpy there). ``kinds`` are codes: 0 complete, 1 limit, 2 undetermined, 3
        ambiguous."""
        G, R, W, S, F, B = pose.raw
        lidx = {name: k for k, name in enumerate(self.links)}
        pidx = {name: k for k, name in enumerate(self.points)}
        spec = []
        for o in outputs:
            if o.kind == "point":
                link = self.prog.mech.point(o.target)[0]
                if link not in lidx:
                    return None
                spec.append((0, lidx[link], pidx[o.target]))
            elif o.kind == "slide" and o.target in self.slides and self.slides.index(o.target) in self.placed:
                spec.append((1, self.slides.index(o.target), 0))
            else:
                return None
        spec = np.array(spec, dtype=np.int64).reshape(len(spec), 3)
        mg, n = R.shape[1], R.shape[2]
        columns = sum(2 if k == 0 else 1 for k, _, _ in spec)
        out = np.empty((columns, mg, n))
        ok = np.empty((mg, n), dtype=np.bool_)
        kinds = np.empty(mg, dtype=np.int64)
        transmission = np.empty(mg)
        residual = np.empty(mg)
        signed = np.array(self.signed, dtype=np.bool_)
        anchors = self.anchors
        _finisher()(spec, anchors, G, R, W, S, F, B, signed, np.broadcast_to(ambiguous, (mg,)).astype(np.bool_),
                    np.broadcast_to(size, (mg,)).astype(float), out, ok, kinds, transmission, residual)
        values, k = {}, 0
        for o in outputs:
            for name in o.columns():
                values[name] = out[k]
                k += 1
        return values, ok, kinds, transmission, residual


_COMPILED = None
_FINISH = None
_EXTREMES = None


def _jit(fn):
    """``fn`` compiled, cached on disk: next to this file (``__pycache__``) or, where that is read-only, in the
    user's cache folder (numba's own fallback; ``NUMBA_CACHE_DIR`` chooses another); in memory only if no folder
    is writable."""
    import numba

    try:
        return numba.njit(cache=True, error_model="numpy", nogil=True)(fn)
    except RuntimeError:  # numba: "cannot cache function ...: no locator available"
        return numba.njit(error_model="numpy", nogil=True)(fn)


def _kernel():
    """The compiled loop (numba imported and the loop compiled, or loaded from its cache, on first use)."""
    global _COMPILED, _quotient, _unit, _placed
    if _COMPILED is None:
        _quotient, _unit = _jit(_quotient), _jit(_unit)
        _placed = _jit(_placed)
        _COMPILED = _jit(_run)
    return _COMPILED


def _quotient(z, w):
    """``z / w`` as numpy divides complex numbers (Smith's method, scaled by a reciprocal), so that both routes
    round alike."""
    if abs(w.real) >= abs(w.imag):
        rat = w.imag / w.real
        scl = 1.0 / (w.real + w.imag * rat)
        return complex((z.real + z.imag * rat) * scl, (z.imag - z.real * rat) * scl)
    rat = w.real / w.imag
    scl = 1.0 / (w.imag + w.real * rat)
    return complex((z.real * rat + z.imag) * scl, (z.imag * rat - z.real) * scl)


def _unit(z):
    """``z / |z|`` for ``|z|`` near 1 (a link's turn from its drawn pose, found as a quotient of two vectors of its
    length): one Newton step of ``1/√m`` from 1, ``z·(3 − m)/2``, within an ulp or two of the quotient while
    ``|m − 1| ≤ 1e-8`` (its error is ``3(m − 1)²/8``); else by the square root."""
    m = z.real * z.real + z.imag * z.imag
    if abs(m - 1.0) <= 1e-8:
        f = 1.5 - 0.5 * m
    else:
        f = 1.0 / np.sqrt(m)
    return complex(z.real * f, z.imag * f)


def _finisher():
    global _FINISH
    if _FINISH is None:
        _FINISH = _jit(_finish)
    return _FINISH


def warm() -> None:
    """Load (or compile) every compiled loop now, on empty arrays: a batch does so before it measures the memory
    of its first chunk, which numba's own allocations would otherwise swell."""
    c, f, one = np.zeros((1, 1), dtype=complex), np.zeros((1, 1)), np.zeros(1, dtype=np.int64)
    _kernel()(np.zeros((0, WIDTH), dtype=np.int64), one, c, c, f, f, f, np.zeros(0), 0, f,
              np.zeros((1, 1, 0), dtype=complex), np.zeros((1, 1, 0), dtype=complex), np.zeros((0, 1, 0)),
              np.zeros((3, 0, 1, 0)), np.zeros((2, 0, 1, 0), dtype=np.bool_), True)
    _finisher()(np.zeros((0, 3), dtype=np.int64), one, c, np.zeros((1, 0, 0), dtype=complex),
                np.zeros((1, 0, 0), dtype=complex), np.zeros((0, 0, 0)), np.zeros((3, 0, 0, 0)),
                np.zeros((2, 0, 0, 0), dtype=np.bool_), np.zeros(0, dtype=np.bool_), np.zeros(0, dtype=np.bool_),
                np.zeros(0), np.zeros((0, 0, 0)), np.zeros((0, 0), dtype=np.bool_), np.zeros(0, dtype=np.int64),
                np.zeros(0), np.zeros(0))
    extremes(np.zeros((0, 1)), 0, np.zeros(1), np.zeros(1), one.copy(), one.copy())


def loaded() -> bool:
    """Whether the compiled loop is loaded in this process."""
    return _COMPILED is not None


def extremes(values, lo, minimum, maximum, argmin, argmax) -> None:
    """Each row's smallest and largest value and their first indices (NaN and −1 for a row of NaN), into
    ``minimum[lo:hi]`` and the others: :class:`~domes.motion.planar.batch.ExtremesSink`'s reduction, compiled."""
    global _EXTREMES
    if _EXTREMES is None:
        _EXTREMES = _jit(_extremes)
    _EXTREMES(np.ascontiguousarray(values), lo, minimum, maximum, argmin, argmax)


def _extremes(values, lo, minimum, maximum, argmin, argmax):  # pragma: no cover - compiled
    for m in range(values.shape[0]):
        row = values[m]
        kmin = kmax = -1
        vmin = vmax = np.nan
        for i in range(row.size):
            x = row[i]
            if np.isnan(x):
                continue
            if kmin < 0 or x < vmin:
                kmin, vmin = i, x
            if kmax < 0 or x > vmax:
                kmax, vmax = i, x
        minimum[lo + m], maximum[lo + m], argmin[lo + m], argmax[lo + m] = vmin, vmax, kmin, kmax


def _finish(spec, anchors, G, R, W, S, F, B, signed, ambiguous, size, out, ok, kinds, transmission,
            residual):  # pragma: no cover - compiled
    nd, mg, n = F.shape[1], R.shape[1], R.shape[2]
    for m in range(mg):
        limit = undetermined = False
        worst = np.inf
        closure = 0.0
        for i in range(n):
            good = not ambiguous[m]
            for d in range(nd):
                if B[0, d, m, i]:
                    limit = True
                    good = False
                if B[1, d, m, i]:
                    undetermined = True
                    good = False
            ok[m, i] = good
            if good:
                for d in range(nd):
                    if signed[d] and F[0, d, m, i] < worst:
                        worst = F[0, d, m, i]
                    if F[2, d, m, i] > closure:
                        closure = F[2, d, m, i]
            k = 0
            for j in range(spec.shape[0]):
                if spec[j, 0] == 0:
                    link = spec[j, 1]
                    P = G[m, anchors[link]] if anchors[link] >= 0 else 0j
                    X = W[link, m, i] + R[link, m, i] * (G[m, spec[j, 2]] - P)
                    out[k, m, i] = X.real if good else np.nan
                    out[k + 1, m, i] = X.imag if good else np.nan
                    k += 2
                else:
                    out[k, m, i] = S[spec[j, 1], m, i] if good else np.nan
                    k += 1
        kinds[m] = 3 if ambiguous[m] else 2 if undetermined else 1 if limit else 0
        transmission[m] = worst if np.isfinite(worst) else np.nan
        residual[m] = closure / size[m]


def run(rows, anchors, G, U, S0, drawn, fixed, qs, swept, sign, R, W, S, F, B, closures=True):
    """Fill ``R, W`` (link rotations and anchors' places), ``S`` (slides), ``F`` (the dyads' roots, margins and,
    with ``closures``, closures) and ``B`` (their unassembled and undetermined masks) for every mechanism and input
    (compiled)."""
    _kernel()(rows, anchors, G, U, S0, drawn, fixed, qs, swept, sign, R, W, S, F, B, closures)


def _run(rows, anchors, G, U, S0, drawn, fixed, qs, swept, sign, R, W, S, F, B, closures):  # pragma: no cover - compiled
    turns = np.empty(qs.size, dtype=np.complex128)
    for i in range(qs.size):
        turns[i] = complex(np.cos(qs[i]), np.sin(qs[i]))
    _placed(rows, anchors, G, U, S0, drawn, fixed, qs, turns, swept, sign, R, W, S, F, B, closures)


def _placed(rows, anchors, G, U, S0, drawn, fixed, qs, turns, swept, sign, R, W, S, F, B,
            closures):  # pragma: no cover - compiled
    """:func:`_run` with the swept input's turns ``e^{iq}`` given."""
    slack = 1e-14 * 64
    n = qs.size
    ends = np.empty((2, n), dtype=np.complex128)  # an RRR dyad's A and C, |C − A| and root: its loop in short passes
    reach = np.empty((2, n))
    for m in range(G.shape[0]):
        g = G[m]
        for r in range(rows.shape[0]):
            op = rows[r, 0]
            if op == DRIVER_R or op == DRIVER_P:
                link, known, pj, k = rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4]
                Rk, Wk = R[known, m], W[known, m]
                Rn, Wn = R[link, m], W[link, m]
                arm = g[pj] - (g[anchors[known]] if anchors[known] >= 0 else 0j)
                back = complex(np.cos(drawn[m, k]), -np.sin(drawn[m, k]))
                x0 = fixed[m, k]
                fixed_turn = complex(np.cos(x0), np.sin(x0)) * back
                if op == DRIVER_R:
                    forward = rows[r, 5] > 0
                    for i in range(n):
                        turn = turns[i] * back if k == swept else fixed_turn
                        Rn[i] = Rk[i] * (turn if forward else turn.conjugate())
                        Wn[i] = Wk[i] + Rk[i] * arm
                else:
                    s = rows[r, 6]
                    along = rows[r, 5] * U[m, s]
                    for i in range(n):
                        x = qs[i] if k == swept else x0
                        S[s, m, i] = x
                        Rn[i] = Rk[i]
                        Wn[i] = Wk[i] + Rk[i] * arm + (x - S0[m, s]) * Rk[i] * along
                continue
            d, l1, l2, ka, kc = rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4], rows[r, 5]
            a, b, c = g[rows[r, 6]], g[rows[r, 7]], g[rows[r, 8]]
            arm_a = a - (g[anchors[ka]] if anchors[ka] >= 0 else 0j)
            arm_c = c - (g[anchors[kc]] if anchors[kc] >= 0 else 0j)
            Ra, Wa, Rc, Wc = R[ka, m], W[ka, m], R[kc, m], W[kc, m]
            R1, W1, R2, W2 = R[l1, m], W[l1, m], R[l2, m], W[l2, m]
            root, margin, closure = F[0, d, m], F[1, d, m], F[2, d, m]
            bad, und = B[0, d, m], B[1, d, m]
            sg = sign[m, d]
            if op == RRR:
                ba, bc = b - a, b - c
                l1n, l2n = abs(ba), abs(bc)
                lo, hi = abs(l1n - l2n), l1n + l2n
                ia, ic = ba.conjugate() * (1.0 / (l1n * l1n)), bc.conjugate() * (1.0 / (l2n * l2n))
                over = 1.0 / (2 * l1n * l2n)
                As, Cs, dds, rps = ends[0], ends[1], reach[0], reach[1]
                for i in range(n):  # short passes: many inputs' square roots in flight at once (twice as fast)
                    A = Wa[i] + Ra[i] * arm_a
                    C = Wc[i] + Rc[i] * arm_c
                    D = C - A
                    As[i], Cs[i] = A, C
                    dds[i] = np.sqrt(D.real * D.real + D.imag * D.imag)
                for i in range(n):
                    dd = dds[i]
                    prod = max((l1n + dd + l2n) * (l1n + dd - l2n) * (l1n - dd + l2n) * (-l1n + dd + l2n), 0.0)
                    rps[i] = np.sqrt(prod)
                for i in range(n):
                    A, C, dd, rp = As[i], Cs[i], dds[i], rps[i]
                    D = C - A
                    dd2 = D.real * D.real + D.imag * D.imag
                    margin[i] = min(hi - dd, dd - lo)
                    near = dd - hi if dd > hi else lo - dd
                    bad[i] = (dd > hi or dd < lo) and near > slack * max(max(dd, l1n), l2n)
                    und[i] = dd == 0.0 and not bad[i]
                    Bp = A + D * complex(l1n * l1n + dd2 - l2n * l2n, sg * rp) * (0.5 / dd2)
                    root[i] = rp * over
                    u1 = _unit((Bp - A) * ia)
                    u2 = _unit((Bp - C) * ic)
                    R1[i], W1[i], R2[i], W2[i] = u1, A, u2, C
                    e = C + u2 * bc - Bp
                    if closures:
                        closure[i] = np.sqrt(e.real * e.real + e.imag * e.imag)
            elif op == RPR:
                s = rows[r, 9]
                first = rows[r, 10] > 0
                gp, sp = (a, c) if first else (c, a)
                u0 = U[m, s]
                rel0 = sp - gp
                e = u0.real * rel0.imag - u0.imag * rel0.real
                t0 = u0.real * rel0.real + u0.imag * rel0.imag
                ae = abs(e)
                for i in range(n):
                    A = Wa[i] + Ra[i] * arm_a
                    C = Wc[i] + Rc[i] * arm_c
                    Gp, Sp = (A, C) if first else (C, A)
                    D = Sp - Gp
                    rr = abs(D)
                    diff = (rr - ae) * (rr + ae)
                    margin[i] = rr - ae
                    bad[i] = diff < -slack * rr * rr
                    und[i] = rr == 0.0 and not bad[i]
                    t = sg * np.sqrt(max(diff, 0.0))
                    z = _quotient(D, complex(t, e) * u0)
                    root[i] = abs(t) / rr
                    Rr = _unit(z)
                    S[s, m, i] = S0[m, s] + t - t0
                    R1[i], W1[i], R2[i], W2[i] = Rr, A, Rr, C
                    slid = Gp + Rr * (b - gp) + (t - t0) * Rr * u0
                    if closures:
                        closure[i] = abs(Sp + Rr * (b - sp) - slid)
            elif op == RRP:
                s = rows[r, 9]
                l1n = abs(b - a)
                for i in range(n):
                    A = Wa[i] + Ra[i] * arm_a
                    C = Wc[i] + Rc[i] * arm_c
                    Rk = Rc[i]
                    u = Rk * U[m, s]
                    p0 = C + Rk * (b - c)
                    w = p0 - A
                    h = abs(u.real * w.imag - u.imag * w.real)
                    diff = (l1n - h) * (l1n + h)
                    margin[i] = l1n - h
                    bad[i] = diff < -slack * max(l1n, h) ** 2
                    und[i] = False
                    rp = np.sqrt(max(diff, 0.0))
                    tau = -(u.real * w.real + u.imag * w.imag) + sg * rp
                    Bp = p0 + tau * u
                    root[i] = rp / l1n
                    u1 = _unit(_quotient(Bp - A, b - a))
                    S[s, m, i] = S0[m, s] + rows[r, 11] * tau
                    R1[i], W1[i], R2[i], W2[i] = u1, A, Rk, C + tau * u
                    if closures:
                        closure[i] = abs(A + u1 * (b - a) - Bp)
            elif op == PRP:
                sa, sc = rows[r, 9], rows[r, 10]
                for i in range(n):
                    A = Wa[i] + Ra[i] * arm_a
                    C = Wc[i] + Rc[i] * arm_c
                    p1, u1 = A + Ra[i] * (b - a), Ra[i] * U[m, sa]
                    p2, u2 = C + Rc[i] * (b - c), Rc[i] * U[m, sc]
                    det = -(u1.real * u2.imag - u1.imag * u2.real)
                    flat = abs(det) <= 1e-15
                    safe = 1.0 if flat else det
                    rhs = p2 - p1
                    t1 = (rhs.real * -u2.imag - rhs.imag * -u2.real) / safe
                    t2 = (u1.real * rhs.imag - u1.imag * rhs.real) / safe
                    S[sa, m, i] = S0[m, sa] + rows[r, 11] * t1
                    S[sc, m, i] = S0[m, sc] + rows[r, 12] * t2
                    R1[i], W1[i], R2[i], W2[i] = Ra[i], A + t1 * u1, Rc[i], C + t2 * u2
                    if closures:
                        closure[i] = abs(p1 + t1 * u1 - p2 - t2 * u2)
                    root[i], margin[i], bad[i], und[i] = np.nan, np.nan, False, flat
            else:  # RPP
                sb, sc = rows[r, 9], rows[r, 10]
                for i in range(n):
                    A = Wa[i] + Ra[i] * arm_a
                    C = Wc[i] + Rc[i] * arm_c
                    Rk = Rc[i]
                    X1 = A + Rk * (b - a)
                    u_in, u_out = Rk * U[m, sb], Rk * U[m, sc]
                    rhs = Rk * (b - c) + C - X1
                    det = -(u_in.real * u_out.imag - u_in.imag * u_out.real)
                    flat = abs(det) <= 1e-15
                    safe = 1.0 if flat else det
                    t_in = (rhs.real * -u_out.imag - rhs.imag * -u_out.real) / safe
                    t_out = (u_in.real * rhs.imag - u_in.imag * rhs.real) / safe
                    S[sb, m, i] = S0[m, sb] + rows[r, 11] * t_in
                    S[sc, m, i] = S0[m, sc] + rows[r, 12] * t_out
                    R1[i], W1[i], R2[i], W2[i] = Rk, A, Rk, C + t_out * u_out
                    if closures:
                        closure[i] = abs(X1 + t_in * u_in - (C + Rk * (b - c) + t_out * u_out))
                    root[i], margin[i], bad[i], und[i] = np.nan, np.nan, False, flat
