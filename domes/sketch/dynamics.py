"""The page of ``domes dynamics --format html``: force curves over the motion and the power balance.

It reads the document the command writes as JSON. A mechanism gets a card
of driving forces or torques over the input, one of the joint reactions'
sizes, and one of the powers (input, loads, dE/dt) with the balance; the
scriber gets its contour (junctions marked), its two actuator forces over
the arc length (the jumps at the junctions visible), and its powers.

>>> doc = {"kind": "mechanism", "name": "m", "message": "ok", "x": "input A (deg)", "drives": {"A": {"kind": "torque",
...        "peak": 2.0, "at": 90.0}}, "max_imbalance": 1e-16, "peak_power": 3.0, "reaction_sizes": {"A": [1.0, 2.0]},
...        "columns": {"input (deg)": [0.0, 90.0], "drive:A": [1.0, 2.0], "input power": [1.0, 2.0],
...                    "load power": [0.0, 0.0], "dE/dt": [1.0, 2.0], "balance/peak": [0.0, 0.0]}}
>>> dynamics_html(doc).count('class="card"')
3
"""

from __future__ import annotations

from domes.sketch.atlas import Card, atlas_html
from domes.sketch.svg import document, num, points, tag
from domes.sketch.synthesis import INK, MARK, SIZE, curve_svg

PALETTE = ("#1d3557", "#c1121f", "#2a9d8f", "#e9c46a", "#6d597a", "#f4a261")


def _series(named: dict) -> list:
    return [(name, values, PALETTE[k % len(PALETTE)], False) for k, (name, values) in enumerate(named.items())]


def _power_card(doc: dict, x, xlabel: str) -> Card:
    cols = doc["columns"]
    named = {"input power": cols["input power"], "dE/dt": cols["dE/dt"]}
    if "load power" in cols:
        named["load power"] = cols["load power"]
    svg = curve_svg(x, _series(named), xlabel, "power")
    return Card("power", "power balance", svg, (("peak power", f"{doc['peak_power']:.4g}"),
                                                ("largest imbalance", f"{doc['max_imbalance']:.2g} of the peak")))


def contour_svg(doc: dict, size: float = SIZE) -> str:
    """The scriber's contour (the sampled points), its block pivots and its junctions."""
    cols = doc["columns"]
    xs, ys = cols["x"], cols["y"]
    s = doc["scriber"]
    px = list(xs) + [s["sa"], s["sb"]]
    py = list(ys) + [0.0, s["H"]]
    lo_x, hi_x, lo_y, hi_y = min(px), max(px), min(py), max(py)
    span = max(hi_x - lo_x, hi_y - lo_y) or 1.0
    pad = 24.0
    k = (size - 2 * pad) / span
    sx = lambda v: pad + (v - lo_x) * k  # noqa: E731
    sy = lambda v: size - pad - (v - lo_y) * k  # noqa: E731
    items = [tag("polyline", {"class": "contour", "fill": "none", "stroke": INK, "stroke-width": "1.6",
                              "points": points((sx(a), sy(b)) for a, b in zip(xs, ys))})]
    for name, (x, y) in (("A", (s["sa"], 0.0)), ("B", (s["sb"], s["H"]))):
        items += [tag("circle", {"class": "pivot", "cx": num(sx(x)), "cy": num(sy(y)), "r": "4", "fill": "white",
                                 "stroke": INK}),
                  tag("text", {"x": num(sx(x) + 6), "y": num(sy(y) - 6), "font-size": "11", "fill": INK}, text=name)]
    seg = doc["contour"]
    here = seg["start"]
    for item in seg["segments"]:
        end = item["line"] if "line" in item else item["arc"]["to"]
        items.append(tag("circle", {"class": "junction", "cx": num(sx(here[0])), "cy": num(sy(here[1])), "r": "3",
                                    "fill": MARK}))
        here = end
    return document(size, size, items, title="contour, block pivots and junctions")


def dynamics_html(doc: dict) -> str:
    """The page for the document of ``domes dynamics --format json``."""
    cols = doc["columns"]
    cards = []
    if doc["kind"] == "mechanism":
        xname = next(n for n in cols if n.startswith("input"))
        x = cols[xname]
        drives = {f"{j} ({d['kind']})": cols[f"drive:{j}"] for j, d in doc["drives"].items()}
        props = tuple((f"peak at {j}", f"{d['peak']:.4g} at {d['at']:.4g}") for j, d in doc["drives"].items())
        cards.append(Card("driving", "driving forces and torques", curve_svg(x, _series(drives), doc["x"], "drive"),
                          props))
        sizes = doc["reaction_sizes"]
        worst = max(sizes, key=lambda j: max(abs(v) for v in sizes[j]))
        cards.append(Card("reactions", "joint reactions (size)",
                          curve_svg(x, _series({f"|F| at {j}": v for j, v in sizes.items()}), doc["x"], "force"),
                          (("largest", f"{max(sizes[worst]):.4g} at {worst}"),)))
        cards.append(_power_card(doc, x, doc["x"]))
    else:
        x = cols["s"]
        cards.append(Card("contour", "contour", contour_svg(doc),
                          (("segments", str(len(doc["contour"]["segments"]))), ("speed", f"{doc['speed']:g}"))))
        props = tuple((f"{k}s", f"Q in [{lo:.4g}, {hi:.4g}]") for k, (lo, hi) in doc["spreads"].items())
        cards.append(Card("forces", "actuator forces Q1, Q2",
                          curve_svg(x, _series({"Q1": cols["Q1"], "Q2": cols["Q2"]}), "arc length s", "force"), props))
        cards.append(Card("strokes", "link lengths q1, q2",
                          curve_svg(x, _series({"q1": cols["q1"], "q2": cols["q2"]}), "arc length s", "length")))
        cards.append(_power_card(doc, x, "arc length s"))
    return atlas_html(cards, f"Dynamics: {doc['name']}", doc["message"])


__all__ = ["contour_svg", "dynamics_html"]
