"""The SQL store: the case base (criterion frames and solved problems) behind SQLAlchemy 2.0.

``casebase.db`` (SQLite) is the embedded default; any SQLAlchemy URL may
replace it (``--db`` or ``DOMES_DB``). Every edit is one transaction.
"""

from domes.store.casebase import DB_ENV, KnowledgeBase, build, database_url

__all__ = ["DB_ENV", "KnowledgeBase", "build", "database_url"]
