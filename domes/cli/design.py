"""``domes design`` (the question-answer session) and ``domes cases`` (the solved problems)."""

from __future__ import annotations

import argparse
import json
import math
import signal
import sys
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

from domes.cli.common import DB_HELP, parallel_options, progress_printer, read_line
from domes.errors import DomesError, InputError
from domes.execution import check_workers
from domes.io.files import check_target

if TYPE_CHECKING:  # loaded by the commands that use them
    from domes.expert.dialogue import Dialogue

STATE = ".domes-design-session.json"


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "design": "the design expert: a question-answer session that designs, screens and remembers",
    "cases": "solved problems: list, show, replay, record, remove",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.design.methods import METHODS

    d = sub.add_parser(
        "design",
        help=COMMANDS["design"],
        description="The DOMES design dialogue (Fig. 7-8): recognise the problem as the same as, similar to "
        "or different from a solved one, ask what is needed, derive links and joints, generate, label and "
        "screen the candidates, and keep the solved problem in the case base.",
    )
    d.add_argument("--answers", metavar="FILE", help="answer from a file ('question: answer' lines, or a transcript .json)")
    d.add_argument("--record", metavar="FILE", help="write the transcript (answers and result) to FILE (JSON)")
    d.add_argument("--resume", metavar="STATE", help=f"resume an interrupted session from its state file (default name {STATE})")
    d.add_argument("--state", metavar="FILE", default=STATE, help=f"where an interrupted session is saved (default {STATE})")
    d.add_argument("--no-vary", action="store_true", help="do not vary loops and gear pairs when everything is eliminated")
    d.add_argument("--dry-run", action="store_true", help="work on a scratch copy of the case base: keep nothing")
    d.add_argument("--db", metavar="URL", help=DB_HELP)
    f = d.add_argument_group("the feasibility level (when the scene dimensions its candidates for requirements)")
    f.add_argument("--report", metavar="DIR", default="auto",
                   help="write the report (index.html) and a mechanism file per feasible design to DIR (default: "
                   "domes-report-CLASS in the working folder)")
    f.add_argument("--no-report", action="store_true", help="write no report")
    f.add_argument("--time-budget", type=float, metavar="SECONDS",
                   help="stop starting candidates once this time is spent; the session says which were not finished")
    f.add_argument("--method", choices=METHODS, default="fast",
                   help="dimensioning: polish the best 4 (fast) or 12 (exact) random layouts of each candidate")
    f.add_argument("--seeds", type=int, default=16, metavar="N", help="screen 200 x N random layouts per candidate "
                   "(default 16)")
    parallel_options(f, "dimension the candidates")
    d.set_defaults(func=run_design)

    c = sub.add_parser("cases", help=COMMANDS["cases"])
    c.add_argument("--db", metavar="URL", help=DB_HELP)
    cs = c.add_subparsers(dest="action", metavar="ACTION")
    cs.required = True
    cs.add_parser("list", help="the solved problems").set_defaults(func=run_list)
    show = cs.add_parser("show", help="one solved problem and its result")
    show.add_argument("id")
    show.add_argument("--format", choices=("text", "json"), default="text")
    show.set_defaults(func=run_show)
    rp = cs.add_parser("replay", help="re-run recorded transcripts against the current knowledge base; show differences")
    rp.add_argument("cases", nargs="*", metavar="CASE", help="case names (knowledge/cases/NAME.json) or transcript files")
    rp.add_argument("--all", action="store_true", help="every shipped case")
    rp.add_argument("--verbose", "-v", action="store_true", help="show the dialogue")
    rp.set_defaults(func=run_replay)
    rc = cs.add_parser("record", help="run an answers file as a new shipped case (knowledge/cases/NAME.json)")
    rc.add_argument("answers", metavar="ANSWERS")
    rc.add_argument("--name", required=True, help="file name of the case (knowledge/cases/NAME.json)")
    rc.add_argument("--method", choices=METHODS, default="fast", help="dimensioning method (kept with the case)")
    rc.add_argument("--seeds", type=int, default=16, metavar="N", help="random layouts 200 x N per candidate (kept "
                    "with the case)")
    rc.set_defaults(func=run_record)
    rm = cs.add_parser("remove", help="remove a solved problem from the case base")
    rm.add_argument("id")
    rm.add_argument("--why", default="", help="why it is removed (kept in the history, `domes kb history`)")
    rm.set_defaults(func=run_remove)


