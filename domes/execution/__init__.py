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

On Dask, a task whose worker dies runs again, and a run that has had no
worker for ``DOMES_WORKER_TIMEOUT`` seconds (:mod:`domes.execution.watch`)
ends in a :class:`ClusterError`: one line saying what was lost and how to
run the rest, never a wait without end or Dask's traceback.

>>> with executor() as run:
...     run.map(abs, [-2, 1, -3])
[2, 1, 3]
"""

from __future__ import annotations

import logging
import os
import time
from collections.abc import Callable, Iterable
from contextlib import contextmanager

from domes.errors import InputError
from domes.execution.watch import (
    LOOK_EVERY,
    WORKER_TIMEOUT_VARIABLE,
    ClusterError,
    Watch,
    killed,
    lost_connection,
    worker_timeout,
)
from domes.results import Progress, Ticker

#: The environment variable naming an existing Dask scheduler.
SCHEDULER_VARIABLE = "DOMES_SCHEDULER"
#: A local cluster has at most this many workers per core of this machine.
MAX_WORKERS_PER_CORE = 4
#: Seconds to wait for a scheduler's answer before saying it does not answer.
SCHEDULER_TIMEOUT = 10
#: How often a task lost with its workers is sent again (Dask itself tries each ``allowed-failures`` + 1 times).
RESUBMIT = 2
#: Seconds to close a cluster whose workers are gone, before leaving it.
CLOSE_TIMEOUT = 10
#: What a lost run's message tells the user to do, unless the command knows better (e.g. a job folder).
RERUN = "run the command again (with fewer --workers, or none to run in this process)"
#: ... on an existing cluster.
RERUN_REMOTE = "run the command again once the cluster is back (or without --scheduler to run in this process)"


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
    """Runs tasks on a Dask cluster through ``client``; results come back in the items' order.

    A task lost with its workers runs again: Dask tries it on ``allowed-failures`` + 1 workers, then this
    executor sends it again, up to :data:`RESUBMIT` times (shared data lost with every copy is sent again
    first). A run without a live worker for :func:`~domes.execution.watch.worker_timeout` seconds ends in a
    :class:`~domes.execution.watch.ClusterError` that says what was lost and how to run the rest (``rerun``);
    ``progress`` hears of the tasks of every map not given a progress of its own.
    """

    def __init__(self, client, where: str, rerun: str = RERUN, progress: Progress | None = None):
        self.client = client
        self.where = where
        self.rerun = rerun
        self.progress = progress                # for the maps not given their own
        self._shared: dict = {}                 # key of a shared future -> (the future, its data), to send again

    @property
    def workers(self) -> int:
        return max(1, len(self._running() or ()))

    def share(self, data):
        """``data`` on every worker, once: a future that tasks' items may hold (Dask resolves it there)."""
        future = self._scatter(data)
        self._shared[future.key] = (future, data)
        return future

    def map(self, fn: Callable, items: Iterable, progress: Progress | None = None) -> list:
        items = list(items)
        out: list = [None] * len(items)
        for k, result in self._run(fn, items, progress):
            out[k] = result
        return out

    def completed(self, fn: Callable, items: Iterable, progress: Progress | None = None):
        """``(index, fn(item))`` for each item, in the order the tasks finish."""
        yield from self._run(fn, list(items), progress)

    def _run(self, fn: Callable, items: list, progress: Progress | None):
        """``(index, fn(item))`` as tasks finish; lost tasks run again; a :class:`ClusterError` past the deadline."""
        from distributed import as_completed

        if not items:
            return
        name = getattr(fn, "__name__", "task")
        progress = progress or self.progress
        watch = Watch(self._running, self.where, self.rerun)
        index: dict = {}                                       # a future's key -> its item's index
        rounds = [0] * len(items)
        pending: dict = {}                                     # futures not yet done, by key
        waiting = as_completed(loop=self.client.loop)

        def submit(ks):
            futures = self._guarded(lambda: self.client.map(fn, [items[k] for k in ks], pure=False))
            for k, future in zip(ks, futures):
                index[future.key] = k
                pending[future.key] = future
            waiting.update(futures)

        def again(k, why):
            """Run item ``k`` once more, or say why not."""
            rounds[k] += 1
            if rounds[k] > RESUBMIT:
                raise ClusterError(f"lost the workers of {self.where}: task {k + 1} of {len(items):,} ({name}) "
                                   f"{why}, {rounds[k]} times; {done:,} of {len(items):,} tasks done. "
                                   f"{_capital(self.rerun)}")
            watch.lost()
            items[k] = self._reshared(items[k])
            submit([k])

        done = 0
        clock, waits = Ticker(progress), Ticker(progress, every=2 * LOOK_EVERY)
        try:
            submit(range(len(items)))
            while pending:
                batch = self._ready(waiting)
                if not batch:
                    watch.look(done, len(items))
                    if watch.state():
                        waits.tick(lambda: f"{done:,}/{len(items):,} tasks done on {self.where}; {watch.state()}")
                    continue
                for future in batch:
                    key = future.key
                    k = index[key]
                    status = future.status
                    if status in ("pending", "lost"):          # its result was lost with a worker: computed again
                        waiting.add(future)
                        continue
                    del pending[key]
                    if status == "finished":
                        try:
                            result = future.result(timeout=watch.timeout)
                        except Exception as exc:  # noqa: BLE001 - its worker died while sending it
                            if not lost_connection(exc):
                                raise
                            future.release()
                            again(k, "could not be fetched from the worker that ran it")
                            continue
                        future.release()
                        done += 1
                        watch.progress()
                        yield k, result
                        clock.tick(lambda: f"{done:,}/{len(items):,} tasks done on {self.where}")
                    elif status == "error":
                        if not killed(future.exception()):
                            future.result()                    # the task's own error, raised as it was
                        future.release()
                        again(k, "was lost with every worker Dask ran it on (killed, or out of memory: the task "
                                 "may be what kills them)")
                    else:                                      # cancelled: its shared data or the scheduler lost
                        future.release()
                        if self.client.status != "running":
                            raise ClusterError(f"lost the scheduler of {self.where}: the connection to it closed, "
                                               f"and Dask cancelled the tasks; {done:,} of {len(items):,} tasks "
                                               f"done. {_capital(self.rerun)}")
                        if not self._lost_shared(items[k]):
                            raise ClusterError(f"the scheduler of {self.where} cancelled the tasks (restarted, or "
                                               f"told so by another client); {done:,} of {len(items):,} tasks done. "
                                               f"{_capital(self.rerun)}")
                        again(k, "lost the data it shares with the other tasks (every worker holding it died)")
        finally:
            if pending:                                        # stopped early or failed: the rest is not wanted
                try:
                    self.client.cancel(list(pending.values()))
                except Exception:  # noqa: BLE001,S110 - the cluster is gone already
                    pass

    @staticmethod
    def _ready(waiting) -> list:
        """The futures done now, or after a short wait (empty when none)."""
        with waiting.thread_condition:
            if not waiting.has_ready():
                waiting.thread_condition.wait(timeout=0.25)
        return waiting.next_batch(block=False)

    def _running(self) -> set | None:
        """The addresses of the workers that can run tasks; None when the scheduler does not answer."""
        if self.client.status not in ("running", "connecting"):
            return None
        try:
            info = self.client.sync(self.client.scheduler.identity, callback_timeout=SCHEDULER_TIMEOUT)
        except Exception:  # noqa: BLE001 - OSError, TimeoutError, CommClosedError: it does not answer
            return None
        return {address for address, w in info.get("workers", {}).items() if w.get("status", "running") == "running"}

    def _scatter(self, data):
        """``data`` sent to every worker; tried again while workers die under it, until the deadline."""
        timeout = worker_timeout()
        started = time.monotonic()
        while True:
            try:
                return self.client.scatter(data, broadcast=True, hash=False, timeout=timeout)
            except Exception as exc:
                if not lost_connection(exc):
                    raise
                if time.monotonic() - started > timeout:
                    raise ClusterError(f"lost the workers of {self.where}: none took the data the tasks share "
                                       f"within {timeout:g} s ({_said_briefly(exc)}). {_capital(self.rerun)}, or set "
                                       f"{WORKER_TIMEOUT_VARIABLE}=SECONDS to wait longer") from None
            time.sleep(LOOK_EVERY)

    def _guarded(self, call, what: str = "sending the tasks"):
        """``call()``; Dask's lost-connection errors said as a :class:`ClusterError`."""
        try:
            return call()
        except Exception as exc:
            if not lost_connection(exc):
                raise
            raise ClusterError(f"lost {self.where} while {what}: {_said_briefly(exc)}. {_capital(self.rerun)}") from None

    def _lost_shared(self, item) -> bool:
        return any(f.status != "finished" for f in _shared_futures(item, self._shared))

    def _reshared(self, item):
        """``item`` with every shared future lost with its workers sent again (each once)."""
        fresh = {}
        for key in {f.key for f in _shared_futures(item, self._shared)}:
            future, data = self._shared[key]
            if future.status != "finished":
                again = self._scatter(data)
                self._shared[again.key] = (again, data)
                self._shared[key] = (again, data)              # items still holding the old one get the new one
                fresh[key] = again
            elif future.key != key:
                fresh[key] = future
        return _swapped(item, fresh) if fresh else item


