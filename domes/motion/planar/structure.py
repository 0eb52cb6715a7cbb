"""Variables, loop equations and the Assur-group decomposition of a mechanism.

Every link ``k`` has a rotation ``Δ_k`` from the drawn pose. Links joined by
a P joint turn together, and a driven R joint ties its two links' rotations
through the input, so each link's rotation is a linear expression
``Δ_k = Σ c·v + const`` in the *rotation variables* (one per class of links
turning together, named ``rot:<first link of the class>``) and the inputs
(``q:<joint>``). Each undriven P joint has a slide variable ``s:<joint>``.
A gear pair (:mod:`domes.model.gears`) is one linear equation among these
(Willis' formula relative to its carrier): it eliminates a rotation variable
from every expression, or makes a rack's slide a *derived* variable, a
linear expression in the others. A cam pair (:mod:`domes.model.cams`) makes
its follower's variable (slide or rotation) a derived one too, through its
law (:class:`CamTie`).

A *group* is a set of moving links whose variables are fixed once the links
it is jointed to are known: an Assur group, or a driver (a link with a
driven joint to a known link). Its loop equations (seed 000, eq. 15) sum
link units (:mod:`domes.motion.planar.units`) around a cycle basis of the
group's links plus the known links contracted to one node.

>>> from domes.motion.planar.examples import four_bar
>>> s = Structure.of(four_bar())
>>> [g.kind for g in s.groups], s.groups[1].unknowns
(['driver', 'RRR'], ('rot:coupler', 'rot:rocker'))
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass
from functools import cached_property
from itertools import combinations

from domes.errors import InputError
from domes.model.cams import CamProfile
from domes.model.mechanism import Joint, Mechanism
from domes.motion import camcontact  # noqa: F401  (a cam pair given by its profile is followed by its contact)
from domes.motion.planar.units import rp2_unit, rr_unit

KNOWN = "<known>"


@dataclass(frozen=True)
class Rotation:
    """``Δ = Σ coeff·var + const`` (rad, from the drawn pose)."""

    terms: tuple[tuple[str, float], ...]
    const: float = 0.0

    def value(self, values) -> float:
        return sum(c * values[v] for v, c in self.terms) + self.const

    def rate(self, rates) -> float:
        return sum(c * rates[v] for v, c in self.terms)

    def shifted(self, terms: dict, const: float) -> "Rotation":
        out = dict(self.terms)
        for v, c in terms.items():
            out[v] = out.get(v, 0.0) + c
        return Rotation(tuple((v, c) for v, c in sorted(out.items()) if c), self.const + const)


@dataclass(frozen=True)
class Segment:
    """One term of a loop sum: a link's vector between two of its points, or a slide.

    ``kind == "link"``: ``l·u(Δ + α)``. ``kind == "slide"``:
    ``sign·(s − s0)·u(Δ + ψ)`` along a P joint, ``Δ`` the guide's rotation.
    """

    kind: str
    rotation: Rotation
    length: float = 0.0
    alpha: float = 0.0
    slide: str = ""
    s0: float = 0.0
    sign: float = 1.0


def link_segment(rotation: Rotation, p, q) -> Segment:
    dx, dy = q[0] - p[0], q[1] - p[1]
    return Segment("link", rotation, math.hypot(dx, dy), math.atan2(dy, dx))


def evaluate(segments, values, rates=None, lib=math):
    """Sum the link units of ``segments``: ``(A, cols, dcols)``.

    ``cols[v]`` is ``∂A/∂v`` and ``dcols[v]`` its time derivative (only when
    ``rates`` is given), each a 2-list; ``A`` is a 2-list.
    """
    A = [0 * lib.cos(0), 0 * lib.cos(0)]
    cols: dict[str, list] = {}
    dcols: dict[str, list] = {}

    def add(store, v, c, col):
        acc = store.setdefault(v, [0, 0])
        acc[0] += c * col[0]
        acc[1] += c * col[1]

    for seg in segments:
        rot = seg.rotation
        delta = sum(c * values[v] for v, c in rot.terms) + rot.const
        ddelta = sum(c * rates[v] for v, c in rot.terms) if rates is not None else 0.0
        if seg.kind == "link":
            a, J, Jd = rr_unit(seg.length, seg.alpha, delta, ddelta, lib)
            A[0] += a[0]
            A[1] += a[1]
            for v, c in rot.terms:
                add(cols, v, c, J[0])
                if rates is not None:
                    add(dcols, v, c, Jd[0])
        else:
            sd = rates[seg.slide] if rates is not None else 0.0
            a, J, Jd = rp2_unit(0.0, delta + seg.alpha, values[seg.slide] - seg.s0, ddelta, sd, lib)
            k = seg.sign
            A[0] += k * a[0]
            A[1] += k * a[1]
            for v, c in rot.terms:
                add(cols, v, k * c, J[0])
                if rates is not None:
                    add(dcols, v, k * c, Jd[0])
            add(cols, seg.slide, k, J[1])
            if rates is not None:
                add(dcols, seg.slide, k, Jd[1])
    return A, cols, dcols


@dataclass(frozen=True)
class Group:
    """An Assur group (or a driver) with its unknowns and loop equations."""

    index: int
    links: tuple[str, ...]
    joints: tuple[str, ...]
    kind: str
    unknowns: tuple[str, ...]
    loops: tuple[tuple[Segment, ...], ...]
    parents: tuple[int, ...]

    @property
    def equations(self) -> int:
        return 2 * len(self.loops)

    @property
    def label(self) -> str:
        return f"{self.kind} group {{{', '.join(self.links)}}}"


def _group_kind(mech: Mechanism, links, joints, driven) -> str:
    if len(links) == 1:
        return "driver"
    if len(links) == 2 and len(joints) == 3 and not (set(joints) & driven):
        inner = next(j for j in joints if set(mech.joint(j).links) == set(links))
        outer = [j for j in joints if j != inner]
        pattern = [mech.joint(outer[0]).kind, mech.joint(inner).kind, mech.joint(outer[1]).kind]
        if pattern[0] == "P" and pattern[2] == "R":
            pattern.reverse()
        return "".join(pattern)
    return f"class-{_class_of(mech, links, joints)}" if not (set(joints) & driven) else f"{len(links)}-link"


def _overconstrained(mech: Mechanism, links, joints, constraints: int, driven) -> InputError:
    """The error for links held by more constraints than they have freedoms once the known links are placed."""
    inputs = [j.joint for j in mech.inputs]
    what = (f"the inputs {', '.join(inputs)} are not independent: together they fix links {list(links)}, which then "
            f"have {constraints} constraints for {3 * len(links)} freedoms{_loop_of(mech, links, joints)}, and leave "
            "another loop free (Yan ch. 3, the active pairs of Fig. 3-19: each input must drive a loop of its own); "
            "choose inputs in different loops"
            if len(inputs) > 1 and 3 * (len(mech.links) - 1) - 2 * len(mech.joints) == len(inputs) else
            f"links {list(links)} have {constraints} constraints for {3 * len(links)} freedoms: redundant constraints")
    return InputError(f"{mech.name}: {what}")


def _loop_of(mech: Mechanism, links, joints) -> str:
    """`` in the loop A–B–C (joints ...)``: the shortest loop through ``links`` of the joints that over-constrain
    them and those among the links already placed ('' when there is none)."""
    import networkx as nx

    near = {x for j in joints for x in j.links} | {mech.ground}
    g = nx.Graph()
    for j in mech.joints:
        if j in joints or set(j.links) <= near:
            g.add_edge(*j.links, joint=j.name)
    loops = [c for c in nx.cycle_basis(g) if set(links) <= set(c)]
    if not loops:
        return ""
    loop = min(loops, key=len)
    if mech.ground in loop:                                   # read from the frame
        k = loop.index(mech.ground)
        loop = loop[k:] + loop[:k]
    names = [g.edges[a, b]["joint"] for a, b in zip(loop, loop[1:] + loop[:1])]
    return f" in the loop {'–'.join(loop)} (joints {', '.join(names)})"


def _class_of(mech: Mechanism, links, joints) -> str:
    """Assur class: the largest closed polygon formed by the group's own links (II for a dyad)."""
    inner = [mech.joint(j).links for j in joints if set(mech.joint(j).links) <= set(links)]
    degree = {x: sum(x in pair for pair in inner) for x in links}
    biggest = max(degree.values()) if degree else 0
    # Triads (class III) have a ternary link joined to two binaries; class IV a closed quadrilateral.
    if len(links) == 4 and len(inner) == 4 and biggest == 2:
        return "IV"
    if len(links) == 4 and biggest == 3:
        return "III"
    return {2: "II", 4: "III"}.get(len(links), "higher")


