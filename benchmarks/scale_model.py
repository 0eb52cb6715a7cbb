"""A model of the atlas's time on N workers, from the task costs measured on a local cluster, and its check.

Runs one atlas on a local Dask cluster with Dask's task stream on, and
splits the wall time into the work done in tasks (their compute time on a
worker) and the rest, done in this process (the starts of the walks, the
merge, passing data). On ``N`` workers the tasks take about their work over
``N`` times the imbalance measured here (the busiest worker's time over the
mean); the rest does not shrink:

    T(N) ≈ S + β·W / N

``--method augment`` (default): the atlas by canonical augmentation, whose
parts are independent. Before the run, the forecast walks a stratified
sample of the starts here (:func:`domes.typesynth.strata.sample`,
``--forecast-starts``, seed 0), as ``domes chains`` does, and scales it by
stratum (count, CPU work, the largest part); the run then says how far the
forecast was. ``--sample M`` walks only ``M`` parts drawn at random
(``--seed``), on the cluster, and compares them with the forecast of those
very parts: the check of a forecast for an atlas too large to build here
(16 links). ``--census`` walks every start alone on the cluster (the whole
atlas, start by start) and then draws the forecast's sample ``--draws``
times from those walks: how far the forecast can be, over many seeds.
``--method merge``: the level-by-level generator (its slices of ears and of
canonical labelling are the tasks).

    python benchmarks/scale_model.py --links 14 --dof 1 --workers 2                 # docs/scale.md
    python benchmarks/scale_model.py --links 14 --dof 1 --workers 2 --census --draws 300
    python benchmarks/scale_model.py --links 16 --dof 1 --workers 2 --sample 6
"""

from __future__ import annotations

import argparse
import pickle
import random
import resource
import statistics
import sys
import time
from collections import defaultdict

from domes.execution import executor
from domes.typesynth import augment, strata
from domes.typesynth.atlas import IMBALANCE, MERGE_SECONDS_PER_CHAIN, ChainGenerator


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


