"""Screening speed: 10,000 labelled graphs x 20 criteria, and the screening-depth knob.

Run from the checkout: ``python benchmarks/bench_screening.py [--graphs N]``.
The graphs are the 6-, 8- and 10-link one-DOF chains (2 + 16 + 230) with random joint types
(R 80 %, P 15 %, G 5 %), a ground and an input jointed to it, other roles
(output, piston, swing arm, shock absorber) each on a random link with
probability 0.4, and a random simple cycle named the drive loop; the criteria are the shipped
ones but the combination modes (which exclude each other) plus 4 more, all treated as relevant. Times are the best of 3 runs.
"""

from __future__ import annotations

import argparse
import random
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from domes.io.criteria import read_knowledge  # noqa: E402
from domes.io.resources import knowledge_dir  # noqa: E402
from domes.knowledge.frames import CriterionFrame  # noqa: E402
from domes.knowledge.screening import screen  # noqa: E402
from domes.language.evaluate import compile_criterion, graph_features  # noqa: E402
from domes.model import LabelledChain  # noqa: E402
from domes.model.labelled import share_topologies  # noqa: E402
from domes.typesynth import chains  # noqa: E402

EXTRA = [
    ("max-degree-4", "every vertex must have degree at most 4"),
    ("few-geared-loops", "the number of loops that have a gear pair must be at most 2"),
    ("output-near-ground", "the output must be at distance at most 2 from the ground"),
    ("short-basis", "every independent loop must have length at most 6"),
]
ROLES = ["output", "piston", "swing_arm", "shock_absorber", "shock_absorber"]


def candidates(count: int, seed: int = 1) -> list[LabelledChain]:
    rng = random.Random(seed)
    atlas = [c for links in (6, 8, 10) for c in chains(links=links, dof=1)]
    out = []
    for _ in range(count):
        c = rng.choice(atlas)
        types = [rng.choices("RPG", weights=(16, 3, 1))[0] for _ in c.edges]
        ground = rng.randrange(c.n)
        neighbours = [v for e in c.edges for u, v in (e, e[::-1]) if u == ground]
        roles: dict[int, set[str]] = {ground: {"ground"}}
        roles.setdefault(rng.choice(neighbours), set()).add("input")
        for role in ROLES:
            if rng.random() < 0.4:
                roles.setdefault(rng.randrange(c.n), set()).add(role)
        topo = c.topology
        mask = rng.choice(topo.cycle_edges)
        ring = _ring([e for i, e in enumerate(c.edges) if mask >> i & 1])
        out.append(LabelledChain.build(c.n, c.edges, types, roles, {"drive": ring}))
    return out


def _ring(cycle_edges: list[tuple[int, int]]) -> list[int]:
    """The links of a simple cycle (given by its joints) in loop order."""
    order = [cycle_edges[0][0]]
    while len(order) < len(cycle_edges):
        last = order[-1]
        order.append(next(w for u, v in cycle_edges for a, w in ((u, v), (v, u)) if a == last and w not in order))
    return order


def best(fn, repeat: int = 3) -> tuple[float, object]:
    times, value = [], None
    for _ in range(repeat):
        start = time.perf_counter()
        value = fn()
        times.append(time.perf_counter() - start)
    return min(times), value


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--graphs", type=int, default=10_000)
    args = parser.parse_args(argv)
    graphs = candidates(args.graphs)
    # The combination-mode criteria exclude each other (a problem asks for one mode), and the spatial ones apply
    # only to spatial single loops: leave them out, so the planar graphs are screened as before.
    shipped = [c for c in read_knowledge(knowledge_dir())
               if "combination" not in c.keywords and "spatial" not in c.keywords]
    criteria = shipped + [CriterionFrame.create(i, t) for i, t in EXTRA]
    tests = [compile_criterion(c.tree) for c in criteria]

    start = time.perf_counter()
    share_topologies(graphs)  # one topology per chain, computed on first use
    features = [graph_features(g) for g in graphs]
    cold = time.perf_counter() - start
    warm, features = best(lambda: [graph_features(g) for g in graphs])
    every, verdicts = best(lambda: [[t(f) for t in tests] for f in features])
    full, result = best(lambda: screen(graphs, criteria))

    n, k = len(graphs), len(criteria)
    print(f"# {n} labelled graphs ({len({(g.n, g.edges) for g in graphs})} chains), {k} criteria, best of 3")
    print(f"{'step':<58} {'seconds':>8}  {'µs/graph':>8}")
    rows = [
        ("graph features, topologies computed (one per chain)", cold),
        ("graph features, topologies known", warm),
        (f"every criterion on every graph ({n * k} evaluations)", every),
        (f"screen(): features + {k} criteria, level by level", full),
    ]
    for label, seconds in rows:
        print(f"{label:<58} {seconds:8.3f}  {seconds / n * 1e6:8.1f}")
    kept_all = sum(all(v) for v in verdicts)
    assert kept_all == len(result.kept)
    print(f"\nkept {len(result.kept)} of {n}; levels (level, left after it): {list(result.levels)}")
    print(f"\n{'max_level (screening depth)':<30} {'seconds':>8}  {'criteria':>8}  {'kept':>6}")
    for depth in (1, 2, 3):
        seconds, r = best(lambda: screen(graphs, criteria, max_level=depth))
        print(f"{depth:<30} {seconds:8.3f}  {len(r.applied):>8}  {len(r.kept):>6}")


if __name__ == "__main__":
    main()
