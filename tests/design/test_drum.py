"""The tyre-building drum end to end (issue 29, item 1; seed 002, §5-1 and §5-3, digest 3.1, 3.3, 3.7, 3.8).

The book's figures are lost, so ``Δ = S × T``, ``α1, β1`` and the tile layout
are the project's readings (docs/drum.md). What is checked here against an
independent route:

* the signed clearance of two polygons against brute force written here:
  the distance by enumerating every vertex against every edge, overlap by a
  point-in-polygon test, and the penetration depth of convex polygons as the
  least support width of their Minkowski difference over 20,000 directions;
* the least clearance over a stroke against dense sampling of the stroke
  (0.02° steps) with that brute-force distance;
* the drum of Fig. 5-1 (our dimensions) passes every check; 10 % longer tiles
  are caught with the pair and the input angle; the anti-retraction torque
  of :func:`~domes.design.forces.drive` against the virtual work of the tiles'
  velocities; Δ_min reaches 0 by the optimisation.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from domes.design import drum as dm
from domes.design.interference import Pair, Shape, clearance, convex_pieces, signed_clearance
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.io.resources import knowledge_dir
from domes.motion.planar.examples import four_bar
from domes.motion.planar.sweep import sweep

FILE = knowledge_dir() / "mechanisms" / "tyre-drum-fig5-1.json"
DRUM = dm.Drum.of(load_mechanism(FILE))


# -- brute force, written here ---------------------------------------------------------------------------------


def brute_distance(a, b) -> float:
    """Distance of two disjoint polygons: every vertex against every edge of the other."""
    best = math.inf
    for p, q in ((a, b), (b, a)):
        for v in p:
            for i in range(len(q)):
                s, e = np.asarray(q[i], float), np.asarray(q[(i + 1) % len(q)], float)
                d = e - s
                t = min(1.0, max(0.0, float(np.dot(np.asarray(v) - s, d) / np.dot(d, d))))
                best = min(best, float(np.hypot(*(np.asarray(v) - s - t * d))))
    return best


def brute_distances(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """:func:`brute_distance` of polygons ``a`` posed at many inputs (T, n, 2) from a fixed polygon ``b`` (m, 2)."""
    best = np.full(a.shape[0], np.inf)
    for p, q in ((a, np.broadcast_to(b, (a.shape[0],) + b.shape)), (np.broadcast_to(b, (a.shape[0],) + b.shape), a)):
        for i in range(q.shape[1]):
            s, e = q[:, i], q[:, (i + 1) % q.shape[1]]
            d = e - s
            for j in range(p.shape[1]):
                v = p[:, j]
                t = np.clip(np.sum((v - s) * d, axis=1) / np.sum(d * d, axis=1), 0.0, 1.0)
                best = np.minimum(best, np.hypot(*(v - s - t[:, None] * d).T))
    return best


def inside(p, poly) -> bool:
    x, y = p
    hit = False
    for i in range(len(poly)):
        (x1, y1), (x2, y2) = poly[i], poly[(i + 1) % len(poly)]
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            hit = not hit
    return hit


def crossing(a, b) -> bool:
    def cross(o, p, q):
        return (p[0] - o[0]) * (q[1] - o[1]) - (p[1] - o[1]) * (q[0] - o[0])

    for i in range(len(a)):
        p, q = a[i], a[(i + 1) % len(a)]
        for j in range(len(b)):
            r, s = b[j], b[(j + 1) % len(b)]
            if cross(p, q, r) * cross(p, q, s) < 0 and cross(r, s, p) * cross(r, s, q) < 0:
                return True
    return False


def overlap(a, b) -> bool:
    return crossing(a, b) or inside(a[0], b) or inside(b[0], a)


def brute_depth(a, b, n=20000) -> float:
    """Penetration depth of convex polygons: the least support width of A ⊖ B over dense directions (20,000 round
    the circle, then 20,001 within two steps of the best)."""

    def width(t):
        u = np.stack([np.cos(t), np.sin(t)], axis=1)
        pa, pb = np.asarray(a) @ u.T, np.asarray(b) @ u.T
        return pa.max(axis=0) - pb.min(axis=0)

    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    w = width(t)
    k = int(np.argmin(w))
    fine = np.linspace(t[k] - 4 * math.pi / n, t[k] + 4 * math.pi / n, 20001)
    return float(min(w[k], width(fine).min()))


def random_convex(rng, centre, radius, k):
    ang = np.sort(rng.uniform(0, 2 * math.pi, k))
    r = radius * rng.uniform(0.6, 1.0, k)
    pts = [(centre[0] + r[i] * math.cos(ang[i]), centre[1] + r[i] * math.sin(ang[i])) for i in range(k)]
    from scipy.spatial import ConvexHull

    hull = ConvexHull(pts)
    return [pts[i] for i in hull.vertices]


def random_star(rng, centre, radius, k):
    """A simple, generally non-convex polygon: a star about its centre (one vertex in each of ``k`` ≥ 5 equal
    sectors, so no two neighbours are half a turn apart)."""
    k = max(k, 5)
    ang = (np.arange(k) + rng.uniform(0, 1, k)) * 2 * math.pi / k
    r = radius * rng.uniform(0.3, 1.0, k)
    return [(centre[0] + r[i] * math.cos(ang[i]), centre[1] + r[i] * math.sin(ang[i])) for i in range(k)]


# -- the signed clearance --------------------------------------------------------------------------------------


def test_signed_clearance_of_polygons_against_brute_force():
    """Distance apart (vertex/edge enumeration), sign by overlap (point in polygon, edge crossings), depth of convex
    pairs (support widths of the Minkowski difference, to 1e-6): 200 seeded pairs, convex and star-shaped."""
    rng = np.random.default_rng(29)
    apart = deep = 0
    for k in range(200):
        make = random_convex if k % 2 else random_star
        a = make(rng, (0.0, 0.0), 1.0, int(rng.integers(3, 9)))
        b = make(rng, tuple(rng.uniform(-2.2, 2.2, 2)), rng.uniform(0.3, 1.2), int(rng.integers(3, 9)))
        s = signed_clearance(a, b)
        if overlap(a, b):
            assert s < 0, k
            if make is random_convex:
                assert s == pytest.approx(-brute_depth(a, b), abs=1e-6), k
                deep += 1
        else:
            assert s == pytest.approx(brute_distance(a, b), abs=1e-12), k
            apart += 1
    assert apart > 100 and deep > 10


def test_convex_pieces_cover_the_polygon():
    """The pieces of a star polygon are convex and their areas add up to the polygon's (shoelace formula)."""
    rng = np.random.default_rng(3)
    for _ in range(30):
        poly = random_star(rng, (0.0, 0.0), 1.0, 9)
        pieces = convex_pieces(poly)
        area = lambda p: 0.5 * abs(sum(p[i][0] * p[(i + 1) % len(p)][1] - p[(i + 1) % len(p)][0] * p[i][1]  # noqa: E731
                                       for i in range(len(p))))
        assert sum(area(p) for p in pieces) == pytest.approx(area(poly), rel=1e-9)
        for p in pieces:
            n = len(p)
            e = [p[(i + 1) % n] - p[i] for i in range(n)]
            assert all(e[i][0] * e[(i + 1) % n][1] - e[i][1] * e[(i + 1) % n][0] >= -1e-12 for i in range(n))
    with pytest.raises(InputError, match="not a simple polygon"):
        convex_pieces([(0, 0), (2, 2), (2, 0), (0, 1)])       # a bow tie
    with pytest.raises(InputError, match="no area"):
        convex_pieces([(0, 0), (1, 1), (2, 2)])


