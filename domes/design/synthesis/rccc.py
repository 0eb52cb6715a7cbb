"""Four-position synthesis of a spatial RCCC linkage by solution regions (seed 004, Cao & Han 2016).

Three steps, as the paper does them (digest ``seed-004-rccc.md``):

1. **Directions.** The four orientations give the spherical Burmester
   curves: a moving axis direction ``u`` is a circle point when
   ``det[(C_j − I) u] = 0`` (j = 1..3); its fixed partner ``v`` is the null
   vector of that matrix (where two of its rows vanish, at an axis two
   displacements share, ``v`` is not unique and is refused). Two circle
   points make the spherical image (region 1).
2. **Positions.** With the directions fixed, the moment equations of a CC
   dyad are linear: five equations in the feet ``M`` (moving axis) and ``F``
   (fixed axis) of the dyad's common normal; their solutions are a pair of
   lines ``(M, F)(t) = x_p + t n`` (the solution lines). Any point on the
   driver's lines and any on the follower's give a 4C that meets the four
   poses exactly (region 2).
3. **The R joint.** The driver's slide on its fixed axis between the poses
   is affine in ``t``, ``Δs_j = a_j + b_j t``; an exact R joint needs the
   three zeros to coincide, which four general poses do not allow. The
   driver point is chosen by the min–max of the slides; locking the slide
   keeps the coupler's orientations exact and moves its translations; the
   result is labelled **exact** or **approximate** with its pose errors from
   the general spatial solver.

Poses come with an explicit orientation convention (:func:`pose_rotation`):
the paper never says how its (azimuth, longitude, latitude) become a
rotation, so no convention is implied.

>>> import numpy as np
>>> R = pose_rotation((15, 90, 0), "lon-lat-roll")
>>> bool(np.allclose(R @ R.T, np.eye(3)))
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialInput, SpatialJoint, SpatialMechanism

#: Named orientation conventions: how three angles (degrees) make a rotation.
CONVENTIONS = ("lon-lat-roll", "zyx", "zyz", "xyz")
#: Twists below this (rad) are reported: the common normal of nearly parallel axes is ill conditioned.
SMALL_TWIST = math.radians(10.0)


def _rx(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def _ry(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def _rz(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def pose_rotation(angles, convention: str) -> np.ndarray:
    """A rotation from three angles (degrees) by a named ``convention``:

    - ``lon-lat-roll``: the table of seed 004 read as (azimuth δ, longitude α, latitude β),
      ``Rz(α) Ry(−β) Rx(δ)`` (the digest's assumed reading; the paper's own is unknown);
    - ``zyx``, ``zyz``, ``xyz``: intrinsic Euler sequences of the three angles in order.
    """
    if convention not in CONVENTIONS:
        raise InputError(f"orientation convention: one of {', '.join(CONVENTIONS)} (the paper names none; say which "
                         f"you use), got {convention!r}")
    a = [math.radians(float(x)) for x in angles]
    if len(a) != 3 or not all(math.isfinite(x) for x in a):
        raise InputError(f"three finite angles (degrees), got {list(angles)}")
    if convention == "lon-lat-roll":
        delta, lon, lat = a
        return _rz(lon) @ _ry(-lat) @ _rx(delta)
    axes = {"x": _rx, "y": _ry, "z": _rz}
    R = np.eye(3)
    for name, x in zip(convention, a):
        R = R @ axes[name](x)
    return R


@dataclass(frozen=True)
class Displacement:
    """The rigid displacement from pose 1 to pose j+1: ``x ↦ C x + d``."""

    C: np.ndarray
    d: np.ndarray

    def line(self, u, moment):
        """A line (direction ``u``, moment ``ū = P × u``) moved: ``(C u, C ū + d × C u)``."""
        cu = self.C @ u
        return cu, self.C @ moment + np.cross(self.d, cu)


def displacements(rotations, positions) -> list[Displacement]:
    """Relative displacements ``C_j = R_{j+1} R_1ᵀ``, ``d_j = p_{j+1} − C_j p_1`` of four (or more) poses."""
    R = [np.asarray(r, float) for r in rotations]
    p = [np.asarray(x, float) for x in positions]
    if len(R) != len(p) or len(R) < 2:
        raise InputError("give a rotation and a position for each pose")
    for k, r in enumerate(R):
        if r.shape != (3, 3) or np.max(np.abs(r @ r.T - np.eye(3))) > 1e-9 or np.linalg.det(r) < 0:
            raise InputError(f"pose {k + 1}: the orientation is not a rotation")
    out = []
    for k in range(1, len(R)):
        C = R[k] @ R[0].T
        out.append(Displacement(C, p[k] - C @ p[0]))
    return out


def check_task(moves: list[Displacement]) -> list[str]:
    """The degenerate inputs of TC-8 (a, b): poses with one orientation, rotations all about one axis."""
    problems = []
    axes = []
    for j, m in enumerate(moves, 2):
        angle = math.acos(max(-1.0, min(1.0, (np.trace(m.C) - 1) / 2)))
        if angle < 1e-9:
            problems.append(f"pose {j} has the orientation of pose 1 (a pure translation): its direction equation "
                            "vanishes")
            continue
        w = np.array([m.C[2, 1] - m.C[1, 2], m.C[0, 2] - m.C[2, 0], m.C[1, 0] - m.C[0, 1]])
        axes.append(w / np.linalg.norm(w))
    if len(axes) >= 2 and all(abs(abs(a @ axes[0]) - 1) < 1e-9 for a in axes[1:]):
        problems.append("every rotation is about one axis: the Burmester cone degenerates (a planar-type motion)")
    return problems


# -- step 1: directions --------------------------------------------------------------------------

def burmester_matrix(moves, u) -> np.ndarray:
    return np.array([(m.C - np.eye(3)) @ u for m in moves])


def circle_determinant(moves, u) -> float:
    """``det[(C_j − I) u]``: zero on the circle-point cone."""
    return float(np.linalg.det(burmester_matrix(moves, u)))


def centre_point(moves, u, tol: float = 1e-9) -> np.ndarray:
    """The fixed axis ``v`` paired with circle point ``u`` (the null vector); refused where the rank is below 2 (a
    pole shared by two displacements: a family of ``v``)."""
    B = burmester_matrix(moves, u)
    _, s, vt = np.linalg.svd(B)
    if s[1] <= tol * max(s[0], 1e-300):
        raise InputError("this circle point is a pole (the axis of a displacement): its centre point is not unique")
    return vt[-1]


def _meridian(lam: float):
    def u(t):
        return np.array([math.cos(t) * math.cos(lam), math.cos(t) * math.sin(lam), math.sin(t)])
    return u


def circle_points(moves, meridians: int = 180, samples: int = 720, where: bool = False) -> list:
    """Circle points on meridian half-planes (longitude λ in [0°, 180°)): the roots of the cone's cubic there.
    With ``where``, each comes as ``(λ, t, u)`` (its meridian and latitude)."""
    if len(moves) != 3:
        raise InputError(f"four poses (three displacements), got {len(moves) + 1}")
    out = []
    for lam in np.radians(np.arange(meridians) * 180.0 / meridians):
        u = _meridian(lam)
        ts = np.linspace(-math.pi / 2, math.pi / 2, samples + 1)
        f = np.array([circle_determinant(moves, u(t)) for t in ts])
        for k in np.flatnonzero(np.sign(f[1:]) != np.sign(f[:-1])):
            t = brentq(lambda x: circle_determinant(moves, u(x)), ts[k], ts[k + 1], xtol=1e-15)
            out.append((float(lam), float(t), u(t)) if where else u(t))
    return out


def _circle_point_near(moves, lam: float, t0: float, width: float):
    """The circle point on meridian ``lam`` near latitude ``t0`` (None when the curve leaves the bracket)."""
    u = _meridian(lam)
    a, b = t0 - width, t0 + width
    fa, fb = circle_determinant(moves, u(a)), circle_determinant(moves, u(b))
    if fa * fb > 0:
        return None
    return u(brentq(lambda x: circle_determinant(moves, u(x)), a, b, xtol=1e-15))


# -- step 2: solution lines ------------------------------------------------------------------------

@dataclass(frozen=True)
class SolutionLines:
    """The CC dyad of directions ``u`` (moving) and ``v`` (fixed): ``(M, F)(t) = base + t·direction`` (6-vectors);
    ``singular``: the ratio of the fifth to the first singular value of the 5 × 6 system."""

    u: np.ndarray
    v: np.ndarray
    base: np.ndarray
    direction: np.ndarray
    singular: float

    def feet(self, t: float) -> tuple[np.ndarray, np.ndarray]:
        x = self.base + t * self.direction
        return x[:3], x[3:]

    @property
    def twist(self) -> float:
        return float(math.acos(min(1.0, abs(float(self.u @ self.v)))))


def solution_lines(moves, u, v) -> SolutionLines:
    """The solution lines of a CC dyad with directions ``u`` (moving, pose 1) and ``v`` (fixed), eq. (23)."""
    u, v = (np.asarray(x, float) / np.linalg.norm(x) for x in (u, v))
    if abs(abs(u @ v) - 1) < 1e-12:
        raise InputError("the dyad's axes are parallel: its common normal, and the slide, are not defined")
    rows, rhs = [], []
    for m in moves:
        c = (m.C.T - np.eye(3)) @ v
        d = (m.C - np.eye(3)) @ u
        rows.append(np.concatenate([np.cross(u, c), np.cross(v, d)]))
        rhs.append(-float(v @ np.cross(m.d, m.C @ u)))
    rows += [np.concatenate([u, -u]), np.concatenate([v, -v])]
    rhs += [0.0, 0.0]
    A, b = np.array(rows), np.array(rhs)
    _, s, vt = np.linalg.svd(A)
    ratio = float(s[4] / s[0]) if s[0] > 0 else 0.0
    if ratio < 1e-10:
        raise InputError(f"the moment equations of this dyad have rank below 5 (σ5/σ1 = {ratio:.2g}): a family or "
                         "no solution; choose another circle point")
    base = np.linalg.lstsq(A, b, rcond=None)[0]
    return SolutionLines(u, v, base, vt[-1], ratio)


def foot_on(a, v, b, u) -> np.ndarray:
    """The foot on line ``(a, v)`` of its common normal with line ``(b, u)`` (unit directions)."""
    c = float(u @ v)
    w = a - b
    return a + ((c * float(u @ w) - float(v @ w)) / (1 - c * c)) * v


def slides(moves, lines: SolutionLines, t: float) -> np.ndarray:
    """``Δs_j``: how far the driver slides along its fixed axis from pose 1 to pose j+1 at line parameter ``t``."""
    M, F = lines.feet(t)
    out = []
    for m in moves:
        uj = m.C @ lines.u
        Mj = m.C @ M + m.d
        out.append(float(lines.v @ (foot_on(F, lines.v, Mj, uj) - F)))
    return np.array(out)


def minmax_slide(moves, lines: SolutionLines) -> tuple[float, float, np.ndarray, np.ndarray]:
    """``(t*, max_j |Δs_j(t*)|, a, b)``: the min–max of the three affine slides ``a_j + b_j t``."""
    a = slides(moves, lines, 0.0)
    b = slides(moves, lines, 1.0) - a
    cands = [0.0]
    for i in range(len(a)):
        if b[i]:
            cands.append(-a[i] / b[i])
        for k in range(i + 1, len(a)):
            for sign in (1, -1):
                den = b[i] - sign * b[k]
                if den:
                    cands.append((sign * a[k] - a[i]) / den)
    worst = [float(np.max(np.abs(a + b * t))) for t in cands]
    k = int(np.argmin(worst))
    return cands[k], worst[k], a, b


# -- step 3: the RCCC and its errors ----------------------------------------------------------------

@dataclass(frozen=True)
class RCCCSolution:
    """A synthesised RCCC: its four joint lines (point, direction) at pose 1, the input angles ``thetas`` at the
    poses, the driver's slides, the pose errors (rotation in rad, translation in length) from the spatial solver,
    ``exact`` when every error is below the tolerance, and ``notes`` (degenerate or ill-conditioned choices)."""

    lines: tuple[tuple[np.ndarray, np.ndarray], ...]
    thetas: tuple[float, ...]
    slides: tuple[float, ...]
    rotation_errors: tuple[float, ...]
    translation_errors: tuple[float, ...]
    exact: bool
    notes: tuple[str, ...] = field(default=())

    @property
    def label(self) -> str:
        return "exact" if self.exact else "approximate"

    @property
    def message(self) -> str:
        return (f"{self.label} RCCC: driver slides {', '.join(f'{s:.3g}' for s in self.slides)}; pose errors: "
                f"rotation ≤ {max(self.rotation_errors):.2g} rad, translation ≤ {max(self.translation_errors):.3g}"
                + "".join(f"; {n}" for n in self.notes))

    def mechanism(self) -> SpatialMechanism:
        """The RCCC as a spatial mechanism in pose 1 (z0 the driven R joint)."""
        return rccc_mechanism(self.lines)


def rccc_mechanism(lines) -> SpatialMechanism:
    """An RCCC from its four joint lines ``(point, direction)`` z0 (R, driver–ground), z1, z2, z3 (C) at pose 1."""
    names = ("frame", "driver", "coupler", "follower")
    pairs = (("frame", "driver"), ("driver", "coupler"), ("coupler", "follower"), ("frame", "follower"))
    joints = tuple(SpatialJoint(f"z{k}", "R" if k == 0 else "C", pairs[k], tuple(map(float, p)), tuple(map(float, u)))
                   for k, (p, u) in enumerate(lines))
    return SpatialMechanism.build("RCCC (seed 004 synthesis)", names, "frame", joints, (SpatialInput("z0"),))


def input_angle(moves, lines: SolutionLines) -> list[float]:
    """``θ_j``: the signed angle about ``v`` from ``u`` to ``C_j u`` (their projections), the driver's turns."""
    v = lines.v
    out = []
    for m in moves:
        a = lines.u - (lines.u @ v) * v
        b = m.C @ lines.u - (m.C @ lines.u @ v) * v
        out.append(float(math.atan2(v @ np.cross(a, b), a @ b)))
    return out


