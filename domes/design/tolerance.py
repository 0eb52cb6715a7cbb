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
method from the nominal pose (the input link kept at its drawn angle), and
the output is evaluated by the compiled kernel at every input value, all
samples at once. Only what the output depends on is solved (a coupler
point or a dyad it does not need cannot make a sample fail), and every
sample is kept in the nominal's assembly mode: a pose Newton's method finds
in the other mode is sought again by continuation from the nominal, and a
sample that still lands there is counted as such. Two estimates of the
output error:

* :func:`sensitivity` (first order): the derivative of the output with
  respect to every dimension (central differences of the exact model), the
  worst case ``Σ |∂y/∂d| t`` and the standard deviation
  ``√Σ (∂y/∂d · σ)²``, the dimensions ranked by their share, and
  :meth:`Sensitivity.allocate`, tolerances that keep a wanted accuracy;
  each input where the estimate is not valid (a dead point, tolerances that
  reach one, an output not linear over the tolerances) is named;
* :func:`monte_carlo`: random dimensions, ``normal`` (``σ = t/3``) or
  ``uniform`` on ``± t``, in seeded batches (one child of
  ``numpy.random.SeedSequence(seed)`` per batch), run on an executor
  (:mod:`domes.execution`) and merged in batch order: the same numbers
  whatever ran them. Failures are counted once per sample, by reason, and
  the standard errors of σ and of the failure fraction say how far to
  trust it.