def _census(args, starts, loops, f) -> int:
    """Walk every start alone on the cluster, then draw the forecast's sample ``--draws`` times from the walks."""
    chunk = 64
    walks: list = [None] * len(starts)
    cpu0 = time.perf_counter()
    with executor(args.workers) as run:
        tasks = [(starts[i:i + chunk], loops, args.dof) for i in range(0, len(starts), chunk)]
        for j, result in run.completed(strata.walk_starts, tasks):
            walks[j * chunk:j * chunk + len(result)] = result
    chains, seconds = sum(w[0] for w in walks), sum(w[1] for w in walks)
    print(f"census: {chains:,} chains from {len(starts):,} starts, {seconds:.1f} s of CPU in the walks "
          f"({time.perf_counter() - cpu0:.1f} s on {args.workers} workers)")
    print(f"  the forecast (seed 0): {f.chains() / chains:.3f}x the chains, {f.seconds() / seconds:.3f}x the CPU")
    by_dof: dict = defaultdict(lambda: [0, 0])
    for g, w in zip(starts, walks):
        by_dof[3 * (g[0] - 1) - 2 * len(g[1])][0] += 1
        by_dof[3 * (g[0] - 1) - 2 * len(g[1])][1] += w[0]
    print("  starts of each DOF, and their chains: " + ", ".join(
        f"DOF {d}: {n:,} ({c / chains:.1%})" for d, (n, c) in sorted(by_dof.items())))
    ranked = sorted((w[0] for w in walks), reverse=True)
    half = next(i + 1 for i in range(len(ranked)) if sum(ranked[:i + 1]) * 2 >= chains)
    parts = augment.plan(loops, args.dof, args.workers)[1]
    sizes = [sum(walks[j][0] for j in range(i, len(starts), parts)) for i in range(parts)]
    print(f"  half the chains from {half} starts, none from {ranked.count(0):,}; the {parts} parts hold "
          f"{min(sizes):,} to {max(sizes):,} chains")
    four = [sum(sizes[i] for i in random.Random(seed).sample(range(parts), 4)) * parts / 4 / chains
            for seed in range(args.draws)]
    print(f"  four parts drawn at random (the forecast before strata), {args.draws} draws: {min(four):.2f}x to "
          f"{max(four):.2f}x the chains")
    keys = [strata.stratum(g) for g in starts]
    ratios = []
    for seed in range(args.draws):
        s = strata.sample(starts, loops, args.dof, args.forecast_starts, seed, walk=walks.__getitem__, strata=keys)
        ratios.append((s.chains() / chains, s.seconds() / seconds, s.seconds_walked / seconds))
    for name, k in (("chains", 0), ("CPU", 1)):
        values = [r[k] for r in ratios]
        print(f"  {args.draws} draws of {args.forecast_starts} starts: {name} {min(values):.3f}x to {max(values):.3f}x "
              f"(sd {statistics.pstdev(values):.3f}); within 30%: {sum(abs(v - 1) <= 0.3 for v in values)}")
    print(f"  the sample walks {statistics.mean(r[2] for r in ratios):.3f} of the work")
    return 0


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--links", type=int, required=True)
    parser.add_argument("--dof", type=int, required=True)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--method", choices=("augment", "merge"), default="augment")
    parser.add_argument("--sample", type=int, help="walk only this many parts, drawn at random (augment)")
    parser.add_argument("--seed", type=int, default=1, help="draws the sampled parts (the forecast draws with 0)")
    parser.add_argument("--forecast-starts", type=int, default=strata.BUDGET,
                        help=f"starts the forecast walks (default {strata.BUDGET}, as domes chains does)")
    parser.add_argument("--census", action="store_true", help="walk every start alone, then redraw the forecast")
    parser.add_argument("--draws", type=int, default=300, help="forecasts drawn from the census (--census)")
    parser.add_argument("--predict", type=int, nargs="*", default=[1, 2, 4, 8, 16, 32])
    args = parser.parse_args()
    from distributed import get_task_stream

    loops = (3 * (args.links - 1) - args.dof) // 2 - args.links + 1
    f = starts = None
    if args.method == "augment":
        clock, cpu0 = time.perf_counter(), time.process_time()
        starts, parts = augment.plan(loops, args.dof, args.workers)
        planned = time.process_time() - cpu0
        f = strata.sample(starts, loops, args.dof, args.forecast_starts, seed=0)
        serial = planned + f.chains() * MERGE_SECONDS_PER_CHAIN
        print(f"forecast ({time.perf_counter() - clock:.1f} s, {time.process_time() - cpu0:.1f} s of CPU; "
              f"{f.walked} of {len(starts):,} starts walked, {f.seconds_walked:.1f} s of CPU): {f.chains():,.0f} "
              f"chains, work {f.seconds():.1f} s of CPU in {parts} parts, serial {serial:.1f} s, "
              f"{serial + IMBALANCE * f.seconds() / args.workers:.1f} s on {args.workers} workers")
    if args.census:
        return _census(args, starts, loops, f)
    with executor(args.workers) as run:
        if args.sample:
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
    what = f"{len(picked)} of {parts} parts {picked}" if args.sample else "the atlas"
    print(f"{args.links} links, DOF {args.dof}, {what}: {count:,} chains in {wall:.1f} s on {args.workers} workers")
    print(f"  work in tasks W = {work:.1f} s of wall time ({tasks} tasks; per worker "
          + ", ".join(f"{s:.1f} s" for s in per_worker.values()) + ")")
    print(f"  wall time with a task running {covered:.1f} s: imbalance beta = {beta:.2f}; the rest S = {serial:.1f} s")
    print("  peak memory of each worker: " + ", ".join(f"{p / 2**20:.0f} MiB" for p in peaks.values()))
    if f is not None and args.sample:
        mine = [i for p in picked for i in range(p, len(starts), parts)]
        chains, seconds = f.chains(mine), f.seconds(mine)
        print(f"  the forecast for these parts: {chains:,.0f} chains (walked {count:,}: {count / chains:.2f}x), "
              f"CPU {seconds:.1f} s (measured {cpu:.1f} s: {cpu / seconds:.2f}x)")
        print(f"  the whole atlas, from these parts: {count * len(starts) / len(mine):,.0f} chains, CPU "
              f"{cpu * len(starts) / len(mine):.0f} s")
    elif f is not None:
        print(f"  the forecast: {f.chains():,.0f} chains ({count / f.chains():.2f}x built), work {f.seconds():.1f} s "
              f"of CPU (W measured {work / f.seconds():.2f}x, wall clock in tasks)")
    if not args.sample:
        print("  model T(N) = S + beta*W/N:")
        for n in args.predict:
            print(f"    N = {n:3d}: {serial + beta * work / n:7.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
