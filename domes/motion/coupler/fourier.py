"""Fourier descriptors of closed curves (seed 002 §6-3, after McGarva; digest B.5.2).

A closed curve ``Z(t) = x(t) + i y(t)`` sampled at ``N`` points has the
coefficients ``a_m = (1/N) Σ Z_k exp(−2πimk/N)`` (6-26). The first harmonic
is an ellipse (6-27)–(6-29): ``a_m = r_m exp(iφ_m)``, major axis at
``α = (φ1 + φ−1)/2``, parameter shift ``β = (φ1 − φ−1)/2`` (the digest's
correction: the book's first statement swaps them). :func:`normalise`
removes translation (``a0 = 0``), rotation (``× e^{−iα}``), scale
(``÷ |a1|``) and start point (``a_m × e^{−imβ}``), leaving ``a1 = 1`` and
``a−1 = r−1/r1`` real in ``[0, 1]`` for a counter-clockwise curve.

Conventions made explicit:

- *Mirror.* Applying the four steps literally gives coefficients whose
  imaginary parts are the negatives of the book's Table 6-2 for every
  ``m ≠ ±1``: the book's table is the complex conjugate (``y → −y``).
  ``convention="book"`` returns the conjugate, ``"literal"`` (the default)
  the literal result.
- *Direction.* A clockwise curve (``|a−1| > |a1|``) is traversed backwards
  (``a_m ↔ a−m``) before normalising, so that a curve and its reversal have
  one descriptor; :class:`Normalised` records it.
- *Ambiguity.* ``α → α + π`` with ``β → β + π`` multiplies ``a_m`` by
  ``(−1)^(m+1)``; principal values of ``φ1, φ−1`` are used, and
  :func:`variants` lists the other reading (and the mirror images) for a
  look-up.

>>> t = np.arange(64) / 64
>>> z = 3 + 2j + 1.5 * np.exp(2j * np.pi * t) + 0.5 * np.exp(-2j * np.pi * t) + 0.1 * np.exp(4j * np.pi * t)
>>> n = normalise(coefficients(z, 5))
>>> round(n.coefficients[1].real, 12), round(n.coefficients[-1].real, 12), round(n.scale, 12)
(1.0, 0.333333333333, 1.5)
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from domes.errors import InputError

#: Harmonics kept by default: m = −5..5 approximate a closed coupler curve well (the book's choice).
HARMONICS = 5


class Coefficients(dict):
    """``{m: a_m}`` for ``m = −M..M`` (a dict, indexed by the harmonic number)."""

    @property
    def harmonics(self) -> int:
        return max(self)

    def vector(self) -> np.ndarray:
        """``[a_−M, ..., a_M]`` as a complex array."""
        return np.array([self[m] for m in range(-self.harmonics, self.harmonics + 1)])

    @classmethod
    def of(cls, vector) -> "Coefficients":
        vector = np.asarray(vector, dtype=complex)
        M = (vector.size - 1) // 2
        return cls({m: complex(vector[m + M]) for m in range(-M, M + 1)})


def coefficients(z, harmonics: int = HARMONICS) -> Coefficients:
    """The coefficients ``a_m`` (6-26) of the closed curve through the complex samples ``z`` (equal steps of t).

    >>> c = coefficients(np.exp(2j * np.pi * np.arange(8) / 8), 2)
    >>> [round(abs(c[m]), 12) for m in (-2, -1, 0, 1, 2)]
    [0.0, 0.0, 0.0, 1.0, 0.0]
    """
    z = np.asarray(z, dtype=complex)
    n = z.size
    if n < 2 * harmonics + 1:
        raise InputError(f"{n} samples cannot give {harmonics} harmonics: at least {2 * harmonics + 1} are needed")
    spectrum = np.fft.fft(z) / n
    return Coefficients({m: complex(spectrum[m % n]) for m in range(-harmonics, harmonics + 1)})


@dataclass(frozen=True)
class Normalised:
    """Normalised coefficients and the transformation that produced them.

    ``translation`` is ``−a0``; ``rotation`` is ``α`` (the curve was turned by
    ``−α``); ``scale`` is ``|a1|`` (divided by it); ``start`` is ``β`` (the
    parameter was shifted by ``β/2π``); ``reversed`` says the curve was
    clockwise and was traversed backwards first; ``mirrored`` says the book's
    conjugate convention was applied.
    """

    coefficients: Coefficients
    translation: complex
    rotation: float
    scale: float
    start: float
    reversed: bool
    mirrored: bool

    def vector(self) -> np.ndarray:
        """The real feature vector used for look-ups: real and imaginary parts of every ``a_m`` but the fixed ones.

        ``a0 = 0``, ``a1 = 1`` and ``Im a−1 = 0`` carry nothing and are left out.
        """
        return features(self.coefficients.vector()[None, :])[0]


def normalise(coeffs: Coefficients, convention: str = "literal") -> Normalised:
    """Remove translation, rotation, scale and start point (steps 1–4 of §6-3); see the module's conventions."""
    if convention not in ("literal", "book"):
        raise InputError(f"convention must be 'literal' or 'book', got {convention!r}")
    c = Coefficients(coeffs)
    if abs(c[1]) == 0 and abs(c[-1]) == 0:
        raise InputError("the curve has no first harmonic (a1 = a−1 = 0): it is a point or retraces itself; "
                         "no Fourier normalisation")
    out, alpha, beta, scale, rev = normalise_many(c.vector()[None, :])
    row = Coefficients.of(out[0])
    if convention == "book":
        row = Coefficients({m: a.conjugate() for m, a in row.items()})
    return Normalised(row, -c[0], float(alpha[0]), float(scale[0]), float(beta[0]), bool(rev[0]), convention == "book")


