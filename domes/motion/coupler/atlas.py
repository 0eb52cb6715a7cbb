"""The coupler-curve atlas: four-bars over the design space and the coupler plane, described for look-up.

An atlas holds, for each sampled four-bar (normalised lengths ``a, b, c, d``
of the design space, :mod:`~domes.motion.coupler.designspace`), each of its
circuits and each coupler point ``(u, v)`` of a grid over
``−4 ≤ u, v ≤ 4`` (in units of the mean link length, the range of seed 002
§6-2), the normalised Fourier descriptor of the closed curve
(:mod:`~domes.motion.coupler.fourier`). Linkages are sampled with a Halton
sequence (evenly, without a lattice's boundary mechanisms) and kept off the
change-point cuts; each linkage is traced once with the backend, and the
curves of all its coupler points follow from the two traced points ``B`` and
``B + (C − B)/b`` without tracing again. A look-up (:meth:`Atlas.lookup`)
queries a k-d tree with the wanted curve's descriptor in its four readings
(both principal readings, each mirrored).

>>> table = build(AtlasSpec("tiny", 6, 2.0))             # 6 linkages × 25 coupler points × their circuits
>>> table.count % 25, table.features.shape[1]
(0, 17)
>>> atlas = Atlas(table)
>>> m = table.entry(17)
>>> best = atlas.lookup(table_curve(table, 17), k=1)[0]
>>> best.index == 17 or best.distance < 1e-12
True
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial import cKDTree

from domes.errors import InputError
from domes.motion.coupler.curves import trace
from domes.motion.coupler.designspace import classify
from domes.motion.coupler.fourbar import four_bar
from domes.motion.coupler.fourier import HARMONICS, describe, features, normalise_many, variants
from domes.results import Progress, Ticker

#: Points per curve after resampling by arc length (the descriptors' samples).
RESAMPLE = 256
#: Half the side of the coupler-plane square sampled (seed 002 §6-2: beyond ±4 curves are wide and featureless).
PLANE = 4.0
#: Keep sampled linkages this far (in normalised length) from the change-point cuts.
MARGIN = 0.02
VERSION = 1
#: Windows indexed for open paths: the share of a curve's length each covers, and the starts per share.
WINDOW_FRACTIONS = (0.2, 0.35, 0.5)
WINDOW_STARTS = 12
#: Points a window (or a wanted open path) is described by.
WINDOW_POINTS = 12


@dataclass(frozen=True)
class AtlasSpec:
    """How an atlas samples: ``linkages`` four-bars, a coupler-plane grid of ``step``, ``harmonics``, trace ``samples``."""

    name: str
    linkages: int
    step: float
    harmonics: int = HARMONICS
    samples: int = 360

    @property
    def plane(self) -> np.ndarray:
        """The coupler points ``(u, v)`` of the grid."""
        n = int(round(2 * PLANE / self.step)) + 1
        g = np.linspace(-PLANE, PLANE, n)
        u, v = np.meshgrid(g, g, indexing="ij")
        return np.c_[u.ravel(), v.ravel()]


#: The atlases a user can build by name: a small one in seconds, a large one for precision.
SIZES = {
    "small": AtlasSpec("small", 600, 0.5),
    "large": AtlasSpec("large", 2400, 0.25),
}


class _Rows:
    """Rows of curves of sampled four-bars: what :class:`AtlasTable` and :class:`WindowTable` share."""

    linkages: np.ndarray
    link: np.ndarray
    point: np.ndarray
    circuit: np.ndarray

    @property
    def count(self) -> int:
        return int(self.circuit.size)

    def lengths(self, index: int) -> tuple[float, float, float, float]:
        """The normalised ``a, b, c, d`` of row ``index``."""
        return tuple(float(x) for x in self.linkages[self.link[index]])

    def entry(self, index: int):
        """The four-bar of row ``index`` (normalised lengths, its coupler point as ``P``)."""
        u, v = (float(x) for x in self.point[index])
        return four_bar(*self.lengths(index), u, v)

    def _repr_html_(self) -> str | None:
        """Some rows' linkages moving along their curves, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


