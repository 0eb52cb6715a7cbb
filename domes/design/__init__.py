"""Design: the dimensional half of the pipeline.

Dimensional verification of a candidate (:mod:`domes.design.verify`) lives
here now; dimensional synthesis, dynamics and tolerances come next.
"""
