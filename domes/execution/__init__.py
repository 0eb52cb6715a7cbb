"""Where parallel work runs: in this process (the default), on a local Dask cluster, or on an existing one.

Every parallel stage takes an *executor*: anything with ``map(fn, items)``
that returns ``fn(item)`` for each item, **in the items' order** (so the
output is the same, byte for byte, whatever ran it and whenever each task
finished), and ``share(data)``, which sends large data every task reads to
the workers once (items may hold what it returns); ``completed(fn, items)``
yields ``(index, result)`` pairs as tasks finish, for stages that write
each result as it comes. :func:`executor` makes
one from the user's knobs:

- nothing: :class:`InProcess`, the builtin ``map``, nothing to start;
- ``workers=N`` (``--workers N``): a Dask ``LocalCluster`` of ``N`` worker
  processes on this machine, closed on exit;
- ``scheduler=ADDRESS`` (``--scheduler``, or the ``DOMES_SCHEDULER``
  environment variable): an existing Dask cluster (``tcp://host:8786``),
  whose workers must have DOMES-py installed.

``fn`` must be a module-level function (it is sent to the workers by name).

>>> with executor() as run:
...     run.map(abs, [-2, 1, -3])
[2, 1, 3]
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable, Iterable
from contextlib import contextmanager

from domes.errors import InputError
from domes.results import Progress, Ticker

#: The environment variable naming an existing Dask scheduler.
SCHEDULER_VARIABLE = "DOMES_SCHEDULER"
#: A local cluster has at most this many workers per core of this machine.
MAX_WORKERS_PER_CORE = 4
#: Seconds to wait for a scheduler's answer before saying it does not answer.
SCHEDULER_TIMEOUT = 10


class InProcess:
    """Runs every task here, one after the other."""

    workers = 1
    where = "in this process"

    def share(self, data):
        return data

    def map(self, fn: Callable, items: Iterable, progress: Progress | None = None) -> list:
        items = list(items)
        clock = Ticker(progress)
        out = []
        for k, item in enumerate(items, 1):
            out.append(fn(item))
            clock.tick(lambda: f"{k:,}/{len(items):,} tasks done")
        return out

    def completed(self, fn: Callable, items: Iterable, progress: Progress | None = None):
        """``(index, fn(item))`` for each item, as each finishes (here: in order)."""
        items = list(items)
        clock = Ticker(progress)
        for k, item in enumerate(items):
            yield k, fn(item)
            clock.tick(lambda: f"{k + 1:,}/{len(items):,} tasks done")


class DaskExecutor:
    """Runs tasks on a Dask cluster through ``client``; results come back in the items' order."""

    def __init__(self, client, where: str):
        self.client = client
        self.where = where

    @property
    def workers(self) -> int:
        return max(1, len(self.client.scheduler_info().get("workers", {})))

    def share(self, data):
        """``data`` on every worker, once: a future that tasks' items may hold (Dask resolves it there)."""
        return self.client.scatter(data, broadcast=True, hash=False)

    def map(self, fn: Callable, items: Iterable, progress: Progress | None = None) -> list:
        from distributed import as_completed

        items = list(items)
        if not items:
            return []
        futures = self.client.map(fn, items, pure=False)
        clock = Ticker(progress)
        for k, _ in enumerate(as_completed(futures, loop=self.client.loop), 1):
            clock.tick(lambda: f"{k:,}/{len(items):,} tasks done on {self.where}")
        results = self.client.gather(futures)
        for f in futures:
            f.release()
        return results

    def completed(self, fn: Callable, items: Iterable, progress: Progress | None = None):
        """``(index, fn(item))`` for each item, in the order the tasks finish."""
        from distributed import as_completed

        items = list(items)
        if not items:
            return
        futures = self.client.map(fn, items, pure=False)
        index = {f.key: k for k, f in enumerate(futures)}
        pending = dict(zip(index, futures))
        clock = Ticker(progress)
        try:
            for done, future in enumerate(as_completed(futures, loop=self.client.loop), 1):
                result = future.result()
                del pending[future.key]
                future.release()
                yield index[future.key], result
                clock.tick(lambda: f"{done:,}/{len(items):,} tasks done on {self.where}")
        finally:
            if pending:                                  # stopped early: the rest is not wanted
                self.client.cancel(list(pending.values()))


def check_workers(workers: int | None = None, scheduler: str | None = None) -> str | None:
    """Refuse knobs no executor can run with, before any work starts; returns the scheduler to use (the knob, or
    ``DOMES_SCHEDULER``)."""
    scheduler = scheduler or os.environ.get(SCHEDULER_VARIABLE) or None
    if workers is not None and (not isinstance(workers, int) or workers < 1):
        raise InputError(f"--workers must be a whole number of at least 1, got {workers!r}")
    cores = os.cpu_count() or 1
    if workers is not None and scheduler is None and workers > MAX_WORKERS_PER_CORE * cores:
        raise InputError(f"--workers {workers}: this machine has {cores} cores, and more than "
                         f"{MAX_WORKERS_PER_CORE * cores} local workers only compete for them; for more, start a "
                         "Dask cluster and give --scheduler ADDRESS")
    return scheduler


