"""Drawings of spatial mechanisms: an axonometric SVG, and a page where the mechanism turns and moves.

The view turns the world about its z axis by the ``azimuth`` and tilts it
by the ``elevation`` (degrees); the screen shows the turned x (right) and z
(up). Links are drawn as bars between their joints (the ground's joints get
their axes as dash-dotted lines), joints by type: S a ball, R a ring with a
short axis, C a ring with a long axis, P a square, H a ring with a cross.
The page (:func:`spatial_html`) carries the joints' positions at every step
of a sweep and draws them in the browser: drag (or the sliders) to turn,
play to move; ``window.domesView`` exposes ``turn(azimuth, elevation)``,
``frame(k)``, ``play()``, ``pause()`` and ``state()``.

>>> from domes.motion.spatial.examples import rssr
>>> svg = spatial_svg(rssr(), {j.name: j.at for j in rssr().joints})
>>> svg.count('class="joint'), 'class="axis ground"' in svg
(4, True)
"""

from __future__ import annotations

import json
import math

import numpy as np

from domes.model.spatial import SpatialMechanism
from domes.sketch.svg import document, num, points, tag

INK = "#1d3557"
GROUND = "#6c757d"
TRACE = "#c1121f"
VIEW = (-35.0, 25.0)


def project(xyz, azimuth: float, elevation: float) -> np.ndarray:
    """Screen coordinates ``(right, up)`` of world points ``(N, 3)`` in the view (degrees)."""
    p = np.atleast_2d(np.asarray(xyz, dtype=float))
    a, e = math.radians(azimuth), math.radians(elevation)
    x = p[:, 0] * math.cos(a) - p[:, 1] * math.sin(a)
    y = p[:, 0] * math.sin(a) + p[:, 1] * math.cos(a)
    return np.column_stack([x, p[:, 2] * math.cos(e) - y * math.sin(e)])


def _links(mech: SpatialMechanism) -> list[tuple[str, list[str]]]:
    return [(link, [j.name for j in mech.joints_of(link)]) for link in mech.links]


def spatial_svg(mech: SpatialMechanism, positions: dict, traces: dict | None = None, size: float = 400.0,
                view: tuple[float, float] = VIEW, title: str | None = None) -> str:
    """The mechanism with its joints at ``positions`` (name -> (x, y, z)), ``traces`` (name -> (N, 3) curves)."""
    az, el = view
    names = list(positions)
    world = np.array([positions[n] for n in names], dtype=float)
    extra = [np.asarray(t, dtype=float).reshape(-1, 3) for t in (traces or {}).values()]
    reach = 0.12 * float(mech.size)
    for j in mech.joints:                  # the ground's axes are drawn too: keep them in the picture
        if mech.ground in j.links and j.axis is not None and j.name in positions:
            c = np.asarray(positions[j.name], dtype=float)
            extra.append(np.array([c - 2 * reach * np.asarray(j.axis), c + 2 * reach * np.asarray(j.axis)]))
    every = np.vstack([world] + extra)
    flat = project(every, az, el)
    lo, hi = flat.min(axis=0), flat.max(axis=0)
    span = float(max(hi - lo)) or 1.0
    pad = 30.0
    k = (size - 2 * pad) / span

    def screen(xyz):
        s = project(xyz, az, el)
        return np.column_stack([pad + (s[:, 0] - lo[0]) * k + (size - 2 * pad - (hi[0] - lo[0]) * k) / 2,
                                size - pad - (s[:, 1] - lo[1]) * k - (size - 2 * pad - (hi[1] - lo[1]) * k) / 2])

    at = dict(zip(names, screen(world)))
    items = []
    for j in mech.joints:
        if mech.ground in j.links and j.axis is not None and j.name in positions:
            c = np.asarray(positions[j.name], dtype=float)
            ends = screen(np.array([c - 2 * reach * np.asarray(j.axis), c + 2 * reach * np.asarray(j.axis)]))
            items.append(tag("polyline", {"class": "axis ground", "points": points(ends), "stroke": GROUND,
                                          "stroke-dasharray": "8 3 2 3", "fill": "none"}))
    for link, joints in _links(mech):
        shown = [at[n] for n in joints if n in at]
        if len(shown) < 2:
            continue
        ground = link == mech.ground
        for a in range(len(shown)):
            for b in range(a + 1, len(shown)):
                if ground:
                    continue
                items.append(tag("line", {"class": f"bar link-{link}", "x1": num(shown[a][0]), "y1": num(shown[a][1]),
                                          "x2": num(shown[b][0]), "y2": num(shown[b][1]), "stroke": INK,
                                          "stroke-width": "3", "stroke-linecap": "round"}))
    for name, curve in (traces or {}).items():
        items.append(tag("polyline", {"class": "trace", "points": points(screen(np.asarray(curve).reshape(-1, 3))),
                                      "stroke": TRACE, "fill": "none", "stroke-width": "1.4"}))
    for j in mech.joints:
        if j.name not in at:
            continue
        x, y = at[j.name]
        cls = f"joint {j.kind}"
        if j.axis is not None and j.kind in ("R", "C", "H"):
            c = np.asarray(positions[j.name], dtype=float)
            half = (0.06 if j.kind == "R" else 0.14) * float(mech.size)
            ends = screen(np.array([c - half * np.asarray(j.axis), c + half * np.asarray(j.axis)]))
            items.append(tag("polyline", {"class": "axis", "points": points(ends), "stroke": INK, "stroke-width": "4",
                                          "fill": "none"}))
        if j.kind == "S":
            items.append(tag("circle", {"class": cls, "cx": num(x), "cy": num(y), "r": "6", "fill": INK}))
        elif j.kind == "P":
            items.append(tag("rect", {"class": cls, "x": num(x - 6), "y": num(y - 6), "width": "12", "height": "12",
                                      "fill": "white", "stroke": INK, "stroke-width": "2"}))
        else:
            items.append(tag("circle", {"class": cls, "cx": num(x), "cy": num(y), "r": "5", "fill": "white",
                                        "stroke": INK, "stroke-width": "2"}))
        items.append(tag("text", {"x": num(x + 8), "y": num(y - 8), "font-size": "12", "fill": INK}, text=j.name))
    return document(size, size, items, title=title or f"{mech.name} (azimuth {az:g}°, elevation {el:g}°)")