class Structure:
    """Rotation classes, variables and the Assur decomposition of a mechanism."""

    def __init__(self, mech: Mechanism, groups: tuple[Group, ...], rotations: dict, inputs: dict, drawn: dict,
                 derived: dict | None = None):
        self.mech = mech
        self.groups = groups
        self.rotations = rotations          # link -> Rotation
        self.input_vars = inputs            # joint name -> variable name
        self.drawn = drawn                  # variable -> value in the drawn pose
        self.derived = derived or {}        # variable fixed by a rack or a cam -> Rotation or CamTie

    def derived_of(self, g: Group) -> list[str]:
        """The derived variables of ``g`` (its joints' slides, its links' rotations), set once ``g``'s are known."""
        names = [f"s:{j}" for j in g.joints] + [f"rot:{x}" for x in g.links]
        return [v for v in names if v in self.derived]

    # -- construction ----------------------------------------------------------------

    @classmethod
    def of(cls, mech: Mechanism, method: str = "assur") -> "Structure":
        """Decompose ``mech`` into groups (``method="assur"``) or one group of all moving links (``"newton"``)."""
        if method not in ("assur", "newton"):
            raise InputError(f"method must be 'assur' or 'newton', got {method!r}")
        rotations, input_vars, drawn = _rotation_classes(mech)
        meshes = mech.meshes()
        derived = _mesh_gears(mech, meshes, rotations, input_vars, drawn)
        contacts = [c.contact(mech) for c in mech.cams]
        derived.update(_cam_ties(mech, contacts, rotations, input_vars, drawn))
        meshes = meshes + [_Higher(c.cam, c.follower, c.carrier) for c in contacts]
        driven = set(input_vars)
        known = {mech.ground}
        owner: dict[str, int] = {}
        groups: list[Group] = []
        remaining = [x for x in mech.links if x != mech.ground]
        while remaining:
            found = None
            sizes = range(1, len(remaining) + 1) if method == "assur" else [len(remaining)]
            for k in sizes:
                for cand in combinations(remaining, k):
                    s = set(cand)
                    js = [j for j in mech.joints if set(j.links) & s and set(j.links) <= s | known]
                    constraints = sum(3 if j.name in driven else 2 for j in js)
                    constraints += sum(1 for m in meshes if {m.a, m.b, m.carrier} <= s | known
                                       and {m.a, m.b, m.carrier} & s)
                    if constraints > 3 * k and method == "assur":
                        raise _overconstrained(mech, cand, js, constraints, driven)
                    if found is None and constraints == 3 * k and _connected(cand, js, known):
                        found = (cand, js)
                if found:
                    break
            if not found:
                raise InputError(f"{mech.name}: links {remaining} do not form Assur groups over the known links "
                                 f"{sorted(known)}: the chain is not driven by its inputs (or has redundant constraints)")
            cand, js = found
            index = len(groups)
            seg_vars = set()
            for x in cand:
                seg_vars |= {v for v, _ in rotations[x].terms}
            seg_vars |= {_slide_var(j, input_vars) for j in js if j.kind == "P"}
            for v in [v for v in seg_vars if v in derived]:
                seg_vars |= {w for w, _ in derived[v].terms} - {v}
                inner = {w for w, _ in derived[v].terms} & ({w for x in cand for w, _ in rotations[x].terms}
                                                            - set(derived) - set(owner))
                if inner - {w for w in inner if w.startswith("q:")}:
                    raise InputError(f"{mech.name}: {v[2:]!r} is driven by a gear or cam pair through the unknowns "
                                     f"{sorted(inner)} of the group {list(cand)} it belongs to; solve with the "
                                     "method 'assur', which places it after them")
            unknowns = tuple(sorted(v for v in seg_vars if not v.startswith("q:") and v not in owner
                                    and v not in derived))
            for v in unknowns:
                owner[v] = index
            parents = {_owner_of_link(groups, other) for j in js for other in j.links if other in known} - {None}
            parents |= {owner[v] for v in seg_vars if v in owner and owner[v] != index}
            ancestors = set(parents)
            for p in parents:
                ancestors |= _ancestors(groups, p)
            allowed = {mech.ground} | {x for g in ancestors for x in groups[g].links}
            loops = _group_loops(mech, cand, js, allowed, rotations, input_vars)
            kind = _group_kind(mech, cand, [j.name for j in js], driven)
            if not unknowns and not {j.name for j in js} & driven and any({m.a, m.b} & set(cand) for m in meshes):
                ties = [derived.get(v) for v in [f"rot:{x}" for x in cand] + [f"s:{j.name}" for j in js]]
                kind = "cammed" if any(isinstance(t, CamTie) for t in ties) else "geared"
            if len(unknowns) != 2 * len(loops):
                raise InputError(f"{mech.name}: links {list(cand)} ({kind}) have {len(unknowns)} unknowns for "
                                 f"{2 * len(loops)} loop equations: not a determinate group (e.g. three P joints)")
            groups.append(Group(index, tuple(cand), tuple(j.name for j in js), kind, unknowns, tuple(loops),
                                tuple(sorted(parents))))
            known |= set(cand)
            remaining = [x for x in remaining if x not in cand]
        return cls(mech, tuple(groups), rotations, input_vars, drawn, derived)

    # -- queries -----------------------------------------------------------------------

    def group_of(self, link: str) -> int | None:
        return _owner_of_link(self.groups, link)

    def needed(self, links) -> list[int]:
        """Indices of the groups that fix ``links`` (with all groups they depend on), in solving order."""
        need = set()
        for x in links:
            g = self.group_of(x)
            if g is not None:
                need |= {g} | _ancestors(self.groups, g)
        return sorted(need)

    def point_path(self, link: str, at, allowed) -> tuple[Segment, ...]:
        """Segments summing to the world position of the drawn point ``at`` of ``link``."""
        mech = self.mech
        prev = _tree(mech, mech.ground, allowed)
        if link != mech.ground and link not in prev:
            raise InputError(f"{mech.name}: link {link!r} is not connected to the ground through solved links")
        chain = []
        x = link
        while x != mech.ground:
            j, parent = prev[x]
            chain.append((parent, j, x))
            x = parent
        chain.reverse()
        segs = []
        here = (0.0, 0.0)
        for parent, j, child in chain:
            segs.append(link_segment(self.rotations[parent], here, j.at))
            if j.kind == "P":
                segs.append(_slide_segment(j, parent, self.rotations, self.input_vars))
            here = j.at
        segs.append(link_segment(self.rotations[link], here, at))
        return tuple(segs)


