"""The four-bar design space of seed 002 §6-2 (digest B.2): normalised lengths and the eight sub-regions.

Lengths are normalised by their mean, ``L = (l1 + l2 + l3 + l4)/4`` (6-1),
so that ``a + b + c + d = 4`` (6-3) with ``a`` the input (crank), ``b`` the
coupler, ``c`` the output (follower) and ``d`` the frame (6-2). A four-bar
exists when every link is shorter than the other three together,
``0 < a, b, c, d < 2`` (6-4). The planes ``a + b = c + d``,
``a + c = b + d`` and ``a + d = b + c`` cut the admissible octahedron into
the eight sub-regions of Table 6-1 (as corrected by the digest: region ② reads
``b + d > c + a``). With normalised lengths each cut compares a link with
``2 − d``, so the signs of ``a + d − 2``, ``b + d − 2``, ``c + d − 2`` name
the region; a zero sign is a boundary (change-point) mechanism.

>>> p = classify(99.58, 199.16, 149.37, 199.16)          # the fuzzy example's linkage (C-01)
>>> [round(x, 4) for x in (p.a, p.b, p.c, p.d)], p.region, p.grashof
([0.6154, 1.2308, 0.9231, 1.2308], 1, True)
>>> classify(0.5, 1.0, 1.0, 1.5).boundary                 # point P of the d = 1.5 diagram (C-02)
('a + d = b + c',)
"""

from __future__ import annotations

from dataclasses import dataclass

from domes.errors import InputError

#: Relative tolerance (of the normalised lengths, which sum to 4) under which a cut counts as met.
BOUNDARY_TOL = 1e-12

#: Table 6-1: region -> (mechanism, the three inequalities that define it).
TABLE_6_1 = {
    8: ("double crank, frame d shortest", ("b+c>a+d", "a+c>b+d", "a+b>c+d")),
    1: ("crank-rocker, input a shortest (the crank)", ("b+c>a+d", "b+d>a+c", "c+d>a+b")),
    2: ("crank-rocker, output c shortest (the output is the crank)", ("a+d>c+b", "a+b>c+d", "b+d>c+a")),
    3: ("double rocker, coupler b shortest", ("a+d>b+c", "a+c>b+d", "c+d>a+b")),
    4: ("double rocker, no crank, output c longest", ("b+c>a+d", "a+c>b+d", "d+c>a+b")),
    5: ("double rocker, no crank, coupler b longest", ("b+c>a+d", "b+a>c+d", "b+d>a+c")),
    6: ("double rocker, no crank, input a longest", ("a+b>c+d", "a+c>b+d", "a+d>c+b")),
    7: ("double rocker, no crank, frame d longest", ("d+a>c+b", "d+c>a+b", "d+b>a+c")),
}

#: The sign rule: signs of (a + d − 2, b + d − 2, c + d − 2) -> region (digest B.2, verified against Table 6-1).
_SIGNS = {(-1, 1, 1): 1, (1, 1, -1): 2, (1, -1, 1): 3, (-1, -1, 1): 4, (-1, 1, -1): 5, (1, -1, -1): 6,
          (1, 1, 1): 7, (-1, -1, -1): 8}
_CUTS = ("a + d = b + c", "b + d = a + c", "c + d = a + b")


@dataclass(frozen=True)
class DesignPoint:
    """A four-bar in the design space: normalised lengths, the scale ``L``, its sub-region and Grashof class.

    ``region`` is 1..8 (Table 6-1), or None on a boundary, where
    ``boundary`` names the cuts it lies on (a change-point mechanism) and
    ``regions`` the sub-regions it touches.
    """

    a: float
    b: float
    c: float
    d: float
    scale: float
    region: int | None
    boundary: tuple[str, ...]
    regions: tuple[int, ...]

    @property
    def grashof(self) -> bool:
        """A link turns fully (regions ①, ②, ③, ⑧); on a boundary: s + l = p + q, Grashof's limit."""
        return self.region in (1, 2, 3, 8) if self.region else True

    @property
    def mechanism(self) -> str:
        if self.region:
            return TABLE_6_1[self.region][0]
        return f"change-point mechanism on {', '.join(self.boundary)} (between regions {self.regions})"

    @property
    def message(self) -> str:
        where = f"region {self.region}" if self.region else "a boundary"
        return (f"a, b, c, d = {self.a:.6g}, {self.b:.6g}, {self.c:.6g}, {self.d:.6g} (L = {self.scale:.6g}): "
                f"{where}: {self.mechanism}")


def normalise(crank: float, coupler: float, follower: float, frame: float) -> tuple[float, float, float, float, float]:
    """``(a, b, c, d, L)`` by (6-1)–(6-3); an InputError when the lengths cannot close a loop (6-4).

    >>> normalise(1, 2, 1.5, 2)[:4]
    (0.6153846153846154, 1.2307692307692308, 0.9230769230769231, 1.2307692307692308)
    """
    lengths = (crank, coupler, follower, frame)
    names = ("crank", "coupler", "follower", "frame")
    for name, value in zip(names, lengths):
        if not (isinstance(value, (int, float)) and value > 0 and value < float("inf")):
            raise InputError(f"the {name} length must be a positive number, got {value!r}")
    scale = sum(lengths) / 4.0
    a, b, c, d = (x / scale for x in lengths)
    for name, x in zip(names, (a, b, c, d)):
        if x >= 2.0:
            raise InputError(f"the {name} ({x * scale:g}) is at least as long as the other three links together: "
                             "no four-bar closes (6-4)")
    return a, b, c, d, scale


def classify(crank: float, coupler: float, follower: float, frame: float, tol: float = BOUNDARY_TOL) -> DesignPoint:
    """The design-space point of a four-bar of these lengths (any unit): its sub-region or boundary."""
    a, b, c, d, scale = normalise(crank, coupler, follower, frame)
    values = (a + d - 2.0, b + d - 2.0, c + d - 2.0)
    zero = tuple(abs(v) <= tol * 4 for v in values)
    if not any(zero):
        signs = tuple(1 if v > 0 else -1 for v in values)
        return DesignPoint(a, b, c, d, scale, _SIGNS[signs], (), (_SIGNS[signs],))
    touching = []
    for signs, region in _SIGNS.items():
        if all(z or (s > 0) == (v > 0) for s, v, z in zip(signs, values, zero)):
            touching.append(region)
    return DesignPoint(a, b, c, d, scale, None, tuple(cut for cut, z in zip(_CUTS, zero) if z), tuple(sorted(touching)))


def table_region(a: float, b: float, c: float, d: float) -> int | None:
    """The region whose three Table 6-1 inequalities hold (None when none holds strictly: a boundary).

    The table itself, read literally: an independent check of the sign rule of :func:`classify`.
    """
    env = {"a": a, "b": b, "c": c, "d": d}
    for region, (_, conditions) in TABLE_6_1.items():
        if all(_side(lhs, env) > _side(rhs, env) for lhs, rhs in (cond.split(">") for cond in conditions)):
            return region
    return None


def _side(expr: str, env: dict) -> float:
    return sum(env[name] for name in expr.split("+"))
