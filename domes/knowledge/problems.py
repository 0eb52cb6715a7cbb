"""Solved-problem frames (Table 7-1 of seed 002, §7-2) as immutable, validated values.

DOMES keeps, for every problem it has solved, a frame of thirteen slots:
id, class, number of outputs, DOF, mechanism type, independent loops, gear
pairs used, sliders used, vertices (links), edges (joints), key
representative attributes, the relevance vector and the results. The design
expert retrieves them to recognise a problem as the same as, similar to or
different from one it has solved. Here a frame also records the scene whose
rules gave the links their roles, the criteria the designer added, what the
design did (e.g. varied the loops), the rejected candidates with the
criterion that removed each, and its provenance.

>>> frame = ProblemFrame.from_dict({"id": "pump", "problem_class": "Double-acting pump",
...                                    "dof": 1, "loops": 3, "names": ["Piston"]})
>>> frame.problem_class, sorted(frame.names), frame.mechanism_type
('double_acting_pump', ['piston'], 'planar')
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from domes.errors import InputError
from domes.knowledge.frames import ID_PATTERN
from domes.knowledge.relevance import RelevanceVector
from domes.language.parse import normalise_name
from domes.model.requirements import Requirement

#: Structural attributes (Table 7-1 slots 3-10), all whole numbers.
STRUCTURAL = ("outputs", "dof", "space", "loops", "gear_pairs", "slider_pairs", "links", "joints")
_FIELDS = ("id", "title", "problem_class", *STRUCTURAL, "names", "scene", "relevance", "results", "rejected",
           "notes", "criteria_added", "source", "date", "mechanisms", "requirements", "designs")


@dataclass(frozen=True)
class ProblemFrame:
    """One solved problem (see the module doc). ``space`` is λ: 3 planar, 6 spatial."""

    id: str
    problem_class: str
    title: str = ""
    outputs: int | None = None
    dof: int | None = None
    space: int = 3
    loops: int | None = None
    gear_pairs: int | None = None
    slider_pairs: int | None = None
    links: int | None = None
    joints: int | None = None
    names: frozenset[str] = frozenset()
    scene: str | None = None
    relevance: RelevanceVector | None = None
    results: tuple[dict, ...] = ()
    rejected: tuple[dict, ...] = ()
    notes: tuple[str, ...] = ()
    criteria_added: tuple[str, ...] = ()
    source: str = ""
    date: str = ""
    #: Verified dimensioned mechanisms of kept candidates: ``{"candidate", "task", "error", "mechanism"}``.
    mechanisms: tuple[dict, ...] = ()
    #: The requirements the designer stated (the motion, stroke, forces, size, accuracy), each with its unit.
    requirements: tuple[Requirement, ...] = ()
    #: The feasibility level and the ranking: one record per quasi-feasible candidate (status, checks,
    #: mechanism, rank and score when feasible), best first.
    designs: tuple[dict, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "problem_class", normalise_name(self.problem_class))
        object.__setattr__(self, "names", frozenset(normalise_name(n) for n in self.names))

    @property
    def mechanism_type(self) -> str:
        """``planar`` (λ = 3) or ``spatial`` (λ = 6)."""
        return "planar" if self.space == 3 else "spatial"

    @property
    def structure(self) -> dict[str, int | None]:
        """The structural attributes (slots 3-10)."""
        return {k: getattr(self, k) for k in STRUCTURAL}

    @classmethod
    def from_dict(cls, data: Mapping[str, Any], where: str = "problem frame") -> "ProblemFrame":
        """A frame from plain data (JSON); errors name the bad field."""
        if not isinstance(data, Mapping):
            raise InputError(f"{where}: expected an object")
        unknown = set(data) - set(_FIELDS)
        if unknown:
            raise InputError(f"{where}: unknown field(s) {sorted(unknown)}")
        frame_id = data.get("id")
        if not isinstance(frame_id, str) or not ID_PATTERN.match(frame_id):
            raise InputError(f"{where}.id: expected an id of letters, digits, '.', '_' or '-', got {frame_id!r}")
        where = f"{where} {frame_id!r}"
        kwargs: dict[str, Any] = {"id": frame_id}
        for key in STRUCTURAL:
            value = data.get(key, 3 if key == "space" else None)
            if value is not None and (not isinstance(value, int) or isinstance(value, bool) or value < 0):
                raise InputError(f"{where}.{key}: expected a whole number >= 0, got {value!r}")
            kwargs[key] = value
        if kwargs["space"] not in (3, 6):
            raise InputError(f"{where}.space: λ is 3 (planar) or 6 (spatial), got {kwargs['space']}")
        for key in ("problem_class", "title", "scene", "source", "date"):
            value = data.get(key)
            if value is not None and not isinstance(value, str):
                raise InputError(f"{where}.{key}: expected text, got {value!r}")
            if value is not None:
                kwargs[key] = value
        if not kwargs.get("problem_class"):
            raise InputError(f"{where}.problem_class: a problem needs a class")
        for key in ("names", "notes", "criteria_added"):
            value = data.get(key, [])
            if isinstance(value, str) or not all(isinstance(x, str) for x in value):
                raise InputError(f"{where}.{key}: expected a list of text")
            kwargs[key] = frozenset(value) if key == "names" else tuple(value)
        for key in ("results", "rejected", "mechanisms", "designs"):
            value = data.get(key, [])
            if not isinstance(value, list) or not all(isinstance(x, dict) for x in value):
                raise InputError(f"{where}.{key}: expected a list of objects")
            kwargs[key] = tuple(value)
        requirements = data.get("requirements", [])
        if not isinstance(requirements, list):
            raise InputError(f"{where}.requirements: expected a list of requirements")
        kwargs["requirements"] = tuple(Requirement.from_dict(r, f"{where}.requirements") for r in requirements)
        relevance = data.get("relevance")
        if relevance is not None:
            if not isinstance(relevance, Mapping) or set(relevance) != {"ids", "bits"}:
                raise InputError(f"{where}.relevance: expected {{'ids': [...], 'bits': [...]}}")
            kwargs["relevance"] = RelevanceVector(tuple(relevance["ids"]), tuple(relevance["bits"]))
        return cls(**kwargs)

    def to_dict(self) -> dict[str, Any]:
        """Plain data (JSON), the inverse of :meth:`from_dict`."""
        out: dict[str, Any] = {"id": self.id, "title": self.title, "problem_class": self.problem_class}
        out.update(self.structure)
        out["names"] = sorted(self.names)
        if self.scene:
            out["scene"] = self.scene
        if self.relevance is not None:
            out["relevance"] = {"ids": list(self.relevance.ids), "bits": list(self.relevance.bits)}
        out["results"] = [dict(r) for r in self.results]
        out["rejected"] = [dict(r) for r in self.rejected]
        out["notes"] = list(self.notes)
        out["criteria_added"] = list(self.criteria_added)
        out["source"] = self.source
        out["date"] = self.date
        if self.mechanisms:
            out["mechanisms"] = [dict(m) for m in self.mechanisms]
        if self.requirements:
            out["requirements"] = [r.to_dict() for r in self.requirements]
        if self.designs:
            out["designs"] = [dict(d) for d in self.designs]
        return out
