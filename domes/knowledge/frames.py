"""Criterion frames (Table 7-2 of seed 002, §7-2) as immutable, validated values.

DOMES's frame has six slots: Id, Explanation, Criterion Type, Key-words,
Relevance-fn and Rejection-fn, the last two being LISP code. Here the
relevance function is a parsed relevance condition and the rejection
function the parsed criterion (the rejection condition is its negation);
both are data, never code. A frame also keeps its text as the designer
wrote it, the screening level, its provenance (source, date) and whether it
is enabled.

>>> frame = CriterionFrame.create("book-v",
...     "THE VERTEX REPRESENTING “PISTON” MUST HAVE ITS “TYPE” PROPERTY-VALUE AS (P R)")
>>> frame.category, frame.level, frame.relevance_text
('v', 1, 'the problem has “piston”')
"""

from __future__ import annotations

import datetime as _dt
import re
from dataclasses import dataclass, replace
from typing import Any, Iterable, Mapping

from domes.errors import DomesError, InputError
from domes.language.parse import parse_criterion, parse_relevance
from domes.language.render import render_criterion, render_relevance
from domes.language.tree import AllOf, Always, Criterion, HasName, Relevance, category, names_used
from domes.language.tree import level as cost_level

ID_PATTERN = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_.\-]{0,63}$")
DATE_PATTERN = re.compile(r"^\d{4}(-\d{2}(-\d{2})?)?$")
KEYWORD_PATTERN = re.compile(r"^[a-z0-9][a-z0-9 _\-]{0,63}$")
#: Highest screening level; level 4 and above are for criteria supplied by later stages.
MAX_LEVEL = 9
#: The fields of a frame in a knowledge source file, in the order they are written.
FIELDS = ("id", "text", "explanation", "keywords", "relevance", "level", "source", "date", "enabled")


