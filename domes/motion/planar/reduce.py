"""A batch reduced to per-mechanism extremes in one compiled loop, without writing its positions to memory.

:class:`~domes.motion.planar.batch.ExtremesSink` keeps, for each mechanism,
the smallest and largest value of each output over the inputs and the
status the batch reports. On the compiled route a chunk is otherwise placed
into arrays of every configuration (:func:`~domes.motion.planar.compiled.run`),
finished into outputs and masks, and reduced in a third pass; here one loop
(:func:`extremes`) places each mechanism at each input with the same closed
forms, in a few local variables, and keeps the running extremes, the
limit/undetermined flags, the smallest dyad root and the largest closure. It
serves tapes of drivers (R or P) and RRR dyads with point and slide outputs
(the four-bar, six-bars built of RRR dyads such as the Watt); :func:`spec` says None otherwise and the batch takes the
general route. Both give the same numbers to rounding
(``tests/motion/test_batch_reduce.py``).

>>> from domes.motion.planar.examples import four_bar
>>> from domes.motion.planar.kernel import Program
>>> from domes.motion.planar.query import Kinematics
>>> spec(Program(Kinematics(four_bar(), outputs=["point:C"]))).tolist()   # x and y of C, on link 2 (the coupler)
[[0, 2, 2]]
>>> spec(Program(Kinematics(four_bar(), outputs=["angle:rocker"]))) is None   # angles: the general route
True
"""

from __future__ import annotations

import numpy as np

from domes.motion.planar import compiled
from domes.motion.planar.compiled import DRIVER_P, DRIVER_R, RRR, Tape

_LOOP = None


def spec(prog):
    """The output table of ``prog`` for :func:`extremes` (rows ``(kind, link or slide, point)``: 0 a point's x and
    y, 1 a slide), or None when the program or an output is outside this loop (an angle, a P-joint dyad, a
    non-dyad group, derivatives)."""
    tape = Tape.of(prog)
    if tape is None or prog.kin.order or any(int(r[0]) not in (DRIVER_R, DRIVER_P, RRR) for r in tape.rows):
        return None
    lidx = {name: k for k, name in enumerate(tape.links)}
    pidx = {name: k for k, name in enumerate(tape.points)}
    rows = []
    for o in prog.kin.outputs:
        if o.kind == "point" and prog.mech.point(o.target)[0] in lidx:
            rows.append((0, lidx[prog.mech.point(o.target)[0]], pidx[o.target]))
        elif o.kind == "slide" and o.target in tape.slides and tape.slides.index(o.target) in tape.placed:
            rows.append((1, tape.slides.index(o.target), 0))
        else:
            return None
    return np.array(rows, dtype=np.int64).reshape(len(rows), 3)


def extremes(prog, table, geom, qs, joint, ambiguous, size, lo, minimum, maximum, argmin, argmax, kinds,
             transmission, residual) -> None:
    """The mechanisms of ``geom`` (rows ``lo ..`` of the outputs) at the inputs ``qs`` of ``joint``, reduced.

    ``table`` is :func:`spec`'s; ``minimum``, ``maximum`` (float) and
    ``argmin``, ``argmax`` (int64) are ``(columns, M)`` and take each
    column's extremes and their first input indices (NaN and −1 where a
    mechanism assembles nowhere); ``kinds`` (int64: 0 complete, 1 limit,
    2 undetermined, 3 ambiguous), ``transmission`` and ``residual`` are
    ``(M,)``, as :class:`~domes.motion.planar.batch.Batch` reports them.
    """
    tape = Tape.of(prog)
    mg = geom.count if geom.count is not None else 1

    def stacked(values, fill, dtype):
        out = np.empty((mg, len(values)), dtype=dtype)
        for k, v in enumerate(values):
            out[:, k] = np.broadcast_to(np.asarray(v if v is not None else fill, dtype=dtype).reshape(-1), (mg,))
        return out

    G = stacked([geom.at[p] for p in tape.points], 0j, complex)
    U = stacked([geom.direction[s] for s in tape.slides], 1 + 0j, complex)
    S0 = stacked([geom.s0[s] for s in tape.slides], 0.0, float)
    drawn = stacked([geom.drawn[j] for j in tape.inputs], 0.0, float)
    sign = stacked([geom.sign.get(i, 1.0) for i in tape.dyads], 1.0, float)
    flags = np.broadcast_to(ambiguous, (mg,)).astype(np.bool_)  # writable copies: one compiled signature
    sizes = np.broadcast_to(size, (mg,)).astype(float)
    signed = np.array(tape.signed, dtype=np.bool_)
    q = np.ascontiguousarray(qs, dtype=float).reshape(-1)
    used = np.zeros(len(tape.links), dtype=np.bool_)  # the links a later step or an output reads
    for r in tape.rows:
        used[[r[2]] if r[0] in (DRIVER_R, DRIVER_P) else [r[4], r[5]]] = True
    used[table[table[:, 0] == 0, 1]] = True
    _loop()(tape.rows, tape.anchors, G, U, S0, drawn, q, tape.inputs.index(joint), sign, signed, table, used, flags,
            sizes, len(tape.links), len(tape.slides), lo, minimum, maximum, argmin, argmax, kinds, transmission,
            residual)