def test_least_clearance_over_a_stroke_is_refined_between_samples():
    """A coupler pad passing a frame stop (seed 000's four-bar): the least over a coarse 5° grid, refined between
    samples, equals the least of a dense 0.02° sampling with the brute-force distance, and is lower than the
    coarse samples' least."""
    pad = [(2.0, 2.3), (2.4, 2.3), (2.4, 2.6), (2.0, 2.6)]
    stop = [(-1.0, 3.05), (0.2, 3.05), (0.2, 3.4), (-1.0, 3.4)]
    shapes = {"pad": Shape.make("pad", "coupler", pad), "stop": Shape.make("stop", "frame", stop)}
    m = four_bar()
    r = clearance(m, [Pair("pad", "stop")], 0.0, 2 * math.pi, math.radians(5.0), shapes=shapes)
    sw = sweep(m, 0.0, 2 * math.pi, math.radians(0.02), outputs=["point:B", "angle:coupler"])
    b0 = m.joint("B").at
    d = sw.table["angle:coupler"] - m.reference_angle("coupler")
    c, s = np.cos(d)[:, None], np.sin(d)[:, None]
    px, py = np.array(pad).T
    placed = np.stack([c * (px - b0[0]) - s * (py - b0[1]) + sw.table["point:B.x"][:, None],
                       s * (px - b0[0]) + c * (py - b0[1]) + sw.table["point:B.y"][:, None]], axis=-1)
    dense = brute_distances(placed, np.array(stop, float))
    k = int(np.argmin(dense))
    assert r.minimum > 0 and r.minimum == pytest.approx(dense[k], abs=1e-6)
    assert abs(r.input - sw.inputs[k]) < math.radians(0.05)
    assert r.minimum < r.samples.min() - 1e-4          # the coarse samples alone miss it
    assert r.refined >= 1 and r.pair.label == "pad / stop"