@dataclass(frozen=True, eq=False)
class AtlasTable(_Rows):
    """The atlas's columns: one row per curve, and the table of sampled linkages.

    ``linkages`` holds the normalised ``a, b, c, d`` of each sampled
    four-bar; per curve, ``link`` is the row of its linkage, ``point`` its
    coupler point ``(u, v)``, ``circuit`` which of the linkage's circuits (in
    the order :func:`~domes.motion.coupler.curves.trace` finds them), and
    ``features`` its descriptor vector. ``meta`` says how it was built.
    """

    linkages: np.ndarray
    link: np.ndarray
    point: np.ndarray
    circuit: np.ndarray
    features: np.ndarray
    meta: dict = field(default_factory=dict)


def design_points(count: int, margin: float = MARGIN) -> np.ndarray:
    """``count`` four-bars ``(a, b, c, d)`` spread over the design space (Halton in ``a, b, c``), off the cuts."""
    out = []
    k = 0
    while len(out) < count:
        k += 1
        a, b, c = (2 * _halton(k, base) for base in (2, 3, 5))
        d = 4.0 - a - b - c
        if not (margin < d < 2 - margin) or min(a, b, c) < margin or max(a, b, c) > 2 - margin:
            continue
        if min(abs(a + d - 2), abs(b + d - 2), abs(c + d - 2)) < margin:
            continue
        out.append((a, b, c, d))
    return np.array(out)


def _halton(index: int, base: int) -> float:
    f, r = 1.0, 0.0
    while index > 0:
        f /= base
        r += f * (index % base)
        index //= base
    return r


def curve_family(a, b, c, d, plane, samples: int = 360, resample: int = RESAMPLE):
    """Every circuit's curves of the coupler points ``plane`` of four-bar ``a, b, c, d``, resampled by arc length.

    Returns ``[(circuit index, Z)]`` with ``Z`` complex ``(len(plane), resample)``.
    """
    curve = trace(four_bar(a, b, c, d, 1.0, 0.0), "P", samples, extra=("B",))
    out = []
    uv = np.asarray(plane[:, 0] + 1j * plane[:, 1])
    for k, circuit in enumerate(curve.circuits):
        B = circuit.extra["B"]
        E = circuit.points
        zb, ze = B[:, 0] + 1j * B[:, 1], E[:, 0] + 1j * E[:, 1]
        Z = zb[None, :] + uv[:, None] * (ze - zb)[None, :]
        out.append((k, resample_closed(Z, resample)))
    return out


def resample_closed(Z, count: int) -> np.ndarray:
    """Rows of complex closed polylines resampled to ``count`` points equally spaced by arc length."""
    Z = np.asarray(Z, dtype=complex)
    rows, n = Z.shape
    closed = np.concatenate([Z, Z[:, :1]], axis=1)
    seg = np.abs(np.diff(closed, axis=1))
    s = np.concatenate([np.zeros((rows, 1)), np.cumsum(seg, axis=1)], axis=1)
    total = s[:, -1:]
    total = np.where(total > 0, total, 1.0)
    frac = s / total + np.arange(rows)[:, None] * 2.0          # disjoint ranges per row for one search
    target = (np.arange(count) / count)[None, :] + np.arange(rows)[:, None] * 2.0
    idx = np.searchsorted(frac.ravel(), target.ravel(), side="right") - 1
    idx = np.clip(idx, 0, frac.size - 2)
    f0, f1 = frac.ravel()[idx], frac.ravel()[idx + 1]
    w = np.where(f1 > f0, (target.ravel() - f0) / np.where(f1 > f0, f1 - f0, 1.0), 0.0)
    flat = closed.ravel()
    return (flat[idx] * (1 - w) + flat[idx + 1] * w).reshape(rows, count)


def descriptors(Z, harmonics: int = HARMONICS) -> np.ndarray:
    """Normalised Fourier feature vectors of rows of resampled closed curves."""
    n = Z.shape[1]
    spectrum = np.fft.fft(Z, axis=1) / n
    cols = [spectrum[:, m % n] for m in range(-harmonics, harmonics + 1)]
    out, *_ = normalise_many(np.stack(cols, axis=1))
    return features(out)


