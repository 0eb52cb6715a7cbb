"""The report of a design session: one self-contained, printable HTML page (inline SVG and CSS, no script, no
network), from the problem and its requirements to the ranked designs.

Sections: the problem (the frame's attributes, the scene and the requirements with their units); the funnel
(how many candidates each level kept, and the criterion or check that removed each group: the structural
screening levels F1-F5 of seed 002 §5-3, then the feasibility level); the ranked designs (each drawn to
scale, moving through its stroke, its curve against the wanted one, every check with its value and limit,
and each factor's part of its score); the designs that are not feasible and why; the session's notes. A
session without requirements stops at the screening: its kept candidates are drawn as sketches instead. A
spatial problem (λ = 6) gets :func:`spatial_report_html`: its single loops told by their joints.

>>> from domes.knowledge.problems import ProblemFrame
>>> frame = ProblemFrame("demo-1", "demo", dof=1, loops=1, results=({"id": 1},), rejected=())
>>> rows = funnel(frame)
>>> [(r.stage, r.count) for r in rows]
[('generated', 1), ('quasi-feasible (after the screening levels)', 1)]
>>> page = report_html(frame)
>>> page.startswith("<!DOCTYPE html>") and "Funnel" in page
True
"""

from __future__ import annotations

import math
from collections import Counter
from dataclasses import dataclass, field

import numpy as np

from domes.errors import DomesError
from domes.knowledge.problems import ProblemFrame
from domes.model.combination_modes import combination_phrase
from domes.model.labelled import LabelledChain
from domes.model.mechanism import Mechanism
from domes.motion.planar.sweep import sweep
from domes.sketch.atlas import STYLE as CARD_STYLE
from domes.sketch.atlas import mechanism_card
from domes.sketch.curves import animated_svg
from domes.sketch.dimensioned import dimensioned_svg
from domes.sketch.svg import document, num, tag
from domes.sketch.synthesis import curve_svg
from domes.typesynth.spatial import SPATIAL_JOINT_TYPES, loop_reading, spatial_phrase

STYLE = CARD_STYLE + """
h2.section { font-size: 1.15em; border-bottom: 1px solid #ccd; margin-top: 1.6em; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.4em 0; }
th, td { border: 1px solid #ccd; padding: 2px 6px; text-align: left; vertical-align: top; }
th { background: #eef; }
td.num { text-align: right; font-family: monospace; }
td.pass { color: #2a7d3f; } td.fail { color: #c1121f; font-weight: bold; }
.design { background: #fff; border: 1px solid #ccd; border-radius: 6px; padding: 8px; margin: 10px 0;
          page-break-inside: avoid; break-inside: avoid; }
.design h3 { margin: 0 0 6px 0; font-size: 1.05em; }
.drawings { display: flex; flex-wrap: wrap; gap: 8px; }
.drawings figure { margin: 0; }
.drawings figcaption { font-size: 0.75em; color: #555; }
p.note { font-size: 0.85em; color: #555; }
@media print { body { background: #fff; margin: 0.5cm; } .design { border-color: #999; } }
"""
#: Frames of a design's animation over its stroke (there and back).
FRAMES = 36
SIZE = 300.0


@dataclass(frozen=True)
class FunnelRow:
    """One level of the funnel: how many candidates it kept (``count``) and what removed the others."""

    stage: str
    count: int
    removed: tuple[tuple[str, int], ...] = field(default_factory=tuple)


def funnel(frame: ProblemFrame, words: dict | None = None) -> list[FunnelRow]:
    """The funnel of a design: generated, each screening level, quasi-feasible, feasible, ranked."""
    words = words or {}
    generated = len(frame.results) + len(frame.rejected)
    rows = [FunnelRow("generated", generated)]
    left = generated
    by_level: dict[int, Counter] = {}
    for r in frame.rejected:
        by_level.setdefault(int(r.get("level", 0)), Counter())[r.get("criterion", "?")] += 1
    for level in sorted(by_level):
        removed = by_level[level]
        left -= sum(removed.values())
        rows.append(FunnelRow(f"screening level {level}", left,
                              tuple((_criterion(c, words), k) for c, k in sorted(removed.items()))))
    rows.append(FunnelRow("quasi-feasible (after the screening levels)", len(frame.results)))
    if frame.designs:
        lost = Counter()
        for d in frame.designs:
            if d.get("status") != "feasible":
                failed = [c["name"] for c in d.get("checks", []) if not c.get("passed")]
                lost[f"{d.get('status')}: {failed[0]}" if failed and d.get("status") == "infeasible"
                     else str(d.get("status"))] += 1
        feasible = sum(d.get("status") == "feasible" for d in frame.designs)
        rows.append(FunnelRow("feasible (dimensioned and verified)", feasible, tuple(sorted(lost.items()))))
        rows.append(FunnelRow("ranked", feasible))
    return rows