# -- the drum of Fig. 5-1 --------------------------------------------------------------------------------------


def test_fig5_1_drum_passes_every_check():
    """Seed 002 §5-3 design requirements and screening rules 1, 2, 4 on our dimensioned Fig. 5-1: a gap-free
    cylinder deployed, folded inside D1, Δ_min = 0 (the tiles touch only when deployed), anti-retraction."""
    c = dm.check(DRUM)
    assert c.success, c.message
    assert c.count == 12
    assert math.degrees(DRUM.deployed) % 360 == pytest.approx(31.9565, abs=1e-3)    # the four-bar's dead centre
    assert math.degrees(DRUM.folded) == pytest.approx(214.728, abs=1e-3)           # the other one
    assert abs(c.delta.minimum) < 1e-9 * c.outer and math.degrees(c.delta.input) % 360 == pytest.approx(31.9565, abs=1e-3)
    assert c.folding_ratio > 1.25 and 1.0 < c.d0_d1 < 1.1
    assert c.angles["tile II"] == 0.0 and 0 < c.angles["tile I"] < math.radians(30)


def test_folded_envelope_and_swept_diameter_against_dense_sampling():
    """Df and D0 (digest 3.3, rule 1 and rule 3) against a dense 0.1° sweep of the tile vertices and joints."""
    lo, hi = DRUM.stroke
    qs = np.linspace(lo, hi, int(math.degrees(hi - lo) * 10) + 1)
    w = DRUM.world(qs)
    r = np.max([DRUM.radii(v).max(axis=1) for v in w.values()], axis=0)
    assert DRUM.swept_diameter() == pytest.approx(2 * r.max(), rel=1e-6)
    assert DRUM.swept_diameter() >= 2 * r.max() - 1e-12
    env = max(DRUM.radii(w[n][0]).max() for n in w)
    env = max(env, DRUM.radii(DRUM.joints_world(lo)).max())
    assert DRUM.envelope(DRUM.folded) == pytest.approx(env, rel=1e-9)


def test_tiles_ten_percent_longer_are_caught_with_pair_and_angle():
    """The same design with every tile 10 % longer round the axis interferes; the pair and the input are named."""
    c = dm.check(dm.lengthen(DRUM, 1.1))
    assert not c.success
    assert c.delta.minimum < -1e-3
    assert c.delta.pair.first != c.delta.pair.second and "turned" in c.delta.pair.label
    assert math.degrees(c.delta.input) % 360 == pytest.approx(31.9565, abs=0.5)
    assert "interference: Δ_min" in c.message and c.delta.pair.label in c.message
    # 10 % shorter: a gap opens in the cylinder, no interference
    short = dm.check(dm.lengthen(DRUM, 0.9))
    assert short.delta.minimum > 0 and "no gap-free cylinder" in short.message


