"""Values drawn in a notebook: the registry behind ``_repr_svg_`` and ``_repr_html_``.

Jupyter shows a value by asking its ``_repr_svg_`` or ``_repr_html_``. The
values that have drawings (chains, labelled chains, mechanisms, sweeps,
atlases, synthesis results) live in layers below :mod:`domes.sketch`, which
they may not import; so each of those methods asks :func:`render`, and the
drawings are registered here from above (:func:`register`).

The one plug-in point: the first time a value is shown, :func:`render`
imports the module named :data:`PLUGIN` (:mod:`domes.sketch.notebook`) by
name, and that module registers a renderer for each kind of value. Importing
the values never loads the drawings; a program that never shows a value
never pays for them.

A repr never raises: :func:`render` gives None for a value it cannot draw
(a mechanism without an input, a chain no layout can place), and the
notebook shows the value's text instead. :func:`draw` does the same work and
raises, to see why.

>>> class Pin:
...     def _repr_svg_(self):
...         return render(self, "svg")
>>> register(Pin, "svg", lambda pin: '<svg xmlns="http://www.w3.org/2000/svg"/>')
>>> Pin()._repr_svg_()
'<svg xmlns="http://www.w3.org/2000/svg"/>'
>>> render(Pin(), "html") is None, render(1.5, "svg") is None
(True, True)
"""

from __future__ import annotations

import importlib
from typing import Callable

from domes.errors import InputError

#: The module that registers the renderers, imported by name on first use.
PLUGIN = "domes.sketch.notebook"
#: What a value can be shown as: the MIME types Jupyter asks for them.
KINDS = {"svg": "image/svg+xml", "html": "text/html"}

_renderers: dict[tuple[type, str], Callable[[object], str]] = {}
_loaded = False


def register(cls: type, kind: str, renderer: Callable[[object], str]) -> None:
    """Draw the values of ``cls`` (and its subclasses) as ``kind`` (``svg`` or ``html``) with ``renderer``."""
    if kind not in KINDS:
        raise InputError(f"a drawing is one of {', '.join(KINDS)}, got {kind!r}")
    if not isinstance(cls, type) or not callable(renderer):
        raise InputError(f"register a class and a function, got {cls!r} and {renderer!r}")
    _renderers[(cls, kind)] = renderer


def renderer(value, kind: str) -> Callable[[object], str] | None:
    """The renderer of ``value`` as ``kind``: its class's, else the nearest base class's; None when none is."""
    _load()
    for cls in type(value).__mro__:
        found = _renderers.get((cls, kind))
        if found is not None:
            return found
    return None


def draw(value, kind: str) -> str:
    """``value`` drawn as ``kind``; raises when there is no drawing of it, or the drawing fails (and says why)."""
    if kind not in KINDS:
        raise InputError(f"a drawing is one of {', '.join(KINDS)}, got {kind!r}")
    found = renderer(value, kind)
    if found is None:
        raise InputError(f"no {kind} drawing of a {type(value).__name__}")
    text = found(value)
    if not isinstance(text, str):
        raise InputError(f"the {kind} drawing of a {type(value).__name__} is not text: {type(text).__name__}")
    return text


def render(value, kind: str) -> str | None:
    """``value`` drawn as ``kind`` for a notebook, or None when it cannot be drawn (never raises)."""
    try:
        return draw(value, kind)
    except Exception:  # a repr must not raise: the notebook shows the text instead
        return None


def _load() -> None:
    """Import :data:`PLUGIN` once (should that fail, its error is what :func:`draw` raises, and the next call tries
    again)."""
    global _loaded
    if not _loaded:
        importlib.import_module(PLUGIN)
        _loaded = True
