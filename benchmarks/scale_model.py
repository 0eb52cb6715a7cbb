"""A model of the atlas's time on N workers, from the task costs measured on a local cluster.

Runs one atlas on a local Dask cluster with Dask's task stream on, and
splits the wall time into the work done in tasks (each slice of ears, each
slice of canonical labelling: its compute time on a worker) and the rest,
done in this process (the merge, the sort, the small levels, passing data).
Each parallel phase is a batch of ``2 × workers`` equal slices, so on ``N``
workers it takes about its work over ``N`` times the imbalance measured here
(the slowest worker's time over the mean); the rest does not shrink:

    T(N) ≈ S + β·W / N

    python benchmarks/scale_model.py --links 14 --dof 1 --workers 2      # docs/scale.md
"""

from __future__ import annotations

import argparse
import sys
import time
from collections import defaultdict

from domes.execution import executor
from domes.typesynth.atlas import ChainGenerator


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--links", type=int, required=True)
    parser.add_argument("--dof", type=int, required=True)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--predict", type=int, nargs="*", default=[1, 2, 4, 8, 16, 32])
    args = parser.parse_args()
    from distributed import get_task_stream

    with executor(args.workers) as run:
        start = time.perf_counter()
        with get_task_stream(run.client) as stream:
            count = len(ChainGenerator(executor=run).chains(args.links, args.dof))
        wall = time.perf_counter() - start
    per_worker: dict[str, float] = defaultdict(float)
    work = 0.0
    spans = []
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
    serial = wall - covered
    beta = covered / (work / args.workers) if work else 1.0
    print(f"{args.links} links, DOF {args.dof}: {count:,} chains in {wall:.1f} s on {args.workers} workers")
    print(f"  work in tasks W = {work:.1f} s ({len(spans)} tasks; per worker "
          + ", ".join(f"{s:.1f} s" for s in per_worker.values()) + ")")
    print(f"  wall time with a task running {covered:.1f} s: imbalance beta = {beta:.2f}; the rest S = {serial:.1f} s")
    print("  model T(N) = S + beta*W/N:")
    for n in args.predict:
        print(f"    N = {n:3d}: {serial + beta * work / n:7.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
