"""The questions of the design dialogue: prompt, default, and a parser that validates an answer.

A parser returns the answer's value or raises :class:`DomesError` with the
reason; the session then asks again.

>>> parse_int_range(1, 8)("3")
3
>>> parse_yes_no("Yes")
True
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from domes.design.verify import Check, matches
from domes.errors import InputError
from domes.io.mechanisms import load_mechanism
from domes.io.resources import knowledge_dir
from domes.io.scenes import load_scene, scene_names
from domes.knowledge.catalogue import motion_pair, requirement
from domes.language.parse import normalise_name, parse_criterion, parse_relevance
from domes.language.tree import Always, ClassIs
from domes.model.labelled import LabelledChain
from domes.model.mechanism import Mechanism


@dataclass(frozen=True)
class Question:
    """A question of the dialogue: its prompt, the parser of its answers, a default and a help text.

    Answering ``?`` or ``help`` shows the help text and asks again.
    """

    id: str
    prompt: str
    parse: Callable[[str], Any]
    default: str | None = None
    help: str = ""
    #: Asked since answers files were first written: a file that does not answer it takes ``script_default``
    #: (None: the default).
    optional_in_scripts: bool = False
    script_default: str | None = None


def parse_int_range(low: int, high: int) -> Callable[[str], int]:
    def parse(text: str) -> int:
        try:
            value = int(text.strip())
        except ValueError:
            raise InputError(f"expected a whole number from {low} to {high}, got {text.strip()!r}") from None
        if not low <= value <= high:
            raise InputError(f"expected a whole number from {low} to {high}, got {value}")
        return value

    return parse


def parse_yes_no(text: str) -> bool:
    word = text.strip().lower()
    if word in ("y", "yes"):
        return True
    if word in ("n", "no"):
        return False
    raise InputError(f"answer yes or no, not {text.strip()!r}")


def parse_class(text: str) -> str:
    name = normalise_name(text)
    if not name or not name.replace("_", "").isalnum():
        raise InputError("a problem class is a name of letters, digits and spaces (e.g. motorcycle rear suspension)")
    return name


def parse_space(text: str) -> int:
    """λ: 3 for planar, 6 for spatial.

    >>> parse_space("Spatial"), parse_space("3")
    (6, 3)
    """
    word = text.strip().lower()
    if word in ("planar", "3"):
        return 3
    if word in ("spatial", "6"):
        return 6
    raise InputError(f"answer planar or spatial, not {text.strip()!r}")


def parse_names(text: str) -> frozenset[str]:
    if text.strip().lower() in ("", "none", "-"):
        return frozenset()
    names = [normalise_name(n) for n in text.split(",")]
    bad = [n for n in names if not n or not n.replace("_", "").isalnum()]
    if bad:
        raise InputError("give names separated by commas (e.g. ground, swing arm, shock absorber)")
    return frozenset(names)


def parse_scene_answer(text: str) -> str | None:
    """A shipped scene's name, or the path of a scene file of the user's (kept as its absolute path), or none."""
    word = text.strip()
    if word.lower() in ("", "none", "-"):
        return None
    known = scene_names()
    if word in known:
        return word
    if word.endswith(".toml") and Path(word).is_file():
        load_scene(word)                                 # a scene file that does not load is refused here
        return str(Path(word).resolve())
    raise InputError(f"no scene {word!r}; the scenes are: {', '.join(known)}, a scene file (FILE.toml, "
                     "docs/regeneration.md) or none")


def parse_criterion_text(text: str) -> str:
    parse_criterion(text)  # raises with the column and what was expected
    return text.strip()


def scope_parser(problem_class: str) -> Callable[[str], Any]:
    """``class`` (the problem's class), ``always``, or a relevance condition of the criterion language.

    >>> scope_parser("pump")("class")
    ClassIs(name='pump')
    """

    def parse(text: str):
        word = text.strip().lower()
        if word == "class":
            return ClassIs(problem_class)
        if word == "always":
            return Always()
        return parse_relevance(text)  # raises with the column and what was expected

    return parse


def requirement_parser(spec) -> Callable[[str], Any]:
    """A requirement's answer, in the spec's unit; a function of x is checked as the synthesis will read it."""
    from domes.design.synthesis.expressions import expression

    def parse(text: str):
        value = spec.parse(text)
        if spec.kind == "function":
            expression(value.value, spec.label)
        return value

    return parse


def parse_weights(text: str) -> dict[str, float]:
    """``default``, or factor weights: ``transmission 2, force 3`` (the others keep their defaults).

    >>> parse_weights("transmission 2, force 0.5")
    {'transmission': 2.0, 'force': 0.5}
    """
    from domes.design.brief import FACTORS, weights_from

    words = text.replace(",", " ").replace("=", " ").split()
    if not words or words == ["default"]:
        return {}
    if len(words) % 2:
        raise InputError(f"give factor weight pairs, e.g. 'transmission 2, force 1'; the factors are {', '.join(FACTORS)}")
    raw = {}
    for name, value in zip(words[::2], words[1::2]):
        try:
            raw[name] = float(value)
        except ValueError:
            raise InputError(f"the weight of {name} must be a number, got {value!r}") from None
    return weights_from(raw, "weights")


def relation_parser(cases: list[str]) -> Callable[[str], tuple[str, str | None]]:
    """``same [CASE]``, ``similar [CASE]`` or ``different``; the case may be left out when there is one."""

    def parse(text: str) -> tuple[str, str | None]:
        words = text.split()
        if not words or words[0].lower() not in ("same", "similar", "different"):
            raise InputError("answer same, similar or different (optionally followed by a case id)")
        relation = words[0].lower()
        if relation == "different":
            return relation, None
        if len(words) > 1:
            if words[1] not in cases:
                raise InputError(f"no case {words[1]!r} in this class; the cases are {', '.join(cases)}")
            return relation, words[1]
        if len(cases) > 1:
            raise InputError(f"say which case: {relation} {cases[0]} (cases: {', '.join(cases)})")
        return relation, cases[0]

    return parse


def overrides_parser(ids: list[str]) -> Callable[[str], list[tuple[str, int]]]:
    """``none``, or criterion ids to declare relevant (``ID`` or ``+ID``) or irrelevant (``-ID``)."""

    def parse(text: str) -> list[tuple[str, int]]:
        words = text.replace(",", " ").split()
        if not words or words == ["none"]:
            return []
        out = []
        for word in words:
            bit = 0 if word.startswith("-") else 1
            criterion = word.lstrip("+-")
            if criterion not in ids:
                raise InputError(f"no criterion {criterion!r} in the knowledge base (see `domes kb list`)")
            out.append((criterion, bit))
        return out

    return parse


def satisfied_parser(ids: list[str]) -> Callable[[str], bool | list[tuple[str, int]]]:
    """``yes``, ``no``, or criterion ids to relax (``-ID``) or add back (``+ID``) and design again."""
    overrides = overrides_parser(ids)

    def parse(text: str) -> bool | list[tuple[str, int]]:
        if text.strip()[:1] in ("-", "+"):
            return overrides(text)
        return parse_yes_no(text)

    return parse



def parse_function(text: str):
    """A motion conversion for the catalogue (``rotation -> straight line``), or None for ``none``."""
    if text.strip().lower() in ("", "none", "-"):
        return None
    return motion_pair(text)


def parse_function_requirements(text: str) -> tuple:
    """Requirements on the catalogue's mechanisms, separated by ``;`` (``dwell >= 90; index = 90``), or none."""
    if text.strip().lower() in ("", "none", "-"):
        return ()
    return tuple(requirement(part) for part in text.split(";") if part.strip())


HELP = {
    "class": "The kind of device, in a few words (e.g. motorcycle rear suspension, window lifter). Problems of "
             "one class are compared with each other: the same, similar or different.",
    "function": "A problem of the second class (seed 002, §5-1) asks for a function by motion mode: name the "
                "motion in and out (rotation, oscillation, reciprocation, intermittent rotation, straight line), e.g. "
                "'rotation -> intermittent rotation', and the catalogue of standard mechanisms proposes those that "
                "do it (domes catalogue, docs/catalogue.md); the dialogue then goes on to type synthesis. none "
                "skips the catalogue.",
    "function_requirements": "What the catalogue's mechanism must do, in its property's own unit, e.g. 'dwell >= "
                             "90' (degrees of the input turn), 'straight-line deviation <= 0.5' (percent), 'time "
                             "ratio >= 1.5'; several separated by ';'. none keeps every mechanism for the motion.",
    "outputs": "How many independent output motions the mechanism delivers (usually 1).",
    "dof": "The degrees of freedom W: how many inputs drive the mechanism (1 for a single motor or cylinder).",
    "space": "planar (λ = 3): every link moves in one plane; spatial (λ = 6): single loops of DOF 1 with R, P, "
             "H, C and S joints (RSSR, RCCC, ...), each with a frame, an input and an output jointed to it "
             "(docs/spatial.md).",
    "loops": "Independent loops L: the closed loops of the chain that are independent, L = joints − links + 1. "
             "A four-bar or a slider-crank has 1; a six-bar (Watt, Stephenson) 2; an eight-bar 3. With W the DOF "
             "and revolute or sliding joints, the chain has W + 2L + 1 links and W + 3L joints.",
    "gear_pairs": "How many gear pairs (each a joint of two degrees of freedom, j_G).",
    "slider_pairs": "How many prismatic (sliding) pairs, e.g. 1 for a piston in its cylinder; 0 for revolute joints only.",
    "more_criteria": "yes to type a criterion of your own in the criterion language (it joins the knowledge base), "
                     "no to design with the relevant criteria.",
    "criterion": "A sentence of the criterion language, e.g. 'the swing arm must be adjacent to the ground', "
                 "'every vertex must have degree at most 3', 'the number of loops that have a slider pair must be at "
                 "most 1'. Grammar: docs/knowledge.md.",
    "criterion_scope": "Which problems the new criterion is relevant to, so that it does not change the answers of "
                       "others: class (problems of this class, the default), always (every problem), or a relevance "
                       "condition, e.g. 'the problem has “piston”', 'the number of slider pairs is at least 1', "
                       "'the problem class is “pump” or the problem class is “compressor”'. Grammar: docs/knowledge.md.",
    "requirements": "yes to state the requirements the scene asks for (the motion wanted, stroke, forces, size, "
                    "accuracy; each with its unit, any unit of the same kind) and have every candidate that passes the "
                    "screening dimensioned for them, verified (assembly and branch, dead points, transmission angle, "
                    "forces, tolerances) and ranked; a report is written. no screens only.",
    "weights": "How much each factor counts in the ranking of the feasible designs, as factor weight pairs, e.g. "
               "'transmission 2, force 3'; the others keep their defaults. Factors: accuracy (the wanted curve), "
               "transmission (the smallest transmission angle), compactness (the space swept), force (the force "
               "requirement's margin), sensitivity (the tolerance spread over its budget), complexity (links, "
               "plates and sliders). 'default' keeps them all (docs/expert.md).",
    "satisfied": "yes keeps the result as a solved case; no adds criteria and designs again; 'rejected' lists every "
                 "rejected candidate with its criterion; -ID declares a criterion irrelevant (+ID relevant) and "
                 "designs again.",
    "relation": "same ID: the problem is that solved case (its result is shown); similar ID: its structure is taken "
                "over and only the attributes and criteria differ; different: a new problem of this class.",
    "scene": "A scene gives the links their roles stage by stage (ground, swing arm, ...), by the rules of a design "
             "(docs/regeneration.md); none labels only the joints (sliders, gear pairs) and has no roles.",
    "relevance_overrides": "none keeps the relevant criteria as listed; ID or +ID declares a criterion relevant, "
                           "-ID irrelevant (several, separated by spaces).",
    "verify": "none, or a kept candidate, a dimensioned mechanism file of it and a check: 'rotatability', 'range "
              "OUTPUT FROM:TO', e.g. 2 mechanisms/suzuki-rm250x.json range slide:g -10:10, or a check with forces: "
              "'force-ratio OUTPUT FROM:TO [RATIO]' (force amplification, the toggle, where RATIO is reached), "
              "'wheel-rate POINT SPRING FROM:TO' (leverage ratio and wheel rate from the file's spring), 'drive "
              "FROM:TO' (the input's force or torque from the file's masses and loads; docs/dynamics.md); or "
              "'path FILE' with a "
              "wanted coupler path (points x, y, CSV or JSON): the four-bars that trace it, from the atlas of "
              "coupler curves, refined and checked, drawn in FILE.matches.html (docs/curves.md); or 'dimension CANDIDATE "
              "TASK.json': the kept candidate dimensioned by least squares for the task's wanted curve, verified, "
              "drawn in TASK.candidate-N.html and kept with the case (docs/synthesis.md).",
}


def names_help(known: list[str]) -> str:
    """The help of the names question, with the names the knowledge base's criteria and the scenes know."""
    return ("Representative attributes: the special links and loops of the problem (roles such as ground, piston, "
            "swing arm), comma separated. Criteria about a name apply to problems that have it; a scene gives "
            "the links their roles. Names the criteria and scenes know: " + (", ".join(known) or "none") + ".")


STATIC = {
    "class": Question("class", "Problem class (e.g. motorcycle rear suspension)", parse_class, help=HELP["class"]),
    "function": Question("function", "Function by motion, to look up the catalogue (e.g. rotation -> intermittent "
                         "rotation), or none", parse_function, "none", HELP["function"], optional_in_scripts=True,
                         script_default="none"),
    "function_requirements": Question("function_requirements", "What must it do? (e.g. dwell >= 90; several "
                                      "separated by ';'), or none", parse_function_requirements, "none",
                                      HELP["function_requirements"], optional_in_scripts=True),
    "outputs": Question("outputs", "Number of output motions", parse_int_range(1, 8), "1", HELP["outputs"]),
    "dof": Question("dof", "Degrees of freedom W", parse_int_range(1, 6), "1", HELP["dof"]),
    "space": Question("space", "Mechanism type: planar or spatial", parse_space, "planar", HELP["space"]),
    "loops": Question("loops", "Independent loops L ('?' explains)", parse_int_range(1, 5), help=HELP["loops"]),
    "gear_pairs": Question("gear_pairs", "Gear pairs j_G", parse_int_range(0, 4), "0", HELP["gear_pairs"]),
    "slider_pairs": Question("slider_pairs", "Slider (prismatic) pairs", parse_int_range(0, 6), "0", HELP["slider_pairs"]),
    "more_criteria": Question("more_criteria", "Specify additional screening criteria? (yes/no)", parse_yes_no, "no",
                              HELP["more_criteria"]),
    "criterion": Question("criterion", "Criterion (e.g. the swing arm must be adjacent to the ground)", parse_criterion_text,
                          help=HELP["criterion"]),
}


def mechanism_for(candidate: LabelledChain, path: str) -> Mechanism:
    """The mechanism file for a kept candidate, checked to be that candidate.

    A relative path is looked up in the working folder, then in the knowledge
    folder (where the shipped cases' mechanisms are: ``mechanisms/NAME.json``).
    """
    found = Path(path)
    if not found.is_file() and not found.is_absolute() and (knowledge_dir() / found).is_file():
        found = knowledge_dir() / found
    if not found.is_file():
        raise InputError(f"no mechanism file {path!r} (looked in the working folder and in {knowledge_dir()})")
    mech = load_mechanism(found)
    if not matches(candidate, mech):
        raise InputError(f"{path} is not this candidate: its chain, joint types or ground differ")
    return mech


def verify_parser(kept: dict[int, LabelledChain]):
    """``none``, ``CANDIDATE FILE CHECK`` (see :mod:`domes.design.verify`), ``path FILE`` (a wanted coupler path)
    or ``dimension CANDIDATE TASK.json`` (dimension a kept candidate for a wanted curve)."""

    def parse(text: str):
        words = text.split()
        if not words or words == ["none"]:
            return None
        if words[0] == "dimension":
            if len(words) != 3 or not words[1].isdigit() or not Path(words[2]).is_file():
                raise InputError("answer: dimension CANDIDATE TASK.json, with TASK.json a curve task file that exists")
            if int(words[1]) not in kept:
                raise InputError(f"candidate {words[1]} is not among those kept ({', '.join(map(str, sorted(kept)))})")
            return ("dimension", int(words[1]), kept[int(words[1])], words[2])
        if words[0] == "path":
            if len(words) != 2 or not Path(words[1]).is_file():
                raise InputError("answer: path FILE, with FILE a file of points x, y (CSV or JSON) that exists")
            return ("path", words[1])
        if len(words) < 3 or not words[0].isdigit():
            raise InputError("answer none, or: CANDIDATE FILE CHECK (e.g. 2 mechanisms/suzuki-rm250x.json range slide:g -10:10)")
        candidate = int(words[0])
        if candidate not in kept:
            raise InputError(f"candidate {candidate} is not among those kept ({', '.join(map(str, sorted(kept)))})")
        check = Check.parse(words[2:])
        return candidate, mechanism_for(kept[candidate], words[1]), check, words[1]

    return parse
