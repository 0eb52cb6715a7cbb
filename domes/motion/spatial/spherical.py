"""The spherical four-bar in closed form: output angle, both assembly modes, rates, motion type.

Four revolute axes through one centre: the input axis ``v`` (ground–input),
the input's moving axis ``u0`` (input–coupler), the output's moving axis
``w0`` (coupler–output) and the output axis ``vs`` (ground–output), unit
vectors in the drawn pose. Turning the input by θ about ``v`` moves ``u0`` to
``u(θ)``; the output turns by ψ about ``vs``; the coupler keeps the angle
between its two axes: ``u(θ)·w(ψ) = u0·w0``, which is

    A cos ψ + B sin ψ = C,   ψ = atan2(B, A) ± acos(C / √(A² + B²))

(digest seed-004 §2.7, the spherical image of an RCCC). It assembles where
``A² + B² ≥ C²``; that discriminant is a trigonometric polynomial of degree
two in θ, so the ranges where it is negative (:meth:`SphericalFourBar.gaps`)
are found exactly. Rates follow from the same condition differentiated.

>>> import numpy as np
>>> s = SphericalFourBar.make((1, 0, 0), (0.6, 0.8, 0), (0.1, 0.4, 0.9), (0.3, 0.3, 0.9))
>>> round(float(s.psi(0.0)), 12)
0.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.spatial import SpatialMechanism
from domes.motion.spatial.trig import negative

#: Rounding of the discriminant, in units of ε times ``A² + B² + C²``: a dip no deeper is a tangency, not a gap.
ROUNDING = 64


def _rotate(axis, angle, x):
    angle = np.asarray(angle, dtype=float)[..., None]
    return x * np.cos(angle) + np.cross(axis, x) * np.sin(angle) + axis * (axis @ x) * (1 - np.cos(angle))


@dataclass(frozen=True)
class SphericalFourBar:
    """Input axis ``v``, output axis ``vs``, the coupler's axes ``u0`` (on the input) and ``w0`` (on the
    output) in the drawn pose (unit vectors through the centre)."""

    v: np.ndarray
    u0: np.ndarray
    w0: np.ndarray
    vs: np.ndarray

    @classmethod
    def make(cls, v, u0, w0, vs) -> "SphericalFourBar":
        vecs = [np.asarray(x, float) for x in (v, u0, w0, vs)]
        if any(np.linalg.norm(x) == 0 for x in vecs):
            raise InputError("a spherical four-bar's axes need directions")
        return cls(*(x / np.linalg.norm(x) for x in vecs))

    @classmethod
    def of(cls, mech: SpatialMechanism) -> "SphericalFourBar":
        """The closed form of a file that is a spherical four-bar: four R joints whose axes meet in one point,
        the input on the ground."""
        if len(mech.links) != 4 or sorted(j.kind for j in mech.joints) != ["R"] * 4 or len(mech.inputs) != 1:
            raise InputError(f"{mech.name}: not a spherical four-bar (four links, four R joints, one input)")
        drive = mech.joint(mech.inputs[0].joint)
        other = next(j for j in mech.joints if mech.ground in j.links and j.name != drive.name)
        inner = [j for j in mech.joints if mech.ground not in j.links]
        # the axes must meet in one point: least-squares centre of the four lines
        A, b = np.zeros((3, 3)), np.zeros(3)
        for j in mech.joints:
            u = np.asarray(j.axis)
            P = np.eye(3) - np.outer(u, u)
            A += P
            b += P @ np.asarray(j.at)
        centre = np.linalg.solve(A, b)
        miss = max(np.linalg.norm((np.eye(3) - np.outer(j.axis, j.axis)) @ (centre - np.asarray(j.at)))
                   for j in mech.joints)
        if miss > 1e-9 * mech.size:
            raise InputError(f"{mech.name}: the four axes do not meet in one point (they miss by {miss:.3g})")
        crank = next(x for x in drive.links if x != mech.ground)
        a = next(j for j in inner if crank in j.links)
        c = next(j for j in inner if j.name != a.name)
        sign = lambda j: 1.0 if j.links[0] == mech.ground else -1.0  # noqa: E731  a joint turns its second link
        return cls.make(sign(drive) * np.asarray(drive.axis), a.axis, c.axis, sign(other) * np.asarray(other.axis))

    def coefficients(self, theta):
        u = _rotate(self.v, theta, self.u0)
        base = self.w0 - (self.w0 @ self.vs) * self.vs
        side = np.cross(self.vs, self.w0)
        A = u @ base
        B = u @ side
        C = float(self.u0 @ self.w0) - float(self.w0 @ self.vs) * (u @ self.vs)
        return A, B, C

    def psi(self, theta, branch: int | None = None):
        """The output angle at input ``theta`` on ``branch`` (±1; default the drawn pose's); NaN where it does
        not assemble."""
        A, B, C = self.coefficients(theta)
        r = np.hypot(A, B)
        with np.errstate(invalid="ignore", divide="ignore"):
            spread = np.arccos(C / r)
        branch = self.drawn_branch() if branch is None else branch
        return np.arctan2(B, A) + branch * spread

    def drawn_branch(self) -> int:
        A, B, C = self.coefficients(0.0)
        phase, spread = math.atan2(B, A), math.acos(max(-1.0, min(1.0, C / math.hypot(A, B))))
        return 1 if abs(math.remainder(phase + spread, 2 * math.pi)) <= abs(math.remainder(phase - spread, 2 * math.pi)) \
            else -1

    def rates(self, theta, psi, speed: float, acceleration: float = 0.0):
        """``ψ̇, ψ̈`` from ``u(θ)·w(ψ) = const`` differentiated once and twice."""
        u = _rotate(self.v, theta, self.u0)
        w = _rotate(self.vs, psi, self.w0)
        du = np.cross(self.v, u)
        dw = np.cross(self.vs, w)
        ddu = np.cross(self.v, du)
        ddw = np.cross(self.vs, dw)
        dot = lambda x, y: np.einsum("...i,...i", x, y)  # noqa: E731
        den = dot(u, dw)
        pd = -speed * dot(du, w) / den
        pdd = -(acceleration * dot(du, w) + speed ** 2 * dot(ddu, w) + 2 * speed * pd * dot(du, dw)
                + pd ** 2 * dot(u, ddw)) / den
        return pd, pdd

    def discriminant(self, theta):
        """``A² + B² − C²``: the linkage assembles at ``theta`` where it is ≥ 0 (the two modes meet at 0)."""
        A, B, C = self.coefficients(theta)
        return A * A + B * B - C * C

    def gaps(self) -> tuple[tuple[float, float], ...]:
        """The input angle ranges (rad, in [0, 2π]) where the linkage does not assemble, found exactly: the
        discriminant is a trigonometric polynomial of degree two (:func:`~domes.motion.spatial.trig.negative`);
        a dip no deeper than its rounding (a change point) is no gap."""
        A, B, C = self.coefficients(np.arange(8) * math.pi / 4)
        floor = ROUNDING * np.finfo(float).eps * float(np.max(A * A + B * B + C * C))
        return negative(self.discriminant, floor)

    def input_turns_fully(self) -> bool:
        """Whether the input can turn fully: the linkage assembles at every θ (no gap, found exactly).

        >>> SphericalFourBar.make((0, 0, 1), (0.1, 0, 1), (0.5, 0.5, 1), (0.6, 0, 1)).input_turns_fully()
        True
        """
        return not self.gaps()


__all__ = ["SphericalFourBar"]
