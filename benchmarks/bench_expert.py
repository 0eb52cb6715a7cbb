"""Benchmark: a problem designed from scratch, then asked again and answered from the case base.

For every shipped case: the time of its recorded design session on a case
base without it (number synthesis, chains, labelling or regeneration,
screening), and the time of the same problem asked again ("same"), answered
from its stored frame. Both in-process, best of N, each on a scratch copy.

    python benchmarks/bench_expert.py
"""

from __future__ import annotations

import argparse
import json
import platform
import tempfile
import time
from pathlib import Path

from domes.expert.dialogue import Dialogue
from domes.expert.replay import scratch_casebase
from domes.io.resources import knowledge_dir


def timed(work, urls: list[str]) -> float:
    """Best time of ``work(url)`` over prepared scratch case bases (copying is not timed)."""
    best = float("inf")
    for url in urls:
        start = time.perf_counter()
        work(url)
        best = min(best, time.perf_counter() - start)
    return best


def run(answers):
    return lambda url: Dialogue(url, answers, interactive=False, out=lambda text: None).run()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"# design expert benchmark: Python {platform.python_version()}, best of {args.repeat}")
    print("| case | candidates kept | design from scratch [s] | asked again, from the case base [s] | speed-up |")
    print("|---|---:|---:|---:|---:|")
    for path in sorted((knowledge_dir() / "cases").glob("*.json")):
        data = json.loads(path.read_text(encoding="utf-8"))
        frame = data["frame"]
        answers = [(e["question"], e["answer"]) for e in data["exchanges"]]
        again = [("class", frame["problem_class"]), ("relation", f"same {frame['id']}")]
        with tempfile.TemporaryDirectory() as tmp:
            folders = [Path(tmp) / str(i) for i in range(2 * args.repeat)]
            for folder in folders:
                folder.mkdir()
            without = [scratch_casebase(None, frame["id"], f) for f in folders[: args.repeat]]
            withit = [scratch_casebase(None, None, f) for f in folders[args.repeat :]]
            t_first = timed(run(answers), without)
            t_again = timed(run(again), withit)
        print(f"| {path.stem} | {len(frame['results'])} | {t_first:.3f} | {t_again:.3f} | {t_first / t_again:.0f}x |", flush=True)


if __name__ == "__main__":
    main()
