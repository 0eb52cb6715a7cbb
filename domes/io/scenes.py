"""Scene files: a design scene's rules read from TOML, every error with the file and the line.

The format is documented in ``docs/regeneration.md``; the shipped scenes are
in the knowledge folder's ``scenes/``.

>>> [s.name for s in load_scene("motorcycle").stages]
['ground', 'shock absorber', 'swing arm', 'swing arm adjacent to ground']
"""

from __future__ import annotations

from functools import lru_cache
from pathlib import Path

from domes.design.brief import brief_from, check_spec, weights_from
from domes.design.verify import CHECKS, USAGE
from domes.errors import DomesError, InputError, shown
from domes.io.files import is_file
from domes.io.resources import knowledge_dir
from domes.io.tomlsource import TomlSource
from domes.io.topology import read_topology
from domes.language.evaluate import compile_criterion
from domes.language.parse import normalise_name, parse_criterion
from domes.language.tree import names_used
from domes.model.chain import Chain
from domes.model.labelled import JOINT_TYPES
from domes.model.mobility import chain_joints
from domes.model.requirements import RequirementSpec, placeholders
from domes.typesynth.atlas import ChainGenerator, clamping_joints
from domes.typesynth.scene import (
    KINDS,
    Degrees,
    Particularization,
    Scene,
    SceneCheck,
    Stage,
    impossible_degree,
    mechanism_links,
)

_STAGE_KEYS = {"name", "role", "select", "rules", "note", "kind", "joint", "optional"}
_CHAINS_KEYS = {"links", "dof", "include_fractionated", "clamping"}
#: Up to this many links the degrees that occur are read off the atlas itself.
DEGREES_FROM_ATLAS = 10
_TOP_KEYS = {"name", "title", "source", "chains", "stages", "particularize", "existing", "book", "checks",
             "requirements", "design"}
_REQUIREMENT_KEYS = {"id", "label", "kind", "unit", "default", "help"}
_DESIGN_KEYS = {"task", "checks", "weights"}


def scene_names() -> list[str]:
    """Names of the shipped scenes."""
    return sorted(p.stem for p in (knowledge_dir() / "scenes").glob("*.toml"))


def load_scene(name_or_path: str | Path) -> Scene:
    """A scene by name (``knowledge/scenes/NAME.toml``) or by file path.

    A scene is an immutable value: one read again while its file is unchanged (same path, size and time of
    change) is the one read before.
    """
    path = Path(name_or_path)
    if not is_file(path):
        candidate = knowledge_dir() / "scenes" / f"{name_or_path}.toml"
        if not is_file(candidate):
            raise InputError(f"no scene {shown(str(name_or_path))}: not a file, and not one of: "
                             f"{', '.join(scene_names())}")
        path = candidate
    try:
        state = path.stat()
    except OSError:
        return parse_scene(TomlSource.read(path))
    return _load(str(path.resolve()), state.st_size, state.st_mtime_ns)


@lru_cache(maxsize=64)
def _load(path: str, size: int, changed: int) -> Scene:
    return parse_scene(TomlSource.read(Path(path)))


