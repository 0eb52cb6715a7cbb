"""Number synthesis against the seed's worked examples (seed 002, §7-1, §7-2, Table 3-1)."""

import pytest

from domes.errors import DomesError
from domes.typesynth import chain_joints, link_assortments, number_synthesis


@pytest.mark.parametrize(
    "dof, loops, gears, links, joints",
    [
        (1, 2, 0, 6, 7),  # DOMES §7-2 example: W=1, λ=3, L=2, j_G=0 -> i=6, j=7
        (1, 3, 0, 8, 10),  # DOMES §7-2 example: L=3 -> i=8, j=10
        (1, 1, 0, 4, 4),  # four-bar, (3-6): (n, p, L) = (4, 4, 1)
        (1, 4, 0, 10, 13),  # (3-6): (10, 13, 4)
    ],
)
def test_domes_formulas(dof, loops, gears, links, joints):
    result = number_synthesis(dof=dof, loops=loops, gear_pairs=gears)
    assert (result.links, result.joints) == (links, joints)


def test_pump_example_mecxprt():
    # seed 002 §7-1 (digest A5): Hoeltzel's pump, W = 1, three loops, R and P joints only -> 8 links, 10 joints
    result = number_synthesis(dof=1, loops=3)
    assert (result.links, result.joints) == (8, 10)


@pytest.mark.parametrize("dof, loops, gears", [(1, 2, 1), (2, 3, 1), (1, 3, 2), (0, 2, 0)])
def test_solution_satisfies_the_mobility_equations(dof, loops, gears):
    # Independent check: substitute back into W = λ(i − j − 1) + Σf (gear pairs have f = 2)
    # and L = j − i + 1 (digest part 4.2, corrected forms).
    for space in (3, 6):
        r = number_synthesis(dof=dof, loops=loops, space=space, gear_pairs=gears)
        assert space * (r.links - r.joints - 1) + r.joints + gears == dof
        assert r.joints - r.links + 1 == loops


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"dof": -1, "loops": 2}, "dof"),
        ({"dof": 1, "loops": -1}, "loops"),
        ({"dof": 1, "loops": 2, "space": 4}, "space"),
        ({"dof": 0, "loops": 0, "gear_pairs": 3}, "gear"),
        ({"dof": 1.5, "loops": 2}, "integer"),
    ],
)
def test_impossible_requests_are_refused(kwargs, message):
    with pytest.raises(DomesError, match=message):
        number_synthesis(**kwargs)


def test_odd_joint_count_is_refused():
    with pytest.raises(DomesError, match="not an integer"):
        chain_joints(5, 1)
    with pytest.raises(DomesError, match=">= 0"):
        chain_joints(6, -1)


# Table 3-1 (seed 002 §3-2-I.3), corrected as in the digest: the last n_2 is 7.
# Columns No. 1..12: (V, b, l, n_3, n_4, n_5, n_2); m = 3V, n = 2V + 1.
TABLE_3_1 = [
    (1, 0, 0, 0, 0, 0, 3),
    (2, 2, 3, 2, 0, 0, 3),
    (3, 4, 6, 4, 0, 0, 3),
    (3, 3, 5, 2, 1, 0, 4),
    (3, 2, 4, 0, 2, 0, 5),
    (4, 6, 9, 6, 0, 0, 3),
    (4, 5, 8, 4, 1, 0, 4),
    (4, 4, 7, 2, 2, 0, 5),
    (4, 4, 7, 3, 0, 1, 5),
    (4, 3, 6, 0, 3, 0, 6),
    (4, 3, 6, 1, 1, 1, 6),
    (4, 2, 5, 0, 0, 2, 7),
]


@pytest.mark.parametrize("loops", [1, 2, 3, 4])
def test_table_3_1_link_assortments(loops):
    expected = {
        (b, l, n3, n4, n5, n2) for v, b, l, n3, n4, n5, n2 in TABLE_3_1 if v == loops
    }
    found = set()
    for a in link_assortments(links=2 * loops + 1, joints=3 * loops):
        c = a.counts
        assert a.links == 2 * loops + 1 and a.joints == 3 * loops
        found.add((a.multi_links, a.branches, c.get(3, 0), c.get(4, 0), c.get(5, 0), c.get(2, 0)))
    assert found == expected


def test_assortments_cover_the_atlas():
    # Every generated chain's assortment is one of the arithmetic solutions.
    from domes.typesynth import chains

    for links, dof in [(8, 1), (10, 1), (9, 2)]:
        atlas = chains(links=links, dof=dof)
        allowed = {tuple(sorted(a.counts.items())) for a in link_assortments(links, atlas[0].joints)}
        assert {tuple(sorted(c.assortment.items())) for c in atlas} <= allowed
