"""The atlas page in a real browser: headless Chromium renders every card (issue acceptance).

Skipped when /usr/bin/chromium is absent (Debian package ``chromium``).
"""

import os
import re
import subprocess

import pytest

from domes.io.scenes import load_scene
from domes.sketch import chain_atlas_html
from domes.sketch.atlas import regeneration_html
from domes.typesynth import chains, regenerate

CHROMIUM = "/usr/bin/chromium"
pytestmark = pytest.mark.skipif(not os.path.exists(CHROMIUM), reason="needs the Debian package chromium (/usr/bin/chromium)")

#: Measures, in the browser, every card's drawing and writes one line per card into <pre id="report">.
PROBE = """<script>
window.addEventListener("load", function () {
  var rows = [];
  document.querySelectorAll(".card").forEach(function (card) {
    var svg = card.querySelector("svg");
    var box = svg ? svg.getBoundingClientRect() : {width: 0, height: 0};
    var drawn = svg && svg.querySelector(".skeleton") ? svg.querySelector(".skeleton").getBBox() : {width: 0, height: 0};
    rows.push([card.dataset.id, box.width, box.height, drawn.width, drawn.height, card.querySelectorAll("circle.joint").length].join(" "));
  });
  var pre = document.createElement("pre");
  pre.id = "report";
  pre.textContent = rows.join("\\n");
  document.body.appendChild(pre);
});
</script>"""


def _chromium(*args):
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--hide-scrollbars", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=180, check=True)


def test_every_card_of_the_ten_bar_atlas_renders(tmp_path):
    # all 230 one-DOF ten-bar chains (seed 002 §3-2-II), each card with a drawing of its 13 joints
    page = chain_atlas_html(chains(links=10, dof=1)).replace("</body>", PROBE + "</body>")
    path = tmp_path / "atlas.html"
    path.write_text(page, encoding="utf-8")
    dom = _chromium("--virtual-time-budget=10000", "--dump-dom", path.as_uri()).stdout
    report = re.search(r'<pre id="report">(.*?)</pre>', dom, re.S)
    assert report, "the probe script did not run"
    rows = [line.split() for line in report.group(1).strip().splitlines()]
    assert [r[0] for r in rows] == [str(i) for i in range(1, 231)]
    for card, width, height, drawn_w, drawn_h, joints in rows:
        assert float(width) > 100 and float(height) > 100, card
        assert float(drawn_w) > 50 and float(drawn_h) > 50, card
        assert int(joints) == 13, card


#: Per card of a candidates page: id, drawing size, hatched ground, shock absorbers, swing-arm labels, marked.
CANDIDATE_PROBE = """<script>
window.addEventListener("load", function () {
  var rows = [];
  document.querySelectorAll(".card").forEach(function (card) {
    var svg = card.querySelector("svg");
    var box = svg.getBoundingClientRect();
    var shock = svg.querySelector(".member.shock");
    var shockBox = shock ? shock.getBBox() : {width: 0, height: 0};
    var arms = Array.prototype.filter.call(svg.querySelectorAll("text.role"), function (t) { return t.textContent === "swing arm"; });
    rows.push([card.dataset.id, box.width, box.height, svg.querySelectorAll('.link[fill="url(#hatch)"]').length,
               svg.querySelectorAll(".ground-pivot").length, Math.max(shockBox.width, shockBox.height), arms.length,
               card.classList.contains("marked") ? 1 : 0].join(" "));
  });
  var pre = document.createElement("pre");
  pre.id = "report";
  pre.textContent = rows.join("\\n");
  document.body.appendChild(pre);
});
</script>"""


def test_every_card_of_the_motorcycle_page_renders(tmp_path):
    # seed 002 §4-1 Fig. 4-12: the six candidates, ground hatched with its pivots, the shock absorber
    # drawn, the swing arm written; exactly one card (the Suzuki RM-250X) marked as existing
    page = regeneration_html(regenerate(load_scene("motorcycle"))).replace("</body>", CANDIDATE_PROBE + "</body>")
    path = tmp_path / "motorcycle.html"
    path.write_text(page, encoding="utf-8")
    dom = _chromium("--virtual-time-budget=10000", "--dump-dom", path.as_uri()).stdout
    report = re.search(r'<pre id="report">(.*?)</pre>', dom, re.S)
    assert report, "the probe script did not run"
    rows = [line.split() for line in report.group(1).strip().splitlines()]
    assert [r[0] for r in rows] == ["1", "2", "3", "4", "5", "6"]
    for card, width, height, hatched, pivots, shock, arms, _ in rows:
        assert float(width) > 100 and float(height) > 100, card
        assert int(hatched) == 1 and int(pivots) >= 2, card
        assert float(shock) > 20 and int(arms) == 1, card
    assert [int(r[-1]) for r in rows] == [0, 1, 0, 0, 0, 0]


def test_screenshot_of_the_atlas(tmp_path):
    path = tmp_path / "atlas.html"
    path.write_text(chain_atlas_html(chains(links=8, dof=1)), encoding="utf-8")
    shot = tmp_path / "atlas.png"
    _chromium("--window-size=1200,900", f"--screenshot={shot}", path.as_uri())
    data = shot.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 20000


#: Per card of a tolerance page: id, drawing width, drawn curves (with their on-screen widths), share bars.
TOLERANCE_PROBE = """<script>
window.addEventListener("load", function () {
  var rows = [];
  document.querySelectorAll(".card").forEach(function (card) {
    var svg = card.querySelector("svg");
    var curves = Array.from(card.querySelectorAll("polyline.curve")).map(function (c) { return c.getBBox().width; });
    var bars = Array.from(card.querySelectorAll("rect.share")).map(function (b) { return b.getBBox().width; });
    rows.push([card.dataset.id, svg.getBoundingClientRect().width, curves.length, Math.min.apply(null, curves.concat([1e9])),
               bars.length, Math.max.apply(null, bars.concat([0]))].join(" "));
  });
  var pre = document.createElement("pre");
  pre.id = "report";
  pre.textContent = rows.join("\\n");
  document.body.appendChild(pre);
});
</script>"""