>>> from domes.motion.planar.examples import four_bar
>>> import numpy as np
>>> tol = Tolerancing(four_bar(), "angle:rocker", np.radians([0.0, 90.0]), relative=1e-4)
>>> [d.name for d in tol.dimensions]
['A.x', 'A.y', 'D.x', 'D.y', 'crank:A-B', 'coupler:B-C', 'rocker:C-D']
>>> s = sensitivity(tol)
>>> mc = monte_carlo(tol, samples=20000, seed=1)
>>> bool(abs(mc.std[0, 0] / s.std[0, 0] - 1) < 0.05), s.notes, mc.failed, mc.trusted
(True, ('', ''), 0, True)
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError
from domes.model.mechanism import Mechanism
from domes.motion.planar.batch import batch
from domes.motion.planar.kernel import Program
from domes.motion.planar.query import SINGULAR_CONDITION, Kinematics
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
#: Continuation steps from the nominal, tried in turn, for the samples Newton's method from the nominal pose does not
#: bring to the nominal's assembly mode.
CONTINUATION = (8, 64)
#: First order is valid at an input where second order changes its σ by at most this (the command's 5%).
LINEAR = 0.05
#: At or below this root of a dyad (the sine of its transmission angle) the linkage is at a dead point: the kernel's
#: singular condition number.
SINGULAR_ROOT = 1.0 / SINGULAR_CONDITION
#: Monte Carlo's σ is trusted where its standard error is at most this fraction of it ...
TRUST_SIGMA = 0.01
#: ... and where at most this fraction of the samples is left out (does not assemble, or only in the other mode).
TRUST_LEFT_OUT = 0.01
#: Why a sample fails, each sample counted once, under the first reason that applies.
UNASSEMBLED, OTHER_MODE, OUT_OF_SPEC = "does not assemble", "other mode", "out of spec"
REASONS = (UNASSEMBLED, OTHER_MODE, OUT_OF_SPEC)
_MADE, _UNASSEMBLED, _OTHER = 0, 1, 2


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
    of the mechanism's unit; angles get ``tolerance / size`` rad; 0 for
    none, as for joint clearances alone: :mod:`domes.design.clearance`), or
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
        self.angular = self.joint is not None and mech.joint(self.joint).kind == "R"
        self.size = mech.size
        self._compile()
        if (tolerance is None) == (relative is None):
            raise InputError("tolerance: give either an absolute tolerance or a relative one")
        if tolerance is not None and not (math.isfinite(tolerance) and tolerance >= 0):   # 0: none (clearances only)
            raise InputError(f"tolerance: tolerance must be a number >= 0, got {tolerance!r}")
        if relative is not None and not (math.isfinite(relative) and relative > 0):
            raise InputError(f"tolerance: relative must be a positive number, got {relative!r}")
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
        triangles = []                                             # (p0, p1, p, dims of p0-p1, p0-p, p1-p, turn)
        for link in mech.links:
            if link == ground or link in slider_links:
                continue
            pts = on_link[link]
            pairs = [(pts[0], pts[1])] if len(pts) >= 2 else []
            pairs += [(pts[a], p) for p in pts[2:] for a in (0, 1)]
            where = {}
            for u, v in pairs:
                length = math.dist(point_at[u], point_at[v])
                if length < 1e-9 * self.size:
                    raise InputError(f"tolerance: {u} and {v} of {link} are at one place; give each joint of a "
                                     "link its own place")
                where[u, v] = len(dims)
                equations.append(("distance", u, v, len(dims)))
                dims.append(Dimension(f"{link}:{u}-{v}", "length", length))
            for p in pts[2:]:
                turn = _cross(np.subtract(point_at[pts[1]], point_at[pts[0]]), np.subtract(point_at[p], point_at[pts[0]]))
                flat = abs(turn) <= 1e-9 * self.size * math.dist(point_at[pts[0]], point_at[pts[1]])
                triangles.append((pts[0], pts[1], p, where[pts[0], pts[1]], where[pts[0], p], where[pts[1], p],
                                  0.0 if flat else math.copysign(1.0, turn)))
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
        self._keep_needed(triangles)
        self._start = np.array([point_at[name] for name in self._unknown], dtype=float).reshape(-1, 2)

    def _keep_needed(self, triangles) -> None:
        """Keep only the unknowns and equations the output depends on.

        The kernel's query for the output names the groups it solves; their
        joints (a slide: its pins), and the point or link watched, are
        wanted. An unknown that is not wanted and takes part in exactly two of
        the remaining equations is placed by them alone (a coupler point by
        its triangle, a dyad's middle joint by its two links): it and they are
        left out, until none is left. The rest is square and regular where the
        whole is, and gives the wanted points the same places.
        """
        mech = self.mech
        self._program = Program(Kinematics(mech, [self.output]))

        def pins(name):
            if name in self._sliders:
                return [self._sliders[name][0]]
            if name in self._cylinders:
                return list(self._cylinders[name][:2])
            return [name]

        wanted = {p for g in self._program.kin.groups for name in g.joints for p in pins(name)}
        kind, _, target = self.output.partition(":")
        if kind == "angle":                                     # its reference line runs through its first two joints
            wanted.update(p for j in mech.joints_of(target)[:2] for p in pins(j.name))
        elif kind == "point":
            wanted.update(pins(target))
        involved = []
        for eq in self._equations:
            names = eq[1:3] if eq[0] in ("distance", "input") else eq[1:5] if eq[0] == "angle" else eq[1:2]
            involved.append({n for n in names if n in self._index})
        alive, rows = set(self._unknown), set(range(len(self._equations)))
        peeled = True
        while peeled:
            peeled = False
            for name in sorted(alive - wanted):
                own = [k for k in rows if name in involved[k]]
                if len(own) == 2:
                    alive.discard(name)
                    rows.difference_update(own)
                    peeled = True
        #: Joints and points the output does not depend on: not solved, so they cannot make a sample fail.
        self.ignored = tuple(n for n in self._unknown if n not in alive)
        self._unknown = [n for n in self._unknown if n in alive]
        self._index = {name: k for k, name in enumerate(self._unknown)}
        self._equations = [eq for k, eq in enumerate(self._equations) if k in rows]
        kept = {eq[3] for eq in self._equations if eq[0] == "distance"}
        self._triangles = [t for t in triangles if {t[3], t[4], t[5]} <= kept]   # all three sides solved
        self._signs = {k: float(v) for k, v in self._program.geometry().sign.items()}
        dead = [g.label for g in self._program.kin.groups if self._signs.get(g.index, 1.0) == 0.0]
        if dead:
            raise InputError(f"tolerance: {mech.name} is drawn on a dead point of {', '.join(dead)}: its assembly "
                             "mode is not defined; draw it at another input value")

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

    def _system(self, X, values):
        """Residuals ``(M, 2n)`` and Jacobians ``(M, 2n, 2n)`` of the kept equations at the poses ``X``."""
        m, n = len(values), len(self._unknown)
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
        return F, J

    def _newton(self, X, values, ok):
        """Newton's method from the poses ``X`` for the rows ``ok``: the poses, and which rows converged with a
        regular Jacobian."""
        n = len(self._unknown)
        if n == 0:
            return X, ok
        for _ in range(ITERATIONS):
            F, J = self._system(X, values)
            if np.all(np.abs(F[ok]) < CLOSURE * self.size):
                break
            with np.errstate(invalid="ignore"):
                regular = np.abs(np.linalg.det(J)) > 1e-14 * max(1.0, self.size) ** (2 * n)
            ok = ok & regular
            step = np.zeros((len(values), 2 * n))
            if ok.any():
                step[ok] = np.linalg.solve(J[ok], -F[ok][:, :, None])[:, :, 0]
            X = X + step.reshape(len(values), n, 2)
        else:
            F, _ = self._system(X, values)
        with np.errstate(invalid="ignore"):
            return X, ok & np.all(np.abs(F) < 1e-9 * self.size, axis=1) & np.all(np.isfinite(X), axis=(1, 2))

    def _coordinates(self, X, values) -> tuple[dict, dict]:
        """The kernel's drawn-pose data of the poses ``X``: coordinates (name -> ``(M, 2)``) and slide directions."""
        coordinates = {name: X[:, k] for name, k in self._index.items()}
        for name, dim in self._known.items():
            if dim is not None:
                coordinates[name] = values[:, list(dim)]
        directions = {}
        for name, (pa, pb, angle0, phi0, slot, origin) in self._cylinders.items():
            if pa not in coordinates or pb not in coordinates:        # not needed by the output: as drawn
                continue
            d = coordinates[pb] - coordinates[pa]
            turn = np.exp(1j * (np.arctan2(d[:, 1], d[:, 0]) - angle0))   # the line turns with the pins
            at, start = coordinates[pb] + _xy(turn * slot), coordinates[pa] + _xy(turn * origin)
            coordinates[name], coordinates[f"origin:{name}"] = at, start
            directions[name] = phi0 + np.angle(turn)
        for name, (pin, angle, _offset, _height, slot, phi0) in self._sliders.items():
            if pin not in coordinates:
                continue
            phi = values[:, angle]
            turn = np.exp(1j * (phi - phi0)) * complex(*slot)          # the slider turns with its line
            coordinates[name] = coordinates[pin] + np.stack([turn.real, turn.imag], axis=1)
            directions[name] = phi
        return coordinates, directions

    def _same_mode(self, coordinates, directions) -> np.ndarray:
        """Which rows are in the nominal's assembly mode: each dyad the output needs (the kernel's sign of its
        drawn pose) and each triangle of a rigid link (not mirrored)."""
        m = len(next(iter(coordinates.values()))) if coordinates else 0
        same = np.ones(m, dtype=bool)
        if self._signs and m:
            signs = self._program.geometry(coordinates, directions or None).sign
            for k, sign in self._signs.items():
                same &= np.broadcast_to(signs[k], (m, 1))[:, 0] == sign
        for p0, p1, p, *_dims, turn in self._triangles:
            if turn:
                a = coordinates[p0]
                same &= np.sign(_cross(coordinates[p1] - a, coordinates[p] - a)) == turn
        return same

    def _closes(self, values) -> np.ndarray:
        """Which rows of dimension values can be made: every triangle of a rigid link the output needs closes."""
        made = np.ones(len(values), dtype=bool)
        for *_points, k01, k0p, k1p, _turn in self._triangles:
            sides = np.sort(values[:, [k01, k0p, k1p]], axis=1)
            made &= sides[:, 2] < sides[:, 0] + sides[:, 1]
        return made

    def _pose(self, values) -> tuple[dict, dict, np.ndarray]:
        """Drawn poses in the nominal's assembly mode: coordinates, slide directions and each row's outcome
        (``_MADE``; ``_UNASSEMBLED``: a rigid link's lengths do not close, or no pose was found; ``_OTHER``: a pose
        was found in the other assembly mode only)."""
        values = np.asarray(values, dtype=float)
        m, n = len(values), len(self._unknown)
        start = np.broadcast_to(self._start, (m, n, 2))
        made = self._closes(values)
        X, ok = self._newton(start.copy(), values, made.copy())
        same = ok & self._same_mode(*self._coordinates(np.where(ok[:, None, None], X, start), values))
        other = ok & ~same
        for steps in CONTINUATION:                             # the rest: from the nominal in small steps
            rows = np.flatnonzero(made & ~same)
            if not rows.size:
                break
            Xc, okc = start[rows].copy(), np.ones(rows.size, dtype=bool)
            for k in range(1, steps + 1):
                Xc, okc = self._newton(Xc, self.nominal + (values[rows] - self.nominal) * (k / steps), okc)
                if not okc.any():
                    break
            found = okc & self._same_mode(*self._coordinates(np.where(okc[:, None, None], Xc, start[rows]),
                                                             values[rows]))
            other[rows[okc & ~found]] = True
            X[rows[found]], same[rows[found]] = Xc[found], True
        outcome = np.where(same, _MADE, np.where(other, _OTHER, _UNASSEMBLED))
        coordinates, directions = self._coordinates(np.where(same[:, None, None], X, start), values)
        return coordinates, directions, outcome

    def assemble(self, values: np.ndarray) -> tuple[dict, dict, np.ndarray]:
        """Drawn poses for rows of dimension values: coordinates (name -> ``(M, 2)``), slide directions, and
        which rows assembled in the nominal's assembly mode (the others are given the nominal pose)."""
        coordinates, directions, outcome = self._pose(values)
        return coordinates, directions, outcome == _MADE

    def _outcome(self, values, roots: bool = False):
        """The output's columns (name -> ``(M, N)``, NaN where a row does not assemble), each row's outcome, and
        with ``roots`` the smallest root of the needed dyads at each input (``(M, N)``; None without dyads)."""
        coordinates, directions, outcome = self._pose(values)
        result = batch(self.mech, coordinates, self.inputs, outputs=[self.output], joint=self.joint,
                       directions=directions or None)
        made = outcome == _MADE
        columns = {col: np.where(made[:, None], v, np.nan) for col, v in result.values.items()}
        smallest = None
        if roots:
            geom = self._program.geometry(coordinates, directions or None)
            pose = self._program.poses(geom, self.inputs[None, :], self.joint)
            if pose.root:
                shape = (len(outcome), self.inputs.size)
                smallest = np.min([np.broadcast_to(r, shape) for r in pose.root.values()], axis=0)
                smallest = np.where(made[:, None] & result.assembled, smallest, np.nan)
        return columns, outcome, smallest

    def evaluate(self, values: np.ndarray) -> dict:
        """The output's columns (name -> ``(M, N)``) for rows of dimension values; NaN where a row does not
        assemble in the nominal's assembly mode (at its drawn input, or at an input value)."""
        return self._outcome(values)[0]

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

    def shown_inputs(self, indices) -> str:
        """Input values by index as shown to a reader (degrees for an R input), at most six then how many more."""
        values = [math.degrees(self.inputs[k]) if self.angular else float(self.inputs[k]) for k in indices]
        text = ", ".join(f"{v:g}" for v in values[:6]) + (f" and {len(values) - 6} more" if len(values) > 6 else "")
        return f"{text} {'deg' if self.angular else 'file units'}"

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


