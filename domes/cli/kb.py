"""``domes kb``: parse criteria, and list, show, edit, export, import, check and build the knowledge base."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from domes.cli.common import db_option, write_output
from domes.errors import DomesError, InputError
from domes.io.resources import DB_ENV, KNOWLEDGE_ENV

if TYPE_CHECKING:  # loaded by the commands that use them
    from domes.knowledge.relevance import Problem
    from domes.store.casebase import KnowledgeBase

WHY_HELP = "why the change is made (kept in the history, `domes kb history`)"


def _open(args: argparse.Namespace, **kwargs) -> KnowledgeBase:
    """The case base of a command that changes it; its history names the command."""
    from domes.store.casebase import KnowledgeBase

    return KnowledgeBase(args.db, actor=f"domes kb {args.kb_command}", **kwargs)


#: The subcommands registered here and their line in ``domes --help``.
COMMANDS = {
    "kb": "the knowledge base of screening criteria (criterion frames, Table 7-2)",
}


def register(sub: argparse._SubParsersAction) -> None:
    from domes.io.criteria import FORMATS

    p = sub.add_parser(
        "kb",
        help=COMMANDS["kb"],
        description="Parse criteria written in the criterion language, and keep the knowledge base of "
        f"criterion frames: your case base (made from the embedded casebase.db on the first edit), or --db URL / {DB_ENV}. "
        "Every edit is one transaction; a refused edit changes nothing.",
    )
    kb = p.add_subparsers(dest="kb_command", metavar="ACTION")
    kb.required = True
    db = db_option()

    q = kb.add_parser("parse", help="print the parsed criterion as JSON (exit 2 if it does not parse)")
    q.add_argument("text", help="a criterion, e.g. 'the swing arm is adjacent to the ground'")
    q.add_argument("--relevance", action="store_true", help="parse a relevance condition instead of a criterion")
    q.set_defaults(func=run_parse)

    q = kb.add_parser("list", parents=[db], help="list the criteria, in knowledge-base order")
    q.add_argument("--format", choices=("text", "json"), default="text")
    q.set_defaults(func=run_list)

    q = kb.add_parser("show", parents=[db], help="show one criterion frame")
    q.add_argument("--id", required=True)
    q.add_argument("--format", choices=("text", "json"), default="text")
    q.set_defaults(func=run_show)

    for name, helptext in (("add", "add a criterion"), ("edit", "change fields of a criterion")):
        q = kb.add_parser(name, parents=[db], help=helptext)
        q.add_argument("--id", required=True)
        q.add_argument("--text", required=name == "add", help="the criterion, in the criterion language")
        q.add_argument("--explanation")
        q.add_argument("--keywords", help="comma-separated keywords")
        q.add_argument("--relevance", help="relevance condition, e.g. 'the problem has “piston”' (default: derived)")
        q.add_argument("--level", type=int, help="screening level (default: the cheapest that can evaluate it)")
        q.add_argument("--source", help="where the criterion comes from")
        q.add_argument("--date", help="YYYY[-MM[-DD]] (default for add: today)")
        if name == "add":
            q.add_argument("--disabled", action="store_true", help="add it disabled")
        q.add_argument("--why", default="", help=WHY_HELP)
        q.set_defaults(func=run_add if name == "add" else run_edit)

    for name, helptext in (("enable", "enable a criterion"), ("disable", "disable a criterion (kept, not applied)"),
                           ("remove", "remove a criterion")):
        q = kb.add_parser(name, parents=[db], help=helptext)
        q.add_argument("--id", required=True)
        q.add_argument("--why", default="", help=WHY_HELP)
        q.set_defaults(func=run_remove if name == "remove" else run_enable, enable=name == "enable")

    q = kb.add_parser("history", parents=[db], help="every change of the case base: what, when, in which session, why")
    q.add_argument("--changes", action="store_true", help="also show each row's values before and after")
    q.add_argument("--format", choices=("text", "json"), default="text")
    q.set_defaults(func=run_history)

    q = kb.add_parser("undo", parents=[db], help="take back the last change (or every change from entry N on)")
    q.add_argument("entry", nargs="?", type=int, metavar="N", help="the history entry to go back to (default: the last)")
    q.set_defaults(func=run_undo)

    q = kb.add_parser("export", parents=[db], help="write the knowledge base as TOML (or JSON)")
    q.add_argument("--output", "-o", help="file to write (default: stdout); .json writes JSON")
    q.add_argument("--format", choices=FORMATS, help="default: from the file name, else toml")
    q.set_defaults(func=run_export)

    q = kb.add_parser("import", parents=[db], help="add the criteria of a TOML or JSON file, all or none")
    q.add_argument("file")
    q.add_argument("--why", default="", help=WHY_HELP)
    q.set_defaults(func=run_import)

    q = kb.add_parser("check", parents=[db], help="check the stored criteria (or given source files) parse as stored")
    q.add_argument("files", nargs="*", help="source files to validate instead of the database")
    q.set_defaults(func=run_check)

    q = kb.add_parser("build", parents=[db], help="build the case base from the knowledge sources")
    q.add_argument("--from", dest="source", metavar="DIR", help=f"knowledge sources folder (default: ${KNOWLEDGE_ENV}, else the shipped knowledge)")
    q.add_argument("--force", action="store_true", help="replace a file or database that is not a case base, or (not SQLite) one whose own cases and criteria the sources lack")
    q.set_defaults(func=run_build)

    q = kb.add_parser(
        "screen", parents=[db], help="screen labelled graphs (JSON) by the relevant criteria, level by level",
        description="Multi-level screening. GRAPHS is a JSON file: a list of labelled graphs, each "
        '{"links": 4, "joints": [[0, 1, "R"], [1, 2, "P"], ...], "roles": {"0": ["ground"]}, "loops": {"drive": [0, 1, 2, 3]}} '
        "(joint type R when omitted). Every rejection names its criterion and what broke it.",
    )
    q.add_argument("graphs", help="JSON file of labelled graphs ('-' reads stdin)")
    q.add_argument("--problem", help="problem attributes as JSON (default: every criterion is relevant)")
    q.add_argument("--max-level", type=int, help="screening depth: apply criteria up to this level only")
    q.add_argument("--format", choices=("text", "json"), default="text")
    q.set_defaults(func=run_screen)

    q = kb.add_parser("relevance", parents=[db], help="the relevance vector of a problem")
    q.add_argument("problem", help='problem attributes as JSON, e.g. \'{"dof": 1, "slider_pairs": 1, "names": ["piston"]}\'')
    q.set_defaults(func=run_relevance)


def run_parse(args: argparse.Namespace) -> int:
    from domes.language.parse import parse_criterion, parse_relevance
    from domes.language.render import render_criterion, render_relevance
    from domes.language.tree import category, to_json

    if args.relevance:
        tree = parse_relevance(args.text)
        out = {"relevance": to_json(tree), "reading": render_relevance(tree)}
    else:
        tree = parse_criterion(args.text)
        out = {"criterion": to_json(tree), "category": category(tree), "reading": render_criterion(tree)}
    json.dump(out, sys.stdout, ensure_ascii=False, indent=1)
    sys.stdout.write("\n")
    return 0


def run_list(args: argparse.Namespace) -> int:
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(args.db) as kb:
        frames = kb.frames()
    if args.format == "json":
        json.dump([f.to_dict() for f in frames], sys.stdout, ensure_ascii=False, indent=1)
        sys.stdout.write("\n")
        return 0
    width = max([len(f.id) for f in frames] + [2])
    print(f"{'#':>3}  {'id':<{width}}  cat  lvl  on   explanation")
    for number, f in enumerate(frames, 1):
        on = "yes" if f.enabled else "no"
        print(f"{number:>3}  {f.id:<{width}}  {f.category:<3}  {f.level:<3}  {on:<3}  {f.explanation or f.text}")
    print(f"# {len(frames)} criteria ({sum(f.enabled for f in frames)} enabled)")
    return 0


def run_show(args: argparse.Namespace) -> int:
    from domes.language.tree import to_json
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(args.db) as kb:
        frame = kb.get(args.id)
    data = frame.to_dict()
    if args.format == "json":
        data["tree"] = to_json(frame.tree)
        data["relevance_tree"] = to_json(frame.relevance)
        json.dump(data, sys.stdout, ensure_ascii=False, indent=1)
        sys.stdout.write("\n")
        return 0
    for key in ("id", "text", "reading", "category", "explanation", "keywords", "relevance", "level", "source", "date", "enabled"):
        value = data[key]
        if isinstance(value, list):
            value = ", ".join(value)
        elif isinstance(value, bool):
            value = "yes" if value else "no"
        print(f"{key + ':':<13}{value}")
    return 0


def _changes(args: argparse.Namespace) -> dict:
    changes = {}
    for key in ("text", "explanation", "relevance", "level", "source", "date"):
        value = getattr(args, key)
        if value is not None:
            changes[key] = value
    if args.keywords is not None:
        changes["keywords"] = [w.strip() for w in args.keywords.split(",") if w.strip()]
    return changes


def run_add(args: argparse.Namespace) -> int:
    from domes.knowledge.frames import CriterionFrame
    from domes.language.render import render_criterion

    changes = _changes(args)
    frame = CriterionFrame.create(args.id, enabled=not args.disabled, **changes)
    with _open(args, write=True) as kb:
        kb.add(frame, why=args.why)
    print(f"added {frame.id}: category ({frame.category}), level {frame.level}: {render_criterion(frame.tree)}")
    return 0


def run_edit(args: argparse.Namespace) -> int:
    from domes.language.render import render_criterion

    changes = _changes(args)
    if not changes:
        raise InputError("nothing to change: give --text, --explanation, --keywords, --relevance, --level, --source or --date")
    with _open(args, write=True) as kb:
        frame = kb.get(args.id).edited(**changes)
        kb.update(frame, why=args.why)
    print(f"edited {frame.id}: category ({frame.category}), level {frame.level}: {render_criterion(frame.tree)}")
    return 0


def run_enable(args: argparse.Namespace) -> int:
    with _open(args, write=True) as kb:
        kb.update(kb.get(args.id).with_enabled(args.enable), why=args.why, action=f"{args.kb_command} criterion")
    print(f"{'enabled' if args.enable else 'disabled'} {args.id}")
    return 0


def run_remove(args: argparse.Namespace) -> int:
    with _open(args, write=True) as kb:
        kb.remove(args.id, why=args.why)
    print(f"removed {args.id}")
    return 0


def run_export(args: argparse.Namespace) -> int:
    from domes.io.criteria import dumps_json, dumps_toml
    from domes.store.casebase import KnowledgeBase

    fmt = args.format or ("json" if args.output and args.output.endswith(".json") else "toml")
    with KnowledgeBase(args.db) as kb:
        frames = kb.frames()
    text = dumps_json(frames) if fmt == "json" else dumps_toml(frames)
    write_output(text, args.output)
    if args.output:
        print(f"exported {len(frames)} criteria to {args.output}", file=sys.stderr)
    return 0


def run_import(args: argparse.Namespace) -> int:
    from domes.io.criteria import check_unique, read_file

    frames = read_file(args.file)
    check_unique(frames, args.file)  # validated whole before the database is even opened
    with _open(args, create=True) as kb:
        try:
            kb.import_frames(frames, why=args.why)
        except DomesError as exc:
            raise InputError(f"{args.file}: {exc}; nothing was imported") from None
    print(f"imported {len(frames)} criteria from {args.file}")
    return 0


def run_check(args: argparse.Namespace) -> int:
    from domes.io.criteria import check_unique, read_file
    from domes.store.casebase import KnowledgeBase

    if args.files:
        frames = []
        for name in args.files:
            frames.extend(read_file(name))
            check_unique(frames, name)
        print(f"ok: {len(frames)} criteria in {len(args.files)} file(s)")
        return 0
    with KnowledgeBase(args.db) as kb:
        frames = kb.frames()
        problems = kb.check()
    if problems:
        raise InputError(f"{len(problems)} problem(s) in the knowledge base:\n  " + "\n  ".join(problems))
    print(f"ok: {len(frames)} criteria parse as stored")
    return 0


def run_history(args: argparse.Namespace) -> int:
    from domes.store.casebase import KnowledgeBase

    with KnowledgeBase(args.db) as kb:
        entries = kb.history()
    if args.format == "json":
        json.dump([e.to_dict() for e in entries], sys.stdout, ensure_ascii=False, indent=1)
        sys.stdout.write("\n")
        return 0
    if not entries:
        print("no recorded change")
        return 0
    for e in entries:
        print(f"{e.number:>4}  {e.time}  {e.session}: {e.action} {e.target}" + (f"  (why: {e.why})" if e.why else ""))
        print(f"      {e.summary}")
        if args.changes:
            for c in e.changes:
                print(f"      {c['table']} {c['key']}: before {json.dumps(c['before'], ensure_ascii=False)}")
                print(f"      {c['table']} {c['key']}: after  {json.dumps(c['after'], ensure_ascii=False)}")
    print(f"# {len(entries)} change(s); `domes kb undo` takes back the last, `domes kb undo N` all from entry N on")
    return 0


def run_undo(args: argparse.Namespace) -> int:
    with _open(args, write=True) as kb:
        undone = kb.undo(args.entry)
    for e in undone:
        print(f"undone {e.number}: {e.action} {e.target} ({e.summary})")
    return 0


def run_build(args: argparse.Namespace) -> int:
    from domes.store.casebase import KnowledgeBase, build

    frames = build(args.source, args.db, force=args.force, say=print)
    with KnowledgeBase(args.db) as kb:
        cases = len(kb.problems())
    print(f"built the knowledge base: {len(frames)} criteria, {cases} solved problems")
    return 0


def _problem(text: str) -> Problem:
    from domes.knowledge.relevance import Problem

    try:
        data = json.loads(Path(text).read_text() if text.endswith(".json") else text)
    except (OSError, json.JSONDecodeError) as exc:
        raise InputError(f"problem: not a JSON object or .json file: {exc}") from None
    if not isinstance(data, dict):
        raise InputError("problem: expected a JSON object of attributes")
    return Problem.from_dict(data)


def run_screen(args: argparse.Namespace) -> int:
    from domes.io.graphs import parse_labelled_graphs, read_labelled_graphs
    from domes.knowledge.screening import screen
    from domes.language.explain import explain
    from domes.store.casebase import KnowledgeBase

    if args.graphs == "-":
        graphs = parse_labelled_graphs(sys.stdin.read(), "stdin")
    else:
        graphs = read_labelled_graphs(args.graphs)
    problem = _problem(args.problem) if args.problem else None
    with KnowledgeBase(args.db) as kb:
        frames = kb.frames()
    result = screen(graphs, frames, problem, max_level=args.max_level)
    by_id = {f.id: f for f in frames}
    reasons = {r.index: explain(by_id[r.criterion].tree, graphs[r.index]) for r in result.rejections}
    if args.format == "json":
        out = {
            "kept": list(result.kept_indices),
            "rejected": [{"graph": r.index, "criterion": r.criterion, "level": r.level, "reason": reasons[r.index]}
                         for r in result.rejections],
            "applied": list(result.applied), "skipped": list(result.skipped), "not_relevant": list(result.not_relevant),
            "emptied_by": result.emptied_by, "levels": [list(x) for x in result.levels], "message": result.message,
        }
        json.dump(out, sys.stdout, ensure_ascii=False, indent=1)
        sys.stdout.write("\n")
        return 0
    print(f"# {result.message}")
    print(f"# criteria applied in order: {', '.join(result.applied) or 'none'}")
    print(f"kept: {' '.join(map(str, result.kept_indices)) or 'none'}")
    for r in result.rejections:
        print(f"  graph {r.index}: rejected by {r.criterion} (level {r.level}): {reasons[r.index]}")
    return 0


def run_relevance(args: argparse.Namespace) -> int:
    from domes.knowledge.relevance import relevance_vector
    from domes.store.casebase import KnowledgeBase

    problem = _problem(args.problem)
    with KnowledgeBase(args.db) as kb:
        vector = relevance_vector(kb.frames(), problem)
    print(" ".join(map(str, vector.bits)))
    for criterion_id, bit in zip(vector.ids, vector.bits):
        print(f"  {bit}  {criterion_id}")
    return 0