def _capital(text: str) -> str:
    return text[:1].upper() + text[1:]


def _said_briefly(exc: BaseException) -> str:
    """Dask's message of ``exc`` for a one-line error: its first 200 characters, no final full stop."""
    return (str(exc).strip().splitlines() or [type(exc).__name__])[0][:200].rstrip(".") or type(exc).__name__


def _shared_futures(item, shared: dict) -> list:
    """The shared futures ``item`` holds (in tuples, lists and dicts, as Dask finds them)."""
    from distributed import Future

    found = []
    stack = [item]
    while stack:
        obj = stack.pop()
        if isinstance(obj, Future):
            if obj.key in shared:
                found.append(obj)
        elif type(obj) in (tuple, list):
            stack.extend(obj)
        elif type(obj) is dict:
            stack.extend(obj.values())
    return found


def _swapped(obj, fresh: dict):
    """``obj`` with the futures whose keys ``fresh`` names replaced by ``fresh[key]``."""
    from distributed import Future

    if isinstance(obj, Future):
        return fresh.get(obj.key, obj)
    if type(obj) in (tuple, list):
        return type(obj)(_swapped(o, fresh) for o in obj)
    if type(obj) is dict:
        return {k: _swapped(v, fresh) for k, v in obj.items()}
    return obj