def parse_scene(src: TomlSource) -> Scene:
    """Validate a scene; every error names the file and the line."""
    data = src.data
    for key in data:
        if key not in _TOP_KEYS:
            raise src.error(f"unknown key {key!r}; a scene has {', '.join(sorted(_TOP_KEYS))}", src.line_of(key))
    chains = data.get("chains")
    if not isinstance(chains, dict) or "links" not in chains or "dof" not in chains:
        raise src.error("a scene needs a [chains] table with links and dof", src.line_of("chains"))
    for key in chains:
        if key not in _CHAINS_KEYS:
            raise src.error(f"[chains]: unknown key {key!r}; [chains] has {', '.join(sorted(_CHAINS_KEYS))}",
                            src.line_of(key))
    links, dof = chains["links"], chains["dof"]
    for key, value in (("links", links), ("dof", dof)):
        if isinstance(value, bool) or not isinstance(value, int):
            raise src.error(f"[chains] links and dof must be whole numbers, got {key} = {value!r}", src.line_of(key))
    fractionated = chains.get("include_fractionated", False)
    if not isinstance(fractionated, bool):
        raise src.error(f"[chains] include_fractionated must be true or false, got {fractionated!r}",
                        src.line_of("include_fractionated"))
    clamping = chains.get("clamping", False)
    if not isinstance(clamping, bool):
        raise src.error(f"[chains] clamping must be true or false, got {clamping!r}", src.line_of("clamping"))
    try:
        clamping_joints(links, dof) if clamping else chain_joints(links, dof)
    except DomesError as exc:
        raise src.error(str(exc), src.line_of("links")) from None
    degrees = link_degrees(links, dof, fractionated, clamping)

    raw_stages = data.get("stages", [])
    if not isinstance(raw_stages, list) or not raw_stages:
        raise src.error("a scene needs at least one [[stages]] table")
    given_at: dict[str, int] = {}
    for i, raw in enumerate(raw_stages):
        if isinstance(raw, dict) and isinstance(raw.get("role"), str):
            given_at.setdefault(normalise_name(raw["role"]), i)
    stages = tuple(_parse_stage(src, i, raw, given_at, degrees) for i, raw in enumerate(raw_stages))
    _check_conversions(src, stages)

    roles = {s.role for s in stages if s.role}
    marks = {s.role: s for s in stages if s.is_conversion}
    particular = []
    for i, raw in enumerate(data.get("particularize", [])):
        line = src.table_line("particularize", i)
        between, joint = raw.get("between"), raw.get("joint")
        if not (isinstance(between, list) and len(between) == 2 and all(isinstance(r, str) for r in between)):
            raise src.error("particularize: 'between' must name two roles", line)
        for role in between:
            if normalise_name(role) not in roles:
                raise src.error(f"particularize: unknown role {role!r}; the stages give out {', '.join(sorted(roles))}", src.line_of(role, line) or line)
        if joint not in JOINT_TYPES:
            raise src.error(f"particularize: unknown joint type {joint!r}; known: {', '.join(JOINT_TYPES)}", src.line_of("joint", line) or line)
        for role in between:
            if normalise_name(role) in marks:
                stage = marks[normalise_name(role)]
                raise src.error(f"particularize: role {role!r} marks the links that stage {stages.index(stage) + 1} "
                                f"({stage.name}) turns into a joint {stage.joint!r}; they are no links of the mechanism",
                                src.line_of(role, line) or line)
        clash = next((m for m in marks.values() if m.joint == joint), None)
        if clash is not None:
            raise src.error(f"particularize: joint {joint!r} is what stage {stages.index(clash) + 1} ({clash.name}) "
                            f"makes of the {clash.role!r} links; a mechanism could not tell the two apart",
                            src.line_of("joint", line) or line)
        particular.append(Particularization((normalise_name(between[0]), normalise_name(between[1])), joint))

    existing = []
    for i, raw in enumerate(data.get("existing", [])):
        line = src.table_line("existing", i)
        ref = raw.get("mechanism") if isinstance(raw, dict) else None
        if not isinstance(ref, str):
            raise src.error("existing: 'mechanism' must be a file path", line)
        try:
            mechanism = read_topology((Path(src.path).parent / ref).resolve())
        except DomesError as exc:
            raise src.error(f"existing design {ref!r}: {exc}", line) from None
        fewest, most = mechanism_links(links, stages)
        if not fewest <= mechanism.n <= most:
            made = f"{fewest}" if fewest == most else f"{fewest} to {most}"
            raise src.error(f"existing design {ref!r} has {mechanism.n} links; the scene's chains have {links}"
                            + (f", its mechanisms {made}" if (fewest, most) != (links, links) else ""), line)
        existing.append(mechanism)

    book = data.get("book", {})
    counts = tuple(book.get("counts", ()))
    if counts and len(counts) != len(stages):
        raise src.error(f"[book] counts has {len(counts)} entries for {len(stages)} stages", src.line_of("counts"))
    checks = []
    for i, raw in enumerate(data.get("checks", [])):
        line = src.table_line("checks", i)
        if not isinstance(raw, dict) or set(raw) != {"check", "why"} or not all(isinstance(v, str) for v in raw.values()):
            raise src.error("checks: each [[checks]] has a 'check' (a verify check: "
                            f"{'; '.join(USAGE)}) and a 'why'", line)
        if (raw["check"].split() or [""])[0] not in CHECKS:
            raise src.error(f"checks: {raw['check']!r} is not a verify check; they are {', '.join(USAGE)}", line)
        checks.append(SceneCheck(raw["check"], raw["why"]))
    requirements = _parse_requirements(src, data.get("requirements", []))
    design = _parse_design(src, data.get("design"), requirements, str(data.get("name", Path(src.path).stem)))
    return Scene(
        name=str(data.get("name", Path(src.path).stem)),
        title=str(data.get("title", data.get("name", ""))),
        source=str(data.get("source", "")),
        path=src.path,
        links=links,
        dof=dof,
        include_fractionated=fractionated,
        clamping=clamping,
        stages=stages,
        particularize=tuple(particular),
        existing=tuple(existing),
        book_counts=counts,
        book_note=str(book.get("note", "")),
        checks=tuple(checks),
        requirements=requirements,
        design=design,
    )


