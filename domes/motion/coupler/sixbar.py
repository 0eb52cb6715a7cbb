"""Watt and Stephenson six-bar path generators: their geometry, curves and design space.

Both are a crank-rocker four-bar ``A B C D`` (crank ``A B``, coupler ``B C``,
rocker ``C D``, frame pivots ``A`` and ``D``) with a dyad ``E F G`` added: a
joint ``E`` on a moving link of the four-bar, a link ``E F`` carrying the
tracing point ``P``, and a link ``F G`` pivoted on the frame at ``G``.

- *Stephenson* (Stephenson III): ``E`` on the coupler ``B C``, so the
  frame and the coupler are the two ternary links, joined by three paths
  (crank, rocker, and the dyad): ``E`` moves on a four-bar coupler curve.
- *Watt* (Watt I): ``E`` on the rocker ``C D``, so the rocker and the frame
  are ternary and adjacent (joint ``D``): two four-bars in series, the
  second ``D E F G`` driven by the first's rocker.

Lengths, in a canonical frame ``A = 0``, ``D = (d, 0)``: crank ``a``,
coupler ``b``, rocker ``c``; ``E`` at ``(p, q)`` on its link (along ``B → C``
from ``B``, or along ``D → C`` from ``D``); ``G = (g, h)``; links ``e = |F − E|``
and ``f = |G − F|``; ``P`` at ``(u, v)`` on ``E F`` (along ``E → F`` from ``E``).
``modes`` are the assembly modes of the four-bar and of the dyad (±1).

>>> s = SixBar("watt", (0.3, 1.2, 1.0, 1.0, 0.6, 0.2, 1.0, 1.1, 1.8, 0.9, 0.5, 0.3), (1, 1))
>>> P = s.curve(np.linspace(0, 2 * np.pi, 8, endpoint=False))
>>> bool(np.all(np.isfinite(P)))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import CouplerPoint, Input, Joint, Mechanism

#: The six-bar types, as named in the answers.
KINDS = {"watt": "Watt I six-bar", "stephenson": "Stephenson III six-bar"}
#: The links, frame first; ``tracer`` carries the point ``P``.
LINKS = ("frame", "crank", "coupler", "rocker", "tracer", "link")


def circle_meet(X, Y, r1, r2, sign):
    """The point at ``r1`` from ``X`` and ``r2`` from ``Y`` on the side ``sign`` (complex arrays), and where it exists.

    >>> M, ok = circle_meet(np.array([0j]), np.array([2 + 0j]), 1.5, 1.5, 1.0)
    >>> float(round(M[0].real, 12)), bool(ok[0] and M[0].imag > 0)
    (1.0, True)
    """
    D = Y - X
    d2 = np.abs(D) ** 2
    prod = (r1 + r2) ** 2 - d2
    prod = prod * (d2 - (r1 - r2) ** 2)
    ok = (prod >= 0) & (d2 > 0)
    with np.errstate(invalid="ignore", divide="ignore"):
        M = X + D * (r1 * r1 + d2 - r2 * r2 + 1j * sign * np.sqrt(np.maximum(prod, 0.0))) / (2 * d2)
    return M, ok


@dataclass(frozen=True)
class SixBar:
    """A six-bar of ``kind`` (``"watt"`` or ``"stephenson"``) with ``lengths`` ``(a, b, c, d, p, q, e, f, g, h, u, v)``
    and assembly ``modes`` (four-bar, dyad), in the canonical frame (see the module)."""

    kind: str
    lengths: tuple
    modes: tuple = (1, 1)

    def __post_init__(self):
        if self.kind not in KINDS:
            raise InputError(f"six-bar kind {self.kind!r}: one of {sorted(KINDS)}")
        if len(self.lengths) != 12:
            raise InputError(f"a six-bar has 12 dimensions (a, b, c, d, p, q, e, f, g, h, u, v), got {len(self.lengths)}")

    def joints(self, theta):
        """``{name: complex positions}`` of the joints ``A``-``G`` and the point ``P`` at crank angles ``theta``,
        and where the linkage assembles."""
        a, b, c, d, p, q, e, f, g, h, u, v = self.lengths
        theta = np.asarray(theta, dtype=float)
        A = np.zeros_like(theta) + 0j
        B = a * np.exp(1j * theta)
        D = np.full_like(B, d)
        C, ok1 = circle_meet(B, D, b, c, self.modes[0])
        if self.kind == "stephenson":
            E = B + (p + 1j * q) * (C - B) / b
        else:
            E = D + (p + 1j * q) * (C - D) / c
        G = np.full_like(B, g + 1j * h)
        F, ok2 = circle_meet(E, G, e, f, self.modes[1])
        P = E + (u + 1j * v) * (F - E) / e
        return {"A": A, "B": B, "C": C, "D": D, "E": E, "F": F, "G": G, "P": P}, ok1 & ok2

    def curve(self, theta):
        """The tracing point's positions (complex) at crank angles ``theta``; NaN where the linkage does not assemble."""
        at, ok = self.joints(theta)
        return np.where(ok, at["P"], np.nan)

    def mechanism(self, theta: float = 0.0, place=lambda z: z) -> Mechanism:
        """The six-bar drawn at crank angle ``theta``, its points mapped by ``place`` (complex to complex)."""
        at, ok = self.joints(np.array([theta]))
        if not ok[0]:
            raise InputError(f"the {KINDS[self.kind]} does not assemble at crank angle {theta:g}")
        return drawn_mechanism(self.kind, {k: complex(place(z[0])) for k, z in at.items()})