def _criterion(criterion_id: str, words: dict) -> str:
    return f"{criterion_id} ({words[criterion_id]})" if words.get(criterion_id) else criterion_id


def report_html(frame: ProblemFrame, words: dict | None = None, scene_title: str = "", files: dict | None = None) -> str:
    """The report page of a solved (or designed) problem ``frame``; ``words`` explain criteria by id, ``files``
    name the mechanism file of each design by candidate id."""
    words, files = words or {}, files or {}
    title = f"Design report: {(frame.title or frame.problem_class).replace('_', ' ')}"
    body = [tag("h1", text=title),
            tag("p", {"class": "summary"}, text=f"case {frame.id}" + (f", {frame.date}" if frame.date else "")
                + "; DOMES-py design session (docs/expert.md)")]
    body += _problem(frame, scene_title)
    body += _funnel(frame, words)
    ranked = sorted((d for d in frame.designs if d.get("status") == "feasible"), key=lambda d: d.get("rank", 0))
    if frame.designs:
        body.append(tag("h2", {"class": "section"}, text=f"Ranked designs ({len(ranked)})"))
        if ranked:
            weights = ranked[0].get("weights") or {}
            body.append(tag("p", {"class": "note"}, text="Fuzzy comprehensive evaluation of soft indices (membership "
                            "functions and grades: docs/expert.md); weights " + ", ".join(
                                f"{k} {v:.2f}" for k, v in weights.items()) + "."))
        for d in ranked:
            body.append(_design(d, frame, files.get(d["candidate"])))
        others = [d for d in frame.designs if d.get("status") != "feasible"]
        if others:
            body.append(tag("h2", {"class": "section"}, text=f"Not feasible ({len(others)})"))
            rows = [tag("tr", children=[tag("th", text=h) for h in ("candidate", "status", "why")])]
            for d in others:
                rows.append(tag("tr", children=[tag("td", {"class": "num"}, text=str(d["candidate"])),
                                                tag("td", text=d.get("status", "")),
                                                tag("td", text=d.get("reason", ""))]))
            body.append(tag("table", children=rows))
    else:
        body += _kept(frame)
    return _page(title, body, frame.notes)


def _page(title: str, body: list[str], notes) -> str:
    """The whole page: ``body`` and the session's ``notes``, with the title and the style in its head."""
    if notes:
        body = body + [tag("h2", {"class": "section"}, text="Notes"), tag("ul", children=[tag("li", text=n)
                                                                                          for n in notes])]
    head = [tag("meta", {"charset": "utf-8"}), tag("title", text=title), tag("style", text=STYLE)]
    page = tag("html", {"xmlns": "http://www.w3.org/1999/xhtml", "lang": "en"},
               [tag("head", children=head), "\n", tag("body", children=body), "\n"])
    return "<!DOCTYPE html>\n" + page + "\n"


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
    body += [tag("h2", {"class": "section"}, text="Problem"), _table(problem)]
    rows = [(r.stage, r.count, "; ".join(f"{k} removed by {what}" for what, k in r.removed))
            for r in funnel(frame, words)]
    body += [tag("h2", {"class": "section"}, text="Funnel"), _table(rows, ("level", "kept", "removed"))]
    body.append(tag("h2", {"class": "section"}, text=f"Candidates kept ({len(frame.results)})"))
    body.append(tag("p", {"class": "note"}, text="Each candidate is a frame (link 0), an input jointed to it and "
                    "an output jointed to it; its joints are read from the input joint round to the output joint. "
                    "Type synthesis gives no dimensions: dimension an RSSR or RCCC with domes synthesize."))
    kept = [(str(c.get("id")), "-".join(loop_reading(c) or "?"), spatial_phrase(c)) for c in frame.results]
    body.append(_table(kept, ("candidate", "joints", "links, joints and DOF")))
    return _page(title, body, frame.notes)


def _table(rows, header=None) -> str:
    out = [tag("tr", children=[tag("th", text=h) for h in header])] if header else []
    for row in rows:
        out.append(tag("tr", children=[tag("th", text=row[0])] + [tag("td", text=str(v)) for v in row[1:]]))
    return tag("table", children=out)


