"""Solid interference of shapes carried by links: the signed clearance, least over a stroke (seed 002, §5-3).

A *shape* is a simple polygon fixed on a link, given in the drawn pose (the
mechanism file's ``polygons``). Along a sweep of the input each shape is
placed by its link's displacement from the drawn pose. A *pair* names two
shapes; the second may be a copy turned by an angle about a centre (a drum's
neighbouring tile pair: the same mechanism turned by 2π/N about the drum axis,
driven by the same main shaft, so its shapes are this mechanism's shapes at the
same input, turned).

The **signed clearance** of two shapes is their distance when they are apart
(``> 0``) and minus a penetration depth when their interiors overlap (``< 0``);
zero when they touch. Each shape is split into convex pieces (ear clipping,
then Hertel–Mehlhorn merging); for two convex pieces the clearance is their
distance (vertex–edge enumeration) when a separating axis exists, else minus
the minimum translation distance (the least overlap over the edge normals,
exact for convex pieces); for two shapes it is the least over their pieces'
pairs. That is the exact distance for shapes apart and, for overlapping
non-convex shapes, minus the deepest overlap of two pieces (a lower bound of
the true depth, exact when both are convex). It is continuous in the poses.

:func:`clearance` evaluates every pair on the sweep's samples (arrays), then
refines the least value **between samples**: each local minimum of the
samples that could hide a value below the least found (its dip bounded by
twice the steepest change per step round it) is searched by bounded Brent's
method on the input, the poses solved at each trial input from the
neighbouring sample's configuration.

>>> sq = [(0, 0), (1, 0), (1, 1), (0, 1)]
>>> round(signed_clearance(sq, [(2, 0), (3, 0), (3, 1), (2, 1)]), 12)
1.0
>>> round(signed_clearance(sq, [(0.75, 0.25), (2, 0.25), (2, 0.5), (0.75, 0.5)]), 12)
-0.25
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize_scalar

from domes.errors import InputError, NumericalError
from domes.model.mechanism import Mechanism
from domes.motion.planar.continuation import Continuation, Stuck
from domes.motion.planar.query import Kinematics, SolveFailure
from domes.motion.planar.sweep import run_sweep
from domes.results import Result, Status

__all__ = ["Clearance", "Pair", "PairMinimum", "Shape", "clearance", "convex_pieces", "shapes_of",
           "signed_clearance", "signed_clearances"]


# -- geometry of polygons ---------------------------------------------------------------------------------


def _area2(poly) -> float:
    p = np.asarray(poly, float)
    x, y = p[:, 0], p[:, 1]
    return float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1)))


def _cross(o, a, b) -> float:
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


def _convex(poly, eps=1e-12) -> bool:
    n = len(poly)
    return all(_cross(poly[i], poly[(i + 1) % n], poly[(i + 2) % n]) >= -eps for i in range(n))


def convex_pieces(outline, where: str = "shape") -> list[np.ndarray]:
    """Convex pieces (counter-clockwise vertex arrays) whose union is the simple polygon ``outline``.

    Ear clipping into triangles, then Hertel–Mehlhorn: a diagonal is dropped
    wherever the two pieces it separates form a convex polygon.

    >>> len(convex_pieces([(0, 0), (2, 0), (2, 2), (1, 1), (0, 2)]))   # a notch: two convex pieces
    2
    """
    pts = [tuple(map(float, v)) for v in outline]
    if len(pts) > 1 and pts[0] == pts[-1]:
        pts = pts[:-1]
    if len(pts) < 3 or not all(math.isfinite(c) for v in pts for c in v):
        raise InputError(f"{where}: needs three or more finite vertices, got {outline!r}")
    area = _area2(pts)
    scale = max(max(abs(c) for v in pts for c in v), 1e-300)
    if not abs(area) > 1e-12 * scale * scale:
        raise InputError(f"{where}: the outline has no area")
    if area < 0:
        pts = pts[::-1]
    if _edges_cross(pts):
        raise InputError(f"{where}: the outline is not a simple polygon (its edges cross)")
    if _convex(pts):
        return [np.array(pts)]
    idx = list(range(len(pts)))
    tris: list[list[int]] = []
    guard = 0
    while len(idx) > 3:
        guard += 1
        if guard > 10 * len(pts) ** 2:
            raise InputError(f"{where}: the outline is not a simple polygon (its edges cross)")
        n = len(idx)
        for k in range(n):
            a, b, c = idx[k - 1], idx[k], idx[(k + 1) % n]
            if _cross(pts[a], pts[b], pts[c]) <= 1e-14 * scale * scale:
                continue
            if any(_inside_tri(pts[m], pts[a], pts[b], pts[c]) for m in idx if m not in (a, b, c)):
                continue
            tris.append([a, b, c])
            idx.pop(k)
            break
        else:
            raise InputError(f"{where}: the outline is not a simple polygon (its edges cross)")
    tris.append(idx)
    pieces = [list(t) for t in tris]
    merged = True
    while merged:
        merged = False
        for i in range(len(pieces)):
            for j in range(i + 1, len(pieces)):
                joined = _join(pieces[i], pieces[j])
                if joined is not None and _convex([pts[m] for m in joined]):
                    pieces[i] = joined
                    pieces.pop(j)
                    merged = True
                    break
            if merged:
                break
    return [np.array([pts[m] for m in p]) for p in pieces]


def _edges_cross(pts) -> bool:
    """Whether two edges of the closed outline that are not neighbours cross or touch."""
    n = len(pts)
    for i in range(n):
        p, q = pts[i], pts[(i + 1) % n]
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            r, s = pts[j], pts[(j + 1) % n]
            d1, d2 = _cross(p, q, r), _cross(p, q, s)
            d3, d4 = _cross(r, s, p), _cross(r, s, q)
            if ((d1 > 0) != (d2 > 0) or d1 == 0 or d2 == 0) and ((d3 > 0) != (d4 > 0) or d3 == 0 or d4 == 0) \
                    and min(p[0], q[0]) <= max(r[0], s[0]) and min(r[0], s[0]) <= max(p[0], q[0]) \
                    and min(p[1], q[1]) <= max(r[1], s[1]) and min(r[1], s[1]) <= max(p[1], q[1]):
                return True
    return False


def _inside_tri(p, a, b, c) -> bool:
    return _cross(a, b, p) >= 0 and _cross(b, c, p) >= 0 and _cross(c, a, p) >= 0


def _join(p, q):
    """Two counter-clockwise index polygons sharing one edge, joined into one (or None)."""
    n, m = len(p), len(q)
    for i in range(n):
        u, v = p[i], p[(i + 1) % n]
        for j in range(m):
            if q[j] == v and q[(j + 1) % m] == u:
                return p[:i + 1] + [q[(j + 2 + k) % m] for k in range(m - 2)] + p[i + 1:]
    return None


def _point_segment(px, py, ax, ay, bx, by):
    """Distance from points to segments (broadcast arrays)."""
    dx, dy = bx - ax, by - ay
    den = dx * dx + dy * dy
    t = np.clip(((px - ax) * dx + (py - ay) * dy) / np.where(den > 0, den, 1.0), 0.0, 1.0)
    return np.hypot(px - ax - t * dx, py - ay - t * dy)


def _piece_clearance(P: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Signed clearance of convex pieces posed along the stroke: ``P`` (T, n, 2), ``Q`` (T, m, 2), both CCW."""
    axes = []
    for R in (P, Q):
        e = np.roll(R, -1, axis=1) - R
        nrm = np.stack([e[..., 1], -e[..., 0]], axis=-1)
        axes.append(nrm / np.linalg.norm(nrm, axis=-1, keepdims=True))
    ax = np.concatenate(axes, axis=1)                                  # (T, k, 2) outward normals
    pp = np.einsum("tkd,tnd->tkn", ax, P)
    qq = np.einsum("tkd,tmd->tkm", ax, Q)
    pmin, pmax, qmin, qmax = pp.min(-1), pp.max(-1), qq.min(-1), qq.max(-1)
    push = np.minimum(pmax - qmin, qmax - pmin)                        # overlap along each axis (< 0: a gap)
    depth = push.min(-1)
    Pn, Qn = np.roll(P, -1, axis=1), np.roll(Q, -1, axis=1)
    d1 = _point_segment(P[:, :, None, 0], P[:, :, None, 1], Q[:, None, :, 0], Q[:, None, :, 1],
                        Qn[:, None, :, 0], Qn[:, None, :, 1]).min(axis=(1, 2))
    d2 = _point_segment(Q[:, :, None, 0], Q[:, :, None, 1], P[:, None, :, 0], P[:, None, :, 1],
                        Pn[:, None, :, 0], Pn[:, None, :, 1]).min(axis=(1, 2))
    return np.where(depth < 0, np.minimum(d1, d2), -np.maximum(depth, 0.0))


