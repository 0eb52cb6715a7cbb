"""Any labelled candidate dimensioned by least squares against a wanted curve (issue 13, item 5).

A :class:`CurveTask` says what the mechanism must do over a stroke of its
input: the link with role ``input_role`` turns about its ground pivot
``pivot`` by ``rotation``, carrying the point ``point``; the wanted curve
is a function of ``x`` for one quantity:

- ``leverage``: the point's rise over the shortening of the length between
  the two outer pivots of the two links with role ``of`` (joined by a P
  joint: a shock absorber), ``x`` the point's rise (a motorcycle's leverage
  ratio over wheel travel: falling for a rising-rate suspension);
- ``length``: that length, ``x`` the input's rotation in degrees;
- ``angle``: the rotation (degrees) of the link with role ``of``, ``x`` the
  input's rotation in degrees;
- ``ratio``: the force the point delivers along its path per unit force in
  that length (an actuator: the rate of the length over the point's speed,
  by virtual work), ``x`` the input's rotation in degrees (a clamp's force
  amplification near its toggle);
- ``slide``: the displacement of the link with role ``of`` along its slide
  on the ground (a P joint of direction ``guide``), ``x`` the input's
  rotation in degrees (a window on its rails).

``of`` names one role carried by two links (a shock absorber) or two roles
(a cylinder and its piston). The wanted curve is matched (``bound``
``equal``) or is a bound (``at least``, ``at most``), over the whole stroke
or over ``over`` (a range of ``x``); ``overtravel`` extends the stroke the
mechanism must move through beyond the last sample where the curve counts
(a clamp's margin before its toggle).

:func:`dimension` places every joint but the input pivot in the task's
``box``: it screens many random layouts at once with the compiled kernel
(:mod:`domes.motion.planar.kernel`: closed-form dyads on arrays, the
rates analytic), polishes the best by ``scipy.optimize.least_squares``
(bounds, Jacobian by forward differences; the polishes side by side, one
batch of the kernel evaluating every layout they ask for:
:mod:`~domes.design.synthesis.polish`), and verifies each result along the whole stroke by the backend's
continuation sweep, an independent route. What is fitted is the *motion
ratio* ``−dℓ/dy`` times the wanted leverage, minus one: the relative error
of the leverage, smooth where the shock stops moving. Transmission angles,
the length's range and link lengths enter as penalties.

>>> from domes.model import LabelledChain
>>> from domes.design.synthesis.expressions import expression
>>> c = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (3, 0)],
...                         roles={0: {"ground"}, 1: {"crank"}, 3: {"rocker"}})
>>> task = CurveTask("rocker", "crank", (0.0, 0.0), (1.0, 0.0), math.radians(60), "angle", "rocker",
...                  expression("0.5 * x"), box=((-1.0, 4.0), (-2.5, 2.5)))
>>> result = dimension(task, [(1, c)], seeds=8)
>>> result.usable[0].error < 0.02
True
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from domes.design.synthesis.polish import polish as polish_side_by_side
from domes.errors import InputError
from domes.model.mechanism import CouplerPoint, Mechanism, from_labelled
from domes.motion.planar.kernel import Program, iterated
from domes.motion.planar.query import Kinematics
from domes.motion.planar.sweep import sweep
from domes.results import Listing, Progress, Status, Ticker

QUANTITIES = ("leverage", "length", "angle", "ratio", "slide")
BOUNDS = ("equal", "at least", "at most")

#: Weight of a penalty (transmission, length range, short links) against the relative curve error.
PENALTY = 10.0
#: Penalties start this far inside their limits (rad for the transmission angle, a fraction of the length range),
#: so that a polished layout meets the limits themselves.
MARGIN = 0.005


@dataclass(frozen=True)
class CurveTask:
    """A wanted curve over a stroke of the input (see the module's docstring); angles in rad."""

    name: str
    input_role: str
    pivot: tuple[float, float]
    point: tuple[float, float] | None
    rotation: float
    quantity: str
    of: str
    wanted: object
    box: tuple[tuple[float, float], tuple[float, float]]
    samples: int = 25
    point_name: str = "P"
    min_transmission: float = math.radians(30)
    length_range: tuple[float, float] | None = None
    tolerance: float = 0.02
    scene: str | None = None
    candidates: tuple = ()
    bound: str = "equal"
    over: tuple[float, float] | None = None
    overtravel: float = 0.0
    guide: float | None = None
    #: The least value a ratio (a force ratio, a leverage) may take anywhere over the stroke.
    least: float | None = None

    def __post_init__(self):
        if self.quantity not in QUANTITIES:
            raise InputError(f"{self.name}: 'quantity' must be one of {', '.join(QUANTITIES)}, got {self.quantity!r}")
        if isinstance(self.of, (list, tuple)):
            if len(self.of) != 2 or not all(isinstance(r, str) and r for r in self.of):
                raise InputError(f"{self.name}: 'of' names a role, or two roles (e.g. cylinder and piston)")
            object.__setattr__(self, "of", tuple(self.of))
        if self.bound not in BOUNDS:
            raise InputError(f"{self.name}: 'bound' must be one of {', '.join(BOUNDS)}, got {self.bound!r}")
        if self.quantity == "slide" and (self.guide is None or not math.isfinite(self.guide)):
            raise InputError(f"{self.name}: a slide needs the direction of its guide on the ground ('guide_deg')")
        if not (math.isfinite(self.overtravel) and 0 <= self.overtravel < 2 * math.pi - abs(self.rotation)):
            raise InputError(f"{self.name}: 'overtravel' must be an angle >= 0 that keeps the stroke under a turn")
        if self.over is not None:
            lo, hi = self.over
            if not lo < hi:
                raise InputError(f"{self.name}: 'over' must be [from, to] with from < to")
        if self.least is not None and not (self.quantity in ("ratio", "leverage") and math.isfinite(self.least)
                                           and self.least > 0):
            raise InputError(f"{self.name}: 'least' (the least value over the stroke) is a positive number, for a "
                             "ratio or a leverage")
        if not (isinstance(self.samples, int) and 5 <= self.samples <= 1000):
            raise InputError(f"{self.name}: 'samples' must be a whole number from 5 to 1000, got {self.samples!r}")
        (x0, x1), (y0, y1) = self.box
        if not (x0 < x1 and y0 < y1):
            raise InputError(f"{self.name}: 'box' must be [[xmin, xmax], [ymin, ymax]] with min < max")
        if not 0 < abs(self.rotation) < 2 * math.pi:
            raise InputError(f"{self.name}: the input's rotation must be nonzero and under a full turn")
        if self.point is None and self.quantity in ("leverage", "ratio"):
            raise InputError(f"{self.name}: a {self.quantity} is measured at a point: give 'point'")
        if self.point is not None and math.dist(self.pivot, self.point) <= 1e-9 * self.size:
            raise InputError(f"{self.name}: the point coincides with the input's pivot: it does not move")
        if not 0 < self.tolerance < 1:
            raise InputError(f"{self.name}: 'tolerance' (relative curve error) must be between 0 and 1")
        xs = self.xs()[self.active()]
        if not xs.size:
            raise InputError(f"{self.name}: 'over' leaves no sample of the stroke where the wanted curve counts")
        with np.errstate(all="ignore"):
            w = np.broadcast_to(np.asarray(self.wanted(xs), dtype=float), xs.shape)
        if not np.all(np.isfinite(w)):
            bad = float(xs[np.flatnonzero(~np.isfinite(w))[0]])
            raise InputError(f"{self.name}: the wanted curve is undefined at x = {bad:.6g}")
        if self.quantity in ("leverage", "ratio") and np.any(w <= 0):
            raise InputError(f"{self.name}: a {'leverage' if self.quantity == 'leverage' else 'force'} ratio must be "
                             "positive over the stroke")

    @property
    def size(self) -> float:
        (x0, x1), (y0, y1) = self.box
        return max(x1 - x0, y1 - y0)

    def stroke_rotations(self) -> np.ndarray:
        """The input's rotation at each sample of the stroke (rad): ``samples`` evenly spaced, and, when the wanted
        curve counts over a part of it (``over``, in degrees of the input), as many again within that part, so
        that a short stretch is held everywhere, not at one sample."""
        stroke = np.linspace(0.0, self.rotation, self.samples)
        if self.over is None or self.quantity == "leverage":
            return stroke
        lo, hi = (math.radians(v) for v in self.over)
        inside = np.linspace(max(min(lo, hi), min(0.0, self.rotation)), min(max(lo, hi), max(0.0, self.rotation)),
                             self.samples)
        both = np.unique(np.round(np.concatenate([stroke, inside]), 14))
        return both if self.rotation > 0 else both[::-1]

    @property
    def stroke_count(self) -> int:
        """How many samples the stroke has (the overtravel's follow them)."""
        return self.stroke_rotations().size

    def rotations(self) -> np.ndarray:
        """The input's rotation from the start at each sample (rad); the overtravel's samples follow the stroke's."""
        stroke = self.stroke_rotations()
        if self.overtravel <= 0:
            return stroke
        extra = max(2, math.ceil(self.samples * self.overtravel / abs(self.rotation)))
        return np.concatenate([stroke, self.rotation + math.copysign(1.0, self.rotation)
                               * np.linspace(0.0, self.overtravel, extra + 1)[1:]])

    def active(self) -> np.ndarray:
        """Where the wanted curve counts: the stroke's samples (not the overtravel's) within ``over``."""
        x = self.xs()
        mask = np.arange(x.size) < self.stroke_count
        if self.over is not None:
            mask &= (x >= self.over[0] - 1e-9 * max(1.0, abs(self.over[0]))) & \
                    (x <= self.over[1] + 1e-9 * max(1.0, abs(self.over[1])))
        return mask

    def xs(self) -> np.ndarray:
        """``x`` at each sample: the point's rise (leverage) or the rotation in degrees."""
        t = self.rotations()
        if self.quantity != "leverage":
            return np.degrees(t)
        d = complex(*self.point) - complex(*self.pivot)
        return (d * np.exp(1j * t)).imag - d.imag


@dataclass(frozen=True)
class Dimensioned:
    """A candidate with dimensions: its mechanism, the curve it gives, the error and the checks."""

    candidate: int
    mechanism: Mechanism
    x: tuple[float, ...]
    achieved: tuple[float, ...]
    wanted: tuple[float, ...]
    error: float
    rms: float
    min_transmission_deg: float
    length: tuple[float, float] | None
    defects: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()

    @property
    def usable(self) -> bool:
        return not self.defects


class SolutionSet(Listing):
    """A result listing solutions that each say whether they are ``usable``: COMPLETE when one is."""

    @property
    def usable(self) -> tuple:
        return tuple(s for s in getattr(self, self.items_field) if s.usable)

    @property
    def status(self) -> Status:
        return Status.COMPLETE if self.usable else Status.EMPTY


@dataclass(frozen=True, eq=False)
class Dimensioning(SolutionSet):
    """The best layouts of every candidate; ``screened`` random layouts were tried, ``polished`` polished."""

    task_name: str
    solutions: tuple[Dimensioned, ...]
    candidates: tuple[int, ...]
    screened: int
    polished: int
    seconds: float
    notes: tuple[str, ...] = field(default_factory=tuple)
    kind: str = "curve"
    items_field = "solutions"

    @property
    def roots(self) -> int:
        return len(self.solutions)

    @property
    def message(self) -> str:
        done = sorted({s.candidate for s in self.usable})
        return (f"{self.status}: {self.task_name}: {len(self.candidates)} candidate(s), {len(self.usable)} verified "
                f"layout(s) for candidate(s) {', '.join(map(str, done)) or 'none'}; {self.seconds:.1f} s")

    def _repr_html_(self) -> str | None:
        """Every layout drawn to scale beside its curve, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


class Model:
    """A candidate made a function of its free joint coordinates, evaluated many layouts at a time."""

    def __init__(self, chain, task: CurveTask, name: str = "candidate"):
        self.task = task
        ground = _one(chain, "ground")
        driven = _one(chain, task.input_role)
        if (min(ground, driven), max(ground, driven)) not in chain.edges:
            raise InputError(f"link {driven} ({task.input_role}) is not jointed to the ground {ground}: the task "
                             "turns it about a ground pivot")
        names = {e: f"J{e[0]}-{e[1]}" for e in chain.edges}
        kinds = dict(zip(chain.edges, chain.joint_types))
        self.fixed = names[(min(ground, driven), max(ground, driven))]
        self.slider = None
        self.guided = None  # the P joint of a slide on the ground
        inv = {v: k for k, v in names.items()}
        if task.quantity in ("leverage", "length", "ratio"):
            pair = (chain.links_with_role(task.of) if isinstance(task.of, str)
                    else [_one(chain, task.of[0]), _one(chain, task.of[1])])
            what = task.of if isinstance(task.of, str) else " and ".join(task.of)
            if len(pair) != 2 or kinds.get((min(pair), max(pair))) != "P":
                raise InputError(f"role {what!r}: a length needs two links joined by a P joint (a cylinder and "
                                 f"its piston), found links {pair}")
            ends = []
            for k in pair:  # the axis runs through each link's pivot: its only R joint, else the one on the ground
                others = [e for e in chain.edges if k in e and e != (min(pair), max(pair)) and kinds[e] == "R"]
                grounded = [e for e in others if ground in e]
                if not others or (len(others) > 1 and len(grounded) != 1):
                    raise InputError(f"role {what!r}: link {k} must carry one R joint besides the P joint, or one "
                                     "on the ground (its pivot)")
                ends.append(names[others[0] if len(others) == 1 else grounded[0]])
            self.slider = names[(min(pair), max(pair))]
            self.ends = tuple(ends)
        elif task.quantity == "slide":
            moving = _one(chain, task.of)
            edge = (min(ground, moving), max(ground, moving))
            if kinds.get(edge) != "P":
                raise InputError(f"role {task.of!r}: a slide needs the link to slide on the ground (a P joint "
                                 f"between links {ground} and {moving})")
            others = [e for e in chain.edges if moving in e and e != edge]
            if len(others) != 1 or kinds[others[0]] != "R":
                raise InputError(f"role {task.of!r}: link {moving} must carry one R joint besides its slide")
            self.slider = self.guided = names[edge]
            self.ends = (names[others[0]],)
        else:
            self.of_link = str(_one(chain, task.of))
        if any(t == "P" and names[e] != self.slider for e, t in kinds.items()):
            raise InputError("least-squares dimensioning places R joints; a P joint is only taken as the slide "
                             f"of role {task.of!r}")
        self.free = [names[e] for e in chain.edges if kinds[e] == "R" and names[e] != self.fixed]
        self.links = {str(k): [names[e] for e in chain.edges if k in e and names[e] != self.slider]
                      for k in range(chain.n)}
        rng = np.random.default_rng(0)
        at = {e: tuple(task.pivot) if names[e] == self.fixed else tuple(self._random(rng, 1)[0]) for e in chain.edges}
        directions, guides = {}, {}
        if self.guided:
            at[inv[self.slider]] = at[inv[self.ends[0]]]
            directions[inv[self.slider]] = task.guide
            guides[inv[self.slider]] = ground
        elif self.slider:
            at[inv[self.slider]] = at[inv[self.ends[1]]]
            p, q = at[inv[self.ends[0]]], at[inv[self.ends[1]]]
            directions[inv[self.slider]] = math.atan2(q[1] - p[1], q[0] - p[0])
        points = [] if task.point is None else [CouplerPoint(task.point_name, str(driven), tuple(task.point))]
        self.template = from_labelled(chain, at, directions, inputs=[(ground, driven)], guides=guides, name=name,
                                      points=points)
        outputs = ([f"point:{task.point_name}"] if points else []) + [f"angle:{k}" for k in self.template.links
                                                                      if k != self.template.ground]
        if self.slider and not self.guided:
            outputs += [f"point:{e}" for e in self.ends]
        if self.guided:
            outputs.append(f"slide:{self.slider}")
        kin = Kinematics(self.template, outputs, order=1)
        newton = iterated(kin)
        if newton:  # their equations come from the drawing: a batch of other layouts has none to evaluate
            raise InputError(f"{name}: the groups {newton} are solved by Newton's method on the drawing's own loop "
                             "equations; layouts are dimensioned in batches of closed-form groups (dyads) only")
        self.program = Program(kin)
        self.ts = task.rotations()
        self.xs = task.xs()
        self.active = task.active()
        with np.errstate(all="ignore"):
            self.wanted = np.broadcast_to(np.asarray(task.wanted(self.xs), dtype=float), self.xs.shape).copy()
        self.wanted[~self.active] = np.nan

    def _random(self, rng, count):
        (x0, x1), (y0, y1) = self.task.box
        return np.c_[rng.uniform(x0, x1, count), rng.uniform(y0, y1, count)]

    def random(self, rng, count: int) -> np.ndarray:
        """``count`` random layouts (rows of free coordinates) in the box."""
        return np.hstack([self._random(rng, count) for _ in self.free])

    def bounds(self):
        (x0, x1), (y0, y1) = self.task.box
        return np.tile([x0, y0], len(self.free)), np.tile([x1, y1], len(self.free))

    def coordinates(self, rows: np.ndarray) -> dict:
        return {name: rows[:, 2 * i:2 * i + 2] for i, name in enumerate(self.free)}

    def evaluate(self, rows: np.ndarray) -> dict:
        """The curve, the transmission and the length of the layouts ``rows`` (``(M, 2k)``) at every sample."""
        rows = np.atleast_2d(np.asarray(rows, dtype=float))
        coords = self.coordinates(rows)
        directions = None
        if self.guided:
            coords[self.slider] = coords[self.ends[0]]
            directions = {self.slider: np.full(rows.shape[0], self.task.guide)}
        elif self.slider:
            p, q = coords[self.ends[0]], coords[self.ends[1]]
            coords[self.slider] = q
            directions = {self.slider: np.arctan2(q[:, 1] - p[:, 1], q[:, 0] - p[:, 0])}
        prog = self.program
        geom = prog.geometry(coords, directions)
        q0 = np.broadcast_to(geom.drawn[self.fixed], (rows.shape[0], 1))
        task = self.task
        with np.errstate(all="ignore"):
            pose = prog.poses(geom, q0 + self.ts[None, :], self.fixed)
            shape = (rows.shape[0], self.ts.size)
            ok = np.ones(shape, dtype=bool)
            for index in pose.unassembled:
                ok &= ~np.broadcast_to(pose.unassembled[index] | pose.undetermined[index], shape)
            for sign in geom.sign.values():
                ok &= ~np.broadcast_to(np.asarray(sign) == 0, (rows.shape[0], 1))
            root = (np.min([np.broadcast_to(r, shape) for r in pose.root.values()], axis=0) if pose.root
                    else np.ones(shape))
            # the links' angles are read only for an angle task: elsewhere they need not be made continuous
            out = prog.outputs(geom, pose, prog.motion(geom, pose, 1), unwrap=task.quantity == "angle")
            length = None
            if self.slider and not self.guided:
                a, b = self.ends
                d = (out[f"point:{a}.x"] - out[f"point:{b}.x"]) + 1j * (out[f"point:{a}.y"] - out[f"point:{b}.y"])
                v = (out[f"point:{a}.x'"] - out[f"point:{b}.x'"]) + 1j * (out[f"point:{a}.y'"] - out[f"point:{b}.y'"])
                length = np.abs(d)
                rate = (d.real * v.real + d.imag * v.imag) / length
            if task.quantity == "leverage":
                rise = out[f"point:{task.point_name}.y'"]
                ratio = -rate / rise                           # the motion ratio: shortening per rise
                value = 1.0 / ratio
                fit = self._bounded(ratio * self.wanted - 1.0)
            elif task.quantity == "length":
                value = length
                fit = self._bounded((length - self.wanted) / max(np.nanmax(self.wanted) - np.nanmin(self.wanted),
                                                                 1e-3 * task.size))
            elif task.quantity == "ratio":
                speed = np.hypot(out[f"point:{task.point_name}.x'"], out[f"point:{task.point_name}.y'"])
                value = np.abs(rate) / speed                   # virtual work: force at the point per unit force
                fit = self._bounded(value / self.wanted - 1.0)
            elif task.quantity == "slide":
                s = out[f"slide:{self.slider}"]
                value = s - s[:, :1]
                fit = self._bounded((value - self.wanted) / max(np.nanmax(self.wanted) - np.nanmin(self.wanted),
                                                                1e-3 * task.size))
            else:
                a = out[f"angle:{self.of_link}"]
                value = np.degrees(a - a[:, :1])
                fit = self._bounded((value - self.wanted) / max(np.nanmax(self.wanted) - np.nanmin(self.wanted), 1.0))
        return {"ok": ok, "root": np.where(ok, root, 0.0), "value": value, "fit": fit, "length": length}

    def _bounded(self, error: np.ndarray) -> np.ndarray:
        """The error where the wanted curve counts (0 elsewhere); for a bound, only on the wrong side of it."""
        if self.task.bound == "at least":
            error = np.minimum(error, 0.0) if self.task.quantity != "leverage" else np.maximum(error, 0.0)
        elif self.task.bound == "at most":
            error = np.maximum(error, 0.0) if self.task.quantity != "leverage" else np.minimum(error, 0.0)
        return np.where(self.active, error, 0.0)

    def residuals(self, rows: np.ndarray, e: dict | None = None) -> np.ndarray:
        """Least-squares residuals of each layout: the curve error and the penalties, ``(M, r)`` (``e``: the
        layouts' :meth:`evaluate`, when the caller has it)."""
        rows = np.atleast_2d(rows)
        e = self.evaluate(rows) if e is None else e
        fit = np.where(e["ok"], e["fit"], 1.0)
        fit = np.where(np.isfinite(fit), fit, 1.0)
        parts = [fit, PENALTY * np.maximum(0.0, math.sin(self.task.min_transmission + MARGIN) - e["root"])]
        if e["length"] is not None and self.task.length_range:
            lo, hi = self.task.length_range
            lo, hi = lo + MARGIN * (hi - lo), hi - MARGIN * (hi - lo)
            ln = np.where(e["ok"], e["length"], lo)
            parts += [PENALTY * np.maximum(0.0, lo - ln) / lo, PENALTY * np.maximum(0.0, ln - hi) / hi]
        if self.task.least is not None:
            stroke = np.arange(self.ts.size) < self.task.stroke_count
            low = np.where(e["ok"] & stroke, np.maximum(0.0, 1.0 - e["value"] / self.task.least), 0.0)
            parts.append(PENALTY * np.where(np.isfinite(low), low, 1.0))
        parts.append(PENALTY * self._short(rows))
        return np.hstack(parts)

    def _short(self, rows) -> np.ndarray:
        """Links shorter than 2% of the box, as penalties (joints of one link must stay apart)."""
        coords = self.coordinates(rows)
        coords[self.fixed] = np.broadcast_to(self.task.pivot, (rows.shape[0], 2))
        gap = 0.02 * self.task.size
        cols = []
        for joints in self.links.values():
            for i, a in enumerate(joints):
                for b in joints[:i]:
                    cols.append(np.maximum(0.0, gap - np.linalg.norm(coords[a] - coords[b], axis=1)) / gap)
        return np.array(cols).T if cols else np.zeros((rows.shape[0], 0))

    def mechanism(self, row: np.ndarray, name: str) -> Mechanism:
        """The layout ``row`` as a mechanism file (drawn at the start of the stroke)."""
        coords = {k: tuple(map(float, v[0])) for k, v in self.coordinates(np.atleast_2d(row)).items()}
        data = self.template.to_dict()
        data["name"] = name
        for j in data["joints"]:
            if j["name"] in coords:
                j["at"] = list(coords[j["name"]])
            if j["name"] == self.slider and self.guided:
                q = coords[self.ends[0]]
                j["at"], j["origin"] = list(q), list(q)
                j["direction"] = math.degrees(self.task.guide)
            elif j["name"] == self.slider:  # the slide runs from the first pivot: it is the eye-to-eye length
                p, q = coords[self.ends[0]], coords[self.ends[1]]
                j["at"], j["origin"] = list(q), list(p)
                j["direction"] = math.degrees(math.atan2(q[1] - p[1], q[0] - p[0]))
        return Mechanism.from_dict(data)


def _one(chain, role: str) -> int:
    links = chain.links_with_role(role)
    if len(links) != 1:
        raise InputError(f"the candidate needs one link with role {role!r}, found {len(links)}")
    return links[0]


def dimension(task: CurveTask, candidates, method: str = "exact", seeds: int = 64, seed: int = 0,
              progress: Progress | None = None, executor=None) -> Dimensioning:
    """Dimension every ``(id, labelled chain)`` of ``candidates`` for ``task``; the verified layouts of each.

    ``200 × seeds`` random layouts per candidate are screened by the kernel;
    the best 12 (``method="exact"``) or 4 (``"fast"``) are polished by least
    squares and verified by a continuation sweep. Each candidate draws from
    its own child of ``SeedSequence(seed)``, so ``executor``
    (:mod:`domes.execution`) may dimension them side by side with the same
    result.
    """
    if method not in ("exact", "fast"):
        raise InputError(f"method must be 'exact' or 'fast', got {method!r}")
    started = time.perf_counter()
    polish = 12 if method == "exact" else 4
    candidates = list(candidates)
    children = np.random.SeedSequence(seed).spawn(len(candidates))
    tasks = [(task, cid, chain, child, 200 * seeds, polish) for (cid, chain), child in zip(candidates, children)]
    if executor is None:
        clock = Ticker(progress)
        results = []
        for k, item in enumerate(tasks, 1):
            clock.tick(lambda: f"candidate {item[1]} ({k}/{len(tasks)}): screening {200 * seeds:,} layouts, "
                               f"polishing {polish}", force=True)
            results.append(_dimension_one(item, clock, f"candidate {item[1]} ({k}/{len(tasks)})"))
    else:
        results = executor.map(_dimension_one, tasks, progress=progress)
    out: list[Dimensioned] = []
    notes = [note for _, note in results if note]
    for kept, _ in results:
        out += kept
    ids = [cid for cid, _ in candidates]
    refused = [n for n in notes if "cannot carry" in n]
    if ids and len(refused) == len(ids):
        raise InputError(f"{task.name}: no candidate can carry the task: " + "; ".join(refused))
    return Dimensioning(task.name, tuple(out), tuple(ids), 200 * seeds, polish, time.perf_counter() - started,
                        tuple(notes))


def _dimension_one(item, clock: Ticker | None = None, where: str = "") -> tuple[list, str]:
    """One candidate: its best three verified layouts (one per distinct curve error) and a note, or none;
    ``clock`` hears of each layout polished and verified."""
    clock = clock or Ticker(None)
    task, cid, chain, child, screened, polish = item
    try:
        model = Model(chain, task, f"{task.name}: candidate {cid}")
    except InputError as exc:
        return [], f"candidate {cid}: cannot carry the task: {exc}"
    found = _fit(model, np.random.default_rng(child), screened, polish, clock, where)
    mine = []
    for k, row in enumerate(found, 1):
        clock.tick(lambda: f"{where}: verifying layout {k} of {len(found)} along the stroke")
        mine.append(_verify(model, cid, row, f"{task.name}: candidate {cid}"))
    mine.sort(key=lambda s: (not s.usable, s.error))
    kept: list[Dimensioned] = []
    for s in mine:                                  # one layout per distinct curve error
        if not any(abs(s.error - k.error) <= 1e-6 * max(k.error, 1e-9) for k in kept):
            kept.append(s)
    note = ""
    if not any(s.usable for s in kept):
        note = (f"candidate {cid}: no verified layout in the box"
                + (f" (best error {100 * kept[0].error:.2g}%)" if kept else ""))
    return kept[:3], note


def _fit(model: Model, rng, screened: int, polish: int, clock: Ticker | None = None,
         where: str = "") -> list[np.ndarray]:
    """Screen ``screened`` random layouts, polish the best ``polish`` by least squares."""
    clock = clock or Ticker(None)
    rows = model.random(rng, screened)
    e = model.evaluate(rows)
    cost = np.sum(model.residuals(rows, e) ** 2, axis=1)
    ok = e["ok"].all(axis=1)
    order = np.flatnonzero(ok)[np.argsort(cost[ok])][:polish]
    lo, hi = model.bounds()

    def tick(running: int) -> None:
        clock.tick(lambda: f"{where}: polishing {len(order)} layouts side by side, {running} still going")

    return polish_side_by_side(model.residuals, [rows[k] for k in order], lo, hi, 1e-7 * model.task.size, tick)


def _verify(model: Model, cid: int, row: np.ndarray, name: str) -> Dimensioned:
    """Check a layout along the whole stroke by the continuation sweep (not the kernel that fitted it)."""
    task = model.task
    mech = model.mechanism(row, name)
    e = model.evaluate(row)
    defects = []
    outputs = [f"point:{task.point_name}"] if task.point is not None else []
    outputs += ([f"point:{x}" for x in model.ends] if model.slider else [f"angle:{model.of_link}"])
    q0 = Kinematics(mech).drawn_inputs()[model.fixed]
    travel = float(model.ts[-1])                          # the stroke and its overtravel
    sw = sweep(mech, q0, q0 + travel, abs(travel) / (4 * model.ts.size), outputs=outputs)
    if sw.status != Status.COMPLETE or sw.dead_points:
        where = f" at {math.degrees(sw.dead_points[0].input - q0):.2f}° of the stroke" if sw.dead_points else ""
        defects.append("dead point: the mechanism does not move through the whole stroke"
                       + (" and its overtravel" if task.overtravel else "") + where)
    ok = bool(e["ok"].all())
    if not ok:
        defects.append("does not assemble over the whole stroke" + (" and its overtravel" if task.overtravel else ""))
    value = e["value"][0]
    rel = relative_error(task, value, model.wanted)
    error = float(np.max(rel[model.active])) if ok else math.inf
    rms = float(np.sqrt(np.mean(rel[model.active] ** 2))) if ok else math.inf
    if not error <= task.tolerance:
        what = "curve error" if task.bound == "equal" else f"shortfall from the bound ({task.bound})"
        defects.append(f"{what} {100 * error:.3g}% above the tolerance {100 * task.tolerance:.3g}%")
    if task.least is not None and ok:
        smallest = float(np.min(value[:task.stroke_count]))
        if not smallest >= task.least * (1 - 1e-9):
            defects.append(f"{task.quantity} falls to {smallest:.3g} over the stroke, below the least {task.least:g}")
    mu = math.degrees(math.asin(min(1.0, float(np.min(e["root"]))))) if ok else 0.0
    if mu < math.degrees(task.min_transmission) - 1e-6:
        defects.append(f"transmission angle {mu:.1f}° below {math.degrees(task.min_transmission):.0f}°")
    length = None
    if e["length"] is not None and ok:
        length = (float(np.min(e["length"])), float(np.max(e["length"])))
        if task.length_range and not (task.length_range[0] - 1e-9 <= length[0] and length[1] <= task.length_range[1] + 1e-9):
            defects.append(f"length {length[0]:.4g} to {length[1]:.4g} outside {task.length_range[0]:.4g} to "
                           f"{task.length_range[1]:.4g}")
    notes = (f"sweep: {sw.inputs.size} steps, largest closure residual {float(np.max(sw.residuals)):.1e}",)
    return Dimensioned(cid, mech, tuple(map(float, model.xs)), tuple(map(float, value)),
                       tuple(map(float, model.wanted)), error, rms, mu, length, tuple(defects), notes)


def relative_error(task: CurveTask, value, wanted) -> np.ndarray:
    """The relative error of a curve at each sample: against the wanted value (a ratio) or the wanted curve's
    range (a length, angle or slide); for a bound, only the shortfall (0 where the bound holds); NaN where the
    wanted curve does not count.

    >>> t = CurveTask("t", "crank", (0.0, 0.0), (1.0, 0.0), 1.0, "ratio", "c", lambda x: 2.0 + 0 * x,
    ...               box=((0.0, 1.0), (0.0, 1.0)), bound="at least")
    >>> relative_error(t, np.array([1.0, 3.0]), np.array([2.0, 2.0])).tolist()
    [0.5, 0.0]
    """
    value, wanted = np.asarray(value, float), np.asarray(wanted, float)
    with np.errstate(all="ignore"):
        if task.quantity in ("leverage", "ratio"):
            signed = (value - wanted) / np.abs(wanted)
        else:
            span = np.nanmax(wanted) - np.nanmin(wanted) if np.isfinite(wanted).any() else 0.0
            signed = (value - wanted) / max(span, 1e-3 * task.size if task.quantity != "angle" else 1.0)
    if task.bound == "at least":
        return np.where(np.isnan(wanted), np.nan, np.maximum(-signed, 0.0))
    if task.bound == "at most":
        return np.where(np.isnan(wanted), np.nan, np.maximum(signed, 0.0))
    return np.abs(signed)
