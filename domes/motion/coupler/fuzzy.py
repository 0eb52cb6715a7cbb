"""Fuzzy shape parameters of closed curves (seed 002 §6-3, after Cao Weiqing et al.; digest B.5.1).

A curve is first put in its *standard position*: turned so that its
bounding rectangle is as long as possible (the long side ``Xm`` is the
curve's diameter), long side horizontal. The curve touches the rectangle at
four contact points, which cut it into four segments. Corners and contact
points are labelled (the book's figure is lost; this is the reading under
which its ratios are defined): ``A`` top-left, ``B`` bottom-left, ``C``
bottom-right, ``D`` top-right; ``E`` on the top side, ``F`` on the left,
``G`` on the bottom, ``H`` on the right. Then

- ``S1 = Ym/Xm``; ``S2 = AF/Ym``, ``S3 = HD/Ym`` (how far below the top the
  left and right contacts are); ``S4 = BG/Xm``, ``S5 = AE/Xm`` (how far from
  the left the bottom and top contacts are);
- Type I (no crossing): ``S6, S7`` the convexity of the two lower segments
  (``F→G``, ``G→H``) graded 1 (strongly convex) .. 4 (strongly concave);
  ``S8, S9, S10`` the curvature near ``F, E, H`` graded 0..7;
- Type II (one crossing ``K``): ``S6 = AK'/Xm``, ``S7 = KK'/Ym`` (``K'`` its
  projection on the top side); ``S8, S10`` the curvature near ``F, H``;
  ``S9 = MN/Ym`` the fatness across the middle of ``Xm``;
- Type III (two crossings ``K, J``): ``S6 = AK'/Xm``, ``S7 = AJ'/Xm``.

Which side is down: Type I puts its concave segments down, or with all four
convex the flatter side; Type II the side towards which ``∠FKH`` opens,
with ``K`` on the left when the angle is straight; Type III the side away
from which ``F K J H`` bulges. The grades of convexity and curvature are
lost with the book's figures: the scales here are this module's own
(:func:`convexity_grade`, :func:`curvature_grade`) and say so.

Recognition compares a wanted curve (the model, ``A = [1, ..., 1]``) with
atlas curves by the normal membership (6-21) and the weighted Hamming
distance (6-24).

>>> t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
>>> p = parameters(np.c_[2 * np.cos(t), np.sin(t)])          # an ellipse 4 × 2
>>> p.type, round(p.values[0], 3), [round(x, 3) for x in p.values[1:5]]
('I', 0.5, [0.5, 0.5, 0.5, 0.5])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.motion.coupler.fourier import resample
from domes.motion.coupler.special import polyline_crossings


def membership(s, a, b):
    """The normal membership (6-21): ``exp(−((S − a)/b)²)``, 1 when the parameter equals the model's."""
    return np.exp(-(((np.asarray(s, dtype=float) - a) / b) ** 2))


def hamming(memberships, weights=None) -> float:
    """The weighted Hamming distance (6-24) to the model ``A = [1, ..., 1]``: ``Σ W_j (1 − L_j)``."""
    L = np.asarray(memberships, dtype=float)
    W = np.ones_like(L) if weights is None else np.asarray(weights, dtype=float)
    if W.shape != L.shape:
        raise InputError(f"{W.size} weights for {L.size} parameters")
    return float(np.sum(W * (1.0 - L)))


@dataclass(frozen=True)
class FuzzyParameters:
    """The curve's type (I, II or III), its parameters ``S1..Sn`` and the standard position that gave them.

    ``angle`` is the rotation that put the curve in standard position and
    ``centre`` the point it was turned about; ``crossings`` their count.
    """

    type: str
    values: tuple[float, ...]
    angle: float
    centre: tuple[float, float]
    crossings: int

    def similarity(self, model: "FuzzyParameters", tolerances, weights=None) -> float:
        """The weighted Hamming distance of this curve to ``model`` (0 = identical); another type is ``inf``."""
        if model.type != self.type:
            return math.inf
        return hamming(membership(self.values, np.asarray(model.values), np.asarray(tolerances)), weights)


def convexity_grade(bulge: float) -> int:
    """1 strongly convex (bulge > 0.15 of the chord), 2 convex, 3 concave, 4 strongly concave (< −0.15)."""
    if bulge > 0.15:
        return 1
    if bulge >= 0.0:
        return 2
    return 3 if bulge >= -0.15 else 4


