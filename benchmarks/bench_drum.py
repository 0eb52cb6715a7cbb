"""Benchmark: the tyre-building drum's long runs, the tables of docs/drum.md (seed 002 §5-3; issue 29, item 1).

``threshold``: the project's D0/D1 threshold of the Fig. 5-1 file, by bisection on the folding ratio D1/Df
(:func:`domes.design.drum.threshold`, every free dimension optimised to Δ_min = 0 at each ratio asked),
one row per ratio tried: docs/drum.md, "D0/D1: the project's threshold for Fig. 5-1".

``candidates``: every regenerated candidate of the tyre-drum scene dimensioned by the seeded construction
(:func:`domes.design.drum.dimension_candidates`), counted per chain: how many got a usable stroke, reached
Δ_min = 0, passed every check: docs/drum.md, "Regenerated candidates". ``--hold none`` leaves
anti-retraction out of the objective.

Times are processor seconds (``time.process_time``), which a busy machine inflates less than the wall clock.

    python benchmarks/bench_drum.py threshold
    python benchmarks/bench_drum.py candidates --hold none
    python benchmarks/bench_drum.py candidates
"""

from __future__ import annotations

import argparse
import math
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FILE = ROOT / "knowledge" / "mechanisms" / "tyre-drum-fig5-1.json"


def threshold(evaluations: int, iterations: int) -> None:
    from domes.cli.drum import _design_of
    from domes.design import drum as dm
    from domes.io.mechanisms import load_mechanism

    design = _design_of(dm.Drum.of(load_mechanism(FILE)))
    start = time.process_time()
    th = dm.threshold(design, 1.25, 1.45, iterations=iterations, free=("reach", "facing", "outer", "share", "slants"),
                      evaluations=evaluations)
    seconds = time.process_time() - start
    print(f"{'ratio asked':>12s} {'reached':>8s} {'D1/Df':>8s} {'D0/D1':>8s} {'best Δ_min':>12s}  limit")
    for ratio, ok, got, d0, delta, why in th.rows:
        print(f"{ratio:12.6g} {'yes' if ok else 'no':>8s} {got:8.4f} {d0:8.4f} {delta:12.3g}  {why}")
    print(th.message)
    if th.design is not None:
        c = dm.check(th.design.drum())
        print(f"at the threshold: {c.message}")
    print(f"{seconds:.0f} s of processor time")


def candidates(hold: float | None, seeds: int, evaluations: int) -> None:
    from domes.design import drum as dm
    from domes.io.scenes import load_scene
    from domes.typesynth.regenerate import regenerate

    found = regenerate(load_scene("tyre-drum")).candidates
    start = time.process_time()
    rows = dm.dimension_candidates(found, seeds=seeds, evaluations=evaluations, hold=hold)
    seconds = time.process_time() - start
    print(f"{'chain':>5s} {'candidates':>10s} {'stroke':>7s} {'reached':>8s} {'passed':>7s}  reached (ids)")
    for chain in sorted({r.chain for r in rows}):
        mine = [r for r in rows if r.chain == chain]
        ids = ", ".join(r.id for r in mine if r.reached)
        print(f"{chain:5d} {len(mine):10d} {sum(r.built > 0 for r in mine):7d} {sum(r.reached for r in mine):8d} "
              f"{sum(r.passes for r in mine):7d}  {ids or '-'}")
    for r in rows:
        if r.reached:
            print(f"candidate {r.id} (chain {r.chain}): {r.check.message if r.check else 'Δ_min = 0, not checked'}")
    print(f"hold {hold}, {seeds} seeds, {evaluations} designs a seed: {seconds:.0f} s of processor time")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("run", choices=("threshold", "candidates"))
    parser.add_argument("--evaluations", type=int, default=None,
                        help="designs per optimisation (default 250 for threshold, 120 for candidates)")
    parser.add_argument("--iterations", type=int, default=6, help="bisection steps of threshold (default 6)")
    parser.add_argument("--seeds", type=int, default=2, help="random seeds per candidate (default 2)")
    parser.add_argument("--hold", default="0.05",
                        help="largest holding-torque share in the candidates' objective, or 'none' (default 0.05)")
    args = parser.parse_args()
    if args.run == "threshold":
        threshold(args.evaluations or 250, args.iterations)
    else:
        hold = None if args.hold == "none" else float(args.hold)
        if hold is not None and not (math.isfinite(hold) and hold > 0):
            parser.error(f"--hold must be a number > 0 or 'none', got {args.hold!r}")
        candidates(hold, args.seeds, args.evaluations or 120)


if __name__ == "__main__":
    main()