def _problem(frame: ProblemFrame, scene_title: str) -> list[str]:
    out = [tag("h2", {"class": "section"}, text="Problem")]
    sizes = sorted({(len(c.get("links", ())), len(c.get("joints", ()))) for c in frame.results})
    size = f"{frame.links}, {frame.joints}"
    if sizes and sizes != [(frame.links, frame.joints)]:  # a scene's generalized chains, particularized
        size += (" (the scene's chains; its elements made the candidates "
                 + " or ".join(f"{n} links, {j} joints" for n, j in sizes) + ")")
    rows = [("class", frame.problem_class.replace("_", " ")), ("degrees of freedom", frame.dof),
            ("independent loops", frame.loops), ("links, joints", size),
            ("sliders, gear pairs", f"{frame.slider_pairs or 0}, {frame.gear_pairs or 0}"),
            ("representative attributes", ", ".join(sorted(n.replace("_", " ") for n in frame.names)) or "none"),
            ("scene", scene_title or frame.scene or "none")]
    out.append(_table(rows))
    if frame.requirements:
        out.append(tag("h2", {"class": "section"}, text="Requirements"))
        out.append(_table([(r.label or r.id, r.shown, r.text) for r in frame.requirements],
                          ("requirement", "value", "as given")))
    return out


def _funnel(frame: ProblemFrame, words: dict) -> list[str]:
    rows = funnel(frame, words)
    top = max((r.count for r in rows), default=1) or 1
    out = [tag("h2", {"class": "section"}, text="Funnel")]
    width, bar = 520.0, 18.0
    items = []
    for k, r in enumerate(rows):
        y = 4 + k * (bar + 6)
        w = max(1.0, (width - 320) * r.count / top)  # room after the longest bar for its number
        items.append(tag("rect", {"class": "funnel-bar", "x": "250", "y": num(y), "width": num(w), "height": num(bar),
                                  "fill": "#457b9d"}))
        items.append(tag("text", {"x": "244", "y": num(y + 13), "font-size": "11", "text-anchor": "end",
                                  "fill": "#1d3557"}, text=r.stage))
        items.append(tag("text", {"x": num(254 + w), "y": num(y + 13), "font-size": "11", "fill": "#1d3557"},
                         text=str(r.count)))
    out.append(document(width, 8 + len(rows) * (bar + 6), items, title="the funnel of candidates"))
    table = []
    for r in rows:
        table.append((r.stage, r.count, "; ".join(f"{k} removed by {what}" for what, k in r.removed)))
    out.append(_table(table, ("level", "kept", "removed")))
    return out


def _kept(frame: ProblemFrame) -> list[str]:
    """The kept candidates' sketches (a session without requirements stops at the screening)."""
    out = [tag("h2", {"class": "section"}, text=f"Candidates kept ({len(frame.results)})")]
    cards = []
    for c in frame.results:
        title = f"Candidate {c.get('id')}"
        badge = "existing design" if c.get("existing") else None
        try:
            chain = LabelledChain.from_dict(c)
            mode = _mode(chain, frame.dof)
            cards.append(mechanism_card(c.get("id"), chain, title=title, badge=badge, size=SIZE * 0.8,
                                        properties=(("combination", mode),) if mode else ()).html())
        except DomesError as exc:
            cards.append(tag("div", {"class": "card"}, [tag("h2", text=title), tag("p", text=f"not drawn: {exc}")]))
    out.append(tag("div", {"class": "cards"}, cards))
    return out


def _mode(chain: LabelledChain, dof: int | None) -> str:
    """The candidate's combination mode (seed 002 §3-3-III.2), or empty without a single frame and driver."""
    try:
        return combination_phrase(chain, dof)
    except DomesError:
        return ""


