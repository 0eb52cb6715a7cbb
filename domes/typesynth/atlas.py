"""The unlabelled graph generator: every non-isomorphic, non-degenerate chain.

A *chain* here is a kinematic chain of planar motion with simple revolute joints: a
connected simple graph (links = vertices, joints = edges), every link with
at least two joints, no proper sub-chain of three or more links rigid or
over-constrained (``3(|S| − 1) − 2e(S) ≤ 0``). Its DOF is
``F = 3(n − 1) − 2j``; ``F = 0`` gives the basic chains of Table 3-4.

Method (exact, not the book's SOC superposition of §3-2-II):

* A chain without a cut link is 2-connected, so it has an open ear
  decomposition, and removing its last ear (a branch of ``k`` binary links
  between two distinct links) leaves a 2-connected chain ``H``. ``H`` is a
  proper sub-chain, so it is non-degenerate too, with ``F(H) = F + 2 − k ≥ 1``
  and one loop fewer. Hence all chains with ``L`` loops come from all chains
  with ``L − 1`` loops by adding one ear, ``k = 0 … F + 1``, starting from the
  single loop (the ``(F + 3)``-gon). An ear is kept when it creates no rigid
  sub-chain (:func:`domes.model.rigidity.pair_slack`).
* A chain with a cut link (fractionated, §3-2-I.5) is a smaller chain ``G0``
  with a 2-connected leaf block ``B`` hung on it, directly on a shared link or
  through a path of ``k`` bridging joints: ``F = F(G0) + F(B) + k``.
* Duplicates are removed by nauty's canonical labelling (``isomorphism=
  "nauty"``, exact). ``isomorphism="charpoly"`` removes them by the adjacency
  matrix's characteristic polynomial instead, as the book does (§3-2-II.4):
  faster to explain, but not exact (it merges two pairs of 10-bar chains).

Only one representative per orbit of link pairs under the automorphism
group of ``H`` is tried, so little work is repeated.

*Clamping chains* (``clamping=True``; seed 002, §3-3-I (4), Fig. 3-23) drop
the non-degeneracy condition: a clamp works with ``W ≤ 0`` and its chain
contains immobile sub-chains. They are every connected simple graph with
the given links and joints, each link with two joints or more, any DOF,
built the same two ways with the rigidity filter left out, by links and
loops instead of DOF (:func:`clamping_ears`).

>>> [len(chains(links=n, dof=1)) for n in (4, 6, 8)]
[1, 2, 16]
"""

from __future__ import annotations

import pickle
import time
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError
from domes.model.canon import automorphisms, canonical_form, certificate
from domes.model.chain import Chain
from domes.model.charpoly import characteristic_polynomial
from domes.model.mobility import chain_joints, check_count, joints_for
from domes.model.pebble import decode_graph6, encode_graph6
from domes.model.rigidity import MAX_LINKS, pair_slack
from domes.results import Listing, Progress, Status, Ticker
from domes.typesynth import augment, strata

Edge = tuple[int, int]
Graph = tuple[int, tuple[Edge, ...]]  # (links, joints) with links 0..n-1

ISOMORPHISM_METHODS = ("nauty", "charpoly")
#: How the chains without a cut link are generated: ``merge`` level by level, every level's children merged by
#: certificate in one process; ``augment`` by canonical augmentation (:mod:`domes.typesynth.augment`), each part of
#: the parents walked on its own; ``auto`` augments atlases of :data:`AUGMENT_LINKS` links or more.
GENERATION_METHODS = ("auto", "augment", "merge")
#: ``auto`` builds atlases of this many links or more by augmentation (12-link atlases take seconds either way;
#: merge keeps every intermediate atlas in a job folder).
AUGMENT_LINKS = 13




def _cycle(n: int) -> Graph:
    return n, tuple((i, (i + 1) % n) if i + 1 < n else (0, n - 1) for i in range(n))


def _add_branch(graph: Graph, u: int, v: int, k: int) -> Graph:
    """``graph`` plus a branch of ``k`` new binary links from link ``u`` to link ``v``."""
    n, edges = graph
    path = [u, *range(n, n + k), v]
    return n + k, edges + tuple(zip(path, path[1:]))


def _glue(base: Graph, u: int, block: Graph, c: int, k: int) -> Graph:
    """``block`` hung on link ``u`` of ``base`` by its link ``c``.

    With ``k = 0`` the two links are merged; with ``k ≥ 1`` they are joined by
    a path of ``k`` joints through ``k − 1`` new binary links.
    """
    n0, edges0 = base
    nb, edgesb = block
    if k == 0:
        # block links: c -> u, the others -> n0, n0+1, ...
        others = [x for x in range(nb) if x != c]
        name = {c: u, **{x: n0 + i for i, x in enumerate(others)}}
        return n0 + nb - 1, edges0 + tuple((name[a], name[b]) for a, b in edgesb)
    name = {x: n0 + x for x in range(nb)}
    path = [u, *range(n0 + nb, n0 + nb + k - 1), name[c]]
    edges = edges0 + tuple((name[a], name[b]) for a, b in edgesb) + tuple(zip(path, path[1:]))
    return n0 + nb + k - 1, edges


def graph_key(graph: Graph, isomorphism: str) -> object:
    """The duplicate-removal key of a graph: nauty's certificate (exact) or the characteristic polynomial."""
    n, edges = graph
    if isomorphism == "nauty":
        return certificate(n, edges)
    return (n, characteristic_polynomial(n, edges))


def ears(task: tuple) -> list[tuple[object, bytes]]:
    """``(key, packed child)`` of every chain made by adding an ear of ``k`` binary links to each parent of the
    task ``(parents, k, isomorphism)``, one pair of links per orbit, children that would hold a rigid sub-chain
    left out, each key once. Children are packed (:func:`pack`) to travel light from a worker."""
    parents, k, isomorphism = task
    out: dict[object, bytes] = {}
    for n, edges in parents:
        slack = pair_slack(n, edges)
        ok = np.argwhere(np.triu(slack >= 3 - k, 1))
        if not len(ok):
            continue
        _children(n, edges, [(int(u), int(v)) for u, v in ok], k, isomorphism, out)
    return list(out.items())


