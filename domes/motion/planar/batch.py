"""Batches: many mechanisms of one topology over a grid of inputs, with a status for each.

:func:`batch` takes a template mechanism and arrays of its joint and point
coordinates (one row per mechanism, each row a drawn pose) and evaluates the
requested outputs of every mechanism at every input value with the kernel
(:mod:`domes.motion.planar.kernel`), a chunk of mechanisms at a time. Each
mechanism keeps its drawn assembly mode at every input (no continuation: for
branch points and located limits, sweep the mechanism); its status says
whether it assembles at every input (``complete``), meets a limit inside the
grid (``limit``: the values there are NaN), has an undetermined pose
somewhere (``undetermined``) or is drawn on a dead point (``ambiguous``: its
assembly mode is not defined). ``transmission`` is the smallest root of its
dyads over the inputs where it assembles: the sine of the worst transmission
angle for an RRR dyad, 0 at a singular (dead or change) point.

Memory: ``memory=`` (bytes) bounds the working arrays of a chunk. The bytes
one mechanism needs are measured on the first chunk (a probe of about
:data:`PROBE` configurations, with :mod:`tracemalloc`), and the later chunks
hold as many mechanisms as fit the budget (at most :data:`CHUNK`
configurations: larger chunks are slower). The measure counts the kernel's
arrays, the chunk's results and the sink's work on them (and anything
another thread allocates meanwhile: an estimate on the safe side). The
values do not depend on the chunking. Each finished chunk (a
:class:`Chunk`) goes to a *sink*: by default :class:`CollectSink`, which
keeps every value and gives the :class:`Batch` (``M × N`` values, so its
result is not bounded); :class:`ExtremesSink` keeps each mechanism's
extremes of each output (``O(M)``); :class:`domes.io.batchfile.HDF5Sink` writes each chunk to
an HDF5 file as it finishes (needs ``h5py``). With a sink given,
:func:`batch` returns a :class:`BatchRun` holding the sink's result.

>>> import numpy as np
>>> from domes.motion.planar.examples import four_bar
>>> cs = np.array([[3.5, 6 ** 0.5], [3.2, 2.0]])        # two positions of joint C
>>> b = batch(four_bar(), {"C": cs}, np.radians(np.arange(0, 360, 90)), outputs=["angle:rocker"])
>>> b.kinds.tolist(), b.values["angle:rocker"].shape
(['complete', 'complete'], (2, 4))
>>> round(float(np.degrees(b.values["angle:rocker"][0, 0])), 6)
78.463041
>>> run = batch(four_bar(), {"C": cs}, np.radians(np.arange(0, 360, 90)), outputs=["angle:rocker"],
...             sink=ExtremesSink())
>>> run.counts, run.result.argmax["angle:rocker"].tolist()
({'complete': 2}, [3, 2])
"""

from __future__ import annotations

import math
import numbers
import tracemalloc
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.planar import compiled, reduce
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import Kinematics
from domes.results import Progress, Result, Status, Ticker

#: Default budget of a chunk's working arrays, bytes (256 MiB).
MEMORY = 256 << 20
#: Configurations (mechanisms × inputs) of the first chunk, on which the bytes per mechanism are measured.
PROBE = 4096
#: Most configurations evaluated at once, whatever the budget. Larger chunks run slower (the working arrays leave
#: the cache; ``benchmarks/bench_batch_memory.py``), and below it no complex array reaches numpy's 256 KiB
#: threshold for reusing temporaries, which swaps the operands of a product and, with fused multiply-adds, can
#: change its last bit: so the values do not depend on the chunking.
CHUNK = (1 << 14) - 1
#: The same for the compiled route (:mod:`~domes.motion.planar.compiled`): one loop per chunk, no temporaries,
#: so larger chunks only spread the fixed cost of a chunk further (values are the same whatever the chunking).
COMPILED_CHUNK = 1 << 17
#: The same for a compiled reduction to extremes (:mod:`~domes.motion.planar.reduce`): no array of the chunk's
#: configurations at all, so a chunk only bounds the geometry tables and the time between progress reports.
REDUCE_CHUNK = 1 << 20
#: The kinds of status, in the order they are reported.
KINDS = ("complete", "limit", "undetermined", "ambiguous")