def signed_clearances(first: list[np.ndarray], second: list[np.ndarray]) -> np.ndarray:
    """Signed clearance over the stroke of two shapes given as convex pieces posed at T inputs, each (T, n, 2).

    The least over every pair of pieces; pieces of equal vertex counts are stacked and done at once.
    """
    groups_a: dict[int, list] = {}
    groups_b: dict[int, list] = {}
    for P in first:
        groups_a.setdefault(P.shape[1], []).append(P)
    for Q in second:
        groups_b.setdefault(Q.shape[1], []).append(Q)
    best = None
    for n, ps in groups_a.items():
        A = np.stack(ps, axis=1)                                        # (T, a, n, 2)
        for m, qs in groups_b.items():
            B = np.stack(qs, axis=1)                                    # (T, b, m, 2)
            T, a, b = A.shape[0], A.shape[1], B.shape[1]
            PP = np.broadcast_to(A[:, :, None], (T, a, b, n, 2)).reshape(T * a * b, n, 2)
            QQ = np.broadcast_to(B[:, None], (T, a, b, m, 2)).reshape(T * a * b, m, 2)
            s = _piece_clearance(PP, QQ).reshape(T, a * b).min(axis=1)
            best = s if best is None else np.minimum(best, s)
    return best


def signed_clearance(a, b) -> float:
    """Signed clearance of two simple polygons (vertex lists): distance apart, minus penetration depth overlapping."""
    pa = [p[None] for p in convex_pieces(a, "first polygon")]
    pb = [p[None] for p in convex_pieces(b, "second polygon")]
    return float(signed_clearances(pa, pb)[0])


