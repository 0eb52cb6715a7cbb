"""Functions of x in task files (domes.design.synthesis.expressions): bounded, checked, never a long wait."""

import math

import numpy as np
import pytest

from domes.cli import main
from domes.design.synthesis.expressions import expression
from domes.errors import InputError


def test_a_power_bomb_is_evaluated_in_floats():
    # issue 31, item 6: 'log10(x) + 0*9**9**9' ran indefinitely (Python's integers); in floats 9**9**9 is inf.
    f = expression("log10(x) + 0*9**9**9")
    assert math.isnan(float(f(2.0)))
    assert float(expression("2**-1 + x**2")(3.0)) == 9.5
    np.testing.assert_allclose(expression("log10(x)")(np.array([1.0, 10.0, 100.0])), [0.0, 1.0, 2.0])


@pytest.mark.parametrize("text, message", [
    ("1" * 400, "too large for a float"),
    ("x + " * 400 + "x", "characters long; at most"),
    ("__import__('os')", "unknown name|not allowed|only the functions"),
])
def test_what_is_refused_is_named_shortly(text, message):
    with pytest.raises(InputError, match=message) as caught:
        expression(text)
    assert len(str(caught.value)) < 300


def test_synthesize_says_the_function_is_not_finite(tmp_path, capsys):
    task = tmp_path / "bomb.json"
    task.write_text('{"name": "bomb", "kind": "function", "function": "log10(x) + 0*9**9**9", "range": [1, 10], '
                    '"input_deg": 60, "output_deg": -90, "points": 3}')
    assert main(["synthesize", str(task)]) == 2
    assert "not defined at x = 1" in capsys.readouterr().err
