"""Benchmark: time to regenerate each shipped scene (chain atlas included, built fresh).

    python benchmarks/bench_regeneration.py
"""

from __future__ import annotations

import argparse
import platform
import time

from domes.io.scenes import load_scene, scene_names
from domes.typesynth import chains, label_joints, regenerate


def best_of(repeat: int, work) -> tuple[float, object]:
    best, result = float("inf"), None
    for _ in range(repeat):
        start = time.perf_counter()
        result = work()
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    print(f"# regeneration benchmark: Python {platform.python_version()}, best of {args.repeat}")
    print("| scene | links | stage counts | candidates | time [s] |")
    print("|---|---:|---|---:|---:|")
    for name in scene_names():
        scene = load_scene(name)
        seconds, result = best_of(args.repeat, lambda: regenerate(scene))
        counts = " → ".join(str(s.count) for s in result.stages)
        print(f"| {name} | {scene.links} | {counts} | {len(result.candidates)} | {seconds:.3f} |", flush=True)
    print()
    print("| labelled graphs | labellings | time [s] |")
    print("|---|---:|---:|")
    for links, counts, limits in [(8, {"P": 1}, None), (8, {"P": 2}, None), (10, {"P": 1}, None), (8, {"G": 2}, {"G": 1})]:
        seconds, result = best_of(args.repeat, lambda: label_joints(chains(links=links, dof=1), counts, limits))
        text = ", ".join(f"{k}={v}" for k, v in counts.items()) + (f", at most {limits} per loop" if limits else "")
        print(f"| {links}-link 1-DOF chains, {text} | {len(result)} | {seconds:.3f} |", flush=True)


if __name__ == "__main__":
    main()
