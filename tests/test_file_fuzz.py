"""No traceback, no hang, no silent NaN (issue 25): damaged and hostile files for every command that reads one.

Each file format starts from a shipped example (mechanisms, spatial mechanisms, dynamics and scriber files,
synthesis tasks, wanted paths in CSV and JSON, coupler-curve atlases in HDF5); a seeded generator damages one
thing at a time: a key dropped, a value of the wrong type (null, a list for a number, a string for a list),
NaN, infinity, 1e300, an integer of 400 or 5,000 digits, a negative or zero size, an empty or duplicated list,
200,000 elements, a string of 200,000 characters, JSON nested 1,000 deep; and the whole file: empty, binary
junk, cut in half, not UTF-8. Paths also get extra columns, a quoted junk line, 20,000 and 200,000 points, the
path traced twice, every point doubled, a degenerate (one point, a line) or scaled (1e300, 1e-300) path; atlases
get columns dropped, emptied, reshaped or filled with NaN, and their metadata every JSON damage.

Every run is a forked child of this test process (the package already imported, so a run costs only its work),
ended after :data:`TIMEOUT` seconds of processor time, with a cap on its memory. It must end as the command line
ends: status 0, 1 or 2, no traceback, no line on stderr longer than :data:`MAX_LINE` characters; and a run that
ends with 0 must not print NaN or infinity unless its output says why. ``DOMES_FULL_TESTS=1`` runs every damage
(4,971 runs; docs/architecture.md, "Damaged and hostile files"); otherwise :data:`CI_RUNS` of them, spread over
the files and the kinds of damage (tests/sampling.py).
"""

from __future__ import annotations

import copy
import json
import os
import random
import re
import resource
import shutil
import signal
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

from tests.sampling import FULL
from tests.shared import TRACEBACK, forked_main

ROOT = Path(__file__).resolve().parents[1]
#: Seconds of processor time a run may take before it counts as a hang (processor time, not the clock's, so that a
#: machine busy with other work does not fail a run); a run still going after three times as long on the clock (one
#: that waits rather than works) counts as a hang too.
TIMEOUT = 60
#: The longest line a run may print on stderr.
MAX_LINE = 500
#: Memory a run may take beyond what this process holds (a run past it fails with a MemoryError traceback).
MEMORY = 3 << 30
#: Runs in the sample of a test run that is not a full one (enough to meet every target and kind of damage).
CI_RUNS = 90
SEED = 25
HUGE = 200_000


@dataclass(frozen=True)
class Target:
    """A file format's example and the commands that read it (``FILE``: the damaged file)."""

    name: str
    source: str
    commands: tuple[tuple[str, ...], ...]
    kind: str = "json"  # json, csv or h5
    trim: tuple = ()  # (path, value) pairs set in the example first, to keep a run short