def check_workers(workers: int | None = None, scheduler: str | None = None) -> str | None:
    """Refuse knobs no executor can run with, before any work starts; returns the scheduler to use (the knob, or
    ``DOMES_SCHEDULER``)."""
    scheduler = scheduler or os.environ.get(SCHEDULER_VARIABLE) or None
    worker_timeout()                                       # a bad DOMES_WORKER_TIMEOUT is refused before the run
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
def executor(workers: int | None = None, scheduler: str | None = None, rerun: str | None = None,
             progress: Progress | None = None):
    """The executor for the knobs (see the module's doc); the cluster it starts is closed on exit. ``rerun``:
    what a :class:`ClusterError` tells the user to do (default :data:`RERUN`, :data:`RERUN_REMOTE` on an existing
    cluster); ``progress``: told of the cluster's start and of the tasks of every map not given a progress of its
    own."""
    scheduler = check_workers(workers, scheduler)
    if scheduler is None and (workers is None or workers == 1):
        yield InProcess()
        return
    try:
        from distributed import Client, LocalCluster
    except ImportError:                                    # pragma: no cover - dask is a dependency
        raise InputError("parallel runs need Dask: pip install 'distributed'") from None
    if scheduler is not None:
        rerun = rerun or RERUN_REMOTE
        if progress is not None:
            progress(f"connecting to the Dask scheduler at {scheduler}")
        client = _connect(Client, scheduler)
        where = f"the Dask cluster at {scheduler}"
        with _quiet_dask() as closed:          # a lost connection is said as a ClusterError, not in Dask's log
            try:
                with _said(where, rerun):
                    yield DaskExecutor(client, where, rerun, progress)
            finally:
                _close(client, closed=closed)
        return
    import dask

    rerun = rerun or RERUN
    where = f"a local Dask cluster of {workers} workers"
    if progress is not None:
        progress(f"starting {where}")
    # The scheduler runs here: no INFO lines on stderr, and a worker's death (a nanny's warning, the scheduler's
    # "marked as failed") is said as a ClusterError when the run cannot go on, not in Dask's log.
    with _quiet_dask() as closed:
        # Dask's workers return freed memory to the system from 64 kB up (MALLOC_TRIM_THRESHOLD_). Setting any value
        # turns off glibc's adaptive thresholds: the atlas, which makes and drops millions of small graphs, ran at
        # half speed, and numpy's large temporaries were mapped and unmapped on every operation (the kernel at a
        # third of its speed). Unset, the workers allocate as this process does.
        try:
            with dask.config.set({"distributed.nanny.pre-spawn-environ.MALLOC_TRIM_THRESHOLD_": None}):
                # Workers log only what is critical: a task's error reaches the caller as its exception, and while
                # the cluster closes a worker's heartbeat can meet the closed scheduler and log a traceback that
                # means nothing.
                cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                                       dashboard_address=":0", silence_logs=logging.CRITICAL)
        except Exception as exc:  # noqa: BLE001 - RuntimeError("Nanny failed to start"), OSError, TimeoutError
            _collect_quietly()
            raise ClusterError(f"could not start {where}: {_said_briefly(exc)} (a worker process died while "
                               f"starting: killed, or out of memory?). {_capital(rerun)}") from None
        try:
            client = Client(cluster, set_as_default=False)
        except Exception as exc:  # noqa: BLE001 - OSError, TimeoutError: the scheduler here did not answer
            _close(None, cluster, closed)
            raise ClusterError(f"could not connect to {where}: {_said_briefly(exc)}. {_capital(rerun)}") from None
        try:
            with _said(where, rerun):
                yield DaskExecutor(client, where, rerun, progress)
        finally:
            _close(client, cluster, closed)                # the same race, on this side, while closing


