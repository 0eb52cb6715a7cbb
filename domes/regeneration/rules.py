"""The declarative link conditions of a scene (a small form of the criterion language).

A condition is about one link ``x`` of a partly labelled chain::

    condition := term ("or" term)*
    term      := ["not"] atom
    atom      := "binary" | "ternary" | "quaternary"
               | "degree" OP INTEGER                 OP: = == != < <= > >=
               | "adjacent to" ROLE ["that is not" ROLE2]
                                                     x shares a joint with a ROLE link
                                                     (that does not also carry ROLE2)
               | ["is"] ROLE                         x carries ROLE

A stage's ``where`` list holds conditions that must all hold. Role names are
identifiers (letters, digits, ``_``); ``a`` and ``an`` are ignored, so
"adjacent to the ground" reads naturally.

>>> c = parse_condition("binary or adjacent to ground")
>>> c
Condition(terms=(Term(negated=False, kind='degree', op='==', value=2, role='', unless=''), Term(negated=False, kind='adjacent', op='', value=0, role='ground', unless='')))
>>> sorted(c.roles())
['ground']
"""

from __future__ import annotations

import operator
import re
from dataclasses import dataclass

from domes.errors import DomesError
from domes.labelled.graph import LabelledChain

_OPS = {"=": operator.eq, "==": operator.eq, "!=": operator.ne, "<": operator.lt, "<=": operator.le, ">": operator.gt, ">=": operator.ge}
_NAMED_DEGREES = {"binary": 2, "ternary": 3, "quaternary": 4, "quinary": 5}
_TOKEN = re.compile(r"\s*(<=|>=|==|!=|[<>=]|[A-Za-z_][A-Za-z0-9_]*|\d+|\S)")
_FILLER = {"the", "a", "an", "link", "links"}


@dataclass(frozen=True)
class Term:
    """One atom, possibly negated: a degree test, an adjacency or a role."""

    negated: bool
    kind: str  # "degree" | "adjacent" | "role"
    op: str = ""
    value: int = 0
    role: str = ""
    unless: str = ""  # for "adjacent to ROLE that is not UNLESS"

    def holds(self, chain: LabelledChain, x: int) -> bool:
        if self.kind == "degree":
            result = _OPS[self.op](chain.degrees[x], self.value)
        elif self.kind == "adjacent":
            result = any(
                self.role in chain.roles[y] and not (self.unless and self.unless in chain.roles[y])
                for y in chain.neighbours[x]
            )
        else:
            result = self.role in chain.roles[x]
        return result != self.negated


@dataclass(frozen=True)
class Condition:
    """Terms joined by ``or``."""

    terms: tuple[Term, ...]

    def holds(self, chain: LabelledChain, x: int) -> bool:
        return any(t.holds(chain, x) for t in self.terms)

    def roles(self) -> set[str]:
        """The role names the condition refers to."""
        return {r for t in self.terms for r in (t.role, t.unless) if r}


def parse_condition(text: str) -> Condition:
    """Parse one condition; a :class:`DomesError` says where it stopped making sense."""
    tokens = [m.group(1) for m in _TOKEN.finditer(text)]
    tokens = [t for t in tokens if t.lower() not in _FILLER]
    if not tokens:
        raise DomesError(f"empty condition {text!r}")
    terms: list[Term] = []
    i = 0

    def expect(what: str) -> str:
        nonlocal i
        if i >= len(tokens):
            raise DomesError(f"condition {text!r}: expected {what} at the end")
        token = tokens[i]
        i += 1
        return token

    while True:
        negated = False
        if i < len(tokens) and tokens[i].lower() == "not":
            negated, i = True, i + 1
        word = expect("a condition (binary, ternary, degree, adjacent to ROLE, or a role)")
        low = word.lower()
        if low in _NAMED_DEGREES:
            terms.append(Term(negated, "degree", "==", _NAMED_DEGREES[low]))
        elif low == "degree":
            op = expect("a comparison (=, <, <=, >, >=, !=)")
            if op not in _OPS:
                raise DomesError(f"condition {text!r}: expected a comparison after 'degree', got {op!r}")
            value = expect("a number")
            if not value.isdigit():
                raise DomesError(f"condition {text!r}: expected a number after 'degree {op}', got {value!r}")
            terms.append(Term(negated, "degree", op, int(value)))
        elif low == "adjacent":
            if expect("'to'").lower() != "to":
                raise DomesError(f"condition {text!r}: expected 'adjacent to ROLE'")
            role = _role(expect("a role name"), text)
            unless = ""
            if i < len(tokens) and tokens[i].lower() == "that":
                i += 1
                if [expect("'is'").lower(), expect("'not'").lower()] != ["is", "not"]:
                    raise DomesError(f"condition {text!r}: expected 'that is not ROLE'")
                unless = _role(expect("a role name"), text)
            terms.append(Term(negated, "adjacent", role=role, unless=unless))
        elif low == "is":
            terms.append(Term(negated, "role", role=_role(expect("a role name"), text)))
        else:
            terms.append(Term(negated, "role", role=_role(word, text)))
        if i == len(tokens):
            return Condition(tuple(terms))
        if tokens[i].lower() != "or":
            raise DomesError(f"condition {text!r}: expected 'or' or the end, got {tokens[i]!r}")
        i += 1


def _role(word: str, text: str) -> str:
    if not re.fullmatch(r"[A-Za-z_][A-Za-z0-9_]*", word) or word.lower() in ("or", "not", "to", "adjacent", "degree", "that", "is"):
        raise DomesError(f"condition {text!r}: expected a role name, got {word!r}")
    return word


def impossible(conditions: list[Condition], links: int) -> str | None:
    """Why a conjunction of conditions can never hold on a chain of ``links`` links, or ``None``.

    Checks degree bounds (every link of a chain has 2 .. n−1 joints) and a
    term required together with its own negation.

    >>> impossible([parse_condition("binary"), parse_condition("ternary")], 6)
    'no link can be binary and ternary at once'
    """
    allowed = set(range(2, links))
    required: dict[tuple, bool] = {}
    for condition in conditions:
        if len(condition.terms) != 1:
            possible = set()
            for t in condition.terms:
                if t.kind == "degree":
                    possible |= {d for d in range(2, links) if _OPS[t.op](d, t.value) != t.negated}
                else:
                    possible = set(range(2, links))
            allowed &= possible
            continue
        term = condition.terms[0]
        if term.kind == "degree":
            allowed &= {d for d in range(2, links) if _OPS[term.op](d, term.value) != term.negated}
            if not allowed:
                names = [t for c in conditions for t in c.terms if t.kind == "degree"]
                words = [next((k for k, v in _NAMED_DEGREES.items() if v == t.value and t.op == "==" and not t.negated), None) for t in names]
                if len(words) >= 2 and all(words):
                    return f"no link can be {' and '.join(words)} at once"
                return f"no link of a {links}-link chain has such a degree (links carry 2 to {links - 1} joints)"
        else:
            key = (term.kind, term.role)
            if required.get(key, term.negated) != term.negated:
                return f"a link cannot be both {'adjacent to ' if term.kind == 'adjacent' else ''}{term.role} and not"
            required[key] = term.negated
    if not allowed:
        return f"no link of a {links}-link chain has such a degree (links carry 2 to {links - 1} joints)"
    return None