def _slide_var(j: Joint, input_vars) -> str:
    return input_vars.get(j.name, f"s:{j.name}")


def _slide_segment(j: Joint, entered_from: str, rotations, input_vars) -> Segment:
    guide = j.links[0]
    return Segment("slide", rotations[guide], alpha=j.direction, slide=_slide_var(j, input_vars), s0=j.s0,
                   sign=1.0 if entered_from == guide else -1.0)


def _rotation_classes(mech: Mechanism):
    """Rotation expressions of the links, input variables and drawn-pose values."""
    input_vars = {i.joint: f"q:{i.joint}" for i in mech.inputs}
    drawn: dict[str, float] = {}
    ref = {x: (0.0 if x == mech.ground else mech.reference_angle(x)) for x in mech.links}
    ties: dict[str, list] = {x: [] for x in mech.links}
    for j in mech.joints:
        a, b = j.links
        if j.kind == "P":
            terms, const = {}, 0.0
        elif j.name in input_vars:
            q = input_vars[j.name]
            if mech.ground in (a, b):
                other = b if a == mech.ground else a
                a, b = mech.ground, other
            # q = angle(b) − angle(a)  ⇒  Δ_b = Δ_a + q − (ref_b − ref_a)
            terms, const = {q: 1.0}, -(ref[b] - ref[a])
            drawn[q] = ref[b] - ref[a]
        else:
            continue
        ties[a].append((b, terms, const))
        ties[b].append((a, {v: -c for v, c in terms.items()}, -const))
    for i in mech.inputs:
        j = mech.joint(i.joint)
        if j.kind == "P":
            drawn[input_vars[j.name]] = j.s0
    for j in mech.joints:
        if j.kind == "P" and j.name not in input_vars:
            drawn[f"s:{j.name}"] = j.s0
    rotations: dict[str, Rotation] = {}
    order = [mech.ground] + [x for x in mech.links if x != mech.ground]
    for root in order:
        if root in rotations:
            continue
        rotations[root] = Rotation(()) if root == mech.ground else Rotation(((f"rot:{root}", 1.0),))
        if root != mech.ground:
            drawn[f"rot:{root}"] = 0.0
        queue = deque([root])
        while queue:
            x = queue.popleft()
            for y, terms, const in ties[x]:
                expr = rotations[x].shifted(terms, const)
                if y not in rotations:
                    rotations[y] = expr
                    queue.append(y)
                elif dict(rotations[y].terms) != dict(expr.terms) or abs(rotations[y].const - expr.const) > 1e-12:
                    raise InputError(f"{mech.name}: link {y!r} is tied to turn with {x!r} in two inconsistent ways "
                                     "(a closed circuit of P joints and driven joints)")
    return rotations, input_vars, drawn


