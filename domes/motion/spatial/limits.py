"""Limits of a spatial sweep located to a precision they state, and the closed forms that keep a walk on its branch.

A walk (:func:`~domes.motion.spatial.sweep.spatial_sweep`) stops where
Newton's method cannot take a step, which near a fold of the loop lies short
of the true limit. The limit is then located anew:

- for a mechanism with a closed form (the RSSR of seed 001, the spherical
  four-bar: :func:`closed_form`), as the root of its discriminant next to the
  last pose, bracketed and found by Brent's method (:func:`closed_limit`);
- otherwise (:func:`fold_limit`) by driving, instead of the input, the joint
  variable that moves fastest there: along it the loop passes the fold
  smoothly and the input's rate changes sign at the limit, a root that
  Brent's method brackets; the input there is the limit, to second order in
  the bracket.

Either states its precision: Brent's tolerance plus the rounding of the
function whose root it is over that function's slope.

>>> import math
>>> from domes.motion.spatial.examples import rssr
>>> cf = closed_form(rssr(L3=300.0))
>>> x, within = closed_limit(cf, 1.84, 1.0)
>>> cf.kind, round(x, 12), within < 1e-12
('RSSR', 1.84315947113, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialInput, SpatialMechanism
from domes.motion.spatial.trig import touches

TAU = 2 * math.pi
#: Brent's absolute tolerance on a limit of a closed form (rad).
EXACT = 1e-13
#: Brent's relative tolerance (the least :func:`scipy.optimize.brentq` accepts).
RTOL = 4 * np.finfo(float).eps
#: How far from the walk's last pose the closed form looks for the limit (rad).
BEYOND = 0.05
#: Rounding of a discriminant ``E² + F² − G²`` in units of ε times ``E² + F² + G²`` (a generous bound).
ROUNDING = 64
#: Brent's tolerance on the driving joint's variable when a limit is located without a closed form.
FOLD_XTOL = 1e-12


@dataclass(frozen=True)
class ClosedForm:
    """A mechanism's closed form as a sweep uses it: ``kind`` (``RSSR`` or ``spherical four-bar``), the ``output``
    joint whose angle it gives, the ``form`` itself (:class:`~domes.motion.spatial.rssr.RSSR` or
    :class:`~domes.motion.spatial.spherical.SphericalFourBar`)."""

    kind: str
    output: str
    form: object

    def parts(self, q):
        """The discriminant at input ``q`` (≥ 0 where the linkage assembles) and the sum of its squares."""
        a, b, c = self.form.coefficients(q)
        return a * a + b * b - c * c, a * a + b * b + c * c

    def angle(self, q, branch: int) -> float:
        """The output joint's angle at input ``q`` on ``branch`` (±1)."""
        f = self.form
        return float(f.beta(q, branch) if self.kind == "RSSR" else f.psi(q, branch))

    def branches(self, q) -> tuple[float, float]:
        """The output angle on branch +1 and on branch −1."""
        return self.angle(q, 1), self.angle(q, -1)

    @property
    def drawn_branch(self) -> int:
        return self.form.drawn_branch()

    def meetings(self) -> tuple[float, ...]:
        """The inputs in ``[0, 2π)`` where the two assembly modes meet: the discriminant touches zero (to its
        rounding) without going below (:func:`~domes.motion.spatial.trig.touches`); change points."""
        squares = max(float(self.parts(x)[1]) for x in np.arange(8) * TAU / 8)
        return touches(lambda x: float(self.parts(x)[0]), ROUNDING * np.finfo(float).eps * squares)

    def next_meeting(self, q0: float, q1: float, meetings) -> float | None:
        """The first of ``meetings`` (this form's, in [0, 2π)) met going from ``q0`` to ``q1``: ``q0`` itself
        included, ``q1`` included; as an input next to ``q0``; None if none."""
        direction = 1.0 if q1 >= q0 else -1.0
        ahead = [(math.remainder(m - q0, TAU) * direction) % TAU for m in meetings]
        ahead = [0.0 if d > TAU - 1e-12 else d for d in ahead]
        best = min((d for d in ahead if d <= abs(q1 - q0)), default=None)
        return None if best is None else q0 + direction * best

    def crosses_gap(self, q0: float, q1: float, gaps) -> bool:
        """Whether inputs between ``q0`` and ``q1`` fall in one of ``gaps`` (this form's, in [0, 2π])."""
        lo, hi = min(q0, q1), max(q0, q1)
        turn = math.floor(lo / TAU)
        return any(a + k * TAU < hi and lo < b + k * TAU for a, b in gaps for k in (turn - 1, turn, turn + 1))


def closed_form(mech: SpatialMechanism) -> ClosedForm | None:
    """The closed form of ``mech`` when it is an RSSR or a spherical four-bar driven at a ground joint, else None."""
    from domes.motion.spatial.rssr import RSSR
    from domes.motion.spatial.spherical import SphericalFourBar

    if len(mech.inputs) != 1 or len(mech.links) != 4:
        return None
    drive = mech.joint(mech.inputs[0].joint)
    if drive.kind != "R" or mech.ground not in drive.links:
        return None
    others = [j for j in mech.joints if j.kind == "R" and mech.ground in j.links and j.name != drive.name]
    for kind, make in (("RSSR", RSSR.of), ("spherical four-bar", SphericalFourBar.of)):
        try:
            form = make(mech)
        except (InputError, StopIteration, ValueError, np.linalg.LinAlgError):
            continue
        if len(others) == 1:
            return ClosedForm(kind, others[0].name, form)
    return None


