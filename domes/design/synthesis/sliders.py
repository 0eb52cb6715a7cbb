"""Slider dyads: body points whose precision positions lie on one straight line (digest A.3.1).

A slider is a crank whose centre point is at infinity: its circle point
(the slider pin ``a1``) has all its positions ``a_j = D1j a1`` on a line,
the slide. The condition that positions 1, 2 and ``j`` are collinear,

    (a_2 − a_1) × (a_j − a_1) = 0,

is, since ``a_j − a_1 = (R_j − I) a1 + t_j`` and ``R_j − I`` is a rotation
times a scale, ``k |a1|² + l · a1 + m = 0``: a circle (or a line). So three
positions leave a circle of slider pins, one for each slide direction
(:func:`slider_for_direction`, two linear equations); four positions cut two
such circles, which share the pole ``P12`` (its first two positions
coincide), in one more point: the slider pin of four positions
(:func:`slider_points`); five positions have one only when that point's
fifth position is on its line too (not in general).

>>> from domes.design.synthesis.guidance import Position
>>> pos = [Position((1.0, 1.0), 0.0), Position((2.0, 0.5), 0.0), Position((3.0, 1.5), math.radians(45)),
...        Position((2.0, 2.0), math.radians(90))]                              # seed 002 §2-3, Example 2
>>> [s.residual < 1e-12 for s in slider_points(pos)]
[True]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.design.synthesis.displacement import moved
from domes.design.synthesis.guidance import Position, check_positions, displacements, size
from domes.errors import InputError


@dataclass(frozen=True)
class SliderDyad:
    """A slider pin ``a1`` (position 1), the slide's ``direction`` (rad) and the largest distance of the pin's
    positions from the slide (its residual)."""

    a1: tuple[float, float]
    direction: float
    residual: float


def _collinear(Ds, j, a) -> float:
    p1, p2, pj = moved(Ds[0], a), moved(Ds[1], a), moved(Ds[j], a)
    u, v = p2 - p1, pj - p1
    return float(u[0] * v[1] - u[1] * v[0])


def _circle(Ds, j, s):
    """``(k, lx, ly, m)`` of ``(a_2 − a_1) × (a_j − a_1) = k |a|² + lx x + ly y + m`` (exact: four samples)."""
    pts = s * np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [-1.0, -2.0]])     # not on one circle
    M = np.c_[(pts ** 2).sum(axis=1), pts, np.ones(4)]
    return np.linalg.solve(M, [_collinear(Ds, j, p) for p in pts])


def slider(positions: list[Position], a1) -> SliderDyad:
    """The slider through pin ``a1``: the line through its first position along its farthest one."""
    Ds = displacements(positions)
    pts = np.array([moved(D, a1) for D in Ds])
    far = pts[np.argmax(np.linalg.norm(pts - pts[0], axis=1))] - pts[0]
    if np.linalg.norm(far) <= 1e-12 * size(positions):
        raise InputError(f"the point {tuple(a1)} does not move: it is the pole of every displacement")
    u = far / np.linalg.norm(far)
    off = np.abs((pts - pts[0]) @ np.array([-u[1], u[0]]))
    return SliderDyad((float(a1[0]), float(a1[1])), math.atan2(u[1], u[0]), float(off.max()))


def slider_for_direction(positions: list[Position], angle: float) -> SliderDyad:
    """The slider of three positions whose slide has direction ``angle`` (rad)."""
    check_positions(positions)
    if len(positions) != 3:
        raise InputError(f"a slider is chosen by its direction for three positions, got {len(positions)}")
    Ds = displacements(positions)
    n = np.array([-math.sin(angle), math.cos(angle)])
    # n · (a_j − a_1) = 0 for j = 2, 3: linear in a1
    A = np.array([n @ (Ds[j][:2, :2] - np.eye(2)) for j in (1, 2)])
    b = -np.array([n @ Ds[j][:2, 2] for j in (1, 2)])
    if abs(np.linalg.det(A)) <= 1e-12 * max(np.abs(A).max() ** 2, 1e-300):
        raise InputError(f"no slider along {math.degrees(angle):.6g}°: the positions' rotations leave that "
                         "direction free or impossible")
    return slider(positions, np.linalg.solve(A, b))


def slider_points(positions: list[Position]) -> list[SliderDyad]:
    """The sliders of four positions (the one pin, besides the pole P12, whose four positions are collinear), or
    of five (that pin when its fifth position is collinear too, to 1e-9 of the positions' size)."""
    check_positions(positions)
    if len(positions) not in (4, 5):
        raise InputError(f"slider points are of four or five positions, got {len(positions)}")
    Ds = displacements(positions)
    s = size(positions)
    c3, c4 = _circle(Ds, 2, s), _circle(Ds, 3, s)
    line = c4[0] * c3 - c3[0] * c4                   # k cancels: a line (or c3 itself when k3 = 0)
    if abs(c3[0]) <= 1e-12 * np.abs(c3).max() and abs(c4[0]) <= 1e-12 * np.abs(c4).max():
        line, circle = c3, c4
    else:
        circle = c3 if abs(c3[0]) >= abs(c4[0]) else c4
    lx, ly, lm = line[1], line[2], line[3]
    norm = math.hypot(lx, ly)
    if norm <= 1e-12 * max(np.abs(line).max(), 1e-300):
        raise InputError("the positions' collinearity circles coincide: every point of a circle is a slider pin "
                         "(degenerate positions)")
    foot = -lm / norm ** 2 * np.array([lx, ly])
    d = np.array([-ly, lx]) / norm
    k, cx, cy, cm = circle
    # k |foot + t d|² + (cx, cy) · (foot + t d) + cm = 0, a quadratic in t
    coef = [k, 2 * k * foot @ d + np.array([cx, cy]) @ d, k * foot @ foot + np.array([cx, cy]) @ foot + cm]
    ts = np.roots(coef) if abs(coef[0]) > 1e-14 * max(abs(coef[1]), abs(coef[2]), 1e-300) else \
        ([-coef[2] / coef[1]] if coef[1] else [])
    out = []
    for t in ts:
        if abs(np.imag(t)) > 1e-9 * max(1.0, abs(t)):
            continue
        a = foot + np.real(t) * d
        images = [moved(D, a) for D in Ds]
        if min(math.dist(p, q) for i, p in enumerate(images) for q in images[:i]) <= 1e-7 * s:
            continue                                  # a pole: two positions of the pin coincide
        dyad = slider(positions, a)
        if dyad.residual <= 1e-9 * s:
            out.append(dyad)
    return out
