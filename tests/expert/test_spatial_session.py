"""A spatial design session from answers to report: the spatial criteria screen, the wording is spatial.

The problem of examples/design/spatial-function.answers: a function generator of one loop, DOF 1, λ = 6
(seed 002, §7-2, structure rule i = W + (λ − 1) L − j_G + 1 = 7). Its candidates are the single-loop
function generators of domes.typesynth.spatial; the criteria of knowledge/criteria/05-spatial.toml keep
the four-link ones with a revolute input and a turning output, among them the RSSR of seed 001 and the
RCCC of seed 004.
"""

from pathlib import Path

from domes.expert.dialogue import Dialogue
from domes.expert.feasible import DesignKnobs
from domes.io.resources import knowledge_dir
from domes.io.transcripts import load_transcript, parse_answers
from domes.knowledge.problems import ProblemFrame
from domes.knowledge.relevance import relevance_vector
from domes.store.casebase import KnowledgeBase
from domes.typesynth.number import number_synthesis
from domes.typesynth.spatial import (
    FunctionGenerator,
    SpatialLoop,
    function_generators,
    idle_freedoms,
    kutzbach,
    loop_reading,
    spatial_loops,
    spatial_phrase,
)

ROOT = Path(__file__).resolve().parents[2]
ANSWERS = (ROOT / "examples" / "design" / "spatial-function.answers").read_text()
SPATIAL_IDS = ("spatial-rotary-input", "spatial-rotary-output", "spatial-four-links")


def session(url, text, report=None):
    said = []
    outcome = Dialogue(url, parse_answers(text), interactive=False, out=said.append,
                       knobs=DesignKnobs(report=report)).run()
    return outcome, "\n".join(said)


def expected_survivors():
    """The criteria's meaning, computed from the listing directly: 4 links, input joint R, output joint not P."""
    found = []
    for links in range(3, 8):
        for gen in function_generators(spatial_loops(links, dof=1)):
            if "P" not in gen.joints and links <= 4 and gen.joints[0] == "R" and gen.joints[-1] != "P":
                found.append(gen.joints)
    return sorted(found)


def test_a_spatial_session_screens_by_the_spatial_criteria_and_speaks_spatially(casebase, tmp_path):
    """Seed 002 §7-2 (screening with reasons), seeds 001 and 004 (RSSR and RCCC survive): the funnel, the
    terminal and the report of examples/design/spatial-function.answers."""
    outcome, said = session(casebase, ANSWERS, report=tmp_path / "report")
    frame = outcome.frame
    assert frame.space == 6 and outcome.relation == "different"
    kept = sorted(c["name"] for c in frame.results)
    assert kept == expected_survivors()
    assert {"RSSR", "RCCC"} <= set(kept) and len(kept) == 11
    generated = len(frame.results) + len(frame.rejected)
    assert generated == 406
    removed = {}
    for r in frame.rejected:
        assert r["criterion"] in SPATIAL_IDS and r["reason"]
        removed[r["criterion"]] = removed.get(r["criterion"], 0) + 1
    # 406 − 22 four-link generators; of the 22 (no P), the 11 driven by a helical input joint
    assert removed == {"spatial-four-links": 384, "spatial-rotary-input": 11}
    assert "384 removed by spatial-four-links" in said and "11 removed by spatial-rotary-input" in said
    # the terminal tells the kept loops by their joints, with the RSSR's idle spin flagged (seed 001: M = 2)
    rssr = next(c["id"] for c in frame.results if c["name"] == "RSSR")
    rccc = next(c["id"] for c in frame.results if c["name"] == "RCCC")
    assert (f"candidate {rssr}: 4 links: R-S-S-R, DOF 1 (Kutzbach count 2, less 1 idle spin: link 2 turns freely "
            "about the line through the centres of its two S joints)") in said
    assert f"candidate {rccc}: 4 links: R-C-C-C, DOF 1\n" in said
    # 'rejected' names each rejected loop by its joints
    assert "(5 links: R-R-R-S-R): rejected by spatial-four-links" in said
    # the report: spatial wording, the funnel with its reasons, no planar sketch
    page = (tmp_path / "report" / "index.html").read_text()
    assert "spatial (λ = 6)" in page and "R-S-S-R" in page and "R-C-C-C" in page
    assert "384 removed by spatial-four-links" in page and "11 removed by spatial-rotary-input" in page
    assert "links, joints</th><td>7, 7" not in page and "<svg" not in page


def test_a_retained_spatial_case_is_listed_by_its_joints(casebase):
    """Seed 002 §7-2 (Fig. 7-8): a problem of a known class lists the solved ones; a spatial one by its loops."""
    session(casebase, ANSWERS)
    with KnowledgeBase(casebase) as kb:
        assert [p.id for p in kb.problems() if p.space == 6] == ["spatial-function-generator-1"]
    _, said = session(casebase, "class: spatial function generator\nrelation: same spatial-function-generator-1\n")
    line = next(s for s in said.splitlines() if s.startswith("  spatial-function-generator-1:"))
    assert line.startswith("  spatial-function-generator-1: DOF 1, spatial (λ = 6), 1 loop, 0 sliders; 11 candidates "
                           "kept: R-C-S-R, R-R-S-C, R-S-C-R, R-S-S-R,")
    assert "links, " not in line


def test_the_spatial_criteria_are_irrelevant_to_every_planar_problem():
    """Seed 002 §7-2: i = W + (λ − 1) L − j_G + 1, so one loop and DOF 1 give 7 links only when λ = 6; every
    shipped (planar) case keeps its relevance vector and so its answers."""
    frames = KnowledgeBase().frames()
    spatial = [f for f in frames if f.id in SPATIAL_IDS]
    assert len(spatial) == 3
    assert [number_synthesis(1, 1, 3, gears).links for gears in range(3)] == [4, 3, 2]
    assert number_synthesis(1, 1, 6, 0).links == 7
    for path in sorted((knowledge_dir() / "cases").glob("*.json")):
        frame = ProblemFrame.from_dict(load_transcript(path)["frame"])
        assert frame.space == 3
        assert relevance_vector(spatial, frame).bits == (0, 0, 0), path.stem
    problem = ProblemFrame("p", "spatial", dof=1, space=6, loops=1, links=7, joints=7)
    assert relevance_vector(spatial, problem).bits == (1, 1, 1)


def test_the_spatial_wording_reads_every_listed_generator_back():
    """Seeds 001 and 004: every function generator of DOF 1 (3 to 7 links) is read back from its labelled chain,
    and its DOF is its Kutzbach count Σ f − 6 less its idle spins (the RSSR: 2 − 1)."""
    for links in range(3, 8):
        for gen in function_generators(spatial_loops(links, dof=1)):
            chain = gen.labelled()
            assert loop_reading(chain.to_dict()) == gen.joints
            phrase = spatial_phrase(chain)
            assert phrase.startswith(f"{links} links: {'-'.join(gen.joints)}, DOF 1")
            assert ("idle spin" in phrase) == (idle_freedoms(gen.joints) == 1)
    rssr = FunctionGenerator("RSSR", SpatialLoop("RRSS"))
    assert kutzbach("RSSR") == 2 and "Kutzbach count 2, less 1 idle spin" in spatial_phrase(rssr.labelled())
    # a chain that is not a single loop with a frame, an input and an output is said to be so
    assert loop_reading(rssr.labelled().with_roles({0: {"ground"}}).to_dict()) is None
