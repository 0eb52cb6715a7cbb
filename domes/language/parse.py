"""The criterion language: near-English screening criteria and scene rules parsed to a typed tree.

A hand-written tokenizer and recursive-descent parser (never eval or exec).
Case does not matter; curly or straight quotes name properties, vertices
and loops; a hyphen inside a word that is a keyword once removed is a
line-break hyphen (``VER-TICES``). The grammar is documented in
docs/knowledge.md; :func:`parse_criterion` returns a
:class:`~domes.language.tree.ForAll` or :class:`~domes.language.tree.Count`,
:func:`parse_relevance` a relevance condition on problem attributes.

>>> parse_criterion("THE NUMBER OF VER-TICES WHOSE “TYPE” PROPERTY HAS VALUE (P R) "
...                 "SHOULD NOT BE GREATER THAN 1")
Count(domain=Domain(kind='vertex', name=None), condition=TypeIs(relation='=', joints=('P', 'R')), comparison=Comparison(op='<=', value=1))
>>> parse_criterion("the swing arm is adjacent to the ground")
ForAll(domain=Domain(kind='vertex', name='swing_arm'), condition=Adjacent(role='ground', joint=None))
>>> parse_criterion("the input pairs must be active pairs with full DOF")
ActivePairs(role='input', dof_type='full')
>>> parse_criterion("every vertex must have type (G P R")
Traceback (most recent call last):
...
domes.language.parse.CriterionSyntaxError: column 35: expected a joint type letter (R P G C O S H F Fp Fr Cyl Sph Hel) or ')', found the end of the text
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from domes.errors import InputError
from domes.language.tree import (
    DOF_TYPES,
    NAME_PATTERN,
    ActivePairs,
    Adjacent,
    AllOf,
    Always,
    And,
    AnyOf,
    Attribute,
    ClassIs,
    Comparison,
    Count,
    Criterion,
    Distance,
    Domain,
    ForAll,
    HasMember,
    HasName,
    InLoop,
    JointCount,
    NoneOf,
    Not,
    Or,
    Relevance,
    Represents,
    SharesJoint,
    TypeIs,
)
from domes.model.labelled import JOINT_TYPES

#: Words naming a joint type (also the type letters themselves).
JOINT_WORDS = {
    "revolute": "R", "hinge": "R", "prismatic": "P", "slider": "P", "sliding": "P", "gear": "G",
    "cam": "C", "higher": "C", "rolling": "O", "spring": "S", "hydraulic": "H", "force": "F",
    **{letter.lower(): letter for letter in JOINT_TYPES},
}
JOINT_NOUNS = ("pair", "pairs", "joint", "joints", "hinges")
VERTEX_WORDS = ("vertex", "vertices", "link", "links")
LOOP_WORDS = ("loop", "loops", "circuit", "circuits")
NUMBER_WORDS = {w: i for i, w in enumerate("zero one two three four five six seven eight nine ten".split())}
DEGREE_WORDS = {"binary": 2, "ternary": 3, "quaternary": 4, "quinary": 5}
PROPERTIES = ("type", "degree", "length")
ATTRIBUTE_WORDS = {
    "dof": "dof", "degrees": "dof", "degree": "dof", "independent": "loops", "loops": "loops",
    "outputs": "outputs", "links": "links", "vertices": "links", "joints": "joints", "edges": "joints",
}

#: Words that open a clause with its own modal after "and" (in a statement; "is"/"are" too).
MODALS = ("must", "should", "shall", "may", "cannot")
#: Every word the grammar uses: an unquoted name stops at any of them.
KEYWORDS = frozenset(
    """a an the of to by via through with in it them its on at as for any every each all no not
    and or must should shall may cannot is are be have has having value values property
    number independent representing represent represents that which whose equal than greater
    more larger less fewer smaller least most exactly other contain contains containing
    include includes including within adjacent connected jointed joined distance from
    intermediate share shares pass passes member adjoin adjoins type degree length
    problem always class freedom outputs dof edges""".split()
) | frozenset(JOINT_WORDS) | frozenset(JOINT_NOUNS) | frozenset(VERTEX_WORDS) | frozenset(LOOP_WORDS) \
  | frozenset(NUMBER_WORDS) | frozenset(DEGREE_WORDS)

_QUOTES = {'"': '"', "“": "”\"", "”": "”", "‘": "’'", "'": "'", "„": "“”", "«": "»"}
_SCANNER = re.compile(
    r"(?P<space>\s+)|(?P<number>\d+)|(?P<word>[^\W\d][\w]*(?:-\w+)*)"
    r"|(?P<op><=|>=|!=|==|≤|≥|≠|<|>|=)|(?P<punct>[()\[\],.])"
)
_SYMBOL_OPS = {"<=": "<=", ">=": ">=", "!=": "!=", "==": "=", "≤": "<=", "≥": ">=", "≠": "!=", "<": "<", ">": ">", "=": "="}
MAX_TEXT = 2000
#: Deepest nesting of brackets and 'not' in a criterion.
MAX_DEPTH = 40


class CriterionSyntaxError(InputError):
    """Text that does not parse: ``position`` (0-based character offset) and ``expected``."""

    def __init__(self, message: str, position: int, expected: str):
        super().__init__(message)
        self.position = position
        self.expected = expected


@dataclass(frozen=True)
class Token:
    kind: str  # word, number, string, op, punct, end
    value: str
    pos: int


def normalise_name(text: str) -> str:
    """A role or loop name in its stored form: lower case, words joined by ``_``.

    >>> normalise_name(" Shock-Absorber ")
    'shock_absorber'
    """
    return re.sub(r"[\s_\-]+", "_", text.strip().lower()).strip("_")


def tokenize(text: str) -> list[Token]:
    """The tokens of a criterion; a character outside the language is a syntax error.

    >>> [t.value for t in tokenize("VER-TICES “TYPE” (P R)")]
    ['vertices', 'TYPE', '(', 'p', 'r', ')', '']
    """
    if not isinstance(text, str):
        raise CriterionSyntaxError(f"expected text, got {type(text).__name__}", 0, "text")
    if len(text) > MAX_TEXT:
        raise CriterionSyntaxError(f"column {MAX_TEXT + 1}: a criterion is at most {MAX_TEXT} characters", MAX_TEXT, "a shorter text")
    tokens: list[Token] = []
    pos = 0
    while pos < len(text):
        ch = text[pos]
        if ch in _QUOTES:
            end = min((i for i in (text.find(c, pos + 1) for c in _QUOTES[ch]) if i >= 0), default=-1)
            if end < 0:
                raise CriterionSyntaxError(
                    f"column {pos + 1}: unterminated quotation: expected a closing {_QUOTES[ch][0]}", pos, "a closing quote"
                )
            tokens.append(Token("string", text[pos + 1:end], pos))
            pos = end + 1
            continue
        m = _SCANNER.match(text, pos)
        if m is None:
            raise CriterionSyntaxError(
                f"column {pos + 1}: unexpected character {ch!r}: expected a word, a number, a quoted name, "
                "a parenthesised joint-type list or a comparison", pos, "a word, number, quoted name or list"
            )
        kind = m.lastgroup
        if kind == "word":
            tokens.extend(_words(m.group(), pos))
        elif kind != "space":
            tokens.append(Token(kind, m.group(), pos))
        pos = m.end()
    tokens.append(Token("end", "", len(text)))
    return tokens


def _words(word: str, pos: int) -> list[Token]:
    lower = word.lower()
    if "-" not in lower or lower.replace("-", "") in KEYWORDS:
        return [Token("word", lower.replace("-", ""), pos)]
    out, offset = [], pos
    for part in lower.split("-"):
        out.append(Token("word", part, offset))
        offset += len(part) + 1
    return out


def _describe(tok: Token) -> str:
    if tok.kind == "end":
        return "the end of the text"
    if tok.kind == "string":
        return f"the quoted name “{tok.value}”"
    return repr(tok.value)


class _Parser:
    def __init__(self, text: str):
        self.tokens = tokenize(text)
        self.i = 0
        self.depth = 0
        self.clause_modals = MODALS

    # -- primitives ------------------------------------------------------------

    @property
    def tok(self) -> Token:
        return self.tokens[self.i]

    def peek(self, k: int = 1) -> Token:
        return self.tokens[min(self.i + k, len(self.tokens) - 1)]

    def at(self, *words: str) -> bool:
        return self.tok.kind == "word" and self.tok.value in words

    def ahead(self, k: int, *words: str) -> bool:
        """Whether the k-th token after the current one is one of ``words``."""
        tok = self.peek(k)
        return tok.kind == "word" and tok.value in words

    def accept(self, *words: str) -> str | None:
        if self.at(*words):
            self.i += 1
            return self.tokens[self.i - 1].value
        return None

    def accept_punct(self, ch: str) -> bool:
        if self.tok.kind == "punct" and self.tok.value == ch:
            self.i += 1
            return True
        return False

    def expect(self, *words: str) -> str:
        found = self.accept(*words)
        if found is None:
            self.error(" or ".join(f"'{w}'" for w in words))
        return found

    def expect_punct(self, ch: str) -> None:
        if not self.accept_punct(ch):
            self.error(f"'{ch}'")

    def error(self, expected: str):
        tok = self.tok
        raise CriterionSyntaxError(f"column {tok.pos + 1}: expected {expected}, found {_describe(tok)}", tok.pos, expected)

    def finish(self) -> None:
        self.accept_punct(".")
        if self.tok.kind != "end":
            self.error("the end of the criterion ('and', 'or' or a comparison may be missing before it)")

    # -- names, numbers, comparisons, joint types -----------------------------------

    def name(self, what: str = "a name") -> str:
        tok = self.tok
        if tok.kind == "string":
            self.i += 1
            name = normalise_name(tok.value)
            if not NAME_PATTERN.match(name):
                raise CriterionSyntaxError(
                    f"column {tok.pos + 1}: “{tok.value}” is not a name: use letters, digits, spaces and hyphens",
                    tok.pos, "a name of letters, digits, spaces and hyphens",
                )
            return name
        words = []
        while self.tok.kind in ("word", "number") and self.tok.value not in KEYWORDS:
            words.append(self.tok.value)
            self.i += 1
        if not words:
            self.error(f"{what} (in quotes, e.g. “ground”)")
        name = normalise_name(" ".join(words))
        if not NAME_PATTERN.match(name):
            raise CriterionSyntaxError(
                f"column {tok.pos + 1}: {' '.join(words)!r} is not a name: use letters a-z, digits, spaces and hyphens",
                tok.pos, "a name of letters, digits, spaces and hyphens",
            )
        return name

    def number(self) -> int:
        tok = self.tok
        if tok.kind == "number":
            self.i += 1
            return int(tok.value)
        if tok.kind == "word" and tok.value in NUMBER_WORDS:
            self.i += 1
            return NUMBER_WORDS[tok.value]
        self.error("a number")

    def comparison(self) -> Comparison:
        """``more than N``, ``at most N``, ``<= N``, ``N or more``, a bare ``N`` (equal), ..."""
        self.accept("be", "is", "are")
        if self.tok.kind == "op":
            op = _SYMBOL_OPS[self.tok.value]
            self.i += 1
            return Comparison(op, self.number())
        if self.accept("greater", "more", "larger"):
            self.expect("than")
            return Comparison(">", self.number())
        if self.accept("less", "fewer", "smaller"):
            self.expect("than")
            return Comparison("<", self.number())
        if self.accept("at"):
            op = {"least": ">=", "most": "<="}[self.expect("least", "most")]
            return Comparison(op, self.number())
        if self.accept("no"):
            op = {"more": "<=", "greater": "<=", "less": ">=", "fewer": ">="}[self.expect("more", "greater", "less", "fewer")]
            self.expect("than")
            return Comparison(op, self.number())
        if self.accept("other"):
            self.expect("than")
            return Comparison("!=", self.number())
        if self.accept("not"):
            self.expect("equal")
            self.expect("to")
            return Comparison("!=", self.number())
        if self.accept("equal"):
            self.expect("to")
        else:
            self.accept("exactly")
        if self.tok.kind != "number" and not self.at(*NUMBER_WORDS):
            self.error("a comparison ('more than 1', 'at most 2', '<= 2', 'equal to 1', ...)")
        value = self.number()
        if self.at("or") and self.ahead(1, "more", "less", "fewer"):
            self.i += 1
            return Comparison(">=" if self.accept("more", "less", "fewer") == "more" else "<=", value)
        return Comparison("=", value)

    def joint_kind(self, loop: bool = False) -> str | None:
        """``gear pairs`` -> G, ``pairs``/``joints`` -> any type (None); for a loop also ``links``."""
        if self.at(*JOINT_WORDS) and self.ahead(1, *JOINT_NOUNS, "cylinder", "cylinders"):
            letter = JOINT_WORDS[self.accept(*JOINT_WORDS)]
            self.i += 1
            return letter
        if self.accept(*JOINT_NOUNS) or (loop and self.accept(*VERTEX_WORDS, "edges")):
            return None
        self.error("a kind of joint ('gear pairs', 'slider pair', 'revolute joints', 'joints', ...)")

    def joint_set(self) -> tuple[str, ...]:
        self.expect_punct("(")
        letters: set[str] = set()
        while not self.accept_punct(")"):
            tok = self.tok
            if tok.kind == "punct" and tok.value == ",":
                self.i += 1
                continue
            if tok.kind == "word" and all(c.upper() in JOINT_TYPES for c in tok.value):
                letters.update(c.upper() for c in tok.value)
                self.i += 1
                continue
            self.error(f"a joint type letter ({' '.join(JOINT_TYPES)}) or ')'")
        if not letters:
            self.error("at least one joint type letter before ')'")
        return tuple(sorted(letters))

    def property_name(self, allowed: tuple[str, ...]) -> tuple[str, int]:
        tok = self.tok
        if tok.kind == "string":
            self.i += 1
            name = normalise_name(tok.value)
        elif self.at(*PROPERTIES):
            name = self.accept(*PROPERTIES)
        else:
            self.error("a property (“type”, “degree” or “length”)")
        if name not in allowed:
            raise CriterionSyntaxError(
                f"column {tok.pos + 1}: unknown property “{tok.value}”: expected "
                + " or ".join(f"“{p}”" for p in allowed), tok.pos, "a known property",
            )
        return name, tok.pos

    def property_relation(self, prop: str):
        """The relation after a property name: a type set relation, or a comparison for degree/length."""
        self.accept("property")
        self.accept("value", "values")
        if prop != "type":
            self.accept("as", "of")
            return JointCount(None, self.comparison())
        self.accept("be", "is", "are")
        relation = "="
        if self.tok.kind == "op" and _SYMBOL_OPS[self.tok.value] in ("=", "!="):
            relation = _SYMBOL_OPS[self.tok.value]
            self.i += 1
        elif self.accept("not"):
            self.expect("equal")
            self.expect("to")
            relation = "!="
        elif self.accept("equal"):
            self.expect("to")
        elif self.accept("contain", "contains", "containing", "include", "includes", "including"):
            relation = "contains"
        elif self.accept("within"):
            relation = "within"
        else:
            self.accept("as", "of")
        return TypeIs(relation, self.joint_set())

    def vertex_ref(self) -> str:
        """``the vertex representing “X”``, ``a vertex representing X``, ``the X``."""
        self.accept("the", "a", "an", "any")
        if self.accept(*VERTEX_WORDS):
            self.expect("representing")
            self.accept("the")
        return self.name("the name of a vertex")

    def loop_ref(self) -> str:
        """``the “X” loop``, ``the loop representing “X”``, ``the independent loop representing X [loop]``."""
        self.accept("the")
        if self.accept("independent"):
            self.expect(*LOOP_WORDS)
            self.expect("representing")
            self.accept("the")
            name = self.name("the name of a loop")
            self.accept("loop")
            return name
        if self.accept(*LOOP_WORDS):
            self.expect("representing")
            self.accept("the")
            name = self.name("the name of a loop")
            self.accept("loop")
            return name
        name = self.name("the name of a loop")
        self.expect("loop")
        return name

    def modal(self, after_no: bool = False) -> bool:
        """``must|should|shall [not]``, ``may not``, ``cannot``, ``is|are [not]``: whether negated.

        After ``no vertex``, ``may`` alone is allowed: "no vertex may have ...".
        """
        if self.accept("must", "should", "shall", "is", "are"):
            return bool(self.accept("not"))
        if self.accept("may"):
            if after_no:
                return bool(self.accept("not"))
            self.expect("not")
            return True
        if self.accept("cannot"):
            return True
        self.error("'must', 'should', 'shall', 'may not', 'cannot', 'is' or 'are'")

    # -- predicates ------------------------------------------------------------------

    def predicate_expr(self, ctx: str):
        items = [self.predicate_and(ctx)]
        while self.accept("or"):
            items.append(self.predicate_and(ctx))
        return items[0] if len(items) == 1 else Or(tuple(items))

    def predicate_and(self, ctx: str):
        items = [self.predicate_term(ctx)]
        while self.at("and") and not self.at_modal_clause():
            self.i += 1
            items.append(self.predicate_term(ctx))
        return items[0] if len(items) == 1 else And(tuple(items))

    def at_modal_clause(self) -> bool:
        """At ``and must ...``: a new clause with its own modal (and its own negation)."""
        return self.at("and") and self.ahead(1, *self.clause_modals)

    def nest(self) -> None:
        """One more level of brackets or 'not': refuse absurd nesting instead of exhausting the stack."""
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise CriterionSyntaxError(
                f"column {self.tok.pos + 1}: nested more than {MAX_DEPTH} deep", self.tok.pos, "less nesting"
            )

    def predicate_term(self, ctx: str):
        self.nest()
        try:
            return self._predicate_term(ctx)
        finally:
            self.depth -= 1

    def _predicate_term(self, ctx: str):
        if self.accept_punct("["):
            inner = self.predicate_expr(ctx)
            self.expect_punct("]")
            return inner
        if self.accept("not"):
            return Not(self.predicate_term(ctx))
        return self.vertex_predicate() if ctx == "vertex" else self.loop_predicate()

    def vertex_predicate(self):
        self.accept("be", "is", "are")
        if self.at("not"):
            return self.predicate_term("vertex")
        if self.accept("adjacent"):
            self.expect("to")
            role = self.vertex_ref()
            return Adjacent(role, self.via_joint())
        if self.accept("connected", "jointed", "joined"):
            self.expect("to", "with")
            role = self.vertex_ref()
            if self.at("through", "via") and self.ahead(1, "a", "an") and self.ahead(2, "intermediate"):
                self.i += 3
                self.expect(*VERTEX_WORDS)
                return Distance(role, Comparison("=", 2))
            return Adjacent(role, self.via_joint())
        if self.accept("at"):
            self.expect("distance")
            comparison = self.comparison()
            self.expect("from")
            return Distance(self.vertex_ref(), comparison)
        if self.at(*DEGREE_WORDS):
            degree = DEGREE_WORDS[self.accept(*DEGREE_WORDS)]
            self.accept(*VERTEX_WORDS)
            return JointCount(None, Comparison("=", degree))
        if self.accept("in", "on"):
            return InLoop(self.loop_ref())
        if self.accept("member"):
            self.expect("of")
            return InLoop(self.loop_ref())
        if self.accept("represent", "represents", "representing"):
            return Represents(self.vertex_ref())
        if self.accept("share", "shares"):
            negated = self.accept("no") is not None
            if not negated:
                self.accept("a", "an", "one", "any")
            joint = self.joint_kind()
            self.expect("with")
            condition = Adjacent(self.vertex_ref(), joint)
            return Not(condition) if negated else condition
        if self.accept("have", "has", "having", "with"):
            return self.have("vertex")
        if self.tok.kind == "string" or self.at("the") or (self.tok.kind == "word" and self.tok.value not in KEYWORDS):
            return Represents(self.vertex_ref())
        self.error("a vertex property ('adjacent to ...', 'have type (P R)', 'have degree 2', 'binary', "
                   "'represent “ground”', 'in the “drive” loop', ...)")

    def via_joint(self) -> str | None:
        if self.accept("by", "through", "via"):
            self.accept("a", "an")
            return self.joint_kind()
        return None

    def loop_predicate(self):
        self.accept("be", "is", "are")
        if self.at("not"):
            return self.predicate_term("loop")
        if self.accept("contain", "contains", "containing", "include", "includes", "including"):
            return HasMember(self.vertex_ref())
        if self.accept("pass", "passes"):
            self.expect("through")
            return HasMember(self.vertex_ref())
        if self.accept("share", "shares"):
            negated = self.accept("no") is not None
            if not negated:
                self.accept("a", "an", "one", "any")
            self.expect(*JOINT_NOUNS)
            self.expect("with")
            condition = SharesJoint(self.loop_ref())
            return Not(condition) if negated else condition
        if self.accept("adjoin", "adjoins"):
            return SharesJoint(self.loop_ref())
        if self.accept("have", "has", "having", "with"):
            return self.have("loop")
        self.error("a loop property ('have a slider pair in it', 'have at most 1 gear pairs', 'have length 4', "
                   "'contain “ground”', 'share a joint with the “drive” loop', ...)")

    def have(self, ctx: str):
        """After ``have``/``has``/``with``: a property value, a number of joints, a member."""
        allowed = ("type", "degree") if ctx == "vertex" else ("type", "length")
        self.accept("its", "the")
        if self.tok.kind == "string" or self.at(*PROPERTIES):
            prop, _ = self.property_name(allowed)
            condition = self.property_relation(prop)
        elif self.accept("no"):
            condition = JointCount(self.joint_kind(loop=ctx == "loop"), Comparison("=", 0))
        elif self.at("a", "an") and not (ctx == "loop" and self.ahead(1, *VERTEX_WORDS)):
            self.i += 1
            condition = JointCount(self.joint_kind(loop=ctx == "loop"), Comparison(">=", 1))
        elif ctx == "loop" and self.at("a", "an", *VERTEX_WORDS):
            condition = HasMember(self.vertex_ref())
            if self.accept("as"):
                self.accept("a")
                self.expect("member")
        else:
            comparison = self.comparison()
            condition = JointCount(self.joint_kind(loop=ctx == "loop"), comparison)
        if self.accept("in"):
            self.expect("it", "them")
        return condition

    # -- statements --------------------------------------------------------------------

    def criterion(self) -> Criterion:
        if self.tok.kind == "end":
            self.error("a criterion (e.g. 'every vertex must have degree at most 3')")
        start = self.i
        self.accept("the")
        if self.at("value") and self.ahead(1, "of"):
            statement = self.value_statement()
        elif self.at("number") and self.ahead(1, "of"):
            statement = self.count_statement()
        else:
            self.i = start
            statement = self.subject_statement()
        self.finish()
        return statement

    def domain_for_any(self) -> Domain:
        self.expect("for")
        self.expect("any", "every", "each", "all")
        if self.accept(*VERTEX_WORDS):
            return Domain("vertex")
        independent = self.accept("independent")
        if self.accept(*LOOP_WORDS):
            return Domain("independent_loop" if independent else "loop")
        self.error("'vertex', 'independent loop' or 'loop'")

    def value_statement(self) -> ForAll:
        """(i): ``[the] value of [the] property “TYPE” should not be equal to (G P R) for any vertex``."""
        self.expect("value")
        self.expect("of")
        self.accept("the")
        self.accept("property")
        prop, prop_pos = self.property_name(PROPERTIES)
        negated = self.modal()
        condition = self.property_relation(prop)
        domain = self.domain_for_any()
        wrong = ("length" if domain.kind == "vertex" else "degree") == prop
        if wrong:
            raise CriterionSyntaxError(
                f"column {prop_pos + 1}: a {domain.kind.replace('_', ' ')} has no property “{prop}”",
                prop_pos, "a property of the domain",
            )
        return ForAll(domain, Not(condition) if negated else condition)

    def count_statement(self):
        """(ii), (iv) and (iii): ``[the] number of <vertices|loops|joints> ... should not be more than N``."""
        self.expect("number")
        self.expect("of")
        condition = None
        if self.at(*DEGREE_WORDS) or self.at(*VERTEX_WORDS):
            degree = DEGREE_WORDS.get(self.accept(*DEGREE_WORDS))  # "the number of binary links"
            self.expect(*VERTEX_WORDS)
            domain = Domain("vertex")
            condition = self.vertex_filter()
            if degree is not None:
                binary = JointCount(None, Comparison("=", degree))
                condition = binary if condition is None else And((binary, condition))
        elif self.at("independent", *LOOP_WORDS):
            independent = self.accept("independent")
            self.expect(*LOOP_WORDS)
            domain = Domain("independent_loop" if independent else "loop")
            condition = self.loop_filter()
        else:
            joint = self.joint_kind()
            negated = self.modal()
            comparison = self.comparison()
            if negated:
                comparison = comparison.negated()
            return ForAll(self.domain_for_any(), JointCount(joint, comparison))
        negated = self.modal()
        comparison = self.comparison()
        return Count(domain, condition, comparison.negated() if negated else comparison)

    def vertex_filter(self):
        if self.accept("whose"):
            prop, _ = self.property_name(("type", "degree"))
            self.accept("property")
            self.accept("has", "have", "is", "are")
            return self.property_relation(prop)
        if self.accept("representing"):
            return Represents(self.vertex_ref())
        if self.at("with", "having", "adjacent", "connected", "jointed", "joined", "at", "in", "on"):
            return self.vertex_predicate()  # "links adjacent to the ground", "links in the drive loop"
        if self.accept("that", "which"):
            return self.predicate_expr("vertex")
        return None

    def loop_filter(self):
        if self.at("with", "having"):
            return self.loop_predicate()
        if self.accept("that", "which"):
            return self.predicate_expr("loop")
        if self.accept("containing", "through"):
            return HasMember(self.vertex_ref())
        return None

    def subject_statement(self) -> ForAll:
        negated_subject = False
        if self.at("no", "every", "each", "any", "all"):
            negated_subject = self.accept("no", "every", "each", "any", "all") == "no"
            if self.accept(*VERTEX_WORDS):
                domain = Domain("vertex")
            else:
                independent = self.accept("independent")
                self.expect(*LOOP_WORDS)
                domain = Domain("independent_loop" if independent else "loop")
        else:
            self.accept("the")
            if self.accept(*VERTEX_WORDS):
                self.expect("representing")
                self.accept("the")
                domain = Domain("vertex", self.name("the name of a vertex"))
            elif self.accept("independent") or self.at(*LOOP_WORDS):
                self.expect(*LOOP_WORDS)
                self.expect("representing")
                self.accept("the")
                domain = Domain("loop", self.name("the name of a loop"))
                self.accept("loop")
            else:
                name = self.name("'every vertex', 'the vertex representing ...', 'the number of ...' or a name")
                if self.at(*JOINT_NOUNS):
                    return self.active_statement(name)
                domain = Domain("loop", name) if self.accept("loop") else Domain("vertex", name)
        ctx = "vertex" if domain.kind == "vertex" else "loop"
        self.clause_modals = MODALS + ("is", "are")
        clauses = []
        while True:  # "must not A and must B": each modal negates its own clause only
            negated = self.modal(after_no=negated_subject)
            condition = self.predicate_expr(ctx)
            clauses.append(Not(condition) if negated != negated_subject else condition)
            if not self.at_modal_clause():
                break
            self.i += 1
        return ForAll(domain, clauses[0] if len(clauses) == 1 else And(tuple(clauses)))

    def active_statement(self, role: str) -> ActivePairs:
        """``the input pairs must be active [pairs] [with full DOF]``: the active-pair criterion (§3-2-I.5)."""
        self.expect(*JOINT_NOUNS)
        tok = self.tok
        if self.modal():
            raise CriterionSyntaxError(
                f"column {tok.pos + 1}: an active-pair statement cannot be negated: write "
                f"'the {role.replace('_', ' ')} pairs must be active pairs'", tok.pos, "'must' without 'not'")
        self.accept("be")
        if not self.accept("active"):
            self.error("'active' ('the input pairs must be active pairs')")
        self.accept(*JOINT_NOUNS)
        dof_type = None
        if self.accept("with", "giving", "of"):
            self.accept("a", "an")
            word = self.accept(*DOF_TYPES, "total")
            if word is None:
                self.error("a DOF type: " + ", ".join(f"'{t}'" for t in DOF_TYPES))
            dof_type = "full" if word == "total" else word
            if self.accept("degrees", "degree"):
                self.expect("of")
                self.expect("freedom")
            else:
                self.expect("dof", "freedom")
        return ActivePairs(role, dof_type)

    # -- relevance ------------------------------------------------------------------------

    def relevance(self) -> Relevance:
        if self.tok.kind == "end":
            self.error("a relevance condition (e.g. 'always' or 'the problem has “piston”')")
        condition = self.relevance_or()
        self.finish()
        return condition

    def relevance_or(self):
        items = [self.relevance_and()]
        while self.accept("or"):
            items.append(self.relevance_and())
        return items[0] if len(items) == 1 else AnyOf(tuple(items))

    def relevance_and(self):
        items = [self.relevance_term()]
        while self.accept("and"):
            items.append(self.relevance_term())
        return items[0] if len(items) == 1 else AllOf(tuple(items))

    def relevance_term(self):
        self.nest()
        try:
            return self._relevance_term()
        finally:
            self.depth -= 1

    def _relevance_term(self):
        if self.accept_punct("["):
            inner = self.relevance_or()
            self.expect_punct("]")
            return inner
        if self.accept("not"):
            return NoneOf(self.relevance_term())
        if self.accept("always"):
            return Always()
        self.accept("the")
        if self.accept("problem"):
            if self.accept("class"):
                self.expect("is")
                return ClassIs(self.name("the name of a problem class"))
            self.expect("has", "have")
            self.accept("a", "an", "the")
            name = self.name("the name of a representative attribute, vertex or loop")
            self.accept(*VERTEX_WORDS, "loop", "attribute")
            return HasName(name)
        if self.accept("number"):
            self.expect("of")
        attribute = self.attribute()
        negated = False if self.tok.kind == "op" else self.modal()
        comparison = self.comparison()
        return Attribute(attribute, comparison.negated() if negated else comparison)

    def attribute(self) -> str:
        if self.at("gear", "slider", "prismatic"):
            word = self.accept("gear", "slider", "prismatic")
            self.expect("pairs", "pair", "joints", "joint")
            return "gear_pairs" if word == "gear" else "slider_pairs"
        word = self.accept(*ATTRIBUTE_WORDS)
        if word is None:
            self.error("'the problem has ...', 'the problem class is ...' or a problem attribute "
                       "(degrees of freedom, independent loops, outputs, gear pairs, slider pairs, links, joints)")
        if word in ("degrees", "degree"):
            self.expect("of")
            self.expect("freedom")
        elif word == "independent":
            self.expect("loops", "loop")
        return ATTRIBUTE_WORDS[word]


def parse_criterion(text: str) -> Criterion:
    """The typed tree of a criterion; :class:`CriterionSyntaxError` says where and what was expected.

    >>> parse_criterion("NUMBER OF GEAR PAIRS SHOULD NOT BE MORE THAN 1 FOR ANY INDEPENDENT LOOP")
    ForAll(domain=Domain(kind='independent_loop', name=None), condition=JointCount(joint='G', comparison=Comparison(op='<=', value=1)))
    """
    return _Parser(text).criterion()


def parse_relevance(text: str) -> Relevance:
    """The typed tree of a relevance condition on problem attributes.

    >>> parse_relevance("the problem has “piston” and the number of slider pairs is at least 1")
    AllOf(items=(HasName(name='piston'), Attribute(attribute='slider_pairs', comparison=Comparison(op='>=', value=1))))
    """
    return _Parser(text).relevance()
