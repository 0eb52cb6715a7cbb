"""A sweep of drivers and dyads in one compiled pass: positions, continuous angles, rates, outputs (numba).

:func:`~domes.motion.planar.sweep.run_sweep` walks a query of drivers and
dyads on arrays (:mod:`~domes.motion.planar.branches`), each stage a numpy
pass. On the compiled route (:func:`~domes.motion.planar.compiled.choose`)
the sweep is first tried here, in one compiled loop over chunks of the
walk's points (each chunk's placements stay in the cache; the sweep's memory
is its results): the placements (the loop of
:func:`~domes.motion.planar.compiled.run`), the continuous angles (numpy's
``unwrap``), the jump and branch-point tests, and the loop equations of
every dyad (the segment sums of
:func:`~domes.motion.planar.structure.evaluate`, ``A = Σ w`` with ``w`` a
segment's length times its unit, or its slide times its unit) for residuals
and condition numbers, and their time derivatives in complex form
(``Ȧ = Σ iwΔ̇``, ``Ä = Σ (iwΔ̈ − wΔ̇²)`` and the slides' terms), the two
unknowns' rates set to zero giving the rest of the loop's and the 2×2
Jacobian solving for them, then the outputs. The loops read a
*program* of integer and float rows made once per query and kept on it
(:meth:`Pass.of`), with work arrays kept for the next sweep of the same size.

Wherever a decision is to be made (a configuration that does not assemble,
would jump, or is undetermined; a dyad's root dipping towards zero, where
a branch point may be; a condition number that refuses derivatives) the
pass gives up and :func:`sweep` returns None: the numpy walk then takes the
whole sweep and makes the decision, so both routes report the same dead
points and branch points, and elsewhere the same numbers to 1e-14 of their
scale (``tests/motion/test_compiled.py``).

>>> from domes.motion.planar.examples import four_bar
>>> from domes.motion.planar.query import Kinematics
>>> prog = Pass.of(Kinematics(four_bar(), outputs=["point:C"], order=2), "A", {"A": 0.0})
>>> prog.columns[:3], prog.names
(['point:C.x', 'point:C.y', "point:C.x'"], ['q:A', 'rot:coupler', 'rot:rocker'])
"""

from __future__ import annotations

import math

import numpy as np

from domes.motion.planar import compiled
from domes.motion.planar.arrays import Compiled
from domes.motion.planar.branches import ROOT_FLOOR
from domes.motion.planar.query import EPS, JUMP, SINGULAR_CONDITION
from domes.results import Status, Ticker

__all__ = ["Pass", "sweep"]

#: Verdicts of the compiled pass.
DONE, FAILED, NEAR_BRANCH = 0, 1, 2
#: Walks of at most this many points keep their work arrays for the next sweep.
SPARE = 1 << 17
#: Configurations per block of the pass's loop equations and outputs (their rows stay in the cache).
BLOCK = 256
#: Walked points placed at a time (their placements stay in the cache: about 0.2 MB for a six-bar).
CHUNK = 1024
#: A link's angle within this tangent of its last one found by ``atan`` is that one's plus the series of the turn
#: from it (:func:`_small_atan`: 3 units in the last place at most, 40% less time than ``atan``); an input within
#: this angle of the last one turned by ``cos`` and ``sin`` is turned from that one by a series
#: (:func:`_small_turn`).
NEAR = 0.05
#: Row kinds of the outputs.
ANGLE, SLIDE, POINT = 0, 1, 2


