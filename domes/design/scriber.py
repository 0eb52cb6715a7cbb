"""The 2-RPR parallel scriber of seed 003 (Deng et al.): kinematics, Lagrange dynamics, path following.

Two blocks turn about A = (s_a, 0) and B = (s_b, H); a link slides through
each (the actuated prismatic joints, lengths q1 = |PA|, q2 = |PB|) and the
links meet at the scribing point P. Inverse kinematics is unique, forward
kinematics has two branches (mirror images about AB); the one singularity is
P on the line AB (``sin(θ2 − θ1) = 0``). The Lagrange model with the
generalised coordinates q: ``Q = M(q) q̈ + c(q, q̇)``, c in Christoffel form.

Two kinetic energies (digest §4): ``"corrected"`` (the rigid-body energy:
each link's mass translating with q̇ plus its inertia about the pivot
turning) and ``"paper"`` (eq. (11) with eq. (13): the pivot inertia added to
the centroid's energy, counting ``½ m r² θ̇²`` twice). Two sets of equations:
``"corrected"`` (from the paper's own intermediate lines) and ``"printed"``
(the final system as printed, which breaks the power balance). Every result
carries its power balance ``Q·q̇ − dE/dt``.

>>> s = Scriber(H=0.317)
>>> q, th = s.inverse(np.array([0.2 + 0.1j]))
>>> [round(float(x), 8) for x in q[:, 0]], round(float(np.degrees(th[1, 0])), 6)
([0.2236068, 0.29510845], -47.334506)
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from domes.design.contour import CORNER, Contour
from domes.errors import InputError
from domes.model.fields import LARGEST, check_keys, read_number
from domes.model.masses import LinkMass, MassModel
from domes.model.mechanism import Input, Joint, Mechanism
from domes.results import Result, Status

KINETIC = ("corrected", "paper")
EQUATIONS = ("corrected", "printed")

#: Below this |sin(θ2 − θ1)| a pose is reported singular (P on the line AB).
SINGULAR_SINE = 1e-4
#: The most sample points of one run.
MAX_POINTS = 10_000_000


@dataclass(frozen=True)
class Scriber:
    """A 2-RPR scriber: block pivots A = (sa, 0), B = (sb, H); link lengths and masses (homogeneous rods).

    ``branch`` (+1 / −1) is the forward kinematics' assembly mode: P on the
    side of the line A→B where ``(B − A) × (P − A)`` has the opposite sign
    (+1: x > 0 for the paper's A = (0, 0), B = (0, H)).
    """

    H: float
    sa: float = 0.0
    sb: float = 0.0
    lengths: tuple[float, float] = (0.4, 0.4)
    masses: tuple[float, float] = (1.0, 1.0)
    branch: int = 1

    def __post_init__(self):
        for name, value in (("H", self.H), ("sa", self.sa), ("sb", self.sb)):
            if not math.isfinite(value):
                raise InputError(f"scriber {name}: must be a finite number, got {value!r}")
        if abs(complex(self.sb, self.H) - complex(self.sa, 0)) == 0:
            raise InputError("scriber: the block pivots A and B coincide")
        if any(not (math.isfinite(x) and x > 0) for x in self.lengths):
            raise InputError(f"scriber lengths: must be > 0, got {self.lengths}")
        if any(not (math.isfinite(x) and x >= 0) for x in self.masses):
            raise InputError(f"scriber masses: must be >= 0, got {self.masses}")
        if self.branch not in (1, -1):
            raise InputError(f"scriber branch: +1 or -1, got {self.branch!r}")

    @property
    def pivots(self) -> tuple[complex, complex]:
        return complex(self.sa, 0.0), complex(self.sb, self.H)

    # -- kinematics ---------------------------------------------------------------------------

    def inverse(self, P) -> tuple[np.ndarray, np.ndarray]:
        """``q`` (2, N) and ``θ`` (2, N) of points ``P`` (complex): unique (digest §2.2)."""
        P = np.atleast_1d(np.asarray(P, dtype=complex))
        A, B = self.pivots
        return np.stack([np.abs(P - A), np.abs(P - B)]), np.stack([np.angle(P - A), np.angle(P - B)])

    def forward(self, q, branch: int | None = None) -> np.ndarray:
        """P (complex, N) from ``q`` (2, N) on ``branch`` (default: the scriber's); NaN where it cannot assemble."""
        q = np.asarray(q, dtype=float).reshape(2, -1)
        A, B = self.pivots
        d = abs(B - A)
        e = (B - A) / d
        n = -1j * e  # (e_y, −e_x)
        a = (q[0] ** 2 - q[1] ** 2 + d * d) / (2 * d)
        with np.errstate(invalid="ignore"):
            h = np.sqrt(q[0] ** 2 - a * a)
        return A + a * e + (self.branch if branch is None else branch) * h * n

    def jacobian(self, P) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``J`` (Ṗ = J q̇), ``J⁻¹`` (rows e1, e2), both (N, 2, 2), and ``sin(θ2 − θ1)`` (N)."""
        _, th = self.inverse(P)
        Jinv = np.stack([np.stack([np.cos(th[0]), np.sin(th[0])], -1), np.stack([np.cos(th[1]), np.sin(th[1])], -1)], 1)
        s = np.sin(th[1] - th[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            J = np.stack([np.stack([np.sin(th[1]), -np.sin(th[0])], -1),
                          np.stack([-np.cos(th[1]), np.cos(th[0])], -1)], 1) / s[:, None, None]
        return J, Jinv, s

    def partials(self, q, th) -> np.ndarray:
        """The paper's eq. (7): ``u[i, k]`` = ∂θ_i/∂q_k, shape (2, 2, N)."""
        c, s = np.cos(th[1] - th[0]), np.sin(th[1] - th[0])
        with np.errstate(divide="ignore", invalid="ignore"):
            u1 = np.stack([-c, np.ones_like(c)]) / (q[0] * s)
            u2 = np.stack([-np.ones_like(c), c]) / (q[1] * s)
        return np.stack([u1, u2])

    def check(self, P, min_sine: float = SINGULAR_SINE) -> dict:
        """Which poses can be made: ``stroke`` (q_i < l_i and > 0), ``singular`` (|sin(θ2 − θ1)| < ``min_sine``)."""
        q, th = self.inverse(P)
        lengths = np.asarray(self.lengths)[:, None]
        stroke = np.all((q > 0) & (q < lengths), axis=0)
        sine = np.sin(th[1] - th[0])
        return {"stroke": stroke, "singular": np.abs(sine) < min_sine, "sine": sine, "q": q}

    # -- dynamics -------------------------------------------------------------------------------

    def _inertias(self, q, kinetic: str):
        m = np.asarray(self.masses)[:, None]
        ln = np.asarray(self.lengths)[:, None]
        r = q - ln / 2
        pivot = m * (ln * ln / 12 + r * r)  # J_i^A: about the block pivot
        if kinetic == "corrected":
            return pivot, 2 * m * r
        return pivot + m * r * r, 4 * m * r

    def mass_matrix(self, q, th, kinetic: str = "corrected") -> np.ndarray:
        """``M(q)`` (N, 2, 2) in kg: ``diag(m) + Σ J_i u_θi u_θiᵀ`` (digest §4)."""
        _kinetic(kinetic)
        u = self.partials(q, th)
        Ji, _ = self._inertias(q, kinetic)
        M = np.einsum("in,ian,ibn->nab", Ji, u, u)
        M[:, 0, 0] += self.masses[0]
        M[:, 1, 1] += self.masses[1]
        return M

    def mass_derivatives(self, q, th, kinetic: str = "corrected") -> np.ndarray:
        """``∂M_ab/∂q_k`` as (N, 2, 2, 2) (last index k), by the chain rule through eq. (7)."""
        _kinetic(kinetic)
        u = self.partials(q, th)
        c, s = np.cos(th[1] - th[0]), np.sin(th[1] - th[0])
        Ji, dJi = self._inertias(q, kinetic)
        n = q.shape[1]
        out = np.zeros((n, 2, 2, 2))
        for k in range(2):
            dphi = u[1, k] - u[0, k]
            dc, ds = -s * dphi, c * dphi
            for i, (vec, scale_q) in enumerate((((-c, np.ones_like(c)), q[0]), ((-np.ones_like(c), c), q[1]))):
                den = scale_q * s
                dden = (1.0 if k == i else 0.0) * s + scale_q * ds
                dvec = (-dc, np.zeros_like(c)) if i == 0 else (np.zeros_like(c), dc)
                du = np.stack([dvec[a] / den - vec[a] * dden / den ** 2 for a in range(2)])
                uu = u[i]
                term = Ji[i][:, None, None] * (np.einsum("an,bn->nab", du, uu) + np.einsum("an,bn->nab", uu, du))
                if k == i:
                    term = term + dJi[i][:, None, None] * np.einsum("an,bn->nab", uu, uu)
                out[..., k] += term
        return out

    def forces(self, q, th, qd, qdd, kinetic: str = "corrected", equations: str = "corrected") -> dict:
        """Driving forces ``Q`` (N, 2) from ``q, θ, q̇, q̈`` (each (2, N)); kinetic energy, its rate, the power ``Q·q̇``."""
        if equations not in EQUATIONS:
            raise InputError(f"equations: one of {EQUATIONS}, got {equations!r}")
        M = self.mass_matrix(q, th, kinetic)
        dM = self.mass_derivatives(q, th, kinetic)
        v, a = qd.T, qdd.T
        inertia = np.einsum("nab,nb->na", M, a)
        if equations == "corrected":
            gamma = dM - 0.5 * np.transpose(dM, (0, 3, 1, 2))  # ∂M_ij/∂q_k − ½ ∂M_jk/∂q_i
            Q = inertia + np.einsum("nijk,nj,nk->ni", gamma, v, v)
        else:  # the final system as printed (digest §5)
            d = lambda i, j, k: dM[:, i - 1, j - 1, k - 1]  # noqa: E731  J_ij,k
            v1, v2 = v[:, 0], v[:, 1]
            Q = inertia + np.stack([
                0.5 * d(1, 1, 1) * v1 ** 2 + (d(1, 2, 2) - 0.5 * d(2, 2, 1)) * v1 * v2 + d(1, 1, 2) * v1 * v2,
                (d(1, 2, 1) - 0.5 * d(1, 1, 2)) * v1 * v2 + 0.5 * d(2, 2, 2) * v2 ** 2 + d(1, 2, 1) * v1 * v2], 1)
        Mdot = np.einsum("nabk,nk->nab", dM, v)
        rate = np.einsum("na,nab,nb->n", v, M, a) + 0.5 * np.einsum("na,nab,nb->n", v, Mdot, v)
        return {"Q": Q, "energy": 0.5 * np.einsum("na,nab,nb->n", v, M, v), "energy_rate": rate,
                "power": np.einsum("na,na->n", Q, v)}

    def rates(self, P, V, A) -> tuple:
        """``q, θ, q̇, q̈`` (each (2, N)) of points ``P`` moving with velocity ``V`` and acceleration ``A`` (§2.5)."""
        q, th = self.inverse(P)
        e = np.exp(1j * th)
        dot = lambda z, w: z.real * w.real + z.imag * w.imag  # noqa: E731
        qd = dot(e, V[None, :])
        across = dot(1j * e, V[None, :])
        qdd = dot(e, A[None, :]) + across ** 2 / q
        return q, th, qd, qdd

    def mechanism(self, P) -> Mechanism:
        """The scriber as a mechanism file's :class:`~domes.model.mechanism.Mechanism`, drawn with the point at
        ``P``: blocks massless, each link a homogeneous rod (centre ``l/2`` from P towards its block, inertia
        ``m l²/12``); the two slides are the inputs. Its general inverse dynamics must match the corrected model.
        """
        A, B = self.pivots
        P = complex(P)
        q, th = self.inverse(np.array([P]))
        joints = (Joint("A", "R", ("frame", "block A"), (A.real, A.imag)),
                  Joint("q1", "P", ("block A", "link 1"), (P.real, P.imag), float(th[0, 0]), (A.real, A.imag)),
                  Joint("P", "R", ("link 1", "link 2"), (P.real, P.imag)),
                  Joint("B", "R", ("frame", "block B"), (B.real, B.imag)),
                  Joint("q2", "P", ("block B", "link 2"), (P.real, P.imag), float(th[1, 0]), (B.real, B.imag)))
        masses = []
        for i, link in enumerate(("link 1", "link 2")):
            c = P - self.lengths[i] / 2 * np.exp(1j * th[i, 0])
            masses.append(LinkMass(link, self.masses[i], (c.real, c.imag), self.masses[i] * self.lengths[i] ** 2 / 12))
        mech = Mechanism.build("2-RPR scriber", ("frame", "block A", "link 1", "block B", "link 2"), "frame", joints,
                               (Input("q1", 0.0), Input("q2", 0.0)))
        return dataclasses.replace(mech, masses=MassModel(tuple(masses)))

    @classmethod
    def from_dict(cls, data, source: str) -> "Scriber":
        check_keys(data, {"H", "sa", "sb", "lengths", "masses", "branch"}, {"H"}, f"{source}: scriber")
        pair = {}
        for key, default in (("lengths", (0.4, 0.4)), ("masses", (1.0, 1.0))):
            value = data.get(key, list(default))
            if not isinstance(value, list) or len(value) != 2:
                raise InputError(f"{source}: scriber.{key}: expected two numbers, got {value!r}")
            pair[key] = tuple(read_number(x, f"{source}: scriber.{key}[{i}]", LARGEST) for i, x in enumerate(value))
        try:
            return cls(read_number(data["H"], f"{source}: scriber.H", LARGEST),
                       read_number(data.get("sa", 0.0), f"{source}: scriber.sa", LARGEST),
                       read_number(data.get("sb", 0.0), f"{source}: scriber.sb", LARGEST), pair["lengths"],
                       pair["masses"], data.get("branch", 1))
        except InputError as exc:
            raise InputError(f"{source}: {exc}") from None

    def to_dict(self) -> dict:
        return {"H": self.H, "sa": self.sa, "sb": self.sb, "lengths": list(self.lengths), "masses": list(self.masses),
                "branch": self.branch}


def _kinetic(kinetic: str) -> None:
    if kinetic not in KINETIC:
        raise InputError(f"kinetic energy: one of {KINETIC}, got {kinetic!r}")


# -- path following ------------------------------------------------------------------------------

@dataclass(frozen=True)
class Junction:
    """Where two segments meet: the tangent's turn, the jumps of q̈ and of Q across it (digest D-13)."""

    index: int
    s: float
    corner: float
    jump_qdd: tuple[float, float]
    jump_Q: tuple[float, float]


@dataclass(frozen=True, eq=False)
class PathForces(Result):
    """Driving forces of the scriber along a contour at constant speed, with the power balance of every point.

    Arrays over the ``N`` sample points: ``s`` (arc length), ``time``,
    ``segment``, ``P``, ``q``, ``qd``, ``qdd``, ``Q`` (N, 2); ``balance`` is
    ``Q·q̇ − dE/dt``. ``work`` is ∫ Q·q̇ dt over the samples (midpoint rule;
    0 over a closed lap). ``spreads`` gives, for lines and for arcs, the
    range of both forces over all such segments.
    """

    scriber: Scriber
    contour: Contour
    speed: float
    kinetic: str
    equations: str
    s: np.ndarray
    time: np.ndarray
    segment: np.ndarray
    P: np.ndarray
    q: np.ndarray
    qd: np.ndarray
    qdd: np.ndarray
    Q: np.ndarray
    energy: np.ndarray
    power: np.ndarray
    energy_rate: np.ndarray
    junctions: tuple[Junction, ...]
    status: Status
    problems: tuple[str, ...] = ()
    min_sine: float = field(default=SINGULAR_SINE)

    @property
    def balance(self) -> np.ndarray:
        return self.power - self.energy_rate

    @property
    def peak_power(self) -> float:
        return float(max(np.max(np.abs(self.power)), np.max(np.abs(self.energy_rate)))) if self.power.size else 0.0

    @property
    def max_imbalance(self) -> float:
        peak = self.peak_power
        return float(np.max(np.abs(self.balance)) / peak) if peak > 0 else 0.0

    @property
    def work(self) -> float:
        return float(np.sum(self.power) * 2 * self.s[0] / self.speed)   # midpoints: the spacing is twice the first

    def spreads(self) -> dict:
        """``{"line": (low, high), "arc": (low, high)}``: the range of both forces over each kind of segment."""
        out = {}
        kinds = np.array([self.contour.segments[k].kind for k in self.segment])
        for kind in ("line", "arc"):
            mask = kinds == kind
            if np.any(mask):
                values = self.Q[mask]
                out[kind] = (float(values.min()), float(values.max()))
        return out

    @property
    def message(self) -> str:
        spread = "; ".join(f"{k}s: Q in [{lo:.4g}, {hi:.4g}] (spread {hi - lo:.4g})" for k, (lo, hi) in self.spreads().items())
        text = (f"{self.status}: {self.contour.name}, {self.s.size} points at {self.speed:g}/s "
                f"({self.kinetic} kinetic energy, {self.equations} equations): {spread}; power balance within "
                f"{self.max_imbalance:.2g} of the peak power {self.peak_power:.4g}")
        return text + "".join(f"; {p}" for p in self.problems)

    def to_dict(self) -> dict:
        return {"status": str(self.status), "message": self.message, "scriber": self.scriber.to_dict(),
                "contour": self.contour.to_dict(), "speed": self.speed, "kinetic": self.kinetic,
                "equations": self.equations, "s": self.s.tolist(), "time": self.time.tolist(),
                "segment": self.segment.tolist(), "x": self.P.real.tolist(), "y": self.P.imag.tolist(),
                "q": self.q.tolist(), "qd": self.qd.tolist(), "qdd": self.qdd.tolist(), "Q": self.Q.tolist(),
                "energy": self.energy.tolist(), "power": self.power.tolist(), "balance": self.balance.tolist(),
                "peak_power": self.peak_power, "max_imbalance": self.max_imbalance, "work": self.work,
                "spreads": {k: list(v) for k, v in self.spreads().items()},
                "junctions": [dataclasses.asdict(j) for j in self.junctions], "problems": list(self.problems)}


def follow(scriber: Scriber, contour: Contour, speed: float, points: int = 1000, kinetic: str = "corrected",
           equations: str = "corrected", min_sine: float = SINGULAR_SINE) -> PathForces:
    """The scriber's driving forces along ``contour`` at constant ``speed`` (``points`` midpoints of equal length).

    Poses out of stroke (q_i ≥ l_i) or singular (|sin(θ2 − θ1)| < ``min_sine``)
    stop the run: the result holds the points before them (status STOPPED)
    and its message names the arc length and the point where the contour
    leaves the scriber's reach; a contour that starts there is refused. Every
    junction reached reports its corner and the jumps of q̈ and Q (D-13).
    """
    if not (math.isfinite(speed) and speed > 0):
        raise InputError(f"speed: must be a number > 0, got {speed!r}")
    if not (isinstance(points, int) and 2 <= points <= MAX_POINTS):
        raise InputError(f"points: an integer from 2 to {MAX_POINTS:,}, got {points!r}")
    _kinetic(kinetic)
    sample = contour.sample(points, speed)
    problems = []
    status = Status.COMPLETE
    ends = np.cumsum([seg.length for seg in contour.segments])
    at = np.concatenate([sample["s"], [0.0], ends])               # the samples, the start and every junction
    ok = scriber.check(contour.at(at, speed)["P"], min_sine)
    bad = ~ok["stroke"] | ok["singular"]
    if np.any(bad):  # the run stops where the contour leaves what the scriber can make
        end = float(np.min(at[bad]))
        first = int(np.searchsorted(sample["s"], end))              # the samples before it
        where, what = _leaves(scriber, contour, speed, min_sine, sample["s"][first - 1] if first else 0.0, end)
        P = contour.at(np.array([where]), speed)["P"][0]
        if first == 0:
            raise InputError(f"{contour.name}: the contour leaves the scriber's reach at s = {where:.6g} (x = "
                             f"{P.real:.6g}, y = {P.imag:.6g}): {what}, before its first sample point")
        problems.append(f"the contour leaves the scriber's reach at s = {where:.6g} (x = {P.real:.6g}, "
                        f"y = {P.imag:.6g}): {what}; stopped there, {first:,} of {points:,} points done")
        status = Status.STOPPED
        sample = {k: v[:first] for k, v in sample.items()}
    P, V, A = sample["P"], sample["V"], sample["A"]
    q, th, qd, qdd = scriber.rates(P, V, A)
    f = scriber.forces(q, th, qd, qdd, kinetic, equations)
    junctions = []
    corners = contour.corners()
    for k, corner in enumerate(corners):
        if status is Status.STOPPED and ends[k] >= where:
            break
        a = contour.segments[k]
        b = contour.segments[(k + 1) % len(contour.segments)]
        if corner > CORNER:
            problems.append(f"junction {k + 1} (s = {ends[k]:.6g}) is a corner of {math.degrees(corner):.4g}°: "
                            "the velocities jump there, the forces are impulses")
        sides = []
        for seg, side in ((a, "end"), (b, "start")):
            local = seg.length if side == "end" else 0.0
            Pk, Vk, Ak = seg.at(np.array([local]), speed)
            qk, thk, qdk, qddk = scriber.rates(Pk, Vk, Ak)
            sides.append((qddk[:, 0], scriber.forces(qk, thk, qdk, qddk, kinetic, equations)["Q"][0]))
        (qdd0, Q0), (qdd1, Q1) = sides
        junctions.append(Junction(k + 1, float(ends[k]), corner, tuple(map(float, qdd1 - qdd0)),
                                  tuple(map(float, Q1 - Q0))))
    return PathForces(scriber, contour, float(speed), kinetic, equations, sample["s"], sample["s"] / speed,
                      sample["segment"], P, q, qd, qdd, f["Q"], f["energy"], f["power"], f["energy_rate"],
                      tuple(junctions), status, tuple(problems), min_sine)


def _leaves(scriber: Scriber, contour: Contour, speed: float, min_sine: float, good: float, bad: float):
    """Where, between arc lengths ``good`` and ``bad``, the contour leaves the poses the scriber can make (located
    by halving to 1e-12 of the contour's length), and what it meets there."""
    def fails(s):
        ok = scriber.check(contour.at(np.array([s]), speed)["P"], min_sine)
        if not ok["stroke"][0]:
            return "the stroke ends there (out of stroke beyond it: q ≥ l or q ≤ 0)"
        return "P reaches the line AB there (a singular pose)" if ok["singular"][0] else ""

    if fails(good):
        return good, fails(good)
    while bad - good > 1e-12 * contour.length:
        mid = 0.5 * (good + bad)
        good, bad = (good, mid) if fails(mid) else (mid, bad)
    return bad, fails(bad)


@dataclass(frozen=True)
class ScriberTask:
    """A scriber task file: the mechanism, the contour, the head's speed and the number of sample points."""

    name: str
    scriber: Scriber
    contour: Contour
    speed: float
    points: int = 1000

    @classmethod
    def from_dict(cls, data, source: str) -> "ScriberTask":
        """``{"scriber": {...}, "contour": {...}, "speed": v, "points": n}`` (format in ``docs/dynamics.md``)."""
        check_keys(data, {"name", "comment", "scriber", "contour", "speed", "points"}, {"scriber", "contour", "speed"},
                   source)
        scriber = Scriber.from_dict(data["scriber"], source) if isinstance(data["scriber"], dict) else None
        if scriber is None:
            raise InputError(f"{source}: scriber: expected a table with H (and sa, sb, lengths, masses, branch)")
        speed = read_number(data["speed"], f"{source}: speed", LARGEST)
        if speed <= 0:
            raise InputError(f"{source}: speed: must be > 0, got {speed!r}")
        points = data.get("points", 1000)
        if not (isinstance(points, int) and not isinstance(points, bool) and 2 <= points <= MAX_POINTS):
            raise InputError(f"{source}: points: an integer from 2 to {MAX_POINTS:,}, got {points!r}")
        name = str(data.get("name", source))
        contour = data["contour"]
        if isinstance(contour, dict) and "name" not in contour:
            contour = {"name": name, **contour}
        return cls(name, scriber, Contour.from_dict(contour, source), speed, points)

__all__ = ["EQUATIONS", "KINETIC", "Junction", "MAX_POINTS", "PathForces", "SINGULAR_SINE", "Scriber", "ScriberTask",
           "follow"]
