"""The spatial kinematics backend: loop closure on rigid transforms, and closed forms where they exist.

:class:`~domes.motion.spatial.loops.Loops` solves any spatial mechanism
(R, P, C, S, H joints; one or several loops) by Newton's method with the
analytic Jacobian, with velocities and accelerations; :mod:`~domes.motion.spatial.rssr`
is the closed form of the RSSR linkage (seed 001), both assembly modes, with
its motion type; :func:`~domes.motion.spatial.sweep.spatial_sweep` sweeps an input, its limits located to a
precision they state by :mod:`~domes.motion.spatial.limits` (closed forms where they exist, the fold of the loop
otherwise).
"""
