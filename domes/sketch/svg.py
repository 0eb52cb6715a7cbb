"""A small SVG writer: escaped text, fixed number format, byte-identical output.

Elements are plain strings built by :func:`tag`; numbers go through
:func:`num` (two decimals, no ``-0.00``), so the same drawing always gives
the same bytes.

>>> tag("circle", {"cx": num(1), "cy": num(-0.001), "r": num(2.5)})
'<circle cx="1.00" cy="0.00" r="2.50"/>'
>>> tag("text", {"x": "0"}, text="a < b & c")
'<text x="0">a &lt; b &amp; c</text>'
"""

from __future__ import annotations

from typing import Iterable, Mapping, Sequence
from xml.sax.saxutils import escape, quoteattr

Point = tuple[float, float]

#: Decimals written for every coordinate and length.
DECIMALS = 2


def num(x: float) -> str:
    """A number with :data:`DECIMALS` decimals; ``-0.00`` is written ``0.00``."""
    text = f"{float(x):.{DECIMALS}f}"
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


def points(pts: Iterable[Point]) -> str:
    """The ``points`` attribute of a polygon or polyline."""
    return " ".join(f"{num(x)},{num(y)}" for x, y in pts)


def path_data(commands: Sequence[tuple[str, Sequence[float]]]) -> str:
    """Path ``d`` from ``(command, numbers)`` pairs; ``int`` values (arc flags) are written as such.

    >>> path_data([("M", (0, 0.5)), ("A", (2.0, 2.0, 0, 1, 1, 3.0, 0.0))])
    'M 0 0.50 A 2.00 2.00 0 1 1 3.00 0.00'
    """
    def word(v: float) -> str:
        return str(v) if isinstance(v, int) else num(v)

    return " ".join(cmd + (" " + " ".join(word(v) for v in args) if args else "") for cmd, args in commands)


def tag(name: str, attrs: Mapping[str, str] | None = None, children: Iterable[str] = (), text: str | None = None) -> str:
    """One element with attributes in the given order, escaped text, child elements."""
    head = name + "".join(f" {key}={quoteattr(str(value))}" for key, value in (attrs or {}).items())
    body = (escape(text) if text is not None else "") + "".join(children)
    return f"<{head}>{body}</{name}>" if body else f"<{head}/>"


def document(width: float, height: float, children: Iterable[str], title: str | None = None) -> str:
    """A standalone SVG document (XML) of the given size in user units."""
    attrs = {
        "xmlns": "http://www.w3.org/2000/svg",
        "width": num(width),
        "height": num(height),
        "viewBox": f"0 0 {num(width)} {num(height)}",
    }
    items = ([tag("title", text=title)] if title else []) + list(children)
    return tag("svg", attrs, ["\n" + item for item in items] + ["\n"])