def _children(n, edges, pairs, k, isomorphism, out: dict) -> None:
    """Add to ``out`` (key -> packed child) an ear of ``k`` binary links on one pair of ``pairs`` per orbit."""
    for u, v in automorphisms(n, edges).pair_orbit_representatives(pairs):
        child = _add_branch((n, edges), u, v, k)
        key = graph_key(child, isomorphism)
        if key not in out:
            out[key] = pack(child)


def clamping_ears(task: tuple) -> list[tuple[object, bytes]]:
    """:func:`ears` without the rigidity filter, for clamping chains: an ear of ``k`` binary links on every pair
    of links of each parent (with ``k = 0`` only between links not jointed already: joints stay simple), one
    pair per orbit, each key once.

    >>> len(clamping_ears(((_cycle(4),), 0, "nauty")))      # a diagonal of the four-bar: two triangles
    1
    """
    parents, k, isomorphism = task
    out: dict[object, bytes] = {}
    for n, edges in parents:
        jointed = {(min(u, v), max(u, v)) for u, v in edges}
        pairs = [(u, v) for u in range(n) for v in range(u + 1, n) if k or (u, v) not in jointed]
        if pairs:
            _children(n, edges, pairs, k, isomorphism, out)
    return list(out.items())


def ears_of_slice(task: tuple) -> bytes:
    """:func:`ears` of the parents ``start:stop`` of a pickled tuple of parents, pickled: the task sent to a
    worker. Its arguments and result are single byte strings, which Dask passes on fast (a list of many small
    byte strings it sends one frame each: seconds per level)."""
    blob, start, stop, k, isomorphism = task
    return pickle.dumps(ears((pickle.loads(blob)[start:stop], k, isomorphism)),
                        protocol=pickle.HIGHEST_PROTOCOL)


def canonical_slice(task: tuple) -> bytes:
    """The packed canonical forms of the graphs ``start:stop`` of a pickled list of packed graphs, pickled: the
    second task of a parallel level (each distinct child labelled once, wherever it was found)."""
    blob, start, stop = task
    return pickle.dumps([pack((g[0], canonical_form(*g)[1])) for g in map(unpack, pickle.loads(blob)[start:stop])],
                        protocol=pickle.HIGHEST_PROTOCOL)


def encode_ears(pairs: list[tuple[object, bytes]]) -> bytes:
    """The ``(key, packed child)`` pairs of :func:`ears` as a file of plain numpy arrays (no pickled objects): the
    slice files of a job folder, which must hold data, never code.

    >>> pairs = ears(((_cycle(4),), 2, "charpoly"))
    >>> decode_ears(encode_ears(pairs)) == pairs
    True
    """
    import io

    keys = [k for k, _ in pairs]
    charpoly = bool(keys) and not isinstance(keys[0], bytes)
    if charpoly:
        fields = {"n": np.array([k[0] for k in keys], np.int64),
                  "poly": np.array([k[1] for k in keys], np.int64).reshape(len(keys), -1)}
    else:
        fields = {"key_bytes": np.frombuffer(b"".join(keys), np.uint8),
                  "key_ends": np.cumsum([len(k) for k in keys], dtype=np.int64)}
    fields.update(child_bytes=np.frombuffer(b"".join(c for _, c in pairs), np.uint8),
                  child_ends=np.cumsum([len(c) for _, c in pairs], dtype=np.int64))
    out = io.BytesIO()
    np.savez(out, **fields)
    return out.getvalue()


def decode_ears(data: bytes) -> list[tuple[object, bytes]]:
    """The pairs of :func:`encode_ears`; ValueError if ``data`` is not such a file."""
    import io
    import zipfile

    try:
        with np.load(io.BytesIO(data), allow_pickle=False) as f:
            arrays = {name: f[name] for name in f.files}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile, KeyError) as exc:
        raise ValueError(f"not a slice file ({exc})") from None

    def split(blob, ends):
        starts = np.concatenate([[0], ends[:-1]]) if len(ends) else ends
        raw = blob.tobytes()
        if len(ends) and (ends[-1] != len(raw) or np.any(np.diff(ends) < 0)):
            raise ValueError("its offsets do not match its bytes")
        return [raw[a:b] for a, b in zip(starts.tolist(), ends.tolist())]

    if "child_bytes" not in arrays or "child_ends" not in arrays:
        raise ValueError("it holds no children")
    children = split(arrays["child_bytes"], arrays["child_ends"])
    if "poly" in arrays:
        keys = [(int(n), tuple(int(c) for c in row)) for n, row in zip(arrays["n"], arrays["poly"])]
    elif "key_bytes" in arrays:
        keys = split(arrays["key_bytes"], arrays["key_ends"])
    else:
        keys = []
    if len(keys) != len(children):
        raise ValueError(f"{len(keys)} keys for {len(children)} children")
    return list(zip(keys, children))


def _graph(line: str) -> Graph:
    """A chain from its canonical graph6 line, as the atlas holds it (joints sorted)."""
    n, edges = decode_graph6(line)
    return n, tuple(sorted(edges))


def pack(graph: Graph) -> bytes:
    """A graph as bytes (its link count, then its joints' link pairs), for the trip back from a worker."""
    n, edges = graph
    return bytes([n]) + np.asarray(edges, dtype=np.uint8).tobytes()


def unpack(data: bytes) -> Graph:
    pairs = np.frombuffer(data[1:], dtype=np.uint8).reshape(-1, 2)
    return data[0], tuple((int(u), int(v)) for u, v in pairs)


#: Levels with at least this many parents go to the executor, in this many tasks per worker (more tasks balance
#: the load; fewer find fewer chains twice).
PARALLEL_PARENTS = 256
TASKS_PER_WORKER = 2
#: With checkpoints, slices have at most this many parents (10-20 s of work each at 14 links), so that a killed run
#: loses little.
CHECKPOINT_PARENTS = 5000


def _completed_here(fn, items, progress=None):
    """``(index, fn(item))`` in order, here: the executor-less :meth:`completed`."""
    clock = Ticker(progress)
    for k, item in enumerate(items):
        yield k, fn(item)
        clock.tick(lambda: f"{k + 1:,}/{len(items):,} slices done")