def _closed_rows(plane, k, Z, spec):
    """The columns of the closed curves ``Z`` of circuit ``k`` (rows whose descriptor is defined)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        f = descriptors(Z, spec.harmonics)
    ok = np.all(np.isfinite(f), axis=1)
    return {"point": plane[ok].astype(np.float32), "circuit": np.full(ok.sum(), k, dtype=np.int8),
            "features": f[ok].astype(np.float32)}


def _open_rows(plane, k, Z, spec):
    """The columns of the windows of the closed curves ``Z`` of circuit ``k``."""
    K = Z.shape[1]
    cols = {name: [] for name in ("point", "circuit", "start", "fraction", "features")}
    for fraction in WINDOW_FRACTIONS:
        span = int(round(fraction * K))
        for j in range(WINDOW_STARTS):
            first = j * K // WINDOW_STARTS
            idx = (first + np.round(np.linspace(0, span, WINDOW_POINTS)).astype(int)) % K
            f = open_features(Z[:, idx])
            ok = np.all(np.isfinite(f), axis=1)
            cols["point"].append(plane[ok].astype(np.float32))
            cols["circuit"].append(np.full(ok.sum(), k, dtype=np.int8))
            cols["start"].append(np.full(ok.sum(), first / K, dtype=np.float32))
            cols["fraction"].append(np.full(ok.sum(), span / K, dtype=np.float32))
            cols["features"].append(f[ok].astype(np.float32))
    return {name: np.concatenate(v) for name, v in cols.items()}


_ROWS = {"closed": _closed_rows, "open": _open_rows}


def _describe_task(task) -> list:
    """:func:`_describe_chunk` of a task ``(spec, kind, chunk)``: the unit of work a worker runs."""
    return _describe_chunk(*task)


def _describe_chunk(spec: AtlasSpec, kind: str, chunk) -> list:
    """Per linkage of ``chunk``: the columns of its curves, or None where it cannot be traced (run in a worker)."""
    plane, rows = spec.plane, _ROWS[kind]
    out = []
    for a, b, c, d in chunk:
        try:
            family = curve_family(a, b, c, d, plane, spec.samples)
        except InputError:
            out.append(None)
            continue
        out.append([rows(plane, k, Z, spec) for k, Z in family])
    return out


#: Linkages per task when an atlas is built by several workers.
CHUNK = 20


def _describe_all(spec: AtlasSpec, kind: str, progress, executor):
    """The linkages traced and the columns of all their curves, in design-point order whatever the executor."""
    points = design_points(spec.linkages)
    chunks = [points[i:i + CHUNK] for i in range(0, len(points), CHUNK)]
    clock = Ticker(progress)
    what = "" if kind == "closed" else " (open paths)"
    linkages, cols, done = [], {}, 0
    tasks = [(spec, kind, chunk) for chunk in chunks]
    mapper = map if executor is None else executor.map
    for chunk, results in zip(chunks, mapper(_describe_task, tasks)):
        for lengths, parts in zip(chunk, results):
            done += 1
            if parts is None:
                continue
            for part in parts:
                cols.setdefault("link", []).append(np.full(part["circuit"].size, len(linkages), dtype=np.int32))
                for name, value in part.items():
                    cols.setdefault(name, []).append(value)
            linkages.append(tuple(lengths))
        clock.tick(lambda: f"atlas {spec.name}{what}: linkage {done}/{len(points)}")
    return np.array(linkages, dtype=np.float64).reshape(-1, 4), {name: np.concatenate(v) for name, v in cols.items()}


def build(spec: AtlasSpec, progress: Progress | None = None, executor=None) -> AtlasTable:
    """Sample the design space and the coupler plane, trace every linkage, describe every curve.

    ``executor`` (anything with ``map``, e.g. a
    ``concurrent.futures.ProcessPoolExecutor``) shares the linkages out in
    chunks of :data:`CHUNK`; the table is the same, row for row, as without.
    """
    started = time.perf_counter()
    linkages, cols = _describe_all(spec, "closed", progress, executor)
    meta = {"name": spec.name, "kind": "closed", "linkages": len(linkages), "step": spec.step, "plane": PLANE,
            "harmonics": spec.harmonics, "samples": spec.samples, "resample": RESAMPLE, "version": VERSION,
            "seconds": time.perf_counter() - started}
    return AtlasTable(linkages, cols["link"], cols["point"], cols["circuit"], cols["features"], meta)


# -- open paths: windows of the curves --------------------------------------------------------



def open_features(Z, q: int = WINDOW_POINTS) -> np.ndarray:
    """Rows of open polylines (complex, equally spaced by arc length, ``q`` points) described for look-up.

    Each is normalised by its chord (first point to 0, last to 1), which
    removes translation, rotation and scale; the interior points' real and
    imaginary parts are the features.
    """
    Z = np.asarray(Z, dtype=complex)
    with np.errstate(invalid="ignore", divide="ignore"):
        w = (Z - Z[:, :1]) / (Z[:, -1:] - Z[:, :1])
    inner = w[:, 1:-1]
    return np.concatenate([inner.real, inner.imag], axis=1)


def resample_open(points, q: int = WINDOW_POINTS) -> np.ndarray:
    """An open polyline resampled to ``q`` points equally spaced by arc length (complex)."""
    p = np.asarray(points, dtype=float)
    if p.ndim != 2 or p.shape[1] != 2 or p.shape[0] < 3:
        raise InputError(f"an open path needs at least 3 points (x, y), got an array of shape {p.shape}")
    z = p[:, 0] + 1j * p[:, 1]
    s = np.concatenate(([0.0], np.cumsum(np.abs(np.diff(z)))))
    if s[-1] == 0:
        raise InputError("the path has no length: all its points coincide")
    t = np.linspace(0.0, s[-1], q)
    return np.interp(t, s, z.real) + 1j * np.interp(t, s, z.imag)


@dataclass(frozen=True, eq=False)
class WindowTable(_Rows):
    """Windows of atlas curves for open paths: per window its linkage row, coupler point, circuit, where it
    starts and how much of the curve it covers (parameters by arc length), and its features."""

    linkages: np.ndarray
    link: np.ndarray
    point: np.ndarray
    circuit: np.ndarray
    start: np.ndarray
    fraction: np.ndarray
    features: np.ndarray
    meta: dict = field(default_factory=dict)


def build_windows(spec: AtlasSpec, progress: Progress | None = None, executor=None) -> WindowTable:
    """The open-path index of an atlas: windows of the curves of half its linkages, coupler points every 1.0."""
    started = time.perf_counter()
    sub = AtlasSpec(spec.name, max(1, spec.linkages // 2), max(spec.step, 1.0), spec.harmonics, spec.samples)
    linkages, cols = _describe_all(sub, "open", progress, executor)
    meta = {"name": spec.name, "kind": "open", "linkages": len(linkages), "step": sub.step, "plane": PLANE,
            "samples": spec.samples, "resample": RESAMPLE, "window_points": WINDOW_POINTS,
            "fractions": list(WINDOW_FRACTIONS), "starts": WINDOW_STARTS, "version": VERSION,
            "seconds": time.perf_counter() - started}
    return WindowTable(linkages, cols["link"], cols["point"], cols["circuit"], cols["start"], cols["fraction"],
                       cols["features"], meta)


@dataclass(frozen=True)
class Candidate:
    """An atlas curve near the wanted one: its row, descriptor distance and the reading that matched.

    For an open path, ``window`` is ``(circuit, start, fraction, backwards,
    mirror)``: where on the row's curve the wanted stretch lies.
    """

    index: int
    distance: float
    reading: int
    window: tuple | None = None


class Atlas:
    """An :class:`AtlasTable` with its k-d tree, for look-ups."""

    def __init__(self, table: AtlasTable):
        self.table = table
        self.tree = cKDTree(table.features.astype(np.float64))

    def lookup(self, points, k: int = 5, distinct: bool = True) -> list[Candidate]:
        """The ``k`` atlas curves nearest the closed curve through ``points`` (any position, size, orientation).

        With ``distinct``, at most one curve per linkage (the nearest of its
        coupler points): candidates that differ, for a refinement to start from.
        """
        wanted = describe(points, self.table.meta.get("harmonics", HARMONICS), RESAMPLE)
        best: dict[int, Candidate] = {}
        wide = min(self.table.count, k * 16 if distinct else k)
        for reading, vector in enumerate(variants(wanted)):
            dist, idx = self.tree.query(vector, k=wide)
            for dd, ii in zip(np.atleast_1d(dist), np.atleast_1d(idx)):
                ii = int(ii)
                if ii not in best or dd < best[ii].distance:
                    best[ii] = Candidate(ii, float(dd), reading)
        return _nearest(best, k, (lambda i: int(self.table.link[i])) if distinct else None)

    def describe_entry(self, index: int) -> str:
        a, b, c, d = self.table.lengths(index)
        u, v = (float(x) for x in self.table.point[index])
        region = classify(a, b, c, d)
        return (f"a, b, c, d = {a:.4f}, {b:.4f}, {c:.4f}, {d:.4f} (region {region.region}), coupler point "
                f"(u, v) = ({u:g}, {v:g}), circuit {int(self.table.circuit[index]) + 1}")

    def _repr_html_(self) -> str | None:
        """Some rows' linkages moving along their curves, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


