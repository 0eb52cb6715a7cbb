"""The deliverable of a design session: the report page and a mechanism file for each feasible design.

:func:`write_report` writes, into one folder, ``index.html`` (:func:`domes.sketch.report.report_html`: the
problem and its requirements, the funnel, the ranked designs with their drawings, motion, curves and checks)
and ``design-RANK-candidate-ID.json`` for each feasible design, a mechanism file that ``domes kinematics``,
``domes tolerance`` and ``domes draw`` take. Every file is written atomically.

A spatial problem (λ = 6) gets :func:`spatial_report_html` instead: its candidates are single loops of
spatial joints, told by their joint sequences (``4 links: R-S-S-R``), not drawn as planar sketches.
"""

from __future__ import annotations

from pathlib import Path

from domes.errors import InputError
from domes.io.files import why_not_made, write_atomic
from domes.io.mechanisms import save_mechanism
from domes.knowledge.problems import ProblemFrame
from domes.model.mechanism import Mechanism
from domes.model.mobility import SPATIAL
from domes.sketch.report import STYLE, funnel, report_html
from domes.sketch.report import _table as table
from domes.sketch.svg import tag
from domes.typesynth.spatial import SPATIAL_JOINT_TYPES, loop_reading, spatial_phrase


def report_folder(base, problem_class: str) -> Path:
    """Where a session's report goes: ``base``, or ``domes-report-CLASS`` in the working folder for ``"auto"``."""
    if str(base) == "auto":
        return Path(f"domes-report-{problem_class.replace('_', '-')}")
    return Path(base)


def write_report(folder: Path, frame: ProblemFrame, words: dict, scene_title: str = "") -> Path:
    """Write the report of ``frame`` and its designs' mechanism files into ``folder``; returns the page's path."""
    folder = Path(folder)
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(f"cannot write the report to {folder}: {why_not_made(folder, exc)}") from None
    files = {}
    for d in frame.designs:
        if d.get("status") == "feasible" and d.get("mechanism"):
            name = f"design-{d['rank']}-candidate-{d['candidate']}.json"
            save_mechanism(Mechanism.from_dict(d["mechanism"]), folder / name)
            files[d["candidate"]] = name
    page = folder / "index.html"  # a session without requirements: the kept candidates, sketched
    if frame.space == SPATIAL:
        write_atomic(page, spatial_report_html(frame, words))
    else:
        write_atomic(page, report_html(frame, words, scene_title, files))
    return page


def spatial_report_html(frame: ProblemFrame, words: dict | None = None) -> str:
    """The report page of a spatial design (λ = 6): the problem, the funnel with the criterion that removed each
    group, and the kept single loops told by their joints, read from the input joint on the frame round to the
    output joint, with their DOF and any idle spin flagged.

    >>> from domes.typesynth.spatial import FunctionGenerator, SpatialLoop
    >>> rssr = FunctionGenerator("RSSR", SpatialLoop("RRSS")).labelled().to_dict()
    >>> page = spatial_report_html(ProblemFrame("s-1", "spatial fg", dof=1, space=6, loops=1, links=7, joints=7,
    ...                                         results=({"id": 4, **rssr},)))
    >>> "R-S-S-R" in page and "1 idle spin" in page and "spatial (λ = 6)" in page
    True
    """
    words = words or {}
    title = f"Design report: {(frame.title or frame.problem_class).replace('_', ' ')}"
    body = [tag("h1", text=title),
            tag("p", {"class": "summary"}, text=f"case {frame.id}" + (f", {frame.date}" if frame.date else "")
                + "; DOMES-py design session (docs/expert.md), spatial type synthesis (docs/spatial.md)")]
    sizes = sorted({len(c.get("links", ())) for c in frame.results}) or [frame.links or 0]
    loops = (f"single loops of {sizes[0]} to {sizes[-1]} links" if sizes[0] != sizes[-1]
             else f"single loops of {sizes[0]} links") + ", as many joints"
    problem = [("class", frame.problem_class.replace("_", " ")), ("mechanism type", "spatial (λ = 6)"),
               ("degrees of freedom", frame.dof), ("independent loops", frame.loops),
               ("candidates kept", f"{loops} (the structure rule's {frame.links} links, {frame.joints} joints "
                                   "hold for joints of one freedom)"),
               ("joints", ", ".join(f"{t} {name}" for t, name in SPATIAL_JOINT_TYPES.items())),
               ("sliders (P joints), gear pairs", f"{frame.slider_pairs or 0}, {frame.gear_pairs or 0}"),
               ("representative attributes", ", ".join(sorted(n.replace("_", " ") for n in frame.names)) or "none")]
    body += [tag("h2", {"class": "section"}, text="Problem"), table(problem)]
    rows = [(r.stage, r.count, "; ".join(f"{k} removed by {what}" for what, k in r.removed))
            for r in funnel(frame, words)]
    body += [tag("h2", {"class": "section"}, text="Funnel"), table(rows, ("level", "kept", "removed"))]
    body.append(tag("h2", {"class": "section"}, text=f"Candidates kept ({len(frame.results)})"))
    body.append(tag("p", {"class": "note"}, text="Each candidate is a frame (link 0), an input jointed to it and "
                    "an output jointed to it; its joints are read from the input joint round to the output joint. "
                    "Type synthesis gives no dimensions: dimension an RSSR or RCCC with domes synthesize."))
    kept = [(str(c.get("id")), "-".join(loop_reading(c) or "?"), spatial_phrase(c)) for c in frame.results]
    body.append(table(kept, ("candidate", "joints", "links, joints and DOF")))
    if frame.notes:
        body.append(tag("h2", {"class": "section"}, text="Notes"))
        body.append(tag("ul", children=[tag("li", text=n) for n in frame.notes]))
    head = [tag("meta", {"charset": "utf-8"}), tag("title", text=title), tag("style", text=STYLE)]
    page = tag("html", {"xmlns": "http://www.w3.org/1999/xhtml", "lang": "en"},
               [tag("head", children=head), "\n", tag("body", children=body), "\n"])
    return "<!DOCTYPE html>\n" + page + "\n"

