"""Mechanism topologies as designers write them: TOML files, Yan's MTM, the book's TYPE matrix.

A mechanism before generalization is a :class:`~domes.model.LabelledChain`
with names: named links (with roles such as ``ground``, ``input``,
``piston``, ``cylinder``) and named joints of the types in
:data:`~domes.model.JOINT_TYPES` (``R``, ``P``, gear ``G``, cam/higher pair
``C``, rolling ``O``, and the two-point elements spring ``S``, hydraulic
cylinder ``H``, force ``F`` / ``Fp`` / ``Fr`` acting between two links).

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

>>> m = from_mtm('''
... G R 0 R
... a L R 0
... 0 b L R
... d 0 c L''')
>>> [f"{m.joint_name(i)}:{t}" for i, t in enumerate(m.joint_types)]
['a:R', 'd:R', 'b:R', 'c:R']
>>> print(to_mtm(m))
G R 0 R
a L R 0
0 b L R
d 0 c L
"""

from __future__ import annotations

from pathlib import Path
from typing import Iterable

from domes.errors import DomesError, InputError
from domes.io.files import write_atomic
from domes.io.tomlsource import TomlSource
from domes.model.labelled import JOINT_TYPES, LabelledChain

#: MTM diagonal codes -> link role (``L``: an ordinary link).
MTM_LINK_CODES = {"G": "ground", "L": None, "P": "piston", "C": "cylinder"}
#: TYPE matrix columns (§5-3) that stand for a role: column -> role.
TYPE_COLUMNS = {"G": "ground", "E": "input", "H1": "cylinder", "H2": "piston", "HS": "HS"}


# -- TOML files -----------------------------------------------------------------------


def read_topology(path: str | Path) -> LabelledChain:
    """Read a mechanism topology file (TOML, see the module doc); errors name the file and line."""
    return parse_topology(TomlSource.read(path))


def parse_topology(src: TomlSource) -> LabelledChain:
    """A named labelled chain from a parsed TOML source."""
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
        return LabelledChain.from_named(data.get("name", Path(src.path).stem), parsed_links, parsed_joints,
                                        data.get("source", ""))
    except DomesError as exc:
        raise src.error(str(exc)) from None


def topology_toml(chain: LabelledChain) -> str:
    """The topology file text of a (named) labelled chain; :func:`read_topology` reads it back."""
    out = [f"name = {_q(chain.name or 'mechanism')}"]
    if chain.source:
        out.append(f"source = {_q(chain.source)}")
    for v, roles in enumerate(chain.roles):
        out += ["", "[[links]]", f"name = {_q(chain.link_name(v))}"]
        if roles:
            out.append("roles = [" + ", ".join(_q(r) for r in sorted(roles)) + "]")
    for i, ((a, b), kind) in enumerate(zip(chain.edges, chain.joint_types)):
        out += ["", "[[joints]]"]
        if chain.joint_names and chain.joint_names[i]:
            out.append(f"name = {_q(chain.joint_names[i])}")
        out.append(f"links = [{_q(chain.link_name(a))}, {_q(chain.link_name(b))}]")
        out.append(f"type = {_q(kind)}")
    return "\n".join(out) + "\n"


def write_topology(chain: LabelledChain, path: str | Path) -> None:
    """Write a topology file atomically."""
    write_atomic(path, topology_toml(chain))


def _q(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


# -- Yan's mechanism topology matrix (MTM) -------------------------------------------------


def from_mtm(text: str, name: str = "MTM", link_names: Iterable[str] | None = None) -> LabelledChain:
    """Read Yan's mechanism topology matrix (see the module doc); errors name the entry."""
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
    return LabelledChain.from_named(name, links, joints)


def to_mtm(chain: LabelledChain) -> str:
    """Yan's mechanism topology matrix of a labelled chain."""
    codes = {role: code for code, role in MTM_LINK_CODES.items() if role}
    matrix = [["0"] * chain.n for _ in range(chain.n)]
    for v, roles in enumerate(chain.roles):
        matrix[v][v] = next((codes[r] for r in ("ground", "piston", "cylinder") if r in roles), "L")
    for i, ((a, b), kind) in enumerate(zip(chain.edges, chain.joint_types)):
        matrix[a][b] = kind
        named = chain.joint_names[i] if chain.joint_names else ""
        matrix[b][a] = named or f"{chain.link_name(a)}{chain.link_name(b)}"
    width = max(len(x) for row in matrix for x in row)
    return "\n".join(" ".join(x.ljust(width) for x in row).rstrip() for row in matrix)


# -- the book's TYPE matrix (§5-3) -----------------------------------------------------------


def type_matrix(chain: LabelledChain) -> str:
    """The book's TYPE matrix (§5-3): link number, pairs, then one 0/1 column per mark.

    ``G`` ground, ``E`` driver (input), ``R`` a rolling pair on the link,
    ``P`` a prismatic pair on the link, ``H1``/``H2`` cylinder/piston,
    ``HS`` a higher-pair link; other roles get a column of their own.
    """
    joint_kinds: list[set[str]] = [set() for _ in range(chain.n)]
    for (a, b), kind in zip(chain.edges, chain.joint_types):
        joint_kinds[a].add(kind)
        joint_kinds[b].add(kind)
    role_of = dict(TYPE_COLUMNS)
    extra = sorted({r for roles in chain.roles for r in roles} - set(role_of.values()))
    columns = ["G", "E", "R", "P", "HS", "H1", "H2", *extra]
    values = []
    for v in range(chain.n):
        row = []
        for c in columns:
            if c == "R":
                row.append(int("O" in joint_kinds[v]))
            elif c == "P":
                row.append(int("P" in joint_kinds[v]))
            else:
                row.append(int(role_of.get(c, c) in chain.roles[v]))
        values.append(row)
    used = [i for i, c in enumerate(columns) if any(r[i] for r in values)]
    lines = [" ".join(["M", "N"] + [columns[i] for i in used])]
    for v in range(chain.n):
        lines.append(" ".join([chain.link_name(v), str(chain.degrees[v])] + [str(values[v][i]) for i in used]))
    return "\n".join(lines)


def from_type_matrix(adjacency: str, type_text: str, name: str = "TYPE") -> LabelledChain:
    """A labelled chain from its adjacency matrix (0/1 rows) and TYPE matrix (header row ``M N ...``).

    >>> m = from_type_matrix("0 1 1\\n1 0 1\\n1 1 0", "M N G E\\n1 2 1 0\\n2 2 0 1\\n3 2 0 0")
    >>> [sorted(r) for r in m.roles]
    [['ground'], ['input'], []]
    """
    rows = [line.split() for line in adjacency.strip().splitlines() if line.strip()]
    size = len(rows)
    if any(len(r) != size or any(x not in ("0", "1") for x in r) for r in rows):
        raise InputError("the adjacency matrix must be square with entries 0 and 1")
    table = [line.split() for line in type_text.strip().splitlines() if line.strip()]
    if not table:
        raise InputError("the TYPE matrix is empty: it needs a header row 'M N ...' and one row per link")
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
    chain = LabelledChain.from_named(name, links, joints)
    for v, row in enumerate(body):
        if row[1] != str(chain.degrees[v]):
            raise InputError(f"TYPE matrix: link {row[0]} has N={row[1]} but {chain.degrees[v]} joints in the adjacency matrix")
    return chain
