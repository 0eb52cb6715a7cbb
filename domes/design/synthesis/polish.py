"""Polishing layouts by least squares side by side, every residual they ask for in one batch of the kernel.

:func:`polish` runs ``scipy.optimize.least_squares`` (trust region
reflective, bounds, Jacobian by forward differences) from each of several
starting layouts. A call of the kernel costs about the same for one layout
as for a hundred (its fixed costs dominate), so the runs go side by side:
each is a thread that asks for the residuals of a layout and of its
perturbed copies (the forward differences) and waits; when every unfinished
run waits, one batch of the kernel answers them all. The kernel works layout
by layout (elementwise), so each run's iterates are those it takes alone.

>>> import numpy as np
>>> def residuals(rows):  # each layout's distance to (1, 2) and to the line x = y: least at (103, 203) / 102
...     return np.c_[rows[:, 0] - 1.0, rows[:, 1] - 2.0, 0.1 * (rows[:, 0] - rows[:, 1])]
>>> found = polish(residuals, [np.array([0.0, 0.0]), np.array([3.0, 3.0])], np.zeros(2), np.full(2, 4.0), 1e-7)
>>> [bool(np.allclose(x * 102, [103, 203], atol=1e-6)) for x in found]
[True, True]
"""

from __future__ import annotations

import threading
from typing import Callable

import numpy as np
from scipy.optimize import least_squares

#: Least squares' limits for every polish: evaluations of the residuals, and the step and cost tolerances.
MAX_NFEV = 200
TOLERANCE = 1e-12


class ForwardDifferences:
    """A layout's residuals and their Jacobian by forward differences (step ``h``, kept in the bounds), the
    layout and its perturbed copies evaluated together by ``evaluate`` (rows of layouts -> rows of residuals).

    Least squares asks for the Jacobian at the layout whose residuals it asked for last: each call for residuals
    evaluates the perturbed layouts too, and the Jacobian at that layout reads them.

    >>> d = ForwardDifferences(lambda rows: np.c_[rows[:, 0] + 2 * rows[:, 1], rows[:, 0] * rows[:, 1]],
    ...                        np.zeros(2), np.full(2, 4.0), 1e-6)
    >>> d.residuals(np.array([1.0, 3.0])).tolist()
    [7.0, 3.0]
    >>> np.round(d.jacobian(np.array([1.0, 3.0])), 6).tolist()
    [[1.0, 2.0], [3.0, 1.0]]
    """

    def __init__(self, evaluate: Callable[[np.ndarray], np.ndarray], lo: np.ndarray, hi: np.ndarray, h: float):
        self.evaluate, self.lo, self.hi, self.h = evaluate, lo, hi, h
        self._at: bytes | None = None
        self._batch = None

    def trial(self, p: np.ndarray) -> np.ndarray:
        """The layout ``p`` and its copies each moved by ``h`` along one coordinate, in the bounds."""
        return np.clip(np.vstack([p, p + self.h * np.eye(p.size)]), self.lo, self.hi)

    def _evaluate(self, p: np.ndarray):
        trial = self.trial(p)
        return trial, self.evaluate(trial)

    def residuals(self, p: np.ndarray) -> np.ndarray:
        self._batch = self._evaluate(p)
        self._at = p.tobytes()
        return self._batch[1][0].copy()

    def jacobian(self, p: np.ndarray) -> np.ndarray:
        trial, r = self._batch if self._at == p.tobytes() else self._evaluate(p)
        return ((r[1:] - r[0]) / (trial[1:] - trial[0]).sum(axis=1)[:, None]).T


class _Closed(Exception):
    """The side-by-side polish stopped (an error or an interrupt elsewhere): a waiting run ends."""


class _SideBySide:
    """The runs' requests for residuals, answered in batches by the thread that started them."""

    def __init__(self, residuals: Callable[[np.ndarray], np.ndarray]):
        self.residuals = residuals
        self.cond = threading.Condition()
        self.asked: dict[int, np.ndarray] = {}
        self.answers: dict[int, np.ndarray] = {}
        self.running = 0
        self.closed = False

    def ask(self, run: int, rows: np.ndarray) -> np.ndarray:
        """A run's request: the residuals of ``rows``, when the batch they join is evaluated."""
        with self.cond:
            if self.closed:
                raise _Closed
            self.asked[run] = rows
            self.cond.notify_all()
            self.cond.wait_for(lambda: run in self.answers or self.closed)
            if run not in self.answers:
                self.asked.pop(run, None)
                raise _Closed
            return self.answers.pop(run)

    def done(self) -> None:
        with self.cond:
            self.running -= 1
            self.cond.notify_all()

    def serve(self, tick: Callable[[int], None]) -> None:
        """Answer batches until every run has ended; ``tick`` hears how many are still running."""
        with self.cond:
            while True:
                self.cond.wait_for(lambda: self.closed or len(self.asked) == self.running)
                if self.closed or not self.running:
                    return
                tick(self.running)
                runs = sorted(self.asked)
                batch = [self.asked.pop(k) for k in runs]
                r = self.residuals(np.vstack(batch))
                start = 0
                for k, rows in zip(runs, batch):
                    self.answers[k] = r[start:start + len(rows)]
                    start += len(rows)
                self.cond.notify_all()

    def close(self) -> None:
        with self.cond:
            self.closed = True
            self.cond.notify_all()


def polish(residuals: Callable[[np.ndarray], np.ndarray], starts, lo: np.ndarray, hi: np.ndarray, h: float,
           tick: Callable[[int], None] | None = None) -> list[np.ndarray]:
    """The least-squares minimum reached from each of ``starts`` (layouts in the bounds ``lo``, ``hi``), the
    Jacobian by forward differences of step ``h``; ``residuals`` maps rows of layouts to rows of residuals, one
    layout's the same in any batch. ``tick`` hears, before each batch, how many runs are still going."""
    starts = list(starts)
    if not starts:
        return []
    side = _SideBySide(residuals)
    found: list = [None] * len(starts)
    failed: list[BaseException] = []

    def run(k: int, x0: np.ndarray) -> None:
        differences = ForwardDifferences(lambda rows: side.ask(k, rows), lo, hi, h)
        try:
            found[k] = least_squares(differences.residuals, x0, jac=differences.jacobian, bounds=(lo, hi),
                                     x_scale="jac", max_nfev=MAX_NFEV, xtol=TOLERANCE, ftol=TOLERANCE).x
        except _Closed:
            pass
        except BaseException as exc:  # handed to the caller's thread
            failed.append(exc)
            side.close()
        finally:
            side.done()

    side.running = len(starts)
    threads = [threading.Thread(target=run, args=(k, x0), daemon=True, name=f"polish-{k}")
               for k, x0 in enumerate(starts)]
    try:
        for t in threads:
            t.start()
        side.serve(tick or (lambda running: None))
    finally:
        side.close()
        for t in threads:
            t.join()
    if failed:
        raise failed[0]
    return found
