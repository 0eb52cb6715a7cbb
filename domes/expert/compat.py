"""Compatibility shim for experta 1.9.4 on Python >= 3.10; import experta from here only.

experta pins ``frozendict==1.2``, which subclasses ``collections.Mapping``;
that alias was removed in Python 3.10, so ``import experta`` fails with
``AttributeError: module 'collections' has no attribute 'Mapping'``
(upstream: nilp0inter/experta issue #34; slezica/python-frozendict issue #39).
The aliases are restored from ``collections.abc`` before experta is
imported, and nothing else is changed.

>>> from domes.expert.compat import KnowledgeEngine, Fact, Rule
>>> KnowledgeEngine.__name__
'KnowledgeEngine'
"""

import collections
import collections.abc

for _name in ("Mapping", "MutableMapping", "Sequence", "MutableSequence", "Iterable", "Hashable", "Callable"):
    if not hasattr(collections, _name):
        setattr(collections, _name, getattr(collections.abc, _name))

from experta import AS, MATCH, NOT, TEST, DefFacts, Fact, Field, KnowledgeEngine, Rule, W  # noqa: E402

__all__ = ["AS", "MATCH", "NOT", "TEST", "W", "DefFacts", "Fact", "Field", "KnowledgeEngine", "Rule"]
