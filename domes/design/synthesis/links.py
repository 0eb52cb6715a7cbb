"""Spatial rigid-body guidance by guiding links (seed 002 §2-3, digest A.3.2): S-S, R-S, R-R, R-C, C-C.

A guided body takes positions ``x ↦ C_j x + d_j`` (j = 1..n, the first the
identity). A guiding link joins it to the frame; each kind of link keeps
some quantities of the motion constant:

- **S-S** (2-57): the moving sphere centre ``a_j = C_j a1 + d_j`` keeps its
  distance from the fixed centre ``a0``. 6 unknowns, one equation per
  position after the first: **7 positions**.
- **R-S** (2-60): also the moving centre stays in the plane through ``a0``
  normal to the fixed axis ``u0``. **4 positions**, one free choice.
- **C-C** (2-84)–(2-85): the fixed line ``(a0, u0)`` and the moving line
  ``(a1, u1)`` (carried as ``C_j u1``, ``C_j a1 + d_j``) keep their twist and
  their common normal's length: two equations per position; each line has
  four freedoms: **5 positions**.
- **R-C**: a C-C whose foot of the common normal does not slide along the
  fixed axis: three equations per position: **3 positions**, two free.
- **R-R** (2-63)–(2-66): neither foot slides: four per position: **3
  positions**, none free.

(The digest's counts, :mod:`domes.design.synthesis.counts`, agree.) The
equations are solved by least squares from seeded random starts in the
positions' box; every distinct solution is returned with its residual, so
a designer sees the whole finite set (or, with free choices fixed by
``fixed``, the family's members through them).

>>> import numpy as np
>>> from domes.design.synthesis.sphere import rot
>>> moves = [(rot((0, 0, 1), t), np.array([0.0, 0.0, 0.0])) for t in (0.0, 0.4, 0.9)]
>>> len(moves), KINDS
(3, ('S-S', 'R-S', 'R-R', 'R-C', 'C-C'))
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from domes.errors import InputError
from domes.results import Progress, Ticker

KINDS = ("S-S", "R-S", "R-R", "R-C", "C-C")
#: The most positions each link meets with no more equations than unknowns, and the free choices left there.
MOST = {"S-S": (7, 0), "R-S": (4, 1), "R-R": (3, 0), "R-C": (3, 2), "C-C": (5, 0)}
#: The unknowns of each link, by name (three coordinates each).
UNKNOWNS = {"S-S": ("a0", "a1"), "R-S": ("u0", "a0", "a1"), "R-R": ("u0", "a0", "u1", "a1"),
            "R-C": ("u0", "a0", "u1", "a1"), "C-C": ("u0", "a0", "u1", "a1")}


@dataclass(frozen=True)
class Link:
    """A guiding link found: its kind, points and axes (``None`` where it has none), the largest residual."""

    kind: str
    a0: np.ndarray
    a1: np.ndarray
    u0: np.ndarray | None
    u1: np.ndarray | None
    residual: float


def _foot(a, v, b, u):
    c = float(u @ v)
    w = a - b
    return a + ((c * float(u @ w) - float(v @ w)) / (1 - c * c)) * v


def _equations(kind: str, x: np.ndarray, moves, scale: float) -> np.ndarray:
    parts = dict(zip(UNKNOWNS[kind], np.split(x, len(UNKNOWNS[kind]))))
    a0, a1 = parts["a0"], parts["a1"]
    out = []
    if kind in ("S-S", "R-S"):
        r1 = float(np.sum((a1 - a0) ** 2))
        for C, d in moves[1:]:
            aj = C @ a1 + d
            out.append((float(np.sum((aj - a0) ** 2)) - r1) / scale)
        if kind == "R-S":
            u0 = parts["u0"]
            out.append(float(u0 @ u0) - 1.0)
            for C, d in moves:
                out.append(float(u0 @ (C @ a1 + d - a0)) / scale)
        return np.array(out)
    u0, u1 = parts["u0"], parts["u1"]
    out += [float(u0 @ u0) - 1.0, float(u1 @ u1) - 1.0]     # the points may lie anywhere on their lines
    twist = float(u0 @ u1)
    n1 = np.cross(u0, u1)
    dist1 = float((a1 - a0) @ n1)
    F1 = _foot(a0, u0, a1, u1)
    M1 = _foot(a1, u1, a0, u0)
    for C, d in moves[1:]:
        uj, aj = C @ u1, C @ a1 + d
        out.append(float(u0 @ uj) - twist)
        out.append((float((aj - a0) @ np.cross(u0, uj)) - dist1) / scale)
        if kind in ("R-C", "R-R"):
            out.append(float(u0 @ (_foot(a0, u0, aj, uj) - F1)) / scale)
        if kind == "R-R":
            Mj = _foot(aj, uj, a0, u0)
            out.append(float(uj @ (Mj - (C @ M1 + d))) / scale)
    return np.array(out)


def _pin(kind: str, x: np.ndarray) -> np.ndarray:
    """Lines have a point anywhere along them: move each point to its line's foot nearest the origin."""
    if kind in ("S-S", "R-S"):
        return x
    parts = dict(zip(UNKNOWNS[kind], np.split(x.copy(), 4)))
    for u, a in (("u0", "a0"), ("u1", "a1")):
        n = parts[u] / np.linalg.norm(parts[u])
        parts[u] = n
        parts[a] = parts[a] - (parts[a] @ n) * n
    return np.concatenate([parts[k] for k in UNKNOWNS[kind]])


