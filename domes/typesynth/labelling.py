"""The labelled graph generator: joint types on the joints of chains (DOMES module 7).

Given chains and how many joints of each type they must have (``P``, ``G``,
...; all others revolute), list every labelling that is different up to the
automorphisms of the chain that keep the labels. Joints are typed one at a
time; after each step duplicates are removed by the labelled chain's nauty
certificate, which is exact and complete (every labelling with one joint
less is isomorphic to a kept one).

Loop limits (e.g. "number of gear pairs should not be more than 1 for any
independent loop", seed 002 §7-2, digest 4.5 criterion iii) hold when some
cycle basis consists of loops within the limits, i.e. the simple cycles
within the limits span the cycle space (their GF(2) rank is ``L``). No one
basis is invariant under isomorphism; "every simple cycle" would be too
strict, since in a chain without cut links any two joints share a cycle.

>>> from domes.typesynth import chains
>>> len(label_joints(chains(links=4, dof=1), {"P": 1}))
1
>>> len(label_joints(chains(links=4, dof=1), {"P": 2}))
2
>>> len(label_joints(chains(links=6, dof=1), {"G": 2}, per_loop_max={"G": 1}))
11
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Mapping

from domes.errors import InputError
from domes.model.chain import Chain
from domes.model.labelled import JOINT_TYPES, LabelledChain
from domes.model.topology import gf2_rank
from domes.results import Listing, Progress, Status, Ticker


def _within_limits(chain: LabelledChain, types: tuple[str, ...], limits: Mapping[str, int]) -> bool:
    """Whether the loops within the limits span the cycle space (some cycle basis keeps the limits)."""
    topo = chain.topology
    typed = {t: sum(1 << i for i, x in enumerate(types) if x == t) for t in limits}
    ok = [mask for mask in topo.cycle_edges if all((mask & typed[t]).bit_count() <= m for t, m in limits.items())]
    return gf2_rank(ok) == topo.loops


@dataclass(frozen=True, repr=False)
class Labelling(Listing):
    """The labelled chains of :func:`label_joints`: a sequence of :class:`~domes.model.LabelledChain`."""

    labelled: tuple[LabelledChain, ...]
    counts: tuple[tuple[str, int], ...]
    per_loop_max: tuple[tuple[str, int], ...] = ()
    chains: int = 0

    items_field = "labelled"

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.labelled else Status.EMPTY

    @property
    def message(self) -> str:
        counts = ", ".join(f"{k} {t}" for t, k in self.counts) or "no special"
        limits = f", at most {', '.join(f'{m} {t}' for t, m in self.per_loop_max)} per loop" if self.per_loop_max else ""
        return f"{len(self.labelled)} labelled chains of {self.chains} chains with {counts} joints{limits}"

    def __repr__(self) -> str:
        return f"<Labelling: {self.message}>"


def label_joints(
    chains: Iterable[Chain | LabelledChain],
    counts: Mapping[str, int],
    per_loop_max: Mapping[str, int] | None = None,
    progress: Progress | None = None,
) -> Labelling:
    """Every non-isomorphic assignment of ``counts[t]`` joints of type ``t`` (the rest ``R``).

    ``per_loop_max[t]`` bounds the joints of type ``t`` on any loop.
    Labellings are listed chain by chain, in a deterministic order.
    """
    for t, k in counts.items():
        if t not in JOINT_TYPES or t == "R":
            raise InputError(f"cannot count joint type {t!r}; choose among {', '.join(x for x in JOINT_TYPES if x != 'R')}")
        if not isinstance(k, int) or isinstance(k, bool) or k < 0:
            raise InputError(f"the number of {t} joints must be a whole number >= 0, got {k!r}")
    limits = dict(per_loop_max or {})
    for t, m in limits.items():
        if t not in JOINT_TYPES:
            raise InputError(f"unknown joint type {t!r} in the loop limits")
        if not isinstance(m, int) or isinstance(m, bool) or m < 0:
            raise InputError(f"the loop limit of {t} joints must be a whole number >= 0, got {m!r}")
    chains = list(chains)
    result: list[LabelledChain] = []
    clock = Ticker(progress)
    for number, chain in enumerate(chains, 1):
        clock.tick(lambda: f"chain {number}/{len(chains)}: {len(result)} labelled chains so far")
        start = chain if isinstance(chain, LabelledChain) else LabelledChain.from_chain(chain)
        if sum(counts.values()) > len(start.edges):
            continue
        layer = [start]
        for t, k in sorted(counts.items()):
            for _ in range(k):
                seen: dict[tuple, LabelledChain] = {}
                for labelled in layer:
                    types = labelled.joint_types
                    for i in range(len(types)):
                        if types[i] != "R":
                            continue
                        new_types = types[:i] + (t,) + types[i + 1 :]
                        if limits and not _within_limits(labelled, new_types, limits):
                            continue
                        child = labelled.with_joint_types(new_types)
                        seen.setdefault(child.certificate, child)
                layer = list(seen.values())
        result.extend(sorted(layer, key=lambda c: c.certificate))
    return Labelling(tuple(result), tuple(sorted(counts.items())), tuple(sorted(limits.items())), len(chains))
