"""Spatial loop closure on rigid transforms: positions, velocities and accelerations of any spatial mechanism.

Every moving link has a pose: a reference point ``o`` (world) and a rotation
``R`` from its drawn pose, so that a drawn point ``d`` of it is at
``o + R (d − c)`` (``c`` the link's drawn reference point). Each joint
constrains the poses of its two links by scalar equations, each a dot
product of world points and directions of the links:

- R: the joint's point coincides on both links (3), the axes stay aligned (2);
- S: the point coincides (3);
- P: aligned axes (2), the point of one link on the other's axis line (2),
  no turning about the axis (1);
- C: aligned axes (2), point on line (2); H: as C, the slide tied to the turn
  by the pitch (1);
- each input fixes a joint variable (an angle by ``atan2``, a slide by a dot product).

Newton's method updates the poses (``o += δo``, ``R ← exp(δφ) R``) with the
analytic Jacobian of these equations in the links' twists; its steps are of
least norm, so the idle freedoms (a coupler held by two spherical joints spins
about their line) stay where they are. Velocities solve ``J ẋ = q̇`` (the
inputs' rows), accelerations ``J ẍ = q̈ − (velocity-product terms)``, all
analytic. Lengths are scaled by the mechanism's size inside.

>>> from domes.motion.spatial.examples import rssr
>>> kin = Loops(rssr(), outputs=["angle:B0"], order=2)
>>> step = kin.at({"A0": 0.0})
>>> [round(step.values[k], 6) for k in ("angle:B0", "angle:B0'", "angle:B0''")]
[0.0, -3.571429, 45.454545]
"""

from __future__ import annotations

import copy
import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialMechanism

#: Newton stops when its correction is below this (relative to the size); the residual is then ~1e-15.
TOL = 1e-13
MAX_ITERATIONS = 50
#: Newton gives up after this many steps in a row that do not halve the residual.
STALL = 4
#: A residual (relative to the size) this small is closure to rounding: Newton stops there even when its
#: correction, near a singular pose, cannot fall below :data:`TOL`.
ROUNDING = 1e-15
#: Beyond this condition number of the scaled Jacobian the configuration is reported singular.
SINGULAR = 1e8


def skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def rotation(phi: np.ndarray) -> np.ndarray:
    """``exp([φ]×)``: the rotation by ``|φ|`` about ``φ`` (Rodrigues)."""
    angle = float(np.linalg.norm(phi))
    if angle < 1e-300:
        return np.eye(3)
    k = skew(phi / angle)
    return np.eye(3) + math.sin(angle) * k + (1 - math.cos(angle)) * (k @ k)


def cross(a, b) -> np.ndarray:
    """``a × b`` over the last axis (length 3); ``np.cross`` without its axis handling, which dominates on the
    small arrays of a Newton step."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return np.stack((a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1], a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2],
                     a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]), axis=-1)


@lru_cache(maxsize=4096)
def _perpendiculars(u: tuple) -> tuple[np.ndarray, np.ndarray]:
    u = np.asarray(u)
    helper = np.eye(3)[int(np.argmin(np.abs(u)))]
    n1 = cross(helper, u)
    n1 /= np.linalg.norm(n1)
    return n1, cross(u, n1)


def perpendiculars(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors completing ``u`` to a right-handed frame ``(n1, n2, u)``."""
    n1, n2 = _perpendiculars(tuple(float(x) for x in u))
    return n1.copy(), n2.copy()


@dataclass(frozen=True)
class Term:
    """A world point (``kind`` "point") or direction ("vector") of a link, from its drawn coordinates."""

    kind: str
    link: int  # −1: the ground
    local: np.ndarray = field(compare=False)