def guiding_links(kind: str, moves, fixed: dict | None = None, starts: int = 48, seed: int = 0,
                  tol: float = 1e-10, progress: Progress | None = None) -> list[Link]:
    """Every distinct guiding link of ``kind`` for the positions ``moves`` (``(C_j, d_j)``, the first the identity)
    that the seeded starts reach; ``fixed`` pins unknown coordinates by name (``"a0x"``, ``"u0z"``, ...).

    The number of positions must not exceed what the link meets (:data:`MOST`), and a position count that
    leaves free choices needs as many ``fixed`` coordinates."""
    if kind not in KINDS:
        raise InputError(f"guiding link: one of {', '.join(KINDS)}, got {kind!r}")
    moves = [(np.asarray(C, float), np.asarray(d, float)) for C, d in moves]
    if not moves or np.max(np.abs(moves[0][0] - np.eye(3))) > 1e-12 or np.max(np.abs(moves[0][1])) > 1e-12:
        raise InputError("the first position is the reference: the identity, no translation")
    for k, (C, _) in enumerate(moves, 1):
        if np.max(np.abs(C @ C.T - np.eye(3))) > 1e-9 or np.linalg.det(C) < 0:
            raise InputError(f"position {k}: its orientation is not a rotation")
    n = len(moves)
    most, _ = MOST[kind]
    if n > most:
        raise InputError(f"a {kind} link meets at most {most} positions; got {n}")
    names = [f"{u}{c}" for u in UNKNOWNS[kind] for c in "xyz"]
    fixed = dict(fixed or {})
    for key in fixed:
        if key not in names:
            raise InputError(f"fixed: {key!r} is not an unknown of a {kind} link ({', '.join(names)})")
    size = len(names)
    equations = _equations(kind, np.ones(size), moves, 1.0).size
    lines = 0 if kind in ("S-S", "R-S") else 2                # a point along each line is free
    free = size - lines - equations - len(fixed)
    if free > 0:
        raise InputError(f"{n} positions leave a {kind} link {free} free choice(s): fix that many coordinates "
                         f"('fixed', e.g. {{'{names[0]}': 0.0}})")
    pts = np.array([d for _, d in moves])
    scale = max(1.0, float(np.max(np.abs(pts))))
    index = {nm: k for k, nm in enumerate(names)}
    open_ = [k for k, nm in enumerate(names) if nm not in fixed]
    rng = np.random.default_rng(seed)
    found: list[Link] = []
    clock = Ticker(progress)
    for start in range(starts):
        clock.tick(lambda: f"{kind} link: start {start + 1} of {starts}, {len(found)} link(s) found")
        x0 = rng.uniform(-2 * scale, 2 * scale, size)
        for k, nm in enumerate(names):
            if nm[0] == "u":
                x0[k] = rng.normal()
        for nm, v in fixed.items():
            x0[index[nm]] = v

        def residual(y):
            x = x0.copy()
            x[open_] = y
            return _equations(kind, x, moves, scale)

        fit = least_squares(residual, x0[open_], xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=150)
        x = x0.copy()
        x[open_] = fit.x
        worst = float(np.max(np.abs(residual(fit.x)))) if fit.x.size else 0.0
        if worst > tol or not np.all(np.isfinite(x)):
            continue
        if kind not in ("S-S", "R-S") and abs(abs(float(x[0:3] @ x[6:9]) / (np.linalg.norm(x[0:3]) *
                                                                              np.linalg.norm(x[6:9]))) - 1) < 1e-6:
            continue                                           # parallel lines: the twist condition degenerates
        x = _pin(kind, x) if not fixed else x
        link = _link(kind, x, worst)
        if not any(_same(link, other, scale) for other in found):
            found.append(link)
    return found