def _mesh_gears(mech: Mechanism, meshes, rotations: dict, input_vars: dict, drawn: dict) -> dict:
    """Eliminate one variable per gear pair (Willis' formula); rack slides fixed this way are returned as derived.

    Each pair's equation, ``Δ_b − Δ_c + s·k·(Δ_a − Δ_c) = 0`` (gears) or
    ``x − x0 − σ·m·(Δ_a − Δ_c) = 0`` (a rack's slide ``x``), is solved for
    the driven gear's rotation variable (``b``, then ``a``), else the rack's
    undriven slide, else the carrier's rotation; a pair that ties only
    inputs is refused.
    """
    derived: dict[str, Rotation] = {}
    for m in meshes:
        ea, ec = rotations[m.a], rotations[m.carrier]
        eq = _combine([(1.0, ea), (-1.0, ec)])
        if m.kind == "rack":
            x = input_vars.get(m.slide, f"s:{m.slide}")
            ex = derived.get(x, Rotation(((x, 1.0),)))
            eq = _combine([(1.0, ex), (-m.sign * m.ratio, eq)], -drawn[x])
        else:
            eq = _combine([(1.0, rotations[m.b]), (-1.0, ec), (m.sign * m.ratio, eq)])
        coeffs = dict(eq.terms)
        sides = (m.a,) if m.kind == "rack" else (m.b, m.a)
        order = [v for x in sides for v, _ in rotations[x].terms if v.startswith("rot:")]
        order += [v for v in coeffs if v.startswith("s:")]
        order += [v for v, _ in rotations[m.carrier].terms if v.startswith("rot:")]
        var = next((v for v in order if abs(coeffs.get(v, 0.0)) > 1e-12), None)
        where = f"{mech.name}: gear pair {m.pair.name!r}"
        if var is None:
            tied = sorted(v for v in coeffs if abs(coeffs[v]) > 1e-12)
            if tied:
                raise InputError(f"{where} ties the inputs {[v[2:] for v in tied]} to each other: they are not "
                                 "independent; drive fewer joints")
            raise InputError(f"{where} repeats what the other pairs and joints already fix (a redundant gear pair)")
        c = coeffs[var]
        solution = Rotation(tuple((v, -k / c) for v, k in eq.terms if v != var), -eq.const / c)

        def put(expr):
            k = dict(expr.terms).get(var)
            if k is None:
                return expr
            rest = Rotation(tuple((v, w) for v, w in expr.terms if v != var), expr.const)
            return _combine([(1.0, rest), (k, solution)])

        for x in list(rotations):
            rotations[x] = put(rotations[x])
        for v in list(derived):
            derived[v] = put(derived[v])
        if var.startswith("s:"):
            derived[var] = solution
        else:
            drawn.pop(var, None)
    return derived


