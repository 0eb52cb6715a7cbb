"""Type synthesis of single-loop spatial chains (λ = 6) with R, P, C, H and S joints.

A single loop of ``n`` links has ``n`` joints, one between each link and the
next. Its joints are lower pairs of ``f`` freedoms: R (revolute), P
(prismatic) and H (helical) 1, C (cylindric) 2, S (spherical) 3. The
Kutzbach count of the loop (seed 002, (7-1) and §7-2 with λ = 6) is::

    M = 6(n − 1) − Σ (6 − f_i) = Σ f_i − 6

A link held by two S joints spins freely about the line through their
centres; the spin moves no other link, so it is an idle freedom, not a DOF
of the mechanism. The DOF of a chain is its Kutzbach count less its idle
freedoms, one per link whose two joints are both S: the RSSR (seed 001) has
``M = 8 − 6 = 2`` and one idle spin (the coupler's), so DOF 1, as the RCCC
(seed 004, ``M = 7 − 6 = 1``). This is the DOF of the chain, its links'
motions relative to each other. Made a mechanism with a frame held by two S
joints (the RSSR's coupler fixed, say), the frame's spin is seen as the
rest of the loop turning about the frame's S–S line, a real motion: such a
mechanism has one DOF more. The function generators below never have such
a frame (their input joint is R, P or H).

Two chains are the same when one's joint sequence is the other's read from
another link or the other way round: the loop's symmetries are the dihedral
group of its ``n`` rotations and ``n`` reflections, and each chain is listed
once, as the least of its ``2n`` readings (by the order R, P, H, C, S): the
RSSR is listed as RRSS, the frame being the link between its two R joints. A
helix's hand is the sign of its pitch, a dimension like a length, so H is
one joint type.

The Kutzbach count is generic: it holds for axes in general position. The
joint types alone can defeat it, whatever the dimensions: a loop of P joints
only translates (its closure is 3 equations, not 6), and three rotation
axes in general position cannot turn a loop alone, so a loop whose only
turning joints are three R's among P's keeps them still. Each chain
therefore also carries its *generic* DOF and the joints that stay still,
from the rank of its joints' screws placed at random in space (any
placement is an assembled pose of a single loop): ``generic_dof`` is the
loop's mobility there, less its idle spins, and ``locked`` lists the joints
whose rates are zero in every motion. Chains are listed by the Kutzbach
count, as the books count them; ``proper`` says whether the generic DOF is
that count and no joint is locked. Special dimensions (all R axes parallel,
a Bennett linkage) are not types and are not considered.

>>> found = spatial_loops(4, dof=1)
>>> len(found), found.get("RSSR").joints, found.get("CCCR").joints
(24, 'RRSS', 'RCCC')
>>> rssr = found.get("RSSR")
>>> rssr.kutzbach, rssr.idle, rssr.dof, rssr.proper
(2, 1, 1, True)
>>> found.get("PCCC").note()
'cannot move: the turn of joint 1 (C), the turn of joint 2 (C), the turn of joint 3 (C)'
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from domes.errors import InputError
from domes.model.labelled import LabelledChain
from domes.model.mobility import SPATIAL, check_count
from domes.results import Listing, Status

__all__ = [
    "FREEDOMS", "FunctionGenerator", "INPUT_JOINTS", "LABELLED_TYPES", "OUTPUT_JOINTS", "function_generators",
    "generic_mobility", "MAX_LOOP_LINKS", "SPATIAL_JOINT_TYPES", "SPATIAL_LETTERS", "SpatialLoop", "SpatialLoops",
    "canonical_loop", "kutzbach", "idle_freedoms", "loop_reading", "spatial_loops", "spatial_phrase",
]

#: Freedoms of the spatial lower pairs, in the order that ranks the readings of a loop.
FREEDOMS: dict[str, int] = {"R": 1, "P": 1, "H": 1, "C": 2, "S": 3}
#: The joint types, as in spatial mechanism files (docs/spatial.md), with their names.
SPATIAL_JOINT_TYPES: dict[str, str] = {
    "R": "revolute", "P": "prismatic", "H": "helical", "C": "cylindric", "S": "spherical",
}
#: The largest loop listed: 12 links (a loop of DOF F has at most F + 6 links).
MAX_LOOP_LINKS = 12
_ORDER = {t: i for i, t in enumerate(FREEDOMS)}
_RANK = str.maketrans({t: str(i) for i, t in enumerate(FREEDOMS)})
_UNRANK = str.maketrans({str(i): t for i, t in enumerate(FREEDOMS)})


def kutzbach(joints: str) -> int:
    """``Σ f − 6``: the Kutzbach count of a single loop with these joints.

    >>> kutzbach("RSSR"), kutzbach("RRRRRRR")
    (2, 1)
    """
    return sum(FREEDOMS[t] for t in _loop(joints)) - SPATIAL


def idle_freedoms(joints: str) -> int:
    """Links of the loop held by two S joints (each spins idle about their line).

    Link ``i`` lies between joints ``i`` and ``i + 1`` (the last between the last and the first joint).

    >>> idle_freedoms("RSSR"), idle_freedoms("SSS"), idle_freedoms("SRS")
    (1, 3, 1)
    """
    joints = _loop(joints)
    n = len(joints)
    return sum(joints[i] == "S" and joints[(i + 1) % n] == "S" for i in range(n))


def canonical_loop(joints: str) -> str:
    """The least of the ``2n`` readings of a loop (rotations and reflections), by the order R, P, H, C, S.

    >>> canonical_loop("RSSR"), canonical_loop("CCCR")
    ('RRSS', 'RCCC')
    """
    return _canonical(_loop(joints))


def _canonical(joints: str) -> str:
    ranked = joints.translate(_RANK)
    n = len(ranked)
    least = min(seq[k:] + seq[:k] for seq in (ranked, ranked[::-1]) for k in range(n))
    return least.translate(_UNRANK)


def _loop(joints: object) -> str:
    """``joints`` in capitals, or an InputError naming what is wrong."""
    if not isinstance(joints, str) or not joints:
        raise InputError(f"a loop's joints are a string of R, P, H, C, S (e.g. 'RSSR'), got {joints!r}")
    bad = sorted({t for t in joints.upper() if t not in FREEDOMS})
    if bad:
        raise InputError(f"joints {joints!r}: unknown joint type(s) {', '.join(map(repr, bad))}; the spatial lower "
                         "pairs are " + ", ".join(f"{t} ({name})" for t, name in SPATIAL_JOINT_TYPES.items()))
    return joints.upper()


def _symmetry(joints: str) -> int:
    """How many of the ``2n`` readings give the loop itself (the order of its symmetry group)."""
    n = len(joints)
    return sum(seq[k:] + seq[:k] == joints for seq in (joints, joints[::-1]) for k in range(n))


def _screws(joints: str, rng: np.random.Generator) -> tuple[np.ndarray, list[tuple[int, str]]]:
    """The unit screws (ω; p × ω + hω) of the loop's joint freedoms at a random pose, and each column's freedom.

    Each joint has a random point ``p`` and axis ``a`` (an S joint turns about the three coordinate axes
    through ``p``); an H joint has a random pitch ``h``.
    """
    n = len(joints)
    points, axes, pitch = rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), rng.normal(size=n)
    axes /= np.linalg.norm(axes, axis=1)[:, None]
    turn = np.hstack([axes, np.cross(points, axes)])
    slide = np.hstack([np.zeros((n, 3)), axes])
    columns, owner = [], []
    for i, t in enumerate(joints):
        if t == "S":
            eye = np.eye(3)
            columns.append(np.hstack([eye, np.cross(points[i], eye)]))
            owner += [(i, "turn")] * 3
            continue
        if t in "RHC":
            columns.append((turn[i] + (pitch[i] * slide[i] if t == "H" else 0))[None])
            owner.append((i, "turn"))
        if t in "PC":
            columns.append(slide[i][None])
            owner.append((i, "slide"))
    return np.vstack(columns).T, owner


def generic_mobility(joints: str, seed: int = 0) -> tuple[int, tuple[tuple[int, str], ...]]:
    """The loop's mobility with its joints in general position, and the freedoms that cannot move.

    The rank of the joints' screws at a random pose (the largest of up to
    three placements) is the rank of the velocity closure ``Σ q̇ $ = 0``; a
    freedom (a joint's ``turn`` or ``slide``; an H joint's screw motion is
    its turn) is locked when its rate is zero in every solution.

    >>> generic_mobility("RSSR"), generic_mobility("PPPPPPP")
    ((2, ()), (4, ()))
    >>> generic_mobility("RRRPPPP")
    (1, ((0, 'turn'), (1, 'turn'), (2, 'turn')))
    """
    joints = _loop(joints)
    rng = np.random.default_rng(seed)
    best = None
    for _ in range(3):
        screws, owner = _screws(joints, rng)
        _, s, vt = np.linalg.svd(screws)
        rank = int(np.sum(s > 1e-9 * s[0]))
        if best is None or rank > best[0]:
            best = (rank, vt[rank:].T, owner)
        if rank == min(screws.shape):  # full rank: no placement does better
            break
    rank, kernel, owner = best
    moves: dict[tuple[int, str], float] = {}
    for row, freedom in zip(kernel, owner):
        moves[freedom] = max(moves.get(freedom, 0.0), float(np.max(np.abs(row), initial=0.0)))
    locked = tuple(freedom for freedom, rate in moves.items() if rate < 1e-9)
    return len(owner) - rank, locked


@dataclass(frozen=True)
class SpatialLoop:
    """A single-loop spatial chain: its joint types in loop order (the canonical reading).

    Link ``i`` lies between joints ``i`` and ``i + 1``.

    >>> loop = SpatialLoop("RCCC")
    >>> loop.links, loop.freedom, loop.kutzbach, loop.idle, loop.dof, loop.symmetry
    (4, 7, 1, 0, 1, 2)
    """

    joints: str

    def __post_init__(self) -> None:
        if len(_loop(self.joints)) < 3:
            raise InputError(f"a loop has 3 links or more, got {self.joints!r}")
        object.__setattr__(self, "joints", self.joints.upper())

    @property
    def links(self) -> int:
        return len(self.joints)

    @property
    def freedom(self) -> int:
        """``Σ f``."""
        return sum(FREEDOMS[t] for t in self.joints)

    @property
    def kutzbach(self) -> int:
        """``Σ f − 6``."""
        return kutzbach(self.joints)

    @property
    def idle(self) -> int:
        """Idle spins: links held by two S joints."""
        return idle_freedoms(self.joints)

    @property
    def dof(self) -> int:
        """The Kutzbach count less the idle spins."""
        return self.kutzbach - self.idle

    @property
    def symmetry(self) -> int:
        """The order of the loop's symmetry group (readings that give it back; 2n for a loop of one joint type)."""
        return _symmetry(self.joints)

    @cached_property
    def _generic(self) -> tuple[int, tuple[int, ...]]:
        return generic_mobility(self.joints)

    @property
    def generic_dof(self) -> int:
        """The DOF with the joints in general position (screw rank), less the idle spins."""
        return self._generic[0] - self.idle

    @property
    def locked(self) -> tuple[tuple[int, str], ...]:
        """Freedoms ``(joint, "turn" or "slide")`` that stay still in every motion of the loop in general position."""
        return self._generic[1]

    @property
    def proper(self) -> bool:
        """The generic DOF is the Kutzbach count's and every joint moves."""
        return self.generic_dof == self.dof and not self.locked

    def note(self) -> str:
        """Why the Kutzbach count does not describe the loop, or ''."""
        parts = []
        if self.generic_dof != self.dof:
            parts.append(f"generic DOF {self.generic_dof}, not {self.dof}")
        if self.locked:
            parts.append("cannot move: " + ", ".join(f"the {kind} of joint {i} ({self.joints[i]})"
                                                      for i, kind in self.locked))
        return "; ".join(parts)

    def to_dict(self) -> dict:
        return {"joints": self.joints, "links": self.links, "freedom": self.freedom, "kutzbach": self.kutzbach,
                "idle": self.idle, "dof": self.dof, "generic_dof": self.generic_dof, "locked": [list(x) for x in self.locked],
                "proper": self.proper, "symmetry": self.symmetry}