def check_links(links: int) -> None:
    """Refuse atlases beyond :data:`~domes.model.rigidity.MAX_LINKS` links, which no machine can build."""
    if links > MAX_LINKS:
        raise InputError(f"chains of more than {MAX_LINKS} links are out of reach: the atlas grows about 30-fold "
                         f"per two links (6856 one-DOF chains of 12 links), and {links} links were asked for")


#: Clamping atlases hold every graph of their size (no rigidity filter), so they grow much faster than the
#: default ones: they stop at this many joints (measured: 46,604 chains of 12 links, 16 joints in 11 s; 94,484 of
#: 11 links, 16 joints in 36 s and 0.5 GB) ...
MAX_CLAMPING_JOINTS = 16
#: ... except for chains of up to this many links, all of whose sizes are in reach (27,930 at most, 9 links,
#: 19 joints, DOF -14, in 11 s).
SMALL_CLAMPING_LINKS = 9


def clamping_in_reach(links: int, joints: int) -> bool:
    """True if the clamping atlas of this size is built (see :data:`MAX_CLAMPING_JOINTS`)."""
    return links <= SMALL_CLAMPING_LINKS or joints <= MAX_CLAMPING_JOINTS


def clamping_joints(links: int, dof: int) -> int:
    """Joints ``j = (3(n − 1) − W)/2`` of a clamping chain of ``links`` links and DOF ``dof`` (any sign), with a
    clear error when no such chain exists (no loop, an odd count, more joints than pairs of links, too large).

    >>> clamping_joints(4, -1), clamping_joints(6, 1)
    (5, 7)
    """
    check_count("links", links, 3)
    if isinstance(dof, bool) or not isinstance(dof, (int, np.integer)):
        raise InputError(f"dof must be a whole number, got {dof!r}")
    twice = 3 * (links - 1) - dof
    if twice % 2:
        raise InputError(f"no clamping chain has {links} links and DOF {dof}: the joint count (3(n-1) - F)/2 = "
                         f"{twice}/2 is not an integer; try {links - 1} or {links + 1} links")
    joints = joints_for(links, dof)
    if joints < links:
        raise InputError(f"{links} links with DOF {dof} give {joints} joints: no closed chain (L = {joints - links + 1}); "
                         f"a clamping chain of {links} links has DOF at most {links - 1}")
    most = links * (links - 1) // 2
    if joints > most:
        raise InputError(f"{links} links with DOF {dof} need {joints} joints, but {links} links have only {most} pairs "
                         f"(simple joints only); the least DOF of {links} links is {3 * (links - 1) - 2 * most}")
    if not clamping_in_reach(links, joints):
        raise InputError(f"the clamping chains of {links} links and {joints} joints (DOF {dof}) are out of reach: a "
                         "clamping atlas keeps every graph of its size, rigid sub-chains and all, so it stops at "
                         f"{MAX_CLAMPING_JOINTS} joints (about 100,000 chains) unless it has {SMALL_CLAMPING_LINKS} "
                         "links or fewer; ask for fewer links or a higher DOF")
    return joints


