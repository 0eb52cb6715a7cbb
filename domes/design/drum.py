"""The tyre-building drum (seed 002, §5-1 and §5-3): tile layout, interference discriminant, D0/D1, α1/β1.

A drum has ``N`` identical tile pairs around its axis, each pair guided by one
copy of a 1-DOF linkage driven by the main shaft (seed 002, §5-3; digest 3.3).
Deployed, the tiles form a gap-free cylinder (inner diameter ``D1``, outer
``D2``); folded, everything is inside the tyre bead; no solid interference in
between; near dead centre when deployed (anti-retraction). The book's figures
are lost, so ``Δ = S × T``, ``α1, β1`` and the tile-layout equation are
undefined in the text (digest 3.8, ambiguity 17). **The readings below are the
project's, not the book's** (docs/drum.md):

* **Tiles** are polygons on the links (the mechanism file's ``polygons``
  named ``tile …``), drawn as annular sectors of the deployed cylinder whose
  end faces may be slanted (shaped tile ends); the drum axis is the frame
  point ``drum axis``; ``N`` is read from the tiles: their outer arcs at
  deployment sum to the pitch ``2π/N`` (checked to be a whole fraction of the
  turn, so the file's tiles fix ``N``).
* **Deployed pose**: the input where the tiles form the cylinder best (every
  tile vertex on the inner or the outer circle); **folded pose**: the input
  where the tiles and the moving joints reach least far from the axis. The
  stroke runs from folded to deployed with the input increasing (the main
  shaft's sense). Gap-free: every end face meets an end face of another tile.
* **Δ(θ)** is the signed clearance (:mod:`domes.design.interference`: gap
  ≥ 0, minus the penetration depth when overlapping) of every pair of tiles:
  the pair's own two tiles and each tile against each tile of the
  neighbouring copies (turned by ±2π/N about the axis). ``S`` is the
  clearance's size and ``T`` its sign (+1 apart, −1 overlapping), so
  ``Δ = S × T``; ``Δ_min`` over the stroke, ``Δ_min ≥ 0`` no interference.
  A gap-free cylinder has its tiles touching when deployed, so ``Δ_min ≤ 0``
  always and the best is ``Δ_min = 0`` (the book's §3-8 condition), passed
  within :data:`DELTA_TOL`.
* **Folding ratio** ``D1/Df``: ``Df`` the diameter of the least circle about
  the axis holding the folded tiles and moving joints; the folded check asks
  ``Df < D_bead`` (``D_bead = D1`` unless given). **D0/D1**: ``D0`` the largest
  diameter the tiles sweep during deployment (screening rule 3).
* **α1, β1**: the angles, at deployment, between the velocity of tile I's
  (and tile II's) centroid and the drum's tangent there (0: the tile moves
  only along the cylinder or stands still, so the blank's radial load does no
  work on the input: dead centre for that load). Anti-retraction: the main
  shaft's holding torque against the blank's radial load at deployment
  (:func:`domes.design.forces.drive`, static), at most :data:`HOLD_SHARE` of
  load × number of tiles × ``D2/2``.
* **Optimal layout** (the §3-8 tile-layout equation, :func:`layout_optimum`):
  the tile count ``N`` and tile I's share of the pitch that make the folded
  tiles' closed outline (the perimeter of their convex hull) least, with no
  interference folded.
* **Dimensional optimisation to Δ_min = 0** (§3-8 step 4, :func:`optimise`):
  free dimensions of a :class:`Design` (end-face slants, tile I's share, the
  pair's facing and reach, the drum radius) varied by Nelder–Mead until
  ``Δ_min = 0``; the deployed cylinder stays exact by construction.
  :func:`threshold`: the largest folding ratio for which it still succeeds
  (bisection). :func:`dimension_candidates`: a seeded construction and the
  same optimisation for regenerated candidates.

>>> from domes.io.mechanisms import load_mechanism
>>> from domes.io.resources import knowledge_dir
>>> drum = Drum.of(load_mechanism(knowledge_dir() / "mechanisms" / "tyre-drum-fig5-1.json"))
>>> drum.count, round(math.degrees(drum.deployed), 3), round(math.degrees(drum.folded), 3)
(12, 391.956, 214.728)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import minimize_scalar

from domes.design import forces
from domes.design.interference import Clearance, Pair, Shape, clearance, shapes_of
from domes.errors import InputError, NumericalError
from domes.model.masses import Load, MassModel
from domes.model.mechanism import CouplerPoint, Mechanism, Polygon
from domes.motion.planar.sweep import solve, sweep
from domes.results import Result, Status

__all__ = ["AXIS", "Design", "Drum", "DrumCheck", "Layout", "LayoutOptimum", "Optimum", "Threshold", "check", "delta_min",
           "dress", "layout_optimum", "lengthen", "optimise", "threshold"]

#: The frame point that marks the drum axis.
AXIS = "drum axis"
#: Anti-retraction: the holding torque may be at most this share of load × D2/2.
HOLD_SHARE = 0.05
#: Touching tolerance of Δ, of D2/2: the tiles touch when deployed (Δ = 0 there), found to rounding of the poses.
DELTA_TOL = 1e-6
#: Relative tolerance of the deployed cylinder (radii and the abutting end faces), of D2/2.
CYLINDER_TOL = 1e-6


# -- the deployed cylinder ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Layout:
    """The deployed cylinder of one tile pair: axis, ``count`` pairs, radii, where the pair starts, tile I's share.

    The pair covers the pitch ``2π/count`` from the angle ``start``, counter-
    clockwise: the tiles in ``order`` (tile II first by default), tile I taking
    ``share`` of the pitch; each tile an annular sector between ``inner`` and
    ``outer`` with ``arcs`` segments on each arc.

    >>> t = Layout((0.0, 0.0), 6, 0.9, 1.0, 0.0, 0.5).sectors()
    >>> [round(math.degrees(math.atan2(v[1], v[0])), 6) for v in (t["tile II"][0], t["tile I"][6])]  # outer arcs
    [0.0, 60.0]
    """

    centre: tuple
    count: int
    inner: float
    outer: float
    start: float
    share: float
    arcs: int = 6
    order: tuple = ("tile II", "tile I")
    slants: tuple = (0.0, 0.0)

    @property
    def pitch(self) -> float:
        return 2 * math.pi / self.count

    def faces(self) -> list[tuple[float, float]]:
        """The three end faces of the pair as (outer angle, inner angle): start, between the tiles, start + pitch."""
        first = self.order[0]
        cut = self.start + (1 - self.share if first == "tile II" else self.share) * self.pitch
        a, b = self.slants
        return [(self.start, self.start + a), (cut, cut + b), (self.start + self.pitch, self.start + self.pitch + a)]

    def sectors(self) -> dict:
        """``{tile: outline}`` (world, deployed): outer arc out, inner arc back; the ends are the faces."""
        cx, cy = self.centre
        f = self.faces()
        out = {}
        for name, (u, v) in zip(self.order, ((f[0], f[1]), (f[1], f[2]))):
            to = np.linspace(u[0], v[0], self.arcs + 1)
            ti = np.linspace(v[1], u[1], self.arcs + 1)
            ring = [(cx + self.outer * math.cos(x), cy + self.outer * math.sin(x)) for x in to]
            ring += [(cx + self.inner * math.cos(x), cy + self.inner * math.sin(x)) for x in ti]
            out[name] = ring
        return out


def _pose(mech: Mechanism, q: float, links) -> dict:
    """``{link: (angle from drawn, pin drawn, pin now)}`` at input ``q``."""
    pins = {x: next(j for j in mech.joints_of(x) if j.kind == "R") for x in links}
    outs = sorted({f"point:{p.name}" for p in pins.values()} | {f"angle:{x}" for x in links})
    v = solve(mech, q, outputs=outs).values
    return {x: (v[f"angle:{x}"] - mech.reference_angle(x), p.at, (v[f"point:{p.name}.x"], v[f"point:{p.name}.y"]))
            for x, p in pins.items()}


def dress(mech: Mechanism, layout: Layout, deployed: float, carriers: dict) -> Mechanism:
    """The mechanism with the layout's tiles on their links and the drum axis on the frame (drawn pose).

    ``carriers`` maps ``"tile I"``/``"tile II"`` to the links that carry them;
    the sectors are placed where the layout puts them at input ``deployed``
    and carried back to the drawn pose by each link's displacement.
    """
    pose = _pose(mech, deployed, set(carriers.values()))
    polys = []
    for name, ring in layout.sectors().items():
        d, p0, p = pose[carriers[name]]
        c, s = math.cos(d), math.sin(d)
        # world = R(d)(x − p0) + p  ⇒  x = R(−d)(world − p) + p0
        verts = tuple((c * (wx - p[0]) + s * (wy - p[1]) + p0[0], -s * (wx - p[0]) + c * (wy - p[1]) + p0[1])
                      for wx, wy in ring)
        polys.append(Polygon(name, carriers[name], verts))
    keep = tuple(x for x in mech.polygons if x.name not in layout.sectors())
    points = tuple(x for x in mech.points if x.name != AXIS) + (CouplerPoint(AXIS, mech.ground, tuple(layout.centre)),)
    return dataclasses.replace(mech, polygons=keep + tuple(polys), points=points)


# -- a drum read from a dressed mechanism --------------------------------------------------------------------


@dataclass(frozen=True)
class Drum:
    """A dressed mechanism read as a drum: axis, tile count, tiles, deployed and folded inputs (rad)."""

    mech: Mechanism
    centre: tuple
    count: int
    tiles: tuple
    deployed: float
    folded: float
    shapes: dict = field(repr=False, compare=False, default_factory=dict)

    @classmethod
    def of(cls, mech: Mechanism, count: int | None = None, deployed: float | None = None,
           folded: float | None = None) -> "Drum":
        """Read the axis (frame point ``drum axis``) and the tiles (polygons ``tile …``); find ``N`` and the poses."""
        axis = next((p for p in mech.points if p.name == AXIS), None)
        if axis is None or axis.link != mech.ground:
            raise InputError(f"{mech.name}: no frame point {AXIS!r} (the drum axis, on {mech.ground!r})")
        shapes = {k: v for k, v in shapes_of(mech).items() if k.startswith("tile")}
        if len(shapes) < 1:
            raise InputError(f"{mech.name}: no tiles (polygons named 'tile …')")
        tiles = tuple(sorted(shapes))
        drum = cls(mech, tuple(axis.at), count or 1, tiles, 0.0, 0.0, shapes)
        if deployed is None or folded is None:                  # one sweep finds both poses
            qs, residual, envelope, drawn = drum._scan()
        qd = drum._least(qs, residual, drum.cylinder_residual, 1e-11, drawn) if deployed is None else deployed
        drum = dataclasses.replace(drum, deployed=qd)
        if count is None:
            spans = drum.spans(qd)
            total = sum(b - a for a, b in spans.values())
            n = round(2 * math.pi / total)
            if n < 2 or abs(n * total - 2 * math.pi) > 1e-4:
                raise InputError(f"{mech.name}: the deployed tiles cover {math.degrees(total):.6g}° of the turn, not a "
                                 "whole fraction of it: give the tile count")
            drum = dataclasses.replace(drum, count=n)
        qf = drum._least(qs, envelope, drum.envelope, 1e-9, drawn) if folded is None else folded
        return dataclasses.replace(drum, folded=qf)

    # geometry at one input -------------------------------------------------------------------------------

    def world(self, q) -> dict:
        """``{tile: vertices (k, 2)}`` at input(s) ``q``; with an array of inputs, ``(T, k, 2)``."""
        qs = np.atleast_1d(np.asarray(q, float))
        links = {s.link for s in self.shapes.values()}
        pins = {x: next(j for j in self.mech.joints_of(x) if j.kind == "R") for x in links}
        outs = sorted({f"point:{p.name}" for p in pins.values()} | {f"angle:{x}" for x in links})
        _, table = self._table(qs, outs)
        out = self._place(table)
        return {k: (v[0] if np.ndim(q) == 0 else v) for k, v in out.items()}

    def _place(self, table) -> dict:
        """``{tile: (T, k, 2)}`` from a table of pin positions and link angles."""
        out = {}
        for name, s in self.shapes.items():
            pin = next(j for j in self.mech.joints_of(s.link) if j.kind == "R")
            d = np.asarray(table[f"angle:{s.link}"]) - self.mech.reference_angle(s.link)
            c, sn = np.cos(d)[:, None], np.sin(d)[:, None]
            v = np.asarray(s.outline)
            x = c * (v[None, :, 0] - pin.at[0]) - sn * (v[None, :, 1] - pin.at[1]) + np.asarray(table[f"point:{pin.name}.x"])[:, None]
            y = sn * (v[None, :, 0] - pin.at[0]) + c * (v[None, :, 1] - pin.at[1]) + np.asarray(table[f"point:{pin.name}.y"])[:, None]
            out[name] = np.stack([x, y], axis=-1)
        return out

    def _table(self, qs, outs) -> tuple:
        """The inputs solved and the outputs there: one input, or a sweep from the first to the last of ``qs``."""
        if qs.size == 1:
            v = solve(self.mech, float(qs[0]), outputs=outs).values
            return qs, {k: np.array([x]) for k, x in v.items()}
        lo, hi = float(qs[0]), float(qs[-1])
        sw = sweep(self.mech, lo, hi, (hi - lo) / (qs.size - 1), outputs=outs)
        if not sw.success or sw.inputs.size != qs.size:
            raise InputError(f"{self.mech.name}: {sw.message}")
        return sw.inputs, sw.table

    def joints_world(self, q: float) -> np.ndarray:
        """The moving links' joints at input ``q`` (k, 2)."""
        names = [j.name for j in self.mech.joints if self.mech.ground not in j.links]
        v = solve(self.mech, q, outputs=[f"point:{n}" for n in names]).values
        return np.array([(v[f"point:{n}.x"], v[f"point:{n}.y"]) for n in names]).reshape(-1, 2)

    def radii(self, pts) -> np.ndarray:
        p = np.asarray(pts, float)
        return np.hypot(p[..., 0] - self.centre[0], p[..., 1] - self.centre[1])

    def spans(self, q: float) -> dict:
        """``{tile: (from, to)}``: the angles each tile's outer arc covers about the axis at input ``q`` (unwrapped)."""
        out = {}
        for name, v in self.world(q).items():
            r = self.radii(v)
            outer = v[r >= r.max() - 1e-9 * max(r.max(), 1.0)]
            a = np.arctan2(outer[:, 1] - self.centre[1], outer[:, 0] - self.centre[0])
            a = a[0] + np.angle(np.exp(1j * (a - a[0])))
            out[name] = (float(a.min()), float(a.max()))
        return out

    def ends(self, q: float) -> list[tuple[str, np.ndarray]]:
        """The tiles' end faces at input ``q``: ``(tile, [[inner point], [outer point]])``, this copy's and its
        neighbours' (turned ±2π/N); an edge from the least to the largest radius is an end face."""
        out = []
        pitch = 2 * math.pi / self.count
        c = np.asarray(self.centre)
        for name, v in self.world(q).items():
            r = self.radii(v)
            lo, hi = r.min(), r.max()
            tol = 1e-7 * hi
            for i in range(len(v)):
                a, b = v[i], v[(i + 1) % len(v)]
                ra, rb = r[i], r[(i + 1) % len(v)]
                if abs(ra - lo) < tol and abs(rb - hi) < tol:
                    face = np.array([a, b])
                elif abs(rb - lo) < tol and abs(ra - hi) < tol:
                    face = np.array([b, a])
                else:
                    continue
                for k in (0, 1, -1):
                    t = k * pitch
                    rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
                    out.append((f"{name}" if k == 0 else f"{name} turned {k:+d}", (face - c) @ rot.T + c))
        return out

    def end_mismatch(self, q: float) -> float:
        """The largest distance from an end face of this copy's tiles to the nearest end face of another tile."""
        ends = self.ends(q)
        worst = 0.0
        for name, f in ends:
            if " turned " in name:
                continue
            others = [g for n, g in ends if n != name]
            worst = max(worst, min((float(np.abs(g - f).max()) for g in others), default=math.inf))
        return worst

    def cylinder_residual(self, q: float) -> float:
        """How far the tiles at ``q`` are from a cylinder: every vertex on the least or the largest radius (length)."""
        r = np.concatenate([self.radii(v) for v in self.world(q).values()])
        lo, hi = r.min(), r.max()
        return float(np.max(np.minimum(r - lo, hi - r)))

    def _scan(self):
        """One sweep over a turn from the drawn pose: the inputs, the cylinder residual and the envelope there."""
        drawn = _drawn_input(self.mech)
        links = {s.link for s in self.shapes.values()}
        pins = {x: next(j for j in self.mech.joints_of(x) if j.kind == "R") for x in links}
        moving = [j.name for j in self.mech.joints if self.mech.ground not in j.links]
        outs = sorted({f"point:{p.name}" for p in pins.values()} | {f"angle:{x}" for x in links}
                      | {f"point:{n}" for n in moving})
        sw = sweep(self.mech, drawn, drawn + math.radians(358.0), math.radians(2.0), outputs=outs)
        qs = sw.inputs
        if qs.size < 3:
            raise InputError(f"{self.mech.name}: the input cannot move from its drawn pose ({sw.message})")
        world = self._place(sw.table)
        r = np.concatenate([self.radii(v) for v in world.values()], axis=1)
        lo, hi = r.min(axis=1, keepdims=True), r.max(axis=1, keepdims=True)
        residual = np.max(np.minimum(r - lo, hi - r), axis=1)
        env = r.max(axis=1)
        if moving:
            j = np.stack([np.stack([sw.table[f"point:{n}.x"], sw.table[f"point:{n}.y"]], -1) for n in moving], 1)
            env = np.maximum(env, self.radii(j).max(axis=1))
        return qs, residual, env, drawn

    def _least(self, qs, values, f, xatol: float, drawn: float) -> float:
        """The input where ``f`` is least: the scan's least sample refined between its neighbours (Brent)."""
        k = int(np.argmin(values))
        lo, hi = qs[max(k - 1, 0)], qs[min(k + 1, qs.size - 1)]
        r = minimize_scalar(lambda q: self._safe(f, q), bounds=(lo, hi), method="bounded", options={"xatol": xatol})
        return _wrap(float(r.x), drawn)

    def envelope(self, q: float) -> float:
        """The radius about the axis that holds every tile vertex and moving joint at input ``q``."""
        r = [self.radii(v).max() for v in self.world(q).values()]
        j = self.joints_world(q)
        return float(max(max(r), self.radii(j).max() if j.size else 0.0))

    @staticmethod
    def _safe(f, q) -> float:
        try:
            return f(q)
        except Exception:  # noqa: BLE001 - an input the linkage cannot reach is no candidate
            return math.inf

    # the stroke --------------------------------------------------------------------------------------------

    @property
    def stroke(self) -> tuple[float, float]:
        """Folded → deployed with the input increasing (rad)."""
        qd = self.deployed
        while qd <= self.folded:
            qd += 2 * math.pi
        while qd - self.folded > 2 * math.pi:
            qd -= 2 * math.pi
        return self.folded, qd

    def pairs(self, neighbours: int = 1) -> list[Pair]:
        """The tile pairs Δ watches: own tiles with each other, each tile with each tile of the copies ±1..±k (a pair
        with the copy turned −k·pitch is the same as the reverse pair with the copy turned +k·pitch, so only those)."""
        out = [Pair(a, b) for i, a in enumerate(self.tiles) for b in self.tiles[i + 1:]]
        pitch = 2 * math.pi / self.count
        for k in range(1, min(neighbours, self.count // 2) + 1):
            # tile a against tile b of the copy turned −k·pitch is tile b against tile a turned +k·pitch, turned
            out += [Pair(a, b, k * pitch, self.centre) for a in self.tiles for b in self.tiles]
        return out

    def discriminant(self, step: float = math.radians(1.0), neighbours: int = 1) -> Clearance:
        """``Δ`` over the stroke (:func:`~domes.design.interference.clearance` of :meth:`pairs`)."""
        lo, hi = self.stroke
        return clearance(self.mech, self.pairs(neighbours), lo, hi, step, shapes=self.shapes)

    def link_shapes(self, width: float) -> dict:
        """Each moving link as a bar: the convex hull of its joints (drawn pose) widened by ``width`` on every side
        (16 offsets round each joint, so within ``width·(1 − cos(π/16))`` of the exact widening). The mechanism
        file has no link widths; ``width`` is the designer's."""
        from scipy.spatial import ConvexHull

        if not (math.isfinite(width) and width > 0):
            raise InputError(f"{self.mech.name}: the links' half-width must be a length > 0, got {width!r}")
        if not width < 0.5 * self.size:
            raise InputError(f"{self.mech.name}: the links' half-width {width:g} is not small beside the linkage "
                             f"(its joints lie within {self.size:.6g} of the drum axis)")
        turn = np.linspace(0.0, 2 * math.pi, 16, endpoint=False)
        ring = width * np.stack([np.cos(turn), np.sin(turn)], axis=-1)
        out = {}
        for link in self.mech.links:
            if link == self.mech.ground:
                continue
            cloud = (np.array([j.at for j in self.mech.joints_of(link)], float)[:, None, :] + ring).reshape(-1, 2)
            out[f"link {link}"] = Shape.make(f"link {link}", link, [tuple(cloud[i]) for i in ConvexHull(cloud).vertices])
        return out

    def link_pairs(self, links) -> list[Pair]:
        """Tiles against links: each tile against every moving link of its own copy but its carrier, and against
        every moving link of the copies turned ±pitch about the axis."""
        pitch = 2 * math.pi / self.count
        out = []
        for t in self.tiles:
            for name, s in links.items():
                if s.link != self.shapes[t].link:
                    out.append(Pair(t, name))
                out += [Pair(t, name, pitch, self.centre), Pair(t, name, -pitch, self.centre)]
        return out

    def link_clearance(self, width: float, step: float = math.radians(1.0)) -> Clearance:
        """The least signed clearance of the tiles against the links (bars of half-width ``width``,
        :meth:`link_shapes`) from folded to deployed."""
        links = self.link_shapes(width)
        lo, hi = self.stroke
        return clearance(self.mech, self.link_pairs(links), lo, hi, step, shapes={**self.shapes, **links})

    def swept_diameter(self, step: float = math.radians(1.0)) -> float:
        """``D0``: twice the largest radius the tiles reach during deployment (samples, then refined)."""
        lo, hi = self.stroke
        n = max(2, math.ceil((hi - lo) / step))
        qs = np.linspace(lo, hi, n + 1)
        w = self.world(qs)
        r = np.max([self.radii(v).max(axis=1) for v in w.values()], axis=0)
        k = int(np.argmax(r))
        a, b = qs[max(k - 1, 0)], qs[min(k + 1, n)]
        res = minimize_scalar(lambda q: -max(self.radii(v).max() for v in self.world(q).values()), bounds=(a, b),
                              method="bounded", options={"xatol": 1e-9})
        return 2 * max(float(r[k]), -float(res.fun))

    def tile_angles(self) -> dict:
        """α1, β1: per tile, the angle between its centroid's velocity at deployment and the drum's tangent (rad)."""
        h = 1e-6
        a, b = self.world(self.deployed - h), self.world(self.deployed + h)
        out = {}
        for name in self.tiles:
            pa, pb = a[name].mean(axis=0), b[name].mean(axis=0)
            v = (pb - pa) / (2 * h)
            p = 0.5 * (pa + pb)
            radial = (p - np.asarray(self.centre)) / np.hypot(*(p - np.asarray(self.centre)))
            speed = float(np.hypot(*v))
            out[name] = 0.0 if speed < 1e-6 * self.size else math.asin(min(1.0, abs(float(v @ radial)) / speed))
        return out

    def hold_share(self) -> float:
        """The holding torque's share of load × tiles × D2/2 by virtual work (the tile centroids' radial rates at
        deployment, central differences): what :meth:`holding_torque` gives, without the inverse statics."""
        h = 1e-6
        a, b = self.world(self.deployed - h), self.world(self.deployed + h)
        c = np.asarray(self.centre)
        power = 0.0
        for name in self.tiles:
            p = 0.5 * (a[name].mean(axis=0) + b[name].mean(axis=0))
            v = (b[name].mean(axis=0) - a[name].mean(axis=0)) / (2 * h)
            power += float(v @ ((c - p) / np.hypot(*(c - p))))
        radius = max(float(self.radii(v).max()) for v in a.values())
        return abs(power) / (len(self.tiles) * radius)

    @property
    def size(self) -> float:
        return float(max(np.hypot(*np.subtract(j.at, self.centre)) for j in self.mech.joints))

    def holding_torque(self, load: float = 1000.0) -> tuple[float, float]:
        """The main shaft's static torque holding the tiles at deployment against an inward radial ``load`` (N) on
        each tile's centroid (:func:`~domes.design.forces.drive`), and its share of ``load × N_tiles × D2/2``."""
        w = self.world(self.deployed)
        loads = []
        for name in self.tiles:
            s = self.shapes[name]
            p = w[name].mean(axis=0)
            u = (np.asarray(self.centre) - p) / np.hypot(*(np.asarray(self.centre) - p))
            drawn = np.asarray(s.outline).mean(axis=0)
            loads.append(Load(f"blank on {name}", s.link, (float(load * u[0]), float(load * u[1])),
                              (float(drawn[0]), float(drawn[1]))))
        static = dataclasses.replace(self.mech, inputs=tuple(dataclasses.replace(i, speed=0.0, acceleration=0.0)
                                                             for i in self.mech.inputs),
                                     masses=MassModel(loads=tuple(loads)))
        # the loads keep their deployed (radial) directions; the torque is read at the deployed input
        h = math.radians(0.01)
        r = forces.drive(static, self.deployed - h, self.deployed + h, h)
        joint = r.joint
        tau = float(r.dynamics.driving[joint][1])
        radius = max(float(self.radii(v).max()) for v in w.values())
        return tau, abs(tau) / (load * len(self.tiles) * radius)


def _drawn_input(mech: Mechanism) -> float:
    from domes.motion.planar.query import Kinematics

    return float(Kinematics(mech).drawn_inputs()[mech.inputs[0].joint])


def _wrap(q: float, ref: float) -> float:
    """``q`` less whole turns, within [ref, ref + 2π)."""
    return ref + (q - ref) % (2 * math.pi)


# -- the checks ------------------------------------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class DrumCheck(Result):
    """Every drum check of one design: cylinder, folded space, Δ_min, D0/D1, α1/β1, anti-retraction."""

    name: str
    count: int
    inner: float
    outer: float
    cylinder_residual: float
    cylinder_gap: float
    folded_diameter: float
    bead: float
    delta: Clearance
    swept: float
    angles: dict
    holding: float
    holding_share: float
    deployed: float
    folded: float
    links: Clearance | None = None
    link_width: float | None = None

    @property
    def folding_ratio(self) -> float:
        """``D1 / Df``."""
        return 2 * self.inner / self.folded_diameter

    @property
    def d0_d1(self) -> float:
        return self.swept / (2 * self.inner)

    @property
    def failures(self) -> list[str]:
        out = []
        scale = self.outer
        if self.cylinder_residual > CYLINDER_TOL * scale or self.cylinder_gap > CYLINDER_TOL * scale:
            out.append(f"deployed, the tiles are no gap-free cylinder (radii off by {self.cylinder_residual:.3g}, "
                       f"end faces {self.cylinder_gap:.3g} from their neighbours')")
        if not self.folded_diameter < self.bead:
            out.append(f"folded, the drum needs a diameter {self.folded_diameter:.6g}, not less than the bead's "
                       f"{self.bead:.6g}")
        if self.delta.minimum < -DELTA_TOL * self.outer:
            out.append(f"interference: Δ_min = {self.delta.minimum:.6g} between {self.delta.pair.label} at input "
                       f"{math.degrees(self.delta.input):.6g}°")
        if self.links is not None and self.links.minimum < -DELTA_TOL * self.outer:
            out.append(f"tiles against links (half-width {self.link_width:g}): clearance {self.links.minimum:.6g} "
                       f"between {self.links.pair.label} at input {math.degrees(self.links.input):.6g}°")
        if self.holding_share > HOLD_SHARE:
            out.append(f"anti-retraction: holding torque {self.holding_share:.3g} of load × radius, more than "
                       f"{HOLD_SHARE:g}")
        return out

    @property
    def status(self) -> Status:
        return Status.COMPLETE if not self.failures else Status.STOPPED

    @property
    def message(self) -> str:
        a = ", ".join(f"{k} {math.degrees(v):.4g}°" for k, v in self.angles.items())
        head = (f"{self.name}: N = {self.count}, D1 = {2 * self.inner:.6g}, D2 = {2 * self.outer:.6g}; folded "
                f"{self.folded_diameter:.6g} (D1/Df = {self.folding_ratio:.4f}); Δ_min = {self.delta.minimum:.6g} "
                f"({self.delta.pair.label} at {math.degrees(self.delta.input):.6g}°); D0/D1 = {self.d0_d1:.4f}; "
                f"α1, β1 = {a}; holding torque {self.holding:.4g} ({self.holding_share:.3g} of load × radius)")
        if self.links is not None:
            head += (f"; tiles against links (half-width {self.link_width:g}): least clearance "
                     f"{self.links.minimum:.6g} ({self.links.pair.label} at {math.degrees(self.links.input):.6g}°)")
        return head + ("" if self.success else "; fails: " + "; ".join(self.failures))


def check(drum: Drum, bead: float | None = None, step: float = math.radians(1.0),
          link_width: float | None = None) -> DrumCheck:
    """Run every drum check on ``drum``; ``bead`` the bead diameter (default ``D1``); with ``link_width``, also the
    tiles against the links as bars of that half-width (:meth:`Drum.link_clearance`)."""
    w = drum.world(drum.deployed)
    r = np.concatenate([drum.radii(v) for v in w.values()])
    inner, outer = float(r.min()), float(r.max())
    gap = drum.end_mismatch(drum.deployed)
    delta = drum.discriminant(step)
    angles = drum.tile_angles()
    tau, share = drum.holding_torque()
    return DrumCheck(drum.mech.name, drum.count, inner, outer, drum.cylinder_residual(drum.deployed), gap,
                     2 * drum.envelope(drum.folded), 2 * inner if bead is None else bead, delta,
                     drum.swept_diameter(step), angles, tau, share, drum.deployed, drum.folded,
                     None if link_width is None else drum.link_clearance(link_width, step), link_width)


# -- a drum design: the free dimensions on a given linkage -------------------------------------------------------


@dataclass(frozen=True)
class Design:
    """The free dimensions of a drum built on a linkage (bare or dressed: its tiles are replaced).

    The tile pair is centred on ``reach`` (a point of the deployed outer
    surface) and faces the direction ``facing`` (rad, outward); the axis lies
    ``outer`` behind ``reach``. ``thickness`` = (D2 − D1)/2; ``count`` pairs;
    tile I takes ``share`` of the pitch; ``slants`` turn the end faces (their
    inner end ``slant`` further round the axis than their outer end: shaped tile
    ends). ``carriers`` are the links of tile I and tile II; ``deployed`` and
    ``folded`` the stroke's ends (rad).
    """

    mech: Mechanism
    carriers: dict
    deployed: float
    folded: float
    reach: tuple
    facing: float
    outer: float
    thickness: float
    count: int
    share: float
    slants: tuple = (0.0, 0.0)
    order: tuple = ("tile II", "tile I")
    arcs: int = 6

    @property
    def centre(self) -> tuple:
        return (self.reach[0] - self.outer * math.cos(self.facing), self.reach[1] - self.outer * math.sin(self.facing))

    def layout(self) -> Layout:
        return Layout(self.centre, self.count, self.outer - self.thickness, self.outer,
                      self.facing - math.pi / self.count, self.share, self.arcs, self.order, tuple(self.slants))

    def drum(self) -> Drum:
        """The dressed mechanism read as a drum (tile count and poses as designed)."""
        return Drum.of(dress(self.mech, self.layout(), self.deployed, self.carriers), count=self.count,
                       deployed=self.deployed, folded=self.folded)

    def with_(self, **changes) -> "Design":
        return dataclasses.replace(self, **changes)


#: The free dimensions :func:`optimise` may vary, by name: how to read and set each from a vector entry.
FREE = {
    "slants": 2,     # the two end-face slants (rad)
    "share": 1,      # tile I's share of the pitch
    "facing": 1,     # the pair's outward direction (rad)
    "reach": 2,      # the pair's mid point on the outer surface
    "outer": 1,      # D2/2, the axis moving along the facing line
}


def _vector(d: Design, free) -> np.ndarray:
    out = []
    for name in free:
        v = getattr(d, name)
        out += list(v) if isinstance(v, tuple) else [v]
    return np.array(out, float)


def _from_vector(d: Design, free, x) -> Design:
    changes, k = {}, 0
    for name in free:
        n = FREE[name]
        changes[name] = tuple(float(v) for v in x[k:k + n]) if n > 1 else float(x[k])
        k += n
    return d.with_(**changes)


def delta_min(design: Design, step: float = math.radians(1.0), fold: float = 1.0, hold: float | None = None) -> float:
    """``Δ_min`` of a design, or a negative penalty when it cannot be built or checked (a bad outline, the
    linkage poking out of the deployed cylinder, a folded drum outside ``D1/fold``, a stroke it cannot sweep);
    with ``hold``, also a negative penalty when the holding torque's share (:meth:`Drum.hold_share`) exceeds it."""
    try:
        drum = design.drum()
        lay = design.layout()
        lo, hi = drum.stroke
        inside = max(drum.radii(drum.joints_world(q)).max() for q in (lo, hi, 0.5 * (lo + hi)))
        if inside > lay.inner:
            return -(inside - lay.inner) - 0.1 * lay.outer
        env = drum.envelope(drum.folded)
        if env * fold >= lay.inner:
            return -(env - lay.inner / fold) - 0.1 * lay.outer
        if hold is not None:
            share = drum.hold_share()
            if share > hold:
                return -0.1 * (share - hold) * lay.outer - 1e-4 * lay.outer
        return drum.discriminant(step).minimum
    except (InputError, NumericalError, ValueError):
        return -0.5 * abs(design.outer)        # worse than any design that can be built


@dataclass(frozen=True, eq=False)
class Optimum(Result):
    """The result of :func:`optimise`: the design, its ``Δ_min``, how many designs were evaluated."""

    design: Design
    start: float
    delta: float
    evaluations: int
    free: tuple
    tol: float

    @property
    def status(self) -> Status:
        return Status.COMPLETE if abs(self.delta) <= self.tol or self.delta > 0 else Status.STOPPED

    @property
    def message(self) -> str:
        word = "reached" if self.success else "did not reach"
        return (f"{word} Δ_min = 0 (within {self.tol:g}): Δ_min {self.start:.6g} → {self.delta:.6g} varying "
                f"{', '.join(self.free)} in {self.evaluations} evaluations")


def optimise(design: Design, free=("slants",), tol: float = 1e-6, evaluations: int = 300,
             step: float = math.radians(1.0), fold: float = 1.0, hold: float | None = None) -> Optimum:
    """Vary the ``free`` dimensions (names of :data:`FREE`) until ``Δ_min = 0`` (within ``tol``, a length).

    ``Δ_min`` cannot exceed 0 for a gap-free cylinder (the tiles touch when
    deployed), so this maximises ``Δ_min`` (Nelder–Mead, adaptive) and stops
    as soon as it is within ``tol`` of 0. The cylinder stays exact: every
    design is built from its layout. ``fold``: the folding ratio ``D1/Df``
    the design must reach (1: fit inside ``D1``); ``hold``: the largest share
    of the holding torque allowed (anti-retraction; None: not asked).
    """
    from scipy.optimize import minimize

    free = tuple(free)
    for name in free:
        if name not in FREE:
            raise InputError(f"optimise: {name!r} is not a free dimension; choose from {sorted(FREE)}")
    x0 = _vector(design, free)
    start = delta_min(design, step, fold, hold)
    count = [1]
    best = [start, x0]

    class Done(Exception):
        pass

    def f(x):
        count[0] += 1
        v = delta_min(_from_vector(design, free, x), step, fold, hold)
        if v > best[0]:
            best[:] = [v, np.array(x)]
        if v >= -tol:
            raise Done
        if count[0] >= evaluations:
            raise Done
        return -v

    if start < -tol:
        try:
            minimize(f, x0, method="Nelder-Mead", options={"maxfev": evaluations, "xatol": 1e-9, "fatol": 1e-12,
                                                          "adaptive": True})
        except Done:
            pass
    return Optimum(_from_vector(design, free, best[1]), start, best[0], count[0], free, tol)


def lengthen(drum: Drum, factor: float) -> Drum:
    """The same drum with every tile ``factor`` times as long round the axis (about its middle, as deployed)."""
    if not (math.isfinite(factor) and factor > 0):
        raise InputError(f"lengthen: the factor must be a number > 0, got {factor!r}")
    pose = _pose(drum.mech, drum.deployed, {s.link for s in drum.shapes.values()})
    world = drum.world(drum.deployed)
    cx, cy = drum.centre
    polys = []
    for name, s in drum.shapes.items():
        v = world[name]
        r = np.hypot(v[:, 0] - cx, v[:, 1] - cy)
        a = np.arctan2(v[:, 1] - cy, v[:, 0] - cx)
        a = a[0] + np.angle(np.exp(1j * (a - a[0])))
        mid = 0.5 * (a.min() + a.max())
        a = mid + factor * (a - mid)
        w = np.stack([cx + r * np.cos(a), cy + r * np.sin(a)], axis=-1)
        d, p0, p = pose[s.link]
        c, sn = math.cos(d), math.sin(d)
        verts = tuple((c * (x - p[0]) + sn * (y - p[1]) + p0[0], -sn * (x - p[0]) + c * (y - p[1]) + p0[1])
                      for x, y in w)
        polys.append(Polygon(name, s.link, verts))
    keep = tuple(x for x in drum.mech.polygons if x.name not in drum.shapes)
    mech = dataclasses.replace(drum.mech, polygons=keep + tuple(polys))
    return Drum.of(mech, count=drum.count, deployed=drum.deployed, folded=drum.folded)


@dataclass(frozen=True, eq=False)
class LayoutOptimum(Result):
    """The tile layout (count ``N``, tile I's share) whose folded tiles close the least perimeter, interference-free
    folded; ``table`` holds ``(N, share, perimeter, folded clearance)`` of every layout tried."""

    count: int
    share: float
    perimeter: float
    table: tuple

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.count else Status.EMPTY

    @property
    def message(self) -> str:
        if not self.count:
            return f"no layout of the {len(self.table)} tried is interference-free folded"
        return (f"N = {self.count}, tile I's share {self.share:.4g}: folded perimeter {self.perimeter:.6g} "
                f"(least of {sum(1 for t in self.table if t[3] >= 0)} interference-free folded layouts of "
                f"{len(self.table)})")


def layout_optimum(design: Design, counts=range(4, 17), shares=np.linspace(0.2, 0.6, 9)) -> LayoutOptimum:
    """The tile-layout reading of §3-8 (step 1): over tile counts and tile I's shares of the pitch (the design's
    own always among them), the layout whose folded tiles (all ``N`` pairs) have the least convex-hull perimeter
    with no interference folded."""
    from scipy.spatial import ConvexHull

    table = []
    counts = sorted(set(int(n) for n in counts) | {design.count})
    shares = sorted(set(float(s) for s in shares) | {design.share})
    for n in counts:
        for s in shares:
            d = design.with_(count=int(n), share=float(s))
            try:
                drum = d.drum()
            except (InputError, NumericalError):
                continue
            w = drum.world(drum.folded)
            pitch = 2 * math.pi / drum.count
            c = np.asarray(drum.centre)
            pts = []
            for k in range(drum.count):
                rot = np.array([[math.cos(k * pitch), -math.sin(k * pitch)], [math.sin(k * pitch), math.cos(k * pitch)]])
                pts += [(v - c) @ rot.T + c for v in w.values()]
            hull = ConvexHull(np.concatenate(pts))
            from domes.design.interference import signed_clearance

            gaps = [signed_clearance(_turn(w[p.first], 0.0, c), _turn(w[p.second], p.turn, c))
                    for p in drum.pairs()]
            table.append((int(n), float(s), float(hull.area), float(min(gaps))))
    ok = [t for t in table if t[3] >= 0]
    if not ok:
        return LayoutOptimum(0, math.nan, math.nan, tuple(table))
    best = min(ok, key=lambda t: t[2])
    return LayoutOptimum(best[0], best[1], best[2], tuple(table))


def _turn(v, t, c):
    rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
    return [tuple(p) for p in (np.asarray(v) - c) @ rot.T + c]


@dataclass(frozen=True, eq=False)
class Threshold(Result):
    """The largest folding ratio ``D1/Df`` for which the optimisation still reaches ``Δ_min = 0`` (bisection).

    ``rows`` holds ``(ratio asked, reached, D1/Df, D0/D1, best Δ_min, what failed)`` of every ratio tried;
    ``design`` is the design at the threshold (the last ratio reached).
    """

    ratio: float
    d0_d1: float
    rows: tuple
    design: Design | None
    limit: str
    free: tuple

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.design is not None else Status.EMPTY

    @property
    def message(self) -> str:
        if self.design is None:
            return "the optimisation reaches Δ_min = 0 at none of the folding ratios asked"
        return (f"threshold D1/Df = {self.ratio:.4f} (D0/D1 = {self.d0_d1:.4f}) varying {', '.join(self.free)}; "
                f"beyond it: {self.limit} ({len(self.rows)} ratios tried)")


def _ratios(design: Design) -> tuple[float, float]:
    drum = design.drum()
    lay = design.layout()
    return lay.inner / drum.envelope(drum.folded), drum.swept_diameter() / (2 * lay.inner)


def threshold(design: Design, low: float, high: float, iterations: int = 6, free=("outer", "slants"),
              tol: float = 1e-6, evaluations: int = 150) -> Threshold:
    """Bisection on the folding ratio ``D1/Df`` between ``low`` (reached) and ``high``: at each ratio asked the
    ``free`` dimensions are optimised (:func:`optimise` with ``fold``) from the last design that reached
    ``Δ_min = 0``; the ratio is reached when ``Δ_min = 0`` is, with the folded drum inside ``D1/ratio``."""
    rows = []
    good, limit = None, "not tried"

    def attempt(ratio, start):
        opt = optimise(start, free, tol=tol, evaluations=evaluations, step=math.radians(2.0), fold=ratio)
        try:
            reached, d0 = _ratios(opt.design)
        except (InputError, NumericalError):
            reached, d0 = math.nan, math.nan
        ok = opt.success and reached >= ratio * (1 - 1e-9)
        why = "" if ok else _why(opt.design, opt.delta, tol, ratio)
        rows.append((float(ratio), ok, reached, d0, opt.delta, why))
        return ok, opt.design, why

    ok, d, why = attempt(low, design)
    if not ok:
        return Threshold(math.nan, math.nan, tuple(rows), None, why, tuple(free))
    good = d
    ok, d, why = attempt(high, good)
    if ok:
        r, d0 = _ratios(d)
        return Threshold(r, d0, tuple(rows), d, "the highest ratio asked was reached", tuple(free))
    limit = why
    lo, hi = low, high
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        ok, d, why = attempt(mid, good)
        if ok:
            lo, good = mid, d
        else:
            hi, limit = mid, why
    r, d0 = _ratios(good)
    return Threshold(r, d0, tuple(rows), good, limit, tuple(free))


def _why(design: Design, delta: float, tol: float, fold: float = 1.0) -> str:
    try:
        drum = design.drum()
        lay = design.layout()
        lo, hi = drum.stroke
        inside = max(drum.radii(drum.joints_world(q)).max() for q in (lo, hi, 0.5 * (lo + hi)))
        if inside > lay.inner:
            return "the linkage reaches out of the deployed cylinder"
        if drum.envelope(drum.folded) * fold >= lay.inner:
            return f"folded, the drum does not fit inside D1/{fold:.4g}"
    except (InputError, NumericalError):
        return "the design cannot be built"
    return f"interference (best Δ_min {delta:.3g})"


# -- regenerated candidates: a seeded construction ------------------------------------------------------------


def seed_design(chain, rng: np.random.Generator, count: int = 12, size: float = 0.15, thickness: float = 0.02,
                name: str = "candidate") -> Design | None:
    """A first drum design on a labelled drum candidate (roles ``ground``, ``input``, ``tile_a``, ``tile_b``), or
    None when this seed gives no usable stroke.

    The joints are drawn at random in a square of half-side ``size`` (the drawn pose is the deployed one);
    the input turns back from there as far as it can within half a turn (at least 60°): that end is the
    folded pose. The tile pair faces the way tile A's link moves outward (folded → deployed), just beyond every
    joint over the stroke, on a drum of outer radius three times the linkage's spread; tile A is tile I.
    """
    from domes.model.mechanism import from_labelled

    roles = {r: chain.links_with_role(r) for r in ("tile_a", "tile_b", "input")}
    if any(len(v) != 1 for v in roles.values()):
        raise InputError(f"{name}: a drum candidate needs one link each with roles tile_a, tile_b and input")
    at = {e: tuple(rng.uniform(-size, size, 2)) for e in chain.edges}
    try:
        mech = from_labelled(chain, at, name=name)
        q0 = _drawn_input(mech)
        moving = [j.name for j in mech.joints if mech.ground not in j.links]
        outs = [f"point:{n}" for n in moving]
        sw = sweep(mech, q0, q0 - math.pi, math.radians(2.0), outputs=outs)
    except (InputError, NumericalError):
        return None
    if sw.inputs.size < 31:
        return None
    qf = float(sw.inputs[-1])
    a = str(roles["tile_a"][0])
    pins = [j.name for j in mech.joints_of(a)]
    pf = np.mean([(sw.table[f"point:{n}.x"][-1], sw.table[f"point:{n}.y"][-1]) for n in pins if n in moving]
                 or [(0.0, 0.0)], axis=0)
    pd = np.mean([mech.joint(n).at for n in pins], axis=0)
    move = pd - pf
    if not np.hypot(*move) > 1e-3 * size:
        return None
    facing = math.atan2(move[1], move[0])
    u = np.array([math.cos(facing), math.sin(facing)])
    pts = np.concatenate([np.stack([sw.table[f"point:{n}.x"], sw.table[f"point:{n}.y"]], -1) for n in moving]
                         + [np.array([j.at for j in mech.joints])])
    spread = float(np.ptp(pts, axis=0).max())
    b = str(roles["tile_b"][0])
    mid = np.mean([mech.joint(n).at for n in pins] + [mech.joint(j.name).at for j in mech.joints_of(b)], axis=0)
    reach = mid + (float(np.max(pts @ u)) - float(mid @ u) + 2 * thickness) * u
    return Design(mech, {"tile I": a, "tile II": b}, q0, qf, (float(reach[0]), float(reach[1])), facing,
                  3.0 * spread, thickness, count, 0.5, (0.0, 0.0))


@dataclass(frozen=True, eq=False)
class CandidateRow:
    """One regenerated candidate's attempt: its id and chain, seeds tried, the best ``Δ_min`` and the design."""

    id: str
    chain: int
    existing: bool
    seeds: int
    built: int
    best: float
    design: Design | None
    check: DrumCheck | None = None

    @property
    def reached(self) -> bool:
        """``Δ_min = 0`` reached (the linkage inside the cylinder and the folded drum inside D1 with it)."""
        return self.design is not None and self.best >= -1e-6

    @property
    def passes(self) -> bool:
        """Every drum check passes too (:func:`check`: anti-retraction included)."""
        return self.check is not None and self.check.success


def dimension_candidates(candidates, seeds: int = 2, evaluations: int = 80, seed: int = 29,
                         free=("reach", "facing", "outer", "share", "slants"),
                         hold: float | None = HOLD_SHARE) -> list[CandidateRow]:
    """Seeded construction (:func:`seed_design`) and :func:`optimise` to ``Δ_min = 0`` for each regenerated candidate
    (objects with ``labelled``, ``id``, ``chain_index``, ``existing``); a design that reaches it is then put
    through every drum check (:func:`check`). With ``hold`` (default :data:`HOLD_SHARE`) anti-retraction is
    part of the optimisation; with None it is only checked."""
    rows = []
    for c in candidates:
        rng = np.random.default_rng([seed, int(c.id) if str(c.id).isdigit() else abs(hash(c.id)) % 10 ** 6])
        best, design, built = -math.inf, None, 0
        for _ in range(seeds):
            d = seed_design(c.labelled, rng, name=f"candidate {c.id}")
            if d is None:
                continue
            built += 1
            opt = optimise(d, free, evaluations=evaluations, step=math.radians(3.0), hold=hold)
            if opt.delta > best:
                best, design = opt.delta, opt.design
            if opt.success:
                break
        row = CandidateRow(str(c.id), int(c.chain_index), bool(c.existing), seeds, built, best, design)
        if row.reached:
            try:
                row = dataclasses.replace(row, check=check(design.drum()))
            except (InputError, NumericalError):
                pass
        rows.append(row)
    return rows
