"""Spatial guiding links (issue 15, item 3; seed 002 §2-3, digest A.3.2): S-S, R-S, R-R, R-C, C-C.

Each link is planted: a body is moved so that the planted link guides it
(a sphere centre kept on a sphere or a circle; screws about a fixed and a
moving line), at the most positions the link meets; the synthesis must
find the planted link among its solutions, and every solution must keep the
link's quantities constant when checked from the moved geometry
(independently of the equations solved).
"""

import math

import numpy as np
import pytest

from domes.design.synthesis.counts import PROBLEMS
from domes.design.synthesis.links import MOST, check, guiding_links
from domes.design.synthesis.sphere import rot
from domes.errors import InputError

I = (np.eye(3), np.zeros(3))


def unit(x):
    return x / np.linalg.norm(x)


def screw(u, a, angle, slide):
    C = rot(u, angle)
    return C, a - C @ a + slide * u


def compose(outer, inner):
    (C1, d1), (C2, d2) = outer, inner
    return C1 @ C2, C1 @ d2 + d1


def test_the_most_positions_agree_with_the_counts():
    for kind, (n, free) in MOST.items():
        assert PROBLEMS[kind].most() == (n, free), kind


def test_s_s_seven_positions():
    rng = np.random.default_rng(1)
    a0, a1 = rng.normal(size=3), rng.normal(size=3) + [2, 0, 0]
    r = np.linalg.norm(a1 - a0)
    moves = [I]
    for _ in range(6):
        C = rot(unit(rng.normal(size=3)), rng.uniform(0.2, 1.0))
        moves.append((C, a0 + r * unit(rng.normal(size=3)) - C @ a1))
    found = guiding_links("S-S", moves)
    assert min(np.linalg.norm(s.a0 - a0) + np.linalg.norm(s.a1 - a1) for s in found) < 1e-9
    assert all(check(s, moves) < 1e-9 for s in found)


def test_r_s_four_positions_with_one_coordinate_fixed():
    rng = np.random.default_rng(2)
    a0 = rng.normal(size=3)
    u0 = unit(rng.normal(size=3))
    e1 = unit(np.cross(u0, [1, 0, 0]))
    e2 = np.cross(u0, e1)
    a1 = a0 + 1.7 * e1
    moves = [I]
    for j in range(3):
        C = rot(unit(rng.normal(size=3)), rng.uniform(0.2, 1.0))
        phi = 0.6 * (j + 1)
        moves.append((C, a0 + 1.7 * (math.cos(phi) * e1 + math.sin(phi) * e2) - C @ a1))
    found = guiding_links("R-S", moves, fixed={"a0x": float(a0[0])})
    best = min(found, key=lambda s: np.linalg.norm(s.a0 - a0) + np.linalg.norm(s.a1 - a1))
    assert np.linalg.norm(best.a0 - a0) < 1e-9 and abs(abs(best.u0 @ u0) - 1) < 1e-9
    assert all(check(s, moves) < 1e-9 for s in found)
    with pytest.raises(InputError, match="1 free choice"):
        guiding_links("R-S", moves)


# random starts: the planted R-R link is first reached after more than 12 of them; the R-C and C-C links from the
# second on
@pytest.mark.parametrize("kind, n, slide_fixed, slide_moving, starts", [("R-R", 3, 0, 0, 24), ("R-C", 3, 0, 1, 6),
                                                                       ("C-C", 5, 1, 1, 6)])
def test_line_links_at_their_most_positions(kind, n, slide_fixed, slide_moving, starts):
    rng = np.random.default_rng(3)
    u0, p0 = unit(rng.normal(size=3)), rng.normal(size=3)
    u1, p1 = unit(rng.normal(size=3)), rng.normal(size=3) + [1, 1, 0]
    moves = [I]
    for _ in range(n - 1):
        moves.append(compose(screw(u0, p0, rng.uniform(0.3, 1), slide_fixed * rng.uniform(-1, 1)),
                             screw(u1, p1, rng.uniform(0.3, 1), slide_moving * rng.uniform(-1, 1))))
    fixed = {"u0x": float(u0[0]), "u0y": float(u0[1])} if kind == "R-C" else None
    found = guiding_links(kind, moves, fixed=fixed, starts=starts)
    assert found
    best = max(found, key=lambda s: abs(s.u0 @ u0) + abs(s.u1 @ u1))
    assert abs(abs(best.u0 @ u0) - 1) < 1e-8 and abs(abs(best.u1 @ u1) - 1) < 1e-8
    for a, p, u in ((best.a0, p0, u0), (best.a1, p1, u1)):        # on the planted lines
        w = a - p
        assert np.linalg.norm(w - (w @ u) * u) < 1e-7
    assert all(check(s, moves) < 1e-9 for s in found)


def test_too_many_positions_and_bad_input_are_refused():
    moves = [I] + [(rot((0, 0, 1), 0.1 * k), np.array([k, 0.0, 0.0])) for k in range(1, 4)]
    with pytest.raises(InputError, match="at most 3 positions"):
        guiding_links("R-R", moves)
    with pytest.raises(InputError, match="reference"):
        guiding_links("S-S", moves[1:])
    with pytest.raises(InputError, match="one of"):
        guiding_links("S-P", moves)
    with pytest.raises(InputError, match="not an unknown"):
        guiding_links("R-S", moves, fixed={"b0x": 1.0})
