"""SQLAlchemy 2.0 models of the case base (``casebase.db``): one declarative Base for every table.

The schema is versioned per component: the ``schema_version`` table has one
row per component (``knowledge`` here; the design expert adds its problem
frames as another component), so that a part of the schema can change
without touching the others. :data:`SCHEMA_VERSIONS` is what this DOMES-py
reads and writes; opening a database of another version is refused with a
message (see :func:`domes.store.casebase.open_engine`).

>>> sorted(Base.metadata.tables)
['criteria', 'history', 'problems', 'schema_version']
"""

from __future__ import annotations

from typing import Any

from sqlalchemy import JSON, Boolean, Integer, String, Text
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column

from domes.knowledge.frames import CriterionFrame
from domes.language.tree import category, from_json, to_json

#: Schema version of each component of the case base.
SCHEMA_VERSIONS: dict[str, int] = {"knowledge": 1, "cases": 1, "history": 1}
#: Components a case base made before them may lack: they are added on the first write.
ADDED_COMPONENTS = ("history",)


class Base(DeclarativeBase):
    """The declarative base shared by every table of the case base."""


class SchemaVersion(Base):
    """One row per schema component: its version."""

    __tablename__ = "schema_version"

    component: Mapped[str] = mapped_column(String(64), primary_key=True)
    version: Mapped[int] = mapped_column(Integer)


class CriterionRow(Base):
    """A criterion frame (Table 7-2): the text as written and its parsed trees as JSON.

    ``number`` orders the knowledge base (the positions of relevance-vector
    elements); it grows with every criterion added and is never reused.
    """

    __tablename__ = "criteria"

    id: Mapped[str] = mapped_column(String(64), primary_key=True)
    number: Mapped[int] = mapped_column(Integer, unique=True)
    text: Mapped[str] = mapped_column(Text)
    tree: Mapped[dict[str, Any]] = mapped_column(JSON)
    category: Mapped[str] = mapped_column(String(4))
    explanation: Mapped[str] = mapped_column(Text)
    keywords: Mapped[list[str]] = mapped_column(JSON)
    relevance_text: Mapped[str] = mapped_column(Text)
    relevance: Mapped[dict[str, Any]] = mapped_column(JSON)
    level: Mapped[int] = mapped_column(Integer)
    source: Mapped[str] = mapped_column(Text)
    date: Mapped[str] = mapped_column(String(10))
    enabled: Mapped[bool] = mapped_column(Boolean)

    @classmethod
    def columns_of(cls, frame: CriterionFrame) -> dict[str, Any]:
        """The stored columns of a frame: its text and its parsed trees as JSON."""
        return {
            "id": frame.id, "text": frame.text, "tree": to_json(frame.tree), "category": frame.category,
            "explanation": frame.explanation, "keywords": list(frame.keywords), "relevance_text": frame.relevance_text,
            "relevance": to_json(frame.relevance), "level": frame.level, "source": frame.source, "date": frame.date,
            "enabled": frame.enabled,
        }

    def frame(self) -> CriterionFrame:
        """The frame of this row: the stored trees are decoded and validated, not re-parsed."""
        tree = from_json(self.tree, "tree", "criterion")
        relevance = from_json(self.relevance, "relevance", "relevance")
        return CriterionFrame(
            id=self.id, text=self.text, tree=tree, category=category(tree), explanation=self.explanation,
            keywords=tuple(self.keywords), relevance_text=self.relevance_text, relevance=relevance, level=self.level,
            source=self.source, date=self.date, enabled=bool(self.enabled),
        )


class ProblemRow(Base):
    """A solved-problem frame (Table 7-1): its class for retrieval, the whole frame as JSON.

    ``number`` orders the case base in the order problems were solved.
    """

    __tablename__ = "problems"

    id: Mapped[str] = mapped_column(String(64), primary_key=True)
    number: Mapped[int] = mapped_column(Integer, unique=True)
    problem_class: Mapped[str] = mapped_column(String(128), index=True)
    frame: Mapped[dict[str, Any]] = mapped_column(JSON)


class HistoryRow(Base):
    """One change of the case base: what (``action``, ``target``), when, in which session, why, and the rows
    it changed (``changes``: ``{"table", "key", "before", "after"}``, each row as its columns, None where there
    was none), from which :meth:`~domes.store.casebase.KnowledgeBase.undo` restores them.
    """

    __tablename__ = "history"

    number: Mapped[int] = mapped_column(Integer, primary_key=True)
    time: Mapped[str] = mapped_column(String(32))
    session: Mapped[str] = mapped_column(Text)
    action: Mapped[str] = mapped_column(String(64))
    target: Mapped[str] = mapped_column(Text)
    why: Mapped[str] = mapped_column(Text)
    changes: Mapped[list[dict[str, Any]]] = mapped_column(JSON)
