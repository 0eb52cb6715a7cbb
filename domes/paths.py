"""Where the shipped knowledge lives: ``knowledge/`` beside the package.

``DOMES_KNOWLEDGE`` overrides the directory.

>>> knowledge_dir().name
'knowledge'
"""

from __future__ import annotations

import os
from pathlib import Path

from domes.errors import DomesError


def knowledge_dir() -> Path:
    """The knowledge directory (criteria, scenes, mechanisms, cases)."""
    env = os.environ.get("DOMES_KNOWLEDGE")
    path = Path(env) if env else Path(__file__).resolve().parents[1] / "knowledge"
    if not path.is_dir():
        raise DomesError(
            f"knowledge directory {path} not found; run from a DOMES-py checkout "
            "(pip install -e .) or set DOMES_KNOWLEDGE to its path"
        )
    return path