def largest(a, axis) -> np.ndarray:
    """``nanmax`` along ``axis`` without a warning: NaN where no value is finite."""
    a = np.asarray(a, dtype=float)
    top = np.max(np.where(np.isfinite(a), a, -np.inf), axis=axis)
    return np.where(np.isfinite(top), top, np.nan)


def _cross(a, b):
    """The cross product of 2-vectors (the last axis)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _xy(z) -> np.ndarray:
    """``(M, 2)`` coordinates of complex numbers."""
    return np.stack([z.real, z.imag], axis=1)


#: Why first order is not valid at an input, by the word kept in :attr:`Sensitivity.notes`.
NOT_VALID = {
    "singular": "the linkage is at a dead point (singular)",
    "reach": "within the tolerances the linkage reaches a dead point",
    "unmade": "within the tolerances a rigid link cannot be made (its lengths do not close)",
    "nonlinear": "the output is not linear over the tolerances",
}


@dataclass(frozen=True, eq=False)
class Sensitivity(Result):
    """First-order tolerance analysis: ``gradient[c]`` is ``(N, D)``, ``∂ output c / ∂ dimension`` at each input.

    ``worst[c]`` (``N``) is ``Σ |∂y/∂d|·t``; ``std[c]`` (``N``) is ``√Σ (∂y/∂d·σ)²``
    under ``distribution``; ``share`` each dimension's part of the variance
    summed over inputs and columns (sums to 1); ``ranking`` the dimension
    names by it, largest first. Where first order is not valid, ``notes``
    (``N``) says why (:data:`NOT_VALID`; ``""`` where it is): ``singular``
    (a derivative does not exist, or the smallest root of the needed dyads,
    the sine of the transmission angle, is at most :data:`SINGULAR_ROOT`:
    ``condition`` is its inverse), ``reach`` (that root's 3σ, worst case for
    ``uniform``, reaches 0, or the linkage does not assemble at that input
    with a dimension at the edge of its band, or two at ``1/√2`` of theirs),
    ``unmade`` (so changed, a rigid link's lengths do not close: every
    input), ``nonlinear``
    (second order, from the output at those edges, changes σ by more than
    :data:`LINEAR`: ``second`` is that σ).
    """

    tolerancing: Tolerancing
    distribution: str
    nominal: np.ndarray
    gradient: np.ndarray
    worst: np.ndarray
    std: np.ndarray
    share: np.ndarray
    condition: np.ndarray
    second: np.ndarray
    notes: tuple
    status: Status = Status.COMPLETE

    @property
    def ranking(self) -> list[str]:
        return [self.tolerancing.dimensions[k].name for k in np.argsort(-self.share, kind="stable")]

    @property
    def valid(self) -> np.ndarray:
        """``(N,)``: whether first order is valid at each input."""
        return np.array([not note for note in self.notes], dtype=bool)

    @property
    def not_valid(self) -> str:
        """Where first order is not valid and why (``""`` when it is valid everywhere)."""
        t = self.tolerancing
        parts = []
        for key, why in NOT_VALID.items():
            at = [k for k, note in enumerate(self.notes) if note == key]
            if not at:
                continue
            if key == "nonlinear":
                with np.errstate(invalid="ignore", divide="ignore"):
                    change = np.nanmax(np.abs(self.second[:, at] / self.std[:, at] - 1))
                why += f" (second order changes σ by up to {100 * change:.0f}%)"
            parts.append(f"at input {t.shown_inputs(at)}: {why}")
        return ("first order is not valid " + "; ".join(parts)) if parts else ""

    @property
    def message(self) -> str:
        t = self.tolerancing
        if np.isfinite(self.worst).any():
            spread = f"worst case {t.shown(np.nanmax(self.worst))}, 3σ {t.shown(3 * np.nanmax(self.std))}"
        else:
            spread = "no derivative at any input"
        text = (f"{t.mech.name}: {t.output} over {t.inputs.size} input values, {len(t.dimensions)} dimensions; "
                f"first order: {spread}; largest share {self.ranking[0]} ({100 * np.max(self.share):.0f}%)")
        return text + (f"; {self.not_valid}" if self.not_valid else "")

    def allocate(self, accuracy: float) -> np.ndarray:
        """Tolerances ``t`` (one per dimension) that keep the output's 3σ (normal) or worst case (uniform) within
        ``accuracy`` at every input, each dimension taking an equal part: ``3σ_d = accuracy / (√D·max|∂y/∂d|)``
        for normal dimensions, ``t_d = accuracy / (D·max|∂y/∂d|)`` for uniform ones (worst case)."""
        if not (math.isfinite(accuracy) and accuracy > 0):
            raise InputError(f"tolerance: the wanted accuracy must be a positive number, got {accuracy!r}")
        slope = largest(np.abs(self.gradient), axis=(0, 1))
        count = slope.size
        with np.errstate(divide="ignore"):
            if self.distribution == "normal":
                return accuracy / (math.sqrt(count) * slope)
            return accuracy / (count * slope)


def sensitivity(tol: Tolerancing, distribution: str = "normal", step: float = 1e-6) -> Sensitivity:
    """First-order analysis: central differences of the exact model, ``step`` × size (rad for angles); where it is
    not valid (a dead point, tolerances that reach one, an output not linear over them) is in ``notes``.

    >>> from domes.motion.planar.examples import four_bar
    >>> s = sensitivity(Tolerancing(four_bar(), "angle:rocker", [0.0], relative=1e-3))
    >>> s.ranking[0], s.gradient.shape, s.notes
    ('coupler:B-C', (1, 1, 7), ('',))
    """
    if distribution not in DISTRIBUTIONS:
        raise InputError(f"tolerance: unknown distribution {distribution!r}; choose {' or '.join(DISTRIBUTIONS)}")
    d = tol.nominal.size
    h = np.array([step if dim.kind == "angle" else step * tol.size for dim in tol.dimensions])
    t, sigma = tol.bands, tol.sigma(distribution)
    active = np.flatnonzero(t > 0)
    unit = np.eye(d)
    pairs = [(i, j) for a, i in enumerate(active) for j in active[a + 1:]]
    corners = ((1, 1), (1, -1), (-1, 1), (-1, -1))
    reach = t / math.sqrt(2.0)                                   # two dimensions at once: 3σ away together
    rows = np.vstack([tol.nominal, tol.nominal + np.diag(h), tol.nominal - np.diag(h)]
                     + [tol.nominal + s * t[i] * unit[i] for i in active for s in (1, -1)]
                     + [tol.nominal + a * reach[i] * unit[i] + b * reach[j] * unit[j] for i, j in pairs for a, b in corners])
    values, outcome, roots = tol._outcome(rows, roots=True)
    Y = np.stack([values[c] for c in tol.columns])                                # (C, rows, N)
    nominal = Y[:, 0]
    if not np.all(np.isfinite(nominal)):
        raise InputError(f"tolerance: {tol.mech.name} does not assemble at every input value asked for")

    def change(y):                                                                # y − nominal, across ±π for angles
        delta = y - nominal[:, None, :]
        return np.angle(np.exp(1j * delta)) if tol.output.startswith("angle:") else delta

    with np.errstate(invalid="ignore"):
        steps = change(Y[:, 1:d + 1]) - change(Y[:, d + 1:2 * d + 1])                # (C, D, N)
    gradient = np.swapaxes(steps / (2 * h[:, None]), 1, 2)                         # (C, N, D)
    effect = gradient * tol.bands                                                # (C, N, D)
    worst = np.sum(np.abs(effect), axis=2)
    std = np.sqrt(np.sum((gradient * sigma) ** 2, axis=2))
    variance = np.nansum((gradient * sigma) ** 2, axis=(0, 1))
    share = variance / variance.sum() if variance.sum() > 0 else variance
    # Second order over the bands: the Hessian from the output at their edges (alone, and by pairs); for
    # independent symmetric dimensions Var(½ dᵀHd) = Σ_i κ/4·H_ii²σ_i⁴ + Σ_{i<j} H_ij²σ_i²σ_j², κ = Var(d²)/σ⁴.
    k, base = active.size, 2 * d + 1
    kappa = 2.0 if distribution == "normal" else 0.8
    unmade = not np.all(tol._closes(rows[base:]))                            # a rigid link cannot be made
    made = outcome[base:] == _MADE                                           # (else: posed in its mode nowhere)
    reached = ~np.all(np.isfinite(Y[:, base:][:, made]), axis=(0, 1))        # posed, but not at this input
    with np.errstate(invalid="ignore", over="ignore"):
        edges = change(Y[:, base:base + 2 * k])
        diagonal = (edges[:, 0::2] + edges[:, 1::2]) / (t[active] ** 2)[None, :, None]          # (C, k, N)
        var2 = std ** 2 + np.nansum(kappa / 4 * diagonal ** 2 * (sigma[active] ** 4)[None, :, None], axis=1)
        if pairs:
            cross = change(Y[:, base + 2 * k:]).reshape(len(tol.columns), len(pairs), 4, -1)
            ii, jj = np.array(pairs).T
            mixed = ((cross[:, :, 0] - cross[:, :, 1] - cross[:, :, 2] + cross[:, :, 3])
                     / (4 * reach[ii] * reach[jj])[None, :, None])
            var2 = var2 + np.nansum(mixed ** 2 * (sigma[ii] ** 2 * sigma[jj] ** 2)[None, :, None], axis=1)
        second = np.sqrt(var2)
        nonlinear = np.any(second > (1 + LINEAR) * std, axis=0)
    # Dead points: the smallest root of the needed dyads at the nominal, and how far the tolerances move its square
    # (which crosses 0 linearly there).
    n = tol.inputs.size
    if roots is None:
        condition = np.ones(n)
        singular = ~np.all(np.isfinite(gradient), axis=(0, 2))
    else:
        root = roots[0]
        with np.errstate(divide="ignore", invalid="ignore"):
            condition = np.where(root > 0, 1.0 / root, np.inf)
            slope = (roots[1:d + 1] ** 2 - roots[d + 1:2 * d + 1] ** 2) / (2 * h[:, None])   # (D, N)
            spread = (3 * np.sqrt(np.sum((slope * sigma[:, None]) ** 2, axis=0)) if distribution == "normal"
                      else np.sum(np.abs(slope) * t[:, None], axis=0))
        singular = ~np.all(np.isfinite(gradient), axis=(0, 2)) | ~(root > SINGULAR_ROOT)
        reached |= root ** 2 <= np.nan_to_num(spread, nan=np.inf)
    notes = tuple("singular" if singular[i] else "reach" if reached[i] else "unmade" if unmade else
                  "nonlinear" if nonlinear[i] else "" for i in range(n))
    return Sensitivity(tol, distribution, nominal, gradient, worst, std, share, condition, second, notes)


def _batch_task(task) -> dict:
    """One seeded Monte Carlo batch: the samples that assemble everywhere (their count, mean, and second to fourth
    central moments and largest |error| per column and input) and the failures by reason."""
    tol, nominal, distribution, seed, count, spec = task
    values, outcome, _ = tol._outcome(tol.sample(np.random.default_rng(seed), count, distribution))
    error = np.stack([values[c] for c in tol.columns]) - nominal[:, None, :]      # (C, M, N)
    if tol.output.startswith("angle:"):
        error = np.angle(np.exp(1j * error))
    made = (outcome == _MADE) & np.all(np.isfinite(error), axis=(0, 2))
    e = error[:, made]
    n = int(made.sum())
    mean = e.mean(axis=1) if n else np.zeros(nominal.shape)
    dev = e - mean[:, None, :]
    square = dev * dev
    out = {"n": n, "mean": mean, "m2": np.sum(square, axis=1), "m3": np.sum(square * dev, axis=1),
           "m4": np.sum(square * square, axis=1),
           "largest": np.max(np.abs(e), axis=1) if n else np.full(nominal.shape, -np.inf),
           UNASSEMBLED: int(np.sum(~made & (outcome != _OTHER))), OTHER_MODE: int(np.sum(outcome == _OTHER)),
           OUT_OF_SPEC: 0}
    if spec is not None and n:
        off = np.hypot(e[0], e[1]) if tol.output.startswith("point:") else np.max(np.abs(e), axis=0)
        out[OUT_OF_SPEC] = int(np.sum(np.max(off, axis=1) > spec))
    return out


def _merge(a: dict, b: dict) -> dict:
    """Two batches' counts and central moments as one (Chan's and Pébay's pairwise formulas), ``a`` first."""
    na, nb = float(a["n"]), float(b["n"])
    out = {key: a[key] + b[key] for key in REASONS}
    out["n"], out["largest"] = a["n"] + b["n"], np.maximum(a["largest"], b["largest"])
    if not nb or not na:
        for key in ("mean", "m2", "m3", "m4"):
            out[key] = (a if nb == 0 else b)[key]
        return out
    n, d = na + nb, b["mean"] - a["mean"]
    out["mean"] = a["mean"] + d * nb / n
    out["m2"] = a["m2"] + b["m2"] + d ** 2 * na * nb / n
    out["m3"] = (a["m3"] + b["m3"] + d ** 3 * na * nb * (na - nb) / n ** 2
                 + 3 * d * (na * b["m2"] - nb * a["m2"]) / n)
    out["m4"] = (a["m4"] + b["m4"] + d ** 4 * na * nb * (na * na - na * nb + nb * nb) / n ** 3
                 + 6 * d ** 2 * (na * na * b["m2"] + nb * nb * a["m2"]) / n ** 2 + 4 * d * (na * b["m3"] - nb * a["m3"]) / n)
    return out


