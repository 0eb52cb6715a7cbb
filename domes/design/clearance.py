"""Joint clearances: the output error of a mechanism whose revolute joints have play, with its tolerances.

The redesign step of seed 002 §7-1 treats "both link-length tolerances and
joint clearances ... usually by the principle of virtual work". A revolute
joint ``J`` with radial clearance ``c_J`` is taken in *contact mode*, the
massless virtual link of the effective-link-length model (Ting, Zhu &
Watkins 2000, "The effects of joint clearance on position and orientation
deviation of linkages and manipulators", Mech. Mach. Theory 35): the pin
rests against the wall of its hole, so the centre of the joint on one link
is ``e_J`` from its centre on the other, ``|e_J| = c_J``, in a direction
uniform on the circle, independent between joints and between poses.

The offset is a virtual link of length ``c_J`` fixed in one of the joint's
links, its *carrier* (:attr:`Clearance.carrier`): the frame for a pivot on
the frame; else a moving link whose shape is a drawing's lengths (not a
slider, not a cylinder's link, not the input link when ``J`` is on its
reference line; the output link, when ``J`` is on the line its angle is
measured along, only if the other link cannot, and then that angle is
corrected by the turn of the line). With ``e_J`` so fixed the mechanism is
again a rigid linkage, the carrier's joint point moved by ``e_J`` (an
effective link length), so each sample is evaluated exactly by the
tolerance model (:class:`~domes.design.tolerance.Tolerancing`).

* :func:`budget` (first order): ``G_J = ∂y/∂e_J`` at every input (a
  2-vector per joint and input, from the dimensions' derivatives by the
  chain rule), the worst case ``Σ c_J |G_J|``, the standard deviation
  ``√Σ c_J² |G_J|² / 2`` (``Var(G·e) = c²|G|²/2`` for a uniform direction),
  and the combined budget with the tolerances (worst cases add, variances
  add), every dimension and joint ranked by its share. By virtual work,
  ``G_J = −F_J`` where ``F_J`` is the reaction the joint's first link exerts
  on its second under a unit load conjugate to the output, the input held
  (tested against :func:`~domes.design.dynamics.inverse_dynamics`).
* :func:`monte_carlo`: random dimensions and random clearance directions
  in the seeded batches of :func:`domes.design.tolerance.monte_carlo`; each
  sample keeps its directions (relative to the carriers) at every input, so
  each input's statistics are the model's (a ``spec`` counts samples off at
  some input with their pins so kept).
* :func:`compare`: both with the clearances and tolerances scaled: where
  first order and Monte Carlo part.

>>> from domes.motion.planar.examples import slider_crank
>>> from domes.design.tolerance import Tolerancing
>>> tol = Tolerancing(slider_crank(), "slide:S", np.radians([0.0, 90.0]), tolerance=0.0)
>>> cl = Clearances(tol, every=1e-3)
>>> [(c.joint, c.carrier) for c in cl]
[('A', 'frame'), ('B', 'rod'), ('C', 'rod')]
>>> b = budget(cl)
>>> [round(float(x), 6) for x in b.worst[0]]          # 3 c / cos φ: 3e-3 at 0°, 3e-3 · 3/√8 at 90°
[0.003, 0.003182]
>>> mc = monte_carlo(cl, 20_000, seed=1)
>>> bool(np.all(abs(mc.std / b.std - 1) < 0.05)), mc.failed
(True, 0)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.design import tolerance as _tolerance
from domes.design.tolerance import BATCH, LARGEST, Comparison, MonteCarlo, Sensitivity, Tolerancing, sensitivity
from domes.errors import InputError
from domes.results import Progress, Result, Status

#: The prefix of a clearance among the budget's names (``clearance:B``), beside the dimensions' names.
PREFIX = "clearance:"
#: The clearance model, in words (the command's documents carry it).
MODEL = ("contact mode (Ting, Zhu & Watkins 2000): the pin on its hole's wall, |e| = clearance, direction uniform "
         "and independent between joints and poses, the offset carried by one of the joint's links")


@dataclass(frozen=True)
class Clearance:
    """A revolute joint's radial clearance ``clearance`` (file units); ``carrier`` is the link whose joint point
    the offset moves (the frame for a pivot on the frame)."""

    joint: str
    clearance: float
    carrier: str


class Clearances:
    """The clearances of a :class:`~domes.design.tolerance.Tolerancing`'s mechanism: ``every`` for each revolute
    joint, ``clearances`` (joint name -> clearance, file units) for named ones (over ``every``); 0 is none.

    Iterating gives the :class:`Clearance` of each joint with play, in the file's order. Each clearance must be
    small beside its joint's links (at most :data:`~domes.design.tolerance.LARGEST` of the shortest distance from
    the joint to another joint or point of the link that carries the offset, of the moving link's for a pivot;
    ``check=False`` skips this, for a scan beyond it).
    """

    def __init__(self, tol: Tolerancing, clearances: dict | None = None, every: float | None = None,
                 check: bool = True):
        mech = tol.mech
        self.tolerancing = tol
        revolute = [j.name for j in mech.joints if j.kind == "R"]
        given = {}
        if every is not None:
            given = {name: _value(every, "every joint") for name in revolute}
        names = {j.name: j for j in mech.joints}
        for name, value in (clearances or {}).items():
            if name not in names:
                raise InputError(f"clearance: {name!r} is not a joint of {mech.name}; its revolute joints are "
                                 f"{', '.join(revolute)}")
            if names[name].kind != "R":
                raise InputError(f"clearance: {name} is a {names[name].kind} joint; a clearance is taken at a "
                                 f"revolute joint ({', '.join(revolute)})")
            given[name] = _value(value, name)
        self._on_link = {link: [j.name for j in mech.joints_of(link) if j.kind == "R"] +
                         [p.name for p in mech.points if p.link == link] for link in mech.links}
        self._at = {j.name: np.array(j.at, dtype=float) for j in mech.joints if j.kind == "R"}
        self._at.update({p.name: np.array(p.at, dtype=float) for p in mech.points})
        items = []
        for name in revolute:
            if given.get(name, 0.0) > 0.0:
                carrier = self._carrier(name)
                if check:
                    self._small(name, given[name], carrier)
                items.append(Clearance(name, given[name], carrier))
        self.items = tuple(items)
        self._plan()

    def __iter__(self):
        return iter(self.items)

    def __len__(self) -> int:
        return len(self.items)

    @property
    def joints(self) -> list[str]:
        return [c.joint for c in self.items]

    @property
    def values(self) -> np.ndarray:
        """Each joint's clearance, in the order of :attr:`items`."""
        return np.array([c.clearance for c in self.items], dtype=float)

    # -- the model ------------------------------------------------------------------------------

    def _refused(self, link: str, joint: str) -> str:
        """Why ``link`` cannot carry the offset of ``joint`` (``""`` when it can)."""
        mech, tol = self.tolerancing.mech, self.tolerancing
        for j in mech.joints_of(link):
            if j.kind == "P":
                return "a slider" if mech.ground in j.links else f"a link of the slide {j.name}"
        if tol.joint is not None:
            pivot = mech.joint(tol.joint)
            moving = pivot.links[1] if pivot.links[0] == mech.ground else pivot.links[0]
            other = next((p for p in self._on_link[moving] if p != pivot.name), None)
            if link == moving and joint in (pivot.name, other):
                return "the input link, whose angle is the input"
        if len(self._on_link[link]) < 2:
            return "it carries no other joint or point"
        return ""

    def _measured(self, link: str, joint: str) -> bool:
        """Whether ``link`` is the output's link and ``joint`` on the line its angle is measured along (then an
        offset it carries turns that line: the angle is corrected by the turn)."""
        kind, _, target = self.tolerancing.output.partition(":")
        return kind == "angle" and link == target and joint in self._on_link[link][:2]

    def _carrier(self, joint: str) -> str:
        mech = self.tolerancing.mech
        links = mech.joint(joint).links
        if mech.ground in links:
            return mech.ground
        why = {link: self._refused(link, joint) for link in links}
        for link in sorted(links, key=lambda link: self._measured(link, joint)):    # the output's link last
            if not why[link]:
                return link
        raise InputError(f"clearance: neither link of joint {joint} can carry its offset ({links[0]}: "
                         f"{why[links[0]]}; {links[1]}: {why[links[1]]}); leave {joint} without a clearance")

    def _small(self, joint: str, value: float, carrier: str) -> None:
        mech = self.tolerancing.mech
        link = carrier
        if carrier == mech.ground:
            links = mech.joint(joint).links
            link = links[1] if links[0] == mech.ground else links[0]
        others = [p for p in self._on_link[link] if p != joint]
        if not others:
            return
        near = min(others, key=lambda p: float(np.linalg.norm(self._at[p] - self._at[joint])))
        distance = float(np.linalg.norm(self._at[near] - self._at[joint]))
        if value > LARGEST * distance:
            raise InputError(f"clearance: {value:.4g} at {joint} is not small beside {distance:.4g}, the distance "
                             f"from {joint} to {near} on {link}: a first-order estimate means nothing there; give at "
                             f"most {LARGEST * distance:.4g} ({LARGEST:g} of it)")

    def _plan(self) -> None:
        """Which dimensions each offset changes: a pivot's ``x`` and ``y``; a carrier link's lengths to the moved
        point (the link's shape rebuilt from its lengths, so that it holds with tolerances too)."""
        tol, mech = self.tolerancing, self.tolerancing.mech
        index = {d.name: k for k, d in enumerate(tol.dimensions)}
        self._pivots, self._bodies = [], []
        carried = {}
        for k, c in enumerate(self.items):
            if c.carrier == mech.ground:
                self._pivots.append((k, index[f"{c.joint}.x"], index[f"{c.joint}.y"]))
            else:
                carried.setdefault(c.carrier, []).append(k)
        for link, ks in carried.items():
            pts = self._on_link[link]
            at = np.array([self._at[p] for p in pts])
            pairs = [(0, 1)] + [(a, p) for p in range(2, len(pts)) for a in (0, 1)]
            dims = [index[f"{link}:{pts[a]}-{pts[b]}"] for a, b in pairs]
            u = at[1] - at[0]
            turns = []
            for p in range(2, len(pts)):
                turn = _cross(u, at[p] - at[0])
                flat = abs(turn) <= 1e-9 * tol.size * float(np.linalg.norm(u))
                turns.append(0.0 if flat else math.copysign(1.0, turn))
            moved = {pts.index(self.items[k].joint): k for k in ks}
            touched = [(a, b, d) for (a, b), d in zip(pairs, dims) if a in moved or b in moved]
            self._bodies.append({"link": link, "points": pts, "at": at, "dims": dims, "turns": turns,
                                 "angle": math.atan2(u[1], u[0]), "moved": moved, "touched": touched})
        #: The carrier whose offsets turn the output's line (the output link's angle is corrected), if any.
        self._measuring = next((b for b in self._bodies if any(self._measured(b["link"], b["points"][p])
                                                               for p in b["moved"])), None)

    def displace(self, values: np.ndarray, offsets: np.ndarray) -> np.ndarray:
        """Dimension rows ``(M, D)`` of the mechanism whose carriers' joint points are moved by ``offsets``
        (``(M, K, 2)``, in each carrier's frame as drawn): exact, the links' shapes rebuilt from their lengths."""
        values = np.asarray(values, dtype=float)
        offsets = np.asarray(offsets, dtype=float)
        return self._displace(values, offsets)[0]

    def _displace(self, values, offsets) -> tuple[np.ndarray, np.ndarray]:
        """The dimension rows, and the angle ``(M,)`` by which the model's line of the output's link is turned
        back from the link's (0 unless an offset moves a joint of that line): the output angle's correction."""
        values = np.asarray(values, dtype=float)
        offsets = np.asarray(offsets, dtype=float)
        out, turn = values.copy(), np.zeros(len(values))
        for k, ix, iy in self._pivots:
            out[:, ix] += offsets[:, k, 0]
            out[:, iy] += offsets[:, k, 1]
        for body in self._bodies:
            local = _shape(values, body)                                      # (M, P, 2), p0 -> p1 along x
            c, s = math.cos(body["angle"]), math.sin(body["angle"])
            for p, k in body["moved"].items():
                e = offsets[:, k]
                local[:, p] += np.stack([c * e[:, 0] + s * e[:, 1], -s * e[:, 0] + c * e[:, 1]], axis=1)
            for a, b, d in body["touched"]:
                out[:, d] = np.hypot(*(local[:, a] - local[:, b]).T)
            if body is self._measuring:                                      # the link's own line is along +x
                line = local[:, 1] - local[:, 0]
                turn = -np.arctan2(line[:, 1], line[:, 0])
        return out, turn

    def jacobian(self) -> np.ndarray:
        """``(D, K, 2)``: each dimension's derivative with respect to each offset at the drawn pose."""
        tol = self.tolerancing
        jac = np.zeros((tol.nominal.size, len(self.items), 2))
        for k, ix, iy in self._pivots:
            jac[ix, k, 0] = jac[iy, k, 1] = 1.0
        for body in self._bodies:
            at = body["at"]
            for a, b, d in body["touched"]:
                unit = (at[a] - at[b]) / np.linalg.norm(at[a] - at[b])
                if a in body["moved"]:
                    jac[d, body["moved"][a]] += unit
                if b in body["moved"]:
                    jac[d, body["moved"][b]] -= unit
        return jac

    def turning(self) -> np.ndarray:
        """``(K, 2)``: the output angle's correction's derivative with respect to each offset (0 but for a joint on
        the line of an output link that carries its offset)."""
        out = np.zeros((len(self.items), 2))
        body = self._measuring
        if body is not None:
            at, sign = body["at"], {0: 1.0, 1: -1.0}
            normal = np.array([-math.sin(body["angle"]), math.cos(body["angle"])]) / np.linalg.norm(at[1] - at[0])
            for p, k in body["moved"].items():
                if p in sign:
                    out[k] += sign[p] * normal
        return out