MECH = "examples/mechanisms/"
SYN = "examples/synthesis/"
MATCH = ("curves", "match", "FILE", "--atlas", "ATLAS", "--candidates", "4", "--results", "1")
TARGETS = [
    Target("four-bar", MECH + "four-bar.json", (
        ("kinematics", "FILE", "--sweep", "0:360:30"),
        ("tolerance", "FILE", "--output", "angle:rocker", "--sweep", "0:90:45", "--samples", "200", "--relative", "1e-4"),
        ("draw", "FILE", "--coupler", "P"),
        ("curves", "trace", "FILE", "--samples", "90"),
        ("curves", "describe", "FILE", "--samples", "90"))),
    Target("slider-crank", MECH + "slider-crank.json", (
        ("kinematics", "FILE", "--sweep", "0:360:30", "--order", "2"),
        ("tolerance", "FILE", "--output", "point:M", "--sweep", "0:90:45", "--samples", "200", "--relative", "1e-4"),
        ("draw", "FILE"))),
    Target("stephenson-six-bar", MECH + "stephenson-six-bar.json", (
        ("kinematics", "FILE", "--sweep", "0:360:30"), ("draw", "FILE"))),
    Target("swing-arm-shock", MECH + "swing-arm-shock.json", (
        ("kinematics", "FILE", "--sweep", "3:3.4:0.1"), ("draw", "FILE"))),
    Target("engine", "examples/dynamics/slider-crank-engine.json", (
        ("dynamics", "FILE", "--sweep", "0:90:45"), ("dynamics", "FILE", "--sweep", "0:360:90", "--format", "json"))),
    Target("scriber", "examples/dynamics/scriber-stadium.json", (
        ("dynamics", "FILE"), ("dynamics", "FILE", "--points", "200", "--format", "json")),
        trim=((("points",), 400),)),
    Target("rssr", "examples/spatial/rssr-seed001.json", (
        ("kinematics", "FILE", "--sweep", "0:360:60"), ("draw", "FILE"))),
    Target("rccc", "examples/spatial/rccc-planted.json", (("kinematics", "FILE", "--sweep", "0:80:20"),)),
    *(Target(f"task {name}", SYN + f"{name}.json", (("synthesize", "FILE"),))
      for name in ("ch2-example-2", "ch2-example-2-slider", "ch2-example-3-spherical", "ch2-example-4",
                   "ch2-example-5", "log10", "rccc-planted", "rccc-table-1", "spherical-function")),
    # fast: 512 random starts instead of 4,096 (the default command runs clean in docs/synthesis.md's commands)
    Target("task path-twelve-points", SYN + "path-twelve-points.json",
           (("synthesize", "FILE", "--format", "json", "--method", "fast"),)),
    Target("task guiding-link-rr", SYN + "guiding-link-rr.json", (("synthesize", "FILE"),), trim=((("starts",), 8),)),
    Target("task rising-rate", SYN + "rising-rate.json", (("synthesize", "FILE"),),
           trim=((("candidates",), [1]), (("wanted", "samples"), 9))),
    Target("path csv", "examples/curves/figure-eight.csv", (MATCH, ("curves", "describe", "FILE")), kind="csv"),
    Target("open path csv", "examples/curves/stretch.csv",
           (("curves", "match", "FILE", "--atlas", "OPEN", "--open", "--candidates", "4", "--results", "1"),),
           kind="csv"),
    Target("path json", "PATH.json", (MATCH, ("curves", "describe", "FILE"))),
    Target("atlas", "ATLAS", (("curves", "atlas", "info", "--file", "FILE"),
                              ("curves", "match", "examples/curves/figure-eight.csv", "--atlas", "FILE",
                               "--candidates", "4", "--results", "1")), kind="h5"),
    Target("open atlas", "OPEN", (("curves", "match", "examples/curves/stretch.csv", "--open", "--atlas", "FILE",
                                   "--candidates", "4", "--results", "1"),), kind="h5"),
]

# -- damage ---------------------------------------------------------------------------------------

#: Damage to a whole file, any format.
FILE_KINDS = ("empty", "binary junk", "cut in half", "not UTF-8")
#: Damage to one value of a JSON document (or of an atlas's metadata).
VALUE_KINDS = ("dropped", "null", "list for number", "string for list", "string for object", "NaN", "inf", "-inf",
               "1e300", "int 10**400", "int of 5000 digits", "negative", "zero", "empty list", "duplicated",
               f"{HUGE:,} elements", "long string", "true", "nested 1000 deep")
#: Damage to a JSON document as a whole.
JSON_KINDS = ("nested 1000 deep", "a list around it", "a number")
#: Damage to a path of points in CSV.
CSV_KINDS = ("extra columns", "quoted junk line", "unterminated quote", "20,000 points", f"{HUGE:,} points",
             "traced twice", "every point doubled", "one point", "two points", "all points equal", "a line",
             "scaled 1e300", "scaled 1e-300", "NaN cell", "inf cell", "1e300 cell", "int of 400 digits",
             "only a header", "semicolons", "a 1 MB line")
