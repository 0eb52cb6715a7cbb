"""A model of the atlas's time on N workers, from the task costs measured on a local cluster, and its check.

Runs one atlas on a local Dask cluster with Dask's task stream on, and
splits the wall time into the work done in tasks (their compute time on a
worker) and the rest, done in this process (the starts of the walks, the
merge, passing data). On ``N`` workers the tasks take about their work over
``N`` times the imbalance measured here (the busiest worker's time over the
mean); the rest does not shrink:

    T(N) ≈ S + β·W / N

``--method augment`` (default): the atlas by canonical augmentation, whose
parts are independent. Before the run, :func:`domes.typesynth.atlas.forecast`
walks a few parts drawn at random here (``--forecast-parts``) and scales them up (count, CPU work,
memory); the run then says how far the forecast was. ``--sample M`` walks
only ``M`` other parts drawn at random (``--seed``), on the cluster: the
check of a forecast for an atlas too large to build here (16 links).
``--method merge``: the level-by-level generator (its slices of ears and of
canonical labelling are the tasks).

    python benchmarks/scale_model.py --links 14 --dof 1 --workers 2                 # docs/scale.md
    python benchmarks/scale_model.py --links 16 --dof 1 --workers 2 --sample 2 --forecast-parts 2
"""

from __future__ import annotations

import argparse
import pickle
import random
import resource
import sys
import time
from collections import defaultdict

from domes.execution import executor
from domes.typesynth import augment
from domes.typesynth.atlas import FORECAST_PARTS, IMBALANCE, ChainGenerator, augment_forecast


def _peak_rss() -> int:
    """This process's peak resident memory, bytes (run on each worker)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def _split(stream, wall: float, workers: int):
    """Work in tasks, per worker, the wall time some task ran, and the imbalance."""
    per_worker: dict[str, float] = defaultdict(float)
    work, spans = 0.0, []
    for task in stream.data:
        for step in task["startstops"]:
            if step["action"] == "compute":
                seconds = step["stop"] - step["start"]
                work += seconds
                per_worker[task["worker"]] += seconds
                spans.append((step["start"], step["stop"]))
    spans.sort()
    covered, end = 0.0, float("-inf")                     # wall time during which some worker computed
    for a, b in spans:
        if b > end:
            covered += b - max(a, end)
            end = b
    beta = covered / (work / workers) if work else 1.0
    return work, per_worker, covered, beta, len(spans)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--links", type=int, required=True)
    parser.add_argument("--dof", type=int, required=True)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--method", choices=("augment", "merge"), default="augment")
    parser.add_argument("--sample", type=int, help="walk only this many parts, drawn at random (augment)")
    parser.add_argument("--seed", type=int, default=1, help="draws the sampled parts (the forecast draws with 0)")
    parser.add_argument("--forecast-parts", type=int, default=FORECAST_PARTS,
                        help=f"parts the forecast walks (default {FORECAST_PARTS}, as domes chains does)")
    parser.add_argument("--predict", type=int, nargs="*", default=[1, 2, 4, 8, 16, 32])
    args = parser.parse_args()
    from distributed import get_task_stream

    f = None
    if args.method == "augment":
        clock = time.perf_counter()
        f = augment_forecast(args.links, args.dof, args.workers, args.forecast_parts)
        print(f"forecast ({time.perf_counter() - clock:.1f} s): {f.count:,.0f} chains, work {f.work:.1f} s of CPU in "
              f"parts, serial {f.serial:.1f} s, {f.seconds_on(args.workers):.1f} s on {args.workers} workers, "
              f"{f.worker_memory / 2**20:.0f} MiB a worker; {f.basis}")
    loops = (3 * (args.links - 1) - args.dof) // 2 - args.links + 1
    with executor(args.workers) as run:
        if args.sample:
            clock = time.perf_counter()
            starts, parts = augment.plan(loops, args.dof, args.workers)
            planned = time.perf_counter() - clock
            picked = sorted(random.Random(args.seed).sample(range(parts), min(args.sample, parts)))
            shared = run.share(pickle.dumps(starts, protocol=pickle.HIGHEST_PROTOCOL))
            start = time.perf_counter()
            kept, cpu = 0, 0.0
            with get_task_stream(run.client) as stream:
                for _, result in run.completed(augment.walk_part, [(shared, i, parts, loops, args.dof)
                                                                    for i in picked]):
                    stats = pickle.loads(result)[1]
                    kept += stats.kept
                    cpu += stats.seconds                 # CPU time in the walks (the forecast's measure)
            wall = time.perf_counter() - start
            count = kept
        else:
            start = time.perf_counter()
            with get_task_stream(run.client) as stream:
                count = len(ChainGenerator(executor=run, method=args.method).chains(args.links, args.dof))
            wall = time.perf_counter() - start
        peaks = run.client.run(_peak_rss)
    work, per_worker, covered, beta, tasks = _split(stream, wall, args.workers)
    serial = wall - covered
    what = f"{len(picked)} of {parts} parts" if args.sample else "the atlas"
    print(f"{args.links} links, DOF {args.dof}, {what}: {count:,} chains in {wall:.1f} s on {args.workers} workers")
    print(f"  work in tasks W = {work:.1f} s of wall time ({tasks} tasks; per worker "
          + ", ".join(f"{s:.1f} s" for s in per_worker.values()) + ")")
    print(f"  wall time with a task running {covered:.1f} s: imbalance beta = {beta:.2f}; the rest S = {serial:.1f} s")
    print("  peak memory of each worker: " + ", ".join(f"{p / 2**20:.0f} MiB" for p in peaks.values()))
    if f is not None and args.sample:
        share = len(picked) / parts
        expect_wall = IMBALANCE * f.work * share / args.workers
        print(f"  the forecast for these parts: {f.count * share:,.0f} chains (walked {count:,}: "
              f"{count / (f.count * share):.2f}x), CPU {f.work * share:.1f} s (measured {cpu:.1f} s: "
              f"{cpu / (f.work * share):.2f}x), wall {expect_wall:.1f} s (measured {wall:.1f} s: "
              f"{wall / expect_wall:.2f}x); starts {planned:.1f} s")
        print(f"  the whole atlas, from this sample: {count / share:,.0f} chains, CPU {cpu / share:.0f} s")
    elif f is not None:
        print(f"  the forecast: {f.count:,.0f} chains ({count / f.count:.2f}x built), work {f.work:.1f} s "
              f"({work / f.work:.2f}x measured), {f.seconds_on(args.workers):.1f} s on {args.workers} workers "
              f"({wall / f.seconds_on(args.workers):.2f}x measured), {f.worker_memory / 2**20:.0f} MiB a worker")
    if not args.sample:
        print("  model T(N) = S + beta*W/N:")
        for n in args.predict:
            print(f"    N = {n:3d}: {serial + beta * work / n:7.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
