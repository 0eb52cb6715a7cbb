"""Property-based tests of the criterion language (bounded: max_examples, no deadline).

Random text and random sequences of the language's own words never crash the
parser with anything but a syntax error; random trees read back from their
canonical text and their JSON unchanged, and the compiled criterion gives the
same verdict as an independent interpreter (criterion_reference.py) on
labelled chains with roles, joint types and a named loop.
"""

import dataclasses

from criterion_reference import Reference
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from domes.language.evaluate import compile_criterion, graph_features
from domes.language.parse import KEYWORDS, CriterionSyntaxError, parse_criterion, parse_relevance
from domes.language.render import render_criterion, render_relevance
from domes.language.tree import (
    PROBLEM_ATTRIBUTES,
    Adjacent,
    AllOf,
    Always,
    And,
    AnyOf,
    Attribute,
    ClassIs,
    Comparison,
    Count,
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
    Represents,
    SharesJoint,
    TypeIs,
    from_json,
    to_json,
)
from domes.model import LabelledChain

BOUNDED = settings(max_examples=300, deadline=None, database=None, suppress_health_check=[HealthCheck.too_slow])

WATT = LabelledChain.build(
    6, [(0, 1), (0, 2), (2, 3), (1, 3), (0, 4), (4, 5), (1, 5)], {(0, 2): "P", (4, 5): "G"},
    {0: {"ground"}, 2: {"input"}, 5: {"output"}}, {"drive": [0, 2, 3, 1]},
)
STEPHENSON = LabelledChain.build(
    6, [(0, 1), (0, 2), (1, 3), (2, 3), (1, 4), (2, 5), (4, 5)], {(4, 5): "P", (1, 3): "S"},
    {0: {"ground", "piston"}, 2: {"swing_arm"}, 4: {"shock_absorber"}, 5: {"shock_absorber", "output"}},
    {"drive": [1, 4, 5, 2, 3]},
)
EIGHT_BAR = LabelledChain.build(  # a three-loop chain with a ternary-to-ternary joint, geared and sliding
    8, [(0, 1), (0, 2), (0, 3), (1, 4), (2, 5), (3, 6), (4, 7), (5, 7), (6, 7), (1, 2)],
    {(0, 1): "G", (5, 7): "G", (3, 6): "P", (1, 2): "P"},
    {0: {"ground"}, 4: {"input"}, 7: {"output", "piston"}}, {"drive": [0, 1, 4, 7, 5, 2]},
)
GRAPHS = [(g, graph_features(g), Reference(g)) for g in (WATT, STEPHENSON, EIGHT_BAR)]
WATT_FEATURES = GRAPHS[0][1]


def agrees_with_reference(tree) -> None:
    """The compiled criterion and the independent interpreter give the same verdict on every test graph;
    a count is compared at every value it could take (``= v`` for v = 0..12), so any difference in the
    number counted shows, not only one that crosses the tree's own comparison."""
    variants = [tree]
    if isinstance(tree, Count):
        variants += [dataclasses.replace(tree, comparison=Comparison("=", v)) for v in range(13)]
    for graph, features, reference in GRAPHS:
        for t in variants:
            assert compile_criterion(t)(features) == reference.holds(t), (t, graph.to_dict())


def parses_or_refuses(parse, text):
    try:
        tree = parse(text)
    except CriterionSyntaxError as exc:
        assert 0 <= exc.position <= len(text)
        assert exc.expected
        return None
    assert from_json(to_json(tree)) == tree
    return tree


@BOUNDED
@given(st.text(max_size=120))
def test_random_text_parses_or_is_refused(text):
    parses_or_refuses(parse_criterion, text)
    parses_or_refuses(parse_relevance, text)


PIECES = sorted(KEYWORDS) + ["“ground”", '"drive"', "“swing arm”", "(G P R)", "(P", ")", "[", "]", "1", "2", "0",
                             "<=", ">", "=", ",", ".", "“", "piston", "VER-TICES", "PROPERTY-VALUE", "“TYPE”"]


