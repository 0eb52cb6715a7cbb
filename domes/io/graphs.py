"""Labelled graphs as JSON: lists of graphs, or the output of ``domes regenerate --format json``.

Each graph is ``{"links": n, "joints": [[u, v, type], ...], "roles": {link: [names]}, "loops": {name: [links]}}``
or the long form of :meth:`~domes.model.LabelledChain.to_dict`; role and loop
names are normalised as in the criterion language ("Swing arm" → ``swing_arm``).

>>> [g.joint_types for g in parse_labelled_graphs('[{"links": 3, "joints": [[0, 1, "P"], [1, 2], [0, 2]]}]')]
[('P', 'R', 'R')]
"""

from __future__ import annotations

import json
from pathlib import Path

from domes.errors import InputError
from domes.io.files import read_text
from domes.language.parse import normalise_name
from domes.model.labelled import LabelledChain


def parse_labelled_graphs(text: str, where: str = "<json>") -> list[LabelledChain]:
    """Labelled graphs from JSON: a list of graphs (see :meth:`LabelledChain.from_dict`), or the
    output of ``domes regenerate --format json`` (its candidates)."""
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise InputError(f"{where}: not valid JSON: {exc}") from None
    if isinstance(data, dict) and isinstance(data.get("candidates"), list):
        data = data["candidates"]
    if not isinstance(data, list):
        raise InputError(f"{where}: expected a list of labelled graphs, or the output of domes regenerate --format json")
    graphs = []
    for index, item in enumerate(data):
        graph = LabelledChain.from_dict(item, f"{where}: graph {index}")
        roles = {v: [normalise_name(r) for r in names] for v, names in enumerate(graph.roles)}
        loops = {normalise_name(name): links for name, links in graph.named_loops}
        graphs.append(LabelledChain.build(graph.n, graph.edges, graph.joint_types, roles, loops, name=graph.name,
                                          link_names=graph.link_names, joint_names=graph.joint_names))
    return graphs




def read_labelled_graphs(path: str | Path) -> list[LabelledChain]:
    """Labelled graphs from a JSON file (see :func:`parse_labelled_graphs`)."""
    return parse_labelled_graphs(read_text(path), str(path))
