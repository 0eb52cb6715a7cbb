"""The case-based reasoner: is a problem the same as, similar to, or different from a solved one?

DOMES (seed 002 §7-2, digest part 4.3): "if two problems have the same (or
different) structural and representative attributes, they are the same (or
different); if they have the same structural attributes but all-different
representative attributes, they are similar". The mixed case (same
structure, representative attributes partly shared) is not defined in the
book; we call it *similar* too, since the structure, which decides the
chains, is shared and only the screening criteria can differ. A problem of
another class, or with other structural attributes, is *different*.

Structural attributes compared: DOF, outputs, λ, independent loops, gear
pairs and sliders (links and joints follow from them). An attribute the
designer has not stated does not count as a difference. The requirements
(stroke, forces, size, accuracy: not in Table 7-1) count as representative
attributes: a problem with other requirements is similar, not the same.

>>> from domes.knowledge.problems import ProblemFrame
>>> old = ProblemFrame("moto", "suspension", dof=1, loops=2, slider_pairs=1, names=frozenset({"swing arm"}))
>>> relation(ProblemFrame("new", "suspension", dof=1, loops=2, slider_pairs=1, names=frozenset({"swing arm"})), old)
'same'
>>> relation(ProblemFrame("new", "suspension", dof=1, loops=2, slider_pairs=1, names=frozenset({"rocker"})), old)
'similar'
>>> relation(ProblemFrame("new", "suspension", dof=1, loops=3), old)
'different'
"""

from __future__ import annotations

from dataclasses import dataclass

from domes.knowledge.problems import ProblemFrame

#: The structural attributes that decide "same structure".
COMPARED = ("dof", "outputs", "space", "loops", "gear_pairs", "slider_pairs")
RELATIONS = ("same", "similar", "different")


def same_structure(a: ProblemFrame, b: ProblemFrame) -> bool:
    """Equal structural attributes, where both are stated."""
    return all(getattr(a, k) is None or getattr(b, k) is None or getattr(a, k) == getattr(b, k) for k in COMPARED)


def same_requirements(a: ProblemFrame, b: ProblemFrame) -> bool:
    """The same requirements, value for value (none on both sides is the same)."""
    return {r.id: r.value for r in a.requirements} == {r.id: r.value for r in b.requirements}


def relation(problem: ProblemFrame, solved: ProblemFrame) -> str:
    """``same``, ``similar`` or ``different`` (see the module doc)."""
    if problem.problem_class != solved.problem_class or not same_structure(problem, solved):
        return "different"
    return "same" if problem.names == solved.names and same_requirements(problem, solved) else "similar"


@dataclass(frozen=True)
class Match:
    """A solved problem and how it relates to the current one."""

    frame: ProblemFrame
    relation: str
    shared: frozenset[str]  # representative attributes in common


def recognise(problem: ProblemFrame, solved: list[ProblemFrame]) -> ProblemFrame | None:
    """The most recently solved problem that is the *same* as ``problem``, if any."""
    return next((s for s in reversed(solved) if relation(problem, s) == "same"), None)


def retrieve(problem: ProblemFrame, solved: list[ProblemFrame]) -> list[Match]:
    """The solved problems of the same class, best first: same, then similar, then different;
    within each, most representative attributes in common, then most recently solved."""
    matches = [
        Match(frame, relation(problem, frame), problem.names & frame.names)
        for frame in solved
        if frame.problem_class == problem.problem_class
    ]
    order = {r: i for i, r in enumerate(RELATIONS)}
    indexed = list(enumerate(matches))
    indexed.sort(key=lambda im: (order[im[1].relation], -len(im[1].shared), -im[0]))
    return [m for _, m in indexed]