def closed_limit(cf: ClosedForm, q: float, direction: float) -> tuple[float, float] | None:
    """The limit next to ``q`` going ``direction`` (±1): the root of the discriminant, and how closely it is known.

    The root is bracketed by doubling from ``q`` (backwards first when the
    closed form says ``q`` itself is just beyond it, by rounding) and found by
    Brent's method to :data:`EXACT`; ``within`` adds the discriminant's
    rounding over its slope. None when the linkage assembles for
    :data:`BEYOND` rad past ``q``.
    """
    def d(x):
        return float(cf.parts(q + direction * x)[0])

    if d(0.0) >= 0.0:
        near, far = 0.0, 1e-12
        while far <= BEYOND and d(far) >= 0.0:
            near, far = far, 2 * far
        if far > BEYOND:
            return None
    else:  # rounding let the walk a hair past the root
        far, near = 0.0, -1e-12
        while near >= -BEYOND and d(near) < 0.0:
            far, near = near, 2 * near
        if near < -BEYOND:
            return None
    root = brentq(d, near, far, xtol=EXACT, rtol=RTOL)
    x = q + direction * root
    wide = max(abs(far - near), 1e-9)
    slope = abs(d(root + wide) - d(root - wide)) / (2 * wide)
    scale = float(cf.parts(x)[1])
    rounding = ROUNDING * np.finfo(float).eps * scale / slope if slope > 0 else math.inf
    return x, float(EXACT + RTOL * abs(x) + rounding)


def fold_limit(kin, state, joint: str, q: float, direction: float, values: dict) -> tuple[float, float, str] | None:
    """The limit of the input ``joint`` next to its value ``q`` (rad or length; pose ``state``) going ``direction``.

    The joint variable with the largest rate there drives instead; the
    input's rate along it changes sign at the fold: Brent's method on that
    rate (bracketed by doubling steps of the driving variable) places the
    fold, and the input's value there is the limit. Returns ``(limit, within,
    driving joint)``; ``within`` is the input's spread over Brent's final
    tolerance plus its rounding (ε times the condition number with the new
    driver). None when no variable passes the fold.
    """
    driven = next(i for i in kin.inputs if i.joint == joint)
    angular = driven.variable == "angle"
    unit = 1.0 if angular else kin.scale
    speeds = {kin.key(i): (1.0 if i.joint == joint else 0.0) for i in kin.inputs}
    try:
        xd, _ = kin.motion(state, 1, speeds)
    except (np.linalg.LinAlgError, ValueError):
        return None
    best = None
    for j in kin.mech.joints:
        for var in j.variables:
            if any(i.joint == j.name and i.variable == var for i in kin.inputs):
                continue
            rate = float(kin._variable(j.name, var, state)[1] @ xd)
            if best is None or abs(rate) > abs(best[2]):
                best = (j.name, var, rate)
    if best is None or not best[2]:
        return None
    name, var, rate = best
    new = SpatialInput(name, var, 1.0)
    fixed = [i for i in kin.inputs if i.joint != joint]
    alt = kin.driven_by([new, *fixed])
    key = alt.key(new)
    rest = {alt.key(i): values.get(kin.key(i), 0.0) for i in fixed}
    alt_speeds = {key: 1.0, **{k: 0.0 for k in rest}}
    t0 = float(kin._variable(name, var, state)[0])
    a0 = float(kin._variable(joint, driven.variable, state)[0])
    toward = math.copysign(1.0, rate) * direction

    def input_of(s) -> float:
        a = float(kin._variable(joint, driven.variable, s)[0])
        return q + (math.remainder(a - a0, 2 * math.pi) if angular else (a - a0) * unit)

    states = {t0: state}

    def solve(t):
        near = min(states, key=lambda x: abs(x - t))
        s, _ = alt.positions({key: t, **rest}, states[near])
        states[t] = s
        return s

    def g(t) -> float:
        s = solve(t)
        xd2, _ = alt.motion(s, 1, alt_speeds)
        return direction * toward * float(kin._variable(joint, driven.variable, s)[1] @ xd2)

    try:
        if not g(t0) > 0:
            return None
        step = 1e-9
        lo = t0
        while True:
            hi = t0 + toward * step
            if g(hi) <= 0:
                break
            lo, step = hi, 2 * step
            if step > 0.5:
                return None
        t = brentq(g, lo, hi, xtol=FOLD_XTOL, rtol=RTOL)
        limit = input_of(solve(t))
        spread = max(abs(input_of(solve(t + dt)) - limit) for dt in (-2 * FOLD_XTOL, 2 * FOLD_XTOL))
        cond = alt.condition(states[t])
    except (NumericalError, ValueError, np.linalg.LinAlgError):
        return None
    if not (math.isfinite(limit) and math.isfinite(cond)) or (limit - q) * direction < -spread:
        return None
    return limit, spread + 16 * np.finfo(float).eps * cond * unit * max(1.0, abs(limit) / unit), name


__all__ = ["ClosedForm", "closed_form", "closed_limit", "fold_limit"]
