"""Batches: many mechanisms of one topology over a grid of inputs, with a status for each.

:func:`batch` takes a template mechanism and arrays of its joint and point
coordinates (one row per mechanism, each row a drawn pose) and evaluates the
requested outputs of every mechanism at every input value with the kernel
(:mod:`domes.motion.planar.kernel`), a few hundred thousand configurations at
a time. Each mechanism keeps its drawn assembly mode at every input (no
continuation: for branch points and located limits, sweep the mechanism);
its status says whether it assembles at every input (``complete``), meets a
limit inside the grid (``limit``: the values there are NaN), has an
undetermined pose somewhere (``undetermined``) or is drawn on a dead point
(``ambiguous``: its assembly mode is not defined). ``transmission`` is the
smallest root of its dyads over the inputs where it assembles: the sine of
the worst transmission angle for an RRR dyad, 0 at a singular (dead or
change) point.

>>> import numpy as np
>>> from domes.motion.planar.examples import four_bar
>>> cs = np.array([[3.5, 6 ** 0.5], [3.2, 2.0]])        # two positions of joint C
>>> b = batch(four_bar(), {"C": cs}, np.radians(np.arange(0, 360, 90)), outputs=["angle:rocker"])
>>> b.kinds.tolist(), b.values["angle:rocker"].shape
(['complete', 'complete'], (2, 4))
>>> round(float(np.degrees(b.values["angle:rocker"][0, 0])), 6)
78.463041
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import Kinematics
from domes.results import Progress, Result, Status, Ticker

#: Configurations evaluated at once (mechanisms × inputs): large enough for numpy, small enough for the cache.
CHUNK = 1 << 18


@dataclass(frozen=True, eq=False)
class Batch(Result):
    """Outputs of ``M`` mechanisms at ``N`` inputs, with a status per mechanism.

    ``values[column]`` is ``(M, N)`` (NaN where the mechanism does not
    assemble); ``assembled`` the ``(M, N)`` mask; ``kinds`` each mechanism's
    status (``complete``, ``limit``, ``undetermined``, ``ambiguous``);
    ``transmission`` its smallest dyad root (0 = singular, 1 = best);
    ``residual`` its largest loop-closure error relative to its size.
    """

    mechanism: str
    joint: str
    inputs: np.ndarray
    values: dict
    assembled: np.ndarray
    kinds: np.ndarray
    transmission: np.ndarray
    residual: np.ndarray
    status: Status = Status.COMPLETE

    @property
    def count(self) -> int:
        return int(self.kinds.size)

    @property
    def message(self) -> str:
        kinds, counts = np.unique(self.kinds, return_counts=True)
        summary = ", ".join(f"{c:,} {k}" for k, c in zip(kinds, counts))
        worst = float(np.nanmax(self.residual)) if self.residual.size else 0.0
        return (f"{self.status}: {self.count:,} mechanisms ({self.mechanism}) × {self.inputs.size:,} inputs of "
                f"{self.joint}: {summary}; max residual {worst:.2g}")

    def limits(self, m: int) -> list[tuple[float, float]]:
        """The input intervals of the grid in which mechanism ``m`` meets a limit (assembles on one side only)."""
        ok = self.assembled[m]
        change = np.flatnonzero(ok[1:] != ok[:-1])
        return [(float(self.inputs[k]), float(self.inputs[k + 1])) for k in change]


def batch(mech: Mechanism, coordinates=None, inputs=None, outputs=None, order: int = 0, joint: str | None = None,
          directions=None, progress: Progress | None = None) -> Batch:
    """Evaluate ``outputs`` (up to derivative ``order``) of many mechanisms of ``mech``'s topology at ``inputs``.

    ``coordinates`` maps joint and point names to ``(M, 2)`` arrays (the
    drawn pose of each mechanism; names not given keep ``mech``'s
    coordinates), ``directions`` P joints to ``(M,)`` slide angles;
    ``inputs`` are values of ``joint`` (default: the first input; rad or
    length). Other inputs stay at each mechanism's drawn values. The
    mechanism must consist of drivers and dyads.
    """
    kin = Kinematics(mech, outputs, order)
    prog = Program(kin)
    joint = joint or mech.inputs[0].joint
    if joint not in kin.inputs:
        raise InputError(f"{joint!r} is not a driven joint of {mech.name}; inputs are {sorted(kin.inputs)}")
    if inputs is None:
        raise InputError("batch: give the input values (an array of angles in rad, or of slides)")
    qs = np.asarray(inputs, dtype=float)
    if qs.ndim != 1 or not qs.size or not np.all(np.isfinite(qs)):
        raise InputError(f"batch inputs must be a 1-D array of finite numbers, got shape {qs.shape}")
    geom = prog.geometry(coordinates, directions)
    total = geom.count or 1
    n = qs.size
    rows = max(1, CHUNK // n)
    values: dict = {}
    assembled = np.zeros((total, n), dtype=bool)
    kinds = np.empty(total, dtype=object)
    transmission = np.full(total, np.nan)
    residual = np.zeros(total)
    size = _sizes(geom, total)
    clock = Ticker(progress)
    for lo in range(0, total, rows):
        hi = min(lo + rows, total)
        clock.tick(lambda: f"mechanisms {lo:,}/{total:,}")
        g = geom.rows(lo, hi) if geom.count is not None else geom
        pose = prog.poses(g, qs[None, :], joint)
        shape = (hi - lo, n)
        limit = np.zeros(shape, dtype=bool)
        undetermined = np.zeros(shape, dtype=bool)
        for index in pose.unassembled:
            limit |= np.broadcast_to(pose.unassembled[index], shape)
            undetermined |= np.broadcast_to(pose.undetermined[index], shape)
        ok = ~(limit | undetermined)
        ambiguous = np.zeros(hi - lo, dtype=bool)
        for sign in g.sign.values():
            ambiguous |= np.broadcast_to(np.asarray(sign) == 0, (hi - lo, 1))[:, 0]
        ok &= ~ambiguous[:, None]
        assembled[lo:hi] = ok
        kinds[lo:hi] = np.where(ambiguous, "ambiguous", np.where(undetermined.any(axis=1), "undetermined",
                                                                 np.where(ok.all(axis=1), "complete", "limit")))
        if pose.root:
            roots = np.min([np.broadcast_to(r, shape) for r in pose.root.values()], axis=0)
            transmission[lo:hi] = np.min(np.where(ok, roots, np.inf), axis=1)
        if pose.closure:
            closure = np.max([np.broadcast_to(c, shape) for c in pose.closure.values()], axis=0)
            residual[lo:hi] = np.max(np.where(ok, closure, 0.0), axis=1) / size[lo:hi]
        with np.errstate(invalid="ignore", over="ignore"):  # configurations that do not assemble are NaN anyway
            levels = prog.motion(g, pose, order) if order else []
            for col, val in prog.outputs(g, pose, levels).items():
                if col not in values:
                    values[col] = np.empty((total, n))
                values[col][lo:hi] = np.where(ok, val, np.nan)
    transmission[~np.isfinite(transmission)] = np.nan
    return Batch(mech.name, joint, qs, values, assembled, kinds.astype(str), transmission, residual)


def _sizes(geom, total) -> np.ndarray:
    """Each mechanism's size: the largest distance between two of its joints or points."""
    pts = list(geom.at.values())
    best = np.zeros(total)
    for i, p in enumerate(pts):
        for q in pts[i + 1:]:
            best = np.maximum(best, np.broadcast_to(np.abs(p - q), (total, 1))[:, 0])
    return np.where(best > 0, best, 1.0)


__all__ = ["Batch", "batch"]