@dataclass(frozen=True)
class _Higher:
    """A higher pair as the group search counts it: one constraint among ``a``, ``b`` and their carrier."""

    a: str
    b: str
    carrier: str


@dataclass(frozen=True)
class CamTie:
    """A follower's variable driven by its cam: ``base + sign·(L(φ + x) − L(φ))``, ``x`` the cam's turn on the
    carrier and ``base`` the carrier's rotation (oscillating follower) or the drawn slide (translating).

    Like :class:`Rotation` it has ``terms`` (what it depends on) and a ``value``; its rates are not linear:
    :meth:`motion` gives its rate and acceleration from the variables' own.
    """

    law: object
    phase: float
    turn: Rotation
    base: Rotation
    sign: float

    @property
    def terms(self) -> tuple[tuple[str, float], ...]:
        return tuple(dict(self.turn.terms + self.base.terms).items())

    @cached_property
    def _s0(self) -> float:
        """The law at the drawn pose (evaluated once)."""
        return float(self.law.evaluate(self.phase, 0)[0])

    def value(self, values) -> float:
        here = float(self.law.evaluate(self.phase + self.turn.value(values), 0)[0])
        return self.base.value(values) + self.sign * (here - self._s0)

    def motion(self, values, rates, accels=None) -> tuple[float, float | None]:
        """The rate and (with ``accels``) the acceleration: ``L'·ẋ`` and ``L''·ẋ² + L'·ẍ``, plus the base's."""
        _, d1, d2 = (float(v) for v in self.law.evaluate(self.phase + self.turn.value(values), 2))
        xd = self.turn.rate(rates)
        rate = self.base.rate(rates) + self.sign * d1 * xd
        if accels is None:
            return rate, None
        return rate, self.base.rate(accels) + self.sign * (d2 * xd * xd + d1 * self.turn.rate(accels))