#: Damage to an atlas's columns.
H5_KINDS = ("dropped", "NaN", "inf", "1e300", "negative", "no rows", "one dimension", "strings", "meta not JSON",
            "meta missing")

_BIGINT = "1" + "0" * 5000
_DEEP = "[" * 1000 + "]" * 1000


def _sites(doc, path=()):
    """Every place in a JSON document: keys of objects; the first and last element of lists."""
    yield path, doc
    if isinstance(doc, dict):
        for key, value in doc.items():
            yield from _sites(value, (*path, key))
    elif isinstance(doc, list):
        for k in sorted({0, len(doc) - 1}) if doc else ():
            yield from _sites(doc[k], (*path, k))


def _applies(kind: str, value, path) -> bool:
    number = isinstance(value, (int, float)) and not isinstance(value, bool)
    if not path:
        return False
    return {"dropped": True, "null": True, "list for number": number, "string for list": isinstance(value, list),
            "string for object": isinstance(value, dict), "NaN": number, "inf": number, "-inf": number,
            "1e300": number, "int 10**400": number, "int of 5000 digits": number, "negative": number,
            "zero": number, "empty list": isinstance(value, list), "duplicated": isinstance(value, list) and value,
            f"{HUGE:,} elements": isinstance(value, list) and value, "long string": isinstance(value, str),
            "true": number, "nested 1000 deep": isinstance(value, (list, dict))}[kind]


def _damaged(kind: str, value):
    """The damaged value, or a placeholder string for what ``json.dumps`` cannot write."""
    if kind == "list for number":
        return [value, value]
    if kind == "string for list":
        return "x, y"
    if kind == "string for object":
        return "{}"
    if kind in ("NaN", "inf", "-inf", "1e300"):
        return float(kind)
    if kind == "int 10**400":
        return 10 ** 400
    if kind == "int of 5000 digits":
        return "@@BIGINT@@"
    if kind == "negative":
        return -abs(value) if value else -1
    if kind == "zero":
        return 0
    if kind == "empty list":
        return []
    if kind == "duplicated":
        return [v for v in value for _ in (0, 1)] if _points(value) else [value[0], *value]
    if kind == f"{HUGE:,} elements":
        if _points(value):
            return _resample(np.array(value, float), HUGE).tolist()
        return (value * (HUGE // len(value) + 1))[:HUGE]
    if kind == "long string":
        return "x" * HUGE
    if kind == "true":
        return True
    if kind == "nested 1000 deep":
        return "@@DEEP@@"
    return None  # null


def _points(value) -> bool:
    return (isinstance(value, list) and len(value) >= 2
            and all(isinstance(p, list) and len(p) in (2, 3) and all(isinstance(v, (int, float)) for v in p)
                    for p in value))


def _resample(points: np.ndarray, count: int) -> np.ndarray:
    """``count`` points spread along the polyline ``points`` (its last point joined to its first)."""
    ring = np.vstack([points, points[:1]])
    s = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(ring, axis=0), axis=1))])
    t = np.linspace(0, s[-1], count, endpoint=False)
    return np.column_stack([np.interp(t, s, ring[:, k]) for k in range(points.shape[1])])


def _json_text(doc) -> str:
    return (json.dumps(doc, indent=1).replace('"@@BIGINT@@"', _BIGINT).replace('"@@DEEP@@"', _DEEP))


def _set(doc, path, kind):
    doc = copy.deepcopy(doc)
    *parents, last = path
    holder = doc
    for key in parents:
        holder = holder[key]
    if kind == "dropped":
        del holder[last]
    else:
        holder[last] = _damaged(kind, holder[last])
    return doc


def _trimmed(doc, trim):
    for path, value in trim:
        holder = doc
        for key in path[:-1]:
            holder = holder[key]
        holder[path[-1]] = value
    return doc