@dataclass(frozen=True, eq=False)
class MonteCarlo(Result):
    """Monte Carlo tolerance analysis: per column ``c`` and input, ``mean[c]``, ``std[c]`` and ``largest[c]``
    (the largest |error| seen) of the output error over the samples that assemble in the nominal's assembly mode
    at every input, and ``std_error[c]``, the standard error of ``std[c]`` (from the fourth moment).

    ``failures`` counts each failing sample once, under the first reason
    that applies (:data:`REASONS`): it does not assemble (a rigid link's
    lengths do not close, no pose at its drawn input, or none at an input
    value), it assembles only in the other assembly mode, or (with ``spec``)
    its output is off by more than ``spec`` at some input (a point: by that
    distance). ``failed`` is how many were left out of the statistics (the
    first two); ``fraction`` and ``fraction_error`` the share of all
    failures and its standard error. ``trusted`` says whether the σ can
    carry a recommendation; ``trust`` why not.
    """

    tolerancing: Tolerancing
    distribution: str
    samples: int
    seed: int
    batches: int
    mean: np.ndarray
    std: np.ndarray
    largest: np.ndarray
    failed: int
    failures: dict
    std_error: np.ndarray
    spec: float | None = None
    status: Status = Status.COMPLETE

    @property
    def fraction(self) -> float:
        return sum(self.failures.values()) / self.samples

    @property
    def fraction_error(self) -> float:
        return math.sqrt(self.fraction * (1 - self.fraction) / self.samples)

    @property
    def relative_error(self) -> float:
        """The largest standard error of σ as a fraction of σ, over the columns and inputs (0 without spread)."""
        spread = self.std > 0
        return float(np.max(self.std_error[spread] / self.std[spread])) if spread.any() else 0.0

    @property
    def trust(self) -> str:
        """Why σ cannot carry a recommendation (``""`` when it can)."""
        made = self.samples - self.failed
        if made < 2:
            return "no sample assembled at every input value"
        if self.failed > TRUST_LEFT_OUT * self.samples:
            return (f"{100 * self.failed / self.samples:.3g}% of the samples do not assemble in the nominal's mode at "
                    f"every input (more than {100 * TRUST_LEFT_OUT:g}%): σ describes only those that do")
        if not np.all(np.isfinite(self.std_error)) or self.relative_error > TRUST_SIGMA:
            wanted = math.ceil(made * (self.relative_error / TRUST_SIGMA) ** 2) if np.isfinite(self.relative_error) else 0
            return (f"σ is known only to ±{100 * self.relative_error:.2g}% (more than {100 * TRUST_SIGMA:g}%)"
                    + (f": take about {wanted:,} samples" if wanted else ""))
        return ""

    @property
    def trusted(self) -> bool:
        return not self.trust

    @property
    def message(self) -> str:
        t = self.tolerancing
        head = f"{t.mech.name}: {t.output}, {self.samples:,} samples ({self.distribution}, seed {self.seed}, " \
               f"{self.batches} batches)"
        if self.failed >= self.samples:
            return f"{head}: no sample assembled at every input value"
        text = (f"{head}: 3σ {t.shown(3 * np.nanmax(self.std))} (σ to ±{100 * self.relative_error:.2g}%), largest "
                f"error {t.shown(np.nanmax(self.largest))}")
        counts = {UNASSEMBLED: "do not assemble", OTHER_MODE: "assemble only in the other assembly mode",
                  OUT_OF_SPEC: f"are off by more than {t.shown(self.spec) if self.spec is not None else ''}"}
        failing = [f"{self.failures[k]:,} {counts[k]}" for k in REASONS if self.failures.get(k)]
        if failing:
            text += (f"; {', '.join(failing)} ({100 * self.fraction:.3g}% ± {100 * self.fraction_error:.2g}% of the "
                     "samples fail)")
        elif self.spec is not None:
            text += f"; none off by more than {t.shown(self.spec)}"
        return text


