"""Which Watt or Stephenson six-bar traces this closed path? Atlas look-up, a short fit of every candidate,
then full refinement of the most promising, best first.

:func:`match_sixbars` looks the path up in a
:class:`~domes.motion.coupler.sixatlas.SixAtlas`, gives each candidate a
short least-squares run (:data:`QUICK` evaluations, the model's error), and
refines the nearest of them in turn (:func:`~domes.motion.coupler.sixfit.sixfit`,
verified by the kernel) until ``results`` distinct six-bars fit within
``tol``. Fits that are one linkage (the same joints' places, or the same
frame pivots and link lengths when the path is symmetric: a mirror image
or turned copy) are merged.

>>> from domes.motion.coupler.sixatlas import SixAtlas
>>> atlas = SixAtlas.build(per_kind=6)
>>> path = atlas.sixbar(40).curve(np.linspace(0, 2 * np.pi, 48, endpoint=False))
>>> fits, merged, tried = match_sixbars(np.c_[path.real, path.imag] * 2, atlas, tol=1e-6, candidates=4)
>>> fits[0].success
True
"""

from __future__ import annotations

import numpy as np

from domes.errors import InputError
from domes.motion.coupler.match import _merge
from domes.motion.coupler.sixatlas import SixAtlas
from domes.motion.coupler.sixfit import SixFit, sixfit

#: Candidates looked up and given a short fit.
CANDIDATES = 24
#: Evaluations of each candidate's short fit.
QUICK = 12
#: Candidates refined fully at most (the best of the short fits first; the refinement stops at the first fit, so
#: only a path none of the first few fits goes further down the list: a Stephenson curve's nearest candidates
#: often end in a minimum near it).
REFINED = 12


def match_sixbars(points, atlas: SixAtlas, results: int = 1, tol: float = 1e-6, candidates: int = CANDIDATES,
                  refined: int = REFINED):
    """``(fits, merged, tried)``: the six-bars fitted to the closed path through ``points``, best first, the fits
    merged into each (with how they repeat it), and the candidates tried."""
    found = atlas.lookup(points, k=candidates)
    quick = []
    for cand in found:
        try:
            quick.append(sixfit(points, cand.sixbar, tol, quick=QUICK))
        except InputError:
            continue
    quick.sort(key=lambda f: f.after[0])
    fits: list[SixFit] = []
    for q in quick[:refined]:
        x, mirror, kind = q.mechanism
        f = sixfit(points, (x.copy(), mirror, kind), tol)
        fits.append(f)
        if sum(g.success for g in fits) >= results:
            break
    fits.sort(key=lambda f: (not f.success, f.mechanism is None, f.after[0]))
    kept, merged = _merge(fits, fits[0].size, relation) if fits else ([], [])
    shown = max(results, sum(f.success for f in kept))          # every fit, else the nearest ``results``
    return kept[:shown], merged[:shown], len(quick)


def _signature(f: SixFit):
    """What does not change when a six-bar is moved, turned or mirrored: its type, the frame pivots' distances
    and the link lengths."""
    at = {j.name: complex(*j.at) for j in f.mechanism.joints}
    pivots = sorted([abs(at["A"] - at["D"]), abs(at["A"] - at["G"]), abs(at["D"] - at["G"])])
    return f.kind, np.array([*pivots, *f.lengths, abs(complex(*f.ternary)), abs(complex(*f.coupler))]), at


def relation(f: SixFit, g: SixFit, tol: float) -> str:
    """How ``g`` repeats ``f`` (the same linkage, or a mirror image or turned copy), or "" when it is another."""
    if f.mechanism is None or g.mechanism is None:
        return ""
    kf, sf, af = _signature(f)
    kg, sg, ag = _signature(g)
    if kf != kg or np.max(np.abs(sf - sg)) > tol:
        return ""
    if all(abs(af[n] - ag[n]) <= tol for n in "ADG"):
        return "the same linkage (another assembly mode or pose)"
    return "the same linkage placed otherwise (its mirror image or a turned copy: the path is symmetric)"