@dataclass(frozen=True)
class Damage:
    """One damaged file and the command that reads it: a run."""

    target: str
    kind: str
    where: str  # the damaged value's place, or "" for the whole file
    command: int

    @property
    def id(self) -> str:
        return f"{self.target}|{self.kind}|{self.where}|{self.command}"


def _base_doc(target: Target):
    if target.source == "PATH.json":
        return {"points": _csv_points(ROOT / "examples/curves/figure-eight.csv").tolist(), "closed": True}
    return _trimmed(json.loads((ROOT / target.source).read_text()), target.trim)


def _csv_points(path: Path) -> np.ndarray:
    rows = [line.split(",") for line in path.read_text().splitlines() if line and not line.startswith(("#", "x"))]
    return np.array(rows, float)


def damages() -> list[Damage]:
    """The full set of runs, in a fixed order: each target's file damaged as a whole and at each of its values, by
    every kind of damage that applies there; each with one of the target's commands (seeded), or with every one for
    paths and atlases."""
    rng = random.Random(SEED)
    out = []
    for target in TARGETS:
        found = [(kind, "") for kind in FILE_KINDS]
        if target.kind == "json":
            found += [(kind, "") for kind in JSON_KINDS]
            found += [(kind, _where(path)) for path, value in _sites(_base_doc(target)) for kind in VALUE_KINDS
                      if _applies(kind, value, path)]
        elif target.kind == "csv":
            found += [(kind, "") for kind in CSV_KINDS]
        else:
            found += [(kind, column) for column in _h5_columns(target) for kind in H5_KINDS if kind[:4] != "meta"]
            found += [(kind, "meta") for kind in ("meta not JSON", "meta missing")]
            found += [(kind, "meta" + _where(path)) for path, value in _sites(_META[target.source])
                      for kind in VALUE_KINDS if _applies(kind, value, path)]
        for kind, where in found:
            if target.kind == "json":
                out.append(Damage(target.name, kind, where, rng.randrange(len(target.commands))))
            else:
                out += [Damage(target.name, kind, where, k) for k in range(len(target.commands))]
    return out


def _spread(items: list, count: int, rng: random.Random, key) -> list:
    """``count`` of ``items`` taken from each group (by ``key``) in turn, each group in a seeded order."""
    groups: dict = {}
    for item in items:
        groups.setdefault(key(item), []).append(item)
    order = list(groups.values())
    for group in order:
        rng.shuffle(group)
    rng.shuffle(order)
    picked, depth = [], 0
    while len(picked) < count and any(depth < len(g) for g in order):
        picked += [g[depth] for g in order if depth < len(g)]
        depth += 1
    return picked[:count]


def _where(path) -> str:
    return "".join(f"[{k}]" if isinstance(k, int) else f".{k}" for k in path)


def _path(where: str) -> tuple:
    return tuple(key or int(index) for key, index in re.findall(r"\.([^.\[]+)|\[(\d+)\]", where))


def _h5_columns(target: Target) -> tuple[str, ...]:
    if target.source == "OPEN":
        return ("linkages", "link", "point", "circuit", "start", "fraction", "features")
    return ("linkages", "link", "point", "circuit", "features")


#: The metadata of the two atlases, as their damage sites (the keys and kinds of value the atlases have).
_META = {"ATLAS": {"name": "fuzz", "kind": "closed", "linkages": 6, "step": 2.0, "plane": 4.0, "harmonics": 5,
                   "samples": 360, "resample": 256, "version": 1, "seconds": 0.1},
         "OPEN": {"name": "fuzz", "kind": "open", "linkages": 3, "step": 2.0, "plane": 4.0, "samples": 360,
                  "resample": 256, "window_points": 12, "fractions": [0.2, 0.35, 0.5], "starts": 12, "version": 1,
                  "seconds": 0.1}}