class Pass:
    """The compiled program of one query's sweep of ``joint`` with the other inputs at ``fixed``."""

    def __init__(self, kin, joint, fixed, tape):
        s = kin.structure
        self.kin, self.joint, self.tape = kin, joint, tape
        groups = [g for g in kin.groups if g.unknowns]
        names = list(s.drawn) + list(s.input_vars.values())
        for g in groups:
            names += g.unknowns
        exprs, segs = [], []

        def expr(rot):
            for v, _ in rot.terms:
                names.append(v)
            exprs.append(rot)
            return len(exprs) - 1

        def segments(seq):
            lo = len(segs)
            for seg in seq:
                segs.append((seg, expr(seg.rotation)))
                if seg.kind != "link":
                    names.append(seg.slide)
            return lo, len(segs)

        values, jumps, grows = [], [], []
        links = {name: k for k, name in enumerate(tape.links)}
        for g in groups:
            for link in g.links:
                rot = s.rotations[link]
                var, coeff = next(((v, c) for v, c in rot.terms if v in g.unknowns), (None, 0.0))
                if var is None:
                    continue
                rest = type(rot)(tuple((v, c) for v, c in rot.terms if v != var), rot.const)
                values.append(((0, var, links[link], expr(rest)), coeff))
            for v in g.unknowns:
                if v.startswith("s:"):
                    values.append(((1, v, tape.slides.index(v[2:]), 0), 1.0))
                jumps.append((v, 1.0 if v.startswith("rot:") else kin.size))
            (loop,) = g.loops
            grows.append((*segments(loop), g.unknowns))
        outs, columns = [], []
        for o in kin.outputs:
            if o.kind == "angle":
                ref = 0.0 if o.target == kin.mech.ground else kin.mech.reference_angle(o.target)
                outs.append(((ANGLE, expr(s.rotations[o.target]), 0), ref))
            elif o.kind == "slide":
                v = s.input_vars.get(o.target, f"s:{o.target}")
                names.append(v)
                outs.append(((SLIDE, v, 0), 0.0))
            else:
                outs.append(((POINT, *segments(kin._output_paths[o.target])), 0.0))
            for k in range(kin.order + 1):
                columns += [name + "'" * k for name in o.columns()]
        self.names = list(dict.fromkeys(names))
        self.states = list(dict.fromkeys(list(s.drawn) + list(s.input_vars.values())
                                         + [v for g in groups for v in g.unknowns]))
        vi = self.index = {v: k for k, v in enumerate(self.names)}
        self.columns = columns
        ptr, var, coef, const = [0], [], [], []
        for rot in exprs:
            var += [vi[v] for v, _ in rot.terms]
            coef += [c for _, c in rot.terms]
            ptr.append(len(var))
            const.append(rot.const)
        self.ex_ptr, self.ex_var = np.array(ptr, dtype=np.int64), np.array(var, dtype=np.int64)
        self.ex_c, self.ex_const = np.array(coef, dtype=float), np.array(const, dtype=float)
        self.seg_i = np.array([(0 if seg.kind == "link" else 1, e, vi.get(seg.slide, -1)) for seg, e in segs],
                              dtype=np.int64).reshape(len(segs), 3)
        self.seg_f = np.array([(seg.length, seg.alpha, seg.s0, seg.sign) for seg, _ in segs],
                              dtype=float).reshape(len(segs), 4)
        # each segment turns with a placed link: its unit u(Δ + α) is that link's rotation times u(α), no sine
        turning = {}
        for k, name in enumerate(tape.links):
            turning.setdefault(s.rotations[name], k)
        self.seg_link = np.array([turning.get(seg.rotation, -1) for seg, _ in segs], dtype=np.int64)
        self.seg_u = np.array([complex(math.cos(seg.alpha), math.sin(seg.alpha)) for seg, _ in segs], dtype=complex)
        self.groups = np.array([(lo, hi, vi[u[0]], vi[u[1]]) for lo, hi, u in grows], dtype=np.int64).reshape(-1, 4)
        # ∂Δ/∂v of each loop segment for its group's unknowns v, and the slide's sign where v is the segment's slide
        self.seg_du = np.zeros((len(segs), 4))
        for lo, hi, u in grows:
            for t in range(lo, hi):
                seg, e = segs[t]
                for c, v in enumerate(u):
                    self.seg_du[t, c] = sum(k for w, k in exprs[e].terms if w == v)
                    self.seg_du[t, 2 + c] = seg.sign if seg.kind != "link" and seg.slide == v else 0.0
        self.complete = all(np.any(self.seg_du[lo:hi, [c, 2 + c]]) for lo, hi, _ in grows for c in range(2))
        self.gscale = np.array([[1.0 / kin.size if v.startswith("rot:") else 1.0 for v in u] for *_, u in grows],
                               dtype=float).reshape(-1, 2)
        self.values_i = np.array([(kind, vi[v], at, e) for (kind, v, at, e), _ in values],
                                 dtype=np.int64).reshape(-1, 4)
        self.values_f = np.array([c for _, c in values], dtype=float)
        self.jump_v = np.array([vi[v] for v, _ in jumps], dtype=np.int64)
        self.jump_s = np.array([x for _, x in jumps], dtype=float)
        self.outs_i = np.array([(kind, a if kind != SLIDE else vi[a], b) for (kind, a, b), _ in outs],
                               dtype=np.int64).reshape(-1, 3)
        self.outs_f = np.array([ref for _, ref in outs], dtype=float)
        self.signed = np.array([d for d, on in enumerate(tape.signed) if on], dtype=np.int64)
        rates, accels = np.zeros(len(self.names)), np.zeros(len(self.names))
        for j, v in s.input_vars.items():
            rates[vi[v]], accels[vi[v]] = kin.inputs[j].speed, kin.inputs[j].acceleration
        self.rates, self.accels = rates, accels
        self.swept = vi[s.input_vars[joint]]
        start = dict(s.drawn)
        for j, v in s.input_vars.items():
            start[v] = float(fixed[j])
        self.start = np.array([start.get(v, 0.0) for v in self.names], dtype=float)
        self._placements(fixed)
        self._spare: list = []
        self._walk = None

    def _placements(self, fixed):
        """The constant tables of :func:`~domes.motion.planar.compiled.run` for this mechanism
        (:meth:`~domes.motion.planar.compiled.Tape.tables`)."""
        others = {j: x for j, x in fixed.items() if j != self.joint}
        self.G, self.U, self.S0, self.drawn, self.fixed, self.sign = self.tape.tables(Compiled.of(self.kin).geometry,
                                                                                   others)
        self.k_swept = self.tape.inputs.index(self.joint)

    def borrow(self, n: int) -> tuple:
        """Work arrays for a walk of ``n`` points: a sweep's arrays again when the last sweep of this size has given
        them back (fresh pages cost more than the pass), else new ones."""
        while self._spare:
            try:
                size, work = self._spare.pop()
            except IndexError:  # another thread took it
                break
            if size == n:
                return work
        nl, nd, ns, nv = len(self.tape.links), len(self.tape.dyads), len(self.tape.slides), len(self.names)
        width, chunk = min(n, BLOCK), min(n, CHUNK)
        R, W = np.empty((nl, 1, chunk), dtype=complex), np.empty((nl, 1, chunk), dtype=complex)
        R[0], W[0] = 1.0, 0.0  # the ground (the placements never write it)
        return (R, W, np.empty((ns, 1, chunk)), np.empty((3, nd, 1, chunk)), np.empty((2, nd, 1, chunk), dtype=np.bool_),
                np.empty((self.signed.size, n)), np.empty((nv, width)), np.empty((nv, width)), np.empty((nv, width)),
                np.empty((4, self.seg_i.shape[0], width)), np.empty((10, width)))

    def give_back(self, work: tuple) -> None:
        """Keep ``work`` for the next sweep of the same size (one set, and only of a modest size)."""
        if work[5].shape[1] <= SPARE:
            self._spare[:] = [(work[5].shape[1], work)]

    def walk_points(self, qs, q0, h) -> tuple:
        """:func:`_walk_points`, kept for the next sweep of the same grid (the pass only reads them; a sweep's
        inputs are copied out)."""
        last = self._walk
        if last is not None and last[0] == (q0, h) and (last[1] is qs or np.array_equal(last[1], qs)):
            return last[2]
        points = _walk_points(qs, q0, h)
        self._walk = ((q0, h), qs if not qs.flags.writeable else qs.copy(), points)
        return points

    @classmethod
    def of(cls, kin, joint, fixed) -> "Pass | None":
        """The query's program for sweeping ``joint`` (other inputs at ``fixed``), made once and kept on the query;
        None when the query is not one of drivers and dyads only (Newton groups, gears, cams, derived variables)."""
        key = (joint, tuple(sorted(fixed.items())))
        cache = kin.__dict__.setdefault("_onepass", {})
        if key not in cache:
            cache[key] = cls._build(kin, joint, fixed)
        return cache[key]

    @classmethod
    def _build(cls, kin, joint, fixed):
        s = kin.structure
        if s.derived or any(g.index not in kin.plans or len(g.unknowns) != 2 or len(g.loops) != 1
                            for g in kin.groups if g.unknowns):
            return None
        tape = compiled.Tape.of(Compiled.of(kin).program)
        if tape is None:
            return None
        if any(o.kind == "slide" and s.input_vars.get(o.target, f"s:{o.target}") not in s.drawn for o in kin.outputs):
            return None
        prog = cls(kin, joint, fixed, tape)
        return prog if prog.complete else None  # a group whose loop misses one of its unknowns: the walk says why