# -- shapes on links and their placement ------------------------------------------------------------------


@dataclass(frozen=True)
class Shape:
    """A polygon on a link (drawn pose) and its convex pieces."""

    name: str
    link: str
    outline: tuple
    pieces: tuple = field(repr=False, compare=False, default=())

    @classmethod
    def make(cls, name: str, link: str, outline) -> "Shape":
        pieces = convex_pieces(outline, f"shape {name!r}")
        return cls(name, link, tuple(tuple(map(float, v)) for v in outline), tuple(pieces))


def shapes_of(mech: Mechanism) -> dict[str, Shape]:
    """The mechanism's polygons as shapes, by name."""
    return {p.name: Shape.make(p.name, p.link, p.vertices) for p in mech.polygons}


@dataclass(frozen=True)
class Pair:
    """Two shapes to keep apart; ``turn`` (rad) turns the second about ``about`` (a neighbouring copy)."""

    first: str
    second: str
    turn: float = 0.0
    about: tuple = (0.0, 0.0)

    @property
    def label(self) -> str:
        if not self.turn:
            return f"{self.first} / {self.second}"
        return f"{self.first} / {self.second} turned {math.degrees(self.turn):+.6g}°"


class _Poser:
    """Places shapes along a sweep: each link's rotation and translation from the drawn pose."""

    def __init__(self, mech: Mechanism, shapes: dict[str, Shape], names, accuracy=None):
        self.mech = mech
        self.shapes = shapes
        self.anchor = {}
        outputs = []
        for name in names:
            link = shapes[name].link
            if link in self.anchor:
                continue
            if link == mech.ground:
                self.anchor[link] = None
                continue
            pins = [j for j in mech.joints_of(link) if j.kind == "R"]
            if not pins:
                raise InputError(f"{mech.name}: shape {name!r} is on link {link!r}, which has no R joint to place it by")
            self.anchor[link] = pins[0]
            outputs += [f"point:{pins[0].name}", f"angle:{link}"]
        self.kin = Kinematics(mech, sorted(set(outputs)) or None, 0, "assur", accuracy)

    def transforms(self, values: dict) -> dict:
        """``{link: (c, s, tx, ty)}`` arrays (or floats) of the displacement from the drawn pose."""
        out = {}
        for link, pin in self.anchor.items():
            if pin is None:
                out[link] = (np.ones(1), np.zeros(1), np.zeros(1), np.zeros(1))
                continue
            d = np.atleast_1d(np.asarray(values[f"angle:{link}"], float)) - self.mech.reference_angle(link)
            c, s = np.cos(d), np.sin(d)
            px = np.atleast_1d(np.asarray(values[f"point:{pin.name}.x"], float))
            py = np.atleast_1d(np.asarray(values[f"point:{pin.name}.y"], float))
            out[link] = (c, s, px - c * pin.at[0] + s * pin.at[1], py - s * pin.at[0] - c * pin.at[1])
        return out

    def pieces(self, name: str, tf: dict, turn: float = 0.0, about=(0.0, 0.0)) -> list[np.ndarray]:
        c, s, tx, ty = tf[self.shapes[name].link]
        out = []
        for piece in self.shapes[name].pieces:
            x = c[:, None] * piece[None, :, 0] - s[:, None] * piece[None, :, 1] + tx[:, None]
            y = s[:, None] * piece[None, :, 0] + c[:, None] * piece[None, :, 1] + ty[:, None]
            if turn:
                ct, st = math.cos(turn), math.sin(turn)
                x, y = (about[0] + ct * (x - about[0]) - st * (y - about[1]),
                        about[1] + st * (x - about[0]) + ct * (y - about[1]))
            out.append(np.stack([x, y], axis=-1))
        return out

    def gaps(self, pairs, values: dict) -> np.ndarray:
        """Signed clearances (pairs × samples)."""
        tf = self.transforms(values)
        n = max(len(v[0]) for v in tf.values()) if tf else 1
        tf = {k: tuple(np.broadcast_to(a, (n,)) for a in v) for k, v in tf.items()}
        return np.array([signed_clearances(self.pieces(p.first, tf), self.pieces(p.second, tf, p.turn, p.about))
                         for p in pairs])


