"""Values shown as drawings in a notebook: the renderers behind their ``_repr_svg_`` and ``_repr_html_``.

The values live below this layer and may not import it; their repr methods
ask :func:`domes.model.display.render`, which imports this module by name the
first time a value is shown (the one plug-in point), and this module
registers a renderer for each kind of value, made of the drawings of
:mod:`domes.sketch`:

================================  ======  =================================================================
value                             shown   drawing
================================  ======  =================================================================
``Chain``                         SVG     the skeleton (:func:`~domes.sketch.draw.chain_svg`)
``LabelledChain``                 SVG     the sketch (:func:`~domes.sketch.mechanism.mechanism_svg`)
``Mechanism``                     SVG     to scale at its drawn pose, with its coupler points' curves
                                          (:func:`~domes.sketch.dimensioned.dimensioned_svg`)
``SpatialMechanism``              SVG     axonometric, at its drawn pose (:func:`~domes.sketch.spatial.spatial_svg`)
``Sweep``, ``SpatialSweep``       HTML    a card per output column, plotted over the input
``Atlas`` (chains)                HTML    a card per chain, the first :data:`CHAINS_SHOWN`
``AtlasTable``, ``WindowTable``,  HTML    :data:`CURVES_SHOWN` rows spread over the atlas, each linkage moving
``Atlas``, ``OpenAtlas`` (curves)         along its curve (:func:`~domes.sketch.curves.moving_svg`)
``Synthesis``, ``Dimensioning``   HTML    the cards of ``domes synthesize --format html``
``SpatialSynthesis``              HTML    a card per spatial mechanism found
================================  ======  =================================================================

HTML is a fragment, not a page: the cards of :func:`~domes.sketch.atlas.atlas_html`
inside a ``div`` of class :data:`ROOT`, the page's style scoped to it, so
the notebook keeps its own look.

>>> from domes.model import Chain
>>> svg = Chain.from_graph6("Cr")._repr_svg_()
>>> svg.startswith("<svg"), svg.count('class="joint"')
(True, 4)
"""

from __future__ import annotations

import html
import re

import numpy as np

from domes.design.synthesis.candidate import Dimensioning
from domes.design.synthesis.solve import Synthesis
from domes.design.synthesis.spatialresult import SpatialSynthesis
from domes.errors import DomesError
from domes.model.chain import Chain
from domes.model.display import register
from domes.model.labelled import LabelledChain
from domes.model.mechanism import Mechanism
from domes.model.spatial import SpatialMechanism
from domes.motion.coupler import atlas as curves_atlas
from domes.motion.coupler.curves import trace
from domes.motion.coupler.designspace import classify
from domes.motion.planar.sweep import Sweep
from domes.motion.spatial.loops import Loops
from domes.motion.spatial.sweep import SpatialSweep
from domes.sketch.atlas import Card, atlas_html, chain_card
from domes.sketch.curves import joint_names, moving_svg
from domes.sketch.dimensioned import dimensioned_svg
from domes.sketch.draw import chain_svg
from domes.sketch.mechanism import mechanism_svg
from domes.sketch.spatial import spatial_svg
from domes.sketch.synthesis import MARK, curve_svg, synthesis_html
from domes.typesynth.atlas import Atlas as ChainAtlas

#: The class of the ``div`` an HTML drawing comes in; the page's style applies inside it only.
ROOT = "domes-notebook"
#: Chains of an atlas drawn (the rest are counted): a card costs about 16 ms.
CHAINS_SHOWN = 24
#: Rows of a coupler-curve atlas drawn, spread evenly over it: each is traced again.
CURVES_SHOWN = 12
#: Samples per input turn of a coupler curve traced for a card.
CURVE_SAMPLES = 180
#: Points a sweep's column is plotted by at most (evenly spaced steps, the first and last among them).
PLOTTED = 1000
#: Colours of successive sweep columns.
COLOURS = ("#1d3557", "#c1121f", "#2a9d8f", "#e76f51", "#6a4c93")


