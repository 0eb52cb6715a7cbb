"""Bounded batches (issue 28, item 3): a memory budget sizes the chunks, sinks take each finished chunk.

The reduction sink's extremes equal those of the full ``Batch``; chunking changes no value; the HDF5 sink writes
the same numbers atomically; the extremes of a crank-rocker's rocker angle sit at the limit positions where crank
and coupler are collinear (seed 001, RSSR digest: "β̇ = 0, i.e. the rocker is at one of its extreme (limit)
positions", the planar four-bar being the RSSR with parallel axes).
"""

from __future__ import annotations

import math
import os

import numpy as np
import pytest

from domes.errors import InputError
from domes.io.batchfile import HDF5Sink
from domes.motion import CouplerPoint, Input, Joint, Mechanism
from domes.motion.planar.batch import CHUNK, BatchRun, CollectSink, ExtremesSink, batch
from domes.motion.planar.checks import grashof

TEMPLATE = Mechanism.build("fb", ["f", "crank", "coupler", "rocker"], "f",
                           [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"), (1.0, 0.0)),
                            Joint("C", "R", ("coupler", "rocker"), (3.5, math.sqrt(6.0))),
                            Joint("D", "R", ("rocker", "f"), (3.0, 0.0))],
                           [Input("A", 2.0, 0.5)], points=[CouplerPoint("P", "coupler", (2.0, 2.0))])
OUTPUTS = ["point:P", "angle:rocker"]


def _four_bars(count, seed, dead=0):
    """Random four-bars (about a tenth meet a limit), the last ``dead`` drawn on a dead point (assemble nowhere)."""
    rng = np.random.default_rng(seed)
    c = {"B": np.c_[rng.uniform(0.5, 1.5, count), rng.uniform(-0.4, 0.4, count)],
         "C": np.c_[rng.uniform(2.5, 4.0, count), rng.uniform(1.5, 3.0, count)],
         "D": np.c_[rng.uniform(2.5, 3.5, count), np.zeros(count)],
         "P": np.c_[rng.uniform(0.0, 4.0, count), rng.uniform(0.0, 4.0, count)]}
    if dead:
        c["B"][-dead:, 1] = 0.0  # B, D, C on the x axis: collinear, exactly
        c["C"][-dead:] = c["D"][-dead:] + [0.7, 0.0]
    return c


def _same(a, b):
    assert a.dtype.kind == b.dtype.kind and a.shape == b.shape
    assert np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def test_extremes_sink_equals_the_full_batch():
    # 3,000 random four-bars (complete, limit, and 20 that assemble nowhere) × 72 inputs, order 1; a small budget
    # so that the reduction runs over many chunks. Extremes and their inputs equal numpy's nan-reductions of the
    # collected Batch (the first index on a tie), the statuses and their counts too.
    coords = _four_bars(3000, 7, dead=20)
    qs = np.radians(np.arange(0.0, 360.0, 5.0))
    full = batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=1)
    run = batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=1, memory=1 << 20, sink=ExtremesSink())
    assert isinstance(run, BatchRun) and run.success and run.chunk < 3000
    ex = run.result
    kinds, counts = np.unique(full.kinds, return_counts=True)
    assert run.counts == dict(zip(kinds.tolist(), counts.tolist())) and run.count == 3000
    assert {"complete", "limit", "ambiguous"} <= set(run.counts) and run.counts["ambiguous"] == 20
    assert ex.kinds.tolist() == full.kinds.tolist()
    _same(ex.transmission, full.transmission)
    _same(ex.residual, full.residual)
    assert run.residual == np.nanmax(full.residual)
    some = ~np.isnan(full.values["point:P.x"]).all(axis=1)
    assert (~some).sum() == 20
    for col, v in full.values.items():
        assert np.array_equal(ex.minimum[col][some], np.nanmin(v[some], axis=1))  # equal, not only to 1e-15
        assert np.array_equal(ex.maximum[col][some], np.nanmax(v[some], axis=1))
        assert np.array_equal(ex.argmin[col][some], np.nanargmin(v[some], axis=1))
        assert np.array_equal(ex.argmax[col][some], np.nanargmax(v[some], axis=1))
        assert np.isnan(ex.minimum[col][~some]).all() and (ex.argmax[col][~some] == -1).all()
    at = ex.at_maximum("angle:rocker")
    assert np.array_equal(at[some], qs[ex.argmax["angle:rocker"][some]]) and np.isnan(at[~some]).all()


