"""The criterion language: the book's six sentences, scene rules, errors, JSON and the canonical reading."""

from pathlib import Path

import pytest

from domes.errors import DomesError
from domes.io.criteria import read_knowledge
from domes.language.parse import CriterionSyntaxError, parse_criterion, parse_relevance, tokenize
from domes.language.render import render_criterion, render_relevance
from domes.language.tree import (
    Adjacent,
    AllOf,
    And,
    Attribute,
    Comparison,
    Count,
    Distance,
    Domain,
    ForAll,
    HasName,
    JointCount,
    Not,
    Represents,
    TypeIs,
    category,
    from_json,
    to_json,
)

ROOT = Path(__file__).resolve().parents[2]  # the checkout

# Seed 002 (Wang 1996), §7-2, knowledge-engineer module; digest part 4.5: the six
# example sentences, verbatim (the "VER-TICES" line-break hyphen and curly quotes kept),
# with the tree each must mean and its category (i)-(vi).
BOOK = [
    (
        "THE VALUE OF PROPERTY “TYPE” SHOULD NOT BE EQUAL TO (G P R) FOR ANY VERTEX",
        ForAll(Domain("vertex"), Not(TypeIs("=", ("G", "P", "R")))),
        "i",
    ),
    (
        "THE NUMBER OF VER-TICES WHOSE “TYPE” PROPERTY HAS VALUE (P R) SHOULD NOT BE GREATER THAN 1",
        Count(Domain("vertex"), TypeIs("=", ("P", "R")), Comparison("<=", 1)),
        "ii",
    ),
    (
        "NUMBER OF GEAR PAIRS SHOULD NOT BE MORE THAN 1 FOR ANY INDEPENDENT LOOP",
        ForAll(Domain("independent_loop"), JointCount("G", Comparison("<=", 1))),
        "iii",
    ),
    (
        "NUMBER OF INDEPENDENT LOOPS WITH A SLIDER PAIR IN IT SHOULD NOT BE MORE THAN 1",
        Count(Domain("independent_loop"), JointCount("P", Comparison(">=", 1)), Comparison("<=", 1)),
        "iv",
    ),
    (
        "THE VERTEX REPRESENTING “PISTON” MUST HAVE ITS “TYPE” PROPERTY-VALUE AS (P R)",
        ForAll(Domain("vertex", "piston"), TypeIs("=", ("P", "R"))),
        "v",
    ),
    (
        "THE INDEPENDENT LOOP REPRESENTING “DRIVE” LOOP MUST NOT HAVE A SLIDER PAIR IN IT",
        ForAll(Domain("loop", "drive"), Not(JointCount("P", Comparison(">=", 1)))),
        "vi",
    ),
]

# The same six, lower case and less shouty (straight quotes, no hyphen, other wording).
PLAIN = [
    'the value of property "type" should not be equal to (G, P, R) for any vertex',
    "the number of vertices whose type property has value (p r) should not be greater than 1",
    "the number of gear pairs must be at most 1 for every independent loop",
    "number of independent loops with a slider pair in it should be no more than 1",
    "the vertex representing piston must have type (P R)",
    "the drive loop must not have a slider pair in it.",
]


@pytest.mark.parametrize("text, tree, cat", BOOK)
def test_book_sentences_parse_to_their_meaning(text, tree, cat):
    parsed = parse_criterion(text)
    assert parsed == tree
    assert category(parsed) == cat
    assert parse_criterion(text.lower()) == tree


@pytest.mark.parametrize("plain, book", list(zip(PLAIN, BOOK)))
def test_plain_forms_mean_the_same(plain, book):
    assert parse_criterion(plain) == book[1]


# Scene rules of seed 002 §4-1 (Yan's motorcycle suspension, digest 2.2 / A8) and
# §5-3 (tyre drum rule F1, digest 3.7), written in the same language.
SCENES = [
    ("the swing arm is adjacent to the ground", ForAll(Domain("vertex", "swing_arm"), Adjacent("ground"))),
    (
        "the vertices representing “shock absorber” must be binary and adjacent to a vertex representing "
        "“shock absorber” and not represent “ground”",
        ForAll(
            Domain("vertex", "shock_absorber"),
            And((JointCount(None, Comparison("=", 2)), Adjacent("shock_absorber"), Not(Represents("ground")))),
        ),
    ),
    (
        "the vertex representing “tile A” must share no joint with the vertex representing “tile B”",
        ForAll(Domain("vertex", "tile_a"), Not(Adjacent("tile_b"))),
    ),
    (
        "the vertex representing “tile A” must be connected to the vertex representing “tile B” through an intermediate link",
        ForAll(Domain("vertex", "tile_a"), Distance("tile_b", Comparison("=", 2))),
    ),
    ("the input is adjacent to the ground by a revolute pair", ForAll(Domain("vertex", "input"), Adjacent("ground", "R"))),
    ("the swing arm must have degree at least 3", ForAll(Domain("vertex", "swing_arm"), JointCount(None, Comparison(">=", 3)))),
    ("no vertex may have type (G P R)", ForAll(Domain("vertex"), Not(TypeIs("=", ("G", "P", "R"))))),
    (
        "the number of binary links adjacent to the ground must be at least 2",
        Count(Domain("vertex"), And((JointCount(None, Comparison("=", 2)), Adjacent("ground"))), Comparison(">=", 2)),
    ),
]