def _cam_ties(mech: Mechanism, contacts, rotations: dict, input_vars: dict, drawn: dict) -> dict:
    """Each cam pair's follower variable as a :class:`CamTie` of the cam's turn on its carrier."""
    out: dict = {}
    for c in contacts:
        where = f"{mech.name}: cam pair {c.pair.name!r}"
        turn = _combine([(1.0, rotations[c.cam]), (-1.0, rotations[c.carrier])])
        if c.kind == "translating":
            var = input_vars.get(c.joint, f"s:{c.joint}")
            base = Rotation((), drawn[var])
        else:
            var = f"rot:{c.follower}"
            if rotations[c.follower] != Rotation(((var, 1.0),)) or c.joint in input_vars:
                raise InputError(f"{where}: the follower {c.follower!r} must turn freely on the carrier (its rotation "
                                 "is already fixed by a driven joint, a gear or a slider)")
            base = rotations[c.carrier]
        if var.startswith("q:"):
            raise InputError(f"{where}: the follower's joint {c.joint!r} is driven; the cam drives it")
        if var in out or var not in drawn:
            raise InputError(f"{where}: the follower's {'slide' if c.kind == 'translating' else 'rotation'} is "
                             "already fixed by another pair")
        if var in {v for v, _ in turn.terms}:
            raise InputError(f"{where}: the cam's turn depends on its own follower")
        law = c.pair.law
        if isinstance(law, CamProfile):                     # the contact's law, built once per profile
            try:
                law = law.law
            except InputError as exc:
                raise InputError(f"{where}: {exc}") from None
        out[var] = CamTie(law, c.pair.phase, turn, base, c.sign)
    return out


def _combine(parts, const: float = 0.0) -> Rotation:
    """``Σ k·expr + const`` as one linear expression (terms with a zero coefficient dropped)."""
    out: dict[str, float] = {}
    total = const
    for k, expr in parts:
        for v, c in expr.terms:
            out[v] = out.get(v, 0.0) + k * c
        total += k * expr.const
    return Rotation(tuple((v, c) for v, c in sorted(out.items()) if abs(c) > 1e-15), total)


def _connected(cand, joints, known) -> bool:
    nodes = set(cand) | {KNOWN}
    adj = {n: set() for n in nodes}
    for j in joints:
        a, b = (KNOWN if x in known else x for x in j.links)
        adj[a].add(b)
        adj[b].add(a)
    seen, stack = {KNOWN}, [KNOWN]
    while stack:
        for y in adj[stack.pop()] - seen:
            seen.add(y)
            stack.append(y)
    return seen == nodes


def _owner_of_link(groups, link):
    for g in groups:
        if link in g.links:
            return g.index
    return None


def _ancestors(groups, index) -> set[int]:
    out, stack = set(), [index]
    while stack:
        for p in groups[stack.pop()].parents:
            if p not in out:
                out.add(p)
                stack.append(p)
    return out


