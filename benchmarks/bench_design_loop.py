"""Benchmark: the design loop, level by level, for the three sessions of docs/expert.md, and the time budget.

For each session (an answers file of examples/design/): the whole session (in-process, on a scratch case
base without solved problems, the report written), then each level of its funnel timed on its own from the
session's problem frame: generating the candidates (regeneration by the scene), screening them by the
knowledge base, the feasibility level (dimensioning and verifying every quasi-feasible candidate; the
slowest candidate), ranking, writing the report. Then the time budget knob on the motorcycle session: how
many designs are ranked, and how long the feasibility level takes, for each budget.

    python benchmarks/bench_design_loop.py
    python benchmarks/bench_design_loop.py --workers 2
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

from domes.design.ranking import rank
from domes.expert.dialogue import Dialogue
from domes.expert.feasible import DesignKnobs, feasible_designs
from domes.expert.replay import scratch_casebase
from domes.expert.report import write_report
from domes.expert.run import candidates_for
from domes.io.transcripts import read_answers
from domes.knowledge.screening import screen
from domes.store.casebase import KnowledgeBase

ROOT = Path(__file__).resolve().parents[1]
SESSIONS = ("motorcycle-rising-rate", "hinge-clamp-toggle", "window-lifter-design")
BUDGETS = (None, 6.0, 3.0, 1.5, 0.5)


def empty_casebase(folder: Path) -> str:
    url = scratch_casebase(None, None, folder)
    with KnowledgeBase(url) as kb:
        for p in kb.problems():
            kb.remove_problem(p.id)
    return url


def clock(work):
    start = time.perf_counter()
    out = work()
    return out, time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, default=None, help="dimension the candidates on N Dask workers")
    parser.add_argument("--seeds", type=int, default=16)
    args = parser.parse_args()
    knobs = DesignKnobs(seeds=args.seeds, workers=args.workers)
    print(f"# design loop benchmark: Python {platform.python_version()}, seeds {args.seeds}, "
          f"{args.workers or 1} worker(s)")
    print("| session | whole session [s] | generate [s] | screen [s] | quasi-feasible | feasibility [s] "
          "(slowest candidate) | feasible | rank [s] | report [s] |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    frames = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name in SESSIONS:
            folder = Path(tmp) / name
            folder.mkdir()
            url = empty_casebase(folder)
            answers = read_answers(ROOT / "examples" / "design" / f"{name}.answers")
            session_knobs = DesignKnobs(seeds=args.seeds, workers=args.workers, report=folder / "report")
            outcome, whole = clock(lambda: Dialogue(url, answers, interactive=False, out=lambda text: None,
                                                    knobs=session_knobs).run())
            frame = frames[name] = outcome.frame
            generated, t_gen = clock(lambda: candidates_for(frame, frame.links, frame.joints))
            with KnowledgeBase(url) as kb:
                criteria = kb.frames()
            _, t_screen = clock(lambda: screen([c for c, _ in generated], criteria, frame, relevance=frame.relevance))
            weights = frame.designs[0].get("weights") if frame.designs else None
            (result, ranking, _), t_feas = clock(lambda: feasible_designs(
                frame.scene, frame.requirements, None, frame.results, knobs))
            slowest = max(d.seconds for d in result.designs)
            _, t_rank = clock(lambda: rank(result.feasible, weights))
            _, t_report = clock(lambda: write_report(folder / "again", frame, {}, ""))
            print(f"| {name} | {whole:.2f} | {t_gen:.3f} | {t_screen:.3f} | {len(frame.results)} | {t_feas:.2f} "
                  f"({slowest:.2f}) | {len(result.feasible)} | {t_rank:.4f} | {t_report:.2f} |", flush=True)
        frame = frames["motorcycle-rising-rate"]
        print()
        print("| time budget [s] | feasibility level [s] | dimensioned | not finished | feasible, ranked |")
        print("|---:|---:|---:|---:|---:|")
        for budget in BUDGETS:
            budgeted = DesignKnobs(seeds=args.seeds, workers=args.workers, time_budget=budget)
            (result, ranking, _), spent = clock(lambda: feasible_designs(frame.scene, frame.requirements, None,
                                                                         frame.results, budgeted))
            done = len(result.designs) - len(result.unfinished)
            print(f"| {'none' if budget is None else f'{budget:g}'} | {spent:.2f} | {done} | {len(result.unfinished)} "
                  f"| {len(ranking)} |", flush=True)


if __name__ == "__main__":
    main()
