"""The compiled tests of the walk by canonical augmentation (domes.typesynth.earkernel) against the pure-Python
ones, branch by branch and ear by ear, and a walk made by each route."""

import pytest

from domes.typesynth import augment, earkernel
from domes.typesynth.atlas import ChainGenerator

pytestmark = pytest.mark.skipif(earkernel.load() is None, reason="numba is not installed (or turned off)")


def _python(monkeypatch):
    monkeypatch.setattr(earkernel, "_loaded", [None])


@pytest.fixture(scope="module")
def parents():
    merged = ChainGenerator(method="merge")
    return merged.chains(10, 3)[::2] + merged.chains(9, 2) + merged.chains(10, 1)


def test_removable_branches_compiled_and_python_agree(parents, monkeypatch):
    compiled, found = [], 0
    for n, edges in parents:
        parent = augment._Parent((n, edges))
        compiled.append(augment.removable_branches(n, parent.adjm, parent.branches))
        for u, v, k in ((0, n - 1, 0), (1, n // 2, 1), (2, n - 2, 2)):       # children, branches split or not
            if k or not parent.adjm[u] >> v & 1:
                _, _, adjm, branches, _, _ = parent.child(u, v, k)
                compiled.append(augment.removable_branches(n + k, adjm, branches))
    _python(monkeypatch)
    i = 0
    for n, edges in parents:
        parent = augment._Parent((n, edges))
        assert augment.removable_branches(n, parent.adjm, parent.branches) == compiled[i]
        i += 1
        for u, v, k in ((0, n - 1, 0), (1, n // 2, 1), (2, n - 2, 2)):
            if k or not parent.adjm[u] >> v & 1:
                _, _, adjm, branches, _, _ = parent.child(u, v, k)
                assert augment.removable_branches(n + k, adjm, branches) == compiled[i]
                found += sum(compiled[i]) < len(compiled[i])
                i += 1
    assert i > 200 and found > 20                   # branches both removable and not were met


def test_ear_rigidity_compiled_and_python_agree(parents, monkeypatch):
    cases = []
    for n, edges in parents[::10]:
        parent = augment._Parent((n, edges))
        for u in range(n):
            for v in range(u + 1, n):
                for k in (0, 1):
                    if k or not parent.adjm[u] >> v & 1:
                        _, deg, _, branches, mine, _ = parent.child(u, v, k)
                        cases.append((n + k, deg, branches, mine))
    compiled = [augment.ear_is_free(*case) for case in cases]
    _python(monkeypatch)
    assert [augment.ear_is_free(*case) for case in cases] == compiled
    assert 0 < sum(compiled) < len(compiled)


def test_a_walk_by_either_route_gives_the_same_records(monkeypatch):
    starts, parts = augment.plan(loops=5, dof=1, workers=1)          # 12 links, DOF 1: 6,856 chains
    picked = starts[::7]
    compiled, _ = augment.descend(picked, 5, 1)
    _python(monkeypatch)
    assert augment.descend(picked, 5, 1)[0] == compiled and len(compiled) > 300