@dataclass(frozen=True)
class CriterionFrame:
    """One screening criterion with everything the knowledge base keeps about it.

    Build one with :meth:`create` (parses and validates); ``tree`` is the
    parsed requirement (a graph that does not meet it is rejected),
    ``relevance`` the parsed relevance condition.
    """

    id: str
    text: str
    tree: Criterion
    category: str
    explanation: str
    keywords: tuple[str, ...]
    relevance_text: str
    relevance: Relevance
    level: int
    source: str
    date: str
    enabled: bool

    @classmethod
    def create(
        cls,
        id: str,
        text: str,
        explanation: str = "",
        keywords: Iterable[str] = (),
        relevance: str | None = None,
        level: int | None = None,
        source: str = "",
        date: str | None = None,
        enabled: bool = True,
    ) -> "CriterionFrame":
        """Parse and validate a frame; errors name the field.

        Without ``relevance`` a criterion about named vertices or loops is
        relevant to problems that have them all (categories v, vi, §7-2 4.5);
        any other is always relevant. Without ``level`` the cheapest level
        that can evaluate it is used.
        """
        if not isinstance(id, str) or not ID_PATTERN.match(id):
            raise InputError(f"id: {id!r} is not an id (letters, digits, '.', '_', '-'; at most 64; starts with a letter or digit)")
        if not isinstance(text, str):
            raise InputError(f"text: expected a string, got {type(text).__name__}")
        text = " ".join(text.split())
        try:
            tree = parse_criterion(text)
        except DomesError as exc:
            raise InputError(f"text: {exc}") from None
        if relevance is None or (isinstance(relevance, str) and not relevance.strip()):
            relevance_tree = default_relevance(tree)
        else:
            if not isinstance(relevance, str):
                raise InputError(f"relevance: expected a string, got {type(relevance).__name__}")
            try:
                relevance_tree = parse_relevance(relevance)
            except DomesError as exc:
                raise InputError(f"relevance: {exc}") from None
        minimum = cost_level(tree)
        if level is None:
            level = minimum
        elif not isinstance(level, int) or isinstance(level, bool) or not minimum <= level <= MAX_LEVEL:
            raise InputError(
                f"level: expected a whole number from {minimum} (the cheapest level that can evaluate this criterion) "
                f"to {MAX_LEVEL}, got {level!r}"
            )
        if date is None:
            date = _dt.date.today().isoformat()
        for name, value in (("explanation", explanation), ("source", source), ("date", date)):
            if not isinstance(value, str):
                raise InputError(f"{name}: expected a string, got {type(value).__name__}")
        if date and not DATE_PATTERN.match(date):
            raise InputError(f"date: {date!r} is not a date (YYYY, YYYY-MM or YYYY-MM-DD)")
        if not isinstance(enabled, bool):
            raise InputError(f"enabled: expected true or false, got {enabled!r}")
        if isinstance(keywords, str):
            raise InputError("keywords: expected a list of keywords, got a single string")
        words = []
        for word in keywords:
            word = " ".join(str(word).lower().split())
            if not KEYWORD_PATTERN.match(word):
                raise InputError(f"keywords: {word!r} is not a keyword (letters, digits, spaces, '-', '_')")
            if word not in words:
                words.append(word)
        return cls(
            id=id,
            text=text,
            tree=tree,
            category=category(tree),
            explanation=" ".join(explanation.split()),
            keywords=tuple(words),
            relevance_text=render_relevance(relevance_tree),
            relevance=relevance_tree,
            level=level,
            source=source.strip(),
            date=date,
            enabled=enabled,
        )

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> "CriterionFrame":
        """A frame from a source-file table or an exported record (the keys of :data:`FIELDS`)."""
        if not isinstance(data, Mapping):
            raise InputError(f"expected a table of fields, got {type(data).__name__}")
        unknown = set(data) - set(FIELDS) - {"category", "reading"}
        if unknown:
            raise InputError(f"unknown field(s) {sorted(unknown)}; known: {', '.join(FIELDS)}")
        for required in ("id", "text"):
            if required not in data:
                raise InputError(f"missing field {required!r}")
        kwargs = {k: data[k] for k in FIELDS if k in data}
        kwargs["date"] = data.get("date", "")
        frame = cls.create(**kwargs)
        if "category" in data and data["category"] != frame.category:
            raise InputError(f"category: the text is a category ({frame.category}) criterion, not ({data['category']})")
        return frame

    def to_dict(self) -> dict[str, Any]:
        """The fields written to a source or export file (readable; re-parsed on import)."""
        return {
            "id": self.id,
            "text": self.text,
            "explanation": self.explanation,
            "keywords": list(self.keywords),
            "relevance": self.relevance_text,
            "level": self.level,
            "source": self.source,
            "date": self.date,
            "enabled": self.enabled,
            "category": self.category,
            "reading": render_criterion(self.tree),
        }

    def edited(self, **changes: Any) -> "CriterionFrame":
        """A new frame with some fields changed, re-validated (``text`` re-parsed)."""
        bad = set(changes) - (set(FIELDS) - {"id"})
        if bad:
            raise InputError(f"cannot edit field(s) {sorted(bad)} (the id is fixed: add a new criterion instead)")
        current = {k: v for k, v in self.to_dict().items() if k in FIELDS}
        if "text" in changes:  # a derived level or relevance follows the new text
            if "level" not in changes and self.level == cost_level(self.tree):
                current.pop("level")
            if "relevance" not in changes and self.relevance == default_relevance(self.tree):
                current.pop("relevance")
        current.update(changes)
        return CriterionFrame.from_dict(current)

    def with_enabled(self, enabled: bool) -> "CriterionFrame":
        return replace(self, enabled=enabled)


def default_relevance(tree: Criterion) -> Relevance:
    """Relevant to problems having every named vertex and loop the criterion mentions; else always.

    >>> from domes.language.parse import parse_criterion
    >>> default_relevance(parse_criterion("the swing arm is adjacent to the ground"))
    AllOf(items=(HasName(name='ground'), HasName(name='swing_arm')))
    """
    roles, loops = names_used(tree)
    names = sorted(set(roles) | set(loops))
    if not names:
        return Always()
    if len(names) == 1:
        return HasName(names[0])
    return AllOf(tuple(HasName(n) for n in names))
