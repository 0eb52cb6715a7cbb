"""Mechanism descriptions: links with roles, joints with types; MTM and TYPE matrices.

A :class:`Mechanism` is what a designer draws before generalization: named
links (with roles such as ``ground``, ``input``, ``piston``, ``cylinder``)
and named joints of the types in :data:`~domes.model.labelled.JOINT_TYPES`
(``R``, ``P``, gear ``G``, cam/higher pair ``C``, rolling ``O``, and the
two-point elements spring ``S``, hydraulic cylinder ``H``, force ``F`` /
``Fp`` / ``Fr`` acting between two links).

File format (TOML; examples in ``knowledge/mechanisms/``)::

    name = "four-bar"
    [[links]]
    name = "1"
    roles = ["ground"]
    [[links]]
    name = "2"
    roles = ["input"]
    ...
    [[joints]]
    name = "a"          # optional
    links = ["1", "2"]
    type = "R"          # optional, R by default

Yan's **mechanism topology matrix** (MTM, seed 002 §4-1) is an N×N text
matrix: the diagonal holds the link type (``G`` ground, ``L`` link, ``P``
piston, ``C`` cylinder), above it the joint type of adjacent links, below
it the joint's name, ``0`` elsewhere.

>>> m = Mechanism.from_mtm('''
... G R 0 R
... a L R 0
... 0 b L R
... d 0 c L''')
>>> [j.name + ":" + j.type for j in m.joints]
['a:R', 'd:R', 'b:R', 'c:R']
>>> print(m.to_mtm())
G R 0 R
a L R 0
0 b L R
d 0 c L
"""

from __future__ import annotations

import os
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Iterable

from domes.errors import DomesError, InputError
from domes.model.labelled import JOINT_TYPES, LabelledChain
from domes.io.tomlsource import TomlSource

#: MTM diagonal codes -> link role (``L``: an ordinary link).
MTM_LINK_CODES = {"G": "ground", "L": None, "P": "piston", "C": "cylinder"}
#: TYPE matrix columns (§5-3) that stand for a role: column -> role.
TYPE_COLUMNS = {"G": "ground", "E": "input", "H1": "cylinder", "H2": "piston", "HS": "HS"}


@dataclass(frozen=True)
class Joint:
    """A joint between two links (by index), with a type and a name."""

    links: tuple[int, int]
    type: str = "R"
    name: str = ""