def normalise_many(vectors):
    """:func:`normalise` of many curves at once: rows ``[a_−M, ..., a_M]`` -> ``(normalised, α, β, |a1|, reversed)``."""
    A = np.array(vectors, dtype=complex)
    M = (A.shape[1] - 1) // 2
    rev = np.abs(A[:, M - 1]) > np.abs(A[:, M + 1])
    A[rev] = A[rev, ::-1]
    phi1, phim1 = np.angle(A[:, M + 1]), np.angle(A[:, M - 1])
    alpha, beta = 0.5 * (phi1 + phim1), 0.5 * (phi1 - phim1)
    scale = np.abs(A[:, M + 1])
    m = np.arange(-M, M + 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        out = A * np.exp(-1j * alpha)[:, None] / scale[:, None] * np.exp(-1j * np.outer(beta, m))
    out[:, M] = 0
    out[:, M + 1] = out[:, M + 1].real
    out[:, M - 1] = out[:, M - 1].real
    return out, alpha, beta, scale, rev


def features(normalised) -> np.ndarray:
    """The look-up vectors of rows of normalised coefficients (see :meth:`Normalised.vector`), ``(n, 4M + 1)``."""
    A = np.asarray(normalised)
    M = (A.shape[1] - 1) // 2
    cols = []
    for k, m in enumerate(range(-M, M + 1)):
        if m in (0, 1):
            continue
        cols.append(A[:, k].real)
        if m != -1:
            cols.append(A[:, k].imag)
    return np.stack(cols, axis=1)


def variants(n: Normalised) -> list[np.ndarray]:
    """The feature vectors of the readings of one curve: as normalised, the other principal reading
    (``a_m × (−1)^(m+1)``), and the mirror images of both (``y → −y``)."""
    out = []
    for flip in (False, True):
        c = Coefficients({m: (a * (-1) ** (m + 1) if flip else a) for m, a in n.coefficients.items()})
        for mirror in (False, True):
            cc = Coefficients({m: a.conjugate() for m, a in c.items()}) if mirror else c
            out.append(Normalised(cc, 0j, 0.0, 1.0, 0.0, False, mirror).vector())
    return out


def distance(a: Normalised, b: Normalised) -> float:
    """The comparison metric (6-30): ``E = Σ (A_i − A'_i)² + (B_i − B'_i)²`` over the coefficients."""
    va, vb = a.coefficients.vector(), b.coefficients.vector()
    if va.size != vb.size:
        raise InputError(f"descriptors of {a.coefficients.harmonics} and {b.coefficients.harmonics} harmonics "
                         "cannot be compared")
    return float(np.sum(np.abs(va - vb) ** 2))


def resample(points, count: int = 256, closed: bool = True) -> np.ndarray:
    """``count`` points equally spaced by arc length along the polyline (closed: back to the first point).

    A drawn curve has no timing; resampling by arc length gives every curve
    the same parameter, so that descriptors of a drawing and of a coupler
    curve can be compared.
    """
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise InputError(f"a curve needs at least 3 points (x, y), got an array of shape {p.shape}")
    if not np.all(np.isfinite(p)):
        raise InputError("every point of the curve must be finite")
    if closed:
        p = np.vstack([p, p[:1]])
    seg = np.hypot(*np.diff(p, axis=0).T)
    s = np.concatenate(([0.0], np.cumsum(seg)))
    if s[-1] == 0:
        raise InputError("the curve has no length: all its points coincide")
    target = np.linspace(0.0, s[-1], count, endpoint=not closed)
    return np.c_[np.interp(target, s, p[:, 0]), np.interp(target, s, p[:, 1])]


def describe(points, harmonics: int = HARMONICS, samples: int = 256, convention: str = "literal") -> Normalised:
    """The normalised Fourier descriptor of a closed curve given by points (resampled by arc length)."""
    r = resample(points, samples, closed=True)
    return normalise(coefficients(r[:, 0] + 1j * r[:, 1], harmonics), convention)
