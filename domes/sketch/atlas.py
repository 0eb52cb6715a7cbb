"""The HTML atlas page: one card per chain or candidate, with its id, properties and drawing.

The page is self-contained (inline SVG and CSS, no script) and well-formed
XML, so any browser shows it and any XML parser reads it back.

>>> from domes.typesynth import chains
>>> page = chain_atlas_html(chains(links=6, dof=1), title="Six-bar chains")
>>> page.count('class="card"'), page.startswith("<!DOCTYPE html>")
(2, True)
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Iterable, Sequence

from domes.errors import DomesError
from domes.model.chain import Chain
from domes.results import Progress, Ticker
from domes.sketch.draw import SIZE, chain_svg
from domes.sketch.layout import SkeletonLayout, skeleton_layout
from domes.sketch.mechanism import mechanism_svg
from domes.sketch.svg import document, num, tag

STYLE = """
body { font-family: sans-serif; margin: 1.5em; color: #1d3557; background: #fafafa; }
h1 { font-size: 1.4em; margin-bottom: 0.2em; }
p.summary { margin-top: 0; color: #555; }
.cards { display: flex; flex-wrap: wrap; gap: 12px; }
.card { background: #fff; border: 1px solid #ccd; border-radius: 6px; padding: 8px; width: min-content; }
.card.marked { border: 2px solid #c1121f; }
.card h2 { font-size: 1em; margin: 0 0 4px 0; }
.card .badge { background: #c1121f; color: #fff; border-radius: 3px; padding: 0 4px; font-size: 0.8em; margin-left: 6px; }
.card dl { display: grid; grid-template-columns: auto 1fr; gap: 0 8px; font-size: 0.8em; margin: 4px 0 0 0; }
.card dt { color: #777; }
.card dd { margin: 0; font-family: monospace; overflow-wrap: anywhere; }
"""


@dataclass(frozen=True)
class Card:
    """One atlas entry: an id, a title, ``(name, value)`` properties, a drawing (SVG) and an optional badge.

    A marked card (``badge`` set, e.g. ``"existing design"``) is framed in red.
    """

    id: str
    title: str
    svg: str
    properties: tuple[tuple[str, str], ...] = ()
    badge: str | None = None

    def html(self) -> str:
        heading = [tag("span", text=self.title)]
        if self.badge:
            heading.append(tag("span", {"class": "badge"}, text=self.badge))
        rows = []
        for name, value in self.properties:
            rows += [tag("dt", text=name), tag("dd", text=value)]
        children = [tag("h2", children=heading), tag("div", {"class": "drawing"}, children=["\n" + self.svg + "\n"])]
        if rows:
            children.append(tag("dl", children=rows))
        return tag("div", {"class": "card marked" if self.badge else "card", "id": f"card-{self.id}", "data-id": self.id}, children)


def atlas_html(cards: Iterable[Card], title: str, summary: str = "") -> str:
    """A standalone HTML page of cards.

    >>> page = atlas_html([Card("1", "four-bar", "<svg/>", (("links", "4"),))], "One chain")
    >>> '<dt>links</dt><dd>4</dd>' in page
    True
    """
    cards = list(cards)
    body = [tag("h1", text=title)]
    body.append(tag("p", {"class": "summary"}, text=summary or (f"{len(cards)} entries" if len(cards) != 1 else "1 entry")))
    body.append(tag("div", {"class": "cards"}, ["\n" + card.html() for card in cards] + ["\n"]))
    head = [tag("meta", {"charset": "utf-8"}), tag("title", text=title), tag("style", text=STYLE)]
    page = tag("html", {"xmlns": "http://www.w3.org/1999/xhtml", "lang": "en"}, [tag("head", children=head), "\n", tag("body", children=body), "\n"])
    return "<!DOCTYPE html>\n" + page + "\n"


def not_drawn_svg(reason: str, size: float = SIZE) -> str:
    """A placeholder drawing that says why there is no drawing."""
    text = tag("text", {"class": "not-drawn", "x": num(size / 2), "y": num(size / 2), "font-size": "11", "text-anchor": "middle", "font-family": "sans-serif", "fill": "#c1121f"}, text="not drawn")
    return document(size, size, [text], title=reason)


def chain_card(index: int | str, chain, *, layout: SkeletonLayout | None = None, graph: bool = False, size: float = SIZE) -> Card:
    """The card of one chain of the atlas: drawing and structural properties.

    Without a ``layout`` one is made; should that fail (a non-planar chain
    with no planar part found), the card gets a placeholder and the reason.
    """
    assortment = " ".join(f"n{d}={k}" for d, k in chain.assortment.items())
    try:
        layout = layout or skeleton_layout(chain)
    except DomesError as exc:
        layout, svg, planarity = None, not_drawn_svg(str(exc), size), f"not drawn: {exc}"
    else:
        svg = chain_svg(chain, layout, graph=graph, size=size)
        planarity = "planar" if layout.planar else f"non-planar (links {', '.join(map(str, layout.crossing_links))} cross)"
    properties = (
        ("links / joints", f"{chain.links} / {chain.joints}"),
        ("loops, DOF", f"{chain.loops}, {chain.dof}"),
        ("assortment", assortment),
        ("DOF type", chain.dof_type),
        ("|Aut|", str(chain.automorphisms.order)),
        ("drawing", planarity),
        ("graph6", chain.graph6),
    )
    return Card(str(index), f"No. {index}", svg, properties)


def mechanism_card(
    index: int | str,
    labelled,
    *,
    title: str | None = None,
    properties: Sequence[tuple[str, str]] = (),
    badge: str | None = None,
    positions=None,
    size: float = SIZE,
) -> Card:
    """The card of one labelled candidate: its sketch, roles, joint types and any further properties.

    ``badge`` marks the card (e.g. ``"existing design"``); ``positions`` as in
    :func:`~domes.sketch.mechanism.mechanism_svg`.

    >>> from domes.model import LabelledChain
    >>> four_bar = LabelledChain.build(4, [(0, 1), (1, 2), (2, 3), (0, 3)], roles={0: {"ground"}})
    >>> mechanism_card(1, four_bar, badge="existing design").properties[0]
    ('roles', '0: ground')
    """
    roles = "; ".join(f"{v}: {', '.join(sorted(r))}" for v, r in enumerate(labelled.roles) if r)
    types = " ".join(f"{u}-{v}={t}" for (u, v), t in zip(labelled.edges, labelled.joint_types) if t != "R")
    rows = (("roles", roles or "none"), ("joint types", types or "all R"), *properties)
    svg = mechanism_svg(labelled, positions, size=size, title=title)
    return Card(str(index), title or f"No. {index}", svg, tuple(rows), badge)


def chain_atlas_html(chains: Sequence, title: str | None = None, *, graph: bool = False,
                     progress: Progress | None = None) -> str:
    """The atlas page of a list of chains, numbered from 1 in the given order (about 16 ms and 6 kB a chain)."""
    chains = list(chains)
    if title is None:
        first = chains[0] if chains else None
        title = f"{len(chains)} chains" + (f": {first.links} links, DOF {first.dof}" if first else "")
    clock = Ticker(progress)
    cards = []
    for i, c in enumerate(chains, 1):
        clock.tick(lambda: f"drawing chain {i}/{len(chains)}")
        cards.append(chain_card(i, c, graph=graph))
    return atlas_html(cards, title, f"{len(cards)} chains, each drawn as a mechanism skeleton (plates and bars, joints as circles).")


def candidate_card(candidate) -> Card:
    """The card of one regenerated candidate (``domes.typesynth.Candidate``): its sketch and where it came from.

    A candidate equal to an existing design gets the badge ``existing design``
    (a red frame) and the design's name among its properties. Should the
    sketch fail, the card gets a placeholder and the reason.
    """
    m = candidate.labelled
    name = Chain(m.n, m.edges).common_name
    properties = (
        ("chain", f"No. {candidate.chain_index}" + (f" ({name})" if name else "")),
        ("existing", "; ".join(candidate.existing) if candidate.existing else "no (new)"),
        ("joints", " ".join(f"{u}-{v}" for u, v in m.edges)),
    )
    badge = "existing design" if candidate.existing else None
    title = f"Candidate {candidate.id}"
    try:
        return mechanism_card(candidate.id, m, title=title, properties=properties, badge=badge)
    except DomesError as exc:  # the page is still written; the card says why there is no drawing
        return Card(str(candidate.id), title, not_drawn_svg(str(exc)), (*properties, ("drawing", f"not drawn: {exc}")), badge)


def regeneration_html(result, *, new_only: bool = False) -> str:
    """The atlas page of a regeneration (``domes.typesynth.Regeneration``): one card per candidate.

    >>> from domes.io.scenes import load_scene

    >>> from domes.typesynth import regenerate
    >>> page = regeneration_html(regenerate(load_scene("motorcycle")))
    >>> page.count('data-id="'), page.count('class="card marked"')
    (6, 1)
    """
    scene = result.scene
    shown = [c for c in result.candidates if not (new_only and c.existing)]
    existing = sum(1 for c in result.candidates if c.existing)
    stages = ", ".join(f"{s.name} {s.count}" for s in result.stages)
    summary = (
        f"{len(result.candidates)} candidates ({existing} existing, {len(result.candidates) - existing} new) "
        f"on the {scene.links}-link chains of DOF {scene.dof}; stages: {stages}."
        + (f" Source: {scene.source}." if scene.source else "")
        + (" Existing designs left out." if new_only else "")
    )
    return atlas_html([candidate_card(c) for c in shown], f"{scene.title} [{scene.name}]", summary)