def test_anti_retraction_torque_is_the_virtual_work_of_the_tiles():
    """The holding torque of forces.drive (inverse statics) equals minus the radial loads' virtual power per unit
    input rate, from the tile centroids' velocities (central differences of the kinematics)."""
    load = 1000.0
    tau, share = DRUM.holding_torque(load)
    h = 1e-6
    a, b = DRUM.world(DRUM.deployed - h), DRUM.world(DRUM.deployed + h)
    c = np.asarray(DRUM.centre)
    power = 0.0
    for n in DRUM.tiles:
        p = 0.5 * (a[n].mean(axis=0) + b[n].mean(axis=0))
        v = (b[n].mean(axis=0) - a[n].mean(axis=0)) / (2 * h)
        power += load * float(v @ ((c - p) / np.hypot(*(c - p))))
    assert tau == pytest.approx(-power, rel=1e-5)
    assert share < dm.HOLD_SHARE
    assert DRUM.hold_share() == pytest.approx(share, rel=1e-5)      # the optimisation's cheap route agrees


def test_optimisation_reaches_delta_min_zero():
    """§3-8 step 4: from the file's design with the slant of the end faces between the tiles 0.025 rad less (they
    interfere), the slants are optimised until Δ_min = 0; the cylinder stays exact. (From square ends, slants 0,
    it takes 68 designs: docs/drum.md.)"""
    design = dm.Design(load_mechanism(FILE), {"tile I": "AB", "tile II": "DC"}, DRUM.deployed, DRUM.folded,
                       (0.2754229909054406, 0.3723547153510717), 0.826773861651835, 0.4215448194380493, 0.02, 12,
                       0.32277237633856276, (-0.04816231175516461, 0.09), ("tile I", "tile II"), 4)
    start = dm.delta_min(design, math.radians(2.0))
    assert start < -1e-4
    opt = dm.optimise(design, ("slants",), tol=1e-6, evaluations=60, step=math.radians(3.0))
    assert opt.success, opt.message
    c = dm.check(opt.design.drum())
    assert c.success, c.message


def test_regenerated_candidates_reach_delta_min_zero_on_each_chain():
    """§3-8 step 4 on the regenerated candidates (issue 29 acceptance): the tyre-drum scene leaves candidates on
    two chains after the graph levels; on chain 1, candidate 8 from its first random seed (the seeded construction
    of :func:`~domes.design.drum.dimension_candidates`) reaches Δ_min = 0 (anti-retraction only checked after), with
    a gap-free cylinder, the folded drum inside D1, and the linkage inside the cylinder. On chain 2 the existing
    candidate is the Fig. 5-1 linkage, reached by the optimisation in the test above; the whole run (every
    candidate of both chains, benchmarks/bench_drum.py candidates, docs/drum.md) reaches it on 3 and 1."""
    from domes.io.scenes import load_scene
    from domes.typesynth.regenerate import regenerate

    found = regenerate(load_scene("tyre-drum")).candidates
    chains = {c.chain_index for c in found}
    assert chains == {1, 2} and len(found) == 41
    assert [c.chain_index for c in found if c.existing] == [2]
    (row,) = dm.dimension_candidates([c for c in found if str(c.id) == "8"], seeds=1, evaluations=120, hold=None)
    assert row.chain == 1 and row.reached and row.check is not None
    c = row.check
    assert abs(c.delta.minimum) <= dm.DELTA_TOL and c.folding_ratio > 1.0
    assert all(f.startswith("anti-retraction") for f in c.failures), c.failures   # the only check not asked
    drum = row.design.drum()
    lo, hi = drum.stroke
    assert max(drum.radii(drum.joints_world(q)).max() for q in np.linspace(lo, hi, 25)) < c.inner


def _point_segment(p, s, e):
    """Distances of points ``p`` (..., 2) from segments ``s``–``e`` (..., 2)."""
    d = e - s
    t = np.clip(np.sum((p - s) * d, axis=-1) / np.sum(d * d, axis=-1), 0.0, 1.0)
    return np.hypot(*np.moveaxis(p - s - t[..., None] * d, -1, 0))


