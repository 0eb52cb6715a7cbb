"""A sweep of drivers and dyads in one compiled pass: positions, continuous angles, rates, outputs (numba).

:func:`~domes.motion.planar.sweep.run_sweep` walks a query of drivers and
dyads on arrays (:mod:`~domes.motion.planar.branches`), each stage a numpy
pass. On the compiled route (:func:`~domes.motion.planar.compiled.choose`)
the sweep is first tried here: the placements
(:func:`~domes.motion.planar.compiled.run`), then one more compiled loop
for the continuous angles (numpy's ``unwrap``), the jump and branch-point
tests, and, a block of configurations at a time, the loop equations of
every dyad (the segment sums of
:func:`~domes.motion.planar.structure.evaluate`) for residuals, condition
numbers, velocities, accelerations and the outputs. The loops read a
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
from domes.motion.planar.query import JUMP, SINGULAR_CONDITION, error_bounds
from domes.results import Status, Ticker

__all__ = ["Pass", "sweep"]

#: Verdicts of the compiled pass.
DONE, FAILED, NEAR_BRANCH = 0, 1, 2
#: Walks of at most this many points keep their work arrays for the next sweep.
SPARE = 1 << 17
#: Configurations per block of the pass's loop equations and outputs (their rows stay in the cache).
BLOCK = 256
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
        """The constant tables of :func:`~domes.motion.planar.compiled.run` (one mechanism), as ``Tape.poses``."""
        tape, geom = self.tape, Compiled.of(self.kin).geometry
        others = {j: x for j, x in fixed.items() if j != self.joint}

        def row(values, fill, dtype):
            out = np.empty((1, len(values)), dtype=dtype)
            for k, v in enumerate(values):
                out[0, k] = np.asarray(v if v is not None else fill, dtype=dtype).reshape(-1)[0]
            return out

        self.G = row([geom.at[p] for p in tape.points], 0j, complex)
        self.U = row([geom.direction[s] for s in tape.slides], 1 + 0j, complex)
        self.S0 = row([geom.s0[s] for s in tape.slides], 0.0, float)
        self.drawn = row([geom.drawn[j] for j in tape.inputs], 0.0, float)
        self.fixed = row([others.get(j, geom.drawn[j]) for j in tape.inputs], 0.0, float)
        self.sign = row([geom.sign.get(i, 1.0) for i in tape.dyads], 1.0, float)
        self.k_swept = tape.inputs.index(self.joint)

    def borrow(self, n: int, nk: int) -> tuple:
        """Work arrays for a walk of ``n`` points keeping ``nk``: a sweep's arrays again when the last sweep of this
        size has given them back (fresh pages cost more than the pass), else new ones."""
        key = (n, max(min(nk, BLOCK), 1))
        while self._spare:
            try:
                size, work = self._spare.pop()
            except IndexError:  # another thread took it
                break
            if size == key:
                return work
        nl, nd, ns, nv = len(self.tape.links), len(self.tape.dyads), len(self.tape.slides), len(self.names)
        width = key[1]
        rows = (nv, width)
        R, W = np.empty((nl, 1, n), dtype=complex), np.empty((nl, 1, n), dtype=complex)
        R[0], W[0] = 1.0, 0.0  # the ground (the placements never write it)
        return (R, W, np.empty((ns, 1, n)),
                np.empty((3, nd, 1, n)), np.empty((2, nd, 1, n), dtype=np.bool_), np.empty(rows), np.empty(rows),
                np.empty(rows), np.empty((self.seg_i.shape[0], width), dtype=complex), np.empty(rows), np.empty(rows),
                np.empty(rows), np.empty(rows), np.empty((4, width)), np.zeros(nv, dtype=np.bool_),
                np.empty(nv, dtype=np.int64))

    def give_back(self, work: tuple) -> None:
        """Keep ``work`` for the next sweep of the same size (one set, and only of a modest size)."""
        if work[0].shape[2] <= SPARE:
            self._spare[:] = [((work[0].shape[2], work[5].shape[1]), work)]

    def walk_points(self, qs, q0, h) -> tuple:
        """:func:`_walk_points`, kept for the next sweep of the same grid (the pass only reads them; a sweep's
        inputs are copied out)."""
        last = self._walk
        if last is not None and last[0] == (q0, h) and np.array_equal(last[1], qs):
            return last[2]
        points = _walk_points(qs, q0, h)
        self._walk = ((q0, h), qs.copy(), points)
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
        return cls(kin, joint, fixed, tape)


def sweep(kin, cont, qs, progress=None):
    """The sweep of :func:`~domes.motion.planar.sweep.run_sweep` over the grid ``qs`` (an array) in one compiled
    pass, or None where a decision is to be made (the numpy walk then takes the sweep) or the query is not of
    drivers and dyads."""
    from domes.motion.planar.sweep import _result

    prog = Pass.of(kin, cont.joint, cont.fixed)
    if prog is None:
        return None
    qs = np.asarray(qs, dtype=float)
    xs, keep, lead, count = prog.walk_points(qs, cont.q0, cont.h)
    n, nk = xs.size, keep.size
    work = prog.borrow(n, nk)
    R, W, S, F, B = work[:5]
    tape = prog.tape
    compiled.run(tape.rows, tape.anchors, prog.G, prog.U, prog.S0, prog.drawn, prog.fixed, xs, prog.k_swept,
                 prog.sign, R, W, S, F, B, closures=False)  # a sweep reads no closure
    X = np.empty((len(prog.names), n))
    out = np.empty((len(prog.columns), nk))
    rc = np.empty((2, nk))
    verdict, worst = _passer()(R, S, F, B, xs, keep, prog.start, prog.swept, prog.values_i, prog.values_f,
                               prog.ex_ptr, prog.ex_var, prog.ex_c, prog.ex_const, prog.jump_v, prog.jump_s, JUMP,
                               prog.signed, ROOT_FLOOR, prog.seg_i, prog.seg_f, prog.seg_link, prog.seg_u, prog.groups,
                               prog.gscale, prog.rates, prog.accels, kin.order, kin.size, prog.outs_i, prog.outs_f, X,
                               out, rc[0], rc[1], *work[5:])
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
    return _result(kin, cont, qs, inputs, table, rc[0], rc[1], states, [], Status.COMPLETE, [],
                   (min(ends), max(ends)))


def _derivatives_known(worst, order, tol) -> bool:
    """Whether no derivative is refused: the test of :func:`~domes.motion.planar.sweep._refuse`, which grows with the
    condition number, made at the largest (``worst``)."""
    return worst <= SINGULAR_CONDITION and all(e <= tol for e in error_bounds(worst, order)[1:])


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


_FINE = None


def _finer():
    global _FINE
    if _FINE is None:
        _FINE = compiled._jit(_fine_grid)
    return _FINE


_PASS = None


def _passer():
    """The compiled pass (numba imported, the loop compiled or loaded from its cache, on first use)."""
    global _PASS, _loop, _meet, _angle
    if _PASS is None:
        _meet, _loop, _angle = compiled._jit(_meet), compiled._jit(_loop), compiled._jit(_angle)
        _PASS = compiled._jit(_pass)
    return _PASS


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


def _meet(v, nb, seen, seq, met, cx, cy, dcx, dcy, again):  # pragma: no cover - compiled
    """Start the rows (``nb`` long) of variable ``v`` at zero when it is first met (``again``: only the rows of the
    time derivative); the count of variables met."""
    if seen[v]:
        return met
    seen[v] = True
    seq[met] = v
    for k in range(nb):
        dcx[v, k] = dcy[v, k] = 0.0
    if not again:
        for k in range(nb):
            cx[v, k] = cy[v, k] = 0.0
    return met + 1


def _loop(lo, hi, nb, seg_i, seg_f, units, ex_ptr, ex_var, ex_c, x, xd, rates, grad, again, a0, a1, cx, cy, dcx, dcy,
          seen, seq, dd):  # pragma: no cover - compiled
    """The segment sum of :func:`~domes.motion.planar.structure.evaluate` over every configuration (``units[t]``
    segment ``t``'s ``u(Δ + α)``; rates ``xd`` when ``rates``): ``A`` into ``a0, a1``; with ``grad`` ``∂A/∂v`` into
    rows of ``cx, cy`` and (with ``rates``) its time derivative into ``dcx, dcy``, the variables in the order first
    met (``seq``: the order of ``evaluate``'s dicts, so sums over them round alike). Returns how many were met.
    ``again`` (with ``rates``) fills only ``dcx, dcy``: ``A`` and ``∂A/∂v`` are those of the last call on the same
    segments. Columns ``0 .. nb - 1`` are the configurations of the block."""
    nk = nb
    sums = not again
    if sums:
        for k in range(nk):
            a0[k] = 0.0
            a1[k] = 0.0
    for v in range(seen.size):
        seen[v] = False
    met = np.int64(0)
    for t in range(lo, hi):
        e, sv = seg_i[t, 1], seg_i[t, 2]
        u = units[t]
        if rates:
            for k in range(nk):
                dd[k] = 0.0
            for p in range(ex_ptr[e], ex_ptr[e + 1]):
                c, v = ex_c[p], ex_var[p]
                for k in range(nk):
                    dd[k] += c * xd[v, k]
        if seg_i[t, 0] == 0:
            ln = seg_f[t, 0]
            if sums:
                for k in range(nk):
                    a0[k] += ln * u[k].real
                    a1[k] += ln * u[k].imag
            if not grad:
                continue
            for p in range(ex_ptr[e], ex_ptr[e + 1]):
                c, v = ex_c[p], ex_var[p]
                met = _meet(v, nb, seen, seq, met, cx, cy, dcx, dcy, again)
                if sums:
                    for k in range(nk):
                        cs, sn = u[k].real, u[k].imag
                        cx[v, k] += c * (-ln * sn)
                        cy[v, k] += c * (ln * cs)
                if rates:
                    for k in range(nk):
                        cs, sn = u[k].real, u[k].imag
                        dcx[v, k] += c * (-ln * dd[k] * cs)
                        dcy[v, k] += c * (-ln * dd[k] * sn)
            continue
        s0, sg = seg_f[t, 2], seg_f[t, 3]
        e0 = 0.0
        if sums:
            for k in range(nk):
                cs, sn = u[k].real, u[k].imag
                s = x[sv, k] - s0
                a0[k] += sg * (e0 * sn + s * cs)
                a1[k] += sg * (-e0 * cs + s * sn)
        if not grad:
            continue
        for p in range(ex_ptr[e], ex_ptr[e + 1]):
            c, v = sg * ex_c[p], ex_var[p]
            met = _meet(v, nb, seen, seq, met, cx, cy, dcx, dcy, again)
            if sums:
                for k in range(nk):
                    cs, sn = u[k].real, u[k].imag
                    s = x[sv, k] - s0
                    cx[v, k] += c * (e0 * cs - s * sn)
                    cy[v, k] += c * (e0 * sn + s * cs)
            if rates:
                for k in range(nk):
                    cs, sn = u[k].real, u[k].imag
                    s = x[sv, k] - s0
                    sd = xd[sv, k]
                    dcx[v, k] += c * (-e0 * dd[k] * sn - s * dd[k] * cs - sd * sn)
                    dcy[v, k] += c * (e0 * dd[k] * cs - s * dd[k] * sn + sd * cs)
        met = _meet(sv, nb, seen, seq, met, cx, cy, dcx, dcy, again)
        if sums:
            for k in range(nk):
                cs, sn = u[k].real, u[k].imag
                cx[sv, k] += sg * cs
                cy[sv, k] += sg * sn
        if rates:
            for k in range(nk):
                cs, sn = u[k].real, u[k].imag
                dcx[sv, k] += sg * (-dd[k] * sn)
                dcy[sv, k] += sg * (dd[k] * cs)
    return met


def _pass(R, S, F, B, xs, keep, start, swept, values_i, values_f, ex_ptr, ex_var, ex_c, ex_const, jump_v, jump_s,
          jump, signed, floor, seg_i, seg_f, seg_link, seg_u, groups, gscale, rates0, accels0, order, size, outs_i, outs_f, X, out,
          residuals, conditions, x, xd, xdd, units, cx, cy, dcx, dcy, rows, seen, seq):  # pragma: no cover - compiled
    n, nv = xs.size, start.size
    # the groups' variables over the walk, continuous from the drawn pose (numpy's unwrap)
    for v in range(nv):
        for i in range(n):
            X[v, i] = start[v]
    for i in range(n):
        X[swept, i] = xs[i]
    for r in range(values_i.shape[0]):
        kind, v, at, e = values_i[r, 0], values_i[r, 1], values_i[r, 2], values_i[r, 3]
        if kind == 1:
            for i in range(n):
                X[v, i] = S[at, 0, i]
            continue
        prev = start[v]
        fix = 0.0
        for i in range(n):
            rest = 0.0
            for p in range(ex_ptr[e], ex_ptr[e + 1]):
                rest += ex_c[p] * X[ex_var[p], i]
            rest += ex_const[e]
            new = (_angle(R[at, 0, i]) - rest) / values_f[r]
            dd = new - prev
            prev = new
            if abs(dd) >= math.pi:  # numpy's unwrap: the step taken to (-π, π], less the step
                ddmod = (dd + math.pi) % (2 * math.pi) - math.pi
                if ddmod == -math.pi and dd > 0:
                    ddmod = math.pi
                fix += ddmod - dd
            X[v, i] = new + fix
    # a decision to make: a configuration that does not assemble, is undetermined or jumps; a root near zero
    for d in range(F.shape[1]):
        for i in range(n):
            if B[0, d, 0, i] or B[1, d, 0, i]:
                return 1, 0.0
    for r in range(jump_v.size):
        v = jump_v[r]
        prev = start[v]
        for i in range(n):
            if not abs(X[v, i] - prev) / jump_s[r] <= jump:
                return 1, 0.0
            prev = X[v, i]
    for t in range(signed.size):
        root = F[0, signed[t], 0]
        for i in range(n):
            if not root[i] > 2 * floor:
                return 2, 0.0
        for i in range(1, n - 1):
            if root[i] <= root[i - 1] and root[i] <= root[i + 1]:
                d0, d1 = abs(xs[i] - xs[i - 1]), abs(xs[i + 1] - xs[i])
                slope = 0.0
                if d0 > 0:
                    slope = abs(root[i] - root[i - 1]) / d0
                if d1 > 0:
                    slope = max(slope, abs(root[i + 1] - root[i]) / d1)
                if root[i] <= 2 * (slope * max(d0, d1) + floor):
                    return 2, 0.0
    # on the kept configurations, a block at a time (its rows stay in cache): each dyad's loop for residual,
    # condition, rates and accelerations; then the outputs
    nk, width = keep.size, x.shape[1]
    on, off = order >= 0, order < 0  # flags as values, not constants: one compiled _loop for every call
    a0, a1, dd, gc = rows[0], rows[1], rows[2], rows[3]
    worst = 1.0
    for blk in range(0, nk, width):
        nb = min(width, nk - blk)
        for v in range(nv):
            for j in range(nb):
                x[v, j] = X[v, keep[blk + j]]
            if order == 0:  # no rates read
                continue
            for j in range(nb):
                xd[v, j] = rates0[v]
                xdd[v, j] = accels0[v]
        for t in range(seg_i.shape[0]):
            link, turn = seg_link[t], seg_u[t]
            if link >= 0:
                for j in range(nb):
                    units[t, j] = R[link, 0, keep[blk + j]] * turn
                continue
            e = seg_i[t, 1]
            for j in range(nb):
                delta = 0.0
                for p in range(ex_ptr[e], ex_ptr[e + 1]):
                    delta += ex_c[p] * x[ex_var[p], j]
                delta += ex_const[e] + seg_f[t, 1]
                units[t, j] = complex(math.cos(delta), math.sin(delta))
        for j in range(nb):
            residuals[blk + j] = 0.0
            conditions[blk + j] = 1.0
        for g in range(groups.shape[0]):
            lo, hi, u0, u1 = groups[g, 0], groups[g, 1], groups[g, 2], groups[g, 3]
            met = _loop(lo, hi, nb, seg_i, seg_f, units, ex_ptr, ex_var, ex_c, x, xd, off, on, off, a0, a1, cx, cy,
                        dcx, dcy, seen, seq, dd)
            if not (seen[u0] and seen[u1]):
                return 3, 0.0
            g0, g1 = gscale[g, 0], gscale[g, 1]
            for j in range(nb):
                k = blk + j
                residuals[k] = max(residuals[k], max(abs(a0[j]), abs(a1[j])) / size)
                j00, j01, j10, j11 = cx[u0, j], cx[u1, j], cy[u0, j], cy[u1, j]
                s00, s01, s10, s11 = j00 * g0, j01 * g1, j10 * g0, j11 * g1
                fro = s00 * s00 + s01 * s01 + s10 * s10 + s11 * s11
                dt = abs(s00 * s11 - s01 * s10)
                top = 0.5 * (fro + math.sqrt(max(fro * fro - 4 * dt * dt, 0.0)))
                c = top / dt if dt != 0.0 else math.inf
                c = max(c, 1.0) if c == c else math.inf
                gc[j] = c
                conditions[k] = max(conditions[k], c)
                if order == 0:
                    continue
                ok = math.isfinite(c)
                det = j00 * j11 - j01 * j10
                r0 = r1 = 0.0
                for m in range(met):
                    v = seq[m]
                    if v != u0 and v != u1:
                        r0 -= cx[v, j] * xd[v, j]
                        r1 -= cy[v, j] * xd[v, j]
                xd[u0, j] = (r0 * j11 - j01 * r1) / det if ok else math.nan
                xd[u1, j] = (j00 * r1 - j10 * r0) / det if ok else math.nan
            if order < 2:
                continue
            met = _loop(lo, hi, nb, seg_i, seg_f, units, ex_ptr, ex_var, ex_c, x, xd, on, on, on, a0, a1, cx, cy, dcx,
                        dcy, seen, seq, dd)
            for j in range(nb):
                j00, j01, j10, j11 = cx[u0, j], cx[u1, j], cy[u0, j], cy[u1, j]
                det = j00 * j11 - j01 * j10
                r0 = r1 = 0.0
                for m in range(met):
                    v = seq[m]
                    if v != u0 and v != u1:
                        r0 -= cx[v, j] * xdd[v, j]
                        r1 -= cy[v, j] * xdd[v, j]
                for m in range(met):
                    v = seq[m]
                    r0 -= dcx[v, j] * xd[v, j]
                    r1 -= dcy[v, j] * xd[v, j]
                ok = math.isfinite(gc[j])
                xdd[u0, j] = (r0 * j11 - j01 * r1) / det if ok else math.nan
                xdd[u1, j] = (j00 * r1 - j10 * r0) / det if ok else math.nan
        for j in range(nb):
            worst = max(worst, conditions[blk + j])
        col = 0
        for o in range(outs_i.shape[0]):
            kind, a, b = outs_i[o, 0], outs_i[o, 1], outs_i[o, 2]
            if kind == 0:
                for j in range(nb):
                    val = 0.0
                    for p in range(ex_ptr[a], ex_ptr[a + 1]):
                        val += ex_c[p] * x[ex_var[p], j]
                    out[col, blk + j] = outs_f[o] + (val + ex_const[a])
                if order >= 1:  # the rates apart: at order 0 their rows are not filled
                    for j in range(nb):
                        rate = accel = 0.0
                        for p in range(ex_ptr[a], ex_ptr[a + 1]):
                            rate += ex_c[p] * xd[ex_var[p], j]
                            accel += ex_c[p] * xdd[ex_var[p], j]
                        out[col + 1, blk + j] = rate
                        if order >= 2:
                            out[col + 2, blk + j] = accel
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
                met = _loop(a, b, nb, seg_i, seg_f, units, ex_ptr, ex_var, ex_c, x, xd, order >= 2, order >= 1, off, a0, a1,
                            cx, cy, dcx, dcy, seen, seq, dd)
                for j in range(nb):
                    k = blk + j
                    out[col, k], out[col + 1, k] = a0[j], a1[j]
                    if order == 0:
                        continue
                    v0 = v1 = w0 = w1 = e0 = e1 = 0.0
                    for m in range(met):
                        v = seq[m]
                        v0 += cx[v, j] * xd[v, j]
                        v1 += cy[v, j] * xd[v, j]
                        w0 += cx[v, j] * xdd[v, j]
                        w1 += cy[v, j] * xdd[v, j]
                        e0 += dcx[v, j] * xd[v, j]
                        e1 += dcy[v, j] * xd[v, j]
                    out[col + 2, k], out[col + 3, k] = v0, v1
                    if order >= 2:
                        out[col + 4, k], out[col + 5, k] = w0 + e0, w1 + e1
                col += 2 * (order + 1)
    return 0, worst