def rotation_angle(R: np.ndarray) -> float:
    """The angle of a rotation matrix, accurate near 0 (``atan2`` of its skew and symmetric parts)."""
    sine = 0.5 * math.sqrt((R[2, 1] - R[1, 2]) ** 2 + (R[0, 2] - R[2, 0]) ** 2 + (R[1, 0] - R[0, 1]) ** 2)
    return float(math.atan2(sine, (np.trace(R) - 1) / 2))


def pose_errors(mech: SpatialMechanism, thetas, moves) -> tuple[list[float], list[float]]:
    """Drive the mechanism from pose 1 to each ``θ_j`` (a continuous sweep) and compare its coupler with the
    poses: the rotation error (rad) and the translation error of the displacement ``x ↦ C x + d``."""
    from domes.motion.spatial.loops import Loops
    from domes.motion.spatial.sweep import spatial_sweep

    kin = Loops(mech)
    k = kin.index["coupler"]
    rot, trans = [], []
    for theta, m in zip(thetas, moves):
        sw = spatial_sweep(mech, 0.0, theta, math.radians(2.0))
        if sw.limit is not None:
            raise InputError(f"the RCCC does not reach the input {math.degrees(theta):.4g}° from pose 1: "
                             f"{sw.limit.message}")
        s = sw.states[-1]
        R = s.R[k]
        d = s.o[k] * kin.scale - R @ (kin.centre[k] * kin.scale)
        rot.append(rotation_angle(m.C.T @ R))
        trans.append(float(np.linalg.norm(d - m.d)))
    return rot, trans