@dataclass(frozen=True)
class SpatialLoops(Listing):
    """Every single-loop spatial chain of ``links`` links and DOF ``dof`` with the given joint types.

    >>> spatial_loops(3, dof=1).names
    ('CCS', 'CSS')
    """

    links: int
    dof: int
    joint_types: str
    loops: tuple[SpatialLoop, ...]

    items_field = "loops"
    status = Status.COMPLETE

    @property
    def message(self) -> str:
        return (f"{len(self.loops)} single-loop spatial chain{'' if len(self.loops) == 1 else 's'} of {self.links} links, DOF {self.dof}, joints "
                f"{', '.join(self.joint_types)} ({sum(loop.proper for loop in self.loops)} proper)")

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(loop.joints for loop in self.loops)

    def get(self, joints: str) -> SpatialLoop:
        """The listed chain with this joint sequence (read any way round)."""
        key = canonical_loop(joints)
        for loop in self.loops:
            if loop.joints == key:
                return loop
        raise InputError(f"{joints!r} is not among the {len(self.loops)} chains of {self.links} links, DOF {self.dof}")


def _check_types(joints: str) -> str:
    """The allowed joint types, each once, in the order R, P, H, C, S."""
    letters = _loop(joints)
    return "".join(t for t in FREEDOMS if t in letters)