def _link(kind, x, worst) -> Link:
    parts = dict(zip(UNKNOWNS[kind], np.split(x, len(UNKNOWNS[kind]))))
    u0 = parts.get("u0")
    u1 = parts.get("u1")
    if u0 is not None:
        u0 = u0 / np.linalg.norm(u0)
    if u1 is not None:
        u1 = u1 / np.linalg.norm(u1)
    return Link(kind, parts["a0"], parts["a1"], u0, u1, worst)


def _same(a: Link, b: Link, scale: float) -> bool:
    """Whether two solutions are one link (axes up to their sign, a line's point anywhere along it)."""
    close = 1e-6 * scale
    if a.kind in ("S-S", "R-S"):
        if a.kind == "R-S" and abs(abs(float(a.u0 @ b.u0)) - 1) > 1e-8:
            return False
        return bool(np.linalg.norm(a.a0 - b.a0) <= close and np.linalg.norm(a.a1 - b.a1) <= close)
    for p, u, q, v in ((a.a0, a.u0, b.a0, b.u0), (a.a1, a.u1, b.a1, b.u1)):
        if abs(abs(float(u @ v)) - 1) > 1e-8:
            return False
        w = p - q
        if np.linalg.norm(w - (w @ u) * u) > close:
            return False
    return True


def check(link: Link, moves) -> float:
    """The largest violation of the link's constant quantities over the positions (an independent check:
    distances, planes, twists, common normals and feet from the moved geometry)."""
    moves = [(np.asarray(C, float), np.asarray(d, float)) for C, d in moves]
    worst = 0.0
    if link.kind in ("S-S", "R-S"):
        r = [np.linalg.norm(C @ link.a1 + d - link.a0) for C, d in moves]
        worst = float(np.ptp(r))
        if link.kind == "R-S":
            worst = max(worst, max(abs(float(link.u0 @ (C @ link.a1 + d - link.a0))) for C, d in moves))
        return worst
    tw, h, f0, m1 = [], [], [], []
    F1 = _foot(link.a0, link.u0, link.a1, link.u1)
    M1 = _foot(link.a1, link.u1, link.a0, link.u0)
    for C, d in moves:
        uj, aj = C @ link.u1, C @ link.a1 + d
        tw.append(float(link.u0 @ uj))
        n = np.cross(link.u0, uj)
        h.append(float((aj - link.a0) @ n / np.linalg.norm(n)))
        f0.append(float(link.u0 @ (_foot(link.a0, link.u0, aj, uj) - F1)))
        m1.append(float(uj @ (_foot(aj, uj, link.a0, link.u0) - (C @ M1 + d))))
    worst = max(float(np.ptp(tw)), float(np.ptp(h)))
    if link.kind in ("R-C", "R-R"):
        worst = max(worst, max(abs(x) for x in f0))
    if link.kind == "R-R":
        worst = max(worst, max(abs(x) for x in m1))
    return worst


__all__ = ["KINDS", "Link", "MOST", "UNKNOWNS", "check", "guiding_links"]