def monte_carlo(tol: Tolerancing, samples: int = 100_000, seed: int = 0, distribution: str = "normal",
                batch_size: int = BATCH, executor=None, progress: Progress | None = None,
                spec: float | None = None) -> MonteCarlo:
    """Monte Carlo over random dimensions, in seeded batches of ``batch_size`` on ``executor`` (default here).

    Batch ``k`` draws ``tol.sample(numpy.random.default_rng(child_k), ...)``
    where ``child_k`` is the ``k``-th child of ``SeedSequence(seed)``; the
    batches are merged in order (Chan's and Pébay's pairwise moments), so
    the result does not depend on the executor or the number of workers.
    ``spec`` (output units, rad for an angle) counts the samples off by more.

    >>> from domes.motion.planar.examples import four_bar
    >>> tol = Tolerancing(four_bar(), "angle:rocker", [0.0], relative=1e-3)
    >>> mc = monte_carlo(tol, 20_000, spec=float(3 * sensitivity(tol).std[0, 0]))     # beyond first order's 3σ
    >>> mc.failures, mc.trusted
    ({'does not assemble': 0, 'other mode': 0, 'out of spec': 47}, True)
    """
    if distribution not in DISTRIBUTIONS:
        raise InputError(f"tolerance: unknown distribution {distribution!r}; choose {' or '.join(DISTRIBUTIONS)}")
    if not isinstance(samples, int) or not 2 <= samples <= MAX_SAMPLES:
        raise InputError(f"tolerance: the samples must be a whole number from 2 to {MAX_SAMPLES:,}, got {samples!r}")
    if not isinstance(seed, int) or seed < 0:
        raise InputError(f"tolerance: the seed must be a whole number >= 0, got {seed!r}")
    if not isinstance(batch_size, int) or batch_size < 1:
        raise InputError(f"tolerance: the batch size must be a whole number >= 1, got {batch_size!r}")
    if spec is not None and not (math.isfinite(spec) and spec > 0):
        raise InputError(f"tolerance: the spec (the largest error accepted) must be a positive number, got {spec!r}")
    nominal = tol.nominal_output
    sizes = [min(batch_size, samples - k) for k in range(0, samples, batch_size)]
    seeds = np.random.SeedSequence(seed).spawn(len(sizes))
    tasks = [(tol, nominal, distribution, s, n, spec) for s, n in zip(seeds, sizes)]
    if executor is None:
        results = [_batch_task(t) for t in tasks]
    else:
        results = executor.map(_batch_task, tasks, progress=progress)
    total = None
    for result in results:                                                       # in batch order
        total = result if total is None else _merge(total, result)
    n = total["n"]
    with np.errstate(invalid="ignore", divide="ignore"):
        std = np.sqrt(total["m2"] / max(n - 1, 1)) if n else np.full(nominal.shape, np.nan)
        # Var(s²) ≈ (μ4 − σ⁴(n−3)/(n−1)) / n, and se(s) = se(s²) / 2s (the delta method)
        mu2, mu4 = total["m2"] / max(n, 1), total["m4"] / max(n, 1)
        var_s2 = np.maximum(mu4 - mu2 ** 2 * (n - 3) / max(n - 1, 1), 0.0) / max(n, 1)
        std_error = np.where(std > 0, np.sqrt(var_s2) / (2 * std), 0.0) if n > 1 else np.full(nominal.shape, np.nan)
    failures = {key: total[key] for key in REASONS}
    failed = failures[UNASSEMBLED] + failures[OTHER_MODE]
    status = Status.COMPLETE if n else Status.EMPTY
    return MonteCarlo(tol, distribution, samples, seed, len(sizes), total["mean"] if n else np.full(nominal.shape, np.nan),
                      std, np.where(n > 0, total["largest"], np.nan), failed, failures, std_error, spec, status)