def sweep(kin, cont, qs, progress=None):
    """The sweep of :func:`~domes.motion.planar.sweep.run_sweep` over the grid ``qs`` (an array) in one compiled
    pass, or None where a decision is to be made (the numpy walk then takes the sweep) or the query is not of
    drivers and dyads."""
    prog = Pass.of(kin, cont.joint, cont.fixed)
    if prog is None:
        return None
    qs = np.asarray(qs, dtype=float)
    xs, keep, lead, count = prog.walk_points(qs, cont.q0, cont.h)
    n, nk = xs.size, keep.size
    work = prog.borrow(n)
    tape = prog.tape
    X = np.empty((len(prog.names), n))
    out = np.empty((len(prog.columns), nk))
    rc = np.empty((2, nk))
    verdict, worst = _passer()(tape.rows, tape.anchors, prog.G, prog.U, prog.S0, prog.drawn, prog.fixed, prog.k_swept,
                               prog.sign, *work[:6], xs, keep, prog.start, prog.swept, prog.values_i, prog.values_f,
                               prog.ex_ptr, prog.ex_var, prog.ex_c, prog.ex_const, prog.jump_v, prog.jump_s, JUMP,
                               prog.signed, ROOT_FLOOR, prog.seg_i, prog.seg_f, prog.seg_link, prog.seg_u, prog.seg_du,
                               prog.groups, prog.gscale, prog.rates, prog.accels, kin.order, kin.size, prog.outs_i,
                               prog.outs_f, X, out, rc[0], rc[1], *work[6:])
    prog.give_back(work)
    if verdict != DONE or (kin.order and not _derivatives_known(worst, kin.order, kin.accuracy.derivatives)):
        return None
    pts = xs[lead:lead + count]
    if progress is not None:
        Ticker(progress).tick(lambda: f"step {count}/{count}: input {cont.fmt(pts[-1])}", force=True)
    if nk == count:  # every walked point is a grid point: the states are views
        X = X[:, lead:lead + nk]
        inputs = pts.copy()  # the walk's points are kept for the next sweep
    else:
        X = X[:, keep]
        inputs = xs[keep]
    index = prog.index
    states = {v: X[index[v]] for v in prog.states}
    table = dict(zip(prog.columns, out))
    ends = (float(inputs[0]), float(inputs[-1]))  # a sweep's grid is monotone
    return _results()(kin, cont, qs, inputs, table, rc[0], rc[1], states, [], Status.COMPLETE, [],
                   (min(ends), max(ends)))


def _derivatives_known(worst, order, tol) -> bool:
    """Whether no derivative is refused: the test of :func:`~domes.motion.planar.sweep._refuse`, which grows with the
    condition number (:func:`~domes.motion.planar.query.error_bounds`, here on one number), made at the largest
    (``worst``)."""
    return worst <= SINGULAR_CONDITION and (order < 1 or worst * worst * EPS <= tol) and \
        (order < 2 or worst * worst * worst * EPS <= tol)


