"""Names a package re-exports, imported from their modules on first use (PEP 562).

A package's ``__init__`` that imported every module it re-exports would
load numpy, scipy and SQLAlchemy for ``domes --help``; instead it lists
where each name lives and gets its ``__getattr__`` and ``__dir__`` here.

>>> import types
>>> pkg = types.ModuleType("pkg")
>>> pkg.__getattr__, pkg.__dir__ = exports(vars(pkg), {"dumps": "json"})
>>> pkg.dumps([1])
'[1]'
"""

from __future__ import annotations

import importlib


def exports(namespace: dict, where: dict[str, str]):
    """``(__getattr__, __dir__)`` for a module whose globals are ``namespace``: each name of ``where`` comes from
    the module named there, imported on first use and kept in ``namespace``."""
    name = namespace.get("__name__", "module")

    def __getattr__(attribute: str):
        module = where.get(attribute)
        if module is None:
            raise AttributeError(f"module {name!r} has no attribute {attribute!r}")
        value = getattr(importlib.import_module(module), attribute)
        namespace[attribute] = value
        return value

    def __dir__() -> list[str]:
        return sorted(set(namespace) | set(where))

    return __getattr__, __dir__


__all__ = ["exports"]
