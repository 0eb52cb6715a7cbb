"""Why a labelled graph fails a criterion: the links, loops or count that break it, in words.

>>> from domes.model import LabelledChain
>>> from domes.language.parse import parse_criterion
>>> g = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], {(0, 1): "P"})
>>> explain(parse_criterion("THE NUMBER OF VER-TICES WHOSE “TYPE” PROPERTY HAS VALUE (P R) SHOULD NOT BE GREATER THAN 1"), g)
'the number of vertices that have type (P R) is 2 (links 0, 1), not at most 1'
>>> explain(parse_criterion("every vertex must have degree 2"), g) is None
True
"""

from __future__ import annotations

from domes.language.evaluate import Features, compile_criterion, compile_loop, compile_vertex, graph_features
from domes.language.render import comparison_text, condition_text, quoted
from domes.language.tree import ActivePairs, Count, Criterion
from domes.model.labelled import LabelledChain


def _links(mask: int, n: int) -> str:
    members = [str(v) for v in range(n) if mask >> v & 1]
    return ("link " if len(members) == 1 else "links ") + ", ".join(members)


def _loops(f: Features, test) -> list[int]:
    topo = f.topology
    return [i for i, c in enumerate(zip(topo.cycle_edges, topo.cycle_vertices, topo.cycle_lengths)) if test(f, *c)]


def _active(tree: ActivePairs, f: Features) -> str:
    """Why the pairs between the ground and the links of a role are not the active pairs asked for."""
    found = f.active_pairs(tree.role)
    if isinstance(found, str):
        return f"{found}: the {quoted(tree.role)} pairs must be active pairs"
    if not found.feasible:
        if not found.joints and not f.roles.get(tree.role):
            return f"no link represents {quoted(tree.role)}, so {found.reason}"
        return f"{found.reason} (each active pair must take exactly one DOF away, seed 002 §3-2-I.5)"
    chain = f.chain
    got = f"{found.dof_type} DOF" if found.dof_type else "no DOF type (the chain has no DOF)"
    text = f"the {quoted(tree.role)} pairs {', '.join(found.names)} give {got}, not {tree.dof_type} DOF"
    if found.dof_type == "partial":
        inputs = {v for i in found.joints for v in chain.edges[i]}
        for x in range(chain.n):
            with_x = [found.names[k] for k, links in enumerate(found.moved_by) if x in links]
            if x not in inputs and 0 < len(with_x) < len(found.joints):
                return f"{text}: link {chain.link_name(x)} moves with {', '.join(with_x)} only"
    return text


def explain(tree: Criterion, chain: LabelledChain) -> str | None:
    """None when the graph meets the criterion, else one sentence saying what breaks it."""
    f = graph_features(chain)
    if compile_criterion(tree)(f):
        return None
    if isinstance(tree, ActivePairs):
        return _active(tree, f)
    domain, topo = tree.domain, f.topology
    loop = domain.kind != "vertex"
    if isinstance(tree, Count):
        noun = {"vertex": "vertices", "independent_loop": "independent loops", "loop": "loops"}[domain.kind]
        that = f" that {condition_text(tree.condition, loop, 'are')}" if tree.condition is not None else ""
        if domain.kind == "vertex":
            mask = compile_vertex(tree.condition)(f) if tree.condition is not None else f.all
            value, where = mask.bit_count(), f" ({_links(mask, f.n)})" if mask else ""
        elif domain.kind == "loop":
            value, where = (len(_loops(f, compile_loop(tree.condition))) if tree.condition else len(topo.cycle_edges)), ""
        else:
            if tree.condition is None:
                value = topo.loops
            else:
                good = sum(1 << i for i in _loops(f, compile_loop(tree.condition)))
                value = topo.loops - topo.rank(f.all_cycles & ~good)
            where = " (the fewest any choice of independent loops has)"
        return f"the number of {noun}{that} is {value}{where}, not {comparison_text(tree.comparison)}"
    rule = "must " + condition_text(tree.condition, loop)
    if domain.kind == "vertex":
        scope = f.roles.get(domain.name, 0) if domain.name is not None else f.all
        return f"not met by {_links(scope & ~compile_vertex(tree.condition)(f), f.n)}: {rule}"
    test = compile_loop(tree.condition)
    if domain.name is not None:
        return f"not met by the {domain.name.replace('_', ' ')} loop ({_links(f.named_loops[domain.name][1], f.n)}): {rule}"
    good = _loops(f, test)
    if domain.kind == "loop":
        bad = next(i for i in range(len(topo.cycle_edges)) if i not in good)
        return f"not met by the loop through {_links(topo.cycle_vertices[bad], f.n)}: {rule}"
    rank = topo.rank(sum(1 << i for i in good))
    return f"only {rank} of the {topo.loops} independent loops can be chosen so that each meets: {rule}"