def warm() -> None:
    """Load (or compile) the loop now, on empty arrays (before a batch measures its first chunk)."""
    e, one = np.zeros((0, 1)), np.zeros((0, 1), dtype=np.int64)
    _loop()(np.zeros((0, compiled.WIDTH), dtype=np.int64), np.zeros(1, dtype=np.int64), np.zeros((0, 1), complex),
            np.zeros((0, 0), complex), np.zeros((0, 0)), np.zeros((0, 1)), np.zeros(1), 0, np.zeros((0, 0)),
            np.zeros(0, dtype=np.bool_), np.zeros((0, 3), dtype=np.int64), np.zeros(1, dtype=np.bool_),
            np.zeros(0, dtype=np.bool_),
            np.zeros(0), 1, 0, 0, e, e, one, one, np.zeros(0, dtype=np.int64), np.zeros(0), np.zeros(0))


def _loop():
    global _LOOP, _keep
    if _LOOP is None:
        _keep = compiled._jit(_keep)
        _LOOP = compiled._jit(_reduce)
    return _LOOP


def _reduce(rows, anchors, G, U, S0, drawn, qs, swept, sign, signed, spec, used, ambiguous, size, nl, ns, lo,
            minimum, maximum, argmin, argmax, kinds, transmission, residual):  # pragma: no cover - compiled
    slack = 1e-14 * 64
    n, nr, no = qs.size, rows.shape[0], spec.shape[0]
    turns = np.empty(n, dtype=np.complex128)
    for i in range(n):
        turns[i] = complex(np.cos(qs[i]), np.sin(qs[i]))
    R = np.empty((nl, n), dtype=np.complex128)  # one mechanism's links at every input: reused, in the cache
    W = np.empty((nl, n), dtype=np.complex128)
    S = np.zeros((max(ns, 1), n))
    good = np.empty(n, dtype=np.bool_)
    nd = 0
    for r in range(nr):
        nd += rows[r, 0] == RRR
    roots = np.empty((max(nd, 1), n))  # each dyad's root numerator; its denominator 2·l1·l2 is the mechanism's
    scale = np.ones(max(nd, 1))
    gaps = np.empty((max(nd, 1), n))  # each dyad's |B − C|², against its length l2
    length = np.ones(max(nd, 1))
    for m in range(G.shape[0]):
        g = G[m]
        limit = undetermined = False
        for i in range(n):
            R[0, i], W[0, i] = 1.0, 0.0
            good[i] = not ambiguous[m]
        for r in range(nr):
            op = rows[r, 0]
            if op == DRIVER_R or op == DRIVER_P:
                link, known, pj, k = rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4]
                Rk, Wk, Rn, Wn = R[known], W[known], R[link], W[link]
                arm = g[pj] - (g[anchors[known]] if anchors[known] >= 0 else 0j)
                back = complex(np.cos(drawn[m, k]), -np.sin(drawn[m, k]))
                x0 = drawn[m, k]
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
                        S[s, i] = x
                        Rn[i] = Rk[i]
                        Wn[i] = Wk[i] + Rk[i] * arm + (x - S0[m, s]) * Rk[i] * along
                continue
            d, l1, l2, ka, kc = rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4], rows[r, 5]
            a, b, c = g[rows[r, 6]], g[rows[r, 7]], g[rows[r, 8]]
            arm_a = a - (g[anchors[ka]] if anchors[ka] >= 0 else 0j)
            arm_c = c - (g[anchors[kc]] if anchors[kc] >= 0 else 0j)
            Ra, Wa, Rc, Wc = R[ka], W[ka], R[kc], W[kc]
            R1, W1, R2, W2 = R[l1], W[l1], R[l2], W[l2]
            sg = sign[m, d]
            used1, used2 = used[l1], used[l2]
            ba, bc = b - a, b - c
            l1n, l2n = abs(ba), abs(bc)
            scale[d] = 2 * l1n * l2n if signed[d] else np.nan  # unsigned: no root
            length[d] = l2n
            dlo, dhi = abs(l1n - l2n), l1n + l2n
            ia, ic = ba.conjugate(), bc.conjugate()
            for i in range(n):
                A = Wa[i] + Ra[i] * arm_a
                C = Wc[i] + Rc[i] * arm_c
                D = C - A
                dd2 = D.real * D.real + D.imag * D.imag
                dd = np.sqrt(dd2)
                near = dd - dhi if dd > dhi else dlo - dd
                if (dd > dhi or dd < dlo) and near > slack * max(max(dd, l1n), l2n):
                    limit = True
                    good[i] = False
                elif dd == 0.0:
                    undetermined = True
                    good[i] = False
                prod = max((l1n + dd + l2n) * (l1n + dd - l2n) * (l1n - dd + l2n) * (-l1n + dd + l2n), 0.0)
                rp = np.sqrt(prod)
                Bp = A + D * complex(l1n * l1n + dd2 - l2n * l2n, sg * rp) * (0.5 / dd2)
                roots[d, i] = rp
                W1[i], W2[i] = A, C
                if used1:
                    z1 = (Bp - A) * ia
                    R1[i] = z1 * (1.0 / np.sqrt(z1.real * z1.real + z1.imag * z1.imag))
                if used2:
                    z2 = (Bp - C) * ic
                    R2[i] = z2 * (1.0 / np.sqrt(z2.real * z2.real + z2.imag * z2.imag))
                e = Bp - C  # the closure: how far B lies from the length B–C, |C + u2·(b − c) − B| = ||B − C| − l2|
                gaps[d, i] = e.real * e.real + e.imag * e.imag
        worst = np.inf  # the smallest root rp / (2·l1·l2) over the good inputs: the smallest rp, divided once
        closure = 0.0
        for k in range(nd):
            if scale[k] != scale[k]:
                continue
            small = np.inf
            for i in range(n):
                if good[i] and roots[k, i] < small:
                    small = roots[k, i]
            if small / scale[k] < worst:
                worst = small / scale[k]
        for k in range(nd):  # ||B − C| − l2| is largest where |B − C|² is (both sides of l2): two roots a dyad
            low, high = np.inf, -np.inf
            for i in range(n):
                if good[i]:
                    low, high = min(low, gaps[k, i]), max(high, gaps[k, i])
            if high >= low:
                closure = max(closure, abs(np.sqrt(high) - length[k]), abs(np.sqrt(low) - length[k]))
        col = 0
        for j in range(no):
            if spec[j, 0] == 0:
                link = spec[j, 1]
                rel = g[spec[j, 2]] - (g[anchors[link]] if anchors[link] >= 0 else 0j)
                _keep(W[link], R[link], rel, good, 0, minimum, maximum, argmin, argmax, col, lo + m)
                _keep(W[link], R[link], rel, good, 1, minimum, maximum, argmin, argmax, col + 1, lo + m)
                col += 2
            else:
                _keep(S[spec[j, 1]], S[spec[j, 1]], 0.0, good, 2, minimum, maximum, argmin, argmax, col, lo + m)
                col += 1
        kinds[lo + m] = 3 if ambiguous[m] else 2 if undetermined else 1 if limit else 0
        transmission[lo + m] = worst if np.isfinite(worst) else np.nan
        residual[lo + m] = closure / size[m]


def _keep(W, R, rel, good, part, minimum, maximum, argmin, argmax, col, m):  # pragma: no cover - compiled
    """Row ``m``'s extremes of column ``col`` over the good inputs (the first index on a tie): of the point
    ``W + R·rel``'s x (``part`` 0) or y (1), or of ``W`` itself (2, a slide)."""
    kmin = kmax = -1
    vmin = vmax = np.nan
    for i in range(good.size):
        if not good[i]:
            continue
        if part == 2:
            x = W[i].real
        else:
            X = W[i] + R[i] * rel
            x = X.real if part == 0 else X.imag
        if x != x:
            continue
        if kmin < 0 or x < vmin:
            kmin, vmin = i, x
        if kmax < 0 or x > vmax:
            kmax, vmax = i, x
    minimum[col, m], maximum[col, m], argmin[col, m], argmax[col, m] = vmin, vmax, kmin, kmax
