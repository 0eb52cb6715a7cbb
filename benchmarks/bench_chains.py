"""Benchmark: time and count of each chain atlas, for each isomorphism method.

Every measurement builds the atlas from nothing (a fresh generator, no cache),
in this process, on one core. The exact count comes from the nauty run; the
``charpoly`` column shows how many chains the book's test keeps instead.

    python benchmarks/bench_chains.py            # all atlases of the acceptance table
    python benchmarks/bench_chains.py --quick    # up to 10 links
"""

from __future__ import annotations

import argparse
import platform
import time

from domes.typesynth import ChainGenerator

ATLASES = [
    (4, 1), (6, 1), (8, 1), (10, 1), (12, 1),
    (5, 2), (7, 2), (9, 2), (11, 2),
    (6, 3), (8, 3), (10, 3),
    (3, 0), (5, 0), (7, 0), (9, 0),
]


def measure(links: int, dof: int, fractionated: bool, method: str, repeat: int) -> tuple[float, int]:
    best, count = float("inf"), -1
    for _ in range(repeat):
        start = time.perf_counter()
        count = len(ChainGenerator(isomorphism=method).chains(links, dof, fractionated))
        best = min(best, time.perf_counter() - start)
    return best, count


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="only atlases of up to 10 links")
    parser.add_argument("--repeat", type=int, default=3, help="best of this many runs (default 3)")
    args = parser.parse_args()
    print(f"# chain atlas benchmark: Python {platform.python_version()}, {platform.machine()}, best of {args.repeat}")
    print("| links | DOF | cut links | chains (nauty) | time nauty [s] | chains (charpoly) | time charpoly [s] |")
    print("|---:|---:|:---:|---:|---:|---:|---:|")
    for links, dof in ATLASES:
        if args.quick and links > 10:
            continue
        for fractionated in ((False, True) if dof >= 2 else (False,)):
            repeat = 1 if links >= 12 else args.repeat
            t_exact, n_exact = measure(links, dof, fractionated, "nauty", repeat)
            t_poly, n_poly = measure(links, dof, fractionated, "charpoly", repeat)
            mark = "" if n_poly == n_exact else f" ({n_poly - n_exact:+d})"
            print(
                f"| {links} | {dof} | {'yes' if fractionated else 'no'} | {n_exact} | {t_exact:.3f} "
                f"| {n_poly}{mark} | {t_poly:.3f} |",
                flush=True,
            )


if __name__ == "__main__":
    main()