def spatial_loops(links: int, dof: int = 1, joints: str = "RPHCS") -> SpatialLoops:
    """Every single-loop chain of ``links`` links and DOF ``dof`` (Kutzbach less idle spins), up to symmetry.

    ``joints`` are the joint types allowed, from R, P, H, C, S. Chains come
    in the order of their canonical readings (R < P < H < C < S).

    >>> spatial_loops(4, dof=1, joints="RCS").names
    ('RRCS', 'RRSS', 'RCRS', 'RCCC')
    >>> len(spatial_loops(7, dof=1, joints="R"))
    1
    """
    check_count("links", links, 0)
    check_count("dof", dof, 0)
    if not 3 <= links <= MAX_LOOP_LINKS:
        raise InputError(f"links: a single loop has 3 to {MAX_LOOP_LINKS} links here, got {links} (two links "
                         "are joined by one pair, not a loop)")
    types = _check_types(joints)
    target = dof + SPATIAL          # Σ f − idle
    found: list[str] = []

    def extend(prefix: list[str], used: int) -> None:
        # ``used`` counts Σ f less the idle spins among the joints placed; each joint left adds at least 1
        # (an S after an S adds 3 − 1), and closing the loop S to S takes one more spin away.
        left = links - len(prefix)
        if used + left > target + (1 if prefix and prefix[0] == "S" else 0):
            return
        if not left:
            seq = "".join(prefix)
            if used - (prefix[0] == "S" == prefix[-1]) == target and seq == _canonical(seq):
                found.append(seq)
            return
        for t in types:
            if prefix and _ORDER[t] < _ORDER[prefix[0]]:  # the least reading starts with the least joint type
                continue
            gain = FREEDOMS[t] - (1 if prefix and prefix[-1] == "S" and t == "S" else 0)
            extend(prefix + [t], used + gain)

    extend([], 0)
    found.sort(key=lambda seq: seq.translate(_RANK))
    loops = tuple(SpatialLoop(seq) for seq in found)
    assert all(loop.dof == dof for loop in loops)
    return SpatialLoops(links, dof, types, loops)