def run_design(args: argparse.Namespace) -> int:
    from domes.expert.dialogue import Dialogue
    from domes.expert.feasible import DesignKnobs
    from domes.expert.replay import scratch_casebase
    from domes.io.transcripts import load_session, read_answers

    for target in (args.record, args.state):  # where the session will be written: refused now, not after it
        if target:
            check_target(target)
    if args.time_budget is not None and not (math.isfinite(args.time_budget) and args.time_budget > 0):
        raise InputError(f"--time-budget must be a positive number of seconds, got {args.time_budget!r}")
    if not 1 <= args.seeds <= 4096:
        raise InputError(f"--seeds must be a whole number from 1 to 4096, got {args.seeds}")
    check_workers(args.workers, args.scheduler)
    answers, interactive = [], True
    if args.answers:
        answers, interactive = read_answers(args.answers), False
    if args.resume:
        answers = load_session(args.resume)
        print(f"Resuming the session saved in {args.resume} ({len(answers)} answers).")
    with tempfile.TemporaryDirectory(prefix="domes-dry-run-") as tmp:
        url = scratch_casebase(args.db, None, Path(tmp)) if args.dry_run else args.db
        if args.dry_run:
            print("Dry run: a scratch copy of the case base; nothing is kept.")
        knobs = DesignKnobs(args.method, args.seeds, args.workers, args.scheduler, args.time_budget,
                            None if args.no_report else args.report)
        status = _design(args, Dialogue(url, answers, interactive=interactive or bool(args.resume), vary=not args.no_vary,
                                        progress=progress_printer(), knobs=knobs, read=read_line))
        if args.dry_run:
            print("Dry run: the case base is unchanged.")
        return status


def _design(args: argparse.Namespace, dialogue: Dialogue) -> int:
    from domes.io.transcripts import save_session, write_transcript

    try:
        outcome = dialogue.run()
    except (KeyboardInterrupt, EOFError) as stop:
        why, status = ("interrupted", 128 + signal.SIGINT) if isinstance(stop, KeyboardInterrupt) else ("end of input", 1)
        if not dialogue.exchanges:
            print(f"\ndomes design: {why} before any answer; nothing saved", file=sys.stderr)
            return status
        save_session(args.state, dialogue.exchanges)
        print(f"\ndomes design: {why}; {len(dialogue.exchanges)} answers saved in {args.state} "
              f"(resume with: domes design --resume {args.state})", file=sys.stderr)
        return status
    if args.record:
        write_transcript(args.record, outcome.to_dict())
        print(f"Transcript written to {args.record}.")
    if args.resume and Path(args.resume).name == STATE:
        Path(args.resume).unlink(missing_ok=True)
    return 0


def run_list(args: argparse.Namespace) -> int:
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(args.db) as kb:
        problems = kb.problems()
    print(f"  {'id':<34s} {'class':<30s} DOF  L  links joints sliders gears  kept")
    for p in problems:
        print(f"  {p.id:<34s} {p.problem_class:<30s} {p.dof!s:>3s} {p.loops!s:>2s} {p.links!s:>6s} {p.joints!s:>6s} "
              f"{p.slider_pairs or 0:>7d} {p.gear_pairs or 0:>5d} {len(p.results):>5d}")
    return 0


def run_show(args: argparse.Namespace) -> int:
    from domes.expert.world import frame_text
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(args.db) as kb:
        frame = kb.get_problem(args.id)
    if args.format == "json":
        print(json.dumps(frame.to_dict(), indent=1, ensure_ascii=False))
    else:
        print(frame_text(frame))
    return 0


def run_replay(args: argparse.Namespace) -> int:
    from domes.expert.replay import replay, shipped_cases

    names = list(args.cases)
    if args.all:
        names += shipped_cases()
    if not names:
        raise InputError("name the cases to replay, or give --all")
    failed = 0
    for name in names:  # every case is replayed, whatever the others gave
        try:
            result = replay(name, args.db, say=print if args.verbose else (lambda text: None))
        except DomesError as exc:
            failed += 1
            print(f"{name}: NOT REPLAYED: {exc}")
            continue
        if result.differences:
            failed += 1
            print(f"{result.name}: DIFFERENT")
            for line in result.differences:
                print(f"  {line}")
        else:
            print(f"{result.name}: same result ({result.outcome.relation}, {len(result.outcome.frame.results) if result.outcome.frame else 0} candidates)")
    if failed:
        print(f"{failed} of {len(names)} case(s) differ")
    return 1 if failed else 0


def run_record(args: argparse.Namespace) -> int:
    from domes.expert.feasible import DesignKnobs
    from domes.expert.replay import record_case
    from domes.io.transcripts import read_answers

    if not 1 <= args.seeds <= 4096:
        raise InputError(f"--seeds must be a whole number from 1 to 4096, got {args.seeds}")
    _, target = record_case(read_answers(args.answers), args.name, args.db, say=print,
                            knobs=DesignKnobs(method=args.method, seeds=args.seeds))
    print(f"Case written to {target}; rebuild the case base with `domes kb build`.")
    return 0


def run_remove(args: argparse.Namespace) -> int:
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(args.db, write=True, actor="domes cases remove") as kb:
        kb.remove_problem(args.id, why=args.why)
    print(f"removed {args.id}")
    return 0