def test_tiles_against_links_over_the_stroke():
    """Item 1's continuous interference of tiles and links: the links as bars about their centre lines. For
    the Fig. 5-1 drum the closest is tile I against the neighbouring copy's link DC just after folded; the
    least clearance of bars of half-width w equals the least distance of the tile from that centre line,
    brute force over a dense 0.05° sampling of the stroke (every tile vertex against the segment, both ends
    against every tile edge), less w (to the bar's 16-gon rounding, w(1 − cos(π/16))). Bars of half-width 0.005
    interfere: the check fails and names the pair and the input."""
    lo, hi = DRUM.stroke
    n = int(math.degrees(hi - lo) * 20)
    qs = np.linspace(lo, hi, n + 1)
    sw = sweep(DRUM.mech, lo, hi, (hi - lo) / n, outputs=["point:D", "point:C"])
    assert sw.inputs.size == n + 1
    pitch, c = 2 * math.pi / DRUM.count, np.asarray(DRUM.centre)
    turn = np.array([[math.cos(pitch), -math.sin(pitch)], [math.sin(pitch), math.cos(pitch)]])
    d, e = ((np.stack([sw.table[f"point:{j}.x"], sw.table[f"point:{j}.y"]], -1) - c) @ turn.T + c for j in "DC")
    tile = DRUM.world(qs)["tile I"]                                          # (T, k, 2)
    dist = _point_segment(tile, d[:, None], e[:, None]).min(axis=1)
    edges = np.roll(tile, -1, axis=1)
    for end in (d, e):
        dist = np.minimum(dist, _point_segment(end[:, None], tile, edges).min(axis=1))
    k = int(np.argmin(dist))
    w = 1e-4
    r = DRUM.link_clearance(w)
    assert r.pair.label == "tile I / link DC turned +30°"
    assert r.minimum == pytest.approx(dist[k] - w, abs=w * (1 - math.cos(math.pi / 16)) + 1e-7)
    assert abs(r.input - qs[k]) < math.radians(0.1) and 0 < r.input - DRUM.folded < math.radians(10)
    assert r.minimum > 0                                      # thin bars clear the tiles: Fig. 5-1 passes
    thick = dm.check(DRUM, link_width=0.005)
    assert not thick.success and thick.links.minimum < -1e-3
    assert "tiles against links (half-width 0.005)" in thick.message and "tile I / link DC turned +30°" in thick.message
    with pytest.raises(InputError, match="half-width must be a length > 0"):
        DRUM.link_clearance(0.0)


def _hull_perimeter(points) -> float:
    """Perimeter of the convex hull by Andrew's monotone chain."""
    pts = sorted(map(tuple, np.round(np.asarray(points, float), 15)))

    def half(seq):
        out = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0:
                out.pop()
            out.append(p)
        return out

    hull = half(pts)[:-1] + half(pts[::-1])[:-1]
    return sum(math.dist(hull[i], hull[(i + 1) % len(hull)]) for i in range(len(hull)))


def test_layout_optimum_is_the_least_folded_perimeter_without_interference():
    """§3-8 step 1's layout (our reading, docs/drum.md): on a small grid of tile counts and shares, each
    layout's folded perimeter equals the perimeter of the hull of all N copies' folded tiles (monotone chain,
    written here), its folded clearance is ≥ 0 exactly when no two tiles overlap (edge crossings and point in
    polygon, written here), and the optimum is the least perimeter among those."""
    from domes.cli.drum import _design_of

    design = _design_of(DRUM)
    best = dm.layout_optimum(design, counts=(10, 12, 14), shares=(0.3, 0.4))
    assert len(best.table) == 9 and best.success
    free = []
    for n, share, perimeter, gap in best.table:
        drum = design.with_(count=n, share=share).drum()
        w = drum.world(drum.folded)
        c = np.asarray(drum.centre)
        copies = []
        for k in range(n):
            t = 2 * math.pi * k / n
            rot = np.array([[math.cos(t), -math.sin(t)], [math.sin(t), math.cos(t)]])
            copies.append({name: (v - c) @ rot.T + c for name, v in w.items()})
        assert perimeter == pytest.approx(_hull_perimeter(np.concatenate([v for cp in copies for v in cp.values()])),
                                          rel=1e-12)
        polys = [v.tolist() for v in copies[0].values()] + [v.tolist() for v in copies[1].values()] \
            + [v.tolist() for v in copies[-1].values()]
        clash = any(overlap(polys[i], polys[j]) for i in range(2) for j in range(i + 1, len(polys)))
        assert (gap < 0) == clash, (n, share, gap)
        if not clash:
            free.append((perimeter, n, share))
    assert (best.perimeter, best.count, best.share) == min(free)
