"""Make the start solutions of the nine-point path homotopy: domes/design/synthesis/ninepoint.npz.

A random complex four-bar is planted (:func:`domes.design.synthesis.isotropic.plant`: random complex linkage and
coupler rotations, the nine points solved from them), so one solution of the nine-point equations at those
(complex, generic) parameters is known; it is tracked to random complex parameters of the size of a query's
(points scaled to size 1, ``δ`` and ``δ̄`` independent, each complex normal of deviation 0.7). Monodromy loops (:func:`domes.design.synthesis.homotopy.monodromy`) then
find the others, one per class of Roberts cognates and the relabelling of the two dyads, until the 1,442 classes
of Wampler, Morgan & Sommese (1992) are known. The same is done for Morgan & Wampler's (1990) five points with two
given pivots (36 solutions, no symmetry). Run once, about ten minutes of CPU:

    python benchmarks/make_ninepoint_start.py [--seed 7]
"""

import argparse
import time
from pathlib import Path

import numpy as np

from domes.design.synthesis.homotopy import DONE, monodromy, track
from domes.design.synthesis.isotropic import DyadSystem, plant
from domes.design.synthesis.ninepoint import CLASSES, FIVE_POINT_COUNT, class_key

OUT = Path(__file__).resolve().parents[1] / "domes" / "design" / "synthesis" / "ninepoint.npz"


def moved(system, z, p, rng):
    """The planted solution ``z`` at ``p`` tracked to random complex parameters of deviation 0.7."""
    for _ in range(10):
        target = 0.7 * (rng.normal(size=p.shape) + 1j * rng.normal(size=p.shape)) / np.sqrt(2)
        end = track(system, z, p, target, gamma=np.exp(1j * rng.uniform(-np.pi, np.pi)))
        if end.status[0] == DONE:
            return end.z, target
    raise SystemExit("the planted solution could not be moved")


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("-o", "--output", type=Path, default=OUT)
    args = ap.parse_args(argv)
    rng = np.random.default_rng(args.seed)
    t0 = time.process_time()

    def say(found, pending, loops):
        print(f"  {found} classes, {pending} (class, loop) pairs to track, {loops} loops, "
              f"{time.process_time() - t0:.0f} s CPU", flush=True)

    nine = DyadSystem(8)
    z, p = moved(nine, *plant(nine, rng), rng)
    print("nine points:")
    reps = monodromy(nine, z, p, class_key, CLASSES, rng, progress=say)
    five = DyadSystem(4, pivots_given=True)
    z5, p5 = moved(five, *plant(five, rng), rng)
    print("five points, two pivots:")
    sols5 = monodromy(five, z5, p5, lambda w, _: w, FIVE_POINT_COUNT, rng, progress=say)
    if len(reps) != CLASSES or len(sols5) != FIVE_POINT_COUNT:
        raise SystemExit(f"found {len(reps)} of {CLASSES} classes and {len(sols5)} of {FIVE_POINT_COUNT}: not saved")
    np.savez_compressed(args.output, nine_z=reps, nine_p=p[0], five_z=sols5, five_p=p5[0])
    print(f"{args.output}: {len(reps)} + {len(sols5)} solutions, {time.process_time() - t0:.0f} s CPU")


if __name__ == "__main__":
    main()