@dataclass(frozen=True)
class Mechanism:
    """A mechanism sketch reduced to its topology: named links with roles, typed joints."""

    name: str
    link_names: tuple[str, ...]
    link_roles: tuple[frozenset[str], ...]
    joints: tuple[Joint, ...]
    source: str = ""

    # -- construction ----------------------------------------------------------

    @classmethod
    def build(
        cls,
        name: str,
        links: Iterable[tuple[str, Iterable[str]]],
        joints: Iterable[tuple[str, str, str, str]],
        source: str = "",
    ) -> "Mechanism":
        """From ``(link name, roles)`` and ``(joint name, link a, link b, type)`` tuples.

        >>> Mechanism.build("pair", [("1", ["ground"]), ("2", [])], [("a", "1", "2", "R")]).joints
        (Joint(links=(0, 1), type='R', name='a'),)
        """
        names, roles = [], []
        for link_name, link_roles in links:
            link_name = str(link_name)
            if link_name in names:
                raise InputError(f"mechanism {name!r}: link {link_name!r} is defined twice")
            names.append(link_name)
            roles.append(frozenset(str(r) for r in link_roles))
        index = {n: i for i, n in enumerate(names)}
        built, seen = [], {}
        for joint_name, a, b, kind in joints:
            label = joint_name or f"{a}-{b}"
            for end in (a, b):
                if str(end) not in index:
                    raise InputError(f"mechanism {name!r}, joint {label!r}: unknown link {end!r} (links: {', '.join(names)})")
            if str(a) == str(b):
                raise InputError(f"mechanism {name!r}, joint {label!r}: a joint needs two different links")
            if kind not in JOINT_TYPES:
                raise InputError(f"mechanism {name!r}, joint {label!r}: unknown type {kind!r}; known: {', '.join(JOINT_TYPES)}")
            pair = tuple(sorted((index[str(a)], index[str(b)])))
            if pair in seen:
                raise InputError(f"mechanism {name!r}, joint {label!r}: links {a} and {b} are already joined by {seen[pair]!r}")
            seen[pair] = label
            built.append(Joint(pair, kind, str(joint_name)))
        return cls(str(name), tuple(names), tuple(roles), tuple(built), str(source))

    @classmethod
    def load(cls, path: str | Path) -> "Mechanism":
        """Read a mechanism file (TOML, see the module doc)."""
        return cls.from_toml(TomlSource.read(path))

    @classmethod
    def from_toml(cls, src: TomlSource) -> "Mechanism":
        data = src.data
        links = data.get("links")
        if not isinstance(links, list) or not links:
            raise src.error("a mechanism needs [[links]] tables, each with a name", src.line_of("links"))
        parsed_links = []
        for i, link in enumerate(links):
            line = src.table_line("links", i)
            if not isinstance(link, dict) or "name" not in link:
                raise src.error(f"link {i + 1} has no name", line)
            roles = link.get("roles", [])
            if not isinstance(roles, list) or not all(isinstance(r, str) for r in roles):
                raise src.error(f"link {link['name']!r}: roles must be a list of names", line)
            parsed_links.append((str(link["name"]), roles))
        parsed_joints = []
        for i, joint in enumerate(data.get("joints", [])):
            line = src.table_line("joints", i)
            ends = joint.get("links") if isinstance(joint, dict) else None
            if not isinstance(ends, list) or len(ends) != 2:
                raise src.error(f"joint {i + 1}: 'links' must name two links", line)
            parsed_joints.append((str(joint.get("name", "")), str(ends[0]), str(ends[1]), str(joint.get("type", "R"))))
        try:
            return cls.build(data.get("name", Path(src.path).stem), parsed_links, parsed_joints, data.get("source", ""))
        except DomesError as exc:
            raise src.error(str(exc)) from None

    # -- views -----------------------------------------------------------------

    @property
    def n(self) -> int:
        return len(self.link_names)

    def labelled(self, roles: Iterable[str] | None = None) -> LabelledChain:
        """The mechanism as a labelled chain (joint types kept; roles filtered to ``roles`` if given)."""
        keep = None if roles is None else set(roles)
        return LabelledChain.build(
            self.n,
            [j.links for j in self.joints],
            [j.type for j in self.joints],
            {v: (r if keep is None else r & keep) for v, r in enumerate(self.link_roles)},
        )

    def to_toml(self) -> str:
        """The mechanism file text (inverse of :meth:`load`)."""
        out = [f"name = {_q(self.name)}"]
        if self.source:
            out.append(f"source = {_q(self.source)}")
        for name, roles in zip(self.link_names, self.link_roles):
            out += ["", "[[links]]", f"name = {_q(name)}"]
            if roles:
                out.append("roles = [" + ", ".join(_q(r) for r in sorted(roles)) + "]")
        for j in self.joints:
            out += ["", "[[joints]]"]
            if j.name:
                out.append(f"name = {_q(j.name)}")
            out.append(f"links = [{_q(self.link_names[j.links[0]])}, {_q(self.link_names[j.links[1]])}]")
            out.append(f"type = {_q(j.type)}")
        return "\n".join(out) + "\n"

    def save(self, path: str | Path) -> None:
        """Write the mechanism file atomically."""
        write_atomic(Path(path), self.to_toml())

    # -- MTM ---------------------------------------------------------------------

    @classmethod
    def from_mtm(cls, text: str, name: str = "MTM", link_names: Iterable[str] | None = None) -> "Mechanism":
        """Read Yan's mechanism topology matrix (see the module doc)."""
        rows = [line.split() for line in text.strip().splitlines() if line.strip()]
        size = len(rows)
        for r, row in enumerate(rows, 1):
            if len(row) != size:
                raise InputError(f"MTM row {r} has {len(row)} entries; a {size}x{size} matrix needs {size}")
        names = list(link_names) if link_names is not None else [str(i + 1) for i in range(size)]
        links, joints = [], []
        for i in range(size):
            code = rows[i][i]
            if code not in MTM_LINK_CODES:
                raise InputError(f"MTM ({i + 1},{i + 1}): unknown link type {code!r}; known: {', '.join(MTM_LINK_CODES)}")
            role = MTM_LINK_CODES[code]
            links.append((names[i], [role] if role else []))
        for i in range(size):
            for k in range(i + 1, size):
                kind, label = rows[i][k], rows[k][i]
                if (kind == "0") != (label == "0"):
                    raise InputError(
                        f"MTM ({i + 1},{k + 1})={kind!r} but ({k + 1},{i + 1})={label!r}: a joint needs both its type "
                        "above the diagonal and its name below it"
                    )
                if kind != "0":
                    if kind not in JOINT_TYPES:
                        raise InputError(f"MTM ({i + 1},{k + 1}): unknown joint type {kind!r}")
                    joints.append((label, names[i], names[k], kind))
        return cls.build(name, links, joints)

    def to_mtm(self) -> str:
        """Yan's mechanism topology matrix of this mechanism."""
        codes = {role: code for code, role in MTM_LINK_CODES.items() if role}
        matrix = [["0"] * self.n for _ in range(self.n)]
        for v, roles in enumerate(self.link_roles):
            matrix[v][v] = next((codes[r] for r in ("ground", "piston", "cylinder") if r in roles), "L")
        for j in self.joints:
            a, b = j.links
            matrix[a][b] = j.type
            matrix[b][a] = j.name or f"{self.link_names[a]}{self.link_names[b]}"
        width = max(len(x) for row in matrix for x in row)
        return "\n".join(" ".join(x.ljust(width) for x in row).rstrip() for row in matrix)

    # -- TYPE matrix ---------------------------------------------------------------

    def type_matrix(self) -> str:
        """The book's TYPE matrix (§5-3): link number, pairs, then one 0/1 column per mark.

        ``G`` ground, ``E`` driver (input), ``R`` a rolling pair on the link,
        ``P`` a prismatic pair on the link, ``H1``/``H2`` cylinder/piston,
        ``HS`` a higher-pair link; other roles get a column of their own.
        """
        degree = [0] * self.n
        joint_kinds: list[set[str]] = [set() for _ in range(self.n)]
        for j in self.joints:
            for v in j.links:
                degree[v] += 1
                joint_kinds[v].add(j.type)
        role_of = dict(TYPE_COLUMNS)
        extra = sorted({r for roles in self.link_roles for r in roles} - set(role_of.values()))
        columns = ["G", "E", "R", "P", "HS", "H1", "H2", *extra]
        values = []
        for v in range(self.n):
            row = []
            for c in columns:
                if c == "R":
                    row.append(int("O" in joint_kinds[v]))
                elif c == "P":
                    row.append(int("P" in joint_kinds[v]))
                else:
                    row.append(int(role_of.get(c, c) in self.link_roles[v]))
            values.append(row)
        used = [i for i, c in enumerate(columns) if any(r[i] for r in values)]
        header = ["M", "N"] + [columns[i] for i in used]
        lines = [" ".join(header)]
        for v in range(self.n):
            lines.append(" ".join([self.link_names[v], str(degree[v])] + [str(values[v][i]) for i in used]))
        return "\n".join(lines)

    @classmethod
    def from_type_matrix(cls, adjacency: str, type_text: str, name: str = "TYPE") -> "Mechanism":
        """A mechanism from its adjacency matrix (0/1 rows) and TYPE matrix (header row ``M N ...``).

        >>> m = Mechanism.from_type_matrix("0 1 1\\n1 0 1\\n1 1 0", "M N G E\\n1 2 1 0\\n2 2 0 1\\n3 2 0 0")
        >>> [sorted(r) for r in m.link_roles]
        [['ground'], ['input'], []]
        """
        rows = [line.split() for line in adjacency.strip().splitlines() if line.strip()]
        size = len(rows)
        if any(len(r) != size or any(x not in ("0", "1") for x in r) for r in rows):
            raise InputError("the adjacency matrix must be square with entries 0 and 1")
        table = [line.split() for line in type_text.strip().splitlines() if line.strip()]
        header, body = table[0], table[1:]
        if header[:2] != ["M", "N"]:
            raise InputError(f"TYPE matrix header must start with 'M N', got {' '.join(header[:2])!r}")
        if len(body) != size:
            raise InputError(f"TYPE matrix has {len(body)} rows for {size} links")
        links = []
        for r, row in enumerate(body, 2):
            if len(row) != len(header):
                raise InputError(f"TYPE matrix line {r}: {len(row)} entries for {len(header)} columns")
            roles = [TYPE_COLUMNS.get(c, c) for c, x in zip(header[2:], row[2:]) if x == "1" and c not in ("R", "P")]
            links.append((row[0], roles))
        names = [row[0] for row in body]
        joints = [("", names[i], names[k], "R") for i in range(size) for k in range(i + 1, size) if rows[i][k] == "1"]
        mechanism = cls.build(name, links, joints)
        degree = [0] * size
        for j in mechanism.joints:
            for v in j.links:
                degree[v] += 1
        for v, row in enumerate(body):
            if row[1] != str(degree[v]):
                raise InputError(f"TYPE matrix: link {row[0]} has N={row[1]} but {degree[v]} joints in the adjacency matrix")
        return mechanism


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def write_atomic(path: Path, text: str) -> None:
    """Write ``text`` to ``path`` through a temporary file and a rename."""
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", dir=path.parent)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as handle:
            handle.write(text)
        os.replace(tmp, path)
    except BaseException:
        os.unlink(tmp)
        raise