@dataclass(frozen=True, eq=False)
class Batch(Result):
    """Outputs of ``M`` mechanisms at ``N`` inputs, with a status per mechanism.

    ``values[column]`` is ``(M, N)`` (NaN where the mechanism does not
    assemble); ``assembled`` the ``(M, N)`` mask; ``kinds`` each mechanism's
    status (``complete``, ``limit``, ``undetermined``, ``ambiguous``);
    ``transmission`` its smallest dyad root (0 = singular, 1 = best);
    ``residual`` its largest loop-closure error relative to its size.
    ``chunk`` is the mechanisms evaluated at once (after the probe chunk),
    ``per_mechanism`` the measured working bytes of one mechanism (0 when
    the chunk was given or the batch fit in the first chunk).
    """

    mechanism: str
    joint: str
    inputs: np.ndarray
    values: dict
    assembled: np.ndarray
    kinds: np.ndarray
    transmission: np.ndarray
    residual: np.ndarray
    status: Status = Status.COMPLETE
    chunk: int = 0
    per_mechanism: int = 0

    @property
    def count(self) -> int:
        return int(self.kinds.size)

    @property
    def message(self) -> str:
        kinds, counts = np.unique(self.kinds, return_counts=True)
        summary = ", ".join(f"{c:,} {k}" for k, c in zip(kinds, counts))
        worst = float(np.nanmax(self.residual)) if self.residual.size else 0.0
        return (f"{self.status}: {self.count:,} mechanisms ({self.mechanism}) × {self.inputs.size:,} inputs of "
                f"{self.joint}: {summary}; max residual {worst:.2g}")

    def limits(self, m: int) -> list[tuple[float, float]]:
        """The input intervals of the grid in which mechanism ``m`` meets a limit (assembles on one side only)."""
        ok = self.assembled[m]
        change = np.flatnonzero(ok[1:] != ok[:-1])
        return [(float(self.inputs[k]), float(self.inputs[k + 1])) for k in change]


@dataclass(frozen=True)
class Plan:
    """What a sink is told before the first chunk: the batch's shape and columns."""

    mechanism: str
    joint: str
    inputs: np.ndarray
    count: int
    columns: tuple


@dataclass(frozen=True, eq=False)
class Chunk:
    """The mechanisms ``lo .. hi − 1`` of a batch, finished: the rows of :class:`Batch`'s arrays for them.

    ``kinds`` is an array of the status names (str).
    """

    lo: int
    hi: int
    values: dict
    assembled: np.ndarray
    kinds: np.ndarray
    transmission: np.ndarray
    residual: np.ndarray


class CollectSink:
    """Keep every value: the default sink; its result is the :class:`Batch`."""

    def start(self, plan: Plan) -> None:
        m, n = plan.count, plan.inputs.size
        self.plan = plan
        self.values = {c: np.empty((m, n)) for c in plan.columns}
        self.assembled = np.zeros((m, n), dtype=bool)
        self.kinds = np.empty(m, dtype=object)
        self.transmission = np.full(m, np.nan)
        self.residual = np.zeros(m)

    def accept(self, c: Chunk) -> None:
        for col, val in c.values.items():
            self.values[col][c.lo:c.hi] = val
        self.assembled[c.lo:c.hi] = c.assembled
        self.kinds[c.lo:c.hi] = c.kinds
        self.transmission[c.lo:c.hi] = c.transmission
        self.residual[c.lo:c.hi] = c.residual

    def finish(self) -> Batch:
        p = self.plan
        return Batch(p.mechanism, p.joint, p.inputs, self.values, self.assembled, self.kinds.astype(str),
                     self.transmission, self.residual)


@dataclass(frozen=True, eq=False)
class Extremes(Result):
    """Each mechanism's extremes of each output column over the inputs where it assembles.

    ``minimum[column]``, ``maximum[column]`` are ``(M,)`` (NaN for a
    mechanism that assembles nowhere); ``argmin``, ``argmax`` the index of
    the input where each is reached (the first, on a tie; −1 where none);
    ``kinds``, ``transmission``, ``residual`` as in :class:`Batch`.
    """

    inputs: np.ndarray
    minimum: dict
    maximum: dict
    argmin: dict
    argmax: dict
    kinds: np.ndarray
    transmission: np.ndarray
    residual: np.ndarray
    status: Status = Status.COMPLETE

    @property
    def message(self) -> str:
        return f"{self.status}: extremes of {len(self.minimum)} columns over {self.kinds.size:,} mechanisms"

    def at_minimum(self, column: str) -> np.ndarray:
        """The input value at which each mechanism's ``column`` is smallest (NaN where none)."""
        return _at(self.inputs, self.argmin[column])

    def at_maximum(self, column: str) -> np.ndarray:
        """The input value at which each mechanism's ``column`` is largest (NaN where none)."""
        return _at(self.inputs, self.argmax[column])


