"""Velocities and accelerations agree with finite differences of positions on every example mechanism.

Issue 5 acceptance; this is also seed 000 T3 (the acceleration identity
d²A/dt² = Jφ̈ + J̇φ̇ + Bq̈ + Ḃq̇, which guards against the printed −Jφ̇ of eq. 5).
"""

import math

import pytest
from kinematics_cases import EXAMPLES, example

from domes.motion import Kinematics
from domes.motion.planar.sweep import Continuation

FILES = sorted(p.name for p in EXAMPLES.glob("*.json"))


@pytest.mark.parametrize("method", ["assur", "newton"])
@pytest.mark.parametrize("name", FILES)
def test_derivatives_match_finite_differences(name, method):
    m = example(name)
    kin = Kinematics(m, order=2, method=method, accuracy="exact")  # Newton to rounding: FD of positions
    cont = Continuation(kin)
    inp = m.inputs[0]
    for k, dq in enumerate((0.3, 1.7, 3.9)):
        q = cont.q0 + dq * (1 if cont.angular else m.size / 10)
        state = cont.start(q)
        step = kin.at(cont.inputs(q), state)
        assert step.residual <= 1e-10

        def pos(t, state=state, q=q):
            qt = q + inp.speed * t + 0.5 * inp.acceleration * t * t
            return kin.output_values(kin.positions(cont.inputs(qt), state), {}, {}, 0)

        h1 = 1e-6 / max(1.0, abs(inp.speed))
        h2 = 1e-4 / max(1.0, abs(inp.speed))
        p_plus, p_minus = pos(h1), pos(-h1)
        q_plus, q_0, q_minus = pos(h2), pos(0.0), pos(-h2)
        for col, x in q_0.items():
            d1 = (p_plus[col] - p_minus[col]) / (2 * h1)
            if col.startswith("angle"):
                d1 = math.remainder(p_plus[col] - p_minus[col], 2 * math.pi) / (2 * h1)
            d2 = (q_plus[col] - 2 * x + q_minus[col]) / h2 ** 2
            v, a = step.values[col + "'"], step.values[col + "''"]
            assert v == pytest.approx(d1, rel=1e-6, abs=1e-6 * max(1.0, abs(inp.speed)) * m.size), (col, dq)
            assert a == pytest.approx(d2, rel=1e-4, abs=1e-4 * max(1.0, inp.speed ** 2) * m.size), (col, dq)