@dataclass
class ChainGenerator:
    """Generates chain atlases and remembers every atlas it has built.

    One generator shares its intermediate atlases between requests, so a
    second request is immediate. ``isomorphism`` is the speed/accuracy knob:
    ``"nauty"`` (exact, default) or ``"charpoly"`` (the book's test, inexact).
    ``executor`` (see :mod:`domes.execution`) runs the large levels in
    parallel: the ears by slices of parents, then the canonical labelling of
    the distinct children, each once; the atlas is sorted after, so it is
    the same. ``checkpoints`` (a :class:`~domes.io.jobs.JobFolder`, or any
    store with ``load``, ``save`` and ``discard`` by name) receives every
    finished atlas as graph6 (``chains-n14-F1.g6``) and the slices of the
    level under way as they come; a generator given the same store later
    loads them instead of computing them again.

    >>> gen = ChainGenerator()
    >>> len(gen.chains(links=7, dof=2)), len(gen.chains(links=7, dof=2, include_fractionated=True))
    (3, 4)

    ``clamping=True`` admits immobile (rigid or over-constrained) sub-chains
    and any DOF, ``W ≤ 0`` included: the chains of clamps (seed 002, §3-3-I (4)).

    >>> len(gen.chains(links=4, dof=-1, clamping=True))      # K4 minus a joint: two rigid triangles
    1
    """

    isomorphism: str = "nauty"
    progress: Progress | None = None
    executor: object = None
    checkpoints: object = None
    method: str = "auto"
    #: what the last walk by augmentation did (:class:`~domes.typesynth.augment.Stats`), for the benchmarks
    stats: augment.Stats | None = field(default=None, repr=False)
    _blocks: dict[tuple[int, int], list[Graph]] = field(default_factory=dict, repr=False)
    _all: dict[tuple[int, int], list[Graph]] = field(default_factory=dict, repr=False)
    _clamp_blocks: dict[tuple[int, int], list[Graph]] = field(default_factory=dict, repr=False)
    _clamp_all: dict[tuple[int, int], list[Graph]] = field(default_factory=dict, repr=False)
    _clock: Ticker = field(init=False, repr=False)

    def __post_init__(self) -> None:
        self._clock = Ticker(self.progress)
        if self.isomorphism not in ISOMORPHISM_METHODS:
            raise InputError(
                f"unknown isomorphism method {self.isomorphism!r}; choose one of {', '.join(ISOMORPHISM_METHODS)}"
            )
        if self.method not in GENERATION_METHODS:
            raise InputError(f"unknown generation method {self.method!r}; choose one of {', '.join(GENERATION_METHODS)}")
        if self.method == "augment" and self.isomorphism != "nauty":
            raise InputError(f"generation by augmentation keeps chains by nauty's canonical labelling, so it is exact; "
                             f"isomorphism {self.isomorphism!r} is for the merge method (method='merge')")

    # -- public -------------------------------------------------------------

    def chains(self, links: int, dof: int, include_fractionated: bool = False, clamping: bool = False) -> list[Graph]:
        """All chains with ``links`` links and DOF ``dof``, canonically labelled and sorted.

        With ``clamping`` (seed 002, §3-3-I (4)): every connected chain of
        simple joints, each link with two or more, immobile sub-chains
        admitted, for any DOF (``W ≤ 0`` for clamps); a superset of the
        default atlas.
        """
        if clamping:
            return self._clamping_chains(links, dof, include_fractionated)
        if isinstance(dof, int) and not isinstance(dof, bool) and dof < 0:
            raise InputError(f"a chain of DOF {dof} is over-constrained: it always holds an immobile sub-chain, which "
                             "the atlas of mobile chains leaves out; to list such chains (clamps, W <= 0, seed 002 "
                             "§3-3-I (4)) pass clamping=True (domes chains --clamping)")
        joints = chain_joints(links, dof)
        check_links(links)
        loops = joints - links + 1
        if loops < 1:
            raise InputError(f"{links} links with DOF {dof} give {joints} joints: no closed chain (L = {loops})")
        if include_fractionated:
            return self._all_chains(loops, dof)
        return self._two_connected(loops, dof)

    # -- internals ----------------------------------------------------------

    def _key(self, graph: Graph) -> object:
        return graph_key(graph, self.isomorphism)

    def _finish(self, found: dict[object, Graph], canonical=frozenset()) -> list[Graph]:
        """Canonically relabel and sort (by link assortment, then certificate); the graphs of the keys in
        ``canonical`` (nauty certificates) are canonically labelled already."""
        out = []
        for key, (n, edges) in found.items():
            cert, canon = (key, edges) if key in canonical else canonical_form(n, edges)
            degrees = np.bincount(np.array(canon).ravel(), minlength=n)
            assortment = tuple(-c for c in np.bincount(degrees)[2:])
            out.append((assortment, cert, (n, canon)))
        out.sort(key=lambda item: (item[0], item[1]))
        return [graph for _, _, graph in out]

    def _two_connected(self, loops: int, dof: int) -> list[Graph]:
        """Chains without a cut link: ``loops`` loops, DOF ``dof``."""
        key = (loops, dof)
        if key in self._blocks:
            return self._blocks[key]
        links = 2 * loops + dof + 1
        name = f"chains-n{links}-F{dof}"
        result = None if loops == 1 else self._load_level(name)
        if loops == 1:
            result = [_cycle(dof + 3)]
        elif result is None and self._augments(links):
            result = [_graph(line) for line in self._merged(self._augment_parts(loops, dof, name))]
            self._save_level(name, result)
        elif result is None:
            found: dict[object, Graph] = {}
            labelled = self.isomorphism == "nauty"        # workers label the distinct children canonically
            canonical: set = set()                        # the keys whose graph is canonically labelled
            raw: dict[object, bytes] = {}                 # children found in slices, packed, not yet labelled
            sliced = self.executor is not None or self.checkpoints is not None
            for k in range(dof + 2):
                parents = self._two_connected(loops - 1, dof + 2 - k)
                if sliced and len(parents) >= PARALLEL_PARENTS:
                    for pairs in self._ears_by_slices(parents, k, f"{name}-k{k}"):
                        for cert, packed in pairs:
                            if cert not in found:
                                found[cert] = None
                                raw[cert] = packed
                else:
                    for index, parent in enumerate(parents):
                        self._clock.tick(lambda: f"{links} links, DOF {dof}: ear k={k} on parent {index + 1}/{len(parents)}, {len(found)} chains so far")
                        for cert, packed in ears(((parent,), k, self.isomorphism)):
                            if cert not in found:
                                found[cert] = unpack(packed)
            if raw:
                self._label(raw, found, canonical if labelled else None)
            result = self._finish(found, canonical)
            self._save_level(name, result)
        self._blocks[key] = result
        self._clock.tick(lambda: f"{links} links, DOF {dof}, {loops} loops: {len(result)} chains without a cut link", force=True)
        return result

    def _augments(self, links: int) -> bool:
        """True if the atlas of ``links`` links without a cut link is generated by augmentation."""
        return self.isomorphism == "nauty" and (
            self.method == "augment" or (self.method == "auto" and links >= AUGMENT_LINKS))

    def stream(self, links: int, dof: int) -> tuple[int, object]:
        """The count and the graph6 lines (in the atlas's order) of the chains without a cut link, without holding
        them as graphs when they are generated by augmentation; with checkpoints the atlas is written first
        (``chains-n14-F1.g6``). Otherwise as :meth:`chains`.

        >>> count, lines = ChainGenerator(method="augment").stream(8, 1)
        >>> count, next(iter(lines))
        (16, 'G_GSZc')
        """
        graphs = None
        joints = chain_joints(links, dof)
        loops = joints - links + 1
        if loops < 2 or not self._augments(links) or (loops, dof) in self._blocks or dof < 0:
            graphs = self.chains(links, dof)
        else:
            name = f"chains-n{links}-F{dof}"
            check_links(links)
            graphs = self._load_level(name)
        if graphs is not None:
            return len(graphs), (encode_graph6(n, e) for n, e in graphs)
        parts = self._augment_parts(loops, dof, name)
        count = sum(len(part) for part in parts)
        if self.checkpoints is None:
            return count, self._merged(parts)
        data = "".join(line + "\n" for line in self._merged(parts)).encode("ascii")
        del parts
        self.checkpoints.save(f"{name}.g6", data)
        self.checkpoints.discard(f"parts/{name}-")
        return count, iter(data.decode("ascii").split())

    @staticmethod
    def _merged(parts: list[list[bytes]]):
        """The graph6 lines of sorted parts of records, merged into the atlas's order."""
        return (augment.graph6_of(r) for r in augment.merge_records(parts))

    def _augment_parts(self, loops: int, dof: int, name: str) -> list[list[bytes]]:
        """The records of the chains of ``loops`` loops and DOF ``dof`` by canonical augmentation, part by part (each
        sorted): walked on the executor (or here), each part written to the checkpoints as it comes and loaded from
        them if an earlier run wrote it; the parts a run was cut into are kept (``parts/NAME-augment.plan``)."""
        links = 2 * loops + dof + 1
        self._clock.tick(lambda: f"{name}: the starts of the walks", force=True)
        starts, parts = augment.plan(loops, dof, getattr(self.executor, "workers", 1))
        plan_name = f"parts/{name}-augment.plan"
        if self.checkpoints is not None:
            plan = self.checkpoints.load(plan_name)
            planned = plan.decode("ascii", "replace").strip() if plan is not None else ""
            if planned.isdigit() and 1 <= int(planned) <= len(starts):
                parts = int(planned)
            else:
                self.checkpoints.save(plan_name, b"%d\n" % parts)
        names = [f"parts/{name}-augment-{i}-of-{parts}.rec" for i in range(parts)]
        found: list = [None] * parts
        if self.checkpoints is not None:
            for i, part in enumerate(names):
                found[i] = self._load_part(part, links)
        todo = [i for i in range(parts) if found[i] is None]
        stats = augment.Stats()
        if todo:
            blob = pickle.dumps(starts, protocol=pickle.HIGHEST_PROTOCOL)
            shared = blob if self.executor is None else self.executor.share(blob)
            tasks = [(shared, i, parts, loops, dof) for i in todo]
            where = f"{name}: {len(starts):,} walks in {parts} parts"
            if len(todo) < parts:
                where += f" ({parts - len(todo)} written by an earlier run)"
            completed = self.executor.completed if self.executor is not None else _completed_here
            chains_so_far = 0
            for j, result in completed(augment.walk_part, tasks, progress=self._progress(where)):
                data, part_stats = pickle.loads(result)      # from this run's own workers, never from a file
                stats.add(part_stats)
                i = todo[j]
                width = augment.record_width(links)
                found[i] = [data[a:a + width] for a in range(0, len(data), width)]
                chains_so_far += len(found[i])
                if self.checkpoints is not None:
                    self.checkpoints.save(names[i], data)
                self._clock.tick(lambda: f"{where}: {chains_so_far:,} chains so far")
        self.stats = stats
        return found

    def _load_part(self, name: str, links: int) -> list[bytes] | None:
        """A part an earlier run wrote, or None (not written, or not a part: then it is walked again)."""
        data = self.checkpoints.load(name)
        if data is None:
            return None
        try:
            return augment.split_records(data, links)
        except ValueError as exc:
            refuse = getattr(self.checkpoints, "refuse", None)
            if refuse is not None:
                refuse(name, f"is not a part of this atlas ({exc})")
            return None

    def _ears_by_slices(self, parents: list[Graph], k: int, name: str) -> list[list]:
        """The :func:`ears` pairs of ``parents`` cut into slices, in slice order: on the executor (or here), each
        written to the checkpoints as it comes (:func:`encode_ears`) and loaded from them if an earlier run wrote
        it."""
        slices = TASKS_PER_WORKER * getattr(self.executor, "workers", 1)
        if self.checkpoints is not None:
            slices = max(slices, -(-len(parents) // CHECKPOINT_PARENTS))
            plan = self.checkpoints.load(f"parts/{name}.plan")     # an earlier run's slices win (other workers)
            planned = plan.decode("ascii", "replace").strip() if plan is not None else ""
            if planned.isdigit() and 1 <= int(planned) <= len(parents):
                slices = int(planned)
            else:
                self.checkpoints.save(f"parts/{name}.plan", b"%d\n" % slices)
        size = -(-len(parents) // slices)
        bounds = [(i, min(i + size, len(parents))) for i in range(0, len(parents), size)]
        blobs: list = [None] * len(bounds)
        if self.checkpoints is not None:
            blobs = [self._load_slice(f"parts/{name}-{a}-{b}.ears") for a, b in bounds]
        todo = [j for j, blob in enumerate(blobs) if blob is None]
        if not todo:
            return blobs
        data = pickle.dumps(tuple(parents), protocol=pickle.HIGHEST_PROTOCOL)
        shared = data if self.executor is None else self.executor.share(data)
        tasks = [(shared, *bounds[j], k, self.isomorphism) for j in todo]
        where = f"{name}: ear k={k} on {len(parents):,} parents in {len(bounds)} slices"
        if len(todo) < len(bounds):
            where += f" ({len(bounds) - len(todo)} written by an earlier run)"
        completed = self.executor.completed if self.executor is not None else _completed_here
        for i, blob in completed(ears_of_slice, tasks, progress=self._progress(where)):
            j = todo[i]
            blobs[j] = pickle.loads(blob)                   # from this run's own workers, never from a file
            if self.checkpoints is not None:
                self.checkpoints.save(f"parts/{name}-{bounds[j][0]}-{bounds[j][1]}.ears", encode_ears(blobs[j]))
        return blobs

    def _load_slice(self, name: str) -> list | None:
        """A slice an earlier run wrote, or None (not written, or not a slice file: then it is computed again)."""
        data = self.checkpoints.load(name)
        if data is None:
            return None
        try:
            return decode_ears(data)
        except ValueError as exc:
            refuse = getattr(self.checkpoints, "refuse", None)
            if refuse is not None:
                refuse(name, f"is {exc}")
            return None

    def _load_level(self, name: str) -> list[Graph] | None:
        """A finished atlas an earlier run wrote to the checkpoints (graph6, one chain a line), or None."""
        if self.checkpoints is None:
            return None
        data = self.checkpoints.load(f"{name}.g6")
        if data is None:
            return None
        try:
            graphs = [decode_graph6(line) for line in data.decode("ascii").split()]
        except (UnicodeDecodeError, ValueError, IndexError) as exc:
            refuse = getattr(self.checkpoints, "refuse", None)
            if refuse is not None:
                refuse(f"{name}.g6", f"is not graph6 ({str(exc)[:100]})")
            return None
        return [(n, tuple(sorted(edges))) for n, edges in graphs]

    def _save_level(self, name: str, result: list[Graph]) -> None:
        if self.checkpoints is None:
            return
        self.checkpoints.save(f"{name}.g6", "".join(encode_graph6(n, e) + "\n" for n, e in result).encode("ascii"))
        self.checkpoints.discard(f"parts/{name}-")

    def _label(self, raw: dict[object, bytes], found: dict, canonical: set | None) -> None:
        """Unpack the children found in slices into ``found``; with nauty keys (``canonical`` a set) and an
        executor, label them canonically on the workers first, each once, and note their keys in ``canonical``."""
        certs = list(raw)
        if canonical is None or self.executor is None:           # here: _finish labels them
            for cert in certs:
                found[cert] = unpack(raw[cert])
            return
        size = -(-len(certs) // (TASKS_PER_WORKER * getattr(self.executor, "workers", 1)))
        blob = self.executor.share(pickle.dumps([raw[c] for c in certs], protocol=pickle.HIGHEST_PROTOCOL))
        tasks = [(blob, i, i + size) for i in range(0, len(certs), size)]
        done = 0
        for result in self.executor.map(canonical_slice, tasks, progress=self._progress("labelling")):
            for packed in pickle.loads(result):
                found[certs[done]] = unpack(packed)
                canonical.add(certs[done])
                done += 1

    def _progress(self, where: str):
        """A progress callback that prefixes ``where`` (None without progress)."""
        if self.progress is None:
            return None
        return lambda message: self.progress(f"{where}: {message}")

    def _clamping_chains(self, links: int, dof: int, include_fractionated: bool) -> list[Graph]:
        """Clamping chains (immobile sub-chains admitted) of ``links`` links and DOF ``dof``."""
        loops = clamping_joints(links, dof) - links + 1
        if include_fractionated:
            return self._clamping_all(loops, links)
        return self._clamping_two_connected(loops, links)

    def _clamping_two_connected(self, loops: int, links: int) -> list[Graph]:
        """Every 2-connected simple graph of ``links`` links and ``loops`` loops: each is a 2-connected graph with
        one loop fewer plus an ear of ``k`` binary links (its last ear), with no rigidity filter."""
        key = (loops, links)
        if key in self._clamp_blocks:
            return self._clamp_blocks[key]
        if links < 3 or loops < 1 or links + loops - 1 > links * (links - 1) // 2:
            result: list[Graph] = []
        elif loops == 1:
            result = [_cycle(links)]
        else:
            found: dict[object, Graph] = {}
            for k in range(links - 2):                    # the parent keeps at least three links
                parents = self._clamping_two_connected(loops - 1, links - k)
                for index, parent in enumerate(parents):
                    self._clock.tick(lambda: f"clamping, {links} links, {loops} loops: ear k={k} on parent "
                                             f"{index + 1}/{len(parents)}, {len(found)} chains so far")
                    for cert, packed in clamping_ears(((parent,), k, self.isomorphism)):
                        if cert not in found:
                            found[cert] = unpack(packed)
            result = self._finish(found)
        self._clamp_blocks[key] = result
        return result

    def _clamping_all(self, loops: int, links: int) -> list[Graph]:
        """Every connected simple graph of ``links`` links (each with two joints or more) and ``loops`` loops: the
        2-connected ones, and a smaller such graph ``G0`` with a 2-connected leaf block hung on it, on a shared link
        or through ``k`` bridging joints (``links = links(G0) + links(B) + k − 1``, loops add up)."""
        key = (loops, links)
        if key in self._clamp_all:
            return self._clamp_all[key]
        found: dict[object, Graph] = {self._key(g): g for g in self._clamping_two_connected(loops, links)}
        for loops_b in range(1, loops):
            for links_b in range(3, links - 1):
                blocks = self._clamping_two_connected(loops_b, links_b)
                if not blocks:
                    continue
                block_sites = [(b, automorphisms(*b).orbits) for b in blocks]
                for k in range(links - links_b - 1):      # the base keeps at least three links
                    bases = self._clamping_all(loops - loops_b, links - links_b - k + 1)
                    for base in bases:
                        self._glue_blocks(base, block_sites, k, found)
        result = self._finish(found)
        self._clamp_all[key] = result
        return result

    def _glue_blocks(self, base: Graph, block_sites, k: int, found: dict) -> None:
        """Add to ``found`` each block of ``block_sites`` glued to ``base`` by ``k`` bridging joints, one link of
        each orbit on either side."""
        for u, *_ in automorphisms(*base).orbits:
            for block, orbits in block_sites:
                for c, *_ in orbits:
                    child = _glue(base, u, block, c, k)
                    found.setdefault(self._key(child), child)

    def _all_chains(self, loops: int, dof: int) -> list[Graph]:
        """All chains, with or without a cut link."""
        key = (loops, dof)
        if key in self._all:
            return self._all[key]
        links = 2 * loops + dof + 1
        name = f"chains-n{links}-F{dof}-with-cut-links"
        saved = self._load_level(name)
        if saved is not None:
            self._all[key] = saved
            return saved
        found: dict[object, Graph] = {self._key(g): g for g in self._two_connected(loops, dof)}
        # G = G0 (any chain) + leaf block B + k bridging joints;
        # loops add up, DOF: F = F0 + FB + k, with F0, FB >= 1.
        for loops_b in range(1, loops):
            loops_0 = loops - loops_b
            for k in range(0, dof - 1):
                for dof_b in range(1, dof - k):
                    dof_0 = dof - k - dof_b
                    bases = self._all_chains(loops_0, dof_0)
                    blocks = self._two_connected(loops_b, dof_b)
                    if not bases or not blocks:
                        continue
                    block_sites = [(b, automorphisms(*b).orbits) for b in blocks]
                    for index, base in enumerate(bases):
                        self._clock.tick(lambda: f"{links} links, DOF {dof}: cut-link chains from base {index + 1}/{len(bases)}")
                        self._glue_blocks(base, block_sites, k, found)
        result = self._finish(found)
        self._save_level(name, result)
        self._all[key] = result
        self._clock.tick(lambda: f"{links} links, DOF {dof}: {len(result)} chains in all", force=True)
        return result


#: Rates measured on the reference machine (2 cores; docs/scale.md): a chain costs about this much more time per
#: two more links (0.29 ms a chain at 12 links, 0.49 ms at 14, one-DOF atlases built from nothing) ...
COST_GROWTH_PER_TWO_LINKS = 1.7
#: ... holds about this much memory while its atlas is built (1.69 GiB for the 318,162 chains of 14 links,
#: ``benchmarks/measure.py``), more for larger chains in proportion to their links ...
BYTES_PER_CHAIN_14 = 5700
#: ... and this share of the time stays in this process on a local cluster (the merge, the sort, the small
#: levels: 16.6 s of 140.5 s at 14 links, ``benchmarks/scale_model.py``): on N workers about T·(s + (1 − s)/N).
SERIAL_SHARE = 0.12
#: The largest atlas built to measure the rate here, and the growth assumed when too few sizes are known.
FORECAST_LINKS = 12
GROWTH_PER_TWO_LINKS = 30


#: Forecasts of atlases made by augmentation walk a stratified sample of this many starts here ...
FORECAST_STARTS = strata.BUDGET
#: ... and add, per chain, the CPU time this process takes to merge the parts' records into graph6 lines (1.5 µs:
#: 318,162 records of 14 links in 65 parts) and the memory it holds (a record and its list entry: the 14-link
#: run's main process peaked at 162 MiB, about 130 bytes a chain above its start) ...
MERGE_SECONDS_PER_CHAIN = 1.5e-6
HELD_BYTES_PER_CHAIN = 130
#: ... and, per process, its memory before any part (Python, numpy, nauty, a Dask worker) ...
PROCESS_BYTES = 1.6e8
#: ... and the imbalance of a local cluster, the busiest worker's work over the mean: assumed (the merge
#: generator's slices measured 1.03, benchmarks/scale_model.py; parts are many and of similar size).
IMBALANCE = 1.1


@dataclass(frozen=True)
class Forecast:
    """How large and how long an atlas is likely to be, before it is built: see :func:`forecast`.

    ``memory`` is the peak of all the processes of a run in one process; for an atlas made by augmentation,
    ``work`` is the CPU time of its parts (split over the workers), ``serial`` the time that stays in this
    process (the starts, the merge), and ``worker_memory`` the peak of one worker."""

    links: int
    dof: int
    count: float
    seconds: float
    memory: float
    basis: str
    work: float = 0.0
    serial: float = 0.0
    worker_memory: float = 0.0

    def seconds_on(self, workers: int) -> float:
        """The likely time on ``workers`` workers of a local cluster (:data:`SERIAL_SHARE` stays serial)."""
        if self.work:
            return self.serial + self.work * (IMBALANCE / workers if workers > 1 else 1.0)
        return self.seconds * (SERIAL_SHARE + (1 - SERIAL_SHARE) / max(1, workers))


def augment_forecast(links: int, dof: int, workers: int = 1, sample: int = FORECAST_STARTS, seed: int = 0,
                     progress: Progress | None = None) -> Forecast:
    """The likely size, time and memory of an atlas made by augmentation, from a sample of its starts walked here.

    The starts are sampled by strata (:func:`~domes.typesynth.strata.sample`:
    about ``sample`` starts, drawn with ``seed``), whose mean chains and CPU
    time per start, times their starts, estimate the whole and each part (the
    largest part sets a worker's memory); the merge and the memory held per
    chain are rates measured on 14 links (:data:`MERGE_SECONDS_PER_CHAIN`,
    :data:`HELD_BYTES_PER_CHAIN`). ``progress`` hears of the walks about once
    a second.

    >>> f = augment_forecast(12, 1, sample=60)              # 6856 chains in fact
    >>> 4800 < f.count < 9000, f.basis.startswith("a stratified sample of")
    (True, True)
    """
    loops = chain_joints(links, dof) - links + 1
    clock = Ticker(progress, every=1.0)
    clock.tick(lambda: f"forecast of {links} links: the starts of the walks and their strata", force=True)
    start = time.process_time()
    starts, parts = augment.plan(loops, dof, workers)
    planned = time.process_time() - start
    found = strata.sample(starts, loops, dof, sample, seed,
                          progress=lambda text: clock.tick(lambda: f"forecast of {links} links: {text}"))
    count, work = found.chains(), found.seconds()
    biggest = max(found.chains(range(i, len(starts), parts)) for i in range(parts))
    serial = planned + count * MERGE_SECONDS_PER_CHAIN
    worker = PROCESS_BYTES + 4 * biggest * augment.record_width(links)
    main = PROCESS_BYTES + count * HELD_BYTES_PER_CHAIN
    basis = (f"a stratified sample of {found.walked} of its {len(starts):,} starts walked here "
             f"({found.chains_walked:,} chains in {found.seconds_walked:.1f} s of CPU), scaled by stratum")
    return Forecast(links, dof, count, serial + work, main + worker, basis, work, serial, worker)


def forecast(links: int, dof: int, include_fractionated: bool = False, method: str = "merge",
             workers: int = 1, progress: Progress | None = None) -> Forecast:
    """The likely size, time (one process, this machine) and memory of an atlas, from smaller ones built now.

    With ``method`` ``augment`` (or ``auto`` from :data:`AUGMENT_LINKS` links), an atlas without a cut link is
    forecast from a sample of its own starts instead (:func:`augment_forecast`, cut for ``workers``; ``progress``
    hears of it).

    The three largest atlases of the same parity up to :data:`FORECAST_LINKS`
    links are built (about two seconds); the count is extrapolated from
    their growth (the ratio of successive counts grows as it did last), the
    time from the rate measured on the largest, made
    :data:`COST_GROWTH_PER_TWO_LINKS` dearer per two links, the memory from
    :data:`BYTES_PER_CHAIN_14`. Rough (a third off at 14 links), but enough
    to tell minutes from days.

    >>> f = forecast(12, 1)                         # 6856 chains in fact
    >>> f.basis.split(";")[0], 5000 < f.count < 8000
    ('extrapolated from 2, 16, 230 chains of 6, 8, 10 links', True)
    """
    chain_joints(links, dof)                            # a clear error for a size no chain has
    if not include_fractionated and dof >= 0 and (method == "augment" or (method == "auto" and links >= AUGMENT_LINKS)):
        return augment_forecast(links, dof, workers, progress=progress)
    top = links - 2
    while top > FORECAST_LINKS:
        top -= 2
    sizes = [b for b in (top - 4, top - 2, top) if b >= 3]
    generator = ChainGenerator()
    start = time.perf_counter()
    counts = [len(generator.chains(b, dof, include_fractionated)) if chain_joints(b, dof) - b >= 0 else 0
              for b in sizes]
    seconds_top = time.perf_counter() - start
    known = [(b, c) for b, c in zip(sizes, counts) if c > 0]
    steps = (links - top) // 2
    if len(known) >= 2 and known[-1][0] == top:
        ratios = [c2 / c1 for (_, c1), (_, c2) in zip(known, known[1:])]
        ratio, growth = ratios[-1], (ratios[-1] / ratios[-2] if len(ratios) > 1 else 1.0)
        count = float(known[-1][1])
        for _ in range(steps):
            ratio *= max(growth, 1.0)
            count *= ratio
    else:
        count = max(1.0, float(counts[-1] if counts else 1)) * GROWTH_PER_TWO_LINKS ** steps
    rate = seconds_top / max(counts[-1] if counts else 1, 1)
    seconds = count * rate * COST_GROWTH_PER_TWO_LINKS ** steps
    memory = 2e8 + count * BYTES_PER_CHAIN_14 * links / 14
    if len(known) >= 2 and known[-1][0] == top:
        basis = (f"extrapolated from {', '.join(str(c) for _, c in known)} chains of "
                 f"{', '.join(str(b) for b, _ in known)} links; the rate measured here on {top} links")
    else:
        basis = f"assumed {GROWTH_PER_TWO_LINKS}-fold per two links from {counts[-1] if counts else 1} chains of {top} links"
    return Forecast(links, dof, count, seconds, memory, basis)


@dataclass(frozen=True, repr=False)
class Atlas(Listing):
    """Every chain of one size: a sequence of :class:`~domes.model.Chain` and how it was made.

    ``isomorphism`` is the method that removed duplicates (the speed/accuracy
    knob); ``status`` is EMPTY when no chain has this size and DOF.

    >>> atlas = chains(links=6, dof=1)
    >>> len(atlas), atlas.success, atlas.message
    (2, True, '2 chains of 6 links, 7 joints, DOF 1 (without a cut link; duplicates removed by nauty, exact)')
    """

    chains: tuple[Chain, ...]
    links: int
    dof: int
    include_fractionated: bool = False
    isomorphism: str = "nauty"
    clamping: bool = False

    items_field = "chains"

    @property
    def joints(self) -> int:
        return joints_for(self.links, self.dof)

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.chains else Status.EMPTY

    @property
    def message(self) -> str:
        kind = "with or without a cut link" if self.include_fractionated else "without a cut link"
        if self.clamping:
            kind += ", immobile sub-chains admitted"
        method = "nauty, exact" if self.isomorphism == "nauty" else "the characteristic polynomial, not exact"
        what = "clamping chains" if self.clamping else "chains"
        return (f"{len(self.chains)} {what} of {self.links} links, {self.joints} joints, DOF {self.dof} "
                f"({kind}; duplicates removed by {method})")

    def __repr__(self) -> str:
        return f"<Atlas: {self.message}>"

    def _repr_html_(self) -> str | None:
        """The first chains drawn as cards, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


def chains(links: int, dof: int, include_fractionated: bool = False, isomorphism: str = "nauty",
           progress: Progress | None = None, generator: ChainGenerator | None = None, executor=None,
           clamping: bool = False, method: str = "auto") -> Atlas:
    """Every non-isomorphic, non-degenerate chain of planar motion with revolute joints (some graphs non-planar).

    Chains with a cut link (fractionated) are left out unless
    ``include_fractionated``. Returns an :class:`Atlas`: the
    :class:`~domes.model.Chain` objects, canonically labelled, sorted by link
    assortment. ``isomorphism`` is the knob (``nauty`` exact, ``charpoly``
    the book's inexact test); ``progress`` receives a line now and then;
    ``generator`` (a :class:`ChainGenerator`) keeps the atlases built, for
    callers that ask again; by default each call builds its own;
    ``executor`` (:mod:`domes.execution`) runs the large levels in parallel
    (same atlas). ``clamping`` admits immobile sub-chains and DOF ``≤ 0``:
    the chains of clamps (seed 002, §3-3-I (4), Fig. 3-23), see
    :meth:`ChainGenerator.chains`. ``method`` is how the chains without a
    cut link are generated (:data:`GENERATION_METHODS`; the same atlas).

    >>> len(chains(links=10, dof=1))
    230
    >>> len(chains(links=9, dof=2, include_fractionated=True))
    40
    >>> chains(links=6, dof=-1, clamping=True).message
    '9 clamping chains of 6 links, 8 joints, DOF -1 (without a cut link, immobile sub-chains admitted; duplicates removed by nauty, exact)'
    """
    if generator is None:
        generator = ChainGenerator(isomorphism=isomorphism, progress=progress, executor=executor,
                                   method="merge" if isomorphism != "nauty" and method == "auto" else method)
    elif generator.isomorphism != isomorphism:
        raise InputError(f"the generator removes duplicates by {generator.isomorphism!r}, not {isomorphism!r}")
    found = tuple(Chain(n, edges) for n, edges in generator.chains(links, dof, include_fractionated, clamping))
    return Atlas(found, links, dof, include_fractionated, isomorphism, clamping)


def atlas_position(chain: Chain, generator: ChainGenerator | None = None, clamping: bool = False) -> int | None:
    """The 1-based position of ``chain`` in its atlas (with cut links if it has one), or None.

    ``domes chains --links n --dof F [--include-fractionated]`` lists the chain
    at this position; a degenerate, disconnected or loop-free chain has none.
    With ``clamping``, the position in the clamping atlas (``--clamping``),
    where degenerate chains have one too.

    >>> atlas_position(Chain.from_graph6("ErOg"))   # the Stephenson chain
    1
    """
    if chain.loops < 1 or not chain.is_connected or min(chain.degrees, default=0) < 2:
        return None
    if clamping:
        if not clamping_in_reach(chain.n, chain.joints):
            return None
    elif chain.dof < 0 or chain.is_degenerate:
        return None
    listed = (generator or ChainGenerator()).chains(chain.n, chain.dof, include_fractionated=bool(chain.cut_links),
                                                    clamping=clamping)
    return next((i for i, (n, e) in enumerate(listed, 1) if Chain(n, e) == chain), None)