def test_chunking_changes_no_value():
    # Chunks of 1, 7 and the default (one probe chunk, then by the budget) give bit-identical arrays, order 2.
    coords = _four_bars(1000, 8, dead=3)
    qs = np.radians(np.arange(0.0, 360.0, 10.0))
    runs = [batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=2, chunk=k) for k in (1, 7, None)]
    assert [r.chunk for r in runs[:2]] == [1, 7] and runs[2].per_mechanism > 0
    ref = runs[2]
    assert len(ref.values) == 9 and ref.chunk == 455
    for r in runs[:2]:
        assert r.kinds.tolist() == ref.kinds.tolist()
        _same(r.assembled, ref.assembled)
        _same(r.transmission, ref.transmission)
        _same(r.residual, ref.residual)
        for col in ref.values:
            _same(r.values[col], ref.values[col])
    # the default sink handed in explicitly is the same Batch, inside a BatchRun
    again = batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=2, chunk=7, sink=CollectSink())
    assert again.counts == {k: int((ref.kinds == k).sum()) for k in again.counts}
    for col in ref.values:
        _same(again.result.values[col], ref.values[col])


def test_the_budget_sets_the_chunk():
    # The measured bytes per mechanism hold at least the chunk's own output arrays (columns × N doubles and the
    # N-byte mask) and, for this closed-form kernel, are within a small multiple of them; the chunk is the budget
    # over them, capped at CHUNK configurations, at least one mechanism.
    coords = _four_bars(400, 9)
    qs = np.radians(np.arange(0.0, 360.0, 1.0))
    for order, columns in ((0, 3), (2, 9)):
        small = batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=order, memory=2 << 20, sink=ExtremesSink())
        floor = qs.size * (8 * columns + 1)
        assert floor <= small.per_mechanism <= 40 * floor, (order, small.per_mechanism / floor)
        assert small.chunk == (2 << 20) // small.per_mechanism
        assert batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=order).chunk == CHUNK // qs.size
        assert batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=order, memory=1, sink=ExtremesSink()).chunk == 1