def _at(inputs, index):
    return np.where(index >= 0, inputs[np.maximum(index, 0)], np.nan)


class ExtremesSink:
    """Reduce each chunk to per-mechanism extremes (:class:`Extremes`): ``O(M)`` memory, not ``O(M·N)``."""

    def start(self, plan: Plan) -> None:
        m, k = plan.count, len(plan.columns)
        self.plan = plan
        self.table = (np.full((k, m), np.nan), np.full((k, m), np.nan), np.full((k, m), -1, dtype=np.int64),
                      np.full((k, m), -1, dtype=np.int64))  # one row per column: the fused loop fills them at once
        self.minimum, self.maximum, self.argmin, self.argmax = (dict(zip(plan.columns, t)) for t in self.table)
        self.kinds = np.empty(m, dtype=f"U{max(map(len, KINDS))}")
        self.transmission = np.full(m, np.nan)
        self.residual = np.zeros(m)

    def accept(self, c: Chunk) -> None:
        rows = np.arange(c.hi - c.lo)
        for col, val in c.values.items():
            if compiled.loaded():  # the same reduction in one compiled pass
                compiled.extremes(val, c.lo, self.minimum[col], self.maximum[col], self.argmin[col], self.argmax[col])
                continue
            bad = np.isnan(val)
            some = ~bad.all(axis=1)
            for best, where, fill, pick in ((self.minimum, self.argmin, np.inf, np.argmin),
                                            (self.maximum, self.argmax, -np.inf, np.argmax)):
                k = pick(np.where(bad, fill, val), axis=1)
                best[col][c.lo:c.hi] = np.where(some, val[rows, k], np.nan)
                where[col][c.lo:c.hi] = np.where(some, k, -1)
        self.kinds[c.lo:c.hi] = c.kinds
        self.transmission[c.lo:c.hi] = c.transmission
        self.residual[c.lo:c.hi] = c.residual

    def finish(self) -> Extremes:
        return Extremes(self.plan.inputs, self.minimum, self.maximum, self.argmin, self.argmax,
                        self.kinds, self.transmission, self.residual)


@dataclass(frozen=True, eq=False)
class BatchRun(Result):
    """A batch handed to a sink: the status counts, the largest residual, the chunking, and the sink's ``result``."""

    mechanism: str
    joint: str
    inputs: np.ndarray
    counts: dict
    residual: float
    chunk: int
    per_mechanism: int
    result: object = field(repr=False)
    status: Status = Status.COMPLETE

    @property
    def count(self) -> int:
        return sum(self.counts.values())

    @property
    def message(self) -> str:
        summary = ", ".join(f"{c:,} {k}" for k, c in self.counts.items())
        return (f"{self.status}: {self.count:,} mechanisms ({self.mechanism}) × {self.inputs.size:,} inputs of "
                f"{self.joint}: {summary}; max residual {self.residual:.2g}; chunks of {self.chunk:,}")