def _design(d: dict, frame: ProblemFrame, file: str | None) -> str:
    heading = f"{d.get('rank')}. candidate {d['candidate']}: score {d.get('score', 0):.3f} ({d.get('grade', '')})"
    children = [tag("h3", text=heading)]
    chosen = next((c for c in frame.results if c.get("id") == d["candidate"]), None)
    try:
        mode = _mode(LabelledChain.from_dict(chosen), frame.dof) if chosen is not None else ""
    except DomesError:
        mode = ""
    if mode:
        children.append(tag("p", {"class": "note"}, text=mode[0].upper() + mode[1:]))
    figures = []
    mech = None
    try:
        mech = Mechanism.from_dict(d["mechanism"])
        figures.append(_figure(dimensioned_svg(mech, size=SIZE), "drawn to scale at the start of the stroke"))
        if d.get("stroke"):
            figures.append(_figure(motion_svg(mech, *d["stroke"]), "moving through its stroke (animated)"))
    except (DomesError, KeyError, ValueError) as exc:
        figures.append(_figure(document(SIZE, 40, [tag("text", {"x": "4", "y": "20", "font-size": "11"},
                                                       text=f"not drawn: {exc}")]), ""))
    curve = d.get("curve")
    if curve:
        x = np.asarray(curve["x"], float)
        achieved = np.array([np.nan if v is None else v for v in curve["achieved"]], float)
        wanted = np.array([np.nan if v is None else v for v in curve["wanted"]], float)
        figures.append(_figure(curve_svg(x, [("achieved", achieved, "#c1121f", False), ("wanted", wanted, "#2a9d8f", True)],
                                         curve.get("x_label") or "x", curve.get("quantity") or "curve", size=SIZE),
                               "the wanted curve and the one the design gives"))
    children.append(tag("div", {"class": "drawings"}, figures))
    rows = [tag("tr", children=[tag("th", text=h) for h in ("check", "", "value", "limit", "what it found")])]
    for c in d.get("checks", []):
        value = "" if c.get("value") is None else f"{c['value']:.4g} {c.get('unit', '')}".strip()
        limit = "" if c.get("limit") is None else (("≥ " if c.get("kind") == "min" else "≤ ")
                                                    + f"{c['limit']:.4g} {c.get('unit', '')}".strip())
        rows.append(tag("tr", children=[tag("td", text=c["name"]),
                                        tag("td", {"class": "pass" if c["passed"] else "fail"},
                                            text="passed" if c["passed"] else "failed"),
                                        tag("td", {"class": "num"}, text=value), tag("td", {"class": "num"}, text=limit),
                                        tag("td", text=c.get("message", ""))]))
    children.append(tag("table", {"class": "checks"}, rows))
    factors = d.get("contributions") or {}
    if factors:
        rows = [tag("tr", children=[tag("th", text=h) for h in ("factor", "value", "goodness", "weight",
                                                                 "part of the score")])]
        for name, part in sorted(factors.items(), key=lambda kv: -(kv[1] or 0)):
            value = (d.get("values") or {}).get(name)
            rows.append(tag("tr", children=[
                tag("td", text=name), tag("td", {"class": "num"}, text="" if value is None else f"{value:.4g}"),
                tag("td", {"class": "num"}, text=f"{(d.get('goodness') or {}).get(name, 0):.3f}"),
                tag("td", {"class": "num"}, text=f"{(d.get('weights') or {}).get(name, 0):.3f}"),
                tag("td", {"class": "num"}, text=f"{part:.3f}")]))
        children.append(tag("table", {"class": "ranking"}, rows))
    if file:
        children.append(tag("p", {"class": "note"}, [tag("a", {"href": file}, text=file), " (the mechanism file: "
                                                     "domes kinematics, domes tolerance, domes draw take it)"]))
    return tag("div", {"class": "design", "id": f"design-{d['candidate']}", "data-rank": str(d.get("rank", ""))},
               children)


def _figure(svg: str, caption: str) -> str:
    return tag("figure", children=["\n" + svg + "\n", tag("figcaption", text=caption)])


def motion_svg(mech: Mechanism, start: float, stop: float, size: float = SIZE) -> str:
    """The mechanism moving from ``start`` to ``stop`` of its input and back (an animated SVG)."""
    names = [j.name for j in mech.joints] + [p.name for p in mech.points]
    step = abs(stop - start) / (FRAMES - 1)
    sw = sweep(mech, start, stop, step, outputs=[f"point:{n}" for n in names])
    tracks = {}
    for n in names:
        xy = np.c_[np.asarray(sw.table[f"point:{n}.x"], float), np.asarray(sw.table[f"point:{n}.y"], float)]
        tracks[n] = np.vstack([xy, xy[::-1][1:]])           # there and back
    point = mech.points[0].name if mech.points else None
    path = None if point is None else tracks[point][: len(tracks[point]) // 2 + 1]
    shown = "°" if mech.joint(mech.inputs[0].joint).kind == "R" else ""
    span = (f"{math.degrees(start):.4g}{shown} to {math.degrees(stop):.4g}{shown}" if shown
            else f"{start:.4g} to {stop:.4g}")
    return animated_svg(mech, tracks, path=path, size=size, point=point, title=f"{mech.name}: {span}")