def scoped(css: str) -> str:
    """A page's style made to apply inside ``div.domes-notebook`` only (``body`` becomes the ``div``).

    >>> scoped("body { margin: 0; }\\n.card h2, p { color: red; }")
    '.domes-notebook { margin: 0; }\\n.domes-notebook .card h2, .domes-notebook p { color: red; }'
    """
    def rule(match: re.Match) -> str:
        selectors = [s.strip() for s in match.group(2).split(",")]
        inside = [f".{ROOT}{s[4:]}" if re.match(r"body\b", s) else f".{ROOT} {s}" for s in selectors]
        return match.group(1) + ", ".join(inside) + " {" + match.group(3) + "}"

    return re.sub(r"(\s*)([^{}]+?)\s*\{([^{}]*)\}", rule, css.strip())


def fragment(page: str) -> str:
    """The body of an atlas page (:func:`~domes.sketch.atlas.atlas_html`) in a ``div``, with its style scoped.

    >>> text = fragment(atlas_html([Card("1", "four-bar", "<svg/>")], "One chain"))
    >>> text.startswith('<div class="domes-notebook"><style>'), "<body" in text, 'class="card"' in text
    (True, False, True)
    """
    style = re.search(r"<style>(.*?)</style>", page, re.S)
    body = re.search(r"<body>(.*)</body>", page, re.S)
    css = html.escape(scoped(html.unescape(style.group(1))), quote=False) if style else ""
    return f'<div class="{ROOT}"><style>{css}</style>{body.group(1)}</div>'


def cards_html(cards, title: str, summary: str) -> str:
    """Cards as a notebook's HTML fragment."""
    return fragment(atlas_html(cards, title, summary))


def chain_drawing(chain: Chain) -> str:
    return chain_svg(chain, title=f"chain {chain.graph6}: {chain.links} links, {chain.joints} joints, DOF {chain.dof}")


def labelled_drawing(labelled: LabelledChain) -> str:
    return mechanism_svg(labelled, title=labelled.name or None)


def mechanism_drawing(mech: Mechanism) -> str:
    """At its drawn pose, with the curves of its coupler points (without, should tracing them fail)."""
    try:
        return dimensioned_svg(mech, coupler=[p.name for p in mech.points])
    except DomesError:
        if not mech.points:
            raise
        return dimensioned_svg(mech)


def spatial_drawing(mech: SpatialMechanism) -> str:
    kin = Loops(mech)
    return spatial_svg(mech, kin.places(kin.drawn()), title=mech.name)


def sweep_html(sw: Sweep | SpatialSweep) -> str:
    """A card per output column over the input (at most :data:`PLOTTED` of its steps); angles in degrees (their
    rates as they are); each card gives the column's range over every step."""
    steps = np.unique(np.linspace(0, sw.inputs.size - 1, min(PLOTTED, sw.inputs.size)).round().astype(int))
    x = np.degrees(sw.inputs) if sw.angular else np.asarray(sw.inputs, dtype=float)
    xlabel = f"input {sw.joint}" + (" (°)" if sw.angular else "")
    cards = []
    for k, (name, values) in enumerate(sw.table.items(), 1):
        angle = name.startswith("angle:") and not name.endswith("'")
        y = np.degrees(values) if angle else np.asarray(values, dtype=float)
        colour = COLOURS[(k - 1) % len(COLOURS)]
        finite = y[np.isfinite(y)]
        span = f"{finite.min():.6g} to {finite.max():.6g}" if finite.size else "no finite value"
        plot = curve_svg(x[steps], [(name, y[steps], colour, False)], xlabel, name + (" (°)" if angle else ""))
        cards.append(Card(str(k), name, plot, (("range", span), ("steps", f"{y.size}, {steps.size} plotted"))))
    name = getattr(sw, "mechanism", "")
    return cards_html(cards, f"Sweep of {sw.joint}" + (f": {name}" if name else ""), sw.message)


def chain_atlas_html(atlas: ChainAtlas) -> str:
    shown = atlas.chains[:CHAINS_SHOWN]
    more = f"; the first {len(shown)} drawn" if len(shown) < len(atlas.chains) else ""
    title = f"Chains of {atlas.links} links, DOF {atlas.dof}"
    return cards_html([chain_card(i, c) for i, c in enumerate(shown, 1)], title, atlas.message + more)


