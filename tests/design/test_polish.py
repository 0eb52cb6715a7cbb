"""Polishing side by side (domes.design.synthesis.polish) reaches, from each start, the layout that least squares
reaches from it alone, bit for bit; an error in one run ends them all and reaches the caller."""

import math

import numpy as np
import pytest
from scipy.optimize import least_squares

from domes.design.synthesis.candidate import CurveTask, Model
from domes.design.synthesis.expressions import expression
from domes.design.synthesis.polish import MAX_NFEV, TOLERANCE, polish
from domes.model import LabelledChain


def _model():
    chain = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)],
                                roles={0: {"ground"}, 1: {"crank"}, 3: {"rocker"}})
    task = CurveTask("rocker", "crank", (0.0, 0.0), (1.0, 0.0), math.radians(60), "angle", "rocker",
                     expression("0.5 * x"), box=((-1.0, 4.0), (-2.5, 2.5)), samples=5)
    return Model(chain, task)


def test_side_by_side_runs_reach_what_each_run_reaches_alone():
    model = _model()
    lo, hi = model.bounds()
    h = 1e-7 * model.task.size
    rows = model.random(np.random.default_rng(3), 400)
    ok = model.evaluate(rows)["ok"].all(axis=1)
    starts = list(rows[ok][:3])

    def jac(p):  # the forward differences of one run, its layout evaluated again with its perturbed copies
        trial = np.clip(np.vstack([p, p + h * np.eye(p.size)]), lo, hi)
        r = model.residuals(trial)
        return ((r[1:] - r[0]) / (trial[1:] - trial[0]).sum(axis=1)[:, None]).T

    alone = [least_squares(lambda p: model.residuals(p)[0], x0, jac=jac, bounds=(lo, hi), x_scale="jac",
                           max_nfev=MAX_NFEV, xtol=TOLERANCE, ftol=TOLERANCE).x for x0 in starts]
    together = polish(model.residuals, starts, lo, hi, h)
    assert len(together) == len(starts) == 3
    for a, b in zip(alone, together):
        assert a.tobytes() == b.tobytes()


def test_an_error_in_the_residuals_ends_every_run_and_reaches_the_caller():
    calls = []

    def residuals(rows):
        calls.append(len(rows))
        if len(calls) == 3:
            raise ValueError("no residuals here")
        return np.c_[rows[:, 0] - 1.0, rows[:, 1] - 2.0]

    with pytest.raises(ValueError, match="no residuals here"):
        polish(residuals, [np.zeros(2), np.ones(2), np.full(2, 3.0)], np.zeros(2), np.full(2, 4.0), 1e-7)
    assert calls[0] == 9  # the three runs' first layouts and their perturbed copies, in one batch
