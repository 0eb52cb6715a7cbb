"""A kept candidate dimensioned against a task file, as a design question (docs/synthesis.md).

At the design dialogue's verification step, ``dimension CANDIDATE TASK.json``
dimensions that kept candidate by least squares for the task's wanted
curve (a ``curve`` task, :mod:`domes.design.synthesis.candidate`), verifies
each layout along the stroke, draws them in ``TASK.candidate-N.html``, and
keeps the best verified mechanism with the case.
"""

from __future__ import annotations

from pathlib import Path

from domes.design.synthesis import synthesize
from domes.design.synthesis.candidate import CurveTask
from domes.errors import InputError
from domes.io.files import write_atomic
from domes.io.tasks import load_task
from domes.sketch.synthesis import synthesis_html


def dimension_candidate(candidate: int, chain, path: str, progress=None) -> tuple[str, dict | None]:
    """The layouts of a kept candidate for the task in ``path`` as text, and the best verified one as a record."""
    task = load_task(path, candidates=[(candidate, chain)])
    if not isinstance(task, CurveTask):
        raise InputError(f"{path}: a kept candidate is dimensioned against a 'curve' task (a wanted curve over "
                         f"its stroke); this task is of another kind")
    result = synthesize(task, progress=progress)
    best = next(iter(result.usable), None)
    lines = [f"dimensioned candidate {candidate} for {path}: {len(result.usable)} verified layout(s)",
             f"  {result.message}"]
    for s in result.solutions:
        state = "verified" if s.usable else "rejected: " + "; ".join(s.defects)
        lines.append(f"  curve error {100 * s.error:.3g}% largest, smallest transmission angle "
                     f"{s.min_transmission_deg:.1f}°: {state}")
    page = Path(path).with_suffix(f".candidate-{candidate}.html")
    write_atomic(page, synthesis_html(result, task))
    lines.append(f"  drawn in {page}")
    record = None if best is None else {"candidate": candidate, "task": task.name, "error": best.error,
                                        "mechanism": best.mechanism.to_dict()}
    if record is not None:
        lines.append("  the best verified layout is kept with the case")
    return "\n".join(lines), record