def curve_atlas_html(value) -> str:
    """A card for :data:`CURVES_SHOWN` rows spread over a coupler-curve atlas (a table, or one with its tree)."""
    table = getattr(value, "table", value)
    rows = sorted({int(i) for i in np.linspace(0, table.count - 1, min(CURVES_SHOWN, table.count))})
    cards = []
    for i in rows:
        mech = table.entry(i)
        curve = trace(mech, "P", CURVE_SAMPLES, extra=joint_names(mech))
        k = int(table.circuit[i])
        if k >= len(curve.circuits):
            continue
        a, b, c, d = table.lengths(i)
        u, v = (float(t) for t in table.point[i])
        props = [("a, b, c, d", f"{a:.4f}, {b:.4f}, {c:.4f}, {d:.4f}"), ("region", str(classify(a, b, c, d).region)),
                 ("coupler point (u, v)", f"({u:g}, {v:g})"), ("circuit", str(k + 1))]
        if hasattr(table, "fraction"):
            props.append(("window", f"from {float(table.start[i]):.3g} of the curve, {float(table.fraction[i]):.3g} "
                                    "of its length"))
        cards.append(Card(str(i), f"row {i}", moving_svg(mech, curve.circuits[k]), tuple(props)))
    meta = table.meta
    what = "windows of curves" if hasattr(table, "fraction") else "curves"
    summary = (f"{meta.get('name', 'an atlas')}: {table.count:,} {what} of {len(table.linkages):,} four-bars; "
               f"rows {', '.join(map(str, rows))} drawn")
    return cards_html(cards, f"Coupler-curve atlas {meta.get('name', '')}".strip(), summary)


def synthesis_result_html(result: Synthesis) -> str:
    """The cards of ``domes synthesize --format html`` (without the task, so without its marks)."""
    return fragment(synthesis_html(result, None))


def dimensioning_html(result: Dimensioning) -> str:
    """Each layout drawn to scale beside the curve it gives and the wanted one."""
    cards = []
    for k, s in enumerate(result.solutions, 1):
        svg = dimensioned_svg(s.mechanism) + "\n" + curve_svg(
            s.x, [("achieved", s.achieved, "#c1121f", False), ("wanted", s.wanted, MARK, True)], "input", "curve")
        props = (("candidate", str(s.candidate)), ("curve error", f"{100 * s.error:.3g}% largest, {100 * s.rms:.3g}% RMS"),
                 ("transmission", f"{s.min_transmission_deg:.1f}° smallest"), *(("defect", x) for x in s.defects))
        cards.append(Card(str(k), f"candidate {s.candidate}", svg, props, None if s.usable else "rejected"))
    summary = result.message + "".join(f"; {n}" for n in result.notes)
    return cards_html(cards, f"Dimensional synthesis: {result.task_name}", summary)


def spatial_synthesis_html(result: SpatialSynthesis) -> str:
    cards = [Card(str(k), m.name, spatial_drawing(m), (("joints", " ".join(f"{j.name} {j.kind}" for j in m.joints)),))
             for k, m in enumerate(result.mechanisms, 1)]
    return cards_html(cards, f"Spatial synthesis: {result.name} ({result.kind})", "; ".join(result.lines) or result.message)


register(Chain, "svg", chain_drawing)
register(LabelledChain, "svg", labelled_drawing)
register(Mechanism, "svg", mechanism_drawing)
register(SpatialMechanism, "svg", spatial_drawing)
register(Sweep, "html", sweep_html)
register(SpatialSweep, "html", sweep_html)
register(ChainAtlas, "html", chain_atlas_html)
for _cls in (curves_atlas.AtlasTable, curves_atlas.WindowTable, curves_atlas.Atlas, curves_atlas.OpenAtlas):
    register(_cls, "html", curve_atlas_html)
register(Synthesis, "html", synthesis_result_html)
register(Dimensioning, "html", dimensioning_html)
register(SpatialSynthesis, "html", spatial_synthesis_html)

__all__ = ["CHAINS_SHOWN", "CURVES_SHOWN", "ROOT", "cards_html", "fragment", "scoped"]