PAGE = """<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"/><title>{title}</title>
<style>
body {{ font-family: sans-serif; color: #1d3557; margin: 1.5em; }}
#view {{ border: 1px solid #ced4da; background: white; cursor: grab; touch-action: none; }}
.controls label {{ margin-right: 1.2em; }}
</style></head>
<body>
<h1>{title}</h1>
<p class="summary">{summary}</p>
<svg id="view" xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}" viewBox="0 0 {size} {size}"></svg>
<div class="controls">
<button id="play" type="button">play</button>
<label>step <input id="step" type="range" min="0" max="{last}" value="0"/></label>
<label>azimuth <input id="azimuth" type="range" min="-180" max="180" value="{azimuth}"/></label>
<label>elevation <input id="elevation" type="range" min="-89" max="89" value="{elevation}"/></label>
<span id="where"></span>
</div>
<script>
const DATA = {data};
(function () {{
  const svg = document.getElementById("view"), NS = "http://www.w3.org/2000/svg";
  let az = {azimuth}, el = {elevation}, k = 0, timer = null;
  const size = {size}, pad = 30;
  function proj(p) {{
    const a = az * Math.PI / 180, e = el * Math.PI / 180;
    const x = p[0] * Math.cos(a) - p[1] * Math.sin(a), y = p[0] * Math.sin(a) + p[1] * Math.cos(a);
    return [x, p[2] * Math.cos(e) - y * Math.sin(e)];
  }}
  function box() {{
    let lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    DATA.frames.forEach(function (f) {{ Object.values(f).forEach(function (p) {{
      const s = proj(p); lo = [Math.min(lo[0], s[0]), Math.min(lo[1], s[1])]; hi = [Math.max(hi[0], s[0]), Math.max(hi[1], s[1])];
    }}); }});
    const span = Math.max(hi[0] - lo[0], hi[1] - lo[1]) || 1;
    return {{lo: lo, hi: hi, k: (size - 2 * pad) / span}};
  }}
  function el_(name, attrs) {{
    const e = document.createElementNS(NS, name);
    Object.keys(attrs).forEach(function (key) {{ e.setAttribute(key, attrs[key]); }});
    svg.appendChild(e); return e;
  }}
  function draw() {{
    while (svg.firstChild) svg.removeChild(svg.firstChild);
    const b = box(), f = DATA.frames[k];
    function screen(p) {{
      const s = proj(p);
      return [pad + (s[0] - b.lo[0]) * b.k + (size - 2 * pad - (b.hi[0] - b.lo[0]) * b.k) / 2,
              size - pad - (s[1] - b.lo[1]) * b.k - (size - 2 * pad - (b.hi[1] - b.lo[1]) * b.k) / 2];
    }}
    DATA.axes.forEach(function (a) {{
      const p = f[a.joint], s0 = screen(a.ends[0].map(function (v, i) {{ return p[i] + v; }})),
            s1 = screen(a.ends[1].map(function (v, i) {{ return p[i] + v; }}));
      el_("line", {{"class": "axis ground", x1: s0[0], y1: s0[1], x2: s1[0], y2: s1[1], stroke: "#6c757d",
                   "stroke-dasharray": "8 3 2 3"}});
    }});
    DATA.bars.forEach(function (bar) {{
      const s0 = screen(f[bar[0]]), s1 = screen(f[bar[1]]);
      el_("line", {{"class": "bar", x1: s0[0], y1: s0[1], x2: s1[0], y2: s1[1], stroke: "#1d3557", "stroke-width": 3,
                   "stroke-linecap": "round"}});
    }});
    Object.keys(DATA.traces).forEach(function (name) {{
      const pts = DATA.frames.map(function (g) {{ return screen(g[name]).join(","); }}).join(" ");
      el_("polyline", {{"class": "trace", points: pts, stroke: "#c1121f", fill: "none"}});
    }});
    DATA.joints.forEach(function (j) {{
      const s = screen(f[j.name]);
      if (j.kind === "S") el_("circle", {{"class": "joint S", cx: s[0], cy: s[1], r: 6, fill: "#1d3557"}});
      else if (j.kind === "P") el_("rect", {{"class": "joint P", x: s[0] - 6, y: s[1] - 6, width: 12, height: 12,
                                            fill: "white", stroke: "#1d3557", "stroke-width": 2}});
      else el_("circle", {{"class": "joint " + j.kind, cx: s[0], cy: s[1], r: 5, fill: "white", stroke: "#1d3557",
                           "stroke-width": 2}});
      const t = el_("text", {{x: s[0] + 8, y: s[1] - 8, "font-size": 12, fill: "#1d3557"}}); t.textContent = j.name;
    }});
    document.getElementById("where").textContent = DATA.input + " = " + DATA.inputs[k].toPrecision(6) + " " +
      DATA.unit + " (step " + k + " of " + (DATA.frames.length - 1) + ")";
    document.getElementById("step").value = k;
  }}
  function turn(a, e) {{ az = a; el = Math.max(-89, Math.min(89, e)); draw(); }}
  function frame(n) {{ k = ((n % DATA.frames.length) + DATA.frames.length) % DATA.frames.length; draw(); }}
  function play() {{ if (!timer) timer = setInterval(function () {{ frame(k + 1); }}, 60);
                     document.getElementById("play").textContent = "pause"; }}
  function pause() {{ clearInterval(timer); timer = null; document.getElementById("play").textContent = "play"; }}
  document.getElementById("play").addEventListener("click", function () {{ timer ? pause() : play(); }});
  document.getElementById("step").addEventListener("input", function (e) {{ frame(+e.target.value); }});
  document.getElementById("azimuth").addEventListener("input", function (e) {{ turn(+e.target.value, el); }});
  document.getElementById("elevation").addEventListener("input", function (e) {{ turn(az, +e.target.value); }});
  let drag = null;
  svg.addEventListener("pointerdown", function (e) {{ drag = [e.clientX, e.clientY, az, el]; }});
  window.addEventListener("pointerup", function () {{ drag = null; }});
  window.addEventListener("pointermove", function (e) {{
    if (drag) turn(drag[2] + (e.clientX - drag[0]) / 2, drag[3] + (e.clientY - drag[1]) / 2); }});
  window.domesView = {{turn: turn, frame: frame, play: play, pause: pause,
                       state: function () {{ return {{azimuth: az, elevation: el, step: k}}; }}}};
  draw();
}})();
</script>
</body></html>
"""