def curvature_grade(k: float) -> int:
    """Grade 0..7 of a curvature ``k`` made dimensionless by ``Ym``: doubling bands from 0.5 (0: below 0.5)."""
    if not k > 0:
        return 0
    return int(min(7, max(0, math.floor(math.log2(k) + 2))))


def parameters(points, samples: int = 512) -> FuzzyParameters:
    """The fuzzy parameters of the closed curve through ``points`` (any position, size and orientation)."""
    p = resample(points, samples, closed=True)
    crossings = _self_crossings(p)
    kind = "I" if not crossings else "II" if len(crossings) == 1 else "III"
    angle = _diameter_angle(p)
    centre = tuple(p.mean(axis=0))
    best = None
    for flip in (0.0, math.pi):
        q = _turn(p, centre, -(angle + flip))
        ks = [tuple(_turn(np.array([k]), centre, -(angle + flip))[0]) for k in crossings]
        score = _downness(q, ks, kind)
        if best is None or score > best[0]:
            best = (score, flip, q, ks)
    _, flip, q, ks = best
    return FuzzyParameters(kind, _values(q, ks, kind), angle + flip, centre, len(crossings))


def mirror_values(params: FuzzyParameters) -> tuple[float, ...]:
    """The parameters of the mirror image (the four-bar mounted reversed, Fig. 6-23), converted, not recomputed.

    A mirror about the vertical axis of the standard position swaps left and
    right: ``S2 ↔ S3``, ``S4 → 1 − S4``, ``S5 → 1 − S5``; Type I swaps the two
    lower segments' grades and the curvatures near ``F`` and ``H``; Type II
    moves the crossing (``S6 → 1 − S6``) and swaps ``S8, S10``; ``S1`` and
    ``S9`` do not change.
    """
    s = list(params.values)
    s[1], s[2] = s[2], s[1]
    s[3], s[4] = 1 - s[3], 1 - s[4]
    if params.type == "I":
        s[5], s[6] = s[6], s[5]
        s[7], s[9] = s[9], s[7]
    elif params.type == "II":
        s[5] = 1 - s[5]
        s[7], s[9] = s[9], s[7]
    else:
        s[5], s[6] = 1 - s[6], 1 - s[5]
    return tuple(s)


# -- standard position -------------------------------------------------------------------------


def _turn(p, centre, angle):
    c, s = math.cos(angle), math.sin(angle)
    d = p - np.asarray(centre)
    return np.c_[c * d[:, 0] - s * d[:, 1], s * d[:, 0] + c * d[:, 1]] + np.asarray(centre)


def _diameter_angle(p) -> float:
    """The direction of the curve's diameter (the turn that makes the bounding rectangle longest)."""
    hull = _hull(p)
    d = hull[:, None, :] - hull[None, :, :]
    dist = np.einsum("ijk,ijk->ij", d, d)
    i, j = np.unravel_index(int(np.argmax(dist)), dist.shape)
    v = hull[j] - hull[i]
    return math.atan2(v[1], v[0])


def _hull(p):
    pts = np.unique(np.round(p, 12), axis=0)
    if len(pts) < 3:
        return pts
    pts = pts[np.lexsort((pts[:, 1], pts[:, 0]))]

    def half(seq):
        out = []
        for q in seq:
            while len(out) >= 2 and _cross(out[-1] - out[-2], q - out[-2]) <= 0:
                out.pop()
            out.append(q)
        return out

    lower, upper = half(pts), half(pts[::-1])
    return np.array(lower[:-1] + upper[:-1])


def _cross(u, v):
    return u[0] * v[1] - u[1] * v[0]


def _contacts(q):
    """Indices of the contact points E (top), F (left), G (bottom), H (right)."""
    return int(np.argmax(q[:, 1])), int(np.argmin(q[:, 0])), int(np.argmin(q[:, 1])), int(np.argmax(q[:, 0]))


def _segment(q, i, j):
    return q[i:j + 1] if i <= j else np.vstack([q[i:], q[:j + 1]])


