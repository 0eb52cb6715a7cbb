"""Contours of lines and circular arcs traversed at constant speed (the scriber's path, seed 003 §4).

A :class:`Contour` starts at a point and chains segments: a ``line`` to a
point, an ``arc`` about a centre to a point (counter-clockwise or
clockwise). :meth:`Contour.sample` gives, at arc lengths along it, the
point, its velocity and its acceleration at speed ``v`` (``v²κ`` towards the
centre on an arc, none on a line). Junctions are checked: a corner (the
tangent turns) makes the velocities jump, so it is reported with its angle.

>>> c = Contour.from_dict({"start": [0, 0], "segments": [{"line": [1, 0]},
...     {"arc": {"centre": [1, 1], "to": [2, 1], "turn": "ccw"}}]}, "<doc>")
>>> round(c.length, 6), [round(a, 9) for a in c.corners()]
(2.570796, [0.0])
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from domes.errors import InputError
from domes.model.fields import check_keys, read_xy

#: A junction whose tangent turns by more than this (rad) is a corner.
CORNER = 1e-6
#: The most segments a contour file may give: the forces are evaluated on both sides of every junction, so a run
#: over a contour grows with its segments as well as its points.
MAX_SEGMENTS = 10_000


@dataclass(frozen=True)
class Segment:
    """A line from ``start`` to ``end``, or an arc about ``centre`` (``turn`` +1 ccw, −1 cw)."""

    kind: str
    start: complex
    end: complex
    centre: complex = 0j
    turn: int = 1

    @property
    def radius(self) -> float:
        return abs(self.start - self.centre) if self.kind == "arc" else math.inf

    @property
    def sweep(self) -> float:
        """The arc's angle (rad, > 0), or 0 for a line."""
        if self.kind != "arc":
            return 0.0
        a0 = np.angle(self.start - self.centre)
        a1 = np.angle(self.end - self.centre)
        d = (a1 - a0) * self.turn % (2 * math.pi)
        return d if d > 1e-15 else 2 * math.pi

    @property
    def length(self) -> float:
        return abs(self.end - self.start) if self.kind == "line" else self.radius * self.sweep

    def tangent(self, where: str) -> complex:
        """Unit tangent at the segment's ``"start"`` or ``"end"``."""
        if self.kind == "line":
            d = self.end - self.start
            return d / abs(d)
        p = self.start if where == "start" else self.end
        r = p - self.centre
        return 1j * self.turn * r / abs(r)

    def at(self, s: np.ndarray, v: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Point, velocity and acceleration at arc lengths ``s`` from the segment's start, at speed ``v``."""
        s = np.asarray(s, dtype=float)
        if self.kind == "line":
            t = self.tangent("start")
            return self.start + s * t, np.full(s.shape, v * t), np.zeros(s.shape, complex)
        r = self.radius
        angle = np.angle(self.start - self.centre) + self.turn * s / r
        e = np.exp(1j * angle)
        return self.centre + r * e, v * 1j * self.turn * e, -(v * v / r) * e


@dataclass(frozen=True)
class Contour:
    """A chain of lines and arcs; ``closed`` when it ends where it starts."""

    name: str
    segments: tuple[Segment, ...]

    @property
    def length(self) -> float:
        return float(sum(s.length for s in self.segments))

    @property
    def closed(self) -> bool:
        size = max(abs(s.start - self.segments[0].start) for s in self.segments) or 1.0
        return abs(self.segments[-1].end - self.segments[0].start) <= 1e-9 * size

    def corners(self) -> list[float]:
        """The tangent's turn (rad) at every junction (the closing one too when closed)."""
        pairs = list(zip(self.segments[:-1], self.segments[1:]))
        if self.closed:
            pairs.append((self.segments[-1], self.segments[0]))
        return [abs(float(np.angle(b.tangent("start") / a.tangent("end")))) for a, b in pairs]

    def sample(self, count: int, v: float) -> dict:
        """``count`` midpoints of equal arc length over the whole contour.

        Returns arrays ``s`` (arc length), ``segment`` (index), ``P``, ``V``, ``A`` (complex).
        """
        total = self.length
        s = (np.arange(count) + 0.5) * total / count
        return self.at(s, v)

    def at(self, s, v: float) -> dict:
        """Points at arc lengths ``s`` along the contour (each on the segment that holds it)."""
        s = np.asarray(s, dtype=float)
        ends = np.cumsum([seg.length for seg in self.segments])
        index = np.minimum(np.searchsorted(ends, s, side="right"), len(self.segments) - 1)
        P = np.empty(s.shape, complex)
        V = np.empty(s.shape, complex)
        A = np.empty(s.shape, complex)
        for k, seg in enumerate(self.segments):
            mask = index == k
            if np.any(mask):
                local = s[mask] - (ends[k] - seg.length)
                P[mask], V[mask], A[mask] = seg.at(local, v)
        return {"s": s, "segment": index, "P": P, "V": V, "A": A}

    @classmethod
    def from_dict(cls, data, source: str) -> "Contour":
        """A contour from ``{"start": [x, y], "segments": [{"line": [x, y]}, {"arc": {"centre", "to", "turn"}}]}``."""
        if not isinstance(data, dict):
            raise InputError(f"{source}: a contour is a table with 'start' and 'segments'")
        check_keys(data, {"name", "start", "segments"}, {"start", "segments"}, f"{source}: contour")
        here = complex(*read_xy(data["start"], f"{source}: contour.start"))
        items = data["segments"]
        if not isinstance(items, list) or not items:
            raise InputError(f"{source}: contour.segments: expected a non-empty list of lines and arcs")
        if len(items) > MAX_SEGMENTS:
            raise InputError(f"{source}: contour.segments: {len(items):,} segments; a contour has at most "
                             f"{MAX_SEGMENTS:,}")
        segments = []
        for k, item in enumerate(items):
            where = f"{source}: contour.segments[{k}]"
            if not isinstance(item, dict) or len(item) != 1 or next(iter(item)) not in ("line", "arc"):
                raise InputError(f"{where}: expected {{\"line\": [x, y]}} or {{\"arc\": {{\"centre\": [x, y], "
                                 "\"to\": [x, y], \"turn\": \"ccw\"}}}}")
            kind, value = next(iter(item.items()))
            if kind == "line":
                end = complex(*read_xy(value, f"{where}.line"))
                if abs(end - here) == 0:
                    raise InputError(f"{where}: the line ends where it starts")
                segments.append(Segment("line", here, end))
            else:
                if not isinstance(value, dict):
                    raise InputError(f"{where}.arc: expected a table with centre, to and turn")
                check_keys(value, {"centre", "to", "turn"}, {"centre", "to"}, f"{where}.arc")
                centre = complex(*read_xy(value["centre"], f"{where}.arc.centre"))
                end = complex(*read_xy(value["to"], f"{where}.arc.to"))
                turn = value.get("turn", "ccw")
                if turn not in ("ccw", "cw"):
                    raise InputError(f"{where}.arc.turn: 'ccw' or 'cw', got {turn!r}")
                r0, r1 = abs(here - centre), abs(end - centre)
                if r0 == 0:
                    raise InputError(f"{where}.arc: it starts at its centre")
                if abs(r0 - r1) > 1e-9 * max(r0, r1):
                    raise InputError(f"{where}.arc: its start is {r0:.9g} from the centre and its end {r1:.9g}; "
                                     "an arc keeps its radius")
                segments.append(Segment("arc", here, end, centre, 1 if turn == "ccw" else -1))
            here = end
        return cls(str(data.get("name", source)), tuple(segments))

    def to_dict(self) -> dict:
        out: dict = {"name": self.name, "start": [self.segments[0].start.real, self.segments[0].start.imag],
                     "segments": []}
        for seg in self.segments:
            if seg.kind == "line":
                out["segments"].append({"line": [seg.end.real, seg.end.imag]})
            else:
                out["segments"].append({"arc": {"centre": [seg.centre.real, seg.centre.imag],
                                                "to": [seg.end.real, seg.end.imag],
                                                "turn": "ccw" if seg.turn > 0 else "cw"}})
        return out


__all__ = ["CORNER", "MAX_SEGMENTS", "Contour", "Segment"]