def _value(value, name: str) -> float:
    try:
        out = float(value)
    except (TypeError, ValueError):
        out = math.nan
    if not (math.isfinite(out) and out >= 0):
        raise InputError(f"clearance: the clearance of {name} must be a number >= 0 (a radial clearance, file "
                         f"units), got {value!r}")
    return out


def _shape(values, body) -> np.ndarray:
    """``(M, P, 2)`` the points of a rigid link from its lengths: the first at 0, the second on +x, each further
    one by its two lengths, on the drawn side (NaN where its triangle does not close)."""
    dims, turns = body["dims"], body["turns"]
    m, count = len(values), len(body["points"])
    local = np.zeros((m, count, 2))
    length = values[:, dims[0]]
    local[:, 1, 0] = length
    for p in range(2, count):
        a, b = values[:, dims[2 * p - 3]], values[:, dims[2 * p - 2]]
        x = (a * a - b * b + length * length) / (2 * length)
        with np.errstate(invalid="ignore"):
            local[:, p, 1] = turns[p - 2] * np.sqrt(a * a - x * x) if turns[p - 2] else 0.0
        local[:, p, 0] = x
    return local


def _cross(a, b) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


@dataclass(frozen=True, eq=False)
class Budget(Result):
    """First-order budget of tolerances and clearances together, per column ``c`` and input.

    ``gradient[c]`` is ``(N, K, 2)``: ``∂y/∂e_J`` for each joint with play
    (its offset in its carrier's frame as drawn; ``|G_J|`` is the same in
    any frame). ``clearance_worst`` ``Σ c_J |G_J|`` and ``clearance_std``
    ``√Σ c_J²|G_J|²/2``; ``worst`` and ``std`` add the tolerances'
    (:attr:`first`'s ``worst`` and ``std``): worst cases sum, variances add.
    ``names`` are the dimensions' names then ``clearance:J`` for each joint;
    ``share`` each one's part of the variance over inputs and columns.
    """

    clearances: Clearances
    first: Sensitivity
    gradient: np.ndarray
    clearance_worst: np.ndarray
    clearance_std: np.ndarray
    worst: np.ndarray
    std: np.ndarray
    names: tuple
    share: np.ndarray
    status: Status = Status.COMPLETE

    @property
    def ranking(self) -> list[str]:
        return [self.names[k] for k in np.argsort(-self.share, kind="stable")]

    @property
    def largest(self) -> np.ndarray:
        """``(K,)``: each joint's largest ``|G_J|`` over the inputs and columns (output unit per file unit)."""
        return _tolerance.largest(np.hypot(self.gradient[..., 0], self.gradient[..., 1]), axis=(0, 1))

    @property
    def message(self) -> str:
        t = self.first.tolerancing
        if not np.isfinite(self.worst).any():
            return f"{t.mech.name}: {t.output}: no derivative at any input"
        text = (f"{t.mech.name}: {t.output}, {len(t.dimensions)} dimensions and {len(self.clearances)} clearances; "
                f"tolerances: worst case {t.shown(np.nanmax(self.first.worst))}, 3σ {t.shown(3 * np.nanmax(self.first.std))}; "
                f"clearances: worst case {t.shown(np.nanmax(self.clearance_worst))}, 3σ "
                f"{t.shown(3 * np.nanmax(self.clearance_std))}; together: worst case {t.shown(np.nanmax(self.worst))}, "
                f"3σ {t.shown(3 * np.nanmax(self.std))}; largest share {self.ranking[0]} ({100 * np.max(self.share):.0f}%)")
        return text + (f"; {self.first.not_valid}" if self.first.not_valid else "")