def rccc(moves, driver: tuple, follower: tuple, t_follower: float = 0.0, tolerance: float = 1e-9) -> RCCCSolution:
    """The RCCC from two Burmester pairs ``(u, v)`` (driver, follower): the driver's point by the min–max of its
    slides, the follower's at ``t_follower`` on its lines; errors from the spatial solver at the driver's angles."""
    notes = check_task(moves)
    d = solution_lines(moves, *driver)
    f = solution_lines(moves, *follower)
    for name, lines in (("driver", d), ("follower", f)):
        if lines.twist < SMALL_TWIST:
            notes.append(f"the {name}'s twist is {math.degrees(lines.twist):.3g}°: nearly parallel axes make its "
                         "common normal ill conditioned")
    t, worst, a, b = minmax_slide(moves, d)
    for j, bj in enumerate(b, 2):
        if abs(bj) < 1e-12 and abs(a[j - 2]) > 0:
            notes.append(f"the slide to pose {j} does not depend on the driver's point: no zero-slide point")
    M, F = d.feet(t)
    D, Fs = f.feet(t_follower)
    lines = ((F, d.v), (M, d.u), (D, f.u), (Fs, f.v))
    thetas = input_angle(moves, d)
    size = max(1.0, max(float(np.linalg.norm(m.d)) for m in moves))
    rot, trans = pose_errors(rccc_mechanism(lines), thetas, moves)
    exact = max(rot) <= tolerance and max(trans) <= tolerance * size
    return RCCCSolution(lines, tuple(thetas), tuple(map(float, a + b * t)), tuple(rot), tuple(trans), exact,
                        tuple(notes))


