"""Ranking feasible designs: a weighted fuzzy comprehensive evaluation of soft indices (seed 002, §5-2: "soft
indices ... in an imprecise evaluation model based on fuzzy mathematics"; §5-3's F6-F8 after the structural
levels F1-F5).

The book gives no membership functions (digest, note 20); these are ours, documented in docs/expert.md:

1. each factor's raw value becomes a *goodness* ``g`` in [0, 1] by a fixed mapping (:data:`GOODNESS`):
   accuracy ``1 - error/tolerance``; transmission ``(μ - 20°)/50°``; compactness ``1 - envelope/box``;
   force ``ln(margin)/ln 3`` (a margin of 3 over the requirement is full marks); sensitivity
   ``1 - spread/budget``; complexity ``(14 - parts)/10``; each clipped to [0, 1];
2. ``g`` belongs to the grades *excellent, good, fair, poor* by triangular membership functions peaking at
   1, 2/3, 1/3 and 0 (each row sums to 1): the evaluation matrix ``R``;
3. the grade distribution is ``B = W · R`` (the weighted-average operator ``M(·, ⊕)``), ``W`` the
   designer's weights normalised over the factors present;
4. the score is ``B · (1, 0.7, 0.4, 0.1)``, and each factor's contribution ``w_i · (R_i · scores)``: the
   contributions add up to the score, so the ranking says what each factor gave.

A factor no design has (e.g. force, without a force check) is left out; one that some designs lack (a check
that could not be evaluated) counts as poor for those.

>>> r = rank([{"candidate": 1, "indices": {"accuracy": 0.1, "transmission": 70.0}},
...           {"candidate": 2, "indices": {"accuracy": 0.5, "transmission": 45.0}}])
>>> [d.candidate for d in r], [round(d.score, 3) for d in r]
([1, 2], [0.955, 0.55])
>>> round(sum(r[0].contributions.values()), 6) == round(r[0].score, 6)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from domes.design.brief import FACTORS
from domes.errors import InputError

GRADES = ("excellent", "good", "fair", "poor")
#: Where each grade's membership peaks (on the goodness scale) and what it scores.
PEAKS = (1.0, 2.0 / 3.0, 1.0 / 3.0, 0.0)
SCORES = (1.0, 0.7, 0.4, 0.1)
#: Default weights of the factors (a scene or the designer may change them).
DEFAULT_WEIGHTS = {"accuracy": 1.0, "transmission": 1.0, "compactness": 1.0, "force": 1.0, "sensitivity": 1.0,
                   "complexity": 0.5}
#: How each factor's raw value becomes a goodness in [0, 1] (before clipping), and what the raw value is.
GOODNESS = {
    "accuracy": (lambda x: 1.0 - x, "largest curve error over its tolerance"),
    "transmission": (lambda x: (x - 20.0) / 50.0, "smallest transmission angle (°)"),
    "compactness": (lambda x: 1.0 - x, "area swept by the joints over the area of the envelope"),
    "force": (lambda x: math.log(x) / math.log(3.0) if x > 0 else 0.0, "force requirement's margin (achieved/wanted)"),
    "sensitivity": (lambda x: 1.0 - x, "tolerance spread over its budget"),
    "complexity": (lambda x: (14.0 - x) / 10.0, "links + links of 3 or more joints + sliders"),
}


def goodness(factor: str, value: float) -> float:
    """A factor's raw value on the goodness scale [0, 1] (:data:`GOODNESS`); NaN or infinite is 0.

    >>> goodness("transmission", 45.0), goodness("force", 9.0)
    (0.5, 1.0)
    """
    if value is None or not math.isfinite(value):
        return 0.0
    return float(min(1.0, max(0.0, GOODNESS[factor][0](value))))


def memberships(g: float) -> tuple[float, ...]:
    """The row of the evaluation matrix: how much goodness ``g`` belongs to each grade (sums to 1).

    >>> memberships(0.5)
    (0.0, 0.5, 0.5, 0.0)
    """
    step = PEAKS[0] - PEAKS[1]
    return tuple(round(max(0.0, 1.0 - abs(g - p) / step), 12) for p in PEAKS)


@dataclass(frozen=True)
class Ranked:
    """A design's evaluation: its ``score`` and ``rank``, the grade distribution ``B``, the ``grade`` of
    largest membership, and per factor the raw value, the goodness and the contribution to the score."""

    candidate: int
    rank: int
    score: float
    grade: str
    distribution: tuple[float, ...]
    values: Mapping[str, float]
    goodness: Mapping[str, float]
    contributions: Mapping[str, float]
    weights: Mapping[str, float] = field(default_factory=dict)

    def to_dict(self) -> dict:
        clean = lambda d: {k: (None if v is None or not math.isfinite(v) else round(float(v), 12)) for k, v in d.items()}  # noqa: E731
        return {"candidate": self.candidate, "rank": self.rank, "score": round(self.score, 12), "grade": self.grade,
                "distribution": [round(b, 12) for b in self.distribution], "values": clean(self.values),
                "goodness": clean(self.goodness), "contributions": clean(self.contributions),
                "weights": clean(self.weights)}

    def explanation(self) -> str:
        """Each factor's part of the score, largest first: ``transmission 0.21 (μ 65.0 → good)``."""
        parts = sorted(self.contributions.items(), key=lambda kv: -kv[1])
        return ", ".join(f"{k} {v:.3f}" for k, v in parts)


def rank(designs, weights: Mapping[str, float] | None = None) -> list[Ranked]:
    """The designs (each with a ``candidate`` id and raw ``indices``; objects or dicts) ranked, best first."""
    rows = [(_get(d, "candidate"), dict(_get(d, "indices") or {})) for d in designs]
    weights = {**DEFAULT_WEIGHTS, **(weights or {})}
    for key, w in weights.items():
        if key not in FACTORS:
            raise InputError(f"ranking: unknown factor {key!r}; the factors are {', '.join(FACTORS)}")
        if not (isinstance(w, (int, float)) and math.isfinite(w) and w >= 0):
            raise InputError(f"ranking: the weight of {key} must be a number >= 0, got {w!r}")
    present = [f for f in FACTORS if any(f in idx for _, idx in rows) and weights.get(f, 0) > 0]
    total = sum(weights[f] for f in present)
    w = {f: weights[f] / total for f in present} if total > 0 else {}
    out = []
    for cid, idx in rows:
        g = {f: goodness(f, idx.get(f)) for f in present}
        R = np.array([memberships(g[f]) for f in present]) if present else np.zeros((0, len(GRADES)))
        W = np.array([w[f] for f in present])
        B = W @ R if present else np.zeros(len(GRADES))
        per = R @ np.array(SCORES) if present else np.zeros(0)
        contributions = {f: float(W[k] * per[k]) for k, f in enumerate(present)}
        score = float(B @ np.array(SCORES))
        out.append((cid, score, tuple(float(b) for b in B), {f: idx.get(f) for f in present}, g, contributions))
    out.sort(key=lambda r: (-round(r[1], 12), r[0]))
    return [Ranked(cid, k, score, GRADES[int(np.argmax(B))] if present else "", B, values, g, contributions, w)
            for k, (cid, score, B, values, g, contributions) in enumerate(out, 1)]


def _get(design, key):
    return design.get(key) if isinstance(design, Mapping) else getattr(design, key)