def test_the_tolerance_page_renders(tmp_path):
    # domes tolerance --format html (issue 16, item 6): a plot per output column, the shares, the scan
    import json
    import sys

    out = subprocess.run([sys.executable, "-m", "domes", "tolerance", "examples/mechanisms/slider-crank.json",
                          "--output", "point:M", "--relative", "1e-4", "--samples", "20000", "--scan", "--format",
                          "json"], capture_output=True, text=True, check=True)
    from domes.sketch.tolerance import tolerance_html

    doc = json.loads(out.stdout)
    path = tmp_path / "tolerance.html"
    path.write_text(tolerance_html(doc).replace("</body>", TOLERANCE_PROBE + "</body>"), encoding="utf-8")
    dom = _chromium("--virtual-time-budget=10000", "--dump-dom", path.as_uri()).stdout
    rows = {r.split()[0]: r.split()[1:] for r in re.search(r'<pre id="report">(.*?)</pre>', dom, re.S).group(1)
            .strip().splitlines()}
    assert list(rows) == ["point:M.x", "point:M.y", "shares", "scan"]
    for column in ("point:M.x", "point:M.y"):
        width, curves, narrowest = float(rows[column][0]), int(rows[column][1]), float(rows[column][2])
        assert width > 300 and curves == 3 and narrowest > 250       # worst case, first order, Monte Carlo
    bars, widest = int(rows["shares"][3]), float(rows["shares"][4])
    assert bars == len(doc["dimensions"]) == 8 and widest > 50
    assert int(rows["scan"][1]) == 1


def test_the_dynamics_pages_render(tmp_path):
    # domes dynamics --format html (issue 16, item 6): force curves over the motion, reactions, powers; the
    # scriber's contour with its junctions and its two forces along the arc length
    import json
    import sys

    from domes.sketch.dynamics import dynamics_html

    for file, expected in (("examples/dynamics/slider-crank-engine.json", {"driving": 1, "reactions": 4, "power": 3}),
                           ("examples/dynamics/scriber-stadium.json", {"contour": 0, "forces": 2, "strokes": 2,
                                                                       "power": 2})):
        out = subprocess.run([sys.executable, "-m", "domes", "dynamics", file, "--format", "json"],
                             capture_output=True, text=True, check=True)
        doc = json.loads(out.stdout)
        path = tmp_path / "dynamics.html"
        path.write_text(dynamics_html(doc).replace("</body>", TOLERANCE_PROBE + "</body>"), encoding="utf-8")
        dom = _chromium("--virtual-time-budget=10000", "--dump-dom", path.as_uri()).stdout
        rows = {r.split()[0]: r.split()[1:] for r in re.search(r'<pre id="report">(.*?)</pre>', dom, re.S).group(1)
                .strip().splitlines()}
        assert list(rows) == list(expected)
        for card, curves in expected.items():
            width, drawn = float(rows[card][0]), int(rows[card][1])
            assert width > 300 and drawn == curves, (file, card, rows[card])
            if curves:
                assert float(rows[card][2]) > 250             # every curve spans the plot
        if "contour" in expected:
            assert dom.count('class="junction"') == 4 and dom.count('class="pivot"') == 2


SPATIAL_PROBE = """<script>
window.addEventListener("load", function () {
  var v = window.domesView, out = [];
  function where() { var c = document.querySelectorAll("circle.joint")[2]; return [+c.getAttribute("cx"), +c.getAttribute("cy")]; }
  out.push("joints " + document.querySelectorAll(".joint").length + " bars " + document.querySelectorAll("line.bar").length +
           " axes " + document.querySelectorAll("line.axis").length + " traces " + document.querySelectorAll("polyline.trace").length);
  var a = where(); v.turn(60, 10); var b = where(); v.frame(18); var c = where();
  out.push("turned " + (Math.abs(a[0] - b[0]) + Math.abs(a[1] - b[1]) > 1) + " moved " + (Math.abs(b[0] - c[0]) + Math.abs(b[1] - c[1]) > 1));
  v.frame(0); v.play();
  setTimeout(function () {
    v.pause();
    out.push("played " + v.state().step);
    var pre = document.createElement("pre"); pre.id = "report"; pre.textContent = out.join("\\n"); document.body.appendChild(pre);
  }, 1000);
});
</script>"""


def test_the_spatial_page_turns_and_plays(tmp_path):
    # domes draw FILE.json --format html on a spatial file (issue 15, item 5): drawn in the browser from the
    # sweep's frames; turning moves the picture, a frame moves the mechanism, play steps through the sweep
    import sys

    out = subprocess.run([sys.executable, "-m", "domes", "draw", "examples/spatial/rssr-seed001.json", "--format",
                          "html", "--coupler", "B"], capture_output=True, text=True, check=True)
    path = tmp_path / "rssr.html"
    path.write_text(out.stdout.replace("</body>", SPATIAL_PROBE + "</body>"), encoding="utf-8")
    dom = _chromium("--virtual-time-budget=5000", "--dump-dom", path.as_uri()).stdout
    report = re.search(r'<pre id="report">(.*?)</pre>', dom, re.S).group(1).strip().splitlines()
    assert report[0] == "joints 4 bars 3 axes 2 traces 1"          # crank, coupler, rocker; the two ground axes
    assert report[1] == "turned true moved true"
    assert int(report[2].split()[1]) > 5                            # about 16 frames a second
