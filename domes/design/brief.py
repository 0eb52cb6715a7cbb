"""A design brief: the requirements of a problem turned into the synthesis task and the checks that decide
whether a quasi-feasible type is feasible (seed 002, §5-2, Fig. 5-4: "the dimensional-synthesis solution is the
final feasibility criterion").

A scene states, as data, how its candidates are dimensioned and checked (``[design]`` in the scene file,
docs/expert.md): a ``task`` template (a ``curve`` task of :mod:`~domes.design.synthesis.task` whose strings
``"{ID}"`` name requirements), ``checks`` (each a :class:`CheckSpec`) and the default ``weights`` of the
ranking. :func:`brief_from` fills them with the designer's answers.

Checks, besides those every dimensioned layout passes (assembly and branch through the stroke, no dead
point, transmission angle, the wanted curve within its tolerance, a length within its range):

* ``wheel-rate``: a spring of ``spring_rate`` between the two pivots of the task's length (the shock); the
  wheel rate at the task's point must stay within ``range`` (N/m) over the travel, and rise when ``rising``;
* ``force-ratio``: the force at the task's point per unit force of the actuator (the task's length, driven):
  at least ``minimum`` over the whole stroke, at least ``ratio`` at its end, or over its last ``over_last``
  degrees (a clamp before its toggle);
* ``drive``: a ``load`` (N) on the link of role ``on``, against its travel along the task's slide (or in
  ``direction_deg``), moved through the stroke in ``time`` (s); the input's peak torque at most ``torque``
  (N·m; a window lifter's motor);
* ``tolerance``: every dimension made to ``± tolerance``; the output the task moves (its length, slide or
  angle) must stay within ``± budget`` over the stroke (first order, worst case).

>>> from domes.model.requirements import RequirementSpec
>>> specs = [RequirementSpec("turn", "rotation", "quantity", "deg", "60 deg")]
>>> task = {"kind": "curve", "input": {"role": "crank", "rotation_deg": "{turn:deg}"}, "point": {"at": [1, 0]},
...         "wanted": {"quantity": "angle", "of": "rocker", "function": "0.5*x"}, "box": [[-1, 4], [-2, 2]]}
>>> b = brief_from("demo", task, [{"check": "tolerance", "tolerance": 0.001, "budget": 0.5}],
...                {"turn": specs[0].parse("45 deg")})
>>> round(math.degrees(b.task.rotation), 6), b.checks[0].kind
(45.0, 'tolerance')
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

from domes.design.synthesis.candidate import CurveTask
from domes.design.synthesis.task import task_from_dict
from domes.errors import InputError
from domes.model.requirements import Requirement, fill

#: The checks a brief may ask for, with the keys each takes (required, optional).
CHECK_KEYS = {
    "wheel-rate": ({"spring_rate"}, {"rising", "range"}),
    "force-ratio": ({"ratio"}, {"minimum", "over_last"}),
    "drive": ({"load", "on", "torque"}, {"time", "direction_deg"}),
    "tolerance": ({"tolerance", "budget"}, set()),
}
#: The soft indices of the ranking (docs/expert.md), in the order reports show them.
FACTORS = ("accuracy", "transmission", "compactness", "force", "sensitivity", "complexity")


@dataclass(frozen=True)
class CheckSpec:
    """One check of a brief: its ``kind`` (a key of :data:`CHECK_KEYS`) and its numbers (SI units)."""

    kind: str
    values: Mapping = field(default_factory=dict)

    def __getitem__(self, key):
        return self.values[key]

    def get(self, key, default=None):
        return self.values.get(key, default)


@dataclass(frozen=True)
class DesignBrief:
    """What every quasi-feasible candidate is dimensioned for (``task``), what it must then pass (``checks``),
    and how feasible designs are ranked (``weights`` of :data:`FACTORS`)."""

    task: CurveTask
    checks: tuple[CheckSpec, ...] = ()
    weights: Mapping[str, float] = field(default_factory=dict)


def check_spec(raw, where: str) -> CheckSpec:
    """A check from plain data, every key and number checked."""
    if not isinstance(raw, Mapping) or raw.get("check") not in CHECK_KEYS:
        raise InputError(f"{where}: a check is {{'check': one of {', '.join(CHECK_KEYS)}, ...}}, got {raw!r:.80}")
    kind = raw["check"]
    need, may = CHECK_KEYS[kind]
    keys = set(raw) - {"check"}
    if need - keys or keys - need - may:
        raise InputError(f"{where}: check {kind!r} takes {', '.join(sorted(need))}"
                         + (f" (and optionally {', '.join(sorted(may))})" if may else "")
                         + f"; got {', '.join(sorted(keys)) or 'nothing'}")
    values = {}
    for key in keys:
        value = raw[key]
        if key == "on":
            if not isinstance(value, str) or not value:
                raise InputError(f"{where}: {kind} 'on' names the role the load acts on, got {value!r}")
        elif key == "rising":
            if not isinstance(value, bool):
                raise InputError(f"{where}: {kind} 'rising' is true or false, got {value!r}")
        elif key == "range":
            if (not isinstance(value, (list, tuple)) or len(value) != 2 or not all(_finite(v) for v in value)
                    or not 0 <= value[0] < value[1]):
                raise InputError(f"{where}: {kind} 'range' is [low, high] with 0 <= low < high, got {value!r}")
            value = (float(value[0]), float(value[1]))
        elif key == "direction_deg":
            if not _finite(value):
                raise InputError(f"{where}: {kind} 'direction_deg' must be a number, got {value!r}")
            value = float(value)
        elif not _finite(value) or value <= 0:
            raise InputError(f"{where}: {kind} {key!r} must be a positive number, got {value!r}")
        else:
            value = float(value)
        values[key] = value
    return CheckSpec(kind, values)


def _finite(value) -> bool:
    return isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)


def weights_from(raw, where: str = "weights") -> dict[str, float]:
    """Ranking weights from plain data: factor names of :data:`FACTORS` to numbers >= 0 (not all zero)."""
    if not isinstance(raw, Mapping):
        raise InputError(f"{where}: expected factor = weight pairs, got {raw!r:.80}")
    out = {}
    for key, value in raw.items():
        if key not in FACTORS:
            raise InputError(f"{where}: unknown factor {key!r}; the factors are {', '.join(FACTORS)}")
        if not _finite(value) or value < 0:
            raise InputError(f"{where}: the weight of {key} must be a number >= 0, got {value!r}")
        out[key] = float(value)
    if out and not any(out.values()):
        raise InputError(f"{where}: at least one weight must be above 0")
    return out


def brief_from(name: str, task: Mapping, checks, requirements: Mapping[str, Requirement],
               weights: Mapping | None = None) -> DesignBrief:
    """The brief of a problem: the scene's ``task`` template and ``checks`` filled with the ``requirements``
    (by id), with the ranking ``weights``."""
    filled = fill(dict(task), requirements)
    filled.setdefault("name", name)
    built = task_from_dict(filled, f"the design task of {name}")
    if not isinstance(built, CurveTask):
        raise InputError(f"the design task of {name}: the candidates are dimensioned by a 'curve' task")
    specs = tuple(check_spec(fill(dict(c), requirements), f"{name}: check {k}") for k, c in enumerate(checks or (), 1))
    return DesignBrief(built, specs, weights_from(dict(weights or {}), f"{name}: weights"))
