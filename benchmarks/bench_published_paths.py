"""Published path-synthesis targets: our fit beside the papers' own solutions, measured the same way (issue 27, item 1).

Run ``python benchmarks/bench_published_paths.py`` (``--targets ID ...`` for some, ``--candidates``,
``--peer-generations N`` to run Pyslvs' differential evolution as a peer on the untimed targets when Pyslvs is
installed, 0 to skip it). The targets, the papers' solutions and where each was taken from are in
``benchmarks/data/published_paths.json``; the small atlases come from the data folder (``$DOMES_HOME/atlas/``),
built the first time. For each target: every published solution and our fit
(:func:`domes.design.synthesis.pathtargets.fit_target`) are measured by
:func:`domes.design.synthesis.pathtargets.measure`: the kinematics kernel traces the linkage's coupler curve and
each point's distance from the circuit the points lie nearest gives the worst and RMS error over the target's
size; with timing, the coupler point's distance from each point at the prescribed crank angles too. Our time is
CPU seconds of the route (one process, one thread). Numbers in docs/curves.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
DATA = ROOT / "benchmarks" / "data" / "published_paths.json"


def _pct(v) -> str:
    return "—" if v is None else "∞" if not np.isfinite(v) else f"{100 * v:.3g}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--targets", nargs="*", help="target ids (default all)")
    parser.add_argument("--candidates", type=int, default=5, help="atlas candidates refined (default 5)")
    parser.add_argument("--peer-generations", type=int, default=300,
                        help="Pyslvs DE generations on the untimed closed targets (0: no peer; default 300)")
    args = parser.parse_args(argv)

    from domes.design.synthesis import pathtargets as pt
    from domes.execution.threads import limited_threads
    from domes.io.atlas import default_atlas
    from domes.motion.coupler.atlas import Atlas, OpenAtlas

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from peer_synthesis import pyslvs_path_synthesis

    data = pt.load(DATA)
    targets = [t for t in data["targets"] if not args.targets or t["id"] in args.targets]
    with limited_threads(1):
        t0 = time.perf_counter()
        closed, opened = Atlas(default_atlas("small")), OpenAtlas(default_atlas("small", kind="open"))
        print(f"# atlases read (or built) in {time.perf_counter() - t0:.1f} s")
        print("| target | kind | points | linkage | worst % | RMS % | timed worst % | timed RMS % | CPU s |")
        print("|---|---|---:|---|---:|---:|---:|---:|---:|")
        verdicts = []
        for t in targets:
            pts = np.asarray(t["points"], dtype=float)
            head = f"| {t['id']} | {t['kind']} | {len(pts)} "
            published = []
            for s in t["published"]:
                fb, angles = pt.published_drawn(t, s)
                m = pt.measure(fb, pts, angles) if fb is not None else None
                published.append(m)
                if m is None:
                    print(head + f"| {s['label']} | loop does not close | | | | |")
                else:
                    print(head + f"| {s['label']} | {_pct(m.worst)} | {_pct(m.rms)} | {_pct(m.timed_worst)} | "
                          f"{_pct(m.timed_rms)} | |")
            c0 = time.process_time()
            fb, angles, route = pt.fit_target(t, closed, opened, args.candidates)
            spent = time.process_time() - c0
            ours = pt.measure(fb, pts, angles) if fb is not None else None
            if ours is None:
                print(head + f"| **ours** ({route}) | — | — | — | — | {spent:.1f} |")
            else:
                print(head + f"| **ours** ({route}) | {_pct(ours.worst)} | {_pct(ours.rms)} | "
                      f"{_pct(ours.timed_worst)} | {_pct(ours.timed_rms)} | {spent:.1f} |")
            if args.peer_generations and not pt.timed(t) and t["kind"] == "closed" and len(pts) >= 9:
                peer = pyslvs_path_synthesis(pts, "DE", args.peer_generations, seed=0)
                if peer is None:
                    print(head + "| Pyslvs DE | not installed | | | | |")
                else:
                    size = pt.size_of(pts)
                    print(head + f"| Pyslvs DE, {args.peer_generations} generations | "
                          f"{_pct(peer['max_error'] / size)} | {_pct(peer['rms_error'] / size)} | — | — | "
                          f"{peer['seconds']:.1f} (wall) |")
            key = "timed_worst" if pt.timed(t) else "worst"
            rivals = [getattr(m, key) for m in published if m is not None]
            if rivals:
                mine = getattr(ours, key) if ours is not None else float("inf")
                verdicts.append((t["id"], mine <= min(rivals), spent))
        won = sum(v for _, v, _ in verdicts)
        print(f"# our worst point at most the best published one's on {won} of {len(verdicts)} targets with a "
              f"published solution" + "".join(f"; lost on {i}" for i, v, _ in verdicts if not v)
              + f"; longest {max((s for _, _, s in verdicts), default=0):.1f} s CPU")
    return 0


if __name__ == "__main__":
    sys.exit(main())
