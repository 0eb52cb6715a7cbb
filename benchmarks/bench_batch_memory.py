"""Peak memory and speed of bounded batches (issue 28, item 3).

Run ``python benchmarks/bench_batch_memory.py``. Each case runs in a fresh
Python process (so ``ru_maxrss``, the peak resident set, is the case's own):
random four-bars (``bench_kernel.random_four_bars``) × 360 inputs, the
positions of a coupler point, through :func:`domes.motion.planar.batch.batch`
with a sink:

- ``extremes``: :class:`~domes.motion.planar.batch.ExtremesSink`, per-mechanism
  extremes (O(M) memory), default 10^6 four-bars (compiled: placed and reduced
  in one loop, :mod:`domes.motion.planar.reduce`);
- ``positions`` (with ``--positions``): the same extremes reduced from each
  chunk's positions (the compiled route without that loop), beside it;
- ``collect``: the default (every value kept, the ``Batch``), default 10^5;
- ``hdf5``: :class:`~domes.io.batchfile.HDF5Sink` into a temporary
  folder (when ``h5py`` is installed), default 10^5.

For each: the peak resident memory, the resident memory before the batch
(Python, numpy and the drawn coordinates), the CPU time and positions per
CPU second (with numba's import and cache load when the batch is compiled),
the route the kernel took, the chunk (mechanisms at once) and the measured
working bytes per mechanism. ``--kernel`` picks the route. ``--chunks`` adds
a table of speed against the chunk size (extremes, 10^5 four-bars, two fresh
processes each), the measurement behind :data:`~domes.motion.planar.batch.CHUNK`.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from bench_kernel import four_bar_template, random_four_bars  # noqa: E402

from domes.io.batchfile import HDF5Sink  # noqa: E402
from domes.motion.planar import compiled  # noqa: E402
from domes.motion.planar.batch import MEMORY, ExtremesSink, batch  # noqa: E402

INPUTS = 360


class PositionsSink(ExtremesSink):
    """Extremes reduced from each chunk's positions: ``batch`` takes its fused loop for ``ExtremesSink`` only."""


def _rss_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024  # kB on Linux


def child(sink: str, count: int, memory: int, chunk: int | None) -> dict:
    """One case, in this process: the numbers as a dict."""
    coords = random_four_bars(count)
    qs = np.radians(np.arange(float(INPUTS)))
    before = _rss_mib()
    folder = tempfile.mkdtemp() if sink == "hdf5" else None
    kw = {"memory": memory, "chunk": chunk}
    if sink == "extremes":
        kw["sink"] = ExtremesSink()
    elif sink == "positions":
        kw["sink"] = PositionsSink()
    elif sink == "hdf5":
        kw["sink"] = HDF5Sink(os.path.join(folder, "batch.h5"))
    t = time.process_time()
    w = time.perf_counter()
    out = batch(four_bar_template(), coords, qs, outputs=["point:P"], **kw)
    cpu, wall = time.process_time() - t, time.perf_counter() - w
    doc = {"sink": sink, "mechanisms": count, "cpu": cpu, "wall": wall, "rate": count * INPUTS / cpu,
           "peak_mib": _rss_mib(), "before_mib": before, "chunk": out.chunk, "per_mechanism": out.per_mechanism,
           "message": out.message, "route": "numba" if compiled.loaded() else "numpy"}
    if sink == "hdf5":
        doc["file_mib"] = os.path.getsize(out.result) / 2**20
        os.unlink(out.result)
        os.rmdir(folder)
    return doc


def run(sink, count, memory=MEMORY, chunk=None) -> dict:
    cmd = [sys.executable, __file__, "--child", sink, str(count), str(memory), str(chunk or 0)]
    done = subprocess.run(cmd, capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mechanisms", type=int, default=1_000_000, help="four-bars reduced to extremes")
    ap.add_argument("--collect", type=int, default=100_000, help="four-bars collected (and written to HDF5)")
    ap.add_argument("--memory", type=int, default=MEMORY, help="the budget, bytes")
    ap.add_argument("--positions", action="store_true",
                    help="also reduce the same four-bars from each chunk's positions (the route without the fused loop)")
    ap.add_argument("--chunks", action="store_true", help="also time chunk sizes (extremes, 3·10^4 four-bars)")
    ap.add_argument("--kernel", choices=["auto", "numpy", "numba"], default="auto",
                    help="the kernel's route (DOMES_KERNEL; auto compiles batches of 2^24 configurations and more)")
    ap.add_argument("--child", nargs=4, help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        sink, count, memory, chunk = args.child
        print(json.dumps(child(sink, int(count), int(memory), int(chunk) or None)))
        return
    os.environ[compiled.VARIABLE] = args.kernel  # the children inherit it
    try:
        import h5py  # noqa: F401
        sinks = [("collect", args.collect), ("hdf5", args.collect)]
    except ImportError:
        sinks = [("collect", args.collect)]
        print("h5py is not installed: the HDF5 sink is skipped\n")
    sinks = [("extremes", args.mechanisms)] + ([("positions", args.mechanisms)] if args.positions else []) + sinks
    print(f"## Bounded batches: random four-bars × {INPUTS} inputs, a coupler point (budget {args.memory:,} B)\n")
    print("| sink | route | mechanisms | peak RSS [MiB] | RSS before [MiB] | CPU [s] | wall [s] | positions / CPU s | "
          "chunk | bytes / mechanism |")
    print("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for sink, count in sinks:
        d = run(sink, count, args.memory)
        extra = f" (file {d['file_mib']:.0f} MiB)" if "file_mib" in d else ""
        print(f"| {sink}{extra} | {d['route']} | {count:,} | {d['peak_mib']:.0f} | {d['before_mib']:.0f} | {d['cpu']:.2f} | "
              f"{d['wall']:.2f} | {d['rate'] / 1e6:.2f} M | {d['chunk']:,} | {d['per_mechanism']:,} |")
        print(f"<!-- {d['message']} -->")
    if args.chunks:
        print("\n## Speed against the chunk (extremes, 100,000 four-bars, two fresh processes each)\n")
        print("| chunk (mechanisms) | configurations | positions / CPU s | peak RSS [MiB] |")
        print("|---:|---:|---:|---:|")
        for chunk in (11, 22, 45, 90, 180, 728, 2912):
            runs = [run("extremes", 100_000, args.memory, chunk) for _ in range(2)]
            rates = " / ".join(f"{d['rate'] / 1e6:.2f} M" for d in runs)
            print(f"| {chunk:,} | {chunk * INPUTS:,} | {rates} | {max(d['peak_mib'] for d in runs):.0f} |")


if __name__ == "__main__":
    main()
