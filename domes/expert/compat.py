"""Compatibility shim for experta 1.9.4 on Python >= 3.10; import experta from here only.

experta pins ``frozendict==1.2``, which subclasses ``collections.Mapping``;
that alias was removed in Python 3.10, so ``import experta`` fails with
``AttributeError: module 'collections' has no attribute 'Mapping'``
(upstream: nilp0inter/experta issue #34; slezica/python-frozendict issue #39).
The aliases are restored from ``collections.abc`` before experta is
imported. experta also calls ``logging.basicConfig()`` when imported, which
gives the root logger a handler on stderr in whatever program imports
DOMES-py (and in every Dask worker process that imports it again: their
INFO lines then reached the terminal); that handler is taken off again.

>>> from domes.expert.compat import KnowledgeEngine, Fact, Rule
>>> KnowledgeEngine.__name__
'KnowledgeEngine'
"""

import collections
import collections.abc
import logging

for _name in ("Mapping", "MutableMapping", "Sequence", "MutableSequence", "Iterable", "Hashable", "Callable"):
    if not hasattr(collections, _name):
        setattr(collections, _name, getattr(collections.abc, _name))

_handlers = list(logging.root.handlers)
from experta import AS, MATCH, NOT, TEST, DefFacts, Fact, Field, KnowledgeEngine, Rule, W  # noqa: E402

for _handler in logging.root.handlers[len(_handlers):]:  # experta's logging.basicConfig(): not ours to set
    logging.root.removeHandler(_handler)

__all__ = ["AS", "MATCH", "NOT", "TEST", "W", "DefFacts", "Fact", "Field", "KnowledgeEngine", "Rule"]
