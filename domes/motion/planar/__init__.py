"""The planar kinematics backend: link units, Assur groups, closed-form dyads, Newton, sweeps and checks.

Its public functions are those of :mod:`domes.motion`.
"""