def _fine_grid(qs, q_from, h):  # pragma: no cover - compiled
    """:func:`~domes.motion.planar.arrays.fine_grid` in one loop (the same operations, so the same points)."""
    n = qs.size
    pieces = np.empty(n, dtype=np.int64)
    total = 0
    for k in range(n):
        prev = q_from if k == 0 else qs[k - 1]
        span = qs[k] - prev
        p = np.int64(math.ceil(abs(span) / h - 1e-9))
        p = 0 if span == 0 else max(p, 1)
        if k == 0:
            p = max(p, 1)
        pieces[k] = p
        total += p
    pts = np.empty(total)
    marks = np.empty(n, dtype=np.int64)
    at = 0
    for k in range(n):
        prev = q_from if k == 0 else qs[k - 1]
        span = qs[k] - prev
        for j in range(1, pieces[k] + 1):
            pts[at] = prev + span * float(j) / float(pieces[k])
            at += 1
        marks[k] = at - 1
    return pts, marks


def _beyond(pts, qa, h) -> list:
    """The walk's point one step beyond the last of ``pts`` (walked from ``qa``), as
    :meth:`~domes.motion.planar.branches.Walker.walk` probes it, or none."""
    if not pts.size:
        return []
    prev = pts[-2] if pts.size > 1 else qa
    spacing = min(abs(pts[-1] - prev), h)
    return [pts[-1] + math.copysign(spacing, pts[-1] - prev)] if spacing > 0 else []


def _walk_points(qs, q0, h):
    """The points a sweep walks: the drawn input ``q0``, the walk from it to ``qs[0]`` and one step beyond, then the
    grid ``qs`` walked in pieces no longer than ``h`` and one step beyond (as ``sweep._reach`` and
    :meth:`~domes.motion.planar.branches.Walker.walk` take them). Returns the points, the indices of the grid's
    points among them, where the walked grid begins and how many points it has."""
    fine = _finer()
    reach, _ = fine(qs[:1], q0, h)
    pts, marks = fine(qs, qs[0], h)
    lead = [q0, *reach.tolist(), *_beyond(reach, q0, h)]
    xs = np.concatenate((lead, pts, _beyond(pts, qs[0], h)))
    return xs, marks + len(lead), len(lead), pts.size


_FINE = _RESULT = None


def _results():
    """:func:`~domes.motion.planar.sweep._result` (imported on first use: the sweep module imports this one)."""
    global _RESULT
    if _RESULT is None:
        from domes.motion.planar.sweep import _result

        _RESULT = _result
    return _RESULT


def _finer():
    global _FINE
    if _FINE is None:
        _FINE = compiled._jit(_fine_grid)
    return _FINE


_PASS = _place = None


def _passer():
    """The compiled pass (numba imported, the loop compiled or loaded from its cache, on first use)."""
    global _PASS, _linear, _angle, _small_atan, _small_turn, _block, _place, _accelerations
    if _PASS is None:
        _accelerations = compiled._jit(_accelerations)
        _linear, _angle, _small_atan = compiled._jit(_linear), compiled._jit(_angle), compiled._jit(_small_atan)
        _small_turn = compiled._jit(_small_turn)
        _block = compiled._jit(_block)
        # numba's cache of the pass follows this file only: a change of the placements' loop in compiled.py
        # reaches a cached pass once this file changes too (or the cache is cleared)
        compiled._kernel()
        _place = compiled._placed
        _PASS = compiled._jit(_pass)
    return _PASS


def _small_atan(t):  # pragma: no cover - compiled
    """``atan(t)`` for ``|t| ≤ NEAR`` by its series to ``t¹³`` (the next term is below 1e-19 of ``t``)."""
    t2 = t * t
    return t * (1.0 - t2 * (1.0 / 3 - t2 * (1.0 / 5 - t2 * (1.0 / 7 - t2 * (1.0 / 9 - t2 * (1.0 / 11
                                                                                          - t2 * (1.0 / 13)))))))


def _small_turn(d):  # pragma: no cover - compiled
    """``e^{id}`` for ``|d| ≤ NEAR`` by the series of cos and sin to ``d⁸`` and ``d⁹`` (the next terms are below
    1e-19)."""
    d2 = d * d
    c = 1.0 - d2 * (0.5 - d2 * (1.0 / 24 - d2 * (1.0 / 720 - d2 * (1.0 / 40320))))
    s = d * (1.0 - d2 * (1.0 / 6 - d2 * (1.0 / 120 - d2 * (1.0 / 5040 - d2 * (1.0 / 362880)))))
    return complex(c, s)


def _angle(z):  # pragma: no cover - compiled
    """``np.angle(z)`` to two units in the last place, by ``atan`` of the smaller part over the larger (half the time
    of ``atan2``); ±π by the sign of a zero imaginary part, as ``atan2``."""
    x, y = z.real, z.imag
    if abs(x) >= abs(y):
        if x == 0.0:
            return math.atan2(y, x)
        t = math.atan(y / x)
        if x < 0:
            t = t + math.pi if math.copysign(1.0, y) > 0 else t - math.pi
        return t
    return -math.atan(x / y) + (math.pi / 2 if y > 0 else -math.pi / 2)


def _linear(e, ex_ptr, ex_var, ex_c, v, nb, dst):  # pragma: no cover - compiled
    """``dst[k]``: the linear part of expression ``e`` at the values ``v[:, k]``, for the ``nb`` configurations of a
    block (their variables, or their rates)."""
    lo, hi = ex_ptr[e], ex_ptr[e + 1]
    if lo == hi:
        for k in range(nb):
            dst[k] = 0.0
        return
    c, row = ex_c[lo], v[ex_var[lo]]
    for k in range(nb):
        dst[k] = c * row[k]
    for p in range(lo + 1, hi):
        c, row = ex_c[p], v[ex_var[p]]
        for k in range(nb):
            dst[k] += c * row[k]