def _rotate(axis, angle, x):
    return x * math.cos(angle) + np.cross(axis, x) * math.sin(angle) + axis * (axis @ x) * (1 - math.cos(angle))


def defects(moves, driver: tuple, follower: tuple, samples: int = 90) -> list[str]:
    """Defects of the spherical image (digest §2.7): the four poses on different assembly branches, a pose the
    driver cannot reach from pose 1 without the image coming apart, the poses out of order along the input.
    ``driver`` and ``follower`` are ``(u, v)`` pairs; an empty list: defect free."""
    (u0, v), (w0, vs) = driver, follower
    base = w0 - (w0 @ vs) * vs
    side = np.cross(vs, w0)
    target = float(u0 @ w0)

    def branches(theta):
        u = _rotate(v, theta, u0)
        A, B = float(u @ base), float(u @ side)
        C = target - float(w0 @ vs) * float(u @ vs)
        r = math.hypot(A, B)
        if r == 0 or abs(C) > r:
            return None
        phase, spread = math.atan2(B, A), math.acos(C / r)
        return phase + spread, phase - spread

    first = branches(0.0)
    if first is None:
        return ["the image does not assemble in pose 1"]
    sign = 0 if abs(math.remainder(first[0], 2 * math.pi)) <= abs(math.remainder(first[1], 2 * math.pi)) else 1
    thetas = input_angle(moves, SolutionLines(u0, v, np.zeros(6), np.zeros(6), 1.0))
    out = []
    for j, (theta, m) in enumerate(zip(thetas, moves), 2):     # the branch of each pose (cheap) first
        got = branches(theta)
        if got is None:
            out.append(f"pose {j}: the image does not assemble there")
            continue
        wj = m.C @ w0
        b = wj - (wj @ vs) * vs
        psi = math.atan2(float(vs @ np.cross(base, b)), float(base @ b))
        if int(np.argmin([abs(math.remainder(g - psi, 2 * math.pi)) for g in got])) != sign:
            out.append(f"pose {j} lies on the other assembly branch")
    if out:
        return out
    far = max(thetas, key=abs)                                 # then the way there, every quarter degree
    for x in np.linspace(0.0, far, max(samples, int(abs(math.degrees(far)) * 4)))[1:]:
        if branches(x) is None:
            out.append(f"the image comes apart at input {math.degrees(x):.4g}° on the way from pose 1")
            break
    if not (all(a < b for a, b in zip([0.0] + thetas, thetas)) or all(a > b for a, b in zip([0.0] + thetas, thetas))):
        out.append("the poses are out of order along the input (" +
                   ", ".join(f"{math.degrees(t):.4g}°" for t in thetas) + ")")
    return out


