"""Joint clearances: the output error of a mechanism whose joints have play, with its tolerances.

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

A *slide on the frame* ``S`` (a prismatic pair: a block of length ``L_S``
in a guide ``2 c_S`` wider than it) is taken in contact mode too, after the
translational clearance joint of Flores, Ambrósio, Claro & Lankarani
("Translational joints with clearance in rigid multibody systems", J.
Comput. Nonlinear Dynam. 3, 011007, 2008): the block's centre (the slide
point, the joint's ``at``) is ``u`` off the guide's mid-line and the block
is tilted by ``α``. With ``w = (L_S/2) α``, the lateral shift of its ends
by the tilt, the ends are at ``u ± w`` and stay within the guide when
``|u| + |w| <= c_S``: the block can shift by up to ``c_S`` and tilt by up
to ``2 c_S / L_S``. In contact a corner touches a wall: ``(u, w)`` is on the
square ``|u| + |w| = c_S``, whose corners are the two-point contacts (flat
on one wall, ``u = ±c_S``; tilted across the guide, two opposite corners
on the walls, ``w = ±c_S``), the worst cases of a linear output. The
random model takes the state uniform on the square (``u`` uniform on
``[−c_S, c_S]``, ``|w| = c_S − |u|``, the tilt's sign at random),
independent between joints and poses, as a pin's direction is. The
block's pin moves with it (its height above the line by ``u − a_t sin α +
a_n (1 − cos α)``, ``(a_t, a_n)`` the slide point from the pin along and
across the line): the slide's offset dimension carries it exactly; a
slide output, read at the block's centre, is corrected by
``(cos α − 1) a_t − a_n sin α`` and the slider's angle by ``α``. The block
length is needed only where the tilt moves something (the pin away from
the slide point, or the slider's angle watched): ``blocks={"S": L}``,
refused by name when needed and missing; else the block is taken as
centred on its pin and only ``u`` acts. A slide between two moving links
takes no clearance.

* :func:`budget` (first order): ``G_J = ∂y/∂e_J`` at every input (a
  2-vector per joint and input, from the dimensions' derivatives by the
  chain rule; for a slide ``(∂y/∂u, ∂y/∂w)``), the worst case
  ``Σ c_J |G_J|`` (for a slide ``c_S max(|∂y/∂u|, |∂y/∂w|)``, the square's
  corners), the standard deviation ``√Σ c_J² |G_J|² / k_J`` (``k = 2`` for a
  pin: ``Var(G·e) = c²|G|²/2`` for a uniform direction; ``k = 3`` for a
  block: ``E u² = E w² = c²/3``, ``E uw = 0`` on the square), and the
  combined budget with the tolerances (worst cases add, variances add),
  every dimension and joint ranked by its share. By virtual work,
  ``G_J = −F_J`` where ``F_J`` is the reaction the joint's first link exerts
  on its second under a unit load conjugate to the output, the input held
  (tested against :func:`~domes.design.dynamics.inverse_dynamics`; for a
  slide: the guide's normal force and its moment about the slide point).
* :func:`monte_carlo`: random dimensions and random clearance states (a
  direction per pin, a point of the square per block) in the seeded batches
  of :func:`domes.design.tolerance.monte_carlo`; each sample keeps its
  states (relative to the carriers) at every input, so each input's
  statistics are the model's (a ``spec`` counts samples off at some input
  with their pins so kept).
* :func:`compare`: both with the clearances and tolerances scaled: where
  first order and Monte Carlo part.

>>> from domes.motion.planar.examples import slider_crank
>>> from domes.design.tolerance import Tolerancing
>>> tol = Tolerancing(slider_crank(), "slide:S", np.radians([0.0, 90.0]), tolerance=0.0)
>>> cl = Clearances(tol, every=1e-3)
>>> [(c.joint, c.kind, c.carrier) for c in cl]
[('A', 'R', 'frame'), ('B', 'R', 'rod'), ('C', 'R', 'rod'), ('S', 'P', 'slider')]
>>> b = budget(cl)
>>> [round(float(x), 6) for x in b.worst[0]]          # 3 c / cos φ + c tan φ: 3e-3 at 0°, 1e-2/√8 at 90°
[0.003, 0.003536]
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
         "and independent between joints and poses, the offset carried by one of the joint's links; a slide's block "
         "(Flores et al. 2008) shifted by u and tilted by 2w/L in its guide with a corner on a wall, |u| + |w| = "
         "clearance, uniform on that square")


@dataclass(frozen=True)
class Clearance:
    """A joint's clearance ``clearance`` (file units): a revolute joint's radial clearance (``kind`` ``"R"``;
    ``carrier`` is the link whose joint point the offset moves, the frame for a pivot on the frame), or a slide's
    lateral play, half the guide's width less the block's (``kind`` ``"P"``; ``carrier`` the block, ``block`` its
    length, None where its tilt moves nothing)."""

    joint: str
    clearance: float
    carrier: str
    kind: str = "R"
    block: float | None = None


class Clearances:
    """The clearances of a :class:`~domes.design.tolerance.Tolerancing`'s mechanism: ``every`` for each revolute
    joint and each slide on the frame, ``clearances`` (joint name -> clearance, file units) for named ones (over
    ``every``); 0 is none. ``blocks`` (slide -> its block's length, file units) where a block's tilt moves
    something (its pin away from the slide point, or the slider's angle watched).

    Iterating gives the :class:`Clearance` of each joint with play, in the file's order. Each clearance must be
    small beside its joint's links (at most :data:`~domes.design.tolerance.LARGEST` of the shortest distance from
    the joint to another joint or point of the link that carries the offset, of the moving link's for a pivot; a
    slide's, of the mechanism's size and of half its block, a tilt of at most that many radians; ``check=False``
    skips this, for a scan beyond it).

    >>> from domes.io.mechanisms import load_mechanism
    >>> tol = Tolerancing(load_mechanism("examples/mechanisms/slider-crank.json"), "slide:S", [0.0], tolerance=0.0)
    >>> Clearances(tol, {"S": 1e-3}).items
    (Clearance(joint='S', clearance=0.001, carrier='slider', kind='P', block=None),)
    """

    def __init__(self, tol: Tolerancing, clearances: dict | None = None, every: float | None = None,
                 check: bool = True, blocks: dict | None = None):
        mech = tol.mech
        self.tolerancing = tol
        revolute = [j.name for j in mech.joints if j.kind == "R"]
        slides = [j.name for j in mech.joints if j.kind == "P" and mech.ground in j.links]
        played = [j.name for j in mech.joints if j.name in revolute or j.name in slides]     # the file's order
        given = {}
        if every is not None:
            given = {name: _value(every, "every joint") for name in played}
        names = {j.name: j for j in mech.joints}
        for name, value in (clearances or {}).items():
            if name not in names:
                raise InputError(f"clearance: {name!r} is not a joint of {mech.name}; its revolute joints are "
                                 f"{', '.join(revolute)}" + (f"; its slides on the frame {', '.join(slides)}"
                                                             if slides else ""))
            if name not in played:
                raise InputError(f"clearance: {name} slides between two moving links ({', '.join(names[name].links)}); "
                                 f"a clearance is taken at a revolute joint ({', '.join(revolute)}) or a slide on the "
                                 f"frame{' (' + ', '.join(slides) + ')' if slides else ''}")
            given[name] = _value(value, name)
        lengths = {}
        for name, value in (blocks or {}).items():
            if name not in slides:
                raise InputError(f"clearance: a block length is given for {name!r}, which is not a slide on the frame "
                                 f"of {mech.name} ({', '.join(slides) or 'it has none'})")
            lengths[name] = _value(value, f"the block of {name}")
            if not lengths[name] > 0:
                raise InputError(f"clearance: the block of {name} must be longer than 0, got {value!r}")
        self._on_link = {link: [j.name for j in mech.joints_of(link) if j.kind == "R"] +
                         [p.name for p in mech.points if p.link == link] for link in mech.links}
        self._at = {j.name: np.array(j.at, dtype=float) for j in mech.joints if j.kind == "R"}
        self._at.update({p.name: np.array(p.at, dtype=float) for p in mech.points})
        self._slot = {}                                          # slide -> the slide point from its pin (a_t, a_n)
        items = []
        for name in played:
            if given.get(name, 0.0) > 0.0 and name in slides:
                items.append(self._slide(name, given[name], lengths.get(name), check))
            elif given.get(name, 0.0) > 0.0:
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

    @property
    def slides(self) -> np.ndarray:
        """``(K,)``: which clearances are a slide's (a block in its guide), in the order of :attr:`items`."""
        return np.array([c.kind == "P" for c in self.items], dtype=bool)

    def states(self, angles: np.ndarray) -> np.ndarray:
        """``(M, K, 2)`` contact states from ``(M, K)`` numbers uniform on ``[0, 2π)``: a pin's offset
        ``c (cos, sin)``; a block's ``(u, w)`` on the square ``|u| + |w| = c``, uniform along it (from the corner
        ``(c, 0)`` through ``(0, c)``, a quarter of the turn per side).

        >>> from domes.motion.planar.examples import slider_crank
        >>> cl = Clearances(Tolerancing(slider_crank(), "slide:S", [0.0], tolerance=0.0), {"A": 1.0, "S": 0.01},
        ...                 check=False)
        >>> cl.states(np.array([[np.pi / 2, np.pi / 4]])).round(6).tolist()     # A along y; S half way to (0, c)
        [[[0.0, 1.0], [0.005, 0.005]]]
        """
        angles = np.asarray(angles, dtype=float)
        c = self.values
        side = angles * (2.0 / math.pi)                         # 0..4 around the square
        triangle = lambda p: np.abs(np.mod(p, 4.0) - 2.0) - 1.0    # noqa: E731  1, 0, -1, 0 at 0, 1, 2, 3
        square = np.stack([triangle(side), triangle(side - 1.0)], axis=-1)
        circle = np.stack([np.cos(angles), np.sin(angles)], axis=-1)
        return c[:, None] * np.where(self.slides[:, None], square, circle)

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

    def _slide(self, joint: str, value: float, block: float | None, check: bool) -> Clearance:
        """A slide's clearance: its block (the slider), the pin's place on it, and whether the tilt matters."""
        tol, mech = self.tolerancing, self.tolerancing.mech
        j = mech.joint(joint)
        slider = j.links[1] if j.links[0] == mech.ground else j.links[0]
        pin = self._on_link[slider][0]                          # the tolerance model takes exactly one
        t = np.array([math.cos(j.direction), math.sin(j.direction)])
        slot = np.array(j.at, dtype=float) - self._at[pin]       # the slide point (the block's centre) from the pin
        along, across = float(slot @ t), float(_cross(t, slot))
        apart = math.hypot(along, across) > 1e-9 * tol.size
        kind, _, target = tol.output.partition(":")
        if block is None and (apart or (kind == "angle" and target == slider)):
            why = (f"its pin {pin} is {math.hypot(along, across):.4g} from the slide point" if apart
                   else f"the output is the angle of its block {slider}")
            raise InputError(f"clearance: the block length of slide {joint} is needed ({why}, so the block's tilt in "
                             f"its guide moves it); give it (blocks={{{joint!r}: L}}; the command's --block "
                             f"{joint}=L)")
        if check:
            limit = LARGEST * min(tol.size, math.inf if block is None else block / 2)
            if value > limit:
                raise InputError(f"clearance: {value:.4g} at {joint} is not small beside "
                                 + (f"half its block, {block / 2:.4g}" if block is not None and block / 2 < tol.size
                                    else f"the mechanism's size {tol.size:.4g}")
                                 + f": a first-order estimate means nothing there; give at most {limit:.4g} "
                                 f"({LARGEST:g} of it)")
        self._slot[joint] = (along, across)
        return Clearance(joint, value, slider, "P", block)

    def _plan(self) -> None:
        """Which dimensions each offset changes: a pivot's ``x`` and ``y``; a carrier link's lengths to the moved
        point (the link's shape rebuilt from its lengths, so that it holds with tolerances too)."""
        tol, mech = self.tolerancing, self.tolerancing.mech
        index = {d.name: k for k, d in enumerate(tol.dimensions)}
        self._pivots, self._bodies, self._blocks = [], [], []
        kind, _, target = tol.output.partition(":")
        carried = {}
        for k, c in enumerate(self.items):
            if c.kind == "P":                                   # (k, offset dim, 2/L, a_t, a_n, output's reading)
                along, across = self._slot[c.joint]
                reads = ("slide" if kind == "slide" and target == c.joint else
                         "angle" if kind == "angle" and target == c.carrier else "")
                self._blocks.append((k, index[f"{c.joint}.offset"], 0.0 if c.block is None else 2.0 / c.block,
                                     along, across, reads))
            elif c.carrier == mech.ground:
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
        (``(M, K, 2)``, in each carrier's frame as drawn; a slide's ``(u, w)``, its block shifted by ``u`` and
        tilted by ``2w/L``): exact, the links' shapes rebuilt from their lengths."""
        values = np.asarray(values, dtype=float)
        offsets = np.asarray(offsets, dtype=float)
        return self._displace(values, offsets)[0]

    def evaluate(self, offsets: np.ndarray, values: np.ndarray | None = None) -> dict:
        """The output's columns (name -> ``(M, N)``) of the mechanism made to the dimension rows ``values`` (the
        nominal when None) with its joints in the states ``offsets`` (as :meth:`displace`): exact, a slide or an
        angle read on the block or the output's line, not the model's."""
        offsets = np.asarray(offsets, dtype=float)
        if values is None:
            values = np.broadcast_to(self.tolerancing.nominal, (len(offsets), self.tolerancing.nominal.size))
        return self._columns(np.asarray(values, dtype=float), offsets)[0]

    def _columns(self, values, offsets, roots: bool = False):
        """:meth:`Tolerancing._outcome` of the displaced rows, the output corrected (see :meth:`_displace`)."""
        tol = self.tolerancing
        rows, correction = self._displace(values, offsets)
        columns, outcome, smallest = Tolerancing._outcome(tol, rows, roots)
        if tol.output.startswith(("angle:", "slide:")):                 # the link's own line, the block's centre
            columns = {name: v + correction[:, None] for name, v in columns.items()}
        return columns, outcome, smallest

    def _displace(self, values, offsets) -> tuple[np.ndarray, np.ndarray]:
        """The dimension rows, and the correction ``(M,)`` of the output read from the model: for an angle, by
        which the model's line of the output's link is turned back from the link's (0 unless an offset moves a
        joint of that line) and a block's tilt for its angle; for a slide, the block's centre from the model's."""
        values = np.asarray(values, dtype=float)
        offsets = np.asarray(offsets, dtype=float)
        out, turn = values.copy(), np.zeros(len(values))
        for k, ix, iy in self._pivots:
            out[:, ix] += offsets[:, k, 0]
            out[:, iy] += offsets[:, k, 1]
        for k, io, tilt, along, across, reads in self._blocks:
            u, alpha = offsets[:, k, 0], offsets[:, k, 1] * tilt
            out[:, io] += u - along * np.sin(alpha) + across * (1.0 - np.cos(alpha))    # the pin's height
            if reads == "slide":
                turn += (np.cos(alpha) - 1.0) * along - across * np.sin(alpha)
            elif reads == "angle":
                turn += alpha
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
                turn = turn - np.arctan2(line[:, 1], line[:, 0])
        return out, turn

    def jacobian(self) -> np.ndarray:
        """``(D, K, 2)``: each dimension's derivative with respect to each offset at the drawn pose."""
        tol = self.tolerancing
        jac = np.zeros((tol.nominal.size, len(self.items), 2))
        for k, ix, iy in self._pivots:
            jac[ix, k, 0] = jac[iy, k, 1] = 1.0
        for k, io, tilt, along, _across, _reads in self._blocks:
            jac[io, k] = (1.0, -along * tilt)
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
        """``(K, 2)``: the output's correction's derivative with respect to each offset (0 but for a joint on the
        line of an output link that carries its offset, and a slide whose block's slide or angle is the output)."""
        out = np.zeros((len(self.items), 2))
        for k, _io, tilt, _along, across, reads in self._blocks:
            out[k, 1] = -across * tilt if reads == "slide" else tilt if reads == "angle" else 0.0
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
    (a pin's offset in its carrier's frame as drawn, ``|G_J|`` the same in
    any frame; a slide's ``(∂y/∂u, ∂y/∂w)``, its block's shift and the shift
    of its ends by its tilt). ``clearance_worst`` ``Σ c_J |G_J|`` (a slide's
    ``|G|`` is ``max(|∂y/∂u|, |∂y/∂w|)``) and ``clearance_std``
    ``√Σ c_J²|G_J|²/k_J`` (``k`` 2 for a pin, 3 for a block, each the
    variance of its random state); ``worst`` and ``std`` add the tolerances'
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
        """``(K,)``: each joint's largest ``|G_J|`` (its worst case per unit of clearance) over the inputs and
        columns (output unit per file unit)."""
        return _tolerance.largest(_size(self.gradient, self.clearances.slides), axis=(0, 1))

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
    worst_c = np.sum(_size(gradient, cl.slides) * c, axis=2)                  # (C, N)
    var_c = np.sum(gradient ** 2, axis=3) * c ** 2 / np.where(cl.slides, 3.0, 2.0)
    std_c = np.sqrt(np.sum(var_c, axis=2))
    sigma = tol.sigma(first.distribution)
    variance = np.concatenate([np.nansum((first.gradient * sigma) ** 2, axis=(0, 1)), np.nansum(var_c, axis=(0, 1))])
    share = variance / variance.sum() if variance.sum() > 0 else variance
    names = tuple(d.name for d in tol.dimensions) + tuple(PREFIX + j for j in cl.joints)
    return Budget(cl, first, gradient, worst_c, std_c, first.worst + worst_c, np.sqrt(first.std ** 2 + std_c ** 2),
                  names, share, first.status)


class _Played(Tolerancing):
    """A tolerancing whose samples also carry a number per clearance: rows of dimensions then uniform angles
    (:meth:`Clearances.states`)."""

    def __init__(self, cl: Clearances):                                     # a view of the tolerancing: not re-built
        self.__dict__.update(cl.tolerancing.__dict__)
        self.clearances = cl

    def sample(self, rng: np.random.Generator, count: int, distribution: str) -> np.ndarray:
        values = super().sample(rng, count, distribution)
        return np.concatenate([values, rng.uniform(0.0, 2 * math.pi, (count, len(self.clearances)))], axis=1)

    def _outcome(self, values, roots: bool = False):
        d = self.nominal.size
        return self.clearances._columns(values[:, :d], self.clearances.states(values[:, d:]), roots)


def monte_carlo(cl: Clearances, samples: int = 100_000, seed: int = 0, distribution: str = "normal",
                batch_size: int = BATCH, executor=None, progress: Progress | None = None,
                spec: float | None = None) -> MonteCarlo:
    """Monte Carlo over random dimensions and random clearance states (a pin's ``|e_J| = c_J`` in a uniform
    direction, a block uniform on its square), in the seeded batches of :func:`domes.design.tolerance.monte_carlo` (the same numbers whatever runs them).

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
        scaled = Clearances(_tolerance._scaled(cl.tolerancing, scale), {c.joint: c.clearance * scale for c in cl},
                            check=False, blocks={c.joint: c.block for c in cl if c.block is not None})
        first = budget(scaled, distribution)
        mc = monte_carlo(scaled, samples, seed, distribution, executor=executor)
        out.append(Comparison(scale, _rms(first.std), _rms(mc.std), mc.failed, bool(first.first.valid.all()),
                              mc.trusted))
    return out


def _size(gradient: np.ndarray, slides: np.ndarray) -> np.ndarray:
    """``(..., K)``: each clearance's worst error per unit of it: ``|G|`` for a pin (the worst direction), the
    larger of ``|∂y/∂u|``, ``|∂y/∂w|`` for a block (the corners of its square)."""
    return np.where(slides, np.max(np.abs(gradient), axis=-1), np.hypot(gradient[..., 0], gradient[..., 1]))


def _rms(a) -> float:
    finite = np.isfinite(a)
    return float(np.sqrt(np.mean(np.square(a[finite])))) if finite.any() else math.nan


__all__ = ["MODEL", "PREFIX", "Budget", "Clearance", "Clearances", "budget", "compare", "monte_carlo"]