class _Dots:
    """The ``dot`` equations compiled to arrays: every term's world value, rate and the Jacobian rows at once."""

    def __init__(self, eqs, links: int):
        terms, index = [], {}

        def idx(t: Term) -> int:
            key = (t.kind, t.link, tuple(np.round(t.local, 17)))
            if key not in index:
                index[key] = len(terms)
                terms.append(t)
            return index[key]

        pad = lambda side: (side + [(0, None)] * 2)[:2]  # noqa: E731
        self.u_idx, self.u_sign, self.v_idx, self.v_sign, self.value = [], [], [], [], []
        for eq in eqs:
            if len(eq[1]) > 2 or len(eq[2]) > 2:
                raise AssertionError("a dot equation has at most two terms a side")
            for side, ids, signs in ((eq[1], self.u_idx, self.u_sign), (eq[2], self.v_idx, self.v_sign)):
                row = pad(list(side))
                ids.append([idx(t) if t is not None else 0 for _, t in row])
                signs.append([float(sg) for sg, _ in row])
            self.value.append(eq[3])
        self.u_idx, self.v_idx = np.array(self.u_idx, int).reshape(-1, 2), np.array(self.v_idx, int).reshape(-1, 2)
        self.u_sign, self.v_sign = np.array(self.u_sign).reshape(-1, 2), np.array(self.v_sign).reshape(-1, 2)
        self.value = np.array(self.value, float)
        self.point = np.array([t.kind == "point" for t in terms], bool)
        self.link = np.array([t.link for t in terms], int)
        self.local = np.array([t.local for t in terms], float).reshape(-1, 3)
        self.links = links

    def world(self, s: State):
        """Each term's world value ``w`` and its lever ``r`` (from its link's reference point, or itself)."""
        L = self.links
        R = np.concatenate([s.R, np.eye(3)[None]]) if L else np.eye(3)[None]
        o = np.concatenate([s.o, np.zeros((1, 3))]) if L else np.zeros((1, 3))
        k = np.where(self.link < 0, L, self.link)
        turned = np.einsum("nij,nj->ni", R[k], self.local)
        w = np.where(self.point[:, None], o[k] + turned, turned)
        return w, turned, k

    def evaluate(self, s: State, xd=None):
        """Values ``(E,)``, Jacobian ``(E, 6L)`` and, with twists ``xd``, the velocity-product terms ``(E,)``."""
        w, r, k = self.world(s)
        U = np.einsum("ej,ejk->ek", self.u_sign, w[self.u_idx])
        V = np.einsum("ej,ejk->ek", self.v_sign, w[self.v_idx])
        values = np.einsum("ek,ek->e", U, V) - self.value
        E, L = len(self.value), self.links
        J = np.zeros((E, L + 1, 6))
        for idx, sign, other in ((self.u_idx, self.u_sign, V), (self.v_idx, self.v_sign, U)):
            for j in range(2):
                t = idx[:, j]
                sg = sign[:, j][:, None]
                rows = np.arange(E)
                lk = k[t]
                pt = self.point[t][:, None]
                # each equation appears once per (side, slot): no index repeats, plain += accumulates
                J[rows, lk, 0:3] += np.where(pt, sg * other, 0.0)
                J[rows, lk, 3:6] += sg * cross(r[t], other)
        J = J[:, :L].reshape(E, 6 * L)
        if xd is None:
            return values, J, None
        tw = np.concatenate([xd.reshape(-1, 6), np.zeros((1, 6))])
        v, om = tw[k, :3], tw[k, 3:]
        rate = np.where(self.point[:, None], v, 0.0) + cross(om, r)
        quad = cross(om, cross(om, r))
        ground = (self.link < 0)[:, None]
        rate, quad = np.where(ground, 0.0, rate), np.where(ground, 0.0, quad)
        Ud = np.einsum("ej,ejk->ek", self.u_sign, rate[self.u_idx])
        Vd = np.einsum("ej,ejk->ek", self.v_sign, rate[self.v_idx])
        Uq = np.einsum("ej,ejk->ek", self.u_sign, quad[self.u_idx])
        Vq = np.einsum("ej,ejk->ek", self.v_sign, quad[self.v_idx])
        bias = np.einsum("ek,ek->e", Uq, V) + np.einsum("ek,ek->e", U, Vq) + 2 * np.einsum("ek,ek->e", Ud, Vd)
        return values, J, bias


class State:
    """Poses of the moving links: reference points ``o`` (L, 3) and rotations ``R`` (L, 3, 3)."""

    def __init__(self, o: np.ndarray, R: np.ndarray):
        self.o, self.R = o, R

    def copy(self) -> "State":
        return State(self.o.copy(), self.R.copy())