def _tree(mech: Mechanism, root: str, allowed) -> dict:
    """BFS tree over links in ``allowed``: ``link -> (joint, parent)``."""
    prev = {root: None}
    queue = deque([root])
    while queue:
        x = queue.popleft()
        for j in mech.joints:
            if x in j.links:
                y = j.links[1] if j.links[0] == x else j.links[0]
                if y in allowed and y not in prev:
                    prev[y] = (j, x)
                    queue.append(y)
    del prev[root]
    return prev


def _group_loops(mech: Mechanism, cand, joints, allowed, rotations, input_vars) -> list[tuple[Segment, ...]]:
    """Fundamental cycles of the group (known links contracted to one node), as segment lists."""
    def node(x):
        return x if x in cand else KNOWN

    adj: dict[str, list] = {n: [] for n in list(cand) + [KNOWN]}
    for j in joints:
        a, b = (node(x) for x in j.links)
        adj[a].append((j, b))
        adj[b].append((j, a))
    prev = {KNOWN: None}
    queue = deque([KNOWN])
    tree = set()
    while queue:
        x = queue.popleft()
        for j, y in adj[x]:
            if y not in prev:
                prev[y] = (j, x)
                tree.add(j.name)
                queue.append(y)

    def to_root(x):
        path = []
        while prev[x] is not None:
            j, p = prev[x]
            path.append((x, j, p))
            x = p
        return path

    known_tree = {}
    loops = []
    for j in joints:
        if j.name in tree:
            continue
        a, b = j.links
        # Cycle: a --j--> b, then b up to the common ancestor and down to a.
        up_b, up_a = to_root(node(b)), to_root(node(a))
        nodes_b = [node(b)] + [p for _, _, p in up_b]
        nodes_a = [node(a)] + [p for _, _, p in up_a]
        common = next(x for x in nodes_b if x in nodes_a)
        steps = [(a, j, b)]  # (from link, joint, to link) with real link names
        for x, jj, p in up_b[: nodes_b.index(common)]:
            steps.append((_end(jj, x, cand), jj, _other(jj, _end(jj, x, cand))))
        down = up_a[: nodes_a.index(common)]
        for x, jj, p in reversed(down):
            frm = _other(jj, _end(jj, x, cand))
            steps.append((frm, jj, _end(jj, x, cand)))
        loops.append(_walk(mech, steps, cand, allowed, rotations, input_vars, known_tree))
    return loops


def _end(j: Joint, node_name, cand) -> str:
    """The real link of joint ``j`` that stands for ``node_name`` (a group link or the known node)."""
    if node_name != KNOWN:
        return node_name
    return next(x for x in j.links if x not in cand)


def _other(j: Joint, x) -> str:
    return j.links[1] if j.links[0] == x else j.links[0]


def _walk(mech, steps, cand, allowed, rotations, input_vars, cache) -> tuple[Segment, ...]:
    """Segments of the closed walk given by its joint crossings ``(from, joint, to)``."""
    segs: list[Segment] = []
    n = len(steps)
    for i, (frm, j, to) in enumerate(steps):
        if j.kind == "P":
            segs.append(_slide_segment(j, frm, rotations, input_vars))
        nxt_from, nxt_j, _ = steps[(i + 1) % n]
        if to == nxt_from:
            segs.append(link_segment(rotations[to], j.at, nxt_j.at))
        else:  # both known: go through known links
            segs.extend(_known_path(mech, to, j.at, nxt_from, nxt_j.at, allowed, rotations, input_vars, cache))
    return tuple(segs)


def _known_path(mech, start, p, goal, q, allowed, rotations, input_vars, cache) -> list[Segment]:
    key = (start, tuple(sorted(allowed)))
    if key not in cache:
        cache[key] = _tree(mech, start, allowed)
    prev = cache[key]
    if goal != start and goal not in prev:
        raise InputError(f"{mech.name}: known links {start!r} and {goal!r} are not connected through solved links")
    chain = []
    x = goal
    while x != start:
        j, parent = prev[x]
        chain.append((parent, j, x))
        x = parent
    chain.reverse()
    segs, here = [], p
    for parent, j, child in chain:
        segs.append(link_segment(rotations[parent], here, j.at))
        if j.kind == "P":
            segs.append(_slide_segment(j, parent, rotations, input_vars))
        here = j.at
    segs.append(link_segment(rotations[goal], here, q))
    return segs