def drivers(moves, meridians: int = 180, refine: int = 3) -> list[tuple[float, np.ndarray, np.ndarray, float]]:
    """Driver dyads on the circle-point curve with their best R joints: ``(max |Δs|, u, v, t*)``, best first;
    the ``refine`` best are refined along the curve (bounded search over the meridian). Circle points at a
    shared pole or with a rank-deficient moment system are left out."""
    from scipy.optimize import minimize_scalar

    def score(u):
        try:
            v = centre_point(moves, u)
            lines = solution_lines(moves, u, v)
        except InputError:
            return None
        t, worst, _, _ = minmax_slide(moves, lines)
        return worst, u, v, t

    found = [(lam, t, x) for lam, t, x, in circle_points(moves, meridians, where=True)]
    out = []
    for lam, t, u in found:
        got = score(u)
        if got is not None:
            out.append((*got, lam, t))
    out.sort(key=lambda x: x[0])
    half = math.pi / meridians
    refined = []
    for worst, u, v, t_star, lam, t in out[:refine]:
        def objective(x, t=t):
            p = _circle_point_near(moves, x, t, 4 * half)
            got = None if p is None else score(p)
            return math.inf if got is None else got[0]
        best = minimize_scalar(objective, bounds=(lam - half, lam + half), method="bounded",
                               options={"xatol": 1e-15, "maxiter": 2000})
        candidates = [best.x]

        def zeros(x, i, k, t=t):
            """The difference of two slides' zero parameters along the curve (a root: they coincide)."""
            p = _circle_point_near(moves, x, t, 4 * half)
            if p is None:
                return math.nan
            try:
                lines = solution_lines(moves, p, centre_point(moves, p))
            except InputError:
                return math.nan
            a = slides(moves, lines, 0.0)
            b = slides(moves, lines, 1.0) - a
            return float(-a[i] / b[i] + a[k] / b[k]) if b[i] and b[k] else math.nan

        for i, k in ((0, 1), (0, 2), (1, 2)):       # where two zeros coincide, the V of the min-max is sharp
            lo, hi = best.x - half / 8, best.x + half / 8
            flo, fhi = zeros(lo, i, k), zeros(hi, i, k)
            if math.isfinite(flo) and math.isfinite(fhi) and flo * fhi < 0:
                candidates.append(brentq(lambda x: zeros(x, i, k), lo, hi, xtol=1e-15))
        for x in candidates:
            p = _circle_point_near(moves, x, t, 4 * half)
            got = None if p is None else score(p)
            if got is not None and got[0] < worst:
                worst, u, v, t_star = got
        refined.append((worst, u, v, t_star))
    result = refined + [x[:4] for x in out[refine:]]
    result.sort(key=lambda x: x[0])
    return result


