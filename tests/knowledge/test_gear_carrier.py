"""The gear-carrier criterion (knowledge/criteria/02-generic.toml): a gear pair closes a three-link loop.

Checked on every simple graph of 5 links and 6 joints and of 7 links and 9
joints with minimum degree 2 (networkx's atlas of graphs, isomorphism-reduced
there), one joint made a gear pair at a time, against the common neighbours
of the gear's two links (a carrier), and against the backend: a geared
five-bar whose gears share a carrier is dimensioned (tests/motion/test_gears.py).
"""

from __future__ import annotations

from pathlib import Path

import networkx as nx
from networkx.generators.atlas import graph_atlas_g

from domes.io.criteria import loads_toml
from domes.language.evaluate import holds
from domes.language.parse import parse_criterion
from domes.model import LabelledChain

ROOT = Path(__file__).resolve().parents[2]


def criterion():
    found = [c for c in loads_toml((ROOT / "knowledge/criteria/02-generic.toml").read_text()) if c.id == "gear-carrier"]
    assert len(found) == 1
    return parse_criterion(found[0].text)


def graphs(n, m):
    for g in graph_atlas_g():
        if g.number_of_nodes() == n and g.number_of_edges() == m and nx.is_connected(g) and \
                min(d for _, d in g.degree()) >= 2:
            yield g


def test_the_criterion_keeps_exactly_the_gear_pairs_with_a_carrier():
    tree = criterion()
    checked = kept = 0
    for n, m in ((5, 6), (7, 9)):
        for g in graphs(n, m):
            edges = sorted(tuple(sorted(e)) for e in g.edges)
            for gear in edges:
                chain = LabelledChain.build(n, edges, {gear: "G"})
                carrier = bool(set(g[gear[0]]) & set(g[gear[1]]))
                assert holds(tree, chain) == carrier, (edges, gear)
                checked += 1
                kept += carrier
    assert checked > 100 and 0 < kept < checked
