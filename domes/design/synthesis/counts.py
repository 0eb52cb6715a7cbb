"""Equations and unknowns of the synthesis problems (digest A.3.2-A.3.6, Tables 2-1 to 2-3): how many
positions a guiding link or a mechanism can meet, and how many free choices remain.

Each problem is the list of its unknowns and of its constraint families,
each family counted per position (``j = 1..n`` or ``j = 2..n``) or once;
the counts are the sums, never typed in. ``free(n)`` is the number of
choices the designer must fix for an exact solution at ``n`` positions
(negative: more positions than the problem can meet; least squares).

>>> PROBLEMS["planar path"].counts(5)          # Table 2-1, Example 5: a0 and b0 given
(8, 12, 4)
>>> PROBLEMS["R-R"].most()                     # at most three positions, no free choice
(3, 0)
"""

from __future__ import annotations

from dataclasses import dataclass

#: How often a family occurs at ``n`` positions: ``"once"``, ``"each"`` (j = 1..n) or ``"after"`` (j = 2..n).
TIMES = {"once": lambda n: 1, "each": lambda n: n, "after": lambda n: n - 1}


@dataclass(frozen=True)
class Problem:
    """A synthesis problem: ``unknowns`` and ``equations`` as ``(name, size, times)`` families."""

    name: str
    task: str
    unknowns: tuple[tuple[str, int, str], ...]
    equations: tuple[tuple[str, int, str], ...]

    def counts(self, n: int) -> tuple[int, int, int]:
        """``(equations, unknowns, free choices)`` at ``n`` positions."""
        eqs = sum(size * TIMES[t](n) for _, size, t in self.equations)
        unknowns = sum(size * TIMES[t](n) for _, size, t in self.unknowns)
        return eqs, unknowns, unknowns - eqs

    def most(self, limit: int = 50) -> tuple[int, int]:
        """The most positions with no fewer unknowns than equations, and the free choices left there."""
        best = max(n for n in range(2, limit) if self.counts(n)[2] >= 0)
        return best, self.counts(best)[2]


def _p(name, task, unknowns, equations) -> Problem:
    return Problem(name, task, tuple(unknowns), tuple(equations))


PROBLEMS = {p.name: p for p in (
    _p("planar crank", "guidance", [("a0", 2, "once"), ("a1", 2, "once")],
       [("constant length (2-56)", 1, "after")]),
    _p("S-S", "guidance", [("a0", 3, "once"), ("a1", 3, "once")], [("constant length (2-57)", 1, "after")]),
    _p("R-S", "guidance", [("u0", 3, "once"), ("a0", 3, "once"), ("a1", 3, "once")],
       [("constant length (2-60)", 1, "after"), ("plane normal to u0", 1, "each"), ("unit u0", 1, "once")]),
    _p("R-R", "guidance", [("u0", 3, "once"), ("u1", 3, "once"), ("a0", 3, "once"), ("a1", 3, "once")],
       [("planes (2-63)", 2, "each"), ("unit vectors (2-64)", 2, "once"), ("twist (2-65)", 1, "after"),
        ("moment (2-66)", 1, "after")]),
    _p("R-C", "guidance", [("u0", 3, "once"), ("u1", 3, "once"), ("a0", 3, "once"), ("a1", 3, "once"),
                           ("slide s_j", 1, "after")],
       [("planes (2-63)", 2, "each"), ("unit vectors (2-64)", 2, "once"), ("twist (2-65)", 1, "after"),
        ("moment (2-66)", 1, "after")]),
    _p("C-C", "guidance", [("u0", 3, "once"), ("u1", 3, "once"), ("a0", 3, "once"), ("a1", 3, "once"),
                           ("fixed slide s'_j", 1, "after"), ("moving slide s_j", 1, "after")],
       [("planes (2-63)", 2, "each"), ("unit vectors (2-64)", 2, "once"), ("twist (2-65)", 1, "after"),
        ("moment (2-66)", 1, "after")]),
    _p("planar path", "path", [("a0, a1, b0, b1", 8, "once"), ("coupler rotation θ1j", 1, "after")],
       [("constant lengths (2-113)", 2, "after")]),
    _p("spherical path", "path", [("a0, a1, b0, b1", 12, "once"), ("spin β1j", 1, "after")],
       [("constant lengths", 2, "after"), ("pivots on the unit sphere", 4, "once")]),
    _p("RRSS path", "path", [("u0, a0, u1, a1, b0, b1", 18, "once"), ("body angles", 3, "after")],
       [("R-R (2-63)-(2-66)", 4, "each"), ("S-S length", 1, "after")]),
    _p("planar path, input angles prescribed", "path", [("a0, a1, b0, b1", 8, "once"),
                                                        ("coupler rotation θ1j", 1, "after")],
       [("crank pin a_j both ways", 2, "after"), ("constant length b", 1, "after")]),
)}
