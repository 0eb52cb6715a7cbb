"""Facts of the design dialogue (experta templates), kept apart from the rules.

* ``Attr(name=..., value=...)``: a known attribute of the problem (class,
  function (a motion conversion or None), outputs, dof, space, loops, gear_pairs, slider_pairs, names, scene, links,
  joints, requirements, weights, relevance).
* ``Needed(name=..., after=...)``: ask ``name`` once ``after`` is known (the
  order of the questions).
* ``Ask(id=...)``: the question the engine is waiting for (one at a time).
* ``Relation(value=..., case=...)``: same / similar / different, and the case.
* ``Phase(name=...)``: criteria, run, review, done.

>>> Attr(name="dof", value=1)["value"]
1
"""

from domes.expert.compat import Fact


class Attr(Fact):
    """A known problem attribute."""


class Needed(Fact):
    """Ask attribute ``name`` once attribute ``after`` is known."""


class Ask(Fact):
    """The pending question."""


class Relation(Fact):
    """How the problem relates to a solved one."""


class Phase(Fact):
    """Where the dialogue is after the attributes are known."""


#: The questions about the problem, in the order they are asked: (attribute, asked after).
QUESTION_ORDER = (
    ("function", "class"),
    ("outputs", "function"),
    ("dof", "outputs"),
    ("space", "dof"),
    ("loops", "space"),
    ("gear_pairs", "loops"),
    ("slider_pairs", "gear_pairs"),
    ("names", "slider_pairs"),
    ("scene", "names"),
)
#: The structural attributes a similar problem takes over from the solved one.
STRUCTURAL = ("outputs", "dof", "space", "loops", "gear_pairs", "slider_pairs")