@pytest.mark.parametrize("text, tree", SCENES)
def test_scene_rules_parse(text, tree):
    assert parse_criterion(text) == tree


def test_relevance_conditions_parse():
    assert parse_relevance("the problem has “piston” and the number of slider pairs is at least 1") == AllOf(
        (HasName("piston"), Attribute("slider_pairs", Comparison(">=", 1)))
    )
    assert parse_relevance("gear pairs > 0") == Attribute("gear_pairs", Comparison(">", 0))
    assert parse_relevance("the number of degrees of freedom should not be more than 2") == Attribute(
        "dof", Comparison("<=", 2)
    )


def shipped():
    return read_knowledge(ROOT / "knowledge")


def test_canonical_reading_parses_back_to_the_same_tree():
    # The renderer is an independent inverse of the parser: text -> tree -> text -> tree.
    texts = [t for t, _, _ in BOOK] + PLAIN + [t for t, _ in SCENES] + [f.text for f in shipped()]
    for text in texts:
        tree = parse_criterion(text)
        assert parse_criterion(render_criterion(tree)) == tree, text
    for f in shipped():
        assert parse_relevance(render_relevance(f.relevance)) == f.relevance


def test_json_round_trip_of_every_shipped_criterion():
    for f in shipped():
        assert from_json(to_json(f.tree)) == f.tree
        assert from_json(to_json(f.relevance)) == f.relevance


@pytest.mark.parametrize(
    "text, column, expected",
    [
        ("", 1, "a criterion"),
        ("banana", 7, "'must'"),
        ("every vertex must have type (G P R", 35, "a joint type letter"),
        ("THE VALUE OF PROPERTY “COLOUR” SHOULD NOT BE EQUAL TO (G P R) FOR ANY VERTEX", 23, "a known property"),
        ("__import__('os').system('rm -rf /')", 11, "'must'"),
        ("every vertex must “never close", 19, "a closing quote"),
        ("every vertex must have type (X)", 30, "a joint type letter"),
        ("every vertex; DROP TABLE criteria", 13, "a word"),
        ("every vertex must have degree at most 3 4", 41, "the end of the criterion"),
        ("the value of property “length” should be 4 for any vertex", 23, "a property of the domain"),
    ],
)
def test_bad_text_is_refused_with_position_and_expectation(text, column, expected):
    with pytest.raises(CriterionSyntaxError) as info:
        parse_criterion(text)
    assert info.value.position == column - 1
    assert expected in info.value.expected
    assert str(info.value).startswith(f"column {column}:")
    assert isinstance(info.value, DomesError)


def test_line_break_hyphen_only_joins_keywords():
    assert [t.value for t in tokenize("VER-TICES PROPERTY-VALUE shock-absorber") if t.kind != "end"] == [
        "vertices", "property", "value", "shock", "absorber",
    ]


@pytest.mark.parametrize(
    "data, expect, message",
    [
        ({"node": "Eval", "code": "1"}, None, "unknown node 'Eval'"),
        ({"node": "ForAll", "domain": {"node": "Domain", "kind": "vertex", "name": None},
          "condition": {"node": "HasMember", "role": "x"}}, None, "HasMember is not a vertex condition"),
        ({"node": "ForAll", "domain": {"node": "Domain", "kind": "vertex", "name": None},
          "condition": {"node": "TypeIs", "relation": "=", "joints": ["R", "P"]}}, None, "sorted distinct joint types"),
        ({"node": "ForAll", "domain": {"node": "Domain", "kind": "vertex", "name": "Swing Arm"},
          "condition": {"node": "Represents", "role": "ground"}}, None, "is not a name"),
        ({"node": "Count", "domain": {"node": "Domain", "kind": "loop", "name": None}, "condition": None,
          "comparison": {"node": "Comparison", "op": "<", "value": -1}}, None, "whole number >= 0"),
        ([1, 2], None, "expected an object"),
        ({"node": "Comparison", "op": "<", "value": 1}, None, "Comparison is not a criterion or relevance condition"),
        ({"node": "Always"}, "criterion", "Always is not a criterion"),
    ],
)
def test_malformed_json_trees_are_refused(data, expect, message):
    with pytest.raises(DomesError, match=message):
        from_json(data, expect=expect)
