"""Mechanism sketches of labelled chains: the symbols of Table 3-5 (seed 002 §3-3-I) and the roles."""

import math
import xml.etree.ElementTree as ET

import networkx as nx
import pytest
from svgcheck import SVG, parse

from domes.errors import DomesError
from domes.model import JOINT_TYPES, LabelledChain
from domes.sketch import mechanism_svg
from domes.typesynth import chains

# Suzuki RM-250X full floater, seed 002 §4-1 (digest 2.2, corrected MTM): links 1..6
# as 0..5; pairs a..g; g (5-6) is the prismatic pair of the shock absorber.
SUZUKI_PAIRS = [(1, 2), (1, 3), (2, 4), (3, 4), (2, 5), (3, 6), (5, 6)]
SUZUKI = LabelledChain.build(
    6,
    [(u - 1, v - 1) for u, v in SUZUKI_PAIRS],
    {(4, 5): "P"},
    roles={0: {"ground"}, 1: {"input"}, 2: {"swing_arm"}, 4: {"shock_absorber"}, 5: {"shock_absorber"}},
)
WATT = [(0, 1), (1, 2), (2, 3), (3, 0), (1, 4), (4, 5), (5, 0)]  # ternary links 0 and 1


def _classes(svg):
    root = ET.fromstring(svg)
    found = {}
    for el in root.iter():
        for cls in el.get("class", "").split():
            found.setdefault(cls, []).append(el)
    return found


def test_suzuki_sketch_symbols():
    svg = mechanism_svg(SUZUKI)
    found = _classes(svg)
    # ground (link 1 of the book) hatched, with a fixed pivot at each of its two joints a, b
    ground = [el for el in found["link"] if el.get("data-link") == "0"]
    assert ground and ground[0].get("fill") == "url(#hatch)"
    assert len(found["ground-pivot"]) == 2
    # the shock absorber dyad 5-6 as one cylinder-and-rod with its spring; its P joint is the piston
    (member,) = found["member"]
    assert member.get("data-links") == "4-5" and "shock-absorber" in found and "shock-spring" in found
    assert "slider-block" not in found
    # the input arrow, and the roles written beside their links
    assert len(found["input-arrow"]) == 1
    roles = {el.get("data-link"): el.text for el in found["role"]}
    assert roles == {"0": "ground", "1": "input", "2": "swing arm", "4": "shock absorber"}


def _distance_to_segment(p, a, b):
    ab = (b[0] - a[0], b[1] - a[1])
    t = ((p[0] - a[0]) * ab[0] + (p[1] - a[1]) * ab[1]) / max(ab[0] ** 2 + ab[1] ** 2, 1e-12)
    t = min(1.0, max(0.0, t))
    return math.dist(p, (a[0] + t * ab[0], a[1] + t * ab[1]))


def test_role_label_sits_beside_its_link():
    # "roles written beside their links": within a label offset (13 units + baseline) of the link's outline
    svg = mechanism_svg(SUZUKI)
    links, _ = parse(svg)
    for el in _classes(svg)["role"]:
        v = int(el.get("data-link"))
        if v not in links:
            continue  # the shock absorber is drawn as a member, not as links
        point = (float(el.get("x")), float(el.get("y")))
        outline = links[v]
        sides = [(outline[i - 1], outline[i]) for i in range(len(outline))]
        assert min(_distance_to_segment(point, a, b) for a, b in sides) <= 18


@pytest.mark.parametrize(
    "joint_type, symbol",
    [("P", "slider-block"), ("G", "gear"), ("C", "cam"), ("O", "roller"), ("H", "cylinder"), ("S", "spring"), ("F", "force")],
)
def test_joint_type_symbols(joint_type, symbol):
    # Table 3-5: each joint type has its own symbol; H, S, F replace the binary-link dyad 4-5.
    chain = LabelledChain.build(6, WATT, {(4, 5): joint_type}, roles={0: {"ground"}, 1: {"input"}})
    found = _classes(mechanism_svg(chain))
    assert symbol in found
    if joint_type in "HSF":
        assert [el.get("data-links") for el in found["member"]] == ["4-5"]
    else:
        assert [el.get("data-joint") for el in found["joint-symbol"]] == ["4-5"]


def test_member_joint_on_a_plate_is_marked_with_its_letter():
    # Table 3-5 marks the middle hinge with H or S; on a ternary link there is no dyad to redraw.
    chain = LabelledChain.build(6, WATT, {(0, 1): "H"}, roles={0: {"ground"}})
    found = _classes(mechanism_svg(chain))
    assert [el.text for el in found["joint-letter"]] == ["H"]


def test_given_joint_positions_are_kept():
    # The plug for the kinematics backend: joints at given points, up to the frame's scale and shift.
    four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={0: {"ground"}})
    given = {(0, 1): (0.0, 0.0), (1, 2): (1.0, 2.0), (2, 3): (4.0, 2.5), (0, 3): (5.0, 0.0)}
    _, joints = parse(mechanism_svg(four_bar, given))
    a, b, c = joints["0-1"], joints["0-3"], joints["2-3"]
    assert math.dist(a, c) / math.dist(a, b) == pytest.approx(math.dist((0, 0), (4, 2.5)) / 5.0, rel=1e-3)
    assert a[1] > joints["1-2"][1]  # y points up in the model, down in SVG


def test_bad_positions_say_which_joint():
    four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)])
    with pytest.raises(DomesError, match=r"\(2, 3\)"):
        mechanism_svg(four_bar, {(0, 1): (0, 0), (1, 2): (1, 0), (0, 3): (0, 1)})


def test_sketch_is_valid_xml_and_byte_identical():
    first = mechanism_svg(SUZUKI)
    assert ET.fromstring(first).tag == SVG + "svg"
    assert first == mechanism_svg(LabelledChain.build(6, SUZUKI.edges, SUZUKI.joint_types, dict(enumerate(SUZUKI.roles))))


def test_every_joint_type_on_every_joint_of_the_six_bars():
    # Robustness over the two one-DOF six-bar chains (Watt, Stephenson; seed 002 §4-1 Fig. 4-8):
    # any joint type on any joint, ground on link 0, input on a link jointed to it.
    for chain in chains(links=6, dof=1):
        driver = next(v for u, v in chain.edges if u == 0)
        for joint in chain.edges:
            for joint_type in JOINT_TYPES:
                labelled = LabelledChain.build(6, chain.edges, {joint: joint_type}, roles={0: {"ground"}, driver: {"input"}})
                found = _classes(mechanism_svg(labelled))
                assert len(found["input-arrow"]) == 1 and found["ground-pivot"]


def test_non_planar_chain_sketch():
    # A non-planar ten-bar chain (networkx check_planarity) still gets a sketch with all its joints.
    chain = next(c for c in chains(links=10, dof=1) if not nx.check_planarity(c.to_networkx())[0])
    labelled = LabelledChain.build(10, chain.edges, roles={0: {"ground"}})
    svg = mechanism_svg(labelled)
    drawn = {el.get("data-joint") for el in _classes(svg)["joint"]}
    assert drawn == {f"{u}-{v}" for u, v in chain.edges}
