"""Six-bar round trip: curves of random Watt and Stephenson six-bars matched back (issue 27, item 2).

Run ``python benchmarks/bench_sixbar_paths.py`` (``--cases N``, ``--seed S``, ``--clock cpu``; ``--only 5,7`` runs
those cases alone). Each case is a
six-bar drawn from the design space of ``domes.motion.coupler.sixbar.sample`` (Watt and Stephenson in turn; a
seeded stream other than the atlas's, so random lengths, not atlas points) whose crank turns fully, traced at 64
equal crank steps from a random start, then scaled (0.1–10), turned, moved and, half the time, mirrored. The
path is matched as ``domes curves match --six-bars auto --tol 1e-4`` does (the small four-bar atlas first, then
the six-bar atlas, both from the data folder, built the first time). A case is recovered when the best linkage
passes through every point within 1e-4 of the path's size, measured by the kinematics kernel. Then ``--fourbars``
random four-bar curves matched with ``--six-bars yes``: each must be answered by a four-bar first. Numbers in
docs/curves.md ("Six-bars").
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

TOL = 1e-4


def planted(kind: str, rng) -> np.ndarray:
    """The 64 points of a random six-bar's curve of ``kind``, placed at random."""
    from domes.motion.coupler.sixbar import sample

    s = sample(kind, rng)
    z = s.curve(rng.uniform(0, 2 * np.pi) + np.linspace(0, 2 * np.pi, 64, endpoint=False))
    z = z * rng.uniform(0.1, 10.0) * np.exp(1j * rng.uniform(0, 2 * np.pi)) + complex(*rng.uniform(-10, 10, 2))
    z = np.conj(z) if rng.random() < 0.5 else z
    return np.c_[z.real, z.imag]


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cases", type=int, default=100, help="random six-bars (default 100)")
    parser.add_argument("--fourbars", type=int, default=10, help="random four-bar curves (default 10)")
    parser.add_argument("--seed", type=int, default=27, help="the random stream (default 27)")
    parser.add_argument("--clock", choices=("cpu", "wall"), default="cpu", help="time measured (default cpu)")
    parser.add_argument("--only", type=lambda t: {int(k) for k in t.split(",")}, default=None,
                        help="run only these cases, comma-separated (the stream is drawn as for all of them)")
    args = parser.parse_args()

    from domes.execution.threads import limited_threads
    from domes.io.atlas import default_atlas
    from domes.io.sixatlas import default_sixatlas
    from domes.motion.coupler.atlas import Atlas
    from domes.motion.coupler.match import kind_of, match

    clock = time.process_time if args.clock == "cpu" else time.perf_counter
    with limited_threads(1):
        t = clock()
        atlas, six = Atlas(default_atlas("small")), default_sixatlas()
        print(f"# atlases read (or built) in {clock() - t:.1f} s ({args.clock}); six-bar atlas {six.count:,} curves")
        rng = np.random.default_rng(args.seed)
        hits, times, worst = 0, [], []
        print("case  type        best type               largest/size  time s")
        for k in range(args.cases):
            kind = ("watt", "stephenson")[k % 2]
            points = planted(kind, rng)
            if args.only is not None and k not in args.only:
                continue
            t = clock()
            result = match(points, atlas, results=1, tol=TOL, sixbars="auto", sixatlas=six)
            times.append(clock() - t)
            f = result.fits[0] if result.fits else None
            err = f.after[0] / result.size if f is not None and f.mechanism is not None else float("inf")
            hits += err <= TOL
            worst.append(err)
            print(f"{k:4d}  {kind:10s}  {kind_of(f) if f else '-':22s}  {err:12.3g}  {times[-1]:6.1f}", flush=True)
        run = len(times)
        if not run:
            parser.error(f"--only names no case below --cases {args.cases}")
        print(f"# recovered within {TOL:g} of the size: {hits} of {run} ({100 * hits / max(run, 1):.0f}%);"
              f" time per curve ({args.clock}) median {statistics.median(times):.1f} s, mean "
              f"{statistics.mean(times):.1f} s, max {max(times):.1f} s")
        missed = sorted(e for e in worst if e > TOL)
        if missed:
            print("# misses' largest distance / size: " + ", ".join(f"{e:.2g}" for e in missed))
        from domes.motion.coupler.curves import trace
        from domes.motion.coupler.fourbar import four_bar

        first = 0
        for _ in range(args.fourbars):
            while True:
                a, b, c = rng.uniform(0.3, 1.0), rng.uniform(0.8, 2.0), rng.uniform(0.8, 2.0)
                try:
                    curve = trace(four_bar(a, b, c, 1.0, *rng.uniform(-2, 2, 2)), "P", 64)
                except Exception:
                    continue
                if curve.circuits and len(curve.circuits[0].points) >= 32:
                    break
            pts = curve.circuits[0].points * rng.uniform(0.5, 5) + rng.uniform(-5, 5, 2)
            result = match(pts, atlas, results=1, sixbars="yes", sixatlas=six)
            first += bool(result.fits) and kind_of(result.fits[0]) == "four-bar" and result.fits[0].success
        print(f"# four-bar curves answered first by a four-bar within 1e-6 (six-bars tried too): {first} of "
              f"{args.fourbars}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