def budget(cl: Clearances, distribution: str = "normal", first: Sensitivity | None = None) -> Budget:
    """The first-order budget of the tolerances (``first``, computed when not given) and the clearances.

    >>> from domes.motion.planar.examples import four_bar
    >>> tol = Tolerancing(four_bar(), "angle:rocker", [0.0], relative=1e-4)
    >>> b = budget(Clearances(tol, {"B": 2e-4, "C": 2e-4}))
    >>> b.ranking[:3], b.gradient.shape
    (['clearance:B', 'clearance:C', 'coupler:B-C'], (1, 1, 2, 2))
    """
    tol = cl.tolerancing
    if first is None:
        first = sensitivity(tol, distribution)
    elif first.tolerancing is not tol:
        raise InputError("clearance: the first-order analysis given is of another tolerancing")
    c = cl.values
    gradient = np.einsum("cnd,dkx->cnkx", first.gradient, cl.jacobian()) + cl.turning()   # (C, N, K, 2)
    size = np.hypot(gradient[..., 0], gradient[..., 1])                       # (C, N, K)
    worst_c = np.sum(size * c, axis=2)
    var_c = size ** 2 * c ** 2 / 2.0
    std_c = np.sqrt(np.sum(var_c, axis=2))
    sigma = tol.sigma(first.distribution)
    variance = np.concatenate([np.nansum((first.gradient * sigma) ** 2, axis=(0, 1)), np.nansum(var_c, axis=(0, 1))])
    share = variance / variance.sum() if variance.sum() > 0 else variance
    names = tuple(d.name for d in tol.dimensions) + tuple(PREFIX + j for j in cl.joints)
    return Budget(cl, first, gradient, worst_c, std_c, first.worst + worst_c, np.sqrt(first.std ** 2 + std_c ** 2),
                  names, share, first.status)


