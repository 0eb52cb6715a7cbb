"""Design scenes as data: the rules of a regeneration, read from TOML.

A scene names the chains to start from, the stages that assign roles (each
stage picks a link, or a pair of links, under ``where`` conditions; see
:mod:`domes.regeneration.rules`), screens that filter, how to particularize
the chosen roles back into joints (e.g. the joint inside the shock absorber
becomes prismatic), the existing designs to recognise, and the book's counts
to print beside ours. The shipped scenes are in ``knowledge/scenes/``; the
format is documented in ``docs/regeneration.md``.

>>> scene = load_scene("motorcycle")
>>> [s.name for s in scene.stages]
['ground', 'shock absorber', 'swing arm', 'swing arm adjacent to ground']
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from domes.errors import DomesError
from domes.labelled.graph import JOINT_TYPES
from domes.labelled.mechanism import Mechanism
from domes.labelled.tomlsource import TomlSource
from domes.paths import knowledge_dir
from domes.regeneration.rules import Condition, impossible, parse_condition
from domes.synthesis.number import chain_joints

SELECTIONS = ("link", "adjacent pair", "pair")
_STAGE_KEYS = {"name", "role", "select", "where", "screen", "note"}
_TOP_KEYS = {"name", "title", "source", "chains", "stages", "particularize", "existing", "book"}


@dataclass(frozen=True)
class Stage:
    """One divergence stage (``role`` is assigned) or one screen (``screen`` role is tested)."""

    name: str
    role: str
    select: str  # one of SELECTIONS, or "screen"
    where: tuple[Condition, ...]
    where_text: tuple[str, ...]
    line: int

    @property
    def is_screen(self) -> bool:
        return self.select == "screen"


@dataclass(frozen=True)
class Particularization:
    """The joint between a link of role ``between[0]`` and one of ``between[1]`` becomes ``joint``."""

    between: tuple[str, str]
    joint: str


@dataclass(frozen=True)
class Scene:
    """A regeneration scene (see the module doc)."""

    name: str
    title: str
    source: str
    path: str
    links: int
    dof: int
    include_fractionated: bool
    stages: tuple[Stage, ...]
    particularize: tuple[Particularization, ...]
    existing: tuple[Mechanism, ...]
    book_counts: tuple[int | None, ...]
    book_note: str

    @property
    def roles(self) -> list[str]:
        """The roles the stages assign, in stage order."""
        return [s.role for s in self.stages if not s.is_screen]


def scene_names() -> list[str]:
    """Names of the shipped scenes."""
    return sorted(p.stem for p in (knowledge_dir() / "scenes").glob("*.toml"))


def load_scene(name_or_path: str | Path) -> Scene:
    """A scene by name (``knowledge/scenes/NAME.toml``) or by file path."""
    path = Path(name_or_path)
    if not path.is_file():
        candidate = knowledge_dir() / "scenes" / f"{name_or_path}.toml"
        if not candidate.is_file():
            raise DomesError(f"no scene {str(name_or_path)!r}: not a file, and not one of: {', '.join(scene_names())}")
        path = candidate
    return parse_scene(TomlSource.read(path))


def parse_scene(src: TomlSource) -> Scene:
    """Validate a scene; every error names the file and the line."""
    data = src.data
    for key in data:
        if key not in _TOP_KEYS:
            raise src.error(f"unknown key {key!r}; a scene has {', '.join(sorted(_TOP_KEYS))}", src.line_of(key))
    chains = data.get("chains")
    if not isinstance(chains, dict) or "links" not in chains or "dof" not in chains:
        raise src.error("a scene needs a [chains] table with links and dof", src.line_of("chains"))
    links, dof = chains["links"], chains["dof"]
    if not isinstance(links, int) or not isinstance(dof, int):
        raise src.error("[chains] links and dof must be integers", src.line_of("links"))
    try:
        chain_joints(links, dof)
    except DomesError as exc:
        raise src.error(str(exc), src.line_of("links")) from None

    stages: list[Stage] = []
    raw_stages = data.get("stages", [])
    if not isinstance(raw_stages, list) or not raw_stages:
        raise src.error("a scene needs at least one [[stages]] table")
    assigned_at: dict[str, int] = {}
    for i, raw in enumerate(raw_stages):
        if isinstance(raw, dict) and "role" in raw and "screen" not in raw:
            assigned_at.setdefault(str(raw["role"]), i)
    for i, raw in enumerate(raw_stages):
        stages.append(_parse_stage(src, i, raw, assigned_at, links))

    roles = {s.role for s in stages if not s.is_screen}
    particular = []
    for i, raw in enumerate(data.get("particularize", [])):
        line = src.table_line("particularize", i)
        between, joint = raw.get("between"), raw.get("joint")
        if not (isinstance(between, list) and len(between) == 2):
            raise src.error("particularize: 'between' must name two roles", line)
        for role in between:
            if role not in roles:
                raise src.error(f"particularize: unknown role {role!r}; the stages assign {', '.join(sorted(roles))}", src.line_of(role, line) or line)
        if joint not in JOINT_TYPES:
            raise src.error(f"particularize: unknown joint type {joint!r}; known: {', '.join(JOINT_TYPES)}", src.line_of("joint", line) or line)
        particular.append(Particularization((str(between[0]), str(between[1])), joint))

    existing = []
    for i, raw in enumerate(data.get("existing", [])):
        line = src.table_line("existing", i)
        ref = raw.get("mechanism") if isinstance(raw, dict) else None
        if not isinstance(ref, str):
            raise src.error("existing: 'mechanism' must be a file path", line)
        path = (Path(src.path).parent / ref).resolve()
        try:
            mechanism = Mechanism.load(path)
        except DomesError as exc:
            raise src.error(f"existing design {ref!r}: {exc}", line) from None
        if mechanism.n != links:
            raise src.error(f"existing design {ref!r} has {mechanism.n} links; the scene's chains have {links}", line)
        existing.append(mechanism)

    book = data.get("book", {})
    counts = tuple(book.get("counts", ()))
    if counts and len(counts) != len(stages):
        raise src.error(f"[book] counts has {len(counts)} entries for {len(stages)} stages", src.line_of("counts"))
    return Scene(
        name=str(data.get("name", Path(src.path).stem)),
        title=str(data.get("title", data.get("name", ""))),
        source=str(data.get("source", "")),
        path=src.path,
        links=links,
        dof=dof,
        include_fractionated=bool(chains.get("include_fractionated", False)),
        stages=tuple(stages),
        particularize=tuple(particular),
        existing=tuple(existing),
        book_counts=counts,
        book_note=str(book.get("note", "")),
    )


def _parse_stage(src: TomlSource, i: int, raw: object, assigned_at: dict[str, int], links: int) -> Stage:
    line = src.table_line("stages", i)
    if not isinstance(raw, dict):
        raise src.error(f"stage {i + 1} must be a table", line)
    for key in raw:
        if key not in _STAGE_KEYS:
            raise src.error(f"stage {i + 1}: unknown key {key!r}; a stage has {', '.join(sorted(_STAGE_KEYS))}", src.line_of(key, line) or line)
    if "screen" in raw:
        role, select = raw["screen"], "screen"
        if role not in assigned_at or assigned_at[role] > i:
            known = sorted(r for r, at in assigned_at.items() if at < i)
            raise src.error(f"stage {i + 1}: screen of unknown role {role!r}; roles assigned before it: {', '.join(known) or 'none'}", src.line_of(role, line) or line)
    else:
        role = raw.get("role")
        if not isinstance(role, str) or not role.isidentifier():
            raise src.error(f"stage {i + 1}: 'role' must be a role name (letters, digits, _)", src.line_of("role", line) or line)
        select = raw.get("select", "link")
        if select not in SELECTIONS:
            raise src.error(f"stage {i + 1}: select must be one of {', '.join(SELECTIONS)}, got {select!r}", src.line_of("select", line) or line)
    texts = raw.get("where", [])
    if isinstance(texts, str):
        texts = [texts]
    conditions = []
    for text in texts:
        at = src.line_of(text, line) or line
        try:
            condition = parse_condition(text)
        except DomesError as exc:
            raise src.error(f"stage {i + 1}: {exc}", at) from None
        for used in sorted(condition.roles()):
            if used not in assigned_at:
                known = sorted(r for r, k in assigned_at.items() if k < i)
                raise src.error(f"stage {i + 1}: unknown role {used!r} in {text!r}; roles assigned before this stage: {', '.join(known) or 'none'}", at)
            if assigned_at[used] > i or (assigned_at[used] == i and select != "screen"):
                raise src.error(
                    f"stage {i + 1}: {text!r} cannot hold: role {used!r} is assigned only at stage {assigned_at[used] + 1}, "
                    "after this choice is made",
                    at,
                )
        conditions.append(condition)
    why = impossible(conditions, links)
    if why:
        raise src.error(f"stage {i + 1}: the conditions {list(texts)} cannot hold: {why}", src.line_of("where", line) or line)
    name = str(raw.get("name", f"{role} {select}" if select != "screen" else f"screen {role}"))
    return Stage(name, role, select, tuple(conditions), tuple(texts), line)