#: Joints that can drive a function generator (one freedom, one input), and that can carry its output
#: (one variable to read: a C joint's turn or slide, not an S joint's three turns).
INPUT_JOINTS, OUTPUT_JOINTS = "RPH", "RPHC"
#: Labelled-chain symbols of the spatial joints (``domes.model.labelled.JOINT_TYPES``: C, S and H there are
#: the cam, the spring and the hydraulic cylinder of seed 002's Table 3-5).
LABELLED_TYPES = {"R": "R", "P": "P", "H": "Hel", "C": "Cyl", "S": "Sph"}


@dataclass(frozen=True)
class FunctionGenerator:
    """A single loop with a frame, an input link and an output link, both jointed to the frame.

    ``joints`` reads the loop from the input joint (frame–input) round to the
    output joint (output–frame); link 0 is the frame, link 1 the input and
    the last link the output. ``loop`` is the chain it comes from.

    >>> gen = FunctionGenerator("RSSR", SpatialLoop("RRSS"))
    >>> gen.labelled().joint_types, sorted(gen.labelled().roles[1])
    (('R', 'R', 'Sph', 'Sph'), ['input'])
    """

    joints: str
    loop: SpatialLoop

    def labelled(self) -> LabelledChain:
        """The labelled chain: links ``0..n−1`` (0 the frame), joint ``k`` between links ``k`` and ``k + 1 (mod n)``."""
        n = len(self.joints)
        edges = [(k, k + 1) for k in range(n - 1)] + [(n - 1, 0)]
        types = [LABELLED_TYPES[t] for t in self.joints]
        return LabelledChain.build(n, edges, types, roles={0: {"ground"}, 1: {"input"}, n - 1: {"output"}},
                                   name=self.joints)