@contextmanager
def _quiet_dask():
    """Dask's loggers (``distributed`` and each ``distributed.*`` its configuration set a level for) and those of
    its event loop (``tornado``, ``asyncio``) say only what is critical in the body. Their levels are put back
    after, unless a cluster could not be closed (it may still speak: of workers it cannot restart, say), except
    ``asyncio``'s: a task of the Dask client that failed when its workers were lost is reported ("Task exception
    was never retrieved", with a traceback) only when it is collected, after the body."""
    names = ["distributed", "tornado", "asyncio"] + [name for name in logging.root.manager.loggerDict
                                                     if name.startswith(("distributed.", "tornado."))]
    loggers = [logging.getLogger(name) for name in names]
    levels = [logger.level for logger in loggers]
    for logger in loggers:
        logger.setLevel(logging.CRITICAL)
    closed = _Closed()
    try:
        yield closed
    finally:
        if closed.cleanly:
            for name, logger, level in zip(names, loggers, levels):
                if name != "asyncio":
                    logger.setLevel(level)


class _Closed:
    """Whether every close in a :func:`_quiet_dask` body finished (:func:`_close` says when one did not)."""

    cleanly = True


@contextmanager
def _said(where: str, rerun: str):
    """Dask's lost-connection errors that reach the body (not through an executor's wait) as a ClusterError."""
    from distributed import KilledWorker
    from distributed.client import FutureCancelledError
    from distributed.comm.core import CommClosedError

    try:
        yield
    except (KilledWorker, CommClosedError, FutureCancelledError) as exc:
        raise ClusterError(f"lost {where}: {_said_briefly(exc)}. {_capital(rerun)}") from None


def _close(client, cluster=None, closed: _Closed | None = None) -> None:
    """Close the client (and the cluster this process started) within :data:`CLOSE_TIMEOUT` seconds; a cluster
    whose workers or scheduler are gone is left as it is (and ``closed.cleanly`` set False)."""
    for thing in (client, cluster):
        if thing is None:
            continue
        try:
            thing.close(timeout=CLOSE_TIMEOUT)
        except Exception:  # noqa: BLE001 - already gone, or not closing: nothing more to do here
            if closed is not None:
                closed.cleanly = False


__all__ = ["ClusterError", "DaskExecutor", "InProcess", "RERUN", "SCHEDULER_VARIABLE", "check_workers", "executor"]