def chosen(runs: list[Damage]) -> list[Damage]:
    """All runs in a full test run; else :data:`CI_RUNS` of them, spread over the targets and kinds of damage."""
    return runs if FULL else _spread(runs, CI_RUNS, random.Random(SEED), key=lambda r: (r.target, r.kind))


# -- writing a damaged file -----------------------------------------------------------------------


def write_damaged(damage: Damage, folder: Path) -> Path:
    target = next(t for t in TARGETS if t.name == damage.target)
    suffix = {"json": ".json", "csv": ".csv", "h5": ".h5"}[target.kind]
    path = folder / f"damaged{suffix}"
    if target.kind == "h5":
        shutil.copy(folder / ("atlas.h5" if target.source == "ATLAS" else "open.h5"), path)
        clean = path.read_bytes()
    elif target.kind == "csv":
        clean = (ROOT / target.source).read_bytes()
    else:
        clean = _json_text(_base_doc(target)).encode()
    kind = damage.kind
    if damage.where == "" and kind in FILE_KINDS:
        rng = random.Random(f"{SEED}{damage.id}")
        path.write_bytes({"empty": b"", "binary junk": bytes(rng.randrange(256) for _ in range(4096)),
                          "cut in half": clean[:len(clean) // 2],
                          "not UTF-8": clean[:len(clean) // 3] + b"\xff\xfe\xc3(" + clean[len(clean) // 3:]}[kind])
    elif target.kind == "json":
        doc = _base_doc(target)
        if damage.where:
            text = _json_text(_set(doc, _path(damage.where), kind))
        else:
            text = {"nested 1000 deep": _DEEP[:1000] + _json_text(doc) + _DEEP[1000:],
                    "a list around it": _json_text([doc]), "a number": "42"}[kind]
        path.write_text(text)
    elif target.kind == "csv":
        path.write_text(_damaged_csv(kind, (ROOT / target.source).read_text()))
    else:
        _damage_atlas(path, damage)
    return path


def _damaged_csv(kind: str, text: str) -> str:
    lines = text.splitlines()
    head = [line for line in lines if line.startswith(("#", "x"))]
    rows = [line for line in lines if line and not line.startswith(("#", "x"))]
    pts = np.array([r.split(",") for r in rows], float)

    def csv(points):
        return "\n".join(head + [f"{x!r},{y!r}" for x, y in np.asarray(points).tolist()]) + "\n"

    if kind == "extra columns":
        return "\n".join(head + [f"{r},7,junk,{k}" for k, r in enumerate(rows)]) + "\n"
    if kind == "quoted junk line":
        return "\n".join(head + rows[:5] + ['"12,5","a ""quoted"" junk, line",x'] + rows[5:]) + "\n"
    if kind == "unterminated quote":
        return "\n".join(head + rows[:5] + ['"12.5, 3'] + rows[5:]) + "\n"
    if kind in ("20,000 points", f"{HUGE:,} points"):
        return csv(_resample(pts, int(kind.split()[0].replace(",", ""))))
    if kind == "traced twice":
        return csv(np.vstack([pts, pts]))
    if kind == "every point doubled":
        return csv(np.repeat(pts, 2, axis=0))
    if kind == "one point":
        return csv(pts[:1])
    if kind == "two points":
        return csv(pts[:2])
    if kind == "all points equal":
        return csv(np.repeat(pts[:1], len(pts), axis=0))
    if kind == "a line":
        return csv(np.column_stack([pts[:, 0], 2 * pts[:, 0] + 1]))
    if kind == "scaled 1e300":
        return csv(pts * 1e300)
    if kind == "scaled 1e-300":
        return csv(pts * 1e-300)
    if kind in ("NaN cell", "inf cell", "1e300 cell", "int of 400 digits"):
        cell = {"NaN cell": "nan", "inf cell": "inf", "1e300 cell": "1e300", "int of 400 digits": "1" + "0" * 400}[kind]
        return "\n".join(head + rows[:3] + [f"{cell},{rows[3].split(',')[1]}"] + rows[4:]) + "\n"
    if kind == "only a header":
        return "\n".join(head) + "\n"
    if kind == "semicolons":
        return "\n".join(head + [r.replace(",", ";") for r in rows]) + "\n"
    if kind == "a 1 MB line":
        return "\n".join(head + rows[:3] + [",".join(["1.5"] * 250_000)] + rows[3:]) + "\n"
    raise AssertionError(kind)


def _damage_atlas(path: Path, damage: Damage) -> None:
    import h5py

    with h5py.File(path, "r+") as f:
        if damage.where.startswith("meta"):
            meta = json.loads(f.attrs["meta"])
            if damage.kind == "meta not JSON":
                f.attrs["meta"] = "{broken"
            elif damage.kind == "meta missing":
                del f.attrs["meta"]
            else:
                f.attrs["meta"] = _json_text(_set(meta, _path(damage.where[4:]), damage.kind))
            return
        name, kind = damage.where, damage.kind
        data = f[name][()]
        del f[name]
        if kind == "dropped":
            return
        if kind in ("NaN", "inf", "1e300", "negative"):
            if kind != "negative":
                data = data.astype(float)
            data = data.copy()
            data.flat[:: max(1, data.size // 7)] = {"NaN": np.nan, "inf": np.inf, "1e300": 1e300, "negative": -1}[kind]
        elif kind == "no rows":
            data = data[:0]
        elif kind == "one dimension":
            data = data.reshape(-1)
        elif kind == "strings":
            data = np.array([b"junk"] * len(data))
        f.create_dataset(name, data=data)


# -- running --------------------------------------------------------------------------------------


@dataclass
class Outcome:
    status: int | None
    out: str
    err: str
    signal: int | None = None


def run_forked(argv: list[str], folder: Path, timeout: int = TIMEOUT) -> Outcome:
    """``domes ARGV`` in a child of this process, in ``folder``, ended after ``timeout`` s of processor time."""
    out_file, err_file = folder / "stdout.txt", folder / "stderr.txt"
    limit = _virtual_memory() + MEMORY

    def limits():
        signal.signal(signal.SIGXCPU, signal.SIG_DFL)
        resource.setrlimit(resource.RLIMIT_CPU, (timeout, timeout + 5))
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    wait = forked_main(argv, folder, out_file, err_file, alarm=3 * timeout, limits=limits)
    out = out_file.read_text(encoding="utf-8", errors="replace")
    err = err_file.read_text(encoding="utf-8", errors="replace")
    if os.WIFSIGNALED(wait):
        return Outcome(None, out, err, os.WTERMSIG(wait))
    return Outcome(os.WEXITSTATUS(wait), out, err)


def _virtual_memory() -> int:
    with open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024
    return 0


NONFINITE = re.compile(r"(?<![A-Za-z_])(nan|[+-]?inf(inity)?)(?![A-Za-z_(])", re.IGNORECASE)


def problems(outcome: Outcome) -> list[str]:
    """What is wrong with a run's ending (nothing: an empty list)."""
    found = []
    if outcome.signal in (signal.SIGXCPU, signal.SIGKILL):
        found.append(f"hang: still running after {TIMEOUT} s of processor time")
    elif outcome.signal == signal.SIGALRM:
        found.append(f"hang: still running after {3 * TIMEOUT} s")
    elif outcome.signal is not None:
        found.append(f"killed by signal {outcome.signal}")
    elif outcome.status == TRACEBACK or "Traceback" in outcome.err:
        last = [line for line in outcome.err.splitlines() if line.strip()][-1:] or ["?"]
        found.append(f"traceback: {last[0][:300]}")
    elif outcome.status not in (0, 1, 2):
        found.append(f"exit status {outcome.status}")
    long = [line for line in outcome.err.splitlines() if len(line) > MAX_LINE]
    if long:
        found.append(f"a line of {len(long[0]):,} characters on stderr: {long[0][:200]}...")
    if outcome.status == 0:
        bad = [line for line in outcome.out.splitlines() if NONFINITE.search(line)]
        if bad and not says_why(outcome.out):
            found.append(f"NaN or infinity in the output, unexplained: {bad[0][:200]}")
    return found


def says_why(output: str) -> bool:
    """Whether an output with NaN or infinity in it says what they mean."""
    return bool(re.search(r"not finite|undefined|no value|refused|singular|dead point|limit", output, re.I))


# -- the tests ------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def folder(tmp_path_factory):
    """A scratch folder with the examples and two tiny atlases; the package warmed up in this process."""
    from domes.io.atlas import save_atlas
    from domes.motion.coupler.atlas import AtlasSpec, build, build_windows

    where = tmp_path_factory.mktemp("file-fuzz")
    shutil.copytree(ROOT / "examples", where / "examples")
    save_atlas(build(AtlasSpec("fuzz", 6, 2.0)), where / "atlas.h5")
    save_atlas(build_windows(AtlasSpec("fuzz", 6, 2.0)), where / "open.h5")
    (where / "home").mkdir()
    os.environ["DOMES_HOME"] = str(where / "home")
    _warm_up(where)
    return where


def _warm_up(folder: Path) -> None:
    """Import what the commands import, so that each forked run does not."""
    import h5py  # noqa: F401
    import scipy.optimize  # noqa: F401

    import domes.cli
    import domes.sketch.curves  # noqa: F401
    import domes.sketch.dynamics  # noqa: F401

    domes.cli.build_parser()


def argv_of(damage: Damage, path: Path) -> list[str]:
    target = next(t for t in TARGETS if t.name == damage.target)
    places = {"FILE": str(path), "ATLAS": str(path.parent / "atlas.h5"), "OPEN": str(path.parent / "open.h5")}
    return [places.get(w, w) for w in target.commands[damage.command]]


RUNS = damages()


def test_the_full_set_is_large_enough():
    assert len(RUNS) >= 1000, len(RUNS)
    assert {r.target for r in chosen(RUNS)} == {t.name for t in TARGETS}


@pytest.mark.slow
@pytest.mark.parametrize("target", TARGETS, ids=lambda t: t.name)     # a test each, for pytest -n to spread
def test_every_example_runs_cleanly(folder, tmp_path, target):
    shutil.copy(folder / "atlas.h5", tmp_path)
    shutil.copy(folder / "open.h5", tmp_path)
    (tmp_path / "examples").symlink_to(folder / "examples")
    path = tmp_path / ("clean" + {"json": ".json", "csv": ".csv", "h5": ".h5"}[target.kind])
    if target.kind == "h5":
        shutil.copy(tmp_path / ("atlas.h5" if target.source == "ATLAS" else "open.h5"), path)
    elif target.kind == "csv":
        shutil.copy(ROOT / target.source, path)
    else:
        path.write_text(_json_text(_base_doc(target)))
    for k in range(len(target.commands)):
        words = argv_of(Damage(target.name, "none", "", k), path)
        outcome = run_forked(words, tmp_path)
        assert outcome.status in (0, 1) and not problems(outcome), (words, outcome.err[-2000:])


@pytest.mark.slow
@pytest.mark.parametrize("damage", chosen(RUNS), ids=lambda d: d.id)
def test_a_damaged_file_ends_cleanly(folder, tmp_path, damage):
    for name in ("atlas.h5", "open.h5"):
        shutil.copy(folder / name, tmp_path / name)
    (tmp_path / "examples").symlink_to(folder / "examples")
    path = write_damaged(damage, tmp_path)
    words = argv_of(damage, path)
    outcome = run_forked(words, tmp_path)
    assert not problems(outcome), f"domes {' '.join(words)}: {problems(outcome)}\n{outcome.err[-3000:]}"