class _Played(Tolerancing):
    """A tolerancing whose samples also carry a direction per clearance: rows of dimensions then angles."""

    def __init__(self, cl: Clearances):                                     # a view of the tolerancing: not re-built
        self.__dict__.update(cl.tolerancing.__dict__)
        self.clearances = cl

    def sample(self, rng: np.random.Generator, count: int, distribution: str) -> np.ndarray:
        values = super().sample(rng, count, distribution)
        return np.concatenate([values, rng.uniform(0.0, 2 * math.pi, (count, len(self.clearances)))], axis=1)

    def _outcome(self, values, roots: bool = False):
        d = self.nominal.size
        angle = values[:, d:]
        offsets = self.clearances.values[None, :, None] * np.stack([np.cos(angle), np.sin(angle)], axis=2)
        rows, turn = self.clearances._displace(values[:, :d], offsets)
        columns, outcome, smallest = super()._outcome(rows, roots)
        if self.output.startswith("angle:"):                           # the link's own line, not the model's
            columns = {name: v + turn[:, None] for name, v in columns.items()}
        return columns, outcome, smallest


def monte_carlo(cl: Clearances, samples: int = 100_000, seed: int = 0, distribution: str = "normal",
                batch_size: int = BATCH, executor=None, progress: Progress | None = None,
                spec: float | None = None) -> MonteCarlo:
    """Monte Carlo over random dimensions and random clearance directions (``|e_J| = c_J``, uniform), in the
    seeded batches of :func:`domes.design.tolerance.monte_carlo` (the same numbers whatever runs them).

    >>> from domes.motion.planar.examples import four_bar
    >>> tol = Tolerancing(four_bar(), "angle:rocker", [0.0], tolerance=0.0)
    >>> mc = monte_carlo(Clearances(tol, every=1e-3), 20_000, seed=3)
    >>> mc.failed, mc.trusted
    (0, True)
    """
    return _tolerance.monte_carlo(_Played(cl), samples, seed, distribution, batch_size, executor, progress, spec)


def compare(cl: Clearances, scales=(1.0, 10.0, 100.0), samples: int = 20_000, seed: int = 0,
            distribution: str = "normal", executor=None) -> list[Comparison]:
    """First order (:func:`budget`) and :func:`monte_carlo` with every clearance and tolerance times each of
    ``scales``: where they part."""
    out = []
    for scale in scales:
        scaled = Clearances(_tolerance._scaled(cl.tolerancing, scale),
                            {c.joint: c.clearance * scale for c in cl}, check=False)
        first = budget(scaled, distribution)
        mc = monte_carlo(scaled, samples, seed, distribution, executor=executor)
        out.append(Comparison(scale, _rms(first.std), _rms(mc.std), mc.failed, bool(first.first.valid.all()),
                              mc.trusted))
    return out


def _rms(a) -> float:
    finite = np.isfinite(a)
    return float(np.sqrt(np.mean(np.square(a[finite])))) if finite.any() else math.nan


__all__ = ["MODEL", "PREFIX", "Budget", "Clearance", "Clearances", "budget", "compare", "monte_carlo"]