@dataclass(frozen=True)
class PairMinimum:
    """One pair's least signed clearance over the stroke and the input where it is least."""

    pair: Pair
    minimum: float
    input: float


@dataclass(frozen=True, eq=False)
class Clearance(Result):
    """The least signed clearance over a stroke: the value, the pair and the input; every pair's least.

    ``minimum > 0``: the shapes stay apart by that much; ``< 0``: they overlap
    that deep at ``input``. ``inputs``/``samples`` are the sweep's samples and
    the pairs' clearances there (pairs × samples); ``refined`` counts the
    Brent searches between samples; ``status`` STOPPED when the sweep stopped
    at a dead point before the end of the stroke (the values cover what was reached).
    """

    minimum: float
    pair: Pair
    input: float
    pairs: tuple[PairMinimum, ...]
    inputs: np.ndarray
    samples: np.ndarray
    refined: int
    status: Status
    reached: tuple[float, float]
    angular: bool = True

    @property
    def interferes(self) -> bool:
        return self.minimum < 0

    @property
    def message(self) -> str:
        word = "interference" if self.interferes else "no interference"
        where = f"{math.degrees(self.input):.6g}°" if self.angular else f"{self.input:.6g}"
        return (f"{word}: least signed clearance {self.minimum:.6g} between {self.pair.label} at input "
                f"{where} ({len(self.pairs)} pairs, {self.inputs.size} samples, "
                f"{self.refined} refined between samples)")


