"""The page of ``domes tolerance --format html``: the output's spread over the input, and who causes it.

A card per output column plots, over the input, the worst case and the 3σ
of first order and of Monte Carlo; a card ranks the dimensions by their
share of the variance (bars); with ``--scan``, a card shows the Monte Carlo
over first-order ratio as the tolerances grow. It reads the document the
command writes as JSON, so the page shows exactly what the JSON says.

>>> doc = {"mechanism": "m", "output": "angle:r", "unit": "deg", "input_unit": "deg", "distribution": "normal",
...        "dimensions": [{"name": "a", "share": 0.75, "tolerance": 0.1}, {"name": "b", "share": 0.25, "tolerance": 0.1}],
...        "inputs": [{"column": "angle:r", "input": x, "worst_case": 2.0, "three_sigma_first_order": 1.0}
...                   for x in (0.0, 90.0)], "first_order": "..."}
>>> page = tolerance_html(doc)
>>> page.count('class="card"'), page.count('class="share"')
(2, 2)
"""

from __future__ import annotations

import math

from domes.sketch.atlas import Card, atlas_html
from domes.sketch.svg import document, num, tag
from domes.sketch.synthesis import INK, MARK, SIZE, curve_svg

FIRST = "#1d3557"
MONTE = "#c1121f"


def shares_svg(dimensions: list[dict], width: float = SIZE) -> str:
    """Horizontal bars: each dimension's share of the output's variance, largest first."""
    row = 18.0
    height = 16.0 + row * len(dimensions)
    label = 130.0
    items = []
    for k, d in enumerate(dimensions):
        y = 8.0 + row * k
        length = max(0.0, float(d["share"])) * (width - label - 56)
        items += [
            tag("text", {"x": num(label - 6), "y": num(y + 12), "font-size": "11", "text-anchor": "end", "fill": INK},
                text=d["name"]),
            tag("rect", {"class": "share", "x": num(label), "y": num(y + 2), "width": num(length), "height": "12",
                         "fill": MARK, "data-name": d["name"]}),
            tag("text", {"x": num(label + length + 4), "y": num(y + 12), "font-size": "11", "fill": INK},
                text=f"{100 * float(d['share']):.1f}%"),
        ]
    return document(width, height, items, title="share of the output variance by dimension")


def tolerance_html(doc: dict) -> str:
    """The page for the document of ``domes tolerance --format json``."""
    rows = doc["inputs"]
    cards = []
    for column in dict.fromkeys(r["column"] for r in rows):
        mine = [r for r in rows if r["column"] == column]
        x = [r["input"] for r in mine]
        series = [("worst case", [r["worst_case"] for r in mine], INK, True),
                  ("3σ first order", [r["three_sigma_first_order"] for r in mine], FIRST, False)]
        if "three_sigma_monte_carlo" in mine[0]:
            series.append(("3σ Monte Carlo", [r["three_sigma_monte_carlo"] for r in mine], MONTE, False))
        svg = curve_svg(x, series, f"input ({doc['input_unit']})", f"error of {column} ({doc['unit']})")
        props = [("largest 3σ", f"{max(r['three_sigma_first_order'] for r in mine):.4g} (first order)")]
        if "three_sigma_monte_carlo" in mine[0]:
            props.append(("", f"{max(r['three_sigma_monte_carlo'] for r in mine):.4g} (Monte Carlo)"))
        cards.append(Card(column, f"error of {column}", svg, tuple(props)))
    top = doc["dimensions"][0]
    cards.append(Card("shares", "who causes it", shares_svg(doc["dimensions"]),
                      (("largest share", f"{top['name']} ± {top['tolerance']:.3g}"),)))
    if "scan" in doc:
        scan = doc["scan"]
        svg = curve_svg([math.log10(s["scale"]) for s in scan],
                        [("Monte Carlo σ / first-order σ", [s["ratio"] for s in scan], MONTE, False)],
                        "log10 of the tolerances' scale", "ratio")
        parted = [s["scale"] for s in scan if not s["agree"]]
        cards.append(Card("scan", "where the estimates part", svg,
                          (("part from", f"× {parted[0]:g}" if parted else "never in the scan"),)))
    summary = doc["first_order"]
    if "monte_carlo" in doc:
        summary += "; " + doc["monte_carlo"]["message"]
    return atlas_html(cards, f"Tolerances: {doc['mechanism']}, {doc['output']}", summary)


__all__ = ["shares_svg", "tolerance_html"]
