"""The RSSR linkage in closed form (seed 001, Sun & Zhou), with the digest's corrections.

The crank turns about the axis ``u_a`` through ``A0``, carrying the sphere
centre A (drawn at ``A1``); the rocker about ``u_b`` through ``B0``, carrying
B (drawn at ``B1``); the coupler keeps ``|A − B| = L2``. With ``w = A − B0``
and ``b = B1 − B0`` the coupler condition is linear in cos β and sin β:

    E cos β + F sin β + G = 0,   E = w·(I − Q_b) b,   F = w·(u_b × b),
    G = w·Q_b b − ½ (|w|² + |b|² − L2²)

(eq. (4) with the digest's corrected G: ``Q_{u_b}``, not ``Q_{u_a}``, and the
½ over all three squares). It assembles where ``E² + F² ≥ G²``, with two
modes ``β = 2 atan2(F ± √(E² + F² − G²), E − G)``. Rates from the coupler's
length differentiated once and twice (eqs. (10)–(13), with the minus signs
the print lost). The motion type follows §2.2: the input is a crank when
the linkage assembles at every α, the output when it assembles at every β.

>>> r = RSSR.paper()          # M = N = 700, L1 = 250, L3 = 550, D = 0 (mm)
>>> round(float(r.beta(math.pi)), 7), r.motion_type().kind
(1.1410967, 'crank-rocker')
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.spatial import SpatialMechanism
from domes.motion.spatial.trig import negative

#: Rounding of the discriminant, in units of ε times ``E² + F² + G²``: a dip no deeper is a tangency, not a gap.
ROUNDING = 64


def _rotate(u: np.ndarray, v: np.ndarray, angle):
    """Rotate ``v`` about unit ``u`` by ``angle`` (array of angles → (N, 3))."""
    angle = np.asarray(angle, dtype=float)[..., None]
    return v * np.cos(angle) + np.cross(u, v) * np.sin(angle) + u * (u @ v) * (1 - np.cos(angle))


@dataclass(frozen=True)
class MotionType:
    """``kind``: double-crank, crank-rocker, rocker-crank or double-rocker; the ranges where each side cannot
    assemble (``input_gaps`` in α, ``output_gaps`` in β, rad)."""

    kind: str
    input_gaps: tuple[tuple[float, float], ...]
    output_gaps: tuple[tuple[float, float], ...]


@dataclass(frozen=True)
class RSSR:
    """An RSSR linkage: axes ``ua``, ``ub`` (unit), points ``A0``, ``B0`` on them, drawn sphere centres ``A1``,
    ``B1``, coupler length ``L2`` (default ``|A1 − B1|``)."""

    ua: np.ndarray
    A0: np.ndarray
    A1: np.ndarray
    ub: np.ndarray
    B0: np.ndarray
    B1: np.ndarray
    L2: float

    @classmethod
    def make(cls, ua, A0, A1, ub, B0, B1, L2: float | None = None) -> "RSSR":
        ua, ub = (np.asarray(v, float) / np.linalg.norm(v) for v in (ua, ub))
        A0, A1, B0, B1 = (np.asarray(v, float) for v in (A0, A1, B0, B1))
        return cls(ua, A0, A1, ub, B0, B1, float(np.linalg.norm(A1 - B1)) if L2 is None else float(L2))

    @classmethod
    def paper(cls, M=700.0, N=700.0, L1=250.0, L3=550.0, D=0.0, L2: float | None = None) -> "RSSR":
        """The frame of seed 001 §3: A0 = (0, 0, N) about z, B0 = (M, D, 0) about x; A1 = (L1, 0, N),
        B1 = (M, D + L3, 0). ``L2`` defaults to the paper's implicit coupler ``√((M − L1)² + L3² + N²)``."""
        if L2 is None:
            L2 = math.sqrt((M - L1) ** 2 + L3 ** 2 + N ** 2)
        return cls.make((0, 0, 1), (0, 0, N), (L1, 0, N), (1, 0, 0), (M, D, 0), (M, D + L3, 0), L2)

    @classmethod
    def of(cls, mech: SpatialMechanism) -> "RSSR":
        """The closed form of a mechanism file that is an RSSR: four links, joints R, S, S, R in one loop, the
        input at an R joint on the ground (its angle α; the other R joint's angle is β)."""
        kinds = sorted(j.kind for j in mech.joints)
        if len(mech.links) != 4 or kinds != ["R", "R", "S", "S"] or len(mech.inputs) != 1:
            raise InputError(f"{mech.name}: not an RSSR (four links, joints R, S, S, R, one input)")
        drive = mech.joint(mech.inputs[0].joint)
        other = next(j for j in mech.joints if j.kind == "R" and j.name != drive.name)
        if mech.ground not in drive.links or mech.ground not in other.links or drive.kind != "R":
            raise InputError(f"{mech.name}: an RSSR's two R joints must be on the ground, the input one of them")
        crank = next(x for x in drive.links if x != mech.ground)
        rocker = next(x for x in other.links if x != mech.ground)
        A = next(j for j in mech.joints_of(crank) if j.kind == "S")
        B = next(j for j in mech.joints_of(rocker) if j.kind == "S")
        # a joint's angle turns its second link about its axis relative to its first
        ua = np.asarray(drive.axis) * (1 if drive.links[0] == mech.ground else -1)
        ub = np.asarray(other.axis) * (1 if other.links[0] == mech.ground else -1)
        return cls.make(ua, drive.at, A.at, ub, other.at, B.at)

    # -- positions -----------------------------------------------------------------------------

    def A(self, alpha) -> np.ndarray:
        return self.A0 + _rotate(self.ua, self.A1 - self.A0, alpha)

    def B(self, beta) -> np.ndarray:
        return self.B0 + _rotate(self.ub, self.B1 - self.B0, beta)

    def coefficients(self, alpha):
        """``E, F, G`` of eq. (4) at the crank angles ``alpha``."""
        w = self.A(alpha) - self.B0
        b = self.B1 - self.B0
        Qb = self.ub * (self.ub @ b)
        E = w @ (b - Qb)
        F = w @ np.cross(self.ub, b)
        G = w @ Qb - 0.5 * (np.einsum("...i,...i", w, w) + b @ b - self.L2 ** 2)
        return E, F, G

    def discriminant(self, alpha):
        """``E² + F² − G²``: the linkage assembles at ``alpha`` where it is ≥ 0 (the modes merge at 0)."""
        E, F, G = self.coefficients(alpha)
        return E * E + F * F - G * G

    def beta(self, alpha, branch: int | None = None):
        """The rocker angle at ``alpha`` on ``branch`` (±1; default: the one through β = 0 at α = 0, the drawn
        pose); NaN where it does not assemble."""
        branch = self.drawn_branch() if branch is None else branch
        E, F, G = self.coefficients(alpha)
        with np.errstate(invalid="ignore"):
            root = np.sqrt(E * E + F * F - G * G)
        return 2 * np.arctan2(F + branch * root, E - G)

    def drawn_branch(self) -> int:
        """The branch on which β = 0 at α = 0 (the drawn pose of a file)."""
        values = {s: abs(math.remainder(float(self.beta(0.0, s)), 2 * math.pi)) for s in (1, -1)}
        return min(values, key=values.get)

    def alpha(self, beta, branch: int = 1):
        """The crank angle for a rocker angle (eq. (9) in general form), by the same construction swapped."""
        return RSSR(self.ub, self.B0, self.B1, self.ua, self.A0, self.A1, self.L2).beta(beta, branch)

    # -- rates ---------------------------------------------------------------------------------

    def rates(self, alpha, beta, speed: float, acceleration: float = 0.0):
        """``β̇, β̈`` from the coupler's length differentiated (eqs. (10)–(13), signs corrected)."""
        A, B = self.A(alpha), self.B(beta)
        ra, rb = A - self.A0, B - self.B0
        c = A - B
        ta, tb = np.cross(self.ua, ra), np.cross(self.ub, rb)
        dot = lambda x, y: np.einsum("...i,...i", x, y)  # noqa: E731
        bd = speed * dot(c, ta) / dot(c, tb)
        Ad = speed * ta
        Bd = bd[..., None] * tb
        rel = Ad - Bd
        Add = acceleration * ta + speed ** 2 * np.cross(self.ua, ta)
        Bquad = (bd ** 2)[..., None] * np.cross(self.ub, tb)
        bdd = (dot(rel, rel) + dot(c, Add - Bquad)) / dot(c, tb)
        return bd, bdd

    def singularity(self, alpha, beta):
        """``(A − B)·(u_b × (B − B0))``: zero where β̇ is unbounded (the modes merge; the crank's dead centre)."""
        A, B = self.A(alpha), self.B(beta)
        return np.einsum("...i,...i", A - B, np.cross(self.ub, B - self.B0))

    # -- mobility ------------------------------------------------------------------------------

    def gaps(self, side: str = "input") -> tuple[tuple[float, float], ...]:
        """The angle ranges (rad, in [0, 2π]) of the crank (``input``) or rocker (``output``) where the linkage
        does not assemble: the discriminant is a trigonometric polynomial of degree two, so its sign changes are
        found exactly (:func:`~domes.motion.spatial.trig.negative`, no sampling grid), each end by Brent's method to
        the discriminant's rounding over its slope (about 1e-15 rad where it crosses zero steeply, more at the ends
        of a narrow gap); a dip no deeper than its rounding (a change point) is no gap."""
        link = self if side == "input" else RSSR(self.ub, self.B0, self.B1, self.ua, self.A0, self.A1, self.L2)
        parts = np.array(link.coefficients(np.arange(8) * math.pi / 4))
        floor = ROUNDING * np.finfo(float).eps * float(np.max(np.sum(parts * parts, axis=0)))
        return negative(link.discriminant, floor)

    def motion_type(self) -> MotionType:
        """Crank or rocker on each side (seed 001 §2.2, as the digest makes it implementable)."""
        gi, go = self.gaps("input"), self.gaps("output")
        kind = {(True, True): "double-crank", (True, False): "crank-rocker", (False, True): "rocker-crank",
                (False, False): "double-rocker"}[(not gi, not go)]
        return MotionType(kind, gi, go)


__all__ = ["MotionType", "RSSR"]
