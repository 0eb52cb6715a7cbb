"""Tolerance sensitivity: how far an output wanders when a mechanism is made to real tolerances.

The redesign step of seed 002 §7-1 evaluates "the effect of link-length
errors on performance": the sensitivity of the output to manufacturing
errors. Here a mechanism's *dimensions* (:func:`dimensions`) are the
numbers a drawing gives a workshop:

* each moving link's lengths: the distance between its first two joints,
  and from each further joint or point to those two (a triangle per point);
* each ground pivot's position (``x``, ``y``);
* each slide line on the frame: its angle and its offset from the origin
  (the height of the slider's pin above the line acts as the offset does,
  so it is counted in it).

A set of dimension values is turned back into a drawn pose by Newton's
method from the nominal pose (the input link kept at its drawn angle, each
assembly mode kept), and the output is evaluated by the compiled kernel at
every input value, all samples at once. Two estimates of the output error:

* :func:`sensitivity` (first order): the derivative of the output with
  respect to every dimension (central differences of the exact model), the
  worst case ``Σ |∂y/∂d| t`` and the standard deviation
  ``√Σ (∂y/∂d · σ)²``, the dimensions ranked by their share, and
  :meth:`Sensitivity.allocate`, tolerances that keep a wanted accuracy;
* :func:`monte_carlo`: random dimensions, ``normal`` (``σ = t/3``) or
  ``uniform`` on ``± t``, in seeded batches (one child of
  ``numpy.random.SeedSequence(seed)`` per batch), run on an executor
  (:mod:`domes.execution`) and merged in batch order: the same numbers
  whatever ran them.

>>> from domes.motion.planar.examples import four_bar
>>> import numpy as np
>>> tol = Tolerancing(four_bar(), "angle:rocker", np.radians([0.0, 90.0]), relative=1e-4)
>>> [d.name for d in tol.dimensions]
['A.x', 'A.y', 'D.x', 'D.y', 'crank:A-B', 'coupler:B-C', 'rocker:C-D']
>>> s = sensitivity(tol)
>>> mc = monte_carlo(tol, samples=20000, seed=1)
>>> bool(abs(mc.std[0, 0] / s.std[0, 0] - 1) < 0.05)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.planar.batch import batch
from domes.results import Progress, Result, Status

DISTRIBUTIONS = ("normal", "uniform")
#: Samples per Monte Carlo batch (one task on an executor); the batches, not the workers, fix the numbers.
BATCH = 20_000
#: The most samples one run takes (about 10 minutes here; 10^6 take 7 s).
MAX_SAMPLES = 100_000_000
#: The most input values one analysis takes.
MAX_INPUTS = 100_000
#: Newton iterations and residual (relative to the mechanism's size) of the re-drawn pose.
ITERATIONS = 30
CLOSURE = 1e-12
#: The largest tolerance taken, as a fraction: of a length (its own), of the size (positions, offsets), of a
#: radian (angles). Beyond it a first-order estimate means nothing and the samples are other mechanisms.
LARGEST = 0.1


@dataclass(frozen=True)
class Dimension:
    """One dimension of a drawing: ``kind`` is ``length``, ``x``, ``y``, ``angle`` (rad) or ``offset``; ``tolerance`` is its ``±`` band (same unit)."""

    name: str
    kind: str
    nominal: float
    tolerance: float = 0.0


class Tolerancing:
    """A mechanism, the output watched and its input values, with the dimensions and their tolerances.

    ``tolerance`` is one ``±`` band for every length and position (lengths
    of the mechanism's unit; angles get ``tolerance / size`` rad), or
    ``relative`` a fraction of each length (positions and offsets: of the
    mechanism's size); ``tolerances`` overrides named dimensions.
    """

    def __init__(self, mech: Mechanism, output: str, inputs, tolerance: float | None = None,
                 relative: float | None = None, tolerances: dict | None = None):
        self.mech = mech
        self.output = output
        self.inputs = np.asarray(inputs, dtype=float)
        if self.inputs.ndim != 1 or not self.inputs.size or not np.all(np.isfinite(self.inputs)):
            raise InputError("tolerance: the input values must be a 1-D array of finite numbers")
        if self.inputs.size > MAX_INPUTS:
            raise InputError(f"tolerance: {self.inputs.size:,} input values; at most {MAX_INPUTS:,} are taken")
        self.joint = mech.inputs[0].joint if mech.inputs else None
        self.size = mech.size
        self._compile()
        if (tolerance is None) == (relative is None):
            raise InputError("tolerance: give either an absolute tolerance or a relative one")
        for name, value in [("tolerance", tolerance), ("relative", relative)]:
            if value is not None and not (math.isfinite(value) and value > 0):
                raise InputError(f"tolerance: {name} must be a positive number, got {value!r}")
        if relative is not None and relative > LARGEST:
            raise InputError(f"tolerance: relative must be at most {LARGEST:g} (a fraction of each length), got "
                             f"{relative:g}: a first-order estimate means nothing there")
        dims = []
        for d in self._dims:
            if relative is not None:
                band = relative * (abs(d.nominal) if d.kind == "length" else (1.0 if d.kind == "angle" else self.size))
            else:
                band = tolerance / self.size if d.kind == "angle" else tolerance
            dims.append(Dimension(d.name, d.kind, d.nominal, band))
        names = {d.name: k for k, d in enumerate(dims)}
        for name, value in (tolerances or {}).items():
            if name not in names:
                raise InputError(f"tolerance: {name!r} is not a dimension of {mech.name}; dimensions are "
                                 f"{', '.join(names)}")
            if not (math.isfinite(value) and value >= 0):
                raise InputError(f"tolerance: the tolerance of {name} must be a number >= 0, got {value!r}")
            dims[names[name]] = Dimension(name, dims[names[name]].kind, dims[names[name]].nominal, float(value))
        _small_enough(dims, self.size)
        self.dimensions = tuple(dims)
        self.nominal = np.array([d.nominal for d in dims])
        self.bands = np.array([d.tolerance for d in dims])
        drawn = self.evaluate(self.nominal[None, :])
        self.columns = list(drawn)
        self.nominal_output = np.stack([drawn[c][0] for c in self.columns])       # (C, N), the nominal mechanism

    # -- the model ------------------------------------------------------------------------------

    def _compile(self) -> None:
        mech = self.mech
        ground = mech.ground
        dims: list[Dimension] = []
        point_at = {j.name: j.at for j in mech.joints if j.kind == "R"}
        point_at.update({p.name: p.at for p in mech.points})
        on_link = {link: [j.name for j in mech.joints_of(link) if j.kind == "R"] +
                   [p.name for p in mech.points if p.link == link] for link in mech.links}
        self._known = {}                                           # ground pivot -> (dim of x, dim of y)
        for j in mech.joints:
            if j.kind == "R" and ground in j.links and j.name not in self._known:
                self._known[j.name] = (len(dims), len(dims) + 1)
                dims += [Dimension(f"{j.name}.x", "x", j.at[0]), Dimension(f"{j.name}.y", "y", j.at[1])]
        for p in mech.points:
            if p.link == ground:
                self._known[p.name] = None                         # fixed with the frame: not a dimension
        self._sliders = {}                                         # P joint -> (slider pin, angle, offset, height dims)
        self._cylinders = {}                                       # P joint between moving links -> its pins
        cylinder_equations = []
        slider_links = {}
        for j in mech.joints:
            if j.kind != "P":
                continue
            if ground not in j.links:
                cylinder_equations += self._cylinder(j, on_link, point_at)
                continue
            slider = j.links[1] if j.links[0] == ground else j.links[0]
            pins = on_link[slider]
            if len(pins) != 1:
                raise InputError(f"tolerance: the slider {slider} of joint {j.name} must carry exactly one pin or "
                                 f"point, it carries {pins or 'none'}")
            n = (-math.sin(j.direction), math.cos(j.direction))
            offset = n[0] * j.at[0] + n[1] * j.at[1]
            pin = point_at[pins[0]]
            height = n[0] * pin[0] + n[1] * pin[1] - offset            # the pin's height above the line: kept
            slot = np.subtract(j.at, pin)                               # the slide point from the pin, on the slider
            self._sliders[j.name] = (pins[0], len(dims), len(dims) + 1, height, slot, j.direction)
            dims += [Dimension(f"{j.name}.angle", "angle", j.direction),
                     Dimension(f"{j.name}.offset", "offset", offset)]
            slider_links[slider] = j.name
        self._unknown = [name for name in point_at if name not in self._known]
        index = {name: k for k, name in enumerate(self._unknown)}
        self._index = index
        equations = []
        for link in mech.links:
            if link == ground or link in slider_links:
                continue
            pts = on_link[link]
            pairs = [(pts[0], pts[1])] if len(pts) >= 2 else []
            pairs += [(pts[a], p) for p in pts[2:] for a in (0, 1)]
            for u, v in pairs:
                length = math.dist(point_at[u], point_at[v])
                if length < 1e-9 * self.size:
                    raise InputError(f"tolerance: {u} and {v} of {link} are at one place; give each joint of a "
                                     "link its own place")
                equations.append(("distance", u, v, len(dims)))
                dims.append(Dimension(f"{link}:{u}-{v}", "length", length))
        for name, (pin, *_rest) in self._sliders.items():
            equations.append(("line", pin, name))
        equations += cylinder_equations
        for inp in mech.inputs:
            j = mech.joint(inp.joint)
            if j.kind != "R" or ground not in j.links:
                raise InputError(f"tolerance: input {inp.joint} must be a revolute joint on the frame")
            link = j.links[1] if j.links[0] == ground else j.links[0]
            other = next((p for p in on_link[link] if p != j.name), None)
            if other is None:
                raise InputError(f"tolerance: the input link {link} carries no second joint or point")
            u = np.subtract(point_at[other], j.at)
            equations.append(("input", j.name, other, u / np.linalg.norm(u)))
        if len(equations) != 2 * len(self._unknown):
            raise InputError(f"tolerance: the dimensions of {mech.name} do not fix its drawn pose "
                             f"({len(equations)} conditions for {2 * len(self._unknown)} coordinates); only "
                             "mechanisms of binary and rigid links, R joints and slides on the frame are taken")
        self._equations = equations
        self._dims = dims
        self._start = np.array([point_at[name] for name in self._unknown], dtype=float)

    def _cylinder(self, j, on_link, point_at) -> list:
        """A slide between two moving links (a cylinder and its rod, an RPR dyad): each link has a pin on the
        slide's line (the pins' heights above it are taken as exact), placed by the other links; a link with
        more pins is rigid and keeps its angle to the line (one equation each). The slide is the distance
        along the line from its origin. Returns the equations it adds."""
        line = complex(math.cos(j.direction), math.sin(j.direction))
        on_line = []
        for link in j.links:
            pins = [p for p in on_link[link] if p in point_at]
            if not pins:
                raise InputError(f"tolerance: link {link} of joint {j.name} carries no pin")
            near = [p for p in pins if abs(((complex(*point_at[p]) - complex(*j.at)) / line).imag) <= 1e-9 * self.size]
            if len(pins) > 1 and not near:
                raise InputError(f"tolerance: no pin of link {link} lies on the line of joint {j.name}; tolerance "
                                 "analysis takes a cylinder pivoted on its axis")
            on_line.append((near or pins)[0])
        pa, pb = on_line
        a, b = complex(*point_at[pa]), complex(*point_at[pb])
        if abs(((b - a) / line).imag) > 1e-9 * self.size or abs(b - a) <= 1e-9 * self.size:
            raise InputError(f"tolerance: joint {j.name} slides between two moving links whose pins {pa} and {pb} "
                             "are not apart on its line (an offset slide); tolerance analysis takes such a slide when "
                             "it is a cylinder whose pins lie on its axis")
        equations = []
        for link, pin in zip(j.links, on_line):  # a link with more pins keeps its angle to the line
            other = next((p for p in on_link[link] if p != pin and p in point_at), None)
            if other is None:
                continue
            c = complex(*point_at[other])
            if pin == pa:   # the rod's pin stays on the cylinder's line
                first, second, third, fourth = pa, pb, pa, other
                u, v = b - a, c - a
            else:           # the rod keeps its angle to the line
                first, second, third, fourth = pb, other, pa, pb
                u, v = c - b, b - a
            turn = np.conj(u * np.conj(v)) / abs(u * np.conj(v))   # Im(u·conj(v)·turn) = 0 in the drawn pose
            equations.append(("angle", first, second, third, fourth, complex(turn), abs(v)))
        angle0 = math.atan2((b - a).imag, (b - a).real)
        self._cylinders[j.name] = (pa, pb, angle0, j.direction, complex(*j.at) - b, complex(*j.slide_origin) - a)
        return equations

    def _point(self, X, values, name):
        """``(M, 2)`` coordinates of a point: unknown (in ``X``), a ground pivot (dimensions), or fixed."""
        if name in self._index:
            return X[:, self._index[name]]
        dim = self._known[name]
        if dim is None:
            p = next(p for p in self.mech.points if p.name == name)
            return np.broadcast_to(np.array(p.at, dtype=float), (len(values), 2))
        return values[:, list(dim)]

    def assemble(self, values: np.ndarray) -> tuple[dict, dict, np.ndarray]:
        """Drawn poses for rows of dimension values: coordinates (name -> ``(M, 2)``), slide directions, and
        which rows assembled (Newton from the nominal pose converged, its Jacobian regular)."""
        values = np.asarray(values, dtype=float)
        m, n = len(values), len(self._unknown)
        X = np.broadcast_to(self._start, (m, n, 2)).copy()
        ok = np.ones(m, dtype=bool)
        for _ in range(ITERATIONS):
            F = np.zeros((m, 2 * n))
            J = np.zeros((m, 2 * n, 2 * n))
            for row, eq in enumerate(self._equations):
                if eq[0] == "distance":
                    _, u, v, d = eq
                    diff = self._point(X, values, u) - self._point(X, values, v)
                    length = np.hypot(diff[:, 0], diff[:, 1])
                    F[:, row] = length - values[:, d]
                    grad = diff / np.where(length > 0, length, 1.0)[:, None]
                    for name, sign in ((u, 1.0), (v, -1.0)):
                        if name in self._index:
                            k = self._index[name]
                            J[:, row, 2 * k:2 * k + 2] += sign * grad
                elif eq[0] == "angle":       # Im((p2 - p1)·conj(p4 - p3)·turn) / scale = 0
                    _, p1, p2, p3, p4, turn, scale = eq
                    u = self._point(X, values, p2) - self._point(X, values, p1)
                    v = self._point(X, values, p4) - self._point(X, values, p3)
                    uc, vc = u[:, 0] + 1j * u[:, 1], v[:, 0] + 1j * v[:, 1]
                    z, y = np.conj(vc) * turn, uc * turn
                    F[:, row] = (uc * z).imag / scale
                    grad_u = np.stack([z.imag, z.real], axis=1) / scale
                    grad_v = np.stack([y.imag, -y.real], axis=1) / scale
                    for name, grad in ((p2, grad_u), (p1, -grad_u), (p4, grad_v), (p3, -grad_v)):
                        if name in self._index:
                            k = self._index[name]
                            J[:, row, 2 * k:2 * k + 2] += grad
                elif eq[0] == "line":
                    _, pin, joint = eq
                    _, angle, offset, height, _slot, _phi = self._sliders[joint]
                    normal = np.stack([-np.sin(values[:, angle]), np.cos(values[:, angle])], axis=1)
                    F[:, row] = np.sum(normal * self._point(X, values, pin), axis=1) - values[:, offset] - height
                    k = self._index[pin]
                    J[:, row, 2 * k:2 * k + 2] += normal
                else:
                    _, pivot, other, unit = eq
                    diff = self._point(X, values, other) - self._point(X, values, pivot)
                    F[:, row] = unit[0] * diff[:, 1] - unit[1] * diff[:, 0]
                    for name, sign in ((other, 1.0), (pivot, -1.0)):
                        if name in self._index:
                            k = self._index[name]
                            J[:, row, 2 * k:2 * k + 2] += sign * np.array([-unit[1], unit[0]])
            if np.all(np.abs(F[ok]) < CLOSURE * self.size):
                break
            with np.errstate(invalid="ignore"):
                regular = np.abs(np.linalg.det(J)) > 1e-14 * max(1.0, self.size) ** (2 * n)
            ok &= regular
            step = np.zeros((m, 2 * n))
            if ok.any():
                step[ok] = np.linalg.solve(J[ok], -F[ok][:, :, None])[:, :, 0]
            X += step.reshape(m, n, 2)
        ok &= np.all(np.abs(F) < 1e-9 * self.size, axis=1) & np.all(np.isfinite(X), axis=(1, 2))
        X[~ok] = self._start                                      # any pose: these rows are reported as failed
        coordinates = {name: X[:, k] for name, k in self._index.items()}
        for name, dim in self._known.items():
            if dim is not None:
                coordinates[name] = values[:, list(dim)]
        directions = {}
        for name, (pa, pb, angle0, phi0, slot, origin) in self._cylinders.items():
            d = coordinates[pb] - coordinates[pa]
            turn = np.exp(1j * (np.arctan2(d[:, 1], d[:, 0]) - angle0))   # the line turns with the pins
            at, start = coordinates[pb] + _xy(turn * slot), coordinates[pa] + _xy(turn * origin)
            coordinates[name], coordinates[f"origin:{name}"] = at, start
            directions[name] = phi0 + np.angle(turn)
        for name, (pin, angle, _offset, _height, slot, phi0) in self._sliders.items():
            phi = values[:, angle]
            turn = np.exp(1j * (phi - phi0)) * complex(*slot)          # the slider turns with its line
            coordinates[name] = coordinates[pin] + np.stack([turn.real, turn.imag], axis=1)
            directions[name] = phi
        return coordinates, directions, ok

    def evaluate(self, values: np.ndarray) -> dict:
        """The output's columns (name -> ``(M, N)``) for rows of dimension values; NaN where a row does not
        assemble (at its drawn input, or at an input value)."""
        coordinates, directions, ok = self.assemble(values)
        result = batch(self.mech, coordinates, self.inputs, outputs=[self.output], joint=self.joint,
                       directions=directions or None)
        return {col: np.where(ok[:, None], v, np.nan) for col, v in result.values.items()}

    def sample(self, rng: np.random.Generator, count: int, distribution: str) -> np.ndarray:
        """``count`` rows of random dimension values: ``normal`` with ``σ = t/3``, or ``uniform`` on ``± t``."""
        if distribution == "normal":
            noise = rng.standard_normal((count, self.nominal.size)) * (self.bands / 3.0)
        elif distribution == "uniform":
            noise = rng.uniform(-1.0, 1.0, (count, self.nominal.size)) * self.bands
        else:
            raise InputError(f"tolerance: unknown distribution {distribution!r}; choose {' or '.join(DISTRIBUTIONS)}")
        return self.nominal + noise

    def sigma(self, distribution: str) -> np.ndarray:
        """Each dimension's standard deviation under ``distribution``."""
        return self.bands / (3.0 if distribution == "normal" else math.sqrt(3.0))

    def shown(self, value: float) -> str:
        """An error of the output as shown to a reader, with its unit: degrees for an angle, else file units."""
        if self.output.startswith("angle:"):
            return f"{math.degrees(value):.3g} deg"
        return f"{value:.3g} file units"


def _small_enough(dims: list[Dimension], size: float) -> None:
    """Refuse bands that are not small beside their dimensions (see :data:`LARGEST`), naming the worst one."""
    def limit(d: Dimension) -> float:
        return LARGEST * (1.0 if d.kind == "angle" else abs(d.nominal) if d.kind == "length" else size)

    worst = max(dims, key=lambda d: d.tolerance / limit(d) if limit(d) > 0 else math.inf, default=None)
    if worst is None or worst.tolerance <= limit(worst):
        return
    if worst.kind == "angle":
        band, most, beside = f"{math.degrees(worst.tolerance):.4g}°", f"{math.degrees(limit(worst)):.4g}°", "a radian"
    else:
        band, most = f"{worst.tolerance:.4g}", f"{limit(worst):.4g}"
        beside = (f"its length {abs(worst.nominal):.4g}" if worst.kind == "length"
                  else f"the mechanism's size {size:.4g}")
    raise InputError(f"tolerance: ±{band} on {worst.name} is not small beside {beside}: a first-order estimate means "
                     f"nothing there and the samples would be other mechanisms; give at most ±{most} "
                     f"({LARGEST:g} of it)")


def _xy(z) -> np.ndarray:
    """``(M, 2)`` coordinates of complex numbers."""
    return np.stack([z.real, z.imag], axis=1)


@dataclass(frozen=True, eq=False)
class Sensitivity(Result):
    """First-order tolerance analysis: ``gradient[c]`` is ``(N, D)``, ``∂ output c / ∂ dimension`` at each input.

    ``worst[c]`` (``N``) is ``Σ |∂y/∂d|·t``; ``std[c]`` (``N``) is ``√Σ (∂y/∂d·σ)²``
    under ``distribution``; ``share`` each dimension's part of the variance
    summed over inputs and columns (sums to 1); ``ranking`` the dimension
    names by it, largest first.
    """

    tolerancing: Tolerancing
    distribution: str
    nominal: np.ndarray
    gradient: np.ndarray
    worst: np.ndarray
    std: np.ndarray
    share: np.ndarray
    status: Status = Status.COMPLETE

    @property
    def ranking(self) -> list[str]:
        return [self.tolerancing.dimensions[k].name for k in np.argsort(-self.share, kind="stable")]

    @property
    def message(self) -> str:
        t = self.tolerancing
        return (f"{t.mech.name}: {t.output} over {t.inputs.size} input values, {len(t.dimensions)} dimensions; "
                f"first order: worst case {t.shown(np.nanmax(self.worst))}, 3σ {t.shown(3 * np.nanmax(self.std))}; "
                f"largest share {self.ranking[0]} ({100 * np.max(self.share):.0f}%)")

    def allocate(self, accuracy: float) -> np.ndarray:
        """Tolerances ``t`` (one per dimension) that keep the output's 3σ (normal) or worst case (uniform) within
        ``accuracy`` at every input, each dimension taking an equal part: ``3σ_d = accuracy / (√D·max|∂y/∂d|)``
        for normal dimensions, ``t_d = accuracy / (D·max|∂y/∂d|)`` for uniform ones (worst case)."""
        if not (math.isfinite(accuracy) and accuracy > 0):
            raise InputError(f"tolerance: the wanted accuracy must be a positive number, got {accuracy!r}")
        slope = np.nanmax(np.abs(self.gradient), axis=(0, 1))
        count = slope.size
        with np.errstate(divide="ignore"):
            if self.distribution == "normal":
                return accuracy / (math.sqrt(count) * slope)
            return accuracy / (count * slope)


def sensitivity(tol: Tolerancing, distribution: str = "normal", step: float = 1e-6) -> Sensitivity:
    """First-order analysis: central differences of the exact model, ``step`` × size (rad for angles).

    >>> from domes.motion.planar.examples import four_bar
    >>> s = sensitivity(Tolerancing(four_bar(), "angle:rocker", [0.0], relative=1e-3))
    >>> s.ranking[0], s.gradient.shape
    ('coupler:B-C', (1, 1, 7))
    """
    if distribution not in DISTRIBUTIONS:
        raise InputError(f"tolerance: unknown distribution {distribution!r}; choose {' or '.join(DISTRIBUTIONS)}")
    d = tol.nominal.size
    h = np.array([step if dim.kind == "angle" else step * tol.size for dim in tol.dimensions])
    rows = np.vstack([tol.nominal, tol.nominal + np.diag(h), tol.nominal - np.diag(h)])
    values = tol.evaluate(rows)
    nominal = np.stack([values[c][0] for c in tol.columns])                     # (C, N)
    if not np.all(np.isfinite(nominal)):
        raise InputError(f"tolerance: {tol.mech.name} does not assemble at every input value asked for")
    steps = np.stack([values[c][1:d + 1] - values[c][d + 1:] for c in tol.columns])  # (C, D, N)
    if tol.output.startswith("angle:"):
        steps = np.angle(np.exp(1j * steps))                                      # across ±π
    gradient = np.swapaxes(steps / (2 * h[:, None]), 1, 2)                         # (C, N, D)
    effect = gradient * tol.bands                                                # (C, N, D)
    worst = np.sum(np.abs(effect), axis=2)
    std = np.sqrt(np.sum((gradient * tol.sigma(distribution)) ** 2, axis=2))
    variance = np.nansum((gradient * tol.sigma(distribution)) ** 2, axis=(0, 1))
    share = variance / variance.sum() if variance.sum() > 0 else variance
    return Sensitivity(tol, distribution, nominal, gradient, worst, std, share)


def _batch_task(task) -> tuple:
    """One seeded Monte Carlo batch: (count assembled, mean, M2, largest |error|) per column and input."""
    tol, nominal, distribution, seed, count = task
    values = tol.evaluate(tol.sample(np.random.default_rng(seed), count, distribution))
    out = []
    for c, col in enumerate(tol.columns):
        error = values[col] - nominal[c]
        if tol.output.startswith("angle:"):
            error = np.angle(np.exp(1j * error))
        good = np.isfinite(error)
        n = good.sum(axis=0)
        with np.errstate(invalid="ignore", divide="ignore"):
            mean = np.where(n > 0, np.nansum(error, axis=0) / n, 0.0)
            m2 = np.nansum((error - mean) ** 2, axis=0)
        largest = np.nanmax(np.where(good, np.abs(error), -np.inf), axis=0)
        out.append((n, mean, m2, largest))
    return out


@dataclass(frozen=True, eq=False)
class MonteCarlo(Result):
    """Monte Carlo tolerance analysis: per column ``c`` and input, ``mean[c]``, ``std[c]`` and ``largest[c]``
    (the largest |error| seen) of the output error over ``samples`` random mechanisms; ``failed`` how many
    did not assemble somewhere (left out of the statistics)."""

    tolerancing: Tolerancing
    distribution: str
    samples: int
    seed: int
    batches: int
    mean: np.ndarray
    std: np.ndarray
    largest: np.ndarray
    failed: int
    status: Status = Status.COMPLETE

    @property
    def message(self) -> str:
        t = self.tolerancing
        head = f"{t.mech.name}: {t.output}, {self.samples:,} samples ({self.distribution}, seed {self.seed}, " \
               f"{self.batches} batches)"
        if not np.isfinite(self.std).any():
            return f"{head}: no sample assembled at every input value"
        return (f"{head}: 3σ {t.shown(3 * np.nanmax(self.std))}, largest error {t.shown(np.nanmax(self.largest))}"
                + (f"; {self.failed:,} samples did not assemble" if self.failed else ""))


def monte_carlo(tol: Tolerancing, samples: int = 100_000, seed: int = 0, distribution: str = "normal",
                batch_size: int = BATCH, executor=None, progress: Progress | None = None) -> MonteCarlo:
    """Monte Carlo over random dimensions, in seeded batches of ``batch_size`` on ``executor`` (default here).

    Batch ``k`` draws from the ``k``-th child of ``SeedSequence(seed)``, and
    the batches are merged in order (Chan's pairwise mean and variance), so
    the result does not depend on the executor or the number of workers.
    """
    if distribution not in DISTRIBUTIONS:
        raise InputError(f"tolerance: unknown distribution {distribution!r}; choose {' or '.join(DISTRIBUTIONS)}")
    if not isinstance(samples, int) or not 2 <= samples <= MAX_SAMPLES:
        raise InputError(f"tolerance: the samples must be a whole number from 2 to {MAX_SAMPLES:,}, got {samples!r}")
    if not isinstance(seed, int) or seed < 0:
        raise InputError(f"tolerance: the seed must be a whole number >= 0, got {seed!r}")
    if not isinstance(batch_size, int) or batch_size < 1:
        raise InputError(f"tolerance: the batch size must be a whole number >= 1, got {batch_size!r}")
    nominal = tol.nominal_output
    sizes = [min(batch_size, samples - k) for k in range(0, samples, batch_size)]
    seeds = np.random.SeedSequence(seed).spawn(len(sizes))
    tasks = [(tol, nominal, distribution, s, n) for s, n in zip(seeds, sizes)]
    if executor is None:
        results = [_batch_task(t) for t in tasks]
    else:
        results = executor.map(_batch_task, tasks, progress=progress)
    shape = nominal.shape
    n, mean, m2 = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    largest = np.full(shape, -np.inf)
    for result in results:                                                       # in batch order
        for c, (nb, mb, m2b, lb) in enumerate(result):
            total = n[c] + nb
            with np.errstate(invalid="ignore", divide="ignore"):
                delta = mb - mean[c]
                mean[c] = np.where(total > 0, mean[c] + delta * nb / np.maximum(total, 1), 0.0)
                m2[c] = m2[c] + m2b + delta ** 2 * n[c] * nb / np.maximum(total, 1)
            n[c] = total
            largest[c] = np.maximum(largest[c], lb)
    with np.errstate(invalid="ignore", divide="ignore"):
        std = np.sqrt(m2 / np.maximum(n - 1, 1))
    failed = int(samples - n.min()) if n.size else 0
    status = Status.COMPLETE if failed < samples else Status.EMPTY
    return MonteCarlo(tol, distribution, samples, seed, len(sizes), mean, std, np.where(n > 0, largest, np.nan),
                      failed, status)


@dataclass(frozen=True)
class Comparison:
    """First order against Monte Carlo at one tolerance scale: ``ratio`` is the Monte Carlo standard deviation
    over the first-order one (RMS over inputs and columns); near 1 the linear estimate is enough."""

    scale: float
    first_order: float
    monte_carlo: float
    failed: int
    ratio: float = field(init=False)

    def __post_init__(self):
        object.__setattr__(self, "ratio", self.monte_carlo / self.first_order if self.first_order else math.nan)


def compare(tol: Tolerancing, scales=(1.0, 10.0, 100.0, 1000.0), samples: int = 20_000, seed: int = 0,
            distribution: str = "normal", executor=None) -> list[Comparison]:
    """First order and Monte Carlo with every tolerance multiplied by each of ``scales``: where they part."""
    out = []
    for scale in scales:
        scaled = _scaled(tol, scale)
        first = sensitivity(scaled, distribution)
        mc = monte_carlo(scaled, samples, seed, distribution, executor=executor)
        rms = lambda a: float(np.sqrt(np.nanmean(np.square(a))))  # noqa: E731
        out.append(Comparison(scale, rms(first.std), rms(mc.std), mc.failed))
    return out


def _scaled(tol: Tolerancing, scale: float) -> Tolerancing:
    copy = object.__new__(Tolerancing)
    copy.__dict__.update(tol.__dict__)
    copy.bands = tol.bands * scale
    copy.dimensions = tuple(Dimension(d.name, d.kind, d.nominal, d.tolerance * scale) for d in tol.dimensions)
    return copy


__all__ = ["BATCH", "DISTRIBUTIONS", "LARGEST", "Comparison", "Dimension", "MonteCarlo", "Sensitivity",
           "Tolerancing", "compare", "monte_carlo", "sensitivity"]