def drawn_mechanism(kind: str, at: dict) -> Mechanism:
    """The six-bar of ``kind`` drawn with its joints ``A``-``G`` and tracing point ``P`` at the places ``at``
    (complex)."""
    xy = {k: (float(z.real), float(z.imag)) for k, z in at.items()}
    carrier = "coupler" if kind == "stephenson" else "rocker"
    joints = [Joint("A", "R", ("frame", "crank"), xy["A"]), Joint("B", "R", ("crank", "coupler"), xy["B"]),
              Joint("C", "R", ("coupler", "rocker"), xy["C"]), Joint("D", "R", ("rocker", "frame"), xy["D"]),
              Joint("E", "R", (carrier, "tracer"), xy["E"]), Joint("F", "R", ("tracer", "link"), xy["F"]),
              Joint("G", "R", ("link", "frame"), xy["G"])]
    return Mechanism.build(f"fitted {KINDS[kind]}", list(LINKS), "frame", joints, [Input("A")],
                           points=[CouplerPoint("P", "tracer", xy["P"])])


def sample(kind: str, rng: np.random.Generator, margin: float = 0.05, tries: int = 1000) -> SixBar:
    """A random six-bar of ``kind`` from the design space whose crank turns fully (``margin`` from a dead point).

    The design space, frame ``d = 1``: crank 0.15–0.5, coupler and rocker
    0.6–2.2 (a crank-rocker, Grashof by ``margin``); ``E`` within ``−1 ≤ p ≤
    1.5``, ``|q| ≤ 1`` on its link; ``G`` within ``−1.5 ≤ g ≤ 2.5``, ``−1.5 ≤ h ≤
    2``; ``e`` 0.3–2.5 and ``f`` such that the dyad assembles at every crank
    angle; ``P`` within ``−0.5 ≤ u/e ≤ 1.5``, ``|v/e| ≤ 1``.

    >>> s = sample("stephenson", np.random.default_rng(1))
    >>> bool(np.all(np.isfinite(s.curve(np.linspace(0, 2 * np.pi, 360)))))
    True
    """
    theta = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    for _ in range(tries):
        a = rng.uniform(0.15, 0.5)
        b, c = np.exp(rng.uniform(math.log(0.6), math.log(2.2), 2))
        sides = sorted((a, b, c, 1.0))
        if sides[0] != a or sides[0] + sides[3] > sides[1] + sides[2] - margin:
            continue
        p, q = rng.uniform(-1.0, 1.5), rng.uniform(-1.0, 1.0)
        g, h = rng.uniform(-1.5, 2.5), rng.uniform(-1.5, 2.0)
        modes = tuple(int(x) for x in rng.choice((-1, 1), 2))
        four = SixBar(kind, (a, b, c, 1.0, p, q, 1.0, 1.0, g, h, 0.0, 0.0), modes)
        at, _ = four.joints(theta)
        r = np.abs(at["E"] - (g + 1j * h))
        lo_r, hi_r = float(r.min()), float(r.max())
        if lo_r < 2 * margin:
            continue
        e = rng.uniform(0.3, 2.5)
        lo, hi = max(hi_r - e, e - lo_r) + margin, e + lo_r - margin
        if hi <= lo:
            continue
        f = rng.uniform(lo, hi)
        u, v = e * rng.uniform(-0.5, 1.5), e * rng.uniform(-1.0, 1.0)
        return SixBar(kind, (a, b, c, 1.0, p, q, e, f, g, h, u, v), modes)
    raise InputError(f"no {KINDS[kind]} that turns fully was drawn in {tries} tries")