def spatial_html(mech: SpatialMechanism, frames: list[dict], inputs, input_name: str, unit: str,
                 traces=(), size: float = 520.0, view: tuple[float, float] = VIEW, summary: str = "") -> str:
    """A page where the mechanism turns (drag, sliders) and moves through ``frames`` (name -> (x, y, z) per step)."""
    reach = 0.24 * float(mech.size)
    axes = [{"joint": j.name, "ends": [list(-reach * np.asarray(j.axis)), list(reach * np.asarray(j.axis))]}
            for j in mech.joints if mech.ground in j.links and j.axis is not None]
    bars = []
    for link, joints in _links(mech):
        if link != mech.ground:
            bars += [[a, b] for i, a in enumerate(joints) for b in joints[i + 1:]]
    data = {"frames": [{n: [float(v) for v in p] for n, p in f.items()} for f in frames],
            "inputs": [float(x) for x in inputs], "input": input_name, "unit": unit,
            "joints": [{"name": j.name, "kind": j.kind} for j in mech.joints], "bars": bars, "axes": axes,
            "traces": {name: True for name in traces}}
    esc = lambda text: (text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;"))  # noqa: E731
    return PAGE.format(title=esc(mech.name), summary=esc(summary), size=int(size), last=len(frames) - 1,
                       azimuth=view[0], elevation=view[1], data=json.dumps(data).replace("</", "<\\/"))


__all__ = ["VIEW", "project", "spatial_html", "spatial_svg"]
