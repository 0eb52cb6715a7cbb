"""Reads a chain drawing back from its SVG and checks its geometry, independently of the layout code.

Used by the sketch tests: links are ``line``/``polygon`` elements of class
``link`` with ``data-link``, joints ``circle`` elements with ``data-joint``.
"""

from __future__ import annotations

import math
import statistics
import xml.etree.ElementTree as ET

SVG = "{http://www.w3.org/2000/svg}"


def parse(svg: str):
    """``(links, joints)``: link -> list of outline points (2 for a bar); joint "u-v" -> point."""
    root = ET.fromstring(svg)
    links: dict[int, list[tuple[float, float]]] = {}
    joints: dict[str, tuple[float, float]] = {}
    for el in root.iter():
        cls = el.get("class", "").split()
        if "link" in cls and "arm" not in cls:
            v = int(el.get("data-link"))
            if el.tag == SVG + "line":
                links[v] = [(float(el.get("x1")), float(el.get("y1"))), (float(el.get("x2")), float(el.get("y2")))]
            else:
                links[v] = [tuple(float(c) for c in p.split(",")) for p in el.get("points").split()]
        elif "joint" in cls and el.tag == SVG + "circle":
            joints[el.get("data-joint")] = (float(el.get("cx")), float(el.get("cy")))
    return links, joints


def sides(outline):
    if len(outline) == 2:
        return [tuple(outline)]
    return [(outline[i - 1], outline[i]) for i in range(len(outline))]


def link_size(outline) -> float:
    return statistics.fmean(math.dist(p, q) for p, q in sides(outline))


def _orient(a, b, c) -> float:
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def segment_contact(p1, p2, q1, q2, eps=1e-6):
    """Points where two segments meet (their intersection, or the ends of a collinear overlap); [] if apart."""
    d1, d2 = _orient(q1, q2, p1), _orient(q1, q2, p2)
    d3, d4 = _orient(p1, p2, q1), _orient(p1, p2, q2)
    scale = max(math.dist(p1, p2), math.dist(q1, q2), 1.0)
    tol = eps * scale * scale
    if abs(d1) <= tol and abs(d2) <= tol:  # collinear: overlap of the projections
        axis = (p2[0] - p1[0], p2[1] - p1[1]) if math.dist(p1, p2) > 0 else (1.0, 0.0)
        t = lambda p: p[0] * axis[0] + p[1] * axis[1]
        lo = max(min(t(p1), t(p2)), min(t(q1), t(q2)))
        hi = min(max(t(p1), t(p2)), max(t(q1), t(q2)))
        if lo > hi + tol:
            return []
        return [p for p in (p1, p2, q1, q2) if lo - tol <= t(p) <= hi + tol]
    if (d1 > tol and d2 > tol) or (d1 < -tol and d2 < -tol) or (d3 > tol and d4 > tol) or (d3 < -tol and d4 < -tol):
        return []
    s = d1 / (d1 - d2) if d1 != d2 else 0.0
    return [(p1[0] + s * (p2[0] - p1[0]), p1[1] + s * (p2[1] - p1[1]))]


def inside(point, polygon) -> bool:
    """Strictly inside a simple polygon (ray casting)."""
    x, y = point
    hit = False
    for (x1, y1), (x2, y2) in sides(polygon):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            hit = not hit
    return hit


def crossings(links, joints, tol=0.05):
    """Every place two links meet other than at their shared joint, and every plate that crosses itself."""
    problems = []
    owner = {}
    for name in joints:
        u, v = map(int, name.split("-"))
        owner.setdefault(u, set()).add(name)
        owner.setdefault(v, set()).add(name)
    order = sorted(links)
    for i, a in enumerate(order):
        for b in order[i + 1 :]:
            shared = [joints[j] for j in owner[a] & owner[b]]
            for p1, p2 in sides(links[a]):
                for q1, q2 in sides(links[b]):
                    for point in segment_contact(p1, p2, q1, q2):
                        if not any(math.dist(point, s) <= tol for s in shared):
                            problems.append((a, b, point))
            for poly, other in ((a, b), (b, a)):
                if len(links[poly]) > 2:
                    for j in owner[other] - owner[poly]:
                        if inside(joints[j], links[poly]):
                            problems.append((poly, other, joints[j]))
    for v, outline in links.items():
        edges = sides(outline)
        if len(edges) > 3:
            for i in range(len(edges)):
                for k in range(i + 2, len(edges)):
                    if i == 0 and k == len(edges) - 1:
                        continue
                    if segment_contact(*edges[i], *edges[k]):
                        problems.append((v, v, edges[i][0]))
    return problems


def closest_joints(joints) -> float:
    pts = list(joints.values())
    return min(math.dist(p, q) for i, p in enumerate(pts) for q in pts[i + 1 :])


def median_link_size(links) -> float:
    return statistics.median(link_size(o) for o in links.values())
