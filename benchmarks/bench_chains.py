"""Benchmark: time and count of each chain atlas, for each generation and isomorphism method.

Every measurement builds the atlas from nothing (a fresh generator, no cache),
in this process, on one core. The exact count comes from the nauty run; the
``merge`` and ``augment`` columns are the two generators (the same atlas,
checked here), the ``charpoly`` column shows how many chains the book's test
keeps instead (merge only).

    python benchmarks/bench_chains.py            # all atlases of the acceptance table (CPU time)
    python benchmarks/bench_chains.py --quick    # up to 10 links
    python benchmarks/bench_chains.py --clock wall
"""

from __future__ import annotations

import argparse
import platform
import time

from domes.typesynth import ChainGenerator

ATLASES = [
    (4, 1), (6, 1), (8, 1), (10, 1), (12, 1),
    (5, 2), (7, 2), (9, 2), (11, 2), (13, 2),
    (6, 3), (8, 3), (10, 3), (12, 3),
    (3, 0), (5, 0), (7, 0), (9, 0), (11, 0),
]


def measure(links: int, dof: int, fractionated: bool, method: str, isomorphism: str, repeat: int,
            clock) -> tuple[float, list]:
    best, found = float("inf"), []
    for _ in range(repeat):
        start = clock()
        found = ChainGenerator(isomorphism=isomorphism, method=method).chains(links, dof, fractionated)
        best = min(best, clock() - start)
    return best, found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only atlases of up to 10 links")
    parser.add_argument("--repeat", type=int, default=3, help="best of this many runs (default 3)")
    parser.add_argument("--clock", choices=("cpu", "wall"), default="cpu", help="CPU time (default) or wall time")
    args = parser.parse_args()
    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    print(f"# chain atlas benchmark: Python {platform.python_version()}, {platform.machine()}, best of {args.repeat}, "
          f"{args.clock} time")
    print("| links | DOF | cut links | chains (nauty) | merge [s] | augment [s] | chains (charpoly) | charpoly [s] |")
    print("|---:|---:|:---:|---:|---:|---:|---:|---:|")
    for links, dof in ATLASES:
        if args.quick and links > 10:
            continue
        for fractionated in ((False, True) if dof >= 2 and links <= 11 else (False,)):
            repeat = 1 if links >= 12 else args.repeat
            t_merge, exact = measure(links, dof, fractionated, "merge", "nauty", repeat, clock)
            t_augment, augmented = measure(links, dof, fractionated, "augment", "nauty", repeat, clock)
            if augmented != exact:
                raise SystemExit(f"{links} links, DOF {dof}: the two generators differ")
            if links >= 13:
                t_poly, poly = float("nan"), None
            else:
                t_poly, poly = measure(links, dof, fractionated, "merge", "charpoly", repeat, clock)
            n_poly = "" if poly is None else f"{len(poly)}" + ("" if len(poly) == len(exact) else
                                                               f" ({len(poly) - len(exact):+d})")
            print(f"| {links} | {dof} | {'yes' if fractionated else 'no'} | {len(exact)} | {t_merge:.3f} "
                  f"| {t_augment:.3f} | {n_poly} | {t_poly:.3f} |".replace("| nan |", "| |"), flush=True)


if __name__ == "__main__":
    main()
