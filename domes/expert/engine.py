"""The production-rule engine of the design expert (experta, after CLIPS and OPS-5).

The rules decide the next step of the dialogue of Fig. 7-8 (digest part
4.4); each is small and calls one action of the :class:`World` (the case
base, the design run, the messages to the designer). Step 0 finds the
problem's class among the solved problems and asks whether the problem is
the same as, similar to or different from one of them:

* same: the stored result is shown at once;
* similar: the structure is taken over, the representative attributes are
  asked, the relevance vector is built and may be overridden, further
  criteria may be added, the design runs, and the vectors are merged;
* different (or a new class): the structural attributes are asked, the
  MECXPRT structure rule derives links and joints, and the same steps follow.

When the scene says how its candidates are dimensioned, the requirements
(motion, stroke, forces, size, accuracy) are asked after the scene, and the
run ends with the feasibility level and the ranking.

``engine.pending`` is the question waiting for an answer, ``engine.answer(...)``
gives it one; the session (:mod:`domes.expert.dialogue`) does the asking.
"""

from __future__ import annotations

from domes.errors import InputError
from domes.expert.compat import AS, MATCH, NOT, DefFacts, KnowledgeEngine, Rule
from domes.expert.facts import QUESTION_ORDER, STRUCTURAL, Ask, Attr, Needed, Phase, Relation


class DesignExpert(KnowledgeEngine):
    """The design dialogue as production rules over the facts of :mod:`domes.expert.facts`."""

    def __init__(self, world):
        super().__init__()
        self.world = world
        self.pending: str | None = None

    # -- driving -------------------------------------------------------------------

    def ask(self, question: str) -> None:
        """Wait for an answer to ``question``. The run goes on to an empty agenda (every rule that asks
        is guarded by ``NOT(Ask())``); halting here would leave experta's network one change behind."""
        self.declare(Ask(id=question))
        self.pending = question

    def answer(self, question: str, value) -> None:
        """Record the designer's (already validated) answer and go on."""
        if question != self.pending:
            raise InputError(f"the engine asked {self.pending!r}, not {question!r}")
        for fact_id, fact in list(self.facts.items()):
            if isinstance(fact, Ask):
                self.retract(fact_id)
        self.pending = None
        self.world.answered(self, question, value)

    def attr(self, name: str):
        """The value of a known attribute, or None."""
        for fact in self.facts.values():
            if isinstance(fact, Attr) and fact["name"] == name:
                return fact["value"]
        return None

    def set_attr(self, name: str, value) -> None:
        for fact_id, fact in list(self.facts.items()):
            if isinstance(fact, Attr) and fact["name"] == name:
                self.retract(fact_id)
        self.declare(Attr(name=name, value=value))

    # -- facts -----------------------------------------------------------------------

    @DefFacts()
    def question_order(self):
        for name, after in QUESTION_ORDER:
            yield Needed(name=name, after=after)

    # -- step 0: the class and the relation to solved problems --------------------------

    @Rule(NOT(Attr(name="class")), NOT(Ask()))
    def ask_class(self):
        self.ask("class")

    @Rule(Attr(name="class", value=MATCH.problem_class), NOT(Relation()), NOT(Ask()))
    def relate(self, problem_class):
        if self.world.solved_in_class(problem_class):
            self.ask("relation")
        else:
            self.world.say(f"No solved problem of class {problem_class!r}: a new class.")
            self.declare(Relation(value="different", case=None))

    @Rule(Relation(value="same", case=MATCH.case), NOT(Phase()), salience=10)
    def same_problem(self, case):
        self.world.show_stored(case)
        self.declare(Phase(name="done"))

    @Rule(Relation(value="similar", case=MATCH.case), NOT(Attr(name="dof")), salience=10)
    def take_over_structure(self, case):
        for name, value in self.world.structure_of(case).items():
            if name in STRUCTURAL:
                self.set_attr(name, value)

    # -- the attributes, in order ------------------------------------------------------

    @Rule(
        Relation(value=MATCH.relation),
        Needed(name=MATCH.name, after=MATCH.after),
        Attr(name=MATCH.after),
        NOT(Attr(name=MATCH.name)),
        NOT(Ask()),
        NOT(Phase(name="done")),
    )
    def ask_attribute(self, relation, name, after):
        self.ask(name)

    @Rule(
        Attr(name="dof", value=MATCH.dof),
        Attr(name="loops", value=MATCH.loops),
        Attr(name="space", value=MATCH.space),
        Attr(name="gear_pairs", value=MATCH.gears),
        NOT(Attr(name="links")),
    )
    def structure_rule(self, dof, loops, space, gears):
        """MECXPRT: the numbers of links and joints follow from W, L, λ and j_G."""
        self.world.number_synthesis(self, dof, loops, space, gears)

    @Rule(
        AS.rel << Relation(value="different"),
        Attr(name="names"),
        Attr(name="links"),
        Attr(name="requirements"),
        NOT(Attr(name="recognised")),
        salience=20,
    )
    def recognise(self, rel):
        """The case-based reasoner: a solved problem with the same attributes and requirements answers at once."""
        self.set_attr("recognised", True)
        case = self.world.recognise(self)
        if case is not None:
            self.retract(rel)
            self.declare(Relation(value="same", case=case))

    # -- relevance, criteria, run, review ----------------------------------------------

    @Rule(Attr(name="scene", value=MATCH.scene), Attr(name="links"), NOT(Attr(name="requirements")), NOT(Ask()),
          NOT(Phase()))
    def requirements(self, scene):
        """The requirements the scene dimensions its candidates for, asked only when it says how."""
        self.world.ask_requirements(self, scene)

    @Rule(Attr(name="scene"), Attr(name="links"), Attr(name="requirements"), NOT(Attr(name="relevance")), NOT(Ask()),
          NOT(Phase()))
    def relevance(self):
        self.world.build_relevance(self)
        self.ask("relevance_overrides")

    @Rule(Attr(name="relevance"), NOT(Phase()), NOT(Ask()))
    def criteria_phase(self):
        self.declare(Phase(name="criteria"))

    @Rule(AS.phase << Phase(name="criteria"), NOT(Ask()))
    def more_criteria(self, phase):
        self.ask("more_criteria")

    @Rule(AS.phase << Phase(name="run"))
    def run_design(self, phase):
        self.retract(phase)
        self.world.run(self)
        self.declare(Phase(name="verify" if self.world.run_result.kept else "review"))

    @Rule(Phase(name="verify"), NOT(Ask()))
    def verify(self):
        self.ask("verify")

    @Rule(Phase(name="review"), NOT(Ask()))
    def review(self):
        self.ask("satisfied")

    @Rule(AS.phase << Phase(name="retain"))
    def retain(self, phase):
        self.retract(phase)
        self.world.retain(self)
        self.declare(Phase(name="done"))

