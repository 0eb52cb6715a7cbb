"""Reference methods independent of the generator: brute force and networkx VF2."""

from __future__ import annotations

import shutil
import subprocess
from itertools import combinations

import networkx as nx


def brute_force_degenerate(n, edges):
    """True if some proper subset S, |S| >= 3, has 3(|S|-1) - 2e(S) <= 0 (plain Python, every subset)."""
    edge_list = list(edges)
    for size in range(3, n):
        for subset in combinations(range(n), size):
            s = set(subset)
            inside = sum(1 for u, v in edge_list if u in s and v in s)
            if 3 * (size - 1) - 2 * inside <= 0:
                return True
    return False


def pairwise_isomorphic(graphs):
    """Pairs (i, j) of isomorphic graphs, by WL-hash buckets then VF2."""
    buckets: dict[str, list[int]] = {}
    for i, g in enumerate(graphs):
        buckets.setdefault(nx.weisfeiler_lehman_graph_hash(g, iterations=4), []).append(i)
    pairs = []
    for members in buckets.values():
        for i, j in combinations(members, 2):
            if nx.is_isomorphic(graphs[i], graphs[j]):
                pairs.append((i, j))
    return pairs


def match_into(graphs, targets):
    """For each graph, the index of an isomorphic target (VF2), or None."""
    buckets: dict[str, list[int]] = {}
    for i, g in enumerate(targets):
        buckets.setdefault(nx.weisfeiler_lehman_graph_hash(g, iterations=4), []).append(i)
    out = []
    for g in graphs:
        key = nx.weisfeiler_lehman_graph_hash(g, iterations=4)
        out.append(next((i for i in buckets.get(key, []) if nx.is_isomorphic(g, targets[i])), None))
    return out


GENG = shutil.which("nauty-geng") or shutil.which("geng")


def geng_chains(n, joints, include_fractionated):
    """All chains by nauty's geng (connected, min degree 2) filtered by brute force."""
    out = subprocess.run([GENG, "-cq", "-d2", str(n), f"{joints}:{joints}"], capture_output=True, text=True, check=True)
    result = []
    for line in out.stdout.split():
        g = nx.from_graph6_bytes(line.encode())
        if brute_force_degenerate(n, g.edges):
            continue
        if not include_fractionated and list(nx.articulation_points(g)):
            continue
        result.append(g)
    return result


def chain_atlas_file(tmp_path_factory, links: int, dof: int):
    """The atlas ``chains(links, dof)`` as graph6, one chain a line, built once in a test run for every test (and
    every ``pytest -n`` worker) that reads it (tests/shared.py)."""
    from domes.typesynth.atlas import chains
    from tests.shared import shared_file

    def write(path):
        path.write_text("".join(c.graph6 + "\n" for c in chains(links, dof)))

    return shared_file(tmp_path_factory, f"chains-n{links}-F{dof}.g6", write)


def chain_atlas(tmp_path_factory, links: int, dof: int) -> list[str]:
    """The graph6 lines of :func:`chain_atlas_file`."""
    return chain_atlas_file(tmp_path_factory, links, dof).read_text().split()