class OpenAtlas:
    """A :class:`WindowTable` with its k-d tree, for looking up open paths (stretches of a curve)."""

    def __init__(self, table: WindowTable):
        self.table = table
        self.tree = cKDTree(table.features.astype(np.float64))

    def lookup(self, points, k: int = 5, distinct: bool = True) -> list[Candidate]:
        """The ``k`` windows nearest the open path through ``points``, in either direction and mirrored."""
        z = resample_open(points, self.table.meta.get("window_points", WINDOW_POINTS))
        best: dict[int, Candidate] = {}
        wide = min(self.table.count, k * 16 if distinct else k)
        for reading, (backwards, mirror) in enumerate([(False, False), (True, False), (False, True), (True, True)]):
            zz = z[::-1] if backwards else z
            zz = np.conj(zz) if mirror else zz
            dist, idx = self.tree.query(open_features(zz[None, :])[0], k=wide)
            for dd, ii in zip(np.atleast_1d(dist), np.atleast_1d(idx)):
                ii = int(ii)
                if ii not in best or dd < best[ii].distance:
                    window = (int(self.table.circuit[ii]), float(self.table.start[ii]), float(self.table.fraction[ii]),
                              backwards, mirror)
                    best[ii] = Candidate(ii, float(dd), reading, window)
        return _nearest(best, k, (lambda i: (int(self.table.link[i]), tuple(self.table.point[i]))) if distinct else None)

    def _repr_html_(self) -> str | None:
        """Some rows' linkages moving along their curves, for a notebook; None if it cannot be drawn."""
        from domes.model.display import render

        return render(self, "html")


def _nearest(best: dict, k: int, key=None) -> list[Candidate]:
    """The ``k`` nearest candidates; with ``key``, at most one per key of their row (the nearest)."""
    ranked = sorted(best.values(), key=lambda c: c.distance)
    if key is None:
        return ranked[:k]
    seen, out = set(), []
    for cand in ranked:
        group = key(cand.index)
        if group not in seen:
            seen.add(group)
            out.append(cand)
            if len(out) == k:
                break
    return out


def table_curve(table: AtlasTable, index: int, samples: int = 360) -> np.ndarray:
    """The curve of row ``index`` (points of its circuit), traced again from the row's linkage."""
    curve = trace(table.entry(index), "P", samples)
    return curve.circuits[int(table.circuit[index])].points


__all__ = ["Atlas", "AtlasSpec", "AtlasTable", "Candidate", "OpenAtlas", "SIZES", "WindowTable", "build",
           "build_windows", "curve_family", "descriptors", "design_points", "open_features", "resample_closed",
           "resample_open", "table_curve"]