class Loops:
    """A compiled spatial query: outputs (``angle:J``, ``slide:J``, ``point:NAME``) up to derivative ``order``."""

    def __init__(self, mech: SpatialMechanism, outputs=None, order: int = 0, tol: float = TOL):
        if order not in (0, 1, 2):
            raise InputError(f"order must be 0, 1 or 2, got {order}")
        self.mech, self.order, self.tol = mech, order, tol
        self.scale = mech.size
        self.moving = [x for x in mech.links if x != mech.ground]
        self.index = {x: k for k, x in enumerate(self.moving)}
        self.index[mech.ground] = -1
        self.centre = np.zeros((len(self.moving), 3))
        for x, k in self.index.items():
            if k >= 0:
                self.centre[k] = np.mean([np.asarray(j.at) for j in mech.joints_of(x)], axis=0) / self.scale
        self.outputs = self._outputs(outputs)
        self.equations = self._equations()
        self._dots = _Dots([e for e in self.equations if e[0] == "dot"], len(self.moving))
        self._others = [e for e in self.equations if e[0] != "dot"]
        self.inputs = list(mech.inputs)
        self.unknowns = 6 * len(self.moving)
        self._check_mobility()

    # -- compiling ------------------------------------------------------------------------------

    def _point(self, link: str, at) -> Term:
        k = self.index[link]
        d = np.asarray(at, dtype=float) / self.scale
        return Term("point", k, d - (self.centre[k] if k >= 0 else 0.0))

    def _vector(self, link: str, u) -> Term:
        return Term("vector", self.index[link], np.asarray(u, dtype=float))

    def _equations(self) -> list[tuple]:
        """Scalar equations: ``("dot", [(sign, term)], [(sign, term)], value)`` or ``("angle", joint)`` kinds."""
        eqs = []
        for j in self.mech.joints:
            a, b = j.links
            if j.kind in ("R", "S"):
                for e in np.eye(3):
                    eqs.append(("dot", [(1, self._point(b, j.at)), (-1, self._point(a, j.at))],
                                [(1, Term("vector", -1, e))], 0.0, j.name))
            if j.kind in ("R", "P", "C", "H"):
                u = np.asarray(j.axis)
                n1, n2 = perpendiculars(u)
                for n in (n1, n2):
                    eqs.append(("dot", [(1, self._vector(a, n))], [(1, self._vector(b, u))], 0.0, j.name))
            if j.kind in ("P", "C", "H"):
                u = np.asarray(j.axis)
                n1, n2 = perpendiculars(u)
                for n in (n1, n2):
                    eqs.append(("dot", [(1, self._point(b, j.at)), (-1, self._point(a, j.at))],
                                [(1, self._vector(a, n))], 0.0, j.name))
            if j.kind == "P":
                u = np.asarray(j.axis)
                n1, n2 = perpendiculars(u)
                eqs.append(("dot", [(1, self._vector(b, n1))], [(1, self._vector(a, n2))], 0.0, j.name))
            if j.kind == "H":
                eqs.append(("helix", j.name))
        return eqs

    def _outputs(self, names) -> list[tuple[str, str]]:
        mech = self.mech
        if not names:
            outs = [("angle", j.name) for j in mech.joints if j.kind in ("R", "C", "H")]
            outs += [("slide", j.name) for j in mech.joints if j.kind in ("P", "C", "H")]
            return outs + [("point", p.name) for p in mech.points]
        joints = {j.name: j for j in mech.joints}
        points = {p.name for p in mech.points}
        out = []
        for name in names:
            kind, _, target = name.partition(":")
            ok = ((kind == "angle" and target in joints and joints[target].kind in ("R", "C", "H"))
                  or (kind == "slide" and target in joints and joints[target].kind in ("P", "C", "H"))
                  or (kind == "point" and (target in joints or target in points)))
            if not ok:
                raise InputError(f"output {name!r}: use angle:JOINT (R, C, H joints "
                                 f"{[j for j in joints if joints[j].kind in 'RCH']}), slide:JOINT (P, C, H joints "
                                 f"{[j for j in joints if joints[j].kind in 'PCH']}) or point:NAME (joints and points "
                                 f"{sorted(set(joints) | points)})")
            out.append((kind, target))
        return out

    def _check_mobility(self) -> None:
        """At the drawn pose the inputs must fix every motion but the idle ones (rank of the Jacobian)."""
        state = self.drawn()
        J = self._jacobian(state, inputs=True)[0]
        rank = np.linalg.matrix_rank(J, tol=1e-9 * max(1.0, np.abs(J).max()))
        free = self.unknowns - rank
        if free != self.mech.idle:
            J0 = self._jacobian(state, inputs=False)[0]
            mobility = self.unknowns - np.linalg.matrix_rank(J0, tol=1e-9 * max(1.0, np.abs(J0).max())) - self.mech.idle
            raise InputError(f"{self.mech.name}: the mechanism moves with {mobility} degree(s) of freedom in its drawn "
                             f"pose (besides {self.mech.idle} idle spin(s)) but has {len(self.inputs)} input(s); "
                             "give one driven joint variable per degree of freedom")

    # -- kinematics of terms ----------------------------------------------------------------------

    def drawn(self) -> State:
        L = len(self.moving)
        return State(self.centre.copy(), np.repeat(np.eye(3)[None], L, axis=0))

    def _world(self, t: Term, s: State) -> np.ndarray:
        if t.link < 0:
            return t.local
        if t.kind == "point":
            return s.o[t.link] + s.R[t.link] @ t.local
        return s.R[t.link] @ t.local

    def _rows(self, t: Term, s: State, w: np.ndarray) -> np.ndarray:
        """The (3, 6L) map from the twists (v, ω of each link) to the term's rate."""
        J = np.zeros((3, self.unknowns))
        if t.link < 0:
            return J
        k = 6 * t.link
        if t.kind == "point":
            J[:, k:k + 3] = np.eye(3)
            J[:, k + 3:k + 6] = -skew(w - s.o[t.link])
        else:
            J[:, k + 3:k + 6] = -skew(w)
        return J

    def _quadratic(self, t: Term, s: State, w: np.ndarray, omega: np.ndarray) -> np.ndarray:
        """The term's acceleration beyond ``J ẍ``: ``ω × (ω × r)``."""
        if t.link < 0:
            return np.zeros(3)
        r = w - s.o[t.link] if t.kind == "point" else w
        om = omega[t.link]
        return cross(om, cross(om, r))

    def _side(self, side, s: State, twist=None, omega=None):
        value = np.zeros(3)
        rows = np.zeros((3, self.unknowns))
        quad = np.zeros(3)
        for sign, t in side:
            w = self._world(t, s)
            value += sign * w
            rows += sign * self._rows(t, s, w)
            if omega is not None:
                quad += sign * self._quadratic(t, s, w, omega)
        return value, rows, quad

    def _scalar(self, eq, s: State, xd=None):
        """Value, Jacobian row and (with velocities ``xd``) the velocity-product term of one equation."""
        if eq[0] == "dot":
            omega = None if xd is None else xd.reshape(-1, 6)[:, 3:]
            U, JU, qU = self._side(eq[1], s, omega=omega)
            V, JV, qV = self._side(eq[2], s, omega=omega)
            row = V @ JU + U @ JV
            bias = 0.0
            if xd is not None:
                bias = qU @ V + U @ qV + 2 * (JU @ xd) @ (JV @ xd)
            return U @ V - eq[3], row, bias
        if eq[0] == "helix":
            j = self.mech.joint(eq[1])
            sv, srow, sbias = self._scalar(self._slide_eq(j), s, xd)
            av, arow, abias = self._angle(j, s, xd)
            return sv - j.pitch / self.scale * av, srow - j.pitch / self.scale * arow, \
                sbias - j.pitch / self.scale * abias
        raise AssertionError(eq)

    def _slide_eq(self, j) -> tuple:
        a, b = j.links
        return ("dot", [(1, self._point(b, j.at)), (-1, self._point(a, j.at))], [(1, self._vector(a, j.axis))], 0.0,
                j.name)

    def _angle(self, j, s: State, xd=None):
        """The joint's angle from the drawn pose: ``atan2(n1_b·n2_a, n1_b·n1_a)``, its row and product term."""
        a, b = j.links
        n1, n2 = perpendiculars(np.asarray(j.axis))
        y = self._scalar(("dot", [(1, self._vector(b, n1))], [(1, self._vector(a, n2))], 0.0), s, xd)
        x = self._scalar(("dot", [(1, self._vector(b, n1))], [(1, self._vector(a, n1))], 0.0), s, xd)
        r2 = x[0] ** 2 + y[0] ** 2
        angle = math.atan2(y[0], x[0])
        row = (x[0] * y[1] - y[0] * x[1]) / r2
        bias = 0.0
        if xd is not None:
            xdot, ydot = x[1] @ xd, y[1] @ xd
            rate = (x[0] * ydot - y[0] * xdot) / r2
            bias = (x[0] * y[2] - y[0] * x[2]) / r2 - 2 * rate * (x[0] * xdot + y[0] * ydot) / r2
        return angle, row, bias

    def _variable(self, joint: str, variable: str, s: State, xd=None):
        j = self.mech.joint(joint)
        if variable == "angle":
            return self._angle(j, s, xd)
        return self._scalar(self._slide_eq(j), s, xd)

    def driven_by(self, inputs) -> "Loops":
        """The same loops with other driven variables (:class:`~domes.model.spatial.SpatialInput`), not checked
        for mobility in the drawn pose: near a limit of the input another joint is the better parameter
        (:mod:`~domes.motion.spatial.limits`)."""
        other = copy.copy(self)
        other.inputs = list(inputs)
        return other

    # -- solving ----------------------------------------------------------------------------------

    def key(self, i) -> str:
        """How an input's value is named: its joint, or ``joint.variable`` when both of a C joint's are driven."""
        both = sum(1 for x in self.inputs if x.joint == i.joint) > 1
        return f"{i.joint}.{i.variable}" if both else i.joint

    def _jacobian(self, s: State, values: dict | None = None, inputs: bool = True, unwrap: dict | None = None):
        dot_values, dot_rows, _ = self._dots.evaluate(s)
        rows, res = list(dot_rows), list(dot_values)
        for eq in self._others:
            v, row, _ = self._scalar(eq, s)
            rows.append(row)
            res.append(v)
        if inputs:
            for i in self.inputs:
                v, row, _ = self._variable(i.joint, i.variable, s)
                target = (values or {}).get(self.key(i), 0.0)
                if i.variable == "angle":
                    d = v - target
                    res.append((d + math.pi) % (2 * math.pi) - math.pi)
                else:
                    res.append(v - target / self.scale)
                rows.append(row)
        return np.array(rows), np.array(res)

    def _update(self, s: State, dx: np.ndarray) -> None:
        d = dx.reshape(-1, 6)
        s.o += d[:, :3]
        for k in range(len(self.moving)):
            s.R[k] = rotation(d[k, 3:]) @ s.R[k]

    def positions(self, values: dict, guess: State | None = None) -> tuple[State, float]:
        """The poses at the input values (rad, lengths; by :meth:`key`), by Newton from ``guess`` (default the
        drawn pose)."""
        s = (guess or self.drawn()).copy()
        slow, last = 0, math.inf
        for _ in range(MAX_ITERATIONS):
            J, f = self._jacobian(s, values)
            size = float(np.max(np.abs(f))) if f.size else 0.0
            if size <= ROUNDING and last < math.inf:
                # Closed to rounding: near a singular pose the correction stays at cond·ε above TOL however
                # long Newton runs, yet no float pose closes better (its error is at most cond × residual).
                return s, size
            slow = slow + 1 if size > 0.5 * last else 0
            if slow >= STALL:        # no longer converging quadratically: no solution near the guess
                break
            last = size
            dx = np.linalg.lstsq(J, -f, rcond=None)[0]
            self._update(s, dx)
            if np.max(np.abs(dx)) < self.tol:
                J, f = self._jacobian(s, values)
                return s, float(np.max(np.abs(f))) if f.size else 0.0
        J, f = self._jacobian(s, values)
        raise NumericalError(f"{self.mech.name}: Newton's method did not converge at {values} (residual "
                             f"{np.max(np.abs(f)):.3g})", kind="newton", residual=float(np.max(np.abs(f))),
                             where={"inputs": dict(values)})

    def condition(self, s: State) -> float:
        """Condition number of the Jacobian with the inputs, over its expected rank (the idle spins left out)."""
        J = self._jacobian(s)[0]
        sv = np.linalg.svd(J, compute_uv=False)
        rank = self.unknowns - self.mech.idle
        small = sv[rank - 1] if rank - 1 < sv.size else 0.0
        return float(sv[0] / small) if small > 0 else math.inf

    def motion(self, s: State, order: int, speeds: dict | None = None, accelerations: dict | None = None):
        """Twists (``order`` 1) and their rates (2) of every link: arrays (6L,), by least-norm solves."""
        if order == 0:
            return None, None
        J = self._jacobian(s)[0]
        m = len(self.equations)
        rhs = np.zeros(J.shape[0])
        for k, i in enumerate(self.inputs):
            rate = (speeds or {}).get(self.key(i), i.speed)
            rhs[m + k] = rate if i.variable == "angle" else rate / self.scale
        xd = np.linalg.lstsq(J, rhs, rcond=None)[0]
        if order == 1:
            return xd, None
        rhs = np.zeros(J.shape[0])
        bias = self._dots.evaluate(s, xd)[2]
        rhs[:bias.size] = -bias
        for n, eq in enumerate(self._others, bias.size):
            rhs[n] = -self._scalar(eq, s, xd)[2]
        for k, i in enumerate(self.inputs):
            acc = (accelerations or {}).get(self.key(i), i.acceleration)
            rhs[m + k] = (acc if i.variable == "angle" else acc / self.scale) - self._variable(i.joint, i.variable, s, xd)[2]
        return xd, np.linalg.lstsq(J, rhs, rcond=None)[0]

    def output_values(self, s: State, xd=None, xdd=None) -> dict:
        out = {}
        for kind, target in self.outputs:
            if kind == "point":
                link, at = self.mech.point(target)
                t = self._point(link, at)
                w = self._world(t, s)
                comps = [w * self.scale]
                if xd is not None:
                    rows = self._rows(t, s, w)
                    comps.append(rows @ xd * self.scale)
                    if xdd is not None:
                        omega = xd.reshape(-1, 6)[:, 3:]
                        comps.append((rows @ xdd + self._quadratic(t, s, w, omega)) * self.scale)
                for k, c in enumerate(comps):
                    for axis, v in zip("xyz", c):
                        out[f"point:{target}.{axis}" + "'" * k] = float(v)
                continue
            value, row, _ = self._variable(target, kind, s)
            factor = 1.0 if kind == "angle" else self.scale
            comps = [value * factor]
            if xd is not None:
                comps.append(row @ xd * factor)
                if xdd is not None:
                    comps.append((row @ xdd + self._variable(target, kind, s, xd)[2]) * factor)
            for k, c in enumerate(comps):
                out[f"{kind}:{target}" + "'" * k] = float(c)
        return out

    def places(self, s: State) -> dict:
        """World positions (the file's units) of every joint (on its second link) and point in state ``s``."""
        out = {}
        for j in self.mech.joints:
            out[j.name] = self._world(self._point(j.links[1], j.at), s) * self.scale
        for p in self.mech.points:
            out[p.name] = self._world(self._point(p.link, p.at), s) * self.scale
        return out

    def at(self, values: dict, guess: State | None = None, order: int | None = None) -> "SpatialStep":
        """One configuration at the input values (rad, lengths; inputs not given stay at their drawn 0)."""
        order = self.order if order is None else order
        s, residual = self.positions(values, guess)
        cond = self.condition(s)
        if order and not cond < SINGULAR:
            raise NumericalError(f"{self.mech.name}: singular configuration at {values} (condition {cond:.3g}): "
                                 "the velocities are not determined", kind="singular", condition=cond,
                                 where={"inputs": dict(values)})
        xd, xdd = self.motion(s, order)
        return SpatialStep(dict(values), self.output_values(s, xd, xdd), residual, cond, s)


@dataclass(frozen=True)
class SpatialStep:
    """One solved configuration: outputs by column, the residual (relative to the size) and condition number."""

    inputs: dict
    values: dict
    residual: float
    condition: float
    state: State = field(repr=False, compare=False)


__all__ = ["Loops", "SpatialStep", "State", "perpendiculars", "rotation", "skew"]
