"""Combination modes of a labelled chain: series, parallel, feedback, stacking (seed 002 §3-3-III.2).

Complex mechanisms built from simple ones (gears, linkages, cams, Geneva
wheels) combine in four typical modes: series (串接), parallel (并接),
feedback (回接) and stacking (叠接). The book reads two of them off a
one-DOF chain with a frame and a driver:

* **series**: "a binary link is the driver and a link joined to it is the
  frame" (Fig. 3-29, an elliptical gear pair in series with a sine mechanism);
* **parallel**: "a multi-pair link (three pairs or more) is the driver and a
  link adjacent to it is the frame" (Fig. 3-28, a five-bar and a cam).

For feedback and stacking it says only that they "can also be represented
by chains". The readings below are DOMES-py's:

* **feedback**: every output link is jointed to the frame and an output lies
  with the driver on a loop that avoids the frame. The book defines parallel
  combination by the input of the additional mechanism *not* being fed back
  from the base mechanism's output; feedback is that case: the output,
  turning on the frame, acts back on the driver through moving links only
  (the loop arrangement of Fig. 1-6c, "for feedback processes");
* **stacking**: the driver is not jointed to the frame. One mechanism is
  carried on a moving link of another, so its actuator rides on that link.

Series, parallel and stacking exclude each other; feedback may come with
parallel (a loop without the frame through a driver on the frame needs two
more pairs on the driver) or with stacking. Roles are read from
the labelled chain: ``ground`` (one link), ``input`` (one link) and
``output`` (any number). The book states its rules for one-DOF chains: pass
``dof`` when it is known, and series and parallel are not given for another.

>>> fig_3_28 = LabelledChain.build(5, [(0, 1), (1, 2), (2, 3), (3, 4), (0, 4), (1, 4)],
...                                {(0, 4): "P", (1, 4): "C"}, roles={0: {"ground"}, 1: {"input"}})
>>> [(m.mode, m.phrase) for m in combination_modes(fig_3_28, dof=1)]
[('parallel', 'parallel combination: a ternary driver on the frame')]
"""

from __future__ import annotations

from dataclasses import dataclass

import networkx as nx

from domes.errors import InputError
from domes.model.labelled import LabelledChain

#: The four modes, in the book's order, with their Chinese names.
MODES = {"series": "串接", "parallel": "并接", "feedback": "回接", "stacking": "叠接"}
BOOK = "seed 002 §3-3-III.2"
OURS = "DOMES-py reading of seed 002 §3-3-III.2 (the book gives no rule)"
_DEGREE = {2: "binary", 3: "ternary", 4: "quaternary", 5: "quinary"}


@dataclass(frozen=True)
class CombinationMode:
    """A mode a chain is in: ``mode``, a short ``phrase``, the ``reason`` on its links, the rule's ``source``."""

    mode: str
    phrase: str
    reason: str
    source: str


def _one(chain: LabelledChain, role: str) -> int:
    links = chain.links_with_role(role)
    if len(links) != 1:
        found = f"links {', '.join(chain.link_name(v) for v in links)}" if links else "none"
        raise InputError(f"combination mode: the chain needs exactly one link with role {role!r}, found {found}")
    return links[0]


def _degree_word(k: int) -> str:
    return _DEGREE.get(k, f"{k}-pair")


def combination_modes(chain: LabelledChain, dof: int | None = None) -> tuple[CombinationMode, ...]:
    """The combination modes of a chain with one ``ground`` and one ``input`` link, in the order of :data:`MODES`.

    ``dof`` (the chain's DOF, when known) other than 1 leaves out series and
    parallel, which the book states for one-DOF chains.

    >>> fig_3_29 = LabelledChain.build(5, [(0, 1), (0, 2), (1, 2), (2, 3), (3, 4), (0, 4)],
    ...                                {(1, 2): "G", (3, 4): "P", (0, 4): "P"}, roles={0: {"ground"}, 1: {"input"}})
    >>> print(combination_modes(fig_3_29)[0].reason)
    link 1, the driver, is binary and link 0, joined to it, is the frame: a series combination
    >>> combination_modes(fig_3_29.with_roles({0: {"ground"}}))
    Traceback (most recent call last):
    ...
    domes.errors.InputError: combination mode: the chain needs exactly one link with role 'input', found none
    """
    if not isinstance(chain, LabelledChain):
        raise InputError(f"combination mode: expected a labelled chain, got {type(chain).__name__}")
    if dof is not None and (not isinstance(dof, int) or isinstance(dof, bool)):
        raise InputError(f"combination mode: dof must be a whole number, got {dof!r}")
    ground, driver = _one(chain, "ground"), _one(chain, "input")
    if ground == driver:
        raise InputError(f"combination mode: link {chain.link_name(ground)} is both the frame (ground) "
                         "and the driver (input)")
    name = chain.link_name
    pairs = chain.degrees[driver]
    on_frame = ground in chain.neighbours[driver]
    modes: list[CombinationMode] = []
    if on_frame and dof in (None, 1):
        if pairs == 2:
            modes.append(CombinationMode(
                "series", "series combination: a binary driver on the frame",
                f"link {name(driver)}, the driver, is binary and link {name(ground)}, joined to it, is the frame: "
                "a series combination", BOOK))
        elif pairs >= 3:
            word = _degree_word(pairs)
            modes.append(CombinationMode(
                "parallel", f"parallel combination: a {word} driver on the frame",
                f"link {name(driver)}, the driver, is a multi-pair link ({pairs} pairs) and link {name(ground)}, "
                "adjacent to it, is the frame: a parallel combination", BOOK))
    outputs = chain.links_with_role("output")
    if outputs and all(ground in chain.neighbours[v] for v in outputs):
        moving = chain.to_networkx()
        moving.remove_node(ground)
        looped = [v for v in outputs if any(
            driver in block and v in block and len(block) >= 3 for block in nx.biconnected_components(moving))]
        if looped:
            modes.append(CombinationMode(
                "feedback", "feedback combination: the output on the frame loops back to the driver",
                f"link {name(looped[0])}, the output, is jointed to the frame and lies with link {name(driver)}, "
                f"the driver, on a loop without the frame {name(ground)}: its motion is fed back to the driver",
                OURS))
    if not on_frame:
        modes.append(CombinationMode(
            "stacking", "stacking combination: the driver rides on a moving link",
            f"link {name(driver)}, the driver, is not jointed to the frame {name(ground)}: its actuator is carried "
            "by a moving link, one mechanism stacked on another", OURS))
    return tuple(modes)


def combination_phrase(chain: LabelledChain, dof: int | None = None) -> str:
    """The modes of a chain as one short phrase (empty when it is in none).

    >>> four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={0: {"ground"}, 2: {"input"}})
    >>> combination_phrase(four_bar)
    'stacking combination: the driver rides on a moving link'
    """
    return "; ".join(m.phrase for m in combination_modes(chain, dof))
