"""Reading and writing text files: one reader, one atomic writer, one rule for output paths.

Every file DOMES-py writes goes through :func:`write_atomic`: the text is
written to a temporary file in the target's folder and renamed over the
target, so a reader never sees half a file and an interrupted write leaves
the old file as it was. The new file gets the permissions a plain ``open``
would give (``0666`` less the umask). A target whose folder does not exist is
refused with a message (no folder is created behind the user's back).

>>> import tempfile, os
>>> path = os.path.join(tempfile.mkdtemp(), "note.txt")
>>> write_atomic(path, "hello\\n")
>>> read_text(path)
'hello\\n'
>>> write_atomic(os.path.join(path + ".d", "x.txt"), "")
Traceback (most recent call last):
...
domes.errors.InputError: cannot write .../note.txt.d/x.txt: folder .../note.txt.d does not exist
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

from domes.errors import InputError


def read_text(path: str | Path) -> str:
    """A UTF-8 text file, or an InputError that names it and says why it cannot be read."""
    path = Path(path)
    try:
        return path.read_text(encoding="utf-8")
    except IsADirectoryError:
        raise InputError(f"{path}: is a folder, not a file") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read: {exc.strerror}") from None
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def check_target(path: str | Path) -> Path:
    """``path`` if a file can be written there (its folder exists, it is not a folder), before any work is done."""
    path = Path(path)
    if not path.parent.is_dir():
        raise InputError(f"cannot write {path}: folder {path.parent} does not exist")
    if path.is_dir():
        raise InputError(f"cannot write {path}: it is a folder")
    return path


def write_atomic(path: str | Path, text: str | bytes) -> None:
    """Write ``text`` (or bytes) to ``path`` through a temporary file in the same folder and a rename."""
    path = check_target(path)
    folder = path.parent
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(text if isinstance(text, bytes) else text.encode("utf-8"))
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror}") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