def _bulge(q, i, j, corner):
    """How far segment ``i → j`` bulges towards ``corner`` beyond its chord, over the chord length (− inward)."""
    seg = _segment(q, i, j) if _arc_len(q, i, j) <= _arc_len(q, j, i) else _segment(q, j, i)
    a, b = q[i], q[j]
    chord = b - a
    length = math.hypot(*chord)
    if length == 0:
        return 0.0
    normal = np.array([-chord[1], chord[0]]) / length
    if np.dot(np.asarray(corner) - a, normal) < 0:
        normal = -normal
    dev = (seg - a) @ normal
    k = int(np.argmax(np.abs(dev)))
    return float(dev[k]) / length


def _arc_len(q, i, j):
    return (j - i) % len(q)


def _curvature(q, i, ym):
    """The curvature at point ``i`` (three-point circle over a few samples) times ``Ym``."""
    n = len(q)
    w = max(2, n // 64)
    a, b, c = q[(i - w) % n], q[i], q[(i + w) % n]
    ab, bc, ca = math.dist(a, b), math.dist(b, c), math.dist(c, a)
    area2 = abs((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    if ab * bc * ca == 0:
        return 0.0
    return 2 * area2 / (ab * bc * ca) * ym


def _downness(q, ks, kind) -> float:
    """How well this turn meets the type's rule for which side is down (larger is better)."""
    E, F, G, H = _contacts(q)
    top, bottom = q[:, 1].max(), q[:, 1].min()
    left, right = q[:, 0].min(), q[:, 0].max()
    if kind == "I":
        lower = [_bulge(q, F, G, (left, bottom)), _bulge(q, G, H, (right, bottom))]
        upper = [_bulge(q, H, E, (right, top)), _bulge(q, E, F, (left, top))]
        concave = -sum(min(x, 0) for x in lower) + sum(min(x, 0) for x in upper)
        flatness = -sum(lower) + sum(upper)
        return concave * 10 + flatness
    if kind == "II":
        k = ks[0]
        f, h = q[F], q[H]
        # The angle FKH opens downwards when K is above the line FH.
        line = f[1] + (h[1] - f[1]) * (k[0] - f[0]) / (h[0] - f[0]) if h[0] != f[0] else f[1]
        above = (k[1] - line) / max(top - bottom, 1e-300)
        if abs(above) < 1e-3:
            return -(k[0] - left) / max(right - left, 1e-300)
        return above
    # Type III: up is where F K J H bulges, i.e. the crossings above the line FH.
    f, h = q[F], q[H]
    mid = np.mean([k[1] for k in ks])
    return mid - 0.5 * (f[1] + h[1])


def _values(q, ks, kind):
    E, F, G, H = _contacts(q)
    top, bottom = q[:, 1].max(), q[:, 1].min()
    left, right = q[:, 0].min(), q[:, 0].max()
    xm, ym = right - left, top - bottom
    if xm <= 0 or ym <= 0:
        raise InputError("the curve is a segment (no area): its fuzzy parameters are undefined")
    s = [ym / xm, (top - q[F][1]) / ym, (top - q[H][1]) / ym, (q[G][0] - left) / xm, (q[E][0] - left) / xm]
    if kind == "I":
        s += [convexity_grade(_bulge(q, F, G, (left, bottom))), convexity_grade(_bulge(q, G, H, (right, bottom)))]
        s += [curvature_grade(_curvature(q, i, ym)) for i in (F, E, H)]
    elif kind == "II":
        k = ks[0]
        s += [(k[0] - left) / xm, (top - k[1]) / ym, curvature_grade(_curvature(q, F, ym)),
              _fatness(q, left + xm / 2) / ym, curvature_grade(_curvature(q, H, ym))]
    else:
        k, j = sorted(ks)[:2]
        s += [(k[0] - left) / xm, (j[0] - left) / xm]
    return tuple(float(x) for x in s)


def _fatness(q, x):
    """MN: the extent of the curve's crossings with the vertical line at ``x``."""
    a, b = q, np.roll(q, -1, axis=0)
    hit = (a[:, 0] - x) * (b[:, 0] - x) <= 0
    ys = []
    for p0, p1 in zip(a[hit], b[hit]):
        if p1[0] == p0[0]:
            ys += [p0[1], p1[1]]
        else:
            ys.append(p0[1] + (p1[1] - p0[1]) * (x - p0[0]) / (p1[0] - p0[0]))
    return max(ys) - min(ys) if ys else 0.0


def _self_crossings(p):
    """The points where the closed polyline crosses itself."""
    return [p[i] + t * (p[(i + 1) % len(p)] - p[i]) for i, _, t, _ in polyline_crossings(p)]