def clearance(mech: Mechanism, pairs, start: float, stop: float, step: float | None = None, tol: float = 1e-7,
              accuracy=None, shapes: dict[str, Shape] | None = None) -> Clearance:
    """The least signed clearance of ``pairs`` (:class:`Pair`) while the input sweeps ``start`` → ``stop``.

    Angles in rad (lengths for a sliding input); ``step`` defaults to 1° (0.01 of the size for a slide);
    ``tol`` is the input tolerance of the refinement between samples. ``shapes`` default to the file's polygons.

    >>> from domes.motion.planar.examples import four_bar
    >>> pad = Shape.make("pad", "coupler", [(1.8, 2.3), (2.2, 2.3), (2.2, 2.7), (1.8, 2.7)])
    >>> stop = Shape.make("stop", "frame", [(-1.0, 2.6), (0.2, 2.6), (0.2, 3.0), (-1.0, 3.0)])
    >>> r = clearance(four_bar(), [Pair("pad", "stop")], 0.0, 2 * math.pi, shapes={"pad": pad, "stop": stop})
    >>> r.interferes, r.pair.label, round(math.degrees(r.input), 1)
    (True, 'pad / stop', 175.0)
    """
    shapes = shapes_of(mech) if shapes is None else shapes
    pairs = tuple(pairs)
    if not pairs:
        raise InputError(f"{mech.name}: no pairs of shapes to check")
    for p in pairs:
        for name in (p.first, p.second):
            if name not in shapes:
                raise InputError(f"{mech.name}: no shape {name!r}; shapes are {sorted(shapes)}")
    if not (math.isfinite(start) and math.isfinite(stop)) or start == stop:
        raise InputError(f"{mech.name}: the stroke {start!r} .. {stop!r} must be two different finite inputs")
    angular = mech.joint(mech.inputs[0].joint).kind == "R" if mech.inputs else True
    poser = _Poser(mech, shapes, {n for p in pairs for n in (p.first, p.second)}, accuracy)
    step = step or (math.radians(1.0) if angular else 0.01 * poser.kin.size)
    sw = run_sweep(poser.kin, start, stop, step)
    if not sw.inputs.size:
        raise NumericalError(f"{mech.name}: the sweep from input {start:.6g} reached no configuration")
    values = {**sw.table}
    samples = poser.gaps(pairs, values)
    cont = Continuation(poser.kin, sw.joint)
    states = sw.states

    def at(q, k):
        guess = {v: float(a[k]) for v, a in states.items()}
        try:
            state = cont.walk(guess, float(sw.inputs[k]), q)
        except (Stuck, SolveFailure, NumericalError):  # a trial input past a limit is not a minimum
            return None
        return poser.kin.output_values(state, {}, {}, 0)

    refined = 0
    best: list[PairMinimum] = []
    qs = sw.inputs
    floor = float(samples.min())
    steps = np.abs(np.diff(samples, axis=1)) if qs.size > 1 else np.zeros((len(pairs), 0))
    for i, p in enumerate(pairs):
        g = samples[i]
        k0 = int(np.argmin(g))
        low, where = float(g[k0]), float(qs[k0])
        if qs.size > 2:
            loc = [k for k in range(qs.size)
                   if (k == 0 or g[k] <= g[k - 1]) and (k == qs.size - 1 or g[k] <= g[k + 1])]
            for k in loc:
                # between its neighbours a minimum can dip below the sample by at most the local change per step
                # (the steepest of the two steps on either side, doubled for safety): refine only if that could
                # reach below the least found so far
                near = steps[i, max(k - 2, 0):k + 2]
                if g[k] - 2.0 * float(near.max(initial=0.0)) > min(low, floor):
                    continue
                lo, hi = float(qs[max(k - 1, 0)]), float(qs[min(k + 1, qs.size - 1)])
                a, b = min(lo, hi), max(lo, hi)

                def f(q, k=k, i=i):
                    v = at(q, k)
                    return math.inf if v is None else float(poser.gaps([pairs[i]], v)[0, 0])

                res = minimize_scalar(f, bounds=(a, b), method="bounded", options={"xatol": tol})
                refined += 1
                if math.isfinite(res.fun) and res.fun < low:
                    low, where = float(res.fun), float(res.x)
        best.append(PairMinimum(p, low, where))
    worst = min(best, key=lambda m: m.minimum)
    return Clearance(worst.minimum, worst.pair, worst.input, tuple(best), qs, samples, refined,
                     Status.COMPLETE if sw.success else Status.STOPPED, sw.reachable, cont.angular)
