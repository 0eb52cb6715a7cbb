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
>>> write_atomic(os.path.join(path, "x.txt"), "")
Traceback (most recent call last):
...
domes.errors.InputError: cannot write .../note.txt/x.txt: .../note.txt is a file, not a folder
"""

from __future__ import annotations

import errno
import json
import os
import re
import sys
import tempfile
from pathlib import Path

from domes.errors import InputError

#: The deepest nesting of lists and objects a JSON file may have (the file formats need a handful of levels).
MAX_JSON_DEPTH = 64
_STRING = re.compile(r'"[^"\\]*(?:\\.[^"\\]*)*"')
_PAIR = re.compile(rb"\[\]|\{\}")
_NOT_BRACKET = bytes(sorted(set(range(256)) - set(b"[]{}")))


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


def is_file(path: str | Path) -> bool:
    """Whether ``path`` is a file; False, not an error, for a name the system cannot even look up (too long)."""
    try:
        return Path(path).is_file()
    except OSError:
        return False


def read_json(path: str | Path, text: str | None = None):
    """The JSON value of a file (or of ``text``, read from it), or an InputError naming the file and the line: the
    text is not JSON, nests lists and objects deeper than :data:`MAX_JSON_DEPTH`, or has an integer too long to read.

    >>> read_json("deep.json", "[" * 100 + "]" * 100)
    Traceback (most recent call last):
    ...
    domes.errors.InputError: deep.json: line 1, column 65: lists and objects nested deeper than 64 levels
    """
    text = read_text(path) if text is None else text
    where = _too_deep(text)
    if where is not None:
        line, column = _line_column(text, where)
        raise InputError(f"{path}: line {line}, column {column}: lists and objects nested deeper than "
                         f"{MAX_JSON_DEPTH} levels")
    try:
        return json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{path}: line {exc.lineno}, column {exc.colno}: invalid JSON: {exc.msg}") from None
    except ValueError:  # an integer longer than Python converts (sys.get_int_max_str_digits())
        digits = sys.get_int_max_str_digits()
        found = re.search(r"\d{%d,}" % (digits + 1), text) if digits else None
        line, column = _line_column(text, found.start()) if found else ("?", "?")
        raise InputError(f"{path}: line {line}, column {column}: an integer of more than {digits:,} digits"
                         ) from None
    except RecursionError:
        raise InputError(f"{path}: lists and objects nested too deep") from None


def _too_deep(text: str) -> int | None:
    """Where in ``text`` lists and objects first nest deeper than :data:`MAX_JSON_DEPTH` (an offset), or None.

    Strings left out, the brackets are peeled one level at a time (innermost pairs); past the limit, the place is
    found by counting.
    """
    brackets = _STRING.sub('""', text).encode("utf-8", "replace").translate(None, _NOT_BRACKET)
    for _ in range(MAX_JSON_DEPTH):
        brackets, peeled = _PAIR.subn(b"", brackets)
        if not brackets or not peeled:
            return None  # every level peeled, or brackets that do not pair (json.loads says where)
    if not brackets:
        return None
    depth = 0
    blank = _STRING.sub(lambda m: " " * len(m.group()), text)
    for match in re.finditer(r"[\[\]{}]", blank):
        depth += 1 if match.group() in "[{" else -1
        if depth > MAX_JSON_DEPTH:
            return match.start()
    return None


def _line_column(text: str, offset: int) -> tuple[int, int]:
    line = text.count("\n", 0, offset) + 1
    return line, offset - (text.rfind("\n", 0, offset) + 1) + 1


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def missing_folder(folder: str | Path) -> str:
    """Why ``folder`` cannot hold files, in words: it, or the nearest of its parents that exists, is a file; or it
    does not exist. Empty when it is a folder."""
    folder = Path(folder)
    if folder.is_dir():
        return ""
    for above in (folder, *folder.parents):
        if above.exists() and not above.is_dir():
            return f"{above} is a file, not a folder"
        if above.is_dir():
            break
    return f"folder {folder} does not exist"


def why_not_made(folder: str | Path, exc: OSError) -> str:
    """Why the system would not make ``folder`` (``exc`` from ``mkdir``), said where it applies."""
    folder = Path(folder)
    parent = folder.parent
    if exc.errno in (errno.EACCES, errno.EPERM):
        return f"{parent} does not let this user make folders in it ({exc.strerror})"
    if exc.errno == errno.EROFS:
        return f"{parent} is on a read-only file system"
    if exc.errno == errno.ENOENT and parent.is_dir():  # e.g. /proc: a system folder that takes no new folders
        return f"{parent} takes no new folders ({exc.strerror})"
    return missing_folder(parent) or exc.strerror or str(exc)


def check_target(path: str | Path) -> Path:
    """``path`` if a file can be written there (its folder exists, it is not a folder), before any work is done."""
    path = Path(path)
    if why := missing_folder(path.parent):
        raise InputError(f"cannot write {path}: {why}")
    if path.is_dir():
        raise InputError(f"cannot write {path}: it is a folder")
    return path


def temporary_beside(path: str | Path) -> tuple[int, str]:
    """An open descriptor and the name of a new temporary file in ``path``'s folder, to be renamed over ``path``
    by :func:`publish` when complete (or deleted): a writer that is interrupted leaves the old file as it was."""
    path = check_target(path)
    try:
        return tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror}") from None


def publish(tmp: str, path: str | Path) -> None:
    """Give the complete temporary file ``tmp`` the user's usual permissions and rename it over ``path``."""
    os.chmod(tmp, 0o666 & ~_umask())
    os.replace(tmp, path)


def write_atomic(path: str | Path, text: str | bytes) -> None:
    """Write ``text`` (or bytes) to ``path`` through a temporary file in the same folder and a rename."""
    path = check_target(path)
    fd, tmp = temporary_beside(path)
    try:
        with os.fdopen(fd, "wb") as out:
            out.write(text if isinstance(text, bytes) else text.encode("utf-8"))
        publish(tmp, path)
    except OSError as exc:
        raise InputError(f"cannot write {path}: {exc.strerror}") from None
    finally:
        if os.path.exists(tmp):
            os.unlink(tmp)
