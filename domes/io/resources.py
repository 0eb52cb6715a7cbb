"""Where the shipped knowledge lives: ``knowledge/`` and ``casebase.db`` of the checkout.

``DOMES_KNOWLEDGE`` overrides the knowledge folder (criteria, scenes,
mechanisms, cases).

>>> knowledge_dir().name
'knowledge'
"""

from __future__ import annotations

import os
from pathlib import Path

import domes
from domes.errors import InputError

KNOWLEDGE_ENV = "DOMES_KNOWLEDGE"


def repo_root() -> Path:
    """The checkout that holds the ``domes`` package (installed editable), with pyproject.toml."""
    root = Path(domes.__file__).resolve().parent.parent
    if not (root / "pyproject.toml").is_file():
        raise InputError(
            f"cannot find the DOMES-py checkout (no pyproject.toml in {root}); "
            f"give the case base with --db or DOMES_DB and the sources with {KNOWLEDGE_ENV}"
        )
    return root


def knowledge_dir(path: str | Path | None = None) -> Path:
    """The knowledge folder: ``path``, else ``$DOMES_KNOWLEDGE``, else ``knowledge/`` of the checkout."""
    chosen = path or os.environ.get(KNOWLEDGE_ENV)
    folder = Path(chosen) if chosen else repo_root() / "knowledge"
    if not folder.is_dir():
        raise InputError(f"knowledge folder {folder} does not exist (set {KNOWLEDGE_ENV} or pass --from)")
    return folder
