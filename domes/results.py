"""How a stage reports its outcome: a status, a message and the numbers that show its quality.

Every stage entry point returns a result object in the style of
``scipy.optimize.OptimizeResult``: ``status`` (a :class:`Status`), ``success``
(the stage did all it was asked), ``message`` (one line for the designer), and
the numbers that show how good the result is (counts, residuals, condition
numbers). Failures that leave nothing to return raise a
:class:`~domes.errors.DomesError` instead.

Long stages take ``progress=``: a callable that receives one line of text
now and then (at most about twice a second).

>>> Status.STOPPED == "stopped", str(Status.COMPLETE)
(True, 'complete')
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from enum import StrEnum
from typing import Callable

#: A progress callback: receives one line of text describing the work done so far.
Progress = Callable[[str], None]


class Status(StrEnum):
    """The outcome of a stage; compares equal to its text."""

    #: The stage did all it was asked.
    COMPLETE = "complete"
    #: The stage stopped early at a limit (e.g. a sweep at a dead point); the result holds what was done.
    STOPPED = "stopped"
    #: The stage ran correctly but has nothing to propose (every candidate eliminated, no chain).
    EMPTY = "empty"


class Result:
    """Mixin of the result objects: ``success`` follows ``status``.

    A subclass provides ``status`` (a :class:`Status`) and ``message``.
    """

    status: Status
    message: str

    @property
    def success(self) -> bool:
        """True when the stage did all it was asked (``status`` is :attr:`Status.COMPLETE`)."""
        return self.status is Status.COMPLETE


class Listing(Result, Sequence):
    """A result that is also the sequence of what the stage found (chains, labelled chains, ...).

    A subclass names the tuple of items in :attr:`items_field`; ``len``,
    indexing, slicing and iteration go to it.
    """

    items_field = "items"

    def __getitem__(self, index):
        return getattr(self, self.items_field)[index]

    def __len__(self) -> int:
        return len(getattr(self, self.items_field))


class Ticker:
    """Calls a progress callback at most every ``every`` seconds; the message is made only when shown.

    >>> shown = []
    >>> clock = Ticker(shown.append, every=0.0)
    >>> clock.tick(lambda: "half way"); shown
    ['half way']
    """

    def __init__(self, progress: Progress | None, every: float = 0.5):
        self.progress = progress
        self.every = every
        self.last = time.monotonic()

    def tick(self, message: Callable[[], str], force: bool = False) -> None:
        if self.progress is None:
            return
        now = time.monotonic()
        if force or now - self.last >= self.every:
            self.last = now
            self.progress(message())
