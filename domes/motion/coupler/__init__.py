"""Coupler curves: the four-bar design space, curves and their special points, shape descriptors, the atlas.

Seed 002, chapter 6 (digest Part B): backward reasoning from a wanted curve
to a linkage. :mod:`~domes.motion.coupler.designspace` classifies four-bars
(Table 6-1); :mod:`~domes.motion.coupler.fourbar` builds them in the
chapter's convention; curves are traced with the kinematics backend.
"""
