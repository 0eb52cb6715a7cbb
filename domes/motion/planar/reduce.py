"""A batch reduced to per-mechanism extremes in one compiled loop, without writing its positions to memory.

:class:`~domes.motion.planar.batch.ExtremesSink` keeps, for each mechanism,
the smallest and largest value of each output over the inputs and the
status the batch reports. On the compiled route a chunk is otherwise placed
into arrays of every configuration (:func:`~domes.motion.planar.compiled.run`),
finished into outputs and masks, and reduced in a third pass; here one loop
(:func:`extremes`) places each mechanism at all the inputs with the same closed
forms, in a few rows reused from one mechanism to the next, and keeps its
extremes, the limit/undetermined flags, the smallest dyad root and the largest
closure. Each dyad is placed in short passes over the inputs (the distances
and their roots, the flags, the transmission roots, the points, the rotations'
norms), so that many inputs' chains of square roots and divisions are in
flight at once instead of one input's after another. It
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

    G, U, S0, drawn, _, sign = tape.tables(geom)
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
    global _LOOP, _keep, _keep2
    if _LOOP is None:
        _keep = compiled._jit(_keep)
        _keep2 = compiled._jit(_keep2)
        _LOOP = compiled._jit(_reduce)
    return _LOOP


def _reduce(rows, anchors, G, U, S0, drawn, qs, swept, sign, signed, spec, used, ambiguous, size, nl, ns, lo,
            minimum, maximum, argmin, argmax, kinds, transmission, residual):  # pragma: no cover - compiled
    slack = 1e-14 * 64
    n, nr, no = qs.size, rows.shape[0], spec.shape[0]
    tc, ts = np.empty(n), np.empty(n)  # the inputs' turns, the same for every mechanism
    for i in range(n):
        tc[i], ts[i] = np.cos(qs[i]), np.sin(qs[i])
    # one mechanism's links at every input, real and imaginary parts apart (reused, in the cache): each complex
    # product is written out as numba forms it, (a + ib)(c + id) = (ac − bd) + i(ad + bc), so the bits are the same
    Rr, Ri, Wr, Wi = np.empty((nl, n)), np.empty((nl, n)), np.empty((nl, n)), np.empty((nl, n))
    S = np.zeros((max(ns, 1), n))
    good = np.empty(n, dtype=np.bool_)
    sq, sq2 = np.empty(n), np.empty(n)
    nd = 0
    for r in range(nr):
        nd += rows[r, 0] == RRR
    roots = np.empty((max(nd, 1), n))  # each dyad's root numerator; its denominator 2·l1·l2 is the mechanism's
    scale = np.ones(max(nd, 1))
    gaps = np.empty((max(nd, 1), n))  # each dyad's |B − C|², against its length l2
    length = np.ones(max(nd, 1))
    for m in range(G.shape[0]):
        g = G[m]
        limits = undetermined = 0
        Rr[0], Ri[0], Wr[0], Wi[0] = 1.0, 0.0, 0.0, 0.0
        good[:] = not ambiguous[m]
        for r in range(nr):
            op = rows[r, 0]
            if op == DRIVER_R or op == DRIVER_P:
                link, known, pj, k = rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4]
                rkr, rki, wkr, wki, rnr, rni, wnr, wni = Rr[known], Ri[known], Wr[known], Wi[known], Rr[link], \
                    Ri[link], Wr[link], Wi[link]
                arm = g[pj] - (g[anchors[known]] if anchors[known] >= 0 else 0j)
                ar, ai = arm.real, arm.imag
                back = complex(np.cos(drawn[m, k]), -np.sin(drawn[m, k]))
                x0 = drawn[m, k]
                fixed_turn = complex(np.cos(x0), np.sin(x0)) * back
                if op == DRIVER_R:
                    flip = 1.0 if rows[r, 5] > 0 else -1.0  # backwards: the turn's conjugate
                    br, bi = back.real, back.imag
                    for i in range(n):
                        if k == swept:
                            tr, ti = tc[i] * br - ts[i] * bi, (tc[i] * bi + ts[i] * br) * flip
                        else:
                            tr, ti = fixed_turn.real, fixed_turn.imag * flip
                        if known == 0:  # on the ground (R = 1, W = 0): the products are the factors themselves
                            rnr[i], rni[i], wnr[i], wni[i] = tr, ti, ar, ai
                        else:
                            rnr[i] = rkr[i] * tr - rki[i] * ti
                            rni[i] = rkr[i] * ti + rki[i] * tr
                            wnr[i] = wkr[i] + (rkr[i] * ar - rki[i] * ai)
                            wni[i] = wki[i] + (rkr[i] * ai + rki[i] * ar)
                else:
                    s = rows[r, 6]
                    along = rows[r, 5] * U[m, s]
                    for i in range(n):
                        x = qs[i] if k == swept else x0
                        S[s, i] = x
                        Rk = complex(rkr[i], rki[i])
                        Wn = complex(wkr[i], wki[i]) + Rk * arm + (x - S0[m, s]) * Rk * along
                        rnr[i], rni[i], wnr[i], wni[i] = rkr[i], rki[i], Wn.real, Wn.imag
                continue
            d, l1, l2, ka, kc = rows[r, 1], rows[r, 2], rows[r, 3], rows[r, 4], rows[r, 5]
            a, b, c = g[rows[r, 6]], g[rows[r, 7]], g[rows[r, 8]]
            arm_a = a - (g[anchors[ka]] if anchors[ka] >= 0 else 0j)
            arm_c = c - (g[anchors[kc]] if anchors[kc] >= 0 else 0j)
            aar, aai, acr, aci = arm_a.real, arm_a.imag, arm_c.real, arm_c.imag
            rar, rai, war, wai = Rr[ka], Ri[ka], Wr[ka], Wi[ka]
            rcr, rci, wcr, wci = Rr[kc], Ri[kc], Wr[kc], Wi[kc]
            r1r, r1i, w1r, w1i = Rr[l1], Ri[l1], Wr[l1], Wi[l1]
            r2r, r2i, w2r, w2i = Rr[l2], Ri[l2], Wr[l2], Wi[l2]
            root, gap = roots[d], gaps[d]
            sg = sign[m, d]
            used1, used2 = used[l1], used[l2]
            ba, bc = b - a, b - c
            l1n, l2n = abs(ba), abs(bc)
            scale[d] = 2 * l1n * l2n if signed[d] else np.nan  # unsigned: no root
            length[d] = l2n
            dlo, dhi = abs(l1n - l2n), l1n + l2n
            c0 = l1n * l1n
            c1 = l2n * l2n
            ia, ic = ba.conjugate() * (1.0 / (l1n * l1n)), bc.conjugate() * (1.0 / (l2n * l2n))  # as compiled.run
            iar, iai, icr, ici = ia.real, ia.imag, ic.real, ic.imag
            for i in range(n):  # short passes: many inputs' square roots and divisions in flight at once
                if ka == 0:
                    Ar, Ai = aar, aai
                else:
                    Ar = war[i] + (rar[i] * aar - rai[i] * aai)
                    Ai = wai[i] + (rar[i] * aai + rai[i] * aar)
                if kc == 0:
                    Cr, Ci = acr, aci
                else:
                    Cr = wcr[i] + (rcr[i] * acr - rci[i] * aci)
                    Ci = wci[i] + (rcr[i] * aci + rci[i] * acr)
                w1r[i], w1i[i], w2r[i], w2i[i] = Ar, Ai, Cr, Ci
                Dr, Di = Cr - Ar, Ci - Ai
                dd2 = Dr * Dr + Di * Di
                sq2[i] = dd2
                sq[i] = np.sqrt(dd2)
            for i in range(n):
                dd = sq[i]
                near = dd - dhi if dd > dhi else dlo - dd
                out = ((dd > dhi) | (dd < dlo)) & (near > slack * max(max(dd, l1n), l2n))
                zero = dd == 0.0
                limits += out
                undetermined += zero & ~out
                good[i] = good[i] & ~(out | zero)
            for i in range(n):
                dd = sq[i]
                prod = max((l1n + dd + l2n) * (l1n + dd - l2n) * (l1n - dd + l2n) * (-l1n + dd + l2n), 0.0)
                root[i] = np.sqrt(prod)
            for i in range(n):
                Ar, Ai, Cr, Ci = w1r[i], w1i[i], w2r[i], w2i[i]
                Dr, Di = Cr - Ar, Ci - Ai
                dd2 = sq2[i]
                u, v = c0 + dd2 - c1, sg * root[i]
                h = 0.5 / dd2
                Br = Ar + (Dr * u - Di * v) * h
                Bi = Ai + (Dr * v + Di * u) * h
                er, ei = Br - Cr, Bi - Ci  # the closure: |C + u2·(b − c) − B| = ||B − C| − l2|
                gap[i] = er * er + ei * ei
                if used1:
                    er, ei = Br - Ar, Bi - Ai
                    zr, zi = er * iar - ei * iai, er * iai + ei * iar
                    sq[i] = zr * zr + zi * zi
                    r1r[i], r1i[i] = zr, zi
                if used2:
                    er, ei = Br - Cr, Bi - Ci
                    zr, zi = er * icr - ei * ici, er * ici + ei * icr
                    sq2[i] = zr * zr + zi * zi
                    r2r[i], r2i[i] = zr, zi
            if used1:  # compiled._unit: one Newton step from 1, or the square root
                for i in range(n):
                    m1 = sq[i]
                    h1 = 1.5 - 0.5 * m1 if abs(m1 - 1.0) <= 1e-8 else 1.0 / np.sqrt(m1)
                    r1r[i], r1i[i] = r1r[i] * h1, r1i[i] * h1
            if used2:
                for i in range(n):
                    m2 = sq2[i]
                    h2 = 1.5 - 0.5 * m2 if abs(m2 - 1.0) <= 1e-8 else 1.0 / np.sqrt(m2)
                    r2r[i], r2i[i] = r2r[i] * h2, r2i[i] * h2
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
                _keep2(Wr[link], Wi[link], Rr[link], Ri[link], rel.real, rel.imag, good, sq, sq2, minimum, maximum,
                       argmin, argmax, col, lo + m)
                col += 2
            else:
                _keep(S[spec[j, 1]], good, minimum, maximum, argmin, argmax, col, lo + m)
                col += 1
        kinds[lo + m] = 3 if ambiguous[m] else 2 if undetermined else 1 if limits else 0
        transmission[lo + m] = worst if np.isfinite(worst) else np.nan
        residual[lo + m] = closure / size[m]


def _keep(x, good, minimum, maximum, argmin, argmax, col, m):  # pragma: no cover - compiled
    """Row ``m``'s extremes of column ``col``: of the values ``x`` over the good inputs (the first index on a tie)."""
    kmin = kmax = -1
    vmin = vmax = np.nan
    for i in range(good.size):
        if good[i] and x[i] == x[i]:
            if kmin < 0 or x[i] < vmin:
                kmin, vmin = i, x[i]
            if kmax < 0 or x[i] > vmax:
                kmax, vmax = i, x[i]
    minimum[col, m], maximum[col, m], argmin[col, m], argmax[col, m] = vmin, vmax, kmin, kmax


def _keep2(Wr, Wi, Rr, Ri, pr, pi, good, ax, ay, minimum, maximum, argmin, argmax, col, m):  # pragma: no cover
    """Row ``m``'s extremes of columns ``col`` and ``col + 1``: the x and y of the point ``W + R·p`` (placed in
    ``ax``, ``ay`` first, in one pass without branches)."""
    for i in range(good.size):
        ax[i] = Wr[i] + (Rr[i] * pr - Ri[i] * pi)
        ay[i] = Wi[i] + (Rr[i] * pi + Ri[i] * pr)
    _keep(ax, good, minimum, maximum, argmin, argmax, col, m)
    _keep(ay, good, minimum, maximum, argmin, argmax, col + 1, m)
