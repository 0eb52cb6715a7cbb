"""Reading knowledge files written in TOML, with errors that name the file and line.

``tomllib`` reports syntax errors with a line but gives no positions for
values; :meth:`TomlSource.line_of` finds the line of a key or value so that
a semantic error can point at it too.

>>> src = TomlSource.parse('name = "x"\\nlinks = 6\\n', "demo.toml")
>>> src.data["links"], src.line_of("links")
(6, 2)
"""

from __future__ import annotations

import re
import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from domes.errors import InputError
from domes.io.files import read_text


@dataclass(frozen=True)
class TomlSource:
    """Parsed TOML plus its text, for locating errors."""

    path: str
    text: str
    data: dict[str, Any]

    @classmethod
    def parse(cls, text: str, path: str = "<text>") -> "TomlSource":
        try:
            data = tomllib.loads(text)
        except tomllib.TOMLDecodeError as exc:
            raise InputError(f"{path}: TOML syntax error: {exc}") from None
        return cls(path, text, data)

    @classmethod
    def read(cls, path: str | Path) -> "TomlSource":
        return cls.parse(read_text(path), str(path))

    def line_of(self, needle: str, after: int = 0) -> int | None:
        """The first line (1-based) after line ``after`` that mentions ``needle`` as a key or quoted value."""
        pattern = re.compile(rf'(^|[\s\[{{,]){re.escape(needle)}\s*=|"{re.escape(needle)}"|\'{re.escape(needle)}\'')
        for number, line in enumerate(self.text.splitlines(), 1):
            if number > after and pattern.search(line.split("#", 1)[0] if '"' not in line else line):
                return number
        return None

    def table_line(self, name: str, index: int) -> int:
        """The line of the ``index``-th ``[[name]]`` array-of-tables header (0 if absent)."""
        count = -1
        for number, line in enumerate(self.text.splitlines(), 1):
            if line.strip() == f"[[{name}]]":
                count += 1
                if count == index:
                    return number
        return 0

    def error(self, message: str, line: int | None = None) -> InputError:
        """An InputError that names this file and, when known, the line."""
        where = f"{self.path}:{line}" if line else self.path
        return InputError(f"{where}: {message}")
