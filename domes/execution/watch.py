"""A parallel run's deadline: how long it may wait for its workers, and the error that ends the wait.

Dask runs a task again when the worker running it dies, and gives up on
it (``KilledWorker``) after a few deaths; it waits for ever when no
worker is left. :class:`Watch` gives that wait a deadline: a run gives up
when, for :func:`worker_timeout` seconds (``DOMES_WORKER_TIMEOUT``,
default :data:`WORKER_TIMEOUT`), no task has finished and either no
worker has been running or the scheduler has not answered. A long task
on a live worker is never cut short. The run then ends with a
:class:`ClusterError`, one line that says what was lost and what to do.

>>> worker_timeout({"DOMES_WORKER_TIMEOUT": "120"})
120.0
>>> str(ClusterError("lost the workers of a local Dask cluster"))
'lost the workers of a local Dask cluster'
"""

from __future__ import annotations

import logging
import math
import os
import time
from collections.abc import Callable, Mapping

from domes.errors import DomesError, InputError

#: The environment variable that sets :func:`worker_timeout`.
WORKER_TIMEOUT_VARIABLE = "DOMES_WORKER_TIMEOUT"
#: Seconds a parallel run waits with no worker alive (or after losing one) and no task finished before it gives
#: up. A local worker is restarted within seconds; a remote cluster that starts its workers on demand may need
#: more (set ``DOMES_WORKER_TIMEOUT``).
WORKER_TIMEOUT = 60.0
#: Seconds between two looks at the cluster's workers while no task finishes.
LOOK_EVERY = 1.0

logger = logging.getLogger("domes")


class ClusterError(DomesError):
    """A parallel run cannot go on: its workers or its scheduler were lost. The message says what was lost, how
    much was done, and how to run the rest."""


def worker_timeout(environ: Mapping[str, str] | None = None) -> float:
    """The seconds of :data:`WORKER_TIMEOUT_VARIABLE` (default :data:`WORKER_TIMEOUT`); a bad value is refused."""
    text = (os.environ if environ is None else environ).get(WORKER_TIMEOUT_VARIABLE, "").strip()
    if not text:
        return WORKER_TIMEOUT
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not (math.isfinite(seconds) and seconds > 0):
        raise InputError(f"{WORKER_TIMEOUT_VARIABLE} must be a number of seconds above 0, got {text!r}")
    return seconds


def killed(exc: BaseException | None) -> bool:
    """Whether a task's error is Dask's ``KilledWorker``: the workers running it died, the task did not fail."""
    from distributed import KilledWorker

    return isinstance(exc, KilledWorker)


def lost_connection(exc: BaseException) -> bool:
    """Whether ``exc``, raised while talking to a cluster, says a worker or the scheduler went away: Dask's
    ``KilledWorker``, ``CommClosedError`` and ``TimeoutError`` (both ``OSError``), a cancelled future."""
    from concurrent.futures import CancelledError

    return killed(exc) or isinstance(exc, (OSError, CancelledError))


class Watch:
    """Looks at a cluster's workers while a run waits, and raises :class:`ClusterError` when the wait is lost.

    ``workers()`` returns the addresses of the workers able to run tasks, or None when the scheduler does not
    answer; ``where`` names the cluster; ``rerun`` says how to run the rest.

    >>> alive = [{"tcp://a:1"}, set(), set()]
    >>> watch = Watch(lambda: alive.pop(0), "a test cluster", "run it again", timeout=0.0, every=0.0)
    >>> watch.look(done=0, total=3)
    >>> watch.look(done=0, total=3)
    Traceback (most recent call last):
    ...
    domes.execution.watch.ClusterError: lost the workers of a test cluster: 1 worker died (killed, or out of \
memory) and none has run for 0 s; 0 of 3 tasks done. Run it again, or set DOMES_WORKER_TIMEOUT=SECONDS to wait \
longer than 0 s
    """

    def __init__(self, workers: Callable[[], set | None], where: str, rerun: str,
                 timeout: float | None = None, every: float = LOOK_EVERY):
        self.workers = workers
        self.where = where
        self.rerun = rerun
        self.timeout = worker_timeout() if timeout is None else timeout
        self.every = every
        self.since = time.monotonic()        # the last sign of life: a task finished, or a worker was running
        self.looked = -math.inf
        self.alive: set = set()              # the workers at the last look
        self.died = 0                        # workers lost over the run
        self.told = False

    def progress(self) -> None:
        """A task finished."""
        self.since = time.monotonic()

    def lost(self) -> None:
        """A worker, or what it held, was lost: say so once (its tasks run again)."""
        if not self.told:
            self.told = True
            logger.warning(f"lost a worker of {self.where} (killed, or out of memory); its tasks run again (the run "
                           f"gives up after {self.timeout:g} s without a worker)")

    def look(self, done: int, total: int) -> None:
        """Nothing finished lately: look at the workers (at most every ``every`` seconds); raise
        :class:`ClusterError` when none has been running (or the scheduler has not answered) for ``timeout``
        seconds."""
        now = time.monotonic()
        if now - self.looked < self.every:
            return
        self.looked = now
        alive = self.workers()
        if alive is None:                                          # the scheduler does not answer
            if now - self.since >= self.timeout:
                raise ClusterError(f"lost the scheduler of {self.where}: it has not answered for "
                                   f"{now - self.since:.0f} s; {done:,} of {total:,} tasks done. {self._rerun()}")
            return
        gone = self.alive - alive
        self.alive = set(alive)
        if gone:
            self.died += len(gone)
            self.lost()
        if alive:
            self.since = now
        elif now - self.since >= self.timeout:
            died = f"{self.died} worker{'s' if self.died != 1 else ''} died (killed, or out of memory) and none"
            raise ClusterError(f"lost the workers of {self.where}: "
                               + (died if self.died else "it has no worker, and none")
                               + f" has run for {now - self.since:.0f} s; {done:,} of {total:,} tasks done. "
                               f"{self._rerun()}")

    def state(self) -> str:
        """How long the run has waited for a worker, for a progress line ('' while one is running)."""
        waited = time.monotonic() - self.since
        if self.alive or waited < self.every:
            return ""
        return f"no worker running for {waited:.0f} s (the run gives up after {self.timeout:g} s)"

    def _rerun(self) -> str:
        return (f"{self.rerun[:1].upper()}{self.rerun[1:]}, or set {WORKER_TIMEOUT_VARIABLE}=SECONDS to wait longer "
                f"than {self.timeout:g} s")


__all__ = ["ClusterError", "WORKER_TIMEOUT", "WORKER_TIMEOUT_VARIABLE", "Watch", "killed", "lost_connection", "worker_timeout"]