def batch(mech: Mechanism, coordinates=None, inputs=None, outputs=None, order: int = 0, joint: str | None = None,
          directions=None, progress: Progress | None = None, memory: int = MEMORY, chunk: int | None = None,
          sink=None, route: str | None = None):
    """Evaluate ``outputs`` (up to derivative ``order``) of many mechanisms of ``mech``'s topology at ``inputs``.

    ``coordinates`` maps joint and point names to ``(M, 2)`` arrays (the
    drawn pose of each mechanism; names not given keep ``mech``'s
    coordinates), ``directions`` P joints to ``(M,)`` slide angles;
    ``inputs`` are values of ``joint`` (default: the first input; rad or
    length). Other inputs stay at each mechanism's drawn values. The
    mechanism must consist of drivers and dyads.

    ``memory`` (bytes) bounds a chunk's working arrays: the first chunk
    (about :data:`PROBE` configurations) is measured unless it is the whole
    batch, and later chunks hold
    ``memory // per_mechanism`` mechanisms (at least one; at most
    :data:`CHUNK` configurations, for speed). ``chunk`` fixes
    the mechanisms per chunk instead (no probe). Without ``sink`` the result
    is the :class:`Batch` (every value kept, on top of the budget); with a
    sink (an object with ``start(plan)``, ``accept(chunk)``, ``finish()``
    and optionally ``abort()``), a :class:`BatchRun` whose ``result`` is
    what ``sink.finish()`` returned. Chunking does not change any value.

    ``route`` (``numpy``, ``numba`` or ``auto``; default ``$DOMES_KERNEL``,
    else ``auto``) chooses how the kernel runs
    (:func:`~domes.motion.planar.compiled.choose`): ``auto`` compiles a batch
    of at least :data:`~domes.motion.planar.compiled.THRESHOLD`
    configurations when numba is installed. Both routes give the same numbers
    to rounding.
    """
    kin = Kinematics(mech, outputs, order)
    prog = Program(kin, route)
    joint = joint or mech.inputs[0].joint
    if joint not in kin.inputs:
        raise InputError(f"{joint!r} is not a driven joint of {mech.name}; inputs are {sorted(kin.inputs)}")
    if inputs is None:
        raise InputError("batch: give the input values (an array of angles in rad, or of slides)")
    qs = np.asarray(inputs, dtype=float)
    if qs.ndim != 1 or not qs.size or not np.all(np.isfinite(qs)):
        raise InputError(f"batch inputs must be a 1-D array of finite numbers, got shape {qs.shape}")
    if chunk is not None and (isinstance(chunk, bool) or not isinstance(chunk, numbers.Real) or int(chunk) != chunk
                              or chunk < 1):
        raise InputError(f"batch chunk must be a whole number of mechanisms ≥ 1, got {chunk!r}")
    if isinstance(memory, bool) or not (isinstance(memory, numbers.Real) and math.isfinite(memory) and memory > 0):
        raise InputError(f"batch memory must be a positive number of bytes, got {memory!r}")
    geom = prog.geometry(coordinates, directions)
    total = geom.count or 1
    n = qs.size
    fast = compiled.Tape.of(prog) is not None and compiled.choose(total * n, route)
    prog.route = "numba" if fast else "numpy"
    prog.scratch = True  # each chunk's poses are used up before the next chunk: the compiled route reuses its arrays
    if fast:
        compiled.warm()  # numba's import and cache load, before the probe measures a chunk's memory
    table = reduce.spec(prog) if fast and type(sink) is ExtremesSink else None
    if table is not None:
        reduce.warm()
    cap = REDUCE_CHUNK if table is not None else COMPILED_CHUNK if fast else CHUNK
    columns = tuple(name + "'" * k for o in kin.outputs for k in range(order + 1) for name in o.columns())
    plan = Plan(mech.name, joint, qs, total, columns)
    collect = sink is None
    sink = CollectSink() if collect else sink
    size = _sizes(geom, total)
    clock = Ticker(progress)
    counts = dict.fromkeys(KINDS, 0)
    worst = [0.0]

    codes = np.zeros(total if table is not None else 0, dtype=np.int64)

    def step(g, lo, hi):
        if table is not None:  # placed and reduced in one compiled loop: no chunk of positions
            ambiguous = _ambiguous(g, hi - lo)
            reduce.extremes(prog, table, g, qs, joint, ambiguous, size[lo:hi], lo, *sink.table, codes,
                            sink.transmission, sink.residual)
            for k, m in enumerate(np.bincount(codes[lo:hi], minlength=len(KINDS)).tolist()):
                counts[KINDS[k]] += m
            sink.kinds[lo:hi] = np.array(KINDS)[codes[lo:hi]]
            worst[0] = max(worst[0], float(np.nanmax(sink.residual[lo:hi])))
            return
        c = _evaluate(prog, g, qs, joint, order, size[lo:hi], lo, hi)
        names, k = np.unique(c.kinds, return_counts=True)
        for name, m in zip(names.tolist(), k.tolist()):
            counts[name] += m
        if c.residual.size:
            worst[0] = max(worst[0], float(np.nanmax(c.residual)))
        sink.accept(c)

    per = 0
    rows = int(chunk) if chunk is not None else max(1, min(total, PROBE // n))
    sink.start(plan)
    try:
        lo = 0
        while lo < total:
            hi = min(lo + rows, total)
            clock.tick(lambda: f"mechanisms {lo:,}/{total:,}")
            g = geom.rows(lo, hi) if geom.count is not None else geom
            if chunk is None and lo == 0 and hi < total:  # the probe: measure the working bytes of one mechanism
                per = _measured(lambda: step(g, lo, hi), hi - lo)
                rows = max(1, min(total, int(memory // per), cap // n))
            else:
                step(g, lo, hi)
            lo = hi
    except BaseException:
        if hasattr(sink, "abort"):
            sink.abort()
        raise
    result = sink.finish()
    if collect:
        return Batch(result.mechanism, result.joint, result.inputs, result.values, result.assembled, result.kinds,
                     result.transmission, result.residual, chunk=rows, per_mechanism=per)
    return BatchRun(mech.name, joint, qs, {k: c for k, c in counts.items() if c}, worst[0], rows, per, result)


def _measured(work, rows: int) -> int:
    """Run ``work`` under :mod:`tracemalloc`; the peak bytes it allocated, per mechanism (of ``rows``)."""
    was = tracemalloc.is_tracing()
    if not was:
        tracemalloc.start()
    try:
        base = tracemalloc.get_traced_memory()[0]
        tracemalloc.reset_peak()
        work()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        if not was:
            tracemalloc.stop()
    return max(1, math.ceil((peak - base) / rows))


def _evaluate(prog, g, qs, joint, order, size, lo, hi) -> Chunk:
    """The mechanisms ``lo .. hi − 1`` (geometry ``g``, sizes ``size``) at the inputs ``qs``: one :class:`Chunk`."""
    n = qs.size
    pose = prog.poses(g, qs[None, :], joint)
    shape = (hi - lo, n)
    ambiguous = _ambiguous(g, hi - lo)
    done = None if order or getattr(pose, "raw", None) is None else \
        compiled.Tape.of(prog).finish(pose, prog.kin.outputs, ambiguous, size)
    if done is not None:
        values, ok, kinds, transmission, residual = done
        return Chunk(lo, hi, values, ok, np.array(KINDS)[kinds], transmission, residual)
    limit = np.zeros(shape, dtype=bool)
    undetermined = np.zeros(shape, dtype=bool)
    for index in pose.unassembled:
        limit |= np.broadcast_to(pose.unassembled[index], shape)
        undetermined |= np.broadcast_to(pose.undetermined[index], shape)
    ok = ~(limit | undetermined)
    ok &= ~ambiguous[:, None]
    kinds = np.where(ambiguous, "ambiguous", np.where(undetermined.any(axis=1), "undetermined",
                                                      np.where(ok.all(axis=1), "complete", "limit")))
    transmission = np.full(hi - lo, np.nan)
    if pose.root:
        roots = np.min([np.broadcast_to(r, shape) for r in pose.root.values()], axis=0)
        transmission = np.min(np.where(ok, roots, np.inf), axis=1)
        transmission[~np.isfinite(transmission)] = np.nan
    residual = np.zeros(hi - lo)
    if pose.closure:
        closure = np.max([np.broadcast_to(c, shape) for c in pose.closure.values()], axis=0)
        residual = np.max(np.where(ok, closure, 0.0), axis=1) / size
    values = {}
    with np.errstate(invalid="ignore", over="ignore"):  # configurations that do not assemble are NaN anyway
        levels = prog.motion(g, pose, order) if order else []
        for col, val in prog.outputs(g, pose, levels).items():
            values[col] = np.where(ok, val, np.nan)
    return Chunk(lo, hi, values, ok, kinds, transmission, residual)


def _ambiguous(g, rows) -> np.ndarray:
    """Which of the ``rows`` mechanisms of geometry ``g`` are drawn on a dead point (a dyad's sign is 0)."""
    ambiguous = np.zeros(rows, dtype=bool)
    for sign in g.sign.values():
        ambiguous |= np.broadcast_to(np.asarray(sign) == 0, (rows, 1))[:, 0]
    return ambiguous


def _sizes(geom, total) -> np.ndarray:
    """Each mechanism's size: the largest distance between two of its joints or points."""
    pts = list(geom.at.values())
    best = np.zeros(total)
    for i, p in enumerate(pts):
        for q in pts[i + 1:]:
            best = np.maximum(best, np.broadcast_to(np.abs(p - q), (total, 1))[:, 0])
    return np.where(best > 0, best, 1.0)


__all__ = ["Batch", "BatchRun", "Chunk", "CollectSink", "Extremes", "ExtremesSink", "MEMORY", "Plan",
           "batch"]
