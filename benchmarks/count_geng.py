"""An independent count of a chain atlas: nauty's geng and the pebble game, partitioned on the executor.

geng lists every 2-connected, triangle-free graph with the atlas's links and
joints (a triangle is a rigid sub-chain, so no chain is lost), split into
``--parts`` classes by its own ``res/mod`` switch; each task runs one class
and keeps the graphs the (3, 4) pebble game on the doubled joints finds
non-degenerate (:mod:`domes.model.pebble`). Nothing of the generator's
method (ears, nauty certificates, subset tables) is used.

    python benchmarks/count_geng.py --links 14 --dof 1 --workers 2     # docs/scale.md
    python benchmarks/count_geng.py --links 13 --dof 2 --compare       # also build the atlas and compare
"""

from __future__ import annotations

import argparse
import shutil
import subprocess
import sys
import time

from domes.execution import executor
from domes.model.mobility import chain_joints
from domes.model.pebble import decode_graph6, pebble_sparse

GENG = shutil.which("nauty-geng") or shutil.which("geng")


def count_class(task: tuple[int, int, int, int]) -> tuple[int, int]:
    """(graphs geng listed, graphs kept) of class ``res`` of ``mod``."""
    links, joints, res, mod = task
    listed = subprocess.run([GENG, "-Ctq", "-d2", str(links), f"{joints}:{joints}", f"{res}/{mod}"],
                            capture_output=True, text=True, check=True).stdout.split()
    return len(listed), sum(pebble_sparse(*decode_graph6(g)) for g in listed)


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--links", type=int, required=True)
    parser.add_argument("--dof", type=int, required=True)
    parser.add_argument("--parts", type=int, default=64, help="geng classes (tasks); default 64")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--compare", action="store_true", help="build the atlas here too and compare the counts")
    args = parser.parse_args()
    if GENG is None:
        print("nauty's geng is not installed (Debian package nauty): no independent count", file=sys.stderr)
        return 2
    joints = chain_joints(args.links, args.dof)
    start = time.perf_counter()
    with executor(args.workers) as run:
        results = run.map(count_class, [(args.links, joints, r, args.parts) for r in range(args.parts)])
    seconds = time.perf_counter() - start
    listed, kept = map(sum, zip(*results))
    print(f"{args.links} links, {joints} joints, DOF {args.dof}: geng listed {listed:,} 2-connected triangle-free "
          f"graphs, the pebble game kept {kept:,} ({seconds:.1f} s, {run.where})")
    if args.compare:
        from domes.typesynth.atlas import chains

        start = time.perf_counter()
        count = len(chains(args.links, args.dof))
        print(f"the atlas: {count:,} chains ({time.perf_counter() - start:.1f} s); "
              f"{'the same' if count == kept else 'DIFFERENT'}")
        return 0 if count == kept else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