def _connect(client_type, scheduler: str):
    """A client of the scheduler at ``scheduler``, or a clear error within about twice
    :data:`SCHEDULER_TIMEOUT` seconds (an address that accepts and never answers included)."""
    import dask

    limit = f"{SCHEDULER_TIMEOUT}s"
    failure = _silent(scheduler, SCHEDULER_TIMEOUT)
    if failure:
        raise InputError(f"cannot reach the Dask scheduler at {scheduler!r} (an address such as tcp://host:8786): "
                         f"{failure}")
    quiet = logging.getLogger("distributed")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL)                         # Dask's own warnings about the failed attempts
    try:
        with dask.config.set({"distributed.comm.timeouts.connect": limit}):
            try:
                return client_type(scheduler, timeout=limit, set_as_default=False)
            except TimeoutError:
                failure = f"no answer as a Dask scheduler within {SCHEDULER_TIMEOUT} s"
            except MemoryError:                              # a length read from another protocol's bytes
                failure = "it answered, but not as a Dask scheduler does"
            except Exception as exc:  # noqa: BLE001 - Dask raises OSError, ValueError, MemoryError and others
                failure = str(exc)[:300] or type(exc).__name__
        _collect_quietly()                                   # the half-made client's closing says nothing more
    finally:
        quiet.setLevel(level)
    raise InputError(f"cannot reach the Dask scheduler at {scheduler!r} (an address such as tcp://host:8786): "
                     f"{failure}")


def _silent(scheduler: str, seconds: float) -> str | None:
    """Why a TCP scheduler address cannot be a Dask scheduler: it refuses the connection, or accepts it and says
    nothing within ``seconds`` (a Dask scheduler sends its handshake at once; Dask itself would wait for ever).
    None when it answers, or for other kinds of address (left to Dask)."""
    import socket

    scheme, _, rest = scheduler.rpartition("://")
    host, _, port = rest.rpartition(":")
    if scheme not in ("", "tcp") or not host or not port.isdigit():
        return None
    try:
        with socket.create_connection((host.strip("[]"), int(port)), timeout=seconds) as probe:
            probe.settimeout(seconds)
            return None if probe.recv(1) else "it closed the connection without a word"
    except TimeoutError:
        return f"it accepts connections but says nothing within {seconds:g} s: not a Dask scheduler, or stuck"
    except OSError as exc:
        return exc.strerror or str(exc)[:200]


def _collect_quietly() -> None:
    import gc
    import sys

    hook = sys.unraisablehook
    sys.unraisablehook = lambda _: None
    try:
        gc.collect()
    finally:
        sys.unraisablehook = hook


@contextmanager
def executor(workers: int | None = None, scheduler: str | None = None):
    """The executor for the knobs (see the module's doc); the cluster it starts is closed on exit."""
    scheduler = check_workers(workers, scheduler)
    if scheduler is None and (workers is None or workers == 1):
        yield InProcess()
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError:                                    # pragma: no cover - dask is a dependency
        raise InputError("parallel runs need Dask: pip install 'distributed'") from None
    if scheduler is not None:
        client = _connect(Client, scheduler)
        try:
            yield DaskExecutor(client, f"the Dask cluster at {scheduler}")
        finally:
            client.close()
        return
    import dask

    logging.getLogger("distributed").setLevel(logging.ERROR)     # the scheduler runs here: no INFO lines on stderr
    # Dask's workers return freed memory to the system from 64 kB up (MALLOC_TRIM_THRESHOLD_). Setting any value
    # turns off glibc's adaptive thresholds: the atlas, which makes and drops millions of small graphs, ran at half
    # speed, and numpy's large temporaries were mapped and unmapped on every operation (the kernel at a third of its
    # speed). Unset, the workers allocate as this process does.
    with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
        # Workers log only what is critical: a task's error reaches the caller as its exception, and while the
        # cluster closes a worker's heartbeat can meet the closed scheduler and log a traceback that means nothing.
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                               silence_logs=logging.CRITICAL)
    client = Client(cluster, set_as_default=False)
    try:
        yield DaskExecutor(client, f"a local Dask cluster of {workers} workers")
    finally:
        quiet = logging.getLogger("distributed")
        level = quiet.level
        quiet.setLevel(logging.CRITICAL)                   # the same race, on this side, while closing
        try:
            client.close()
            cluster.close()
        finally:
            quiet.setLevel(level)


__all__ = ["DaskExecutor", "InProcess", "SCHEDULER_VARIABLE", "check_workers", "executor"]
