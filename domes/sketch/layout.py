"""Where the joints of a chain go: the skeleton layout (DOMES module 8, §7-2; §5-3 drawing).

A mechanism skeleton places *joints* (the chain graph's edges) at points;
a binary link is the bar between its two joints and a link of three or
more joints is the plate (polygon) through them. For a planar chain the
layout is a planar straight-line drawing of the chain's *medial graph*:

1. take a planar embedding of the chain graph (links as vertices) and its
   faces (the loops of the drawing);
2. build the medial graph ``H``: one vertex per joint; a plate's joints are
   joined in their cyclic order around the link, a bar's two joints by the
   bar. The faces of ``H`` are the plates and the loops;
3. put the joints of one loop on a circle, add a centre vertex inside every
   other face of ``H`` joined to the face's joints (so the disc is
   triangulated), and place every other vertex at the weighted average of
   its neighbours (Tutte's barycentric embedding; by Tutte's and Floater's
   theorem it is a planar straight-line drawing for any positive weights and
   a strictly convex outer polygon);
4. reweight a few times, weight ∝ current length, to even out the link
   sizes (still planar by the same theorem); try every loop as the outer
   one and keep the best drawing (:func:`layout_quality`);
5. refine: move joints towards even side lengths and apart from close
   joints, taking back any move that would turn a triangle of step 3 over.

Plates and bars are then faces and edges of one planar drawing: no two links
cross or overlap except at their shared joints. A joint in no loop (a
bridge) is first given a loop by a helper link, dropped after the layout
(:func:`_bridged_layout`). A non-planar chain is drawn
from a planar part: the fewest branches (paths of binary links between
multi-joint links, or direct joints) are taken out, the rest is laid out as
above, and the branches are drawn back as straight bars between pins placed
inside their end plates; those branches cross other links.

>>> from domes.model import Chain
>>> layout = skeleton_layout(Chain.from_graph6("Cr"))     # the four-bar
>>> layout.planar, len(layout.positions), layout.link_rings
(True, 4, ((0, 1), (0, 2), (1, 3), (2, 3)))
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from itertools import combinations, product
from typing import Mapping, Sequence

import networkx as nx
import numpy as np

from domes.errors import InputError

Edge = tuple[int, int]
Point = tuple[float, float]

#: Reweighting rounds that even out link sizes (0 gives the plain Tutte drawing).
EQUALIZE_ROUNDS = 8
#: Weight of a face-centre spoke relative to a link side (lower lets faces open up).
SPOKE_WEIGHT = 0.25
#: Rounds of planarity-keeping refinement of the chosen drawing (0: none).
REFINE_ROUNDS = 100
#: Joints closer than this fraction of the median side are pushed apart while refining.
REPEL = 0.6
#: Helper rungs tried for a chain with bridges before taking the last one.
RUNG_TRIES = 16


@dataclass(frozen=True)
class SkeletonLayout:
    """Joint positions of a chain drawing and how each link is drawn through them.

    ``joints[k]`` is the link pair of joint ``k`` (sorted, as in the chain),
    ``positions[k]`` its point. ``link_rings[v]`` lists the joints of link
    ``v`` in the order its plate outline visits them (two for a bar); joints
    of ``v`` not on the ring (pins inside a plate, only in non-planar
    drawings) are in ``link_pins[v]``. ``link_centres[v]`` is a point inside
    link ``v`` (for labels and the abstract-graph view). ``planar`` is true
    when the layout comes from a planar embedding (no link crosses another);
    ``crossing_links`` names the links drawn across the others of a
    non-planar chain.
    """

    n: int
    joints: tuple[Edge, ...]
    positions: tuple[Point, ...]
    link_rings: tuple[tuple[int, ...], ...]
    link_pins: tuple[tuple[int, ...], ...]
    link_centres: tuple[Point, ...]
    planar: bool
    crossing_links: tuple[int, ...] = ()

    def link_lengths(self) -> tuple[float, ...]:
        """Size of each link: a bar's length, a plate's mean side."""
        sizes = []
        for ring in self.link_rings:
            pts = [self.positions[k] for k in ring]
            if len(pts) == 2:
                sizes.append(math.dist(*pts))
            else:
                sides = [math.dist(pts[i], pts[i - 1]) for i in range(len(pts))]
                sizes.append(sum(sides) / len(sides))
        return tuple(sizes)


def _checked_edges(n: int, edges: Sequence[Edge]) -> tuple[Edge, ...]:
    joints = tuple(sorted((min(u, v), max(u, v)) for u, v in edges))
    graph = nx.Graph(joints)
    graph.add_nodes_from(range(n))
    if n < 2 or not nx.is_connected(graph):
        raise InputError(f"cannot draw a chain of {n} links that is not connected")
    low = [v for v in range(n) if graph.degree(v) < 2]
    if low:
        raise InputError(f"cannot draw link(s) {low}: every link of a chain needs at least two joints")
    return joints


def skeleton_layout(chain, *, equalize: int = EQUALIZE_ROUNDS, refine: int = REFINE_ROUNDS) -> SkeletonLayout:
    """The joint layout of a chain (a ``Chain``, ``LabelledChain`` or anything with ``n`` and ``edges``).

    Deterministic: the same chain (same link numbering) gives the same layout.

    >>> from domes.typesynth import chains
    >>> watt = chains(links=6, dof=1)[0]
    >>> layout = skeleton_layout(watt)
    >>> sorted(len(ring) for ring in layout.link_rings)
    [2, 2, 2, 2, 3, 3]
    """
    n = int(chain.n)
    return _layout(n, _checked_edges(n, chain.edges), equalize, refine)


def _layout(n: int, joints: tuple[Edge, ...], equalize: int, refine: int, outside: tuple[Edge, ...] = ()) -> SkeletonLayout:
    """Dispatch on bridges and planarity; ``outside``: joints to put on the outer loop."""
    graph = nx.Graph(joints)
    bridges = sorted((min(e), max(e)) for e in nx.bridges(graph))
    if bridges:
        return _bridged_layout(n, joints, bridges, equalize, refine)
    planar, embedding = nx.check_planarity(graph)
    if planar:
        return _planar_layout(n, joints, embedding, equalize, refine, outside)
    return _nonplanar_layout(n, joints, graph, equalize, refine)


# -- planar chains ---------------------------------------------------------------


def _faces(embedding: nx.PlanarEmbedding) -> list[list[Edge]]:
    """Faces as lists of half-edges, in a deterministic order."""
    seen: set[Edge] = set()
    faces = []
    for v in sorted(embedding.nodes):
        for w in embedding.neighbors_cw_order(v):
            if (v, w) in seen:
                continue
            face, half = [], (v, w)
            while half not in seen:
                seen.add(half)
                face.append(half)
                half = embedding.next_face_half_edge(*half)
            faces.append(face)
    return faces


def _planar_layout(
    n: int, joints: tuple[Edge, ...], embedding: nx.PlanarEmbedding, equalize: int, refine: int, outside: tuple[Edge, ...] = ()
) -> SkeletonLayout:
    index = {e: k for k, e in enumerate(joints)}

    def joint(u: int, v: int) -> int:
        return index[(min(u, v), max(u, v))]

    rings = []
    for v in range(n):
        around = list(embedding.neighbors_cw_order(v))
        start = around.index(min(around))
        rings.append(tuple(joint(v, w) for w in around[start:] + around[:start]))
    loops = [[joint(u, w) for u, w in face] for face in _faces(embedding)]
    plates = [ring for ring in rings if len(ring) >= 3]
    sides = sorted({(min(a, b), max(a, b)) for ring in rings for a, b in zip(ring, ring[1:] + ring[:1]) if a != b})
    wanted = [index[e] for e in outside]
    fit = [(sum(k in loop for k in wanted), len(loop) if wanted else 0) for loop in loops]
    best = None
    for outer in range(len(loops)):
        if fit[outer] < max(fit):
            continue  # joints asked to be outside go on the longest loop through them
        inner = plates + [f for i, f in enumerate(loops) if i != outer]
        xy = _tutte(len(joints), sides, loops[outer], inner, equalize)
        layout = _assemble(n, joints, rings, xy)
        closest, spread = layout_quality(layout)
        if best is None or closest / spread > best[0]:
            best = (closest / spread, layout, xy, loops[outer], inner)
    _, layout, xy, outer_loop, inner = best
    if refine:
        layout = _assemble(n, joints, rings, _refine(xy, len(joints), sides, outer_loop, inner, refine))
    return layout


def _assemble(n: int, joints: tuple[Edge, ...], rings: list[tuple[int, ...]], xy: np.ndarray) -> SkeletonLayout:
    """The layout from the positions of the joints and then of the face centres (plates first)."""
    points = [(float(x), float(y)) for x, y in xy]
    positions = points[: len(joints)]
    plate_centres = iter(points[len(joints) :])
    link_centres = [next(plate_centres) if len(ring) >= 3 else _midpoint(positions[ring[0]], positions[ring[1]]) for ring in rings]
    return SkeletonLayout(n, joints, tuple(positions), tuple(rings), tuple(() for _ in range(n)), tuple(link_centres), True)


def _refine(xy: np.ndarray, count: int, sides: list[Edge], outer: list[int], faces: list, rounds: int) -> np.ndarray:
    """Even out link sides and spread close joints, never turning a triangle of the disc over.

    Each round moves every free vertex towards where its sides would have
    the median length and away from joints closer than :data:`REPEL` of it
    (face centres towards their face's centroid). A move that would flip or
    flatten one of the triangles (face centre, joint, next joint) is taken
    back, so the drawing stays a planar straight-line drawing.
    """
    tri = np.array([(count + f, face[i - 1], face[i]) for f, face in enumerate(faces) for i in range(len(face))])
    side = np.array(sides)
    free = np.ones(len(xy), dtype=bool)
    free[outer] = False

    def areas(p: np.ndarray) -> np.ndarray:
        a, b, c = p[tri[:, 0]], p[tri[:, 1]], p[tri[:, 2]]
        return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])

    sign = np.sign(areas(xy))
    joint_pairs = np.array(list(combinations(range(count), 2)))
    centroid = np.zeros((len(faces), len(xy)))
    for f, face in enumerate(faces):
        centroid[f, list(face)] = 1.0 / len(face)
    centres = np.arange(count, count + len(faces))
    for _ in range(rounds):
        d = xy[side[:, 0]] - xy[side[:, 1]]
        length = np.hypot(d[:, 0], d[:, 1])
        target = float(np.median(length))
        move = np.zeros_like(xy)
        weight = np.zeros(len(xy))
        pull = (0.5 * (target - length) / length)[:, None] * d
        np.add.at(move, side[:, 0], pull)
        np.add.at(move, side[:, 1], -pull)
        np.add.at(weight, side.ravel(), 1.0)
        d = xy[joint_pairs[:, 0]] - xy[joint_pairs[:, 1]]
        gap = np.hypot(d[:, 0], d[:, 1])
        near = gap < REPEL * target
        push = (0.5 * (REPEL * target - gap[near]) / np.maximum(gap[near], 1e-12))[:, None] * d[near]
        np.add.at(move, joint_pairs[near, 0], push)
        np.add.at(move, joint_pairs[near, 1], -push)
        move /= np.maximum(weight, 1.0)[:, None]
        move[centres] = centroid @ xy - xy[centres]
        move[~free] = 0.0
        new = xy + move
        floor = 1e-3 * target * target
        for _ in range(len(xy)):
            bad = sign * areas(new) < floor
            if not bad.any():
                break
            back = np.unique(tri[bad].ravel())
            new[back] = xy[back]
        xy = new
    return xy


def layout_quality(layout: SkeletonLayout) -> tuple[float, float]:
    """``(closest joints / median link size, largest / smallest link size)`` of a layout.

    The first should be large, the second near 1. For every loop of a planar
    chain tried as the outer one, the layout with the best ratio of the two
    is kept.
    """
    sizes = sorted(layout.link_lengths())
    median = float(np.median(sizes))
    pts = np.array(layout.positions)
    gaps = np.hypot(*(pts[:, None, :] - pts[None, :, :]).transpose(2, 0, 1))
    closest = float(gaps[np.triu_indices(len(pts), 1)].min()) if len(pts) > 1 else median
    return closest / median, sizes[-1] / max(sizes[0], 1e-12)


def _tutte(count: int, sides: list[Edge], outer: list[int], faces: list, equalize: int) -> np.ndarray:
    """Barycentric embedding of the joints, then one centre per face: their positions, in that order."""
    total = count + len(faces)
    pairs = list(sides) + [(count + f, k) for f, face in enumerate(faces) for k in face]
    ends = np.array(pairs)
    base = np.array([1.0] * len(sides) + [SPOKE_WEIGHT] * (len(pairs) - len(sides)))
    fixed = np.zeros((total, 2))
    angles = math.pi / 2 + 2 * math.pi * np.arange(len(outer)) / len(outer)
    fixed[outer] = np.column_stack((np.cos(angles), np.sin(angles)))
    free = np.ones(total, dtype=bool)
    free[outer] = False
    weights = base
    xy = fixed
    for round_ in range(equalize + 1):
        laplacian = np.zeros((total, total))
        np.add.at(laplacian, (ends[:, 0], ends[:, 1]), -weights)
        np.add.at(laplacian, (ends[:, 1], ends[:, 0]), -weights)
        np.add.at(laplacian, (ends[:, 0], ends[:, 0]), weights)
        np.add.at(laplacian, (ends[:, 1], ends[:, 1]), weights)
        xy = fixed.copy()
        if free.any():
            rhs = -laplacian[np.ix_(free, ~free)] @ fixed[~free]
            xy[free] = np.linalg.solve(laplacian[np.ix_(free, free)], rhs)
        if round_ < equalize:
            lengths = np.hypot(*(xy[ends[:, 0]] - xy[ends[:, 1]]).T)
            weights = base * np.clip(lengths / np.median(lengths[: len(sides)]), 0.2, 5.0)
    return xy


def _midpoint(p: Point, q: Point) -> Point:
    return ((p[0] + q[0]) / 2, (p[1] + q[1]) / 2)


# -- non-planar chains -----------------------------------------------------------


def _branches(graph: nx.Graph) -> list[tuple[int, ...]]:
    """Paths ``end, binary..., end`` between links of 3+ joints (the contracted graph's edges)."""
    multi = sorted(v for v in graph if graph.degree(v) >= 3)
    found, seen = [], set()
    for start in multi:
        for first in sorted(graph[start]):
            path = [start, first]
            while graph.degree(path[-1]) == 2:
                path.append(next(w for w in sorted(graph[path[-1]]) if w != path[-2]))
            key = (min(path[0], path[-1]), max(path[0], path[-1]), tuple(sorted(path[1:-1])))
            if key not in seen:
                seen.add(key)
                found.append(tuple(path))
    return found


def _nonplanar_layout(n: int, joints: tuple[Edge, ...], graph: nx.Graph, equalize: int, refine: int) -> SkeletonLayout:
    branches = _branches(graph)
    for size in range(1, len(branches) + 1):
        for chosen in combinations(branches, size):
            rest = graph.copy()
            for path in chosen:
                rest.remove_edges_from(zip(path, path[1:]))
                rest.remove_nodes_from(path[1:-1])
            if (
                nx.is_connected(rest)
                and min(d for _, d in rest.degree) >= 2
                and not nx.has_bridges(rest)
                and nx.check_planarity(rest)[0]
            ):
                return _with_branches(n, joints, rest, chosen, equalize, refine)
    raise InputError(f"no planar part found to draw the chain with joints {list(joints)}")


def _with_branches(
    n: int, joints: tuple[Edge, ...], rest: nx.Graph, chosen: Sequence[tuple[int, ...]], equalize: int, refine: int
) -> SkeletonLayout:
    """Lay out the planar part, then draw the chosen branches across it as straight bars."""
    kept = sorted(rest.nodes)
    renumber = {v: i for i, v in enumerate(kept)}
    part_joints = tuple(sorted((min(renumber[u], renumber[v]), max(renumber[u], renumber[v])) for u, v in rest.edges))
    part = _planar_layout(len(kept), part_joints, nx.check_planarity(nx.Graph(part_joints))[1], equalize, refine)
    index = {e: k for k, e in enumerate(joints)}
    positions: dict[int, Point] = {}
    rings: dict[int, tuple[int, ...]] = {}
    centres: dict[int, Point] = {}
    for old in kept:
        new = renumber[old]
        rings[old] = tuple(index[tuple(sorted((kept[a], kept[b])))] for a, b in (part.joints[k] for k in part.link_rings[new]))
        centres[old] = part.link_centres[new]
        for k in part.link_rings[new]:
            a, b = part.joints[k]
            positions[index[tuple(sorted((kept[a], kept[b])))]] = part.positions[k]
    pins: dict[int, list[int]] = {v: [] for v in range(n)}
    ring_owner = {}
    for path in chosen:
        start, end = centres[path[0]], centres[path[-1]]
        steps = len(path) - 1
        for i, (u, v) in enumerate(zip(path, path[1:])):
            t = i / (steps - 1) if steps > 1 else 0.5
            k = index[(min(u, v), max(u, v))]
            positions[k] = (start[0] + t * (end[0] - start[0]), start[1] + t * (end[1] - start[1]))
            for link in (u, v):
                if link in rings:
                    pins[link].append(k)
                else:
                    ring_owner.setdefault(link, []).append(k)
    for link, ks in ring_owner.items():
        rings[link] = tuple(ks)
        centres[link] = _midpoint(positions[ks[0]], positions[ks[1]])
    crossing = sorted({v for path in chosen for v in (path if len(path) == 2 else path[1:-1])})
    return SkeletonLayout(
        n,
        joints,
        tuple(positions[k] for k in range(len(joints))),
        tuple(rings[v] for v in range(n)),
        tuple(tuple(pins[v]) for v in range(n)),
        tuple(centres[v] for v in range(n)),
        False,
        tuple(crossing),
    )


# -- chains with a joint in no loop --------------------------------------------------


def _bridged_layout(n: int, joints: tuple[Edge, ...], bridges: list[Edge], equalize: int, refine: int) -> SkeletonLayout:
    """Draw a chain with bridges: add a helper rung beside each, lay out, then drop the helpers.

    A bridge ``u-v`` (a joint in no loop, found only in fractionated chains
    of DOF 3 or more) has the same face on both sides. A helper link ``w``
    jointed to a neighbour ``a`` of ``u`` and a neighbour ``b`` of ``v``
    (on their own sides of the bridge) closes a loop ``u-v…b-w-a…u``, so the
    two sides are drawn next to each other, joined by the bridge and the
    rung; the bridge stays on the outer loop. Removing ``w`` takes a corner
    off the links ``a`` and ``b``: binary ones are preferred (the triangle
    becomes a bar along one of its sides), and a choice is kept only if each
    removed corner is an ear of its plate, so what is left stays inside it.
    """
    graph = nx.Graph(joints)
    sides = nx.Graph(e for e in joints if e not in set(bridges))
    sides.add_nodes_from(range(n))

    def rung_ends(u: int) -> list[int]:
        """Neighbours of ``u`` off the bridges, binary ones first, then ``u`` itself."""
        return sorted(sides[u], key=lambda a: (graph.degree(a) != 2, a)) + [u]

    choices = list(product(*(product(rung_ends(u), rung_ends(v)) for u, v in bridges)))
    for choice in choices[:RUNG_TRIES]:
        extra = []
        for i, (a, b) in enumerate(choice):
            extra += [(min(a, n + i), max(a, n + i)), (min(b, n + i), max(b, n + i))]
        wide = _layout(n + len(bridges), tuple(sorted(joints + tuple(extra))), equalize, refine, tuple(bridges))
        if all(_ear(wide, wide.joints.index(e), e[0] if e[1] >= n else e[1]) for e in extra):
            break
    index = {e: k for k, e in enumerate(wide.joints)}
    keep = [index[e] for e in joints]
    renumber = {old: new for new, old in enumerate(keep)}

    def mapped(ks: tuple[int, ...]) -> tuple[int, ...]:
        return tuple(renumber[k] for k in ks if k in renumber)

    rings = [mapped(wide.link_rings[v]) for v in range(n)]
    positions = tuple(wide.positions[k] for k in keep)
    centres = [wide.link_centres[v] if len(rings[v]) >= 3 else _midpoint(positions[rings[v][0]], positions[rings[v][1]]) for v in range(n)]
    return SkeletonLayout(
        n,
        joints,
        positions,
        tuple(rings),
        tuple(mapped(wide.link_pins[v]) for v in range(n)),
        tuple(centres),
        wide.planar,
        tuple(v for v in wide.crossing_links if v < n),
    )


def _ear(layout: SkeletonLayout, k: int, v: int) -> bool:
    """Whether joint ``k`` is an ear of link ``v``'s outline: a convex corner with no other corner in its triangle.

    Cutting an ear off leaves the rest of the plate inside the old plate, so
    it cannot reach any other link (a bar's end and a triangle's corner
    always qualify).
    """
    ring = layout.link_rings[v]
    if len(ring) <= 3:
        return True
    pts = [layout.positions[j] for j in ring]
    i = ring.index(k)
    a, b, c = pts[i - 1], pts[i], pts[(i + 1) % len(pts)]

    def cross(p: Point, q: Point, r: Point) -> float:
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    area = sum(p[0] * q[1] - q[0] * p[1] for p, q in zip(pts, pts[1:] + pts[:1]))
    if cross(a, b, c) * area <= 0:
        return False
    others = [p for j, p in enumerate(pts) if j not in (i - 1 if i else len(pts) - 1, i, (i + 1) % len(pts))]
    return not any(cross(a, b, p) * area > 0 and cross(b, c, p) * area > 0 and cross(c, a, p) * area > 0 for p in others)


# -- layouts from given joint positions (kinematics, hand-made drawings) ----------


def layout_from_positions(chain, positions: Mapping[Edge, Point]) -> SkeletonLayout:
    """A layout with the joints at given points (for example a kinematic solution).

    Each plate's outline visits its joints in angular order about their
    centroid. Nothing is checked about crossings (``planar`` is false): the
    positions decide.

    >>> from domes.model import Chain
    >>> square = {(0, 1): (0, 0), (1, 2): (1, 0), (2, 3): (1, 1), (0, 3): (0, 1)}
    >>> layout_from_positions(Chain(4, ((0, 1), (1, 2), (2, 3), (0, 3))), square).link_lengths()
    (1.0, 1.0, 1.0, 1.0)
    """
    n = int(chain.n)
    joints = _checked_edges(n, chain.edges)
    given = {(min(u, v), max(u, v)): (float(p[0]), float(p[1])) for (u, v), p in positions.items()}
    missing = [e for e in joints if e not in given]
    if missing:
        raise InputError(f"no position given for joint(s) {missing}")
    extra = sorted(set(given) - set(joints))
    if extra:
        raise InputError(f"position(s) given for {extra}, which are not joints of the chain")
    points = tuple(given[e] for e in joints)
    rings, centres = [], []
    for v in range(n):
        mine = [k for k, e in enumerate(joints) if v in e]
        cx = sum(points[k][0] for k in mine) / len(mine)
        cy = sum(points[k][1] for k in mine) / len(mine)
        mine.sort(key=lambda k: (math.atan2(points[k][1] - cy, points[k][0] - cx), k))
        rings.append(tuple(mine))
        centres.append((cx, cy))
    return SkeletonLayout(n, joints, points, tuple(rings), tuple(() for _ in range(n)), tuple(centres), False)
