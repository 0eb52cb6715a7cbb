"""The deliverable of a design session: the report page and a mechanism file for each feasible design.

:func:`write_report` writes, into one folder, ``index.html`` (:func:`domes.sketch.report.report_html`: the
problem and its requirements, the funnel, the ranked designs with their drawings, motion, curves and checks)
and ``design-RANK-candidate-ID.json`` for each feasible design, a mechanism file that ``domes kinematics``,
``domes tolerance`` and ``domes draw`` take. Every file is written atomically.

A spatial problem (λ = 6) gets :func:`domes.sketch.report.spatial_report_html` instead: its candidates are single loops of
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
from domes.sketch.report import report_html, spatial_report_html


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