def search(moves, meridians: int = 180, tolerance: float = 1e-9, tries: int = 40) -> RCCCSolution:
    """An RCCC for four poses: drivers in order of their min–max slide, each paired with the followers whose
    spherical image is defect free (:func:`defects`), the farthest in direction first; the first that reaches
    the four poses is labelled exact or approximate by its pose errors."""
    found = drivers(moves, meridians)
    if not found:
        raise InputError("no circle point gives a driver dyad (every one at a pole or rank deficient)")
    reasons = []
    for _, u, v, _ in found[:tries]:
        others = sorted(found, key=lambda x: abs(float(x[1] @ u)))
        for _, w, vf, _ in others:
            if abs(float(w @ u)) > 0.999 or defects(moves, (u, v), (w, vf)):
                continue
            try:
                sol = rccc(moves, (u, v), (w, vf), tolerance=tolerance)
            except (InputError, NumericalError) as exc:
                reasons.append(str(exc))
                continue
            if max(sol.rotation_errors) <= 1e-6:
                return sol
            reasons.append("the orientations are missed")
    raise InputError(f"no defect-free RCCC among the {tries} best drivers and their followers"
                     + (f" ({reasons[-1]})" if reasons else ": every pairing has a branch, assembly or order defect"))


__all__ = ["defects", "drivers", "search", "CONVENTIONS", "Displacement", "RCCCSolution", "SolutionLines", "burmester_matrix", "centre_point",
           "check_task", "circle_determinant", "circle_points", "displacements", "foot_on", "input_angle",
           "minmax_slide", "pose_errors", "rccc_mechanism", "rotation_angle", "pose_rotation", "rccc", "slides", "solution_lines"]