def _accelerations(t, nb, turning, seg_i, seg_f, ur, ui, wr, wi, dl, ddl, xd, xdd, sr,
                   si):  # pragma: no cover - compiled
    """Add segment ``t``'s part of ``Ä`` to ``sr + i·si``: ``iwΔ̈ − wΔ̇²`` where it ``turning`` (``dl, ddl``: its
    ``Δ̇, Δ̈``), and for a slide ``±(s̈u + 2iṡuΔ̇)``."""
    if turning:
        for j in range(nb):
            v2 = dl[j] * dl[j]
            sr[j] += -wi[j] * ddl[j] - wr[j] * v2
            si[j] += wr[j] * ddl[j] - wi[j] * v2
    if seg_i[t, 0] != 0:
        sg, sd, sdd = seg_f[t, 3], xd[seg_i[t, 2]], xdd[seg_i[t, 2]]
        for j in range(nb):
            v = dl[j] if turning else 0.0
            sr[j] += sg * (sdd[j] * ur[j] - 2 * sd[j] * v * ui[j])
            si[j] += sg * (sdd[j] * ui[j] + 2 * sd[j] * v * ur[j])


def _pass(rows, anchors, G, U, S0, drawn, fixed, k_swept, sign, R, W, S, F, B, roots, xs, keep, start, swept,
          values_i, values_f, ex_ptr, ex_var, ex_c, ex_const, jump_v, jump_s, jump, signed, floor, seg_i, seg_f,
          seg_link, seg_u, seg_du, groups, gscale, rates0, accels0, order, size, outs_i, outs_f, X, out, residuals,
          conditions, x, xd, xdd, blk_f, acc):  # pragma: no cover - compiled
    """The sweep's pass, a chunk of the walk's points at a time (the placements ``R, W, S, F, B`` of a chunk stay
    in the cache): placements, continuous angles and tests, then the loop equations and outputs of the kept
    configurations among them. Returns the verdict and the largest condition number."""
    n, nv, nk, chunk = xs.size, start.size, keep.size, R.shape[2]
    nvals, njump = values_i.shape[0], jump_v.size
    prev, fix, ta, za = np.empty(nvals), np.zeros(nvals), np.empty(nvals), np.empty(nvals, dtype=np.complex128)
    jprev = np.empty(njump)
    for r in range(nvals):
        prev[r] = start[values_i[r, 1]]
    for r in range(njump):
        jprev[r] = start[jump_v[r]]
    for v in range(nv):
        for j in range(x.shape[1]):
            xd[v, j] = rates0[v]
            xdd[v, j] = accels0[v]
    worst = 1.0
    k0 = 0
    turns = np.empty(chunk, dtype=np.complex128)
    q_anchor, e_anchor = xs[0], complex(math.cos(xs[0]), math.sin(xs[0]))
    for c0 in range(0, n, chunk):
        c1 = min(n, c0 + chunk)
        for i in range(c0, c1):
            # the input's turn: near the last one found by cos and sin (the anchor), the anchor's times the series
            # of the small turn from it; else by cos and sin, a new anchor
            d = xs[i] - q_anchor
            if abs(d) > NEAR:
                q_anchor, e_anchor = xs[i], complex(math.cos(xs[i]), math.sin(xs[i]))
                turns[i - c0] = e_anchor
            else:
                turns[i - c0] = e_anchor * _small_turn(d)
        _place(rows, anchors, G, U, S0, drawn, fixed, xs[c0:c1], turns, k_swept, sign, R, W, S, F, B, False)
        # the groups' variables, continuous from the drawn pose (numpy's unwrap)
        for v in range(nv):
            for i in range(c0, c1):
                X[v, i] = start[v]
        for i in range(c0, c1):
            X[swept, i] = xs[i]
        for r in range(nvals):
            kind, v, at, e = values_i[r, 0], values_i[r, 1], values_i[r, 2], values_i[r, 3]
            if kind == 1:
                for i in range(c0, c1):
                    X[v, i] = S[at, 0, i - c0]
                continue
            if c0 == 0:
                za[r] = R[at, 0, 0]
                ta[r] = _angle(za[r])
            p_r, f_r, z_a, t_a, inv = prev[r], fix[r], za[r], ta[r], 1.0 / values_f[r]
            for i in range(c0, c1):
                rest = 0.0
                for p in range(ex_ptr[e], ex_ptr[e + 1]):
                    rest += ex_c[p] * X[ex_var[p], i]
                rest += ex_const[e]
                # the link's angle: near the last one found by atan (the anchor), the anchor's plus the series of
                # the small turn from it; else by atan, a new anchor
                z = R[at, 0, i - c0]
                turn = z * z_a.conjugate()
                if turn.real > 0.0 and abs(turn.imag) <= NEAR * turn.real:
                    angle = t_a + _small_atan(turn.imag / turn.real)
                else:
                    z_a, t_a = z, _angle(z)
                    angle = t_a
                new = (angle - rest) * inv  # the reciprocal (±1 as a rule: exact)
                dd = new - p_r
                p_r = new
                if abs(dd) >= math.pi:  # numpy's unwrap: the step taken to (-π, π], less the step
                    ddmod = (dd + math.pi) % (2 * math.pi) - math.pi
                    if ddmod == -math.pi and dd > 0:
                        ddmod = math.pi
                    f_r += ddmod - dd
                X[v, i] = new + f_r
            prev[r], fix[r], za[r], ta[r] = p_r, f_r, z_a, t_a
        # a decision to make: a configuration that does not assemble, is undetermined or jumps; a root near zero
        for d in range(F.shape[1]):
            for i in range(c1 - c0):
                if B[0, d, 0, i] or B[1, d, 0, i]:
                    return FAILED, 0.0
        for r in range(njump):
            v, p_r = jump_v[r], jprev[r]
            for i in range(c0, c1):
                if not abs(X[v, i] - p_r) / jump_s[r] <= jump:
                    return FAILED, 0.0
                p_r = X[v, i]
            jprev[r] = p_r
        for t in range(signed.size):
            for i in range(c0, c1):
                root = F[0, signed[t], 0, i - c0]
                if not root > 2 * floor:
                    return NEAR_BRANCH, 0.0
                roots[t, i] = root
        k1 = k0
        while k1 < nk and keep[k1] < c1:
            k1 += 1
        if k1 > k0:
            worst = max(worst, _block(k0, k1, c0, R, X, keep, nv, ex_ptr, ex_var, ex_c, ex_const, seg_i, seg_f,
                                      seg_link, seg_u, seg_du, groups, gscale, order, size, outs_i, outs_f, out,
                                      residuals, conditions, x, xd, xdd, blk_f, acc))
        k0 = k1
    # a root dipping towards zero in a V between two steps: a branch point may be near
    for t in range(signed.size):
        root = roots[t]
        for i in range(1, n - 1):
            if root[i] <= root[i - 1] and root[i] <= root[i + 1]:
                d0, d1 = abs(xs[i] - xs[i - 1]), abs(xs[i + 1] - xs[i])
                slope = 0.0
                if d0 > 0:
                    slope = abs(root[i] - root[i - 1]) / d0
                if d1 > 0:
                    slope = max(slope, abs(root[i + 1] - root[i]) / d1)
                if root[i] <= 2 * (slope * max(d0, d1) + floor):
                    return NEAR_BRANCH, 0.0
    return DONE, worst


