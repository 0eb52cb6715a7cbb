"""The size of an atlas made by augmentation, forecast from a stratified sample of its walks' starts.

The starts of the walks (:func:`~domes.typesynth.augment.plan`) differ in
the chains they lead to by three orders of magnitude: at 14 links, DOF 1,
the 230 starts of DOF 1 (of 16,147) lead to 61% of the chains, 114 starts to
half, 14,885 to none; and a start with a long removable branch leads to few
(every later ear must be at least as long: the canonical ear is the largest). So the starts are cut into
*strata* by what is seen at once (:func:`stratum`: their DOF, the degrees of
their links, the length of their longest removable branch); one start of
each stratum is walked (the pilot), then the rest of the budget goes to the
strata in proportion to their size times the square root of one more than
the pilot's chains (Neyman's allocation with a spread and a cost that grow
with the chains; counts, not CPU times, so that a seed draws the same
sample on any machine).
Each stratum's mean chains and CPU time per start, times its starts, is its
share; a part (or any set of starts) is forecast the same way.

>>> from domes.typesynth import augment
>>> starts, _ = augment.plan(5, 1)                          # 12 links, DOF 1: 6,856 chains
>>> s = sample(starts, 5, 1, budget=60)
>>> 4800 < s.chains() < 9000, s.walked <= 60
(True, True)
"""

from __future__ import annotations

import math
import random
import time
from collections import defaultdict
from dataclasses import dataclass, field

from domes.typesynth import augment

#: Starts walked by a forecast (the pilot's one a stratum included): at 14 links, DOF 1, a tenth of the work, and
#: the count within 27% in each of 300 draws from a census of every start (docs/scale.md).
BUDGET = 300


def stratum(graph: augment.Graph) -> tuple:
    """The stratum of a start: its DOF, its links' degrees (largest first), its longest removable branch.

    >>> stratum(augment.cycle(5))
    (2, (2, 2, 2, 2, 2), 0)
    """
    n, edges = graph
    adjm = [0] * n
    for a, b in edges:
        adjm[a] |= 1 << b
        adjm[b] |= 1 << a
    deg = [m.bit_count() for m in adjm]
    longest = 0
    if max(deg) > 2:
        full = (1 << n) - 1
        for br in sorted(augment._branches(n, adjm, deg), key=lambda br: len(br[2]), reverse=True):
            if augment._removable(adjm, full, br):
                longest = len(br[2])
                break
    return 3 * (n - 1) - 2 * len(edges), tuple(sorted(deg, reverse=True)), longest


@dataclass
class Sample:
    """A stratified sample of starts walked: each start's stratum, and per stratum the chains and CPU seconds
    of the starts walked."""

    strata: list                                          # the stratum of each start
    walks: dict = field(default_factory=dict)             # stratum -> [(chains, seconds), ...]
    sizes: dict = field(default_factory=dict)             # stratum -> its starts

    @property
    def walked(self) -> int:
        return sum(len(w) for w in self.walks.values())

    @property
    def seconds_walked(self) -> float:
        return sum(s for w in self.walks.values() for _, s in w)

    @property
    def chains_walked(self) -> int:
        return sum(c for w in self.walks.values() for c, _ in w)

    def _mean(self, key, what: int) -> float:
        w = self.walks.get(key)
        return sum(x[what] for x in w) / len(w) if w else 0.0

    def chains(self, indices=None) -> float:
        """The chains forecast for the starts of ``indices`` (all if None)."""
        return self._total(indices, 0)

    def seconds(self, indices=None) -> float:
        """The CPU seconds forecast for walking the starts of ``indices`` (all if None)."""
        return self._total(indices, 1)

    def _total(self, indices, what: int) -> float:
        counts = self.sizes if indices is None else _count(self.strata[i] for i in indices)
        return sum(n * self._mean(key, what) for key, n in counts.items())


def _count(keys) -> dict:
    out: dict = defaultdict(int)
    for key in keys:
        out[key] += 1
    return out


def walk_start(graph: augment.Graph, loops: int, dof: int) -> tuple[int, float]:
    """The chains of ``loops`` loops and DOF ``dof`` one start leads to, and the CPU seconds of its walk."""
    clock = time.process_time()
    _, stats = augment.descend([graph], loops, dof)
    return stats.kept, time.process_time() - clock


def walk_starts(task: tuple) -> list[tuple[int, float]]:
    """A task for a worker: ``(starts, loops, dof)`` -> :func:`walk_start` of each (a census of the starts)."""
    starts, loops, dof = task
    return [walk_start(g, loops, dof) for g in starts]


def sample(starts: list, loops: int, dof: int, budget: int = BUDGET, seed: int = 0, walk=None,
           progress=None, strata: list | None = None) -> Sample:
    """Walk a stratified sample of about ``budget`` of ``starts`` (to chains of ``loops`` loops, DOF ``dof``):
    one start of each stratum, then the rest of the budget shared by size times the square root of one more
    than the pilot's chains. ``walk(i)`` gives ``(chains, CPU seconds)`` of start ``i`` (by default it is walked
    here); ``progress(text)``, if given, is called after each start walked; ``strata``, the starts' strata if
    known."""
    if walk is None:
        def walk(i):
            return walk_start(starts[i], loops, dof)
    strata = strata if strata is not None else [stratum(g) for g in starts]
    members: dict = defaultdict(list)
    for i, key in enumerate(strata):
        members[key].append(i)
    result = Sample(strata, {}, {key: len(m) for key, m in members.items()})
    draw = random.Random(seed)
    order = sorted(members)
    picked = {key: draw.sample(members[key], len(members[key])) for key in order}     # each stratum shuffled
    total = min(budget, len(starts))

    def run(key, count):
        for i in picked[key][len(result.walks.get(key, ())):][:count]:
            result.walks.setdefault(key, []).append(walk(i))
            if progress is not None:
                progress(f"walked {result.walked} of about {total} sampled starts (of {len(starts):,})")

    for key in order:
        run(key, 1)
    left = total - result.walked
    if left > 0:
        weight = {key: len(members[key]) * math.sqrt(result._mean(key, 0) + 1) for key in order}
        whole = sum(weight.values())
        if whole > 0:
            for key in order:
                run(key, round(left * weight[key] / whole))
    return result