def test_rocker_extremes_are_at_the_collinear_positions():
    # Independent check of the reduction: for every crank-rocker (Grashof, crank shortest) the rocker angle is
    # extreme where crank and coupler are collinear, |AC| = l2 ± l1. Closed form: C on the circles (A, l2 ± l1) and
    # (D, l4) on the side of AD of the drawn assembly mode; the swing is the angle between the two positions of DC,
    # and the grid's extremes (0.25° steps) lie within a step of the crank angles there (55 crank-rockers of 60).
    coords = _four_bars(60, 10)
    h = math.radians(0.25)
    qs = np.arange(0.0, 2 * math.pi, h)
    run = batch(TEMPLATE, coords, qs, outputs=["angle:rocker"], sink=ExtremesSink())
    ex = run.result
    checked = 0
    for m in range(60):
        b0, c0, d = (complex(*coords[k][m]) for k in "BCD")
        mech = Mechanism.build("fb", ["f", "crank", "coupler", "rocker"], "f",
                               [Joint("A", "R", ("f", "crank"), (0.0, 0.0)), Joint("B", "R", ("crank", "coupler"),
                                                                                  (b0.real, b0.imag)),
                                Joint("C", "R", ("coupler", "rocker"), (c0.real, c0.imag)),
                                Joint("D", "R", ("rocker", "f"), (d.real, d.imag))], [Input("A")])
        g = grashof(mech)
        if not g.input_rotates or g.kind != "crank-rocker":
            continue
        l1, l2, l4 = abs(b0), abs(c0 - b0), abs(c0 - d)
        side = np.sign(((c0 - b0).conjugate() * (d - b0)).imag)  # the assembly mode: the side of BC that D is on
        limits = []
        for r, flip in ((l1 + l2, 1.0), (l2 - l1, -1.0)):
            a = (r * r - l4 * l4 + abs(d) ** 2) / (2 * abs(d))  # C = A + a u + h n along and across AD
            k = math.sqrt(r * r - a * a)
            u = d / abs(d)
            for c in (a * u + k * 1j * u, a * u - k * 1j * u):
                if np.sign((c.conjugate() * d).imag) == side:  # B on AC: the side of AC that D is on
                    crank = math.atan2((flip * c).imag, (flip * c).real)
                    limits.append((c, crank % (2 * math.pi)))
        (ce, te), (cf, tf) = limits
        swing = abs(math.remainder(math.atan2((ce - d).imag, (ce - d).real) - math.atan2((cf - d).imag, (cf - d).real),
                                   2 * math.pi))
        col = "angle:rocker"
        grid = ex.maximum[col][m] - ex.minimum[col][m]
        assert -1e-5 <= grid - swing <= 1e-12, m  # a grid's extremes lie inside the true ones, by O(step²)
        got = sorted([ex.at_maximum(col)[m], ex.at_minimum(col)[m]])
        for t in (te, tf):
            assert min(abs(math.remainder(t - x, 2 * math.pi)) for x in got) <= h, m
        checked += 1
    assert checked >= 40


def test_hdf5_sink_writes_the_batch_atomically(tmp_path):
    h5py = pytest.importorskip("h5py")
    coords = _four_bars(500, 11, dead=4)
    qs = np.radians(np.arange(0.0, 360.0, 6.0))
    path = tmp_path / "batch.h5"
    full = batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=1)
    run = batch(TEMPLATE, coords, qs, outputs=OUTPUTS, order=1, chunk=64, sink=HDF5Sink(path))
    assert run.result == str(path) and os.listdir(tmp_path) == ["batch.h5"]
    with h5py.File(path, "r") as f:
        assert f.attrs["mechanism"] == "fb" and f.attrs["joint"] == "A"
        _same(f["inputs"][:], qs)
        assert sorted(f["values"]) == sorted(full.values)
        for col, v in full.values.items():
            _same(f["values"][col][:], v)
        _same(f["assembled"][:], full.assembled)
        assert f["kinds"][:].astype(str).tolist() == full.kinds.tolist()
        _same(f["transmission"][:], full.transmission)

    class Failing(HDF5Sink):
        def accept(self, c):
            if c.lo >= 128:
                raise RuntimeError("disk full")
            super().accept(c)

    before = path.read_bytes()
    with pytest.raises(RuntimeError, match="disk full"):
        batch(TEMPLATE, coords, qs, outputs=OUTPUTS, chunk=64, sink=Failing(path))
    assert os.listdir(tmp_path) == ["batch.h5"] and path.read_bytes() == before  # no temporary left, old file kept
    with pytest.raises(InputError, match="does not exist"):
        batch(TEMPLATE, coords, qs, outputs=OUTPUTS, sink=HDF5Sink(tmp_path / "no" / "x.h5"))


def test_bad_budgets_are_refused():
    coords = _four_bars(3, 12)
    for kw, match in (({"memory": 0}, "memory"), ({"memory": math.nan}, "memory"), ({"chunk": 0}, "chunk"),
                      ({"chunk": 2.5}, "chunk")):
        with pytest.raises(InputError, match=match):
            batch(TEMPLATE, coords, [0.0], **kw)
