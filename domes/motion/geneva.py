"""The external Geneva wheel: intermittent rotation from a turning crank, in closed form (issue 26, item 7).

A crank of radius ``r`` turns about ``O``; its pin enters the radial slots
of a wheel of ``n`` slots about ``W`` at a distance ``c`` (entering
tangentially: ``r = c sin(π/n)``). With the crank angle ``θ`` measured from
``O→W``, the pin is in a slot while ``|θ| ≤ α = π/2 − π/n`` and the wheel
turns by ``β`` with ``tan β = λ sin θ / (1 − λ cos θ)``, ``λ = r/c``; the rest
of the turn (``2π − 2α = π + 2π/n``) it dwells, locked. Over a crank turn the
wheel indexes ``2π/n``.

>>> g = Geneva(4)
>>> round(math.degrees(g.index_angle), 9), round(math.degrees(g.dwell_angle), 9)
(90.0, 270.0)
>>> b = g.wheel([-g.index_angle / 2, g.index_angle / 2])[0]     # pin entering and leaving: one index
>>> round(math.degrees(float(b[1] - b[0])), 9)
90.0
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError


@dataclass(frozen=True)
class Geneva:
    """An external Geneva drive of ``slots`` slots, wheel centre ``centre_distance`` from the crank's."""

    slots: int
    centre_distance: float = 1.0

    def __post_init__(self):
        if not (isinstance(self.slots, int) and self.slots >= 3):
            raise InputError(f"a Geneva wheel needs 3 or more slots, got {self.slots!r}")
        if not (isinstance(self.centre_distance, (int, float)) and math.isfinite(self.centre_distance)
                and self.centre_distance > 0):
            raise InputError(f"the centre distance must be a number > 0, got {self.centre_distance!r}")

    @property
    def ratio(self) -> float:
        """``λ = r/c = sin(π/n)``."""
        return math.sin(math.pi / self.slots)

    @property
    def crank(self) -> float:
        return self.centre_distance * self.ratio

    @property
    def index_angle(self) -> float:
        """The crank angle over which the wheel moves: ``π − 2π/n``."""
        return math.pi - 2 * math.pi / self.slots

    @property
    def dwell_angle(self) -> float:
        """The crank angle over which the wheel rests: ``π + 2π/n``."""
        return 2 * math.pi - self.index_angle

    def wheel(self, theta) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The wheel's angle and its first two derivatives in the crank angle, at ``theta`` (rad, from ``O→W``).

        The angle counts whole indexes: ``2π/n`` per crank turn (the wheel turns
        the other way from the crank; its angle is given positive). The
        acceleration jumps where the pin enters and leaves a slot.
        """
        theta = np.asarray(theta, dtype=float)
        lam = self.ratio
        turns = np.floor((theta + math.pi) / (2 * math.pi))
        t = theta - 2 * math.pi * turns                        # in [−π, π)
        step = 2 * math.pi / self.slots
        alpha = self.index_angle / 2
        engaged = np.abs(t) <= alpha
        d = 1 - 2 * lam * np.cos(t) + lam * lam
        inside = np.arctan2(lam * np.sin(t), 1 - lam * np.cos(t))
        beta = np.where(engaged, inside, np.sign(t) * step / 2) + step * turns
        rate = np.where(engaged, lam * (np.cos(t) - lam) / d, 0.0)
        accel = np.where(engaged, -lam * np.sin(t) * (1 - lam * lam) / (d * d), 0.0)
        return beta, rate, accel

    def peak(self) -> tuple[float, float]:
        """The largest wheel speed and acceleration per unit crank speed (and its square)."""
        lam = self.ratio
        t = np.linspace(-self.index_angle / 2, self.index_angle / 2, 20001)
        _, rate, accel = self.wheel(t)
        return lam / (1 - lam), float(np.max(np.abs(accel)))
