"""Walking a compiled query on arrays: branch continuity, dead points and bifurcations.

A :class:`Walker` places the mechanism at a whole array of inputs at once
(:func:`~domes.motion.planar.arrays.positions_many`) and touches scalar
code only where a decision is needed: at the first configuration that
cannot be solved it hands the one interval to
:meth:`~domes.motion.planar.continuation.Continuation.reach`, which halves
the step and either passes or locates the dead point; and where a dyad's
root (the normalised discriminant of its closed form, see
:mod:`~domes.motion.planar.kernel`) dips to zero in a V, two assembly modes
meet: a change or branch point (a bifurcation). There the walker locates
the input by shrinking a bracket on dense samples and follows the branch
on which the velocities are continuous, as the mechanism's inertia would:
it compares the rates just before the point with those just after it on
both branches. The parallelogram four-bar passes such a point twice a turn.

>>> import math
>>> from domes.motion.planar.examples import parallelogram
>>> from domes.motion.planar.query import Kinematics
>>> from domes.motion.planar.arrays import Compiled
>>> from domes.motion.planar.continuation import Continuation
>>> kin = Kinematics(parallelogram(), outputs=["angle:rocker"])
>>> walker = Walker(Continuation(kin), Compiled(kin))
>>> w = walker.walk(dict(kin.structure.drawn), 1.0, np.radians(np.arange(60, 421, 5)))
>>> [(str(d.kind), round(math.degrees(d.input), 6)) for d in w.branch_points]
[('bifurcation', 180.0), ('bifurcation', 360.0)]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from domes.motion.planar.arrays import Compiled, motion_many, positions_many
from domes.motion.planar.continuation import Continuation, DeadPoint, DeadPointKind, Stuck
from domes.motion.planar.kernel import SIGNED
from domes.motion.planar.query import FailureKind, sign_key

#: A normalised root below this cannot be told from zero (its square is computed to a few ε).
ROOT_FLOOR = 1e-7
#: Points evaluated at once (bounds the memory of very long sweeps).
CHUNK = 1 << 16
#: Samples per round when a branch point is located (each round shrinks the bracket eightfold).
SAMPLES = 17
#: Brent's relative tolerance on a located limit (the least :func:`scipy.optimize.brentq` accepts).
RTOL = 4 * np.finfo(float).eps
#: Rounding of a dyad's assembly margin, in units of ε times the mechanism's size: the margin is a difference of
#: lengths each computed through a few rotations and sums of the drawn coordinates (a generous bound).
MARGIN_ROUNDING = 64


@dataclass(frozen=True)
class Gap:
    """The walk's arrays stepped over inputs that do not assemble: ``input`` is the first such one sampled."""

    input: float


@dataclass
class Walk:
    """What a walk reached: ``values`` (variable -> array over the points reached), the end state, dead points.

    ``stuck`` is the :class:`~domes.motion.planar.continuation.Stuck` where
    it could not go on (None when every point was reached);
    ``branch_points`` the bifurcations passed, as dead points.
    """

    values: dict
    count: int
    state: dict
    stuck: Stuck | None = None
    branch_points: list = field(default_factory=list)


