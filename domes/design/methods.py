"""The dimensioning's methods (the knob of :func:`~domes.design.synthesis.candidate.dimension`): a module of its
own, so that the command line offers them without loading the numerics.

>>> METHODS
('exact', 'fast')
"""

#: Polish the best 12 (exact) or 4 (fast) random layouts of each candidate.
METHODS = ("exact", "fast")
