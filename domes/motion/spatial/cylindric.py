"""The RCCC (and 4C) linkage in closed form: the coupler's pose at an input, both assembly modes.

Four joint lines in the drawn pose: z0 (the R joint, ground–driver; point
``F``, direction ``v``), z1 (C, driver–coupler; ``M``, ``u0``), z2 (C,
coupler–follower; ``D``, ``w0``), z3 (C, ground–follower; ``G``, ``vs``).
The directions move as a spherical four-bar (its image:
:class:`~domes.motion.spatial.spherical.SphericalFourBar`), which gives the
follower's turn ψ and so the coupler's rotation (it carries ``u0`` to
``u(θ)`` and ``w0`` to ``w(ψ)``). The coupler then slides along z1 by σ;
z2 must keep its common normal with z3, which is affine in σ (digest
seed-004 §2.7): ``σ = (h·|vs × w| − f0) / k`` with ``k = u·(vs × w)``; ``k = 0``
is the translational singularity, reported.

>>> import numpy as np
>>> lines = [((0, 0, 0), (0.1, 0.2, 1.0)), ((30, 5, 10), (0.3, -0.2, 1.0)), ((60, 40, 5), (-0.2, 0.4, 1.0)),
...          ((20, 60, -5), (0.1, -0.3, 1.0))]
>>> C, d, slide = RCCCLinkage.make(lines).coupler(0.0)
>>> bool(np.allclose(C, np.eye(3)) and np.allclose(d, 0) and abs(slide) < 1e-12)
True
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError, NumericalError
from domes.model.spatial import SpatialMechanism
from domes.motion.spatial.spherical import SphericalFourBar, _rotate


@dataclass(frozen=True)
class RCCCLinkage:
    """Joint lines ``(point, unit direction)`` z0 (R), z1, z2, z3 (C) in the drawn pose."""

    lines: tuple

    @classmethod
    def make(cls, lines) -> "RCCCLinkage":
        out = []
        for p, u in lines:
            u = np.asarray(u, float)
            out.append((np.asarray(p, float), u / np.linalg.norm(u)))
        if len(out) != 4:
            raise InputError("an RCCC has four joint lines z0 .. z3")
        return cls(tuple(out))

    @classmethod
    def of(cls, mech: SpatialMechanism) -> "RCCCLinkage":
        """From a file: four links, an R joint on the ground driven, three C joints in a loop."""
        kinds = sorted(j.kind for j in mech.joints)
        if len(mech.links) != 4 or kinds != ["C", "C", "C", "R"] or len(mech.inputs) != 1:
            raise InputError(f"{mech.name}: not an RCCC (four links, joints R, C, C, C, one input)")
        z0 = mech.joint(mech.inputs[0].joint)
        if z0.kind != "R" or mech.ground not in z0.links:
            raise InputError(f"{mech.name}: the RCCC's input is its R joint on the ground")
        driver = next(x for x in z0.links if x != mech.ground)
        z1 = next(j for j in mech.joints_of(driver) if j.name != z0.name)
        coupler = next(x for x in z1.links if x != driver)
        z2 = next(j for j in mech.joints_of(coupler) if j.name != z1.name)
        z3 = next(j for j in mech.joints if j.name not in (z0.name, z1.name, z2.name))
        sign = 1.0 if z0.links[0] == mech.ground else -1.0
        return cls.make([(z0.at, sign * np.asarray(z0.axis)), (z1.at, z1.axis), (z2.at, z2.axis), (z3.at, z3.axis)])

    @property
    def image(self) -> SphericalFourBar:
        (_, v), (_, u0), (_, w0), (_, vs) = self.lines
        return SphericalFourBar.make(v, u0, w0, vs)

    def coupler(self, theta: float, branch: int | None = None, slide: float = 0.0) -> tuple[np.ndarray, np.ndarray, float]:
        """The coupler's displacement ``x ↦ C x + d`` from the drawn pose at input ``theta``, and its slide σ
        along z1. ``slide`` moves the driver along z0: a 4C (whose z0 is cylindric) driven by both.
        Raises :class:`~domes.errors.NumericalError` where it does not assemble or is singular."""
        (F, v), (M, u0), (D, w0), (G, vs) = self.lines
        image = self.image
        psi = float(image.psi(theta, branch))
        if not math.isfinite(psi):
            raise NumericalError(f"the RCCC does not assemble at input {math.degrees(theta):.6g}°", kind="limit",
                                 where={"input": theta})
        u = _rotate(v, theta, u0)
        w = _rotate(vs, psi, w0)
        C = np.column_stack([u, w, np.cross(u, w)]) @ np.linalg.inv(np.column_stack([u0, w0, np.cross(u0, w0)]))
        Mt = F + slide * v + _rotate(v, theta, M - F)
        n0 = np.cross(vs, w0)
        h = float((D - G) @ n0) / np.linalg.norm(n0)        # z2–z3 common normal, signed, at the drawn pose
        n = np.cross(vs, w)
        k = float(u @ n)
        base = C @ (D - M) + Mt
        f0 = float((base - G) @ n)
        if abs(k) < 1e-12 * np.linalg.norm(n):
            raise NumericalError(f"translational singularity at input {math.degrees(theta):.6g}° (k = 0: the slide "
                                 "along z1 does not move z2 across z3)", kind="singular", where={"input": theta})
        sigma = (h * np.linalg.norm(n) - f0) / k
        d = Mt + sigma * u - C @ M
        return C, d, float(sigma)


__all__ = ["RCCCLinkage"]