class Walker:
    """Walks one input of a compiled query of drivers and dyads over arrays of input values."""

    def __init__(self, cont: Continuation, compiled: Compiled):
        self.cont = cont
        self.compiled = compiled
        self.kin = kin = cont.kin
        self.signed = [g for g in kin.groups if g.index in kin.plans and kin.plans[g.index].kind in SIGNED]
        self.seen: list[float] = []
        self.scale = 1.0 if cont.angular else kin.size

    def positions(self, xs, state):
        return positions_many(self.compiled, self.cont.joint, xs, state, self.cont.fixed)

    def walk(self, state: dict, qa: float, pts, tick=None) -> Walk:
        """Walk from the configuration ``state`` at input ``qa`` through the input values ``pts`` (monotone).

        One point beyond the last is evaluated too (never kept), so that a
        branch point just before the end is seen and passed.
        """
        pts = np.asarray(pts, dtype=float)
        pieces: list[dict] = []
        lead = [(qa, state)]
        found: list[DeadPoint] = []
        i, n = 0, pts.size
        ext = pts
        if n:
            prev = pts[-2] if n > 1 else qa
            spacing = min(abs(pts[-1] - prev), self.cont.h)
            if spacing > 0:
                ext = np.append(pts, pts[-1] + math.copysign(spacing, pts[-1] - prev))
        while i < n:
            xs = np.concatenate(([x for x, _ in lead], ext[i:i + CHUNK]))
            first = len(lead)
            real = first + n - i  # xs[real:] is the probe beyond the last point
            run = self.positions(xs, lead[0][1])
            failed = max(run.failure[0], first) if run.failure else xs.size
            turn = self._bifurcation(xs, run, first, failed, found, pts[-1])
            if isinstance(turn, Gap):
                # the last point before the gap; the scalar code walks into it and locates its first limit
                direction = 1.0 if xs[-1] >= xs[0] else -1.0
                j = max((k for k in range(min(failed, xs.size)) if (turn.input - xs[k]) * direction > 0), default=0)
                pieces.append(_piece(run, first, j + 1))
                i += max(j + 1 - first, 0)
                base = run.state(j)
                try:
                    self.cont.reach(base, xs[j], turn.input)
                except Stuck as st:
                    return Walk(self._join(pieces), i, base, st, found)
                lead = [(xs[k], run.state(k)) for k in range(max(j - 1, 0), j + 1)]
                continue
            if turn is not None:
                kk, q, state = turn
                pieces.append(_piece(run, first, kk))
                i += kk - first
                lead = [(q, state)]
                continue
            end = min(failed, real)
            if end == xs.size and i + end - first < ext.size:
                end -= 1  # hold the last point back: a V there is judged with the next points
            pieces.append(_piece(run, first, end))
            i += end - first
            lead = [(xs[k], run.state(k)) for k in range(max(end - 2, 0), end)]
            if end == failed < real:  # the arrays could not go on: the scalar code decides this interval
                last = lead[-1][1]
                try:
                    nxt = self.cont.reach(last, xs[end - 1], xs[end])
                except Stuck as st:
                    return Walk(self._join(pieces), i, last, st, found)
                pieces.append({v: np.array([value]) for v, value in nxt.items()})
                i += 1
                lead = [(xs[end - 1], last), (xs[end], nxt)]
            if tick:
                tick(i, n)
        return Walk(self._join(pieces), n, lead[-1][1], None, found)

    # -- limits ---------------------------------------------------------------------------

    def limit(self, st: Stuck) -> DeadPoint | None:
        """The limit where the walk stuck, located by Brent's method on the failing dyad's assembly margin.

        The margin (a length, positive where the dyad assembles) is bracketed
        between the walk's last solved input (moved back until the margin is
        positive, should the dyad's rounding slack have let the walk a little
        beyond the limit) and the input it could not reach. ``within`` is
        Brent's tolerance (half the accuracy's ``locate``) plus the rounding
        of the margin over its slope. None when the walk stuck for another
        reason (no dyad's margin changes sign there).
        """
        f = st.failure
        g = getattr(f, "group", None)
        if f.kind != FailureKind.LIMIT or g is None or g.index not in self.kin.plans or \
                self.kin.plans[g.index].kind not in SIGNED:
            return None
        base = st.state

        def margin(x):
            run = self.positions(np.array([x]), base)
            return float(run.margins[g.index][0]) if g.index in run.margins else math.nan

        good, bad = float(st.good), float(st.bad)
        direction = 1.0 if bad >= good else -1.0
        step = max(abs(bad - good), 1e-3 * self.cont.locate)
        fg, fb = margin(good), margin(bad)
        while not fg >= 0.0 and step <= self.cont.h:  # the slack let the walk past the limit: step back
            good -= direction * step
            fg = margin(good)
            step *= 2
        if not (fg >= 0.0 and fb < 0.0):
            return None
        xtol = 0.5 * self.cont.locate
        root = good if fg == 0.0 else brentq(margin, good, bad, xtol=xtol, rtol=RTOL)
        wide = max(abs(bad - good), 1e-6 * self.scale)
        slope = abs(margin(root - direction * wide) - margin(root + direction * wide)) / (2 * wide)
        rounding = MARGIN_ROUNDING * np.finfo(float).eps * self.kin.size / slope if slope > 0 else math.inf
        if not math.isfinite(rounding):
            return None
        within = xtol + RTOL * abs(root) + rounding
        c = self.cont
        return DeadPoint(root, within, DeadPointKind.LIMIT, g.label, g.joints,
                         f"{f}; the input cannot pass {c.fmt(root)} ± {c.fmt(within)} (the root of the dyad's "
                         f"assembly condition, by Brent's method; last solved {c.fmt(st.good)}): a limit (dead) "
                         "position")

    # -- bifurcations --------------------------------------------------------------------

    def on_branch_point(self, state: dict, q: float, end: str, known=()) -> list[DeadPoint]:
        """A walk that starts or ends (``end``) exactly on a branch point cannot choose a branch there: say so.

        ``known`` are the dead points already reported (none is reported twice).
        """
        run = self.positions(np.array([q]), state)
        out = []
        for g in self.signed:
            if run.failure is None and run.roots[g.index][0] <= ROOT_FLOOR and \
                    not any(abs(d.input - q) <= d.within for d in known):
                out.append(DeadPoint(q, 4 * math.sqrt(2.2e-16) * self.scale, DeadPointKind.BIFURCATION, g.label,
                                     g.joints, f"{g.label}: the sweep {end} on a branch point at input "
                                     f"{self.cont.fmt(q)} (joints {', '.join(g.joints)}): two assembly modes meet "
                                     "there; the sweep stays in the mode it came in (or was drawn in)"))
        return out

    def _bifurcation(self, xs, run, first, end, found, last):
        """Locate the next V-shaped zero of a dyad's root; on a change of branch return ``(index, input, state)``.

        ``index`` is the first point past the branch point, ``state`` the
        configuration at it with the new assembly mode. A branch point at or
        beyond ``last`` (the walk's last point) is not passed, so not reported.
        """
        direction = 1.0 if xs[-1] >= xs[0] else -1.0
        while True:
            cand = self._candidate(xs, run, first, end)
            if cand is None:
                return None
            k, g = cand
            located = self._locate(xs, run, k, g)
            if isinstance(located, Gap):
                if (last - located.input) * direction >= 0:
                    return located
                continue  # the gap begins beyond the walk's last point
            q, within, is_zero = located
            if not is_zero or (last - q) * direction <= within:
                continue  # not a branch point, or not passed (the walk ends on or before it)
            at = self.positions([q], run.state(k - 1))
            if at.failure is not None:
                return Gap(q)
            here = at.state(0)
            flip, text = self._follow(here, q, within, xs[k + 1] - xs[k - 1], g)
            found.append(DeadPoint(q, within, DeadPointKind.BIFURCATION, g.label, g.joints, text))
            if flip:
                kk = next((j for j in range(k - 1, end) if (xs[j] - q) * direction > within), end)
                here[sign_key(g)] = -here.get(sign_key(g), self.kin.plans[g.index].sign)
                return kk, q, here

    def _candidate(self, xs, run, first, end):
        """The first interior local minimum of a root that looks like a V reaching zero (not yet examined)."""
        best = None
        for g in self.signed:
            r = run.roots[g.index][:end]
            if r.size < 3:
                continue
            k = np.arange(1, r.size - 1)
            dx = np.abs(np.diff(xs[:end]))
            with np.errstate(invalid="ignore", divide="ignore"):  # a repeated point (dx = 0) is no candidate
                slope = np.maximum(np.abs(r[k] - r[k - 1]) / dx[k - 1], np.abs(r[k + 1] - r[k]) / dx[k])
            v = (r[k] <= r[k - 1]) & (r[k] <= r[k + 1]) & (r[k] <= slope * np.maximum(dx[k - 1], dx[k]) + ROOT_FLOOR)
            v &= k >= first
            for kk in k[v]:
                lo, hi = sorted((xs[kk - 1], xs[kk + 1]))
                if any(lo <= s <= hi for s in self.seen):
                    continue
                if best is None or kk < best[0]:
                    best = (int(kk), g)
                break
        return best

    def _locate(self, xs, run, k, g):
        """``(input, within, is_zero)`` of the root's minimum in ``(xs[k-1], xs[k+1])``, or a :class:`Gap` where a
        sample there does not assemble (or would jump)."""
        r = run.roots[g.index]
        with np.errstate(divide="ignore", invalid="ignore"):  # a repeated input (a zero step): an infinite slope
            slope = max(abs(r[k] - r[k - 1]) / abs(xs[k] - xs[k - 1]), abs(r[k + 1] - r[k]) / abs(xs[k + 1] - xs[k]))
        lo, hi, base = xs[k - 1], xs[k + 1], run.state(k - 1)
        q, rmin = xs[k], r[k]
        self.seen.append(q)
        while abs(hi - lo) > self.cont.locate and rmin > 0.0:
            ts = np.linspace(lo, hi, SAMPLES)
            sub = self.positions(ts, base)
            if sub.failure is not None:
                self.seen[-1] = q
                return Gap(float(ts[sub.failure[0]]))
            rr = sub.roots[g.index]
            j = int(np.argmin(rr))
            q, rmin = ts[j], rr[j]
            j0, j1 = max(j - 1, 0), min(j + 1, SAMPLES - 1)
            lo, hi, base = ts[j0], ts[j1], sub.state(j0)
        self.seen[-1] = q
        width = abs(hi - lo) if rmin > 0.0 else 0.0
        floor = ROOT_FLOOR / slope if slope > 0 else 0.0
        within = max(width / 2, rmin / slope if slope > 0 else 0.0, floor, 4 * math.sqrt(2.2e-16) * self.scale)
        return q, within, rmin <= max(10 * slope * width, ROOT_FLOOR)

    def _follow(self, here, q, within, span, g):
        """Whether to change the dyad's assembly mode at the branch point ``q``, and the dead point's text.

        ``here`` is the configuration at ``q``. The rates of the group's
        variables a little before ``q`` are compared with those a little
        after it on each branch; the branch whose rates continue them is followed.
        """
        direction = 1.0 if span >= 0 else -1.0
        delta = max(min(1e-4 * self.scale, abs(span) / 4), 4 * within)
        flipped = {**here, sign_key(g): -here.get(sign_key(g), self.kin.plans[g.index].sign)}
        rate0 = self._rates(here, q - direction * delta, g)
        gaps = []
        for start in (here, flipped):
            rate1 = self._rates(start, q + direction * delta, g)
            gaps.append(math.inf if rate0 is None or rate1 is None else float(np.max(np.abs(rate1 - rate0))))
        flip = gaps[1] < 0.5 * gaps[0]
        text = (f"{g.label}: branch point at input {self.cont.fmt(q)} (joints {', '.join(g.joints)}): two assembly "
                f"modes meet here; the sweep {'changes' if flip else 'keeps'} the dyad's assembly mode, following "
                f"the branch on which the velocities are continuous (rates differ by {min(gaps):.2g} on it, "
                f"{max(gaps):.2g} on the other)")
        return flip, text

    def _join(self, pieces) -> dict:
        """One array per variable over all pieces (an assembly mode not yet changed is the drawn one)."""
        pieces = [p for p in pieces if p and len(next(iter(p.values()))) > 0]
        if not pieces:
            return {}
        keys = set().union(*pieces)
        drawn = {sign_key(g): self.kin.plans[g.index].sign for g in self.signed}
        return {v: np.concatenate([p[v] if v in p else np.full(len(next(iter(p.values()))), drawn.get(v, np.nan))
                                   for p in pieces]) for v in keys}

    def _rates(self, state, x, g):
        """The group's rates (slides over the size) at input ``x``, reached from ``state``; None if not solvable."""
        run = self.positions(np.array([x]), state)
        if run.failure is not None:
            return None
        rates = motion_many(self.kin, run.values, 1)[0]
        return np.array([rates[v][0] / (1.0 if v.startswith("rot:") else self.kin.size) for v in g.unknowns])


def _piece(run, lo, hi) -> dict:
    """The values of ``run`` at points ``lo .. hi − 1`` (scalars repeated)."""
    out = {}
    for v, a in run.values.items():
        out[v] = a[lo:hi] if isinstance(a, np.ndarray) and a.ndim else np.full(max(hi - lo, 0), float(a))
    return out


