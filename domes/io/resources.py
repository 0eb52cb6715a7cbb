"""Where DOMES-py's data is: the shipped knowledge and case base, and the user's own case base.

* The **shipped knowledge** (criteria, scenes, mechanisms, cases) and the
  **embedded case base** ``casebase.db`` built from it are package data
  (``domes/data/``), found with :mod:`importlib.resources`: in a checkout they
  are the top-level ``knowledge/`` and ``casebase.db``, in an installed wheel
  copies of them. ``DOMES_KNOWLEDGE`` names another knowledge folder.
* The **user case base** is where a user's own criteria and solved problems
  go: ``$DOMES_HOME/casebase.db``, else ``$XDG_DATA_HOME/domes/casebase.db``,
  else ``~/.local/share/domes/casebase.db``. It is created, as a copy of the
  embedded one, the first time something is written without ``--db`` or
  ``DOMES_DB``; until then the embedded case base is read. The embedded one
  is never written to by a command that was not given it.

>>> knowledge_dir().name, (knowledge_dir() / "scenes" / "motorcycle.toml").is_file()
('knowledge', True)
>>> shipped_casebase().name
'casebase.db'
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
from importlib.resources import files
from pathlib import Path

from domes.errors import InputError

KNOWLEDGE_ENV = "DOMES_KNOWLEDGE"
HOME_ENV = "DOMES_HOME"
#: The environment variable naming the case base (an SQLAlchemy URL or an SQLite file), used by
#: :mod:`domes.store.casebase`; here so the command line's help can name it without loading SQLAlchemy.
DB_ENV = "DOMES_DB"
CASEBASE_NAME = "casebase.db"

log = logging.getLogger("domes")


def shipped_data() -> Path:
    """The package's data folder (``domes/data``: ``knowledge/`` and ``casebase.db``)."""
    return Path(str(files("domes") / "data"))


def knowledge_dir(path: str | Path | None = None) -> Path:
    """The knowledge folder: ``path``, else ``$DOMES_KNOWLEDGE``, else the shipped knowledge."""
    chosen = path or os.environ.get(KNOWLEDGE_ENV)
    folder = Path(chosen) if chosen else shipped_data() / "knowledge"
    if not folder.is_dir():
        hint = f"set {KNOWLEDGE_ENV} or pass --from" if chosen else "the installation is incomplete: reinstall DOMES-py"
        raise InputError(f"knowledge folder {folder} does not exist ({hint})")
    return folder


def shipped_casebase() -> Path:
    """The embedded case base, built from the shipped knowledge (read-only for the commands)."""
    return shipped_data() / CASEBASE_NAME


def user_dir() -> Path:
    """Where the user's data goes: ``$DOMES_HOME``, else ``$XDG_DATA_HOME/domes``, else ``~/.local/share/domes``."""
    home = os.environ.get(HOME_ENV)
    if home:
        return Path(home)
    xdg = os.environ.get("XDG_DATA_HOME")
    return (Path(xdg) if xdg else Path.home() / ".local" / "share") / "domes"


def user_casebase() -> Path:
    """The user's case base (it may not exist yet)."""
    return user_dir() / CASEBASE_NAME


def default_casebase(write: bool = False) -> Path:
    """The case base used without ``--db`` or ``DOMES_DB``.

    The user's case base when it exists; otherwise the embedded one for
    reading, and for writing a new user case base copied from the embedded
    one (atomically: a reader never sees half a copy).
    """
    user = user_casebase()
    if user.exists() or not write:
        return user if user.exists() else shipped_casebase()
    try:
        user.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{user.name}.", suffix=".tmp", dir=user.parent)
        os.close(fd)
        try:
            shutil.copyfile(shipped_casebase(), tmp)
            if not user.exists():  # another process may have made it meanwhile: keep theirs
                os.replace(tmp, user)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
    except OSError as exc:
        raise InputError(f"cannot create your case base {user}: {exc.strerror}; "
                         f"choose another place with {HOME_ENV}, or a case base with --db") from None
    log.info("created your case base %s (a copy of the shipped one); your criteria and cases go there", user)
    return user