def function_generators(loops: SpatialLoops | list[SpatialLoop], proper: bool = True) -> list[FunctionGenerator]:
    """Every way to make function generators of the loops: a frame link, its neighbours input and output.

    The input joint must be R, P or H (driven by one input), the output joint
    R, P, H or C (one variable read); two readings that give the same string
    are one mechanism. ``proper`` keeps only loops whose every freedom moves
    and whose generic DOF is the Kutzbach count's.

    >>> names = [g.joints for g in function_generators(spatial_loops(4, dof=1, joints="RCS"))]
    >>> names
    ['RCSR', 'RRSC', 'RSCR', 'RSSR', 'RSRC', 'RCCC']
    """
    found: dict[str, FunctionGenerator] = {}
    for loop in loops:
        if proper and not loop.proper:
            continue
        n = loop.links
        for seq in (loop.joints, loop.joints[::-1]):
            for k in range(n):
                reading = seq[k:] + seq[:k]
                if reading[0] in INPUT_JOINTS and reading[-1] in OUTPUT_JOINTS:
                    found.setdefault(reading, FunctionGenerator(reading, loop))
    return list(found.values())


#: Spatial joint letters of the labelled chains' symbols (the inverse of :data:`LABELLED_TYPES`).
SPATIAL_LETTERS = {symbol: letter for letter, symbol in LABELLED_TYPES.items()}


def loop_reading(candidate: LabelledChain | dict) -> str | None:
    """The joints of a single-loop function generator, read from the input joint round to the output joint.

    ``candidate`` is a labelled chain (or its plain data) as
    :meth:`FunctionGenerator.labelled` makes it: one loop, a link with the
    role ``ground``, its neighbours ``input`` and ``output``. None when it is
    not such a loop (several loops, no frame, input or output off the frame).

    >>> loop_reading(FunctionGenerator("RSSR", SpatialLoop("RRSS")).labelled().to_dict())
    'RSSR'
    """
    walk = _walk(candidate)
    return None if walk is None else walk[0]


def _walk(candidate: LabelledChain | dict) -> tuple[str, tuple[int, ...]] | None:
    """The joint letters from the input joint round to the output joint, and the links passed (frame first)."""
    chain = candidate if isinstance(candidate, LabelledChain) else LabelledChain.from_dict(candidate)
    if chain.n < 3 or len(chain.edges) != chain.n or any(d != 2 for d in chain.degrees):
        return None
    role = {r: [v for v in range(chain.n) if r in chain.roles[v]] for r in ("ground", "input", "output")}
    if any(len(found) != 1 for found in role.values()):
        return None
    ground, first, last = role["ground"][0], role["input"][0], role["output"][0]
    if first == last or {first, last} != set(chain.neighbours[ground]):
        return None
    letters, links, before, link = [], [ground], ground, first
    while True:
        letters.append(SPATIAL_LETTERS.get(chain.joint_type(before, link), "?"))
        if link == ground:
            break
        links.append(link)
        before, link = link, next(v for v in chain.neighbours[link] if v != before)
    return "".join(letters), tuple(links)


def spatial_phrase(candidate: LabelledChain | dict) -> str:
    """A spatial candidate in words: its links and joints read from the input joint, and its DOF count.

    The DOF is the Kutzbach count ``Σ f − 6`` less the idle spins; a link
    held by two S joints is flagged: it spins about the line through their
    centres, a freedom the count sees that drives nothing (seed 001's RSSR:
    count 2, DOF 1).

    >>> spatial_phrase(FunctionGenerator("RSSR", SpatialLoop("RRSS")).labelled())
    '4 links: R-S-S-R, DOF 1 (Kutzbach count 2, less 1 idle spin: link 2 turns freely about the line through the centres of its two S joints)'
    >>> spatial_phrase(FunctionGenerator("RCCC", SpatialLoop("RCCC")).labelled())
    '4 links: R-C-C-C, DOF 1'
    """
    walk = _walk(candidate)
    if walk is None:
        chain = candidate if isinstance(candidate, LabelledChain) else LabelledChain.from_dict(candidate)
        return f"{chain.n} links, {len(chain.edges)} joints ({', '.join(chain.joint_types)}): not a single loop"
    joints, links = walk
    n = len(joints)
    text = f"{n} links: {'-'.join(joints)}"
    if "?" in joints:
        return text
    spinning = [k for k in range(1, n) if joints[k - 1] == joints[k] == "S"]
    if joints[-1] == joints[0] == "S":
        spinning.append(0)
    dof = kutzbach(joints) - len(spinning)
    if not spinning:
        return f"{text}, DOF {dof}"
    which = ", ".join(f"link {links[k]}" for k in spinning)
    verb = "turns" if len(spinning) == 1 else "turn"
    return (f"{text}, DOF {dof} (Kutzbach count {kutzbach(joints)}, less {len(spinning)} idle spin"
            f"{'' if len(spinning) == 1 else 's'}: {which} {verb} freely about the line through the centres of "
            f"{'its' if len(spinning) == 1 else 'their'} two S joints)")