def _block(k0, k1, c0, R, X, keep, nv, ex_ptr, ex_var, ex_c, ex_const, seg_i, seg_f, seg_link, seg_u, seg_du, groups,
           gscale, order, size, outs_i, outs_f, out, residuals, conditions, x, xd, xdd, blk_f,
           acc):  # pragma: no cover - compiled
    """The loop equations and outputs at the kept configurations ``k0 .. k1`` (of the walk's points in the chunk from
    ``c0``, placed in ``R``), a block of them at a time; the largest condition number."""
    # on the kept configurations, a block at a time (its rows stay in the cache): each dyad's loop equations
    # A = Σ w (w = l·u for a link, ±(s − s₀)·u for a slide; u = e^{i(Δ + α)}) for residual and condition; their
    # rates Ȧ = Σ iwΔ̇ (+ ±ṡu) and Ä = Σ (iwΔ̈ − wΔ̇²) (+ ±s̈u + 2i·±ṡuΔ̇), the unknowns' rates at zero giving the rest
    # of the loop's, solved by the 2×2 Jacobian (its columns Σ iw·∂Δ/∂v (+ ±u)); then the outputs, as sums alike
    width, nseg = x.shape[1], seg_i.shape[0]
    ur, ui, wr, wi = blk_f[0], blk_f[1], blk_f[2], blk_f[3]
    ar, ai, c0r, c0i, c1r, c1i, kr, ki, dl, ddl = (acc[0], acc[1], acc[2], acc[3], acc[4], acc[5], acc[6], acc[7],
                                                   acc[8], acc[9])
    worst = 1.0
    for blk in range(k0, k1, width):
        nb = min(width, k1 - blk)
        base = keep[blk]
        together = keep[blk + nb - 1] - base == nb - 1  # the kept configurations in a row: no gather
        for v in range(nv):
            if together:
                for j in range(nb):
                    x[v, j] = X[v, base + j]
            else:
                for j in range(nb):
                    x[v, j] = X[v, keep[blk + j]]
        base -= c0
        for t in range(nseg):
            link, turn, ur_t, ui_t, wr_t, wi_t = seg_link[t], seg_u[t], ur[t], ui[t], wr[t], wi[t]
            if link >= 0 and seg_i[t, 0] == 0:  # a link's segment: its unit and w in one loop
                ln, tr, ti = seg_f[t, 0], turn.real, turn.imag
                if together:
                    Rl = R[link, 0, base:base + nb]
                    for j in range(nb):
                        rr, ri = Rl[j].real, Rl[j].imag
                        a, b = rr * tr - ri * ti, rr * ti + ri * tr
                        ur_t[j], ui_t[j], wr_t[j], wi_t[j] = a, b, ln * a, ln * b
                else:
                    for j in range(nb):
                        u = R[link, 0, keep[blk + j] - c0] * turn
                        ur_t[j], ui_t[j] = u.real, u.imag
                        wr_t[j], wi_t[j] = ln * u.real, ln * u.imag
                continue
            if link >= 0:
                for j in range(nb):
                    u = R[link, 0, keep[blk + j] - c0] * turn
                    ur_t[j], ui_t[j] = u.real, u.imag
            else:
                e = seg_i[t, 1]
                _linear(e, ex_ptr, ex_var, ex_c, x, nb, dl)
                for j in range(nb):
                    delta = dl[j] + ex_const[e] + seg_f[t, 1]
                    ur_t[j], ui_t[j] = math.cos(delta), math.sin(delta)
            if seg_i[t, 0] == 0:
                ln = seg_f[t, 0]
                for j in range(nb):
                    wr_t[j], wi_t[j] = ln * ur_t[j], ln * ui_t[j]
            else:
                sv, s0, sg = seg_i[t, 2], seg_f[t, 2], seg_f[t, 3]
                for j in range(nb):
                    a = sg * (x[sv, j] - s0)
                    wr_t[j], wi_t[j] = a * ur_t[j], a * ui_t[j]
        for j in range(nb):
            residuals[blk + j] = 0.0
            conditions[blk + j] = 1.0
        for g in range(groups.shape[0]):
            lo, hi, u0, u1 = groups[g, 0], groups[g, 1], groups[g, 2], groups[g, 3]
            for j in range(nb):
                ar[j] = ai[j] = c0r[j] = c0i[j] = c1r[j] = c1i[j] = kr[j] = ki[j] = 0.0
                xd[u0, j] = xd[u1, j] = xdd[u0, j] = xdd[u1, j] = 0.0
            for t in range(lo, hi):
                ur_t, ui_t, wr_t, wi_t = ur[t], ui[t], wr[t], wi[t]
                d0, d1, s0, s1 = seg_du[t, 0], seg_du[t, 1], seg_du[t, 2], seg_du[t, 3]
                e = seg_i[t, 1]
                if order > 0 and ex_ptr[e + 1] - ex_ptr[e] == 1:  # one variable's multiple: Δ̇ in the loop
                    c, xv = ex_c[ex_ptr[e]], xd[ex_var[ex_ptr[e]]]
                    for j in range(nb):
                        d = c * xv[j]
                        ar[j] += wr_t[j]
                        ai[j] += wi_t[j]
                        kr[j] -= wi_t[j] * d
                        ki[j] += wr_t[j] * d
                elif order > 0 and ex_ptr[e + 1] > ex_ptr[e]:  # A and the rest of Ȧ in one loop
                    _linear(e, ex_ptr, ex_var, ex_c, xd, nb, dl)
                    dl_t = dl
                    for j in range(nb):
                        ar[j] += wr_t[j]
                        ai[j] += wi_t[j]
                        kr[j] -= wi_t[j] * dl_t[j]
                        ki[j] += wr_t[j] * dl_t[j]
                else:  # a segment of constant direction adds no rate
                    for j in range(nb):
                        ar[j] += wr_t[j]
                        ai[j] += wi_t[j]
                if d0 != 0.0 or s0 != 0.0:  # most segments turn with neither unknown
                    for j in range(nb):
                        c0r[j] += s0 * ur_t[j] - d0 * wi_t[j]
                        c0i[j] += s0 * ui_t[j] + d0 * wr_t[j]
                if d1 != 0.0 or s1 != 0.0:
                    for j in range(nb):
                        c1r[j] += s1 * ur_t[j] - d1 * wi_t[j]
                        c1i[j] += s1 * ui_t[j] + d1 * wr_t[j]
                if order > 0 and seg_i[t, 0] != 0:
                    sg, sd = seg_f[t, 3], xd[seg_i[t, 2]]
                    for j in range(nb):
                        kr[j] += sg * sd[j] * ur_t[j]
                        ki[j] += sg * sd[j] * ui_t[j]
            g0, g1 = gscale[g, 0], gscale[g, 1]
            for j in range(nb):  # no branch: the loop runs four configurations at once
                k = blk + j
                residuals[k] = max(residuals[k], max(abs(ar[j]), abs(ai[j])) / size)
                s00, s01, s10, s11 = c0r[j] * g0, c1r[j] * g1, c0i[j] * g0, c1i[j] * g1
                fro = s00 * s00 + s01 * s01 + s10 * s10 + s11 * s11
                dt = abs(s00 * s11 - s01 * s10)
                top = 0.5 * (fro + math.sqrt(max(fro * fro - 4 * dt * dt, 0.0)))
                c = top / dt  # infinite where dt is zero (NaN where top is too)
                c = max(c, 1.0) if c == c else math.inf
                dl[j] = c
                conditions[k] = max(conditions[k], c)
            if order == 0:
                continue
            for j in range(nb):
                j00, j01, j10, j11 = c0r[j], c1r[j], c0i[j], c1i[j]
                ok = dl[j] < math.inf
                det = j00 * j11 - j01 * j10 if ok else math.nan  # NaN: the configuration's derivatives refused
                r0, r1 = -kr[j], -ki[j]
                xd[u0, j] = (r0 * j11 - j01 * r1) / det
                xd[u1, j] = (j00 * r1 - j10 * r0) / det
                c0r[j] = j00 if ok else math.nan
            if order < 2:
                continue
            for j in range(nb):
                kr[j] = ki[j] = 0.0
            for t in range(lo, hi):  # Δ̇ now with the unknowns' rates; their accelerations at zero
                ur_t, ui_t, wr_t, wi_t = ur[t], ui[t], wr[t], wi[t]
                e, slide, terms = seg_i[t, 1], seg_i[t, 0] != 0, ex_ptr[seg_i[t, 1] + 1] - ex_ptr[seg_i[t, 1]]
                if terms == 1 and not slide:
                    p = ex_ptr[e]
                    c, xv, xa = ex_c[p], xd[ex_var[p]], xdd[ex_var[p]]
                    for j in range(nb):
                        d, dd = c * xv[j], c * xa[j]
                        v2 = d * d
                        kr[j] += -wi_t[j] * dd - wr_t[j] * v2
                        ki[j] += wr_t[j] * dd - wi_t[j] * v2
                    continue
                if terms:
                    _linear(e, ex_ptr, ex_var, ex_c, xd, nb, dl)
                    _linear(e, ex_ptr, ex_var, ex_c, xdd, nb, ddl)
                _accelerations(t, nb, terms > 0, seg_i, seg_f, ur_t, ui_t, wr_t, wi_t, dl, ddl, xd, xdd, kr, ki)
            for j in range(nb):
                j00, j01, j10, j11 = c0r[j], c1r[j], c0i[j], c1i[j]
                det = j00 * j11 - j01 * j10
                r0, r1 = -kr[j], -ki[j]
                xdd[u0, j] = (r0 * j11 - j01 * r1) / det
                xdd[u1, j] = (j00 * r1 - j10 * r0) / det
        for j in range(nb):
            worst = max(worst, conditions[blk + j])
        col = 0
        for o in range(outs_i.shape[0]):
            kind, a, b = outs_i[o, 0], outs_i[o, 1], outs_i[o, 2]
            if kind == 0 and ex_ptr[a + 1] - ex_ptr[a] == 1:  # one variable's multiple: every row in one loop
                c, v, ref = ex_c[ex_ptr[a]], ex_var[ex_ptr[a]], outs_f[o] + ex_const[a]
                for j in range(nb):
                    out[col, blk + j] = ref + c * x[v, j]
                    if order >= 1:
                        out[col + 1, blk + j] = c * xd[v, j]
                    if order >= 2:
                        out[col + 2, blk + j] = c * xdd[v, j]
                col += order + 1
            elif kind == 0:
                _linear(a, ex_ptr, ex_var, ex_c, x, nb, dl)
                for j in range(nb):
                    out[col, blk + j] = outs_f[o] + (dl[j] + ex_const[a])
                if order >= 1:  # the rates apart: at order 0 their rows are not filled
                    _linear(a, ex_ptr, ex_var, ex_c, xd, nb, dl)
                    for j in range(nb):
                        out[col + 1, blk + j] = dl[j]
                if order >= 2:
                    _linear(a, ex_ptr, ex_var, ex_c, xdd, nb, dl)
                    for j in range(nb):
                        out[col + 2, blk + j] = dl[j]
                col += order + 1
            elif kind == 1:
                for j in range(nb):
                    out[col, blk + j] = x[a, j]
                    if order >= 1:
                        out[col + 1, blk + j] = xd[a, j]
                    if order >= 2:
                        out[col + 2, blk + j] = xdd[a, j]
                col += order + 1
            else:
                for j in range(nb):
                    ar[j] = ai[j] = kr[j] = ki[j] = c0r[j] = c0i[j] = 0.0
                for t in range(a, b):
                    ur_t, ui_t, wr_t, wi_t = ur[t], ui[t], wr[t], wi[t]
                    e, slide = seg_i[t, 1], seg_i[t, 0] != 0
                    if order == 0 or not (slide or ex_ptr[e + 1] > ex_ptr[e]):  # constant: no rate
                        for j in range(nb):
                            ar[j] += wr_t[j]
                            ai[j] += wi_t[j]
                        continue
                    _linear(e, ex_ptr, ex_var, ex_c, xd, nb, dl)
                    if order >= 2 and not slide:  # the point, its rate and its acceleration in one loop
                        _linear(e, ex_ptr, ex_var, ex_c, xdd, nb, ddl)
                        for j in range(nb):
                            ar[j] += wr_t[j]
                            ai[j] += wi_t[j]
                            kr[j] -= wi_t[j] * dl[j]
                            ki[j] += wr_t[j] * dl[j]
                            v2 = dl[j] * dl[j]
                            c0r[j] += -wi_t[j] * ddl[j] - wr_t[j] * v2
                            c0i[j] += wr_t[j] * ddl[j] - wi_t[j] * v2
                        continue
                    for j in range(nb):
                        ar[j] += wr_t[j]
                        ai[j] += wi_t[j]
                        kr[j] -= wi_t[j] * dl[j]
                        ki[j] += wr_t[j] * dl[j]
                    if slide:
                        sg, sd = seg_f[t, 3], xd[seg_i[t, 2]]
                        for j in range(nb):
                            kr[j] += sg * sd[j] * ur_t[j]
                            ki[j] += sg * sd[j] * ui_t[j]
                    if order == 1:
                        continue
                    _linear(e, ex_ptr, ex_var, ex_c, xdd, nb, ddl)
                    _accelerations(t, nb, True, seg_i, seg_f, ur_t, ui_t, wr_t, wi_t, dl, ddl, xd, xdd, c0r, c0i)
                for j in range(nb):
                    k = blk + j
                    out[col, k], out[col + 1, k] = ar[j], ai[j]
                    if order >= 1:
                        out[col + 2, k], out[col + 3, k] = kr[j], ki[j]
                    if order >= 2:
                        out[col + 4, k], out[col + 5, k] = c0r[j], c0i[j]
                col += 2 * (order + 1)
    return worst