def _parse_requirements(src: TomlSource, raw) -> tuple[RequirementSpec, ...]:
    """The scene's ``[[requirements]]``: each a question of the design dialogue with its unit and default."""
    if not isinstance(raw, list):
        raise src.error("requirements: expected [[requirements]] tables", src.line_of("requirements"))
    specs = []
    for i, item in enumerate(raw):
        line = src.table_line("requirements", i)
        if not isinstance(item, dict) or not all(isinstance(v, str) for v in item.values()):
            raise src.error("requirements: each [[requirements]] has text values: "
                            f"{', '.join(sorted(_REQUIREMENT_KEYS))}", line)
        unknown = set(item) - _REQUIREMENT_KEYS
        if unknown or not {"id", "label", "kind"} <= set(item):
            raise src.error(f"requirements: a requirement has id, label and kind (and unit, default, help); "
                            f"got {', '.join(sorted(item))}", line)
        try:
            spec = RequirementSpec(item["id"], item["label"], item["kind"], item.get("unit", ""),
                                   item.get("default", ""), item.get("help", ""))
        except DomesError as exc:
            raise src.error(f"requirements: {exc}", line) from None
        if any(s.id == spec.id for s in specs):
            raise src.error(f"requirements: {spec.id!r} is declared twice", line)
        specs.append(spec)
    return tuple(specs)


def _mentions(src: TomlSource, needle: str, after: int) -> int:
    """The first line after ``after`` whose text holds ``needle`` (``after`` when none does)."""
    return next((n for n, text in enumerate(src.text.splitlines(), 1) if n > after and needle in text), after)


def _parse_design(src: TomlSource, raw, requirements, name) -> dict | None:
    """The scene's ``[design]``: a task template, checks and weights, tried with the requirements' defaults."""
    if raw is None:
        return None
    line = next((n for n, text in enumerate(src.text.splitlines(), 1) if text.strip().startswith("[design")), 0)
    if not isinstance(raw, dict) or not isinstance(raw.get("task"), dict) or set(raw) - _DESIGN_KEYS:
        raise src.error("[design] has a [design.task] table (a curve task, docs/synthesis.md), and optionally "
                        "[[design.checks]] and [design.weights]", line)
    declared = {s.id for s in requirements}
    for rid, _unit in sorted(placeholders([raw.get("task"), raw.get("checks", [])]), key=str):
        if rid not in declared:
            raise src.error(f"[design] names requirement {rid!r}, which [[requirements]] does not declare "
                            f"(declared: {', '.join(sorted(declared)) or 'none'})", _mentions(src, f"{{{rid}", line))
    checks = raw.get("checks", [])
    if not isinstance(checks, list):
        raise src.error("[design] checks: expected [[design.checks]] tables", line)
    try:
        weights_from(raw.get("weights", {}), "[design.weights]")
        defaults = {s.id: s.parse(s.default) for s in requirements if s.default}
        missing = declared - set(defaults)
        if not missing:  # every default given: the brief must build from them
            brief_from(name, raw["task"], checks, defaults, raw.get("weights"))
        else:
            for k, c in enumerate(checks, 1):
                if not placeholders(c):
                    check_spec(c, f"check {k}")
    except DomesError as exc:
        raise src.error(f"[design]: {exc}", line) from None
    return {"task": raw["task"], "checks": list(checks), "weights": dict(raw.get("weights", {}))}