@BOUNDED
@given(st.lists(st.sampled_from(PIECES), max_size=25))
def test_random_word_sequences_parse_or_are_refused(words):
    text = " ".join(words)
    tree = parses_or_refuses(parse_criterion, text)
    if tree is not None:
        assert parse_criterion(render_criterion(tree)) == tree
        agrees_with_reference(tree)
    parses_or_refuses(parse_relevance, text)


# -- random trees -----------------------------------------------------------------------

# Names the test graphs use (so that conditions bite), and others (so that absent roles and loops are read right).
names = st.sampled_from(["ground", "input", "output", "piston", "swing_arm", "shock_absorber", "drive"]) | st.from_regex(
    r"[a-z][a-z0-9]{0,5}(_[a-z0-9]{1,4}){0,2}", fullmatch=True)
comparisons = st.builds(Comparison, st.sampled_from(["<", "<=", "=", "!=", ">=", ">"]), st.integers(0, 12))
joint = st.sampled_from(list("RPGCOSHF"))
joint_sets = st.sets(joint, min_size=1, max_size=4).map(lambda s: tuple(sorted(s)))
type_is = st.builds(TypeIs, st.sampled_from(["=", "!=", "contains", "within"]), joint_sets)
joint_count = st.builds(JointCount, st.none() | joint, comparisons)

vertex_atoms = st.one_of(
    type_is, joint_count, st.builds(Adjacent, names, st.none() | joint), st.builds(Distance, names, comparisons),
    st.builds(Represents, names), st.builds(InLoop, names),
)
loop_atoms = st.one_of(type_is, joint_count, st.builds(HasMember, names), st.builds(SharesJoint, names))


def conditions(atoms):
    return st.recursive(
        atoms,
        lambda inner: st.one_of(
            st.builds(Not, inner),
            st.lists(inner, min_size=2, max_size=3).map(lambda xs: And(tuple(xs))),
            st.lists(inner, min_size=2, max_size=3).map(lambda xs: Or(tuple(xs))),
        ),
        max_leaves=6,
    )


vertex_conditions = conditions(vertex_atoms)
loop_conditions = conditions(loop_atoms)
criteria = st.one_of(
    st.builds(ForAll, st.builds(Domain, st.just("vertex"), st.none() | names), vertex_conditions),
    st.builds(ForAll, st.builds(Domain, st.sampled_from(["loop", "independent_loop"])), loop_conditions),
    st.builds(ForAll, st.builds(Domain, st.just("loop"), names), loop_conditions),
    st.builds(Count, st.just(Domain("vertex")), st.none() | vertex_conditions, comparisons),
    st.builds(Count, st.builds(Domain, st.sampled_from(["loop", "independent_loop"])), st.none() | loop_conditions, comparisons),
)
relevances = st.recursive(
    st.one_of(st.just(Always()), st.builds(HasName, names), st.builds(ClassIs, names),
              st.builds(Attribute, st.sampled_from(PROBLEM_ATTRIBUTES), comparisons)),
    lambda inner: st.one_of(
        st.builds(NoneOf, inner),
        st.lists(inner, min_size=2, max_size=3).map(lambda xs: AllOf(tuple(xs))),
        st.lists(inner, min_size=2, max_size=3).map(lambda xs: AnyOf(tuple(xs))),
    ),
    max_leaves=5,
)


@BOUNDED
@given(criteria)
def test_every_tree_reads_back_from_its_canonical_text(tree):
    text = render_criterion(tree)
    assert parse_criterion(text) == tree, text
    assert parse_criterion(text.upper()) == tree
    assert from_json(to_json(tree)) == tree
    agrees_with_reference(tree)


@BOUNDED
@given(relevances)
def test_every_relevance_reads_back_from_its_canonical_text(tree):
    text = render_relevance(tree)
    assert parse_relevance(text) == tree, text
    assert from_json(to_json(tree)) == tree
