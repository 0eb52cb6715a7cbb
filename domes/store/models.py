"""SQLAlchemy 2.0 models of the case base (``casebase.db``): one declarative Base for every table.

The schema is versioned per component: the ``schema_version`` table has one
row per component (``knowledge`` here; the design expert adds its problem
frames as another component), so that a part of the schema can change
without touching the others. :data:`SCHEMA_VERSIONS` is what this DOMES-py
reads and writes; opening a database of another version is refused with a
message (see :func:`domes.store.casebase.open_engine`).

>>> sorted(Base.metadata.tables)
['criteria', 'problems', 'schema_version']
"""

from __future__ import annotations

from typing import Any

from sqlalchemy import JSON, Boolean, Integer, String, Text
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column

#: Schema version of each component of the case base.
SCHEMA_VERSIONS: dict[str, int] = {"knowledge": 1, "cases": 1}


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

    #: Columns that hold a frame field (all but ``number``).
    FRAME_COLUMNS = (
        "id", "text", "tree", "category", "explanation", "keywords", "relevance_text", "relevance", "level",
        "source", "date", "enabled",
    )

    def record(self) -> dict[str, Any]:
        return {c: getattr(self, c) for c in self.FRAME_COLUMNS}


class ProblemRow(Base):
    """A solved-problem frame (Table 7-1): its class for retrieval, the whole frame as JSON.

    ``number`` orders the case base in the order problems were solved.
    """

    __tablename__ = "problems"

    id: Mapped[str] = mapped_column(String(64), primary_key=True)
    number: Mapped[int] = mapped_column(Integer, unique=True)
    problem_class: Mapped[str] = mapped_column(String(128), index=True)
    frame: Mapped[dict[str, Any]] = mapped_column(JSON)