def link_degrees(links: int, dof: int, fractionated: bool, clamping: bool = False) -> Degrees:
    """The numbers of joints the links of the scene's chains have, and what to call that range.

    Read off the atlas itself up to :data:`DEGREES_FROM_ATLAS` links (a tenth of a second); beyond, the
    bound of Table 3-1: at most L + 1 joints on a link of a chain without a cut link, 2L with one
    (and a clamping chain's: a link may be jointed to every other).
    """
    loops = (clamping_joints(links, dof) if clamping else chain_joints(links, dof)) - links + 1
    if links <= DEGREES_FROM_ATLAS:
        found = {d for n, edges in ChainGenerator().chains(links, dof, fractionated, clamping)
                 for d in Chain(n, edges).degrees}
        if found:
            return Degrees(frozenset(found), f"every link of the {links}-link chains of DOF {dof} has "
                           f"{_joints_text(found)} joints")
    top = links - 1 if clamping else 2 * loops if fractionated else loops + 1
    return Degrees(frozenset(range(2, top + 1)), f"a link of a {links}-link chain with {loops} loops has 2 to {top} joints")


def _joints_text(degrees) -> str:
    d = sorted(degrees)
    return str(d[0]) if len(d) == 1 else f"{d[0]} to {d[-1]}" if d == list(range(d[0], d[-1] + 1)) else ", ".join(map(str, d))


def _check_conversions(src: TomlSource, stages: tuple[Stage, ...]) -> None:
    """A role that marks links to become a joint is given by stages of one kind, joint and selection, and no two such
    roles make the same joint: each joint of a mechanism then comes from one marking (one labelled chain).

    The first stage of a role or a joint type is the one the error names; the line is the later stage's.
    """
    by_role: dict[str, tuple[int, Stage]] = {}
    by_joint: dict[str, tuple[int, Stage]] = {}
    for i, stage in enumerate(stages):
        if not stage.role:
            continue
        first = by_role.setdefault(stage.role, (i, stage))
        if (first[1].kind, first[1].joint, first[1].select) != (stage.kind, stage.joint, stage.select) and (
                first[1].is_conversion or stage.is_conversion):
            raise src.error(f"stage {i + 1}: role {stage.role!r} is given by stage {first[0] + 1} ({first[1].name}) as "
                            f"{_what(first[1])}; here it is {_what(stage)}: give this stage a role of its own",
                            stage.line)
        if stage.is_conversion:
            other = by_joint.setdefault(stage.joint, (i, stage))
            if other[1].role != stage.role:
                raise src.error(f"stage {i + 1}: joint {stage.joint!r} is made by stage {other[0] + 1} ({other[1].name}) "
                                f"of the {other[1].role!r} links; a mechanism could not tell the two apart: "
                                f"use role {other[1].role!r} here too", stage.line)


def _what(stage: Stage) -> str:
    """A stage's kind in words, for the errors of :func:`_check_conversions`."""
    if stage.kind == "role":
        return "a role"
    return f"a {stage.kind} ({stage.tag})"