@dataclass(frozen=True)
class Comparison:
    """First order against Monte Carlo at one tolerance scale: ``ratio`` is the Monte Carlo standard deviation
    over the first-order one (RMS over inputs and columns); near 1, with first order ``valid`` at every input
    and Monte Carlo ``trusted``, the linear estimate is enough. ``failed``: samples left out."""

    scale: float
    first_order: float
    monte_carlo: float
    failed: int
    valid: bool
    trusted: bool
    ratio: float = field(init=False)

    def __post_init__(self):
        object.__setattr__(self, "ratio", self.monte_carlo / self.first_order if self.first_order else math.nan)

    @property
    def agree(self) -> bool:
        """Whether first order is enough here: valid everywhere, Monte Carlo trusted, within :data:`LINEAR`."""
        return self.valid and self.trusted and abs(self.ratio - 1) <= LINEAR


def compare(tol: Tolerancing, scales=(1.0, 10.0, 100.0, 1000.0), samples: int = 20_000, seed: int = 0,
            distribution: str = "normal", executor=None) -> list[Comparison]:
    """First order and Monte Carlo with every tolerance multiplied by each of ``scales``: where they part."""
    out = []
    for scale in scales:
        scaled = _scaled(tol, scale)
        first = sensitivity(scaled, distribution)
        mc = monte_carlo(scaled, samples, seed, distribution, executor=executor)
        rms = lambda a: float(np.sqrt(np.mean(np.square(a[np.isfinite(a)])))) if np.isfinite(a).any() else math.nan  # noqa: E731
        out.append(Comparison(scale, rms(first.std), rms(mc.std), mc.failed, bool(first.valid.all()), mc.trusted))
    return out


def _scaled(tol: Tolerancing, scale: float) -> Tolerancing:
    copy = object.__new__(Tolerancing)
    copy.__dict__.update(tol.__dict__)
    copy.bands = tol.bands * scale
    copy.dimensions = tuple(Dimension(d.name, d.kind, d.nominal, d.tolerance * scale) for d in tol.dimensions)
    return copy


__all__ = ["BATCH", "DISTRIBUTIONS", "LARGEST", "LINEAR", "NOT_VALID", "OTHER_MODE", "OUT_OF_SPEC", "REASONS",
           "UNASSEMBLED", "Comparison", "Dimension", "MonteCarlo", "Sensitivity", "Tolerancing", "compare",
           "monte_carlo", "sensitivity"]
