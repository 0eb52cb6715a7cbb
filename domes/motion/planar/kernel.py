"""The compiled kernel: closed-form poses and motion of dyad mechanisms on arrays.

A :class:`Program` is compiled once from a
:class:`~domes.motion.planar.query.Kinematics` whose groups are drivers and
dyads (RRR, RPR, RRP, PRP, RPP: seed 002, chapter 2, and the digest's §F.1),
gear and cam pairs, and larger Assur groups (class III and IV, solved by
Newton's method on arrays: :mod:`~domes.motion.planar.groups`), and
evaluated on arrays: many input values of one mechanism, or many
mechanisms of one topology (a :class:`Geometry` of arrays of joint
coordinates) over many inputs at once. Points are complex numbers ``x + iy``
and a link's rotation from its drawn pose is a unit complex number, so a
pose costs a few dozen arithmetic operations per configuration and no
trigonometry beyond the input's own.

Each link is placed by its rotation ``R`` and one *anchor*: its drawn point
``P`` now at ``W``; any drawn point ``p`` of it is at ``W + R·(p − P)``.
Velocities and accelerations follow from the dyads' joint constraints,
solved (2 × 2) for the two unknown rates of each dyad. Each dyad also
reports its *root*: the normalised discriminant of its closed form (for an
RRR dyad the sine of the angle between its links, the transmission angle
of a four-bar), which is zero exactly where its Jacobian is singular.

>>> import numpy as np
>>> from domes.motion.planar.examples import four_bar
>>> from domes.motion.planar.query import Kinematics
>>> prog = Program(Kinematics(four_bar(), outputs=["angle:rocker"]))
>>> geom = prog.geometry()
>>> pose = prog.poses(geom, np.radians([0.0, 30.0, 60.0]))
>>> [round(float(np.degrees(x)), 6) for x in prog.outputs(geom, pose)["angle:rocker"]]
[78.463041, 70.546922, 75.228684]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from domes.errors import InputError
from domes.motion.planar.compiled import Tape, choose
from domes.motion.planar.dyads import ASSEMBLY_SLACK
from domes.motion.planar.groups import Loops, follow
from domes.motion.planar.groups import solve as solve_stack
from domes.motion.planar.structure import CamTie, Rotation

SIGNED = ("RRR", "RPR", "RRP")


def vectorizable(kin) -> bool:
    """Whether every group the query needs is a driver, a dyad with a closed form, or a geared or cammed group
    whose pairs are driven by the inputs and the links those place (:func:`blocked` names the others; the kernel
    also takes larger Assur groups, by Newton's method on arrays: :func:`iterated`)."""
    return not blocked(kin) and not iterated(kin)


def iterated(kin) -> list[str]:
    """Labels of the groups the kernel solves by Newton's method on arrays (:mod:`~domes.motion.planar.groups`):
    class-III, class-IV and larger Assur groups.

    >>> from domes.motion.planar.examples import four_bar
    >>> from domes.motion.planar.query import Kinematics
    >>> iterated(Kinematics(four_bar())), iterated(Kinematics(four_bar(), method="newton"))
    ([], [])
    """
    stuck = set(blocked(kin))
    return [g.label for g in kin.groups if _newton_group(kin, g) and g.label not in stuck]


def blocked(kin) -> list[str]:
    """Labels of the groups the kernel cannot evaluate: the whole loop-closure model (``method="newton"``: a
    group holding a driven joint to a placed link, which the step-by-step route keeps as the reference), groups
    with gear or cam pairs inside, and geared, cammed or larger groups that read a variable no earlier group
    holds on arrays.

    >>> from domes.motion.planar.examples import four_bar
    >>> from domes.motion.planar.query import Kinematics
    >>> blocked(Kinematics(four_bar(), method="newton"))
    ['3-link group {crank, coupler, rocker}']
    """
    cached = kin.__dict__.get("_blocked")  # a query does not change: asked once per sweep, found once
    if cached is not None:
        return list(cached)
    s = kin.structure
    driven = set(s.input_vars)
    whole = []
    for g in kin.groups:
        if not _newton_group(kin, g):
            continue
        outer = any(jn in driven and not set(kin.mech.joint(jn).links) <= set(g.links) for jn in g.joints)
        if outer or s.derived_of(g):
            whole.append(g.label)
    whole += [label for label in _compile(kin)[2] if label not in whole]
    kin.__dict__["_blocked"] = tuple(whole)
    return whole


def _newton_group(kin, g) -> bool:
    """Whether ``g`` is solved by Newton's method (not a driver, a dyad with a closed form, nor geared or cammed)."""
    return g.kind not in ("geared", "cammed") and g.index not in kin.plans and bool(g.unknowns or len(g.links) > 1)


def _compile(kin):
    """What the kernel carries between groups: ``(reads, order, blocked)``.

    ``reads[i]`` lists the variables that later gear and cam pairs and
    groups solved by Newton's method need from dyad ``i``, in the order
    they are read: ``("rot", var, link, coeff, rest)`` (from ``link``'s rotation ``coeff·var + rest``) or ``("slide",
    var, joint)``. ``order[i]`` lists the derived variables of geared or
    cammed group ``i`` (racks' slides, cams' followers) in the order they are
    computed; ``blocked`` the labels of the geared, cammed or Newton groups
    that need a variable no earlier step holds.
    """
    s = kin.structure
    have = set(s.input_vars.values())
    offers: dict = {}
    reads: dict = {}
    order: dict = {}
    stuck: list = []

    def get(v) -> bool:
        if v in have:
            return True
        if v not in offers:
            return False
        index, how = offers[v]
        have.add(v)
        if how[0] == "rot" and not all(get(w) for w, _ in how[4].terms):
            have.discard(v)
            return False
        reads.setdefault(index, []).append(how)
        return True

    for g in kin.groups:
        if g.kind in ("geared", "cammed"):
            own = s.derived_of(g)
            done: list = []
            pending = list(own)
            while pending:
                v = next((v for v in pending if all(w in done or (w not in own and get(w))
                                                    for w, _ in s.derived[v].terms if w != v)), None)
                if v is None:
                    break
                done.append(v)
                pending.remove(v)
            links_ok = all(w in done or get(w) for x in g.links for w, _ in s.rotations[x].terms)
            if pending or not links_ok:
                stuck.append(g.label)
            order[g.index] = done
            have.update(done)
        elif _newton_group(kin, g):
            need = {w for x in g.links for w, _ in s.rotations[x].terms}
            need |= {w for loop in g.loops for seg in loop for w, _ in seg.rotation.terms}
            need |= {seg.slide for loop in g.loops for seg in loop if seg.kind == "slide"}
            if not all(get(w) for w in sorted(need - set(g.unknowns))):
                stuck.append(g.label)
            have.update(g.unknowns)
        elif g.index in kin.plans:
            for x in g.links:
                expr = s.rotations[x]
                var, coeff = next(((v, c) for v, c in expr.terms if v in g.unknowns), (None, 0.0))
                if var is not None and var not in offers:
                    rest = Rotation(tuple((v, c) for v, c in expr.terms if v != var), expr.const)
                    offers[var] = (g.index, ("rot", var, x, coeff, rest))
            for jn in g.joints:
                if f"s:{jn}" in g.unknowns:
                    offers[f"s:{jn}"] = (g.index, ("slide", f"s:{jn}", jn))
    return reads, order, stuck


def law_at(tie, turn, order: int = 2) -> tuple:
    """A cam's law and its derivatives at ``phase + turn`` (arrays; NaN where the turn is not finite).

    >>> from domes.model.laws import Motion
    >>> from domes.motion.planar.structure import CamTie, Rotation
    >>> tie = CamTie(Motion.cam([("cycloidal", 180, 1.0), ("cycloidal", 180, -1.0)]), 0.0, Rotation(()), Rotation(()), 1.0)
    >>> [round(float(x), 6) for x in law_at(tie, np.array([np.pi / 2, np.nan]), 0)[0]]
    [0.5, nan]
    """
    x = np.asarray(tie.phase + turn, dtype=float)
    ok = np.isfinite(x)
    return tuple(np.where(ok, v, np.nan) for v in tie.law.evaluate(np.where(ok, x, 0.0), order))


def cam_rates(tie, values, rates, accels=None, law=None) -> tuple:
    """A cam follower's rate and (given ``accels``) acceleration on arrays, as
    :meth:`~domes.motion.planar.structure.CamTie.motion`: ``L'·ẋ`` and ``L''·ẋ² + L'·ẍ``, plus the base's.

    ``law`` is the law's ``(L, L', L'')`` at the follower's turn when already evaluated.
    """
    _, d1, d2 = law if law is not None else law_at(tie, tie.turn.value(values), 2)
    xd = tie.turn.rate(rates)
    rate = tie.base.rate(rates) + tie.sign * d1 * xd
    if accels is None:
        return rate, None
    return rate, tie.base.rate(accels) + tie.sign * (d2 * xd * xd + d1 * tie.turn.rate(accels))


def _c(p) -> complex:
    return complex(p[0], p[1])


def _cross(p, q):
    """``Im(conj(p)·q)``: the cross product of two complex vectors."""
    return p.real * q.imag - p.imag * q.real


def _dot(p, q):
    return p.real * q.real + p.imag * q.imag


def _unit(z):
    with np.errstate(invalid="ignore", divide="ignore"):
        return z / np.abs(z)


@dataclass
class Geometry:
    """Drawn-pose data of one mechanism (numbers) or of ``M`` mechanisms of one topology (arrays ``(M, 1)``).

    ``at``: joints and coupler points (complex); ``direction``: each P joint's
    slide direction (unit complex); ``s0``: its drawn slide coordinate;
    ``reference``: each link's reference angle; ``drawn``: each input's drawn
    value; ``sign``: each signed dyad's assembly mode (by group index; 0 where
    the drawn pose is on a dead point and the mode is ambiguous).
    """

    at: dict
    direction: dict
    s0: dict
    reference: dict
    drawn: dict
    sign: dict
    count: int | None = None

    def rows(self, lo: int, hi: int) -> "Geometry":
        """The mechanisms ``lo .. hi − 1`` of a batch geometry."""
        def take(d):
            return {k: (v[lo:hi] if np.ndim(v) else v) for k, v in d.items()}

        return Geometry(take(self.at), take(self.direction), take(self.s0), take(self.reference), take(self.drawn),
                        take(self.sign), None if self.count is None else max(0, min(hi, self.count) - lo))


@dataclass
class Poses:
    """Link placements, slides and the dyads' diagnostics on an array of configurations.

    ``links[name] = (R, W, P)``; ``slides[joint]``; ``unassembled`` and
    ``undetermined`` are masks by group index, ``root`` the dyads' normalised
    discriminants, ``margin`` their signed assembly margins (a length, positive
    where the dyad assembles, negative beyond a limit, not clamped: its root
    is the limit), ``closure`` each dyad's loop-closure error (absolute).
    ``values`` holds the variables gear and cam pairs read (inputs, rotations
    read from dyads' links, racks' slides, followers' variables) and
    ``turns`` each cam's turn (by its follower's variable).
    """

    links: dict
    slides: dict
    inputs: dict
    shape: tuple = ()
    unassembled: dict = field(default_factory=dict)
    undetermined: dict = field(default_factory=dict)
    root: dict = field(default_factory=dict)
    margin: dict = field(default_factory=dict)
    closure: dict = field(default_factory=dict)
    values: dict = field(default_factory=dict)
    turns: dict = field(default_factory=dict)
    laws: dict = field(default_factory=dict)

    def world(self, geom: Geometry, link: str, name: str):
        """World position of the drawn point (joint or coupler point) ``name`` of ``link``."""
        R, W, P = self.links[link]
        return W + R * (geom.at[name] - P)

    @property
    def failed(self):
        """Configurations where some dyad cannot be assembled or is undetermined (a boolean array, or False)."""
        out = False
        for mask in list(self.unassembled.values()) + list(self.undetermined.values()):
            out = out | mask
        return out


@dataclass
class Motion:
    """Angular and linear rates of each link (``w``, ``V`` at its anchor) and slide rates, at one derivative level.

    ``rates`` holds the same level's rates of the variables in :attr:`Poses.values`.
    """

    w: dict
    V: dict
    slide: dict
    rates: dict = field(default_factory=dict)


class Program:
    """A compiled :class:`~domes.motion.planar.query.Kinematics` of drivers, dyads, gear and cam pairs, on arrays.

    A geared or cammed group reads the rotations of the links placed before
    it (a dyad's link: its angle from the drawn pose, continuous along the
    last axis from the drawn pose or the ``start`` of :meth:`poses`) and
    their rates; a cam's follower moves by its law at the cam's turn. A
    class-III, class-IV or larger group is solved by Newton's method along
    the last axis, continuing from ``start``
    (:func:`~domes.motion.planar.groups.follow`); its rates solve its loop
    equations as a stack. Its ``unassembled`` mask holds the configurations
    from the first one it could not reach.

    >>> from domes.motion.planar.examples import stephenson_iii
    >>> from domes.motion.planar.query import Kinematics
    >>> prog = Program(Kinematics(stephenson_iii(), outputs=["angle:link1"]))
    >>> geom = prog.geometry()
    >>> pose = prog.poses(geom, np.radians([0.0, 90.0, 180.0]))
    >>> [round(float(np.degrees(x)), 6) for x in prog.outputs(geom, pose)["angle:link1"]]
    [-90.0, -77.18777, -66.376967]
    """

    def __init__(self, kin, route: str | None = None):
        others = blocked(kin)
        if others:
            raise InputError(f"{kin.mech.name}: the kernel evaluates drivers, dyads, gear and cam pairs driven "
                             "by the inputs and the links these place, and larger Assur groups (Newton's method on "
                             f"arrays); groups {others} are solved step by step (Newton's method: the whole "
                             "loop-closure model, or a group reading what no earlier group holds on arrays)")
        self.kin = kin
        #: ``numpy``, ``numba`` or ``auto`` (None: ``$DOMES_KERNEL``): how :meth:`poses` runs
        #: (:func:`~domes.motion.planar.compiled.choose`).
        self.route = route
        self.reads, order, _ = _compile(kin)
        s = kin.structure
        self.lifts = {v: float(t.law.evaluate(t.phase, 0)[0]) for v, t in s.derived.items() if isinstance(t, CamTie)}
        mech = kin.mech
        self.mech = mech
        self.ground = mech.ground
        self.steps = []
        placed = {mech.ground}
        for g in kin.groups:
            if g.kind in ("geared", "cammed"):
                self.steps.append(("geared", g, _placements(mech, g, placed), order[g.index]))
            elif _newton_group(kin, g):
                self.steps.append(("newton", g, Loops(kin, g), _placements(mech, g, placed)))
            elif g.index in kin.plans:
                plan = kin.plans[g.index]
                ka = next(x for x in plan.a.links if x != plan.l1)
                kc = next(x for x in plan.c.links if x != plan.l2)
                self.steps.append(("dyad", g, plan, ka, kc))
            else:
                j = mech.joint(g.joints[0])
                link = g.links[0]
                known = next(x for x in j.links if x != link)
                self.steps.append(("driver", g, j, link, known))
            placed |= set(g.links)
        self.inputs = {i.joint: i for i in mech.inputs}

    # -- geometry ------------------------------------------------------------------------

    def geometry(self, coordinates=None, directions=None) -> Geometry:
        """The drawn-pose data: the mechanism's own, or with ``coordinates`` (name -> ``(M, 2)``) replaced.

        ``directions`` (P joint -> ``(M,)`` angles, rad) replaces slide
        directions, and ``coordinates["origin:JOINT"]`` a slide's origin.
        Names not given keep the mechanism's values.
        """
        mech = self.mech
        if mech.gears and (coordinates or directions):
            raise InputError(f"{mech.name}: a geared mechanism's ratios come from its drawn pitch points; batches with "
                             "other coordinates or directions are not evaluated (build each mechanism instead)")
        newton = [g.label for kind, g, *_ in self.steps if kind == "newton"]
        if newton and (coordinates or directions):
            raise InputError(f"{mech.name}: the groups {newton} are solved by Newton's method on the mechanism's own "
                             "loop equations; batches with other coordinates or directions are not evaluated (build "
                             "each mechanism and sweep it instead)")
        count = None
        at = {j.name: _c(j.at) for j in mech.joints}
        at.update({p.name: _c(p.at) for p in mech.points})
        at.update({f"origin:{j.name}": _c(j.slide_origin) for j in mech.joints if j.kind == "P"})
        for name, value in (coordinates or {}).items():
            if name not in at:
                raise InputError(f"coordinates: {name!r} is not a joint or point of {mech.name}; "
                                 f"names are {sorted(at)}")
            arr = np.asarray(value, dtype=float)
            if arr.ndim != 2 or arr.shape[1] != 2:
                raise InputError(f"coordinates[{name!r}] must have shape (M, 2), got {arr.shape}")
            if not np.all(np.isfinite(arr)):
                raise InputError(f"coordinates[{name!r}]: every coordinate must be a finite number")
            count = _count(count, arr.shape[0], name)
            at[name] = (arr[:, 0] + 1j * arr[:, 1])[:, None]
        direction, s0 = {}, {}
        for j in mech.joints:
            if j.kind != "P":
                continue
            angle = j.direction
            if directions and j.name in directions:
                angle = np.asarray(directions[j.name], dtype=float)
                count = _count(count, angle.shape[0], j.name)
                angle = angle[:, None]
            direction[j.name] = np.exp(1j * angle) if isinstance(angle, np.ndarray) else complex(math.cos(angle), math.sin(angle))
            s0[j.name] = _dot(at[j.name] - at[f"origin:{j.name}"], direction[j.name])
        for name in directions or {}:
            if name not in direction:
                raise InputError(f"directions: {name!r} is not a P joint of {mech.name}")
        given = dict(mech.link_angles)
        reference = {}
        for link in mech.links:
            joints = [j.name for j in mech.joints_of(link)]
            rule = _reference(at, joints)
            if link == mech.ground:
                reference[link] = 0.0
            elif link in given and np.ndim(rule):  # the given line keeps its place on each link of a batch
                reference[link] = rule + (given[link] - mech.reference_angle_rule(link))
            else:
                reference[link] = given.get(link, rule)
        drawn = {}
        for j, i in self.inputs.items():
            joint = mech.joint(j)
            if joint.kind == "P":
                drawn[j] = s0[j]
            else:
                a, b = joint.links
                if mech.ground in (a, b):
                    a, b = mech.ground, (b if a == mech.ground else a)
                drawn[j] = reference[b] - reference[a]
        geom = Geometry(at, direction, s0, reference, drawn, {}, count)
        for kind, g, plan, *_ in self.steps:
            if kind == "dyad" and plan.kind in SIGNED:
                geom.sign[g.index] = _drawn_sign(plan, geom)
        return geom

    # -- positions -----------------------------------------------------------------------

    def poses(self, geom: Geometry, q, joint: str | None = None, others: dict | None = None,
              signs: dict | None = None, start: dict | None = None) -> Poses:
        """Place every needed link at the input values ``q`` of ``joint`` (default: the first input).

        Other inputs keep their drawn values (or ``others``); ``signs`` (group
        index -> ±1) overrides the drawn assembly modes. Rotations that gear and
        cam pairs read from dyads' links are continuous along the last axis of
        ``q``, from the state ``start`` (variable -> value; default the drawn pose).
        """
        joint = joint or self.mech.inputs[0].joint
        shape = np.broadcast_shapes(np.shape(q), (geom.count, 1) if geom.count is not None else ())
        if self._compiled(q, shape, others, signs):
            return Tape.of(self).poses(geom, q, joint, others, signs, shape)
        inputs = {j: (q if j == joint else (others or {}).get(j, geom.drawn[j])) for j in self.inputs}
        pose = Poses({self.ground: (1.0 + 0j, 0j, 0j)}, {}, inputs, shape)
        variables = self.kin.structure.input_vars
        pose.values = {variables[j]: np.asarray(v, dtype=float) for j, v in inputs.items()}
        start = self.kin.structure.drawn if start is None else start
        for kind, g, *rest in self.steps:
            if kind == "driver":
                self._driver(geom, pose, *rest)
            elif kind == "geared":
                self._geared(geom, pose, g, *rest)
            elif kind == "newton":
                self._newton(geom, pose, g, *rest, joint, start)
            else:
                self._dyad(geom, pose, g, *rest, (signs or {}).get(g.index, geom.sign.get(g.index, 1.0)))
                for how in self.reads.get(g.index, ()):
                    pose.values[how[1]] = _read(pose, how, start)
        return pose

    def _compiled(self, q, shape, others, signs) -> bool:
        """Whether :meth:`poses` takes the compiled loop: one row of inputs, fixed other inputs and assembly modes,
        a program of drivers and dyads, and the route (:func:`~domes.motion.planar.compiled.choose`)."""
        if not (np.ndim(q) == 1 or (np.ndim(q) == 2 and np.shape(q)[0] == 1)) or not shape:
            return False
        if any(np.ndim(v) for v in (others or {}).values()) or any(np.ndim(v) for v in (signs or {}).values()):
            return False
        return choose(math.prod(shape), self.route) and Tape.of(self) is not None

    def _driver(self, geom, pose, j, link, known):
        q = np.asarray(pose.inputs[j.name], dtype=float)
        R, _, _ = pose.links[known]
        X = pose.world(geom, known, j.name)
        if j.kind == "R":
            a, b = j.links
            if self.ground in (a, b):
                b = b if a == self.ground else a
            turn = np.exp(1j * q) * np.exp(-1j * geom.drawn[j.name])  # per input × per mechanism
            pose.links[link] = (R * (turn if link == b else np.conj(turn)), X, geom.at[j.name])
        else:
            pose.slides[j.name] = q
            pose.links[link] = (R, X + _sigma(j, known) * (q - geom.s0[j.name]) * R * geom.direction[j.name],
                                geom.at[j.name])

    def _geared(self, geom, pose, g, placements, order):
        """Place a geared or cammed group's links, each at its joint: first the derived variables (racks' slides,
        linear; followers', by their cams' laws), then the rotations (linear in the variables read so far)."""
        s = self.kin.structure
        values = pose.values
        for v in order:
            expr = s.derived[v]
            if isinstance(expr, CamTie):
                turn = pose.turns[v] = expr.turn.value(values)
                lift = expr.sign * (law_at(expr, turn, 0)[0] - self.lifts[v])
                values[v] = (geom.s0[v[2:]] if v.startswith("s:") else expr.base.value(values)) + lift
            else:
                values[v] = expr.value(values)
        self._place(geom, pose, placements)

    def _place(self, geom, pose, placements):
        """Place links whose variables are known, each at its joint to a link placed before it."""
        s = self.kin.structure
        values = pose.values
        for link, j, known in placements:
            X = pose.world(geom, known, j.name)
            R = np.exp(1j * s.rotations[link].value(values))
            if j.kind == "R":
                pose.links[link] = (R, X, geom.at[j.name])
            else:
                x = values[self.kin.structure.input_vars.get(j.name, f"s:{j.name}")]
                pose.slides[j.name] = x
                u = pose.links[known][0] * geom.direction[j.name]
                pose.links[link] = (R, X + _sigma(j, known) * (x - geom.s0[j.name]) * u, geom.at[j.name])

    def _newton(self, geom, pose, g, loops, placements, joint, start):
        """Solve a group by Newton's method along the last axis of the inputs, continuing from ``start``
        (:func:`~domes.motion.planar.groups.follow`), and place its links."""
        s = self.kin.structure
        q = np.asarray(pose.inputs[joint], dtype=float)
        shape = pose.shape
        n = shape[-1] if shape else 1
        if any(d != 1 for d in shape[:-1]):
            raise InputError(f"{self.mech.name}: {g.label} is solved by Newton's method along one array of inputs; "
                             f"got inputs of shape {shape}")
        path = np.broadcast_to(q, shape).reshape(n)
        ext = np.empty((n, len(loops.external)))
        for k, v in enumerate(loops.external):
            ext[:, k] = np.broadcast_to(pose.values[v], shape).reshape(n)
        q0 = float(start.get(s.input_vars[joint], geom.drawn[joint]))
        t = np.cumsum(np.abs(np.diff(np.concatenate(([q0], path)))))
        drawn = self.kin.structure.drawn
        ext0 = np.array([float(start.get(v, drawn.get(v, 0.0))) for v in loops.external])
        ext0[[k for k, v in enumerate(loops.external) if v == s.input_vars[joint]]] = q0
        x, first = follow(loops, ext, t, np.array([float(start[v]) for v in loops.unknowns]), ext0)
        for k, v in enumerate(loops.unknowns):
            pose.values[v] = x[:, k].reshape(shape) if shape else x[0, k]
        failed = np.arange(n) >= first
        pose.unassembled[g.index] = failed.reshape(shape) if shape else failed[0]
        pose.undetermined[g.index] = np.zeros(shape, dtype=bool) if shape else False
        X = np.concatenate((x, ext), axis=1)
        closure = np.full(n, np.nan)
        closure[:first] = loops.closure(X[:first])
        pose.closure[g.index] = closure.reshape(shape) if shape else closure[0]
        self._place(geom, pose, placements)
        for jn in g.joints:
            if self.mech.joint(jn).kind == "P":
                pose.slides[jn] = pose.values[s.input_vars.get(jn, f"s:{jn}")]

    def _dyad(self, geom, pose, g, plan, ka, kc, sign):
        a, b, c = plan.a, plan.b, plan.c
        at = geom.at
        A, C = pose.world(geom, ka, a.name), pose.world(geom, kc, c.name)
        kind = plan.kind
        bad = undetermined = False
        root = margin = None
        if kind == "RRR":
            l1, l2 = np.abs(at[b.name] - at[a.name]), np.abs(at[b.name] - at[c.name])
            D = C - A
            d = np.abs(D)
            undetermined = d == 0.0
            margin = np.minimum(l1 + l2 - d, d - np.abs(l1 - l2))
            near = np.where(d > l1 + l2, d - (l1 + l2), np.abs(l1 - l2) - d)
            bad = ((d > l1 + l2) | (d < np.abs(l1 - l2))) & (near > ASSEMBLY_SLACK * 64 * np.maximum(np.maximum(d, l1), l2))
            prod = np.maximum((l1 + d + l2) * (l1 + d - l2) * (l1 - d + l2) * (-l1 + d + l2), 0.0)
            rp = np.sqrt(prod)
            with np.errstate(invalid="ignore", divide="ignore"):
                B = A + D * (l1 * l1 + d * d - l2 * l2 + 1j * sign * rp) / (2 * d * d)
                root = rp / (2 * l1 * l2)
            R1, R2 = _unit((B - A) / (at[b.name] - at[a.name])), _unit((B - C) / (at[b.name] - at[c.name]))
            pose.links[plan.l1] = (R1, A, at[a.name])
            pose.links[plan.l2] = (R2, C, at[c.name])
            pose.closure[g.index] = np.abs(C + R2 * (at[b.name] - at[c.name]) - B)
        elif kind == "RPR":
            guide_first = b.links[0] == plan.l1
            (gp, Gp), (sp, Sp) = ((a, A), (c, C)) if guide_first else ((c, C), (a, A))
            u0 = geom.direction[b.name]
            rel0 = at[sp.name] - at[gp.name]
            e, t0 = _cross(u0, rel0), _dot(u0, rel0)
            D = Sp - Gp
            r = np.abs(D)
            diff = (r - np.abs(e)) * (r + np.abs(e))
            margin = r - np.abs(e)
            bad = diff < -ASSEMBLY_SLACK * r * r * 64
            undetermined = r == 0.0
            t = sign * np.sqrt(np.maximum(diff, 0.0))
            with np.errstate(invalid="ignore", divide="ignore"):
                R = D / ((t + 1j * e) * u0)
                root = np.abs(t) / r
            R = _unit(R)
            pose.slides[b.name] = geom.s0[b.name] + t - t0
            pose.links[plan.l1] = (R, A, at[a.name])
            pose.links[plan.l2] = (R, C, at[c.name])
            slid = Gp + R * (at[b.name] - at[gp.name]) + (t - t0) * R * u0
            pose.closure[g.index] = np.abs(Sp + R * (at[b.name] - at[sp.name]) - slid)
        elif kind == "RRP":
            R2 = pose.links[kc][0]
            u = R2 * geom.direction[c.name]
            p0 = C + R2 * (at[b.name] - at[c.name])
            w = p0 - A
            l1 = np.abs(at[b.name] - at[a.name])
            h = np.abs(_cross(u, w))
            diff = (l1 - h) * (l1 + h)
            margin = l1 - h
            bad = diff < -ASSEMBLY_SLACK * np.maximum(l1, h) ** 2 * 64
            rp = np.sqrt(np.maximum(diff, 0.0))
            tau = -_dot(u, w) + sign * rp
            B = p0 + tau * u
            root = rp / l1
            R1 = _unit((B - A) / (at[b.name] - at[a.name]))
            sg = _sigma(c, kc)
            pose.slides[c.name] = geom.s0[c.name] + sg * tau
            pose.links[plan.l1] = (R1, A, at[a.name])
            pose.links[plan.l2] = (R2, C + tau * u, at[c.name])
            pose.closure[g.index] = np.abs(A + R1 * (at[b.name] - at[a.name]) - B)
        elif kind == "PRP":
            ends = []
            for joint, link, known, X in ((a, plan.l1, ka, A), (c, plan.l2, kc, C)):
                Rk = pose.links[known][0]
                ends.append((X + Rk * (at[b.name] - at[joint.name]), Rk * geom.direction[joint.name], Rk))
            (p1, u1, Ra), (p2, u2, Rc) = ends
            det = -_cross(u1, u2)
            undetermined = np.abs(det) <= 1e-15
            safe = np.where(undetermined, 1.0, det)
            rhs = p2 - p1
            t1, t2 = _cross(rhs, -u2) / safe, _cross(u1, rhs) / safe
            pose.slides[a.name] = geom.s0[a.name] + _sigma(a, ka) * t1
            pose.slides[c.name] = geom.s0[c.name] + _sigma(c, kc) * t2
            pose.links[plan.l1] = (Ra, A + t1 * u1, at[a.name])
            pose.links[plan.l2] = (Rc, C + t2 * u2, at[c.name])
            pose.closure[g.index] = np.abs(p1 + t1 * u1 - p2 - t2 * u2)
        else:  # RPP: l1 pinned at a, b the inner P, c the outer P
            Rk = pose.links[kc][0]
            X1 = A + Rk * (at[b.name] - at[a.name])
            u_in = Rk * geom.direction[b.name]
            u_out = Rk * geom.direction[c.name]
            rhs = Rk * (at[b.name] - at[c.name]) + C - X1
            det = -_cross(u_in, u_out)
            undetermined = np.abs(det) <= 1e-15
            safe = np.where(undetermined, 1.0, det)
            t_in, t_out = _cross(rhs, -u_out) / safe, _cross(u_in, rhs) / safe
            pose.slides[b.name] = geom.s0[b.name] + (1.0 if b.links[0] == plan.l1 else -1.0) * t_in
            pose.slides[c.name] = geom.s0[c.name] + _sigma(c, kc) * t_out
            pose.links[plan.l1] = (Rk, A, at[a.name])
            pose.links[plan.l2] = (Rk, C + t_out * u_out, at[c.name])
            pose.closure[g.index] = np.abs(X1 + t_in * u_in - (C + Rk * (at[b.name] - at[c.name]) + t_out * u_out))
        pose.unassembled[g.index] = np.asarray(bad)
        pose.undetermined[g.index] = np.asarray(undetermined) & ~np.asarray(bad)
        if root is not None:
            pose.root[g.index] = root
            pose.margin[g.index] = margin

    # -- velocities and accelerations -----------------------------------------------------------

    def motion(self, geom: Geometry, pose: Poses, order: int = 1, speeds: dict | None = None,
               accelerations: dict | None = None) -> list[Motion]:
        """Rates (``order`` 1) and accelerations (``order`` 2) of every link and slide: ``[velocity, acceleration]``.

        Input rates are the mechanism's (``Input.speed``, ``Input.acceleration``) unless given.
        """
        levels: list[Motion] = []
        given = [{j: (speeds or {}).get(j, i.speed) for j, i in self.inputs.items()},
                 {j: (accelerations or {}).get(j, i.acceleration) for j, i in self.inputs.items()}]
        variables = self.kin.structure.input_vars
        for level in range(1, order + 1):
            m = Motion({self.ground: 0.0}, {self.ground: 0j}, {},
                       {variables[j]: r for j, r in given[level - 1].items()})
            for kind, g, *rest in self.steps:
                if kind == "driver":
                    self._driver_motion(geom, pose, levels, m, given[level - 1], *rest)
                elif kind == "geared":
                    self._geared_motion(geom, pose, levels, m, *rest)
                elif kind == "newton":
                    self._newton_motion(geom, pose, levels, m, g, *rest)
                else:
                    self._dyad_motion(geom, pose, levels, m, *rest)
                    for how in self.reads.get(g.index, ()):
                        m.rates[how[1]] = _read_rate(m, how)
            levels.append(m)
        return levels

    def _driver_motion(self, geom, pose, levels, m, given, j, link, known):
        X = pose.world(geom, known, j.name)
        rate = given[j.name]
        V = _point(pose, levels, m.w[known], m.V[known], known, X)
        if j.kind == "R":
            a, b = j.links
            if self.ground in (a, b):
                b = b if a == self.ground else a
            m.w[link] = m.w[known] + (rate if link == b else -rate)
            m.V[link] = V
        else:
            m.slide[j.name] = rate
            m.w[link] = m.w[known]
            m.V[link] = V + _sigma(j, known) * _relative(geom, pose, levels, j, known, m.w[known], rate)

    def _geared_motion(self, geom, pose, levels, m, placements, order):
        s = self.kin.structure
        rates = m.rates
        for v in order:
            expr = s.derived[v]
            if isinstance(expr, CamTie):
                if v not in pose.laws:
                    pose.laws[v] = law_at(expr, pose.turns[v], 2)
                if levels:  # the acceleration: L''·ẋ² + L'·ẍ, ẋ from the velocities
                    _, d1, d2 = pose.laws[v]
                    xd = expr.turn.rate(levels[0].rates)
                    rates[v] = expr.base.rate(rates) + expr.sign * (d2 * xd * xd + d1 * expr.turn.rate(rates))
                else:
                    rates[v] = cam_rates(expr, pose.values, rates, law=pose.laws[v])[0]
            else:
                rates[v] = expr.rate(rates)
        self._place_motion(geom, pose, levels, m, placements)

    def _place_motion(self, geom, pose, levels, m, placements):
        """Rates (or accelerations) of links placed by :meth:`_place`, their variables' being known."""
        s = self.kin.structure
        for link, j, known in placements:
            X = pose.world(geom, known, j.name)
            V = _point(pose, levels, m.w[known], m.V[known], known, X)
            m.w[link] = s.rotations[link].rate(m.rates)
            if j.kind == "P":
                rate = m.rates[s.input_vars.get(j.name, f"s:{j.name}")]
                m.slide[j.name] = rate
                V = V + _sigma(j, known) * _relative(geom, pose, levels, j, known, m.w[known], rate)
            m.V[link] = V

    def _newton_motion(self, geom, pose, levels, m, g, loops, placements):
        """A Newton group's rates from its loop equations: ``J·ẋ = −B·ė`` (``ė`` the rates of the variables it
        reads) and ``J·ẍ = −B·ë − (the loops' second derivative at ẍ = 0)``, solved as a stack."""
        shape = pose.shape
        n = shape[-1] if shape else 1
        U = len(loops.unknowns)
        names = loops.unknowns + loops.external

        def column(store, v):
            return np.broadcast_to(store[v], shape).reshape(n)

        X = np.stack([column(pose.values, v) for v in names], axis=1)
        _, J = loops.system(X)
        given = np.stack([column(m.rates, v) for v in loops.external], axis=1)
        rhs = -np.einsum("nrv,nv->nr", J[:, :, U:], given)
        if levels:  # the loops' second derivative with the unknowns' accelerations at zero
            rhs -= loops.second(X, np.stack([column(levels[0].rates, v) for v in names], axis=1))
        ok = np.all(np.isfinite(J[:, :, :U]), axis=(1, 2))
        safe = np.where(ok[:, None, None], J[:, :, :U], np.eye(2 * loops.loops, U))
        sol = solve_stack(safe, np.where(ok[:, None], rhs, 0.0))
        sol[~ok] = np.nan
        for k, v in enumerate(loops.unknowns):
            m.rates[v] = sol[:, k].reshape(shape) if shape else sol[0, k]
        self._place_motion(geom, pose, levels, m, placements)
        variables = self.kin.structure.input_vars
        for jn in g.joints:
            if self.mech.joint(jn).kind == "P":
                m.slide[jn] = m.rates[variables.get(jn, f"s:{jn}")]

    def _dyad_motion(self, geom, pose, levels, m, plan, ka, kc):
        """Solve the dyad's two unknown rates from the constraint at its inner joint (linear in them)."""
        def trial(x):
            return self._dyad_rates(geom, pose, levels, m, plan, ka, kc, x)

        f0 = trial((0.0, 0.0))[-1]
        c1 = trial((1.0, 0.0))[-1] - f0
        c2 = trial((0.0, 1.0))[-1] - f0
        det = _cross(c1, c2)
        with np.errstate(invalid="ignore", divide="ignore"):
            x = (_cross(-f0, c2) / det, _cross(c1, -f0) / det)
        w1, V1, w2, V2, slides, _ = trial(x)
        m.w[plan.l1], m.V[plan.l1], m.w[plan.l2], m.V[plan.l2] = w1, V1, w2, V2
        m.slide.update(slides)

    def _dyad_rates(self, geom, pose, levels, m, plan, ka, kc, x):
        """Rates of the dyad's links for trial unknowns ``x`` and the constraint residual at the inner joint."""
        a, b, c = plan.a, plan.b, plan.c
        free = iter(x)
        if b.kind == "R":
            w1 = next(free) if a.kind == "R" else m.w[ka]
            w2 = next(free) if c.kind == "R" else m.w[kc]
        else:
            w1 = w2 = m.w[ka] if a.kind == "P" else m.w[kc] if c.kind == "P" else next(free)
        slides = {j.name: next(free) for j in (a, b, c) if j.kind == "P"}
        ends = []
        for joint, link, known, w in ((a, plan.l1, ka, w1), (c, plan.l2, kc, w2)):
            V = _point(pose, levels, m.w[known], m.V[known], known, pose.world(geom, known, joint.name))
            if joint.kind == "P":
                V = V + _sigma(joint, known) * _relative(geom, pose, levels, joint, known, m.w[known], slides[joint.name])
            ends.append((w, V))
        (w1, V1), (w2, V2) = ends
        rates = {plan.l1: (w1, V1), plan.l2: (w2, V2)}

        def at_b(link):
            return _point(pose, levels, *rates[link], link, pose.world(geom, link, b.name))

        if b.kind == "R":
            residual = at_b(plan.l1) - at_b(plan.l2)
        else:
            guide, slider = b.links
            residual = at_b(slider) - at_b(guide) - _relative(geom, pose, levels, b, guide, rates[guide][0],
                                                              slides[b.name])
        return w1, V1, w2, V2, slides, residual

    # -- outputs -------------------------------------------------------------------------

    def outputs(self, geom: Geometry, pose: Poses, levels: list[Motion] = (), unwrap: bool = True) -> dict:
        """The query's output columns (as :meth:`~domes.motion.planar.query.Kinematics.output_values`).

        Angles are continuous along the last axis when ``unwrap``.
        """
        out = {}
        for o in self.kin.outputs:
            if o.kind == "angle":
                R = pose.links[o.target][0]
                angle = geom.reference[o.target] + np.angle(R)
                comps = [[np.unwrap(angle, axis=-1) if unwrap and np.ndim(angle) else angle]]
                comps += [[lv.w[o.target]] for lv in levels]
            elif o.kind == "slide":
                comps = [[pose.slides[o.target]]] + [[lv.slide[o.target]] for lv in levels]
            else:
                link = self.mech.point(o.target)[0]
                X = pose.world(geom, link, o.target)
                comps = [[X.real, X.imag]]
                for k, lv in enumerate(levels):
                    v = _point(pose, levels[:k], lv.w[link], lv.V[link], link, X)
                    comps.append([v.real, v.imag])
            for k, comp in enumerate(comps):
                for name, val in zip(o.columns(), comp):
                    out[name + "'" * k] = np.broadcast_to(val, pose.shape)
        return out


def _point(pose, levels, w, V, link, X):
    """Velocity (``levels`` empty) or acceleration (``levels`` the velocities) of the world point ``X`` of ``link``.

    ``w, V`` are the link's angular rate and its anchor's rate at the level being built.
    """
    W = pose.links[link][1]
    if not levels:
        return V + 1j * w * (X - W)
    omega = levels[0].w[link]
    return V + (1j * w - omega * omega) * (X - W)


def _relative(geom, pose, levels, j, guide, w, rate):
    """Rate (or acceleration) of the slider's point over the guide's point at P joint ``j``.

    ``guide`` is any link turning with the joint's guide (their rotations are
    equal), ``w`` its angular rate at this level, ``rate`` the slide's.
    """
    u = pose.links[guide][0] * geom.direction[j.name]
    ds = pose.slides[j.name] - geom.s0[j.name]
    if not levels:
        return rate * u + ds * 1j * w * u
    omega = levels[0].w[guide]
    return rate * u + 2 * levels[0].slide[j.name] * 1j * omega * u + ds * (1j * w - omega * omega) * u


def _read(pose, how, start):
    """A variable a gear or cam pair reads from a dyad: a slide, or a rotation from its link's (continued)."""
    if how[0] == "slide":
        return pose.slides[how[2]]
    _, var, link, coeff, rest = how
    return _continued((np.angle(pose.links[link][0]) - rest.value(pose.values)) / coeff, start.get(var, 0.0))


def _read_rate(m, how):
    """The rate (or acceleration) at one level of a variable read by :func:`_read`."""
    if how[0] == "slide":
        return m.slide[how[2]]
    _, var, link, coeff, rest = how
    return (m.w[link] - rest.rate(m.rates)) / coeff


def _continued(angle, start: float):
    """Angles known to a whole turn made continuous along the last axis, the first next to ``start``.

    Entries that are not finite stay NaN and do not break the path.

    >>> [round(float(x), 6) for x in _continued(np.array([3.0, -3.0, np.nan, 3.0]), 0.0)]
    [3.0, 3.283185, nan, 3.0]
    """
    angle = np.asarray(angle, dtype=float)
    if angle.ndim == 0:
        return start + math.remainder(float(angle) - start, 2 * math.pi)
    head = np.broadcast_to(np.asarray(start, dtype=float), angle.shape[:-1] + (1,))
    path = np.concatenate((head, angle), axis=-1)
    finite = np.isfinite(path)
    last = np.maximum.accumulate(np.where(finite, np.arange(path.shape[-1]), 0), axis=-1)
    out = np.unwrap(np.take_along_axis(path, last, axis=-1), axis=-1)[..., 1:]
    return np.where(finite[..., 1:], out, np.nan)


def _placements(mech, g, known) -> list:
    """``(link, joint, known link)`` for each link of a geared group, each joined to one placed before it."""
    done, out = set(known), []
    todo = list(g.links)
    while todo:
        for link in todo:
            j = next((j for j in mech.joints_of(link) if j.name in g.joints and
                      (j.links[0] if j.links[1] == link else j.links[1]) in done), None)
            if j is not None:
                out.append((link, j, j.links[0] if j.links[1] == link else j.links[1]))
                done.add(link)
                todo.remove(link)
                break
        else:
            raise InputError(f"{mech.name}: the geared links {todo} are not joined to placed links")
    return out


def _sigma(j, known) -> float:
    """+1 when the known link is the P joint's guide (the other link slides on it), −1 when it is the slider."""
    return 1.0 if j.links[0] == known else -1.0


def _count(count, m, name):
    if count is not None and m != count:
        raise InputError(f"{name!r} has {m} rows, other entries {count}: every array must describe the same mechanisms")
    return m


def _reference(at, joints):
    """The reference angle rule of :meth:`~domes.model.mechanism.Mechanism.reference_angle` on arrays."""
    first = at[joints[0]]
    angle = 0.0
    for name in reversed(joints[1:]):
        d = at[name] - first
        angle = np.where(d != 0, np.angle(d), angle) if np.ndim(d) else (float(np.angle(d)) if d != 0 else angle)
    return angle


def _drawn_sign(plan, geom):
    """The assembly mode of a signed dyad in the drawn pose (as :meth:`~domes.motion.planar.dyads.DyadPlan.of`)."""
    a, b, c = plan.a, plan.b, plan.c
    at = geom.at
    if plan.kind == "RRR":
        value = _cross(at[c.name] - at[a.name], at[b.name] - at[a.name])
    elif plan.kind == "RPR":
        gp, sp = (a, c) if b.links[0] == plan.l1 else (c, a)
        value = _dot(geom.direction[b.name], at[sp.name] - at[gp.name])
    else:
        value = _dot(geom.direction[c.name], at[b.name] - at[a.name])
    return np.sign(value) if np.ndim(value) else math.copysign(1.0, value) if value else 0.0