def _parse_kind(src: TomlSource, i: int, raw: dict, line: int) -> tuple[str, str, str, str, bool]:
    """``(kind, role, select, joint, optional)`` of a stage; a stage without a kind and a role is a screen."""
    def at(key: str) -> int:
        return src.line_of(key, line) or line

    kind = raw.get("kind", "role")
    if kind not in KINDS:
        raise src.error(f"stage {i + 1}: kind must be one of {', '.join(KINDS)}, got {kind!r}", at("kind"))
    selections, joints = KINDS[kind]
    if kind == "role":
        for key in ("joint", "optional"):
            if key in raw:
                raise src.error(f"stage {i + 1}: {key!r} belongs to a stage of kind "
                                f"{', '.join(k for k in KINDS if k != 'role')}; this one gives a role", at(key))
    else:
        joint = raw.get("joint", joints[0] if kind == "joint type" else None)
        if joint not in joints:
            raise src.error(f"stage {i + 1}: a {kind} stage makes a joint {' or '.join(joints)} "
                            f"(joint = ...), got {joint!r}", at("joint") if "joint" in raw else line)
        optional = raw.get("optional", False)
        if not isinstance(optional, bool):
            raise src.error(f"stage {i + 1}: optional must be true or false, got {optional!r}", at("optional"))
    if kind == "joint type":
        if "role" in raw:
            raise src.error(f"stage {i + 1}: a joint type stage gives no role (its rules speak of joint types)",
                            at("role"))
        select = raw.get("select", "joint")
    elif "role" in raw:
        if not isinstance(raw["role"], str) or not normalise_name(raw["role"]).isidentifier():
            raise src.error(f"stage {i + 1}: 'role' must be a role name", at("role"))
        select = raw.get("select", "link")
    elif kind != "role":
        raise src.error(f"stage {i + 1}: a {kind} stage needs a 'role' to mark the links it turns into a joint "
                        f"(its rules speak of them by it)", line)
    else:
        if "select" in raw:
            raise src.error(f"stage {i + 1}: a screen (a stage without a role) selects nothing", at("select"))
        return kind, "", "screen", "", False
    if select not in selections:
        what = "" if kind == "role" else f" for a {kind} stage"
        raise src.error(f"stage {i + 1}: select must be one of {', '.join(selections)}{what}, got {select!r}",
                        at("select"))
    role = normalise_name(raw["role"]) if "role" in raw else ""
    return (kind, role, select, "", False) if kind == "role" else (kind, role, select, joint, optional)


def _parse_stage(src: TomlSource, i: int, raw: object, given_at: dict[str, int], degrees: Degrees) -> Stage:
    line = src.table_line("stages", i)
    if not isinstance(raw, dict):
        raise src.error(f"stage {i + 1} must be a table", line)
    for key in raw:
        if key not in _STAGE_KEYS:
            raise src.error(f"stage {i + 1}: unknown key {key!r}; a stage has {', '.join(sorted(_STAGE_KEYS))}", src.line_of(key, line) or line)
    kind, role, select, joint, optional = _parse_kind(src, i, raw, line)
    texts = raw.get("rules", [])
    if isinstance(texts, str):
        texts = [texts]
    if select == "screen" and not texts:
        raise src.error(f"stage {i + 1}: a stage needs a 'role' to give out, or 'rules' to screen by", line)
    trees = []
    for text in texts:
        at = src.line_of(text, line) or line
        if not isinstance(text, str):
            raise src.error(f"stage {i + 1}: rules must be sentences (strings)", at)
        try:
            tree = parse_criterion(text)
        except DomesError as exc:
            raise src.error(f"stage {i + 1}: rule {text!r}: {exc}", at) from None
        roles, _ = names_used(tree)
        for used in roles:
            if used not in given_at:
                known = sorted(r for r, k in given_at.items() if k <= i)
                raise src.error(f"stage {i + 1}: unknown role {used!r} in {text!r}; roles given out so far: {', '.join(known) or 'none'}", at)
            if given_at[used] > i:
                raise src.error(
                    f"stage {i + 1}: rule {text!r} cannot hold yet: role {used!r} is given out only at stage {given_at[used] + 1}",
                    at,
                )
        why = impossible_degree([tree], degrees)
        if why:
            raise src.error(f"stage {i + 1}: rule {text!r} cannot hold: {why}", at)
        trees.append(tree)
    why = impossible_degree(trees, degrees)
    if why:  # each rule alone can hold, together they cannot
        raise src.error(f"stage {i + 1}: rules {' and '.join(repr(t) for t in texts)} cannot hold together: {why}",
                        src.line_of(texts[0], line) or line)
    name = str(raw.get("name", role or (kind if kind != "role" else f"screen {i + 1}")))
    return Stage(name, role, select, tuple(trees), tuple(texts), tuple(compile_criterion(t) for t in trees), line,
                 kind, joint, optional)


