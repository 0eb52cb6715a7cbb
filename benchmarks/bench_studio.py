"""The studio's mechanism editor: how long a drag takes from the pointer's move to the linkage re-solved and redrawn.

Run ``python benchmarks/bench_studio.py``. It starts ``domes studio`` on a
temporary data folder, opens the editor in headless Chromium (Debian's
``/usr/bin/chromium`` through Playwright), opens a six-bar
(``examples/mechanisms/stephenson-six-bar.json``) and drags one of its ground
pivots (``F``) ``--reach`` pixels out and back in ``--steps`` pointer moves (on
the way the six-bar's input stops turning fully: the route then sweeps twice,
forward and back from the drawn pose to the two limits; rows split
the steps by that). Each move waits until the
editor has redrawn (``window.studioEditor.timings``: from the pointer move to
the links, the coupler curve of 360 points, the dead and branch points drawn
again), so every step is one full round: the page's request, the route, the
answer decoded and drawn. A second pass moves the pointer every 16 ms (a
drag at 60 Hz) without waiting: there the editor keeps one request in flight
and the latest position wins, so fewer steps are solved, each timed the same
way. The route's own time is measured in this process, on the same
mechanisms, with the page's encoding (``f64``) and with plain JSON lists,
as wall-clock time and as the processor time it used (which a machine busy
with other work inflates less). Prints one table (median, 90th percentile
and least, in ms) with the load average it ran under.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import statistics
import subprocess
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from domes.studio.mechanism import solve  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SIX_BAR = os.path.join(ROOT, "examples", "mechanisms", "stephenson-six-bar.json")
CHROMIUM = "/usr/bin/chromium"
FLAGS = ["--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run", "--disable-background-networking",
         "--disable-component-update", "--disable-sync"]


def percentile(values, p: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, round(p / 100 * (len(ordered) - 1))))]


def start_studio(home: str):
    proc = subprocess.Popen([sys.executable, "-m", "domes", "studio", "--home", home],
                            env={**os.environ, "DOMES_HOME": home, "PYTHONUNBUFFERED": "1"}, stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, start_new_session=True)
    found = re.search(r"http://127\.0\.0\.1:\d+", proc.stdout.readline())
    if not found:
        proc.kill()
        raise SystemExit("domes studio did not say its address")
    return proc, found.group()


def drag(page, pivot: str, steps: int, wait: bool, reach: float) -> tuple[list[float], list[dict], list[dict]]:
    """Drag ``pivot`` out ``reach`` pixels (right, and half as far up) and back in ``steps`` pointer moves.

    Answers the editor's timings of the drag, their phases and (``wait``) each step's mechanism and whether its
    input turned fully."""
    page.evaluate("() => { window.studioEditor.drawnPose(); window.studioEditor.timings.length = 0; "
                  "window.studioEditor.phases.length = 0; }")
    box = page.locator(f"#panel-editor circle.handle[data-name={pivot}]").bounding_box()
    x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
    page.mouse.move(x, y)
    page.mouse.down()
    solved = []
    for k in range(1, steps + 1):
        out = math.sin(math.pi * k / steps)
        page.mouse.move(x + reach * out, y - 0.5 * reach * out)
        if wait:
            page.wait_for_function("() => window.studioEditor.idle()", polling=1)
            solved.append(page.evaluate("() => ({mechanism: window.studioEditor.state.mechanism, "
                                        "full: window.studioEditor.state.solved.full_turn})"))
        else:
            page.wait_for_timeout(16)
    page.mouse.up()
    page.wait_for_function("() => window.studioEditor.idle()", polling=5)
    points = page.evaluate("() => JSON.parse(document.querySelector('#panel-editor .coupler-curve').dataset.points)"
                           ".length")
    if points != 360:
        raise SystemExit(f"the redrawn coupler curve has {points} points, not 360")
    timings, phases = page.evaluate("() => [window.studioEditor.timings.slice(), window.studioEditor.phases.slice()]")
    return timings, phases, solved


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=100, help="pointer moves of the drag (default 100)")
    parser.add_argument("--reach", type=float, default=60.0, help="how far the drag goes out, in pixels (default 60)")
    parser.add_argument("--file", default=SIX_BAR, help="mechanism file (default: the Stephenson six-bar)")
    parser.add_argument("--pivot", default="F", help="the joint dragged (default F, a ground pivot of the six-bar)")
    args = parser.parse_args(argv)
    from playwright.sync_api import sync_playwright

    with open(args.file, encoding="utf-8") as f:
        mechanism = json.load(f)
    rows = []
    with tempfile.TemporaryDirectory() as home:
        proc, url = start_studio(home)
        try:
            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=CHROMIUM, args=FLAGS)
                page = browser.new_page(viewport={"width": 1400, "height": 900})
                page.goto(url + "/")
                page.click("#tabs button[data-panel=editor]")
                page.evaluate("([m]) => Studio.openInEditor(m, null)", [mechanism])
                page.wait_for_function("() => window.studioEditor.idle() && "
                                       "document.querySelector('#panel-editor circle.handle')")
                drag(page, args.pivot, 6, True, 10.0)                       # warm up: the server's first solves
                timings, phases, solved = drag(page, args.pivot, args.steps, True, args.reach)
                full = [s["full"] for s in solved]
                rows.append(("drag step -> re-solved and redrawn (browser, one at a time)", timings))
                rows.append(("  steps where the input turns fully (one sweep)", [t for t, f in zip(timings, full) if f]))
                rows.append(("  steps where it stops at two limits (two sweeps)",
                             [t for t, f in zip(timings, full) if not f]))
                rows.append(("  of which the request (fetch: route, transfer, JSON)", [p["answered"] for p in phases]))
                rows.append(("  of which decoding and drawing", [p["drawn"] for p in phases]))
                live, phases, _ = drag(page, args.pivot, args.steps, False, args.reach)
                rows.append(("drag at 60 Hz -> redrawn (browser, latest wins)", live))
                rows.append(("  of which waiting for the request before", [p["waited"] for p in phases]))
                browser.close()
        finally:
            proc.terminate()
            proc.wait(10)
    for encoding in ("f64", "json"):
        wall, cpu = [], []
        for s in solved:
            start, used = time.perf_counter(), time.process_time()
            solve(None, {"mechanism": s["mechanism"], "encoding": encoding})
            wall.append(1e3 * (time.perf_counter() - start))
            cpu.append(1e3 * (time.process_time() - used))
        rows.append((f"route /api/mechanism/solve in process ({encoding})", wall))
        if encoding == "f64":
            rows.append(("  steps where the input turns fully", [t for t, f in zip(wall, full) if f]))
            rows.append(("  steps where it stops at two limits", [t for t, f in zip(wall, full) if not f]))
        rows.append(("  its processor time (the same calls)", cpu))
    print(f"# {mechanism.get('name')}: pivot {args.pivot} dragged {args.reach:g} px out and back in {args.steps} steps "
          f"(the input turns fully at {sum(full)}); coupler curve of 360 points; load average "
          f"{os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    print(f"{'measure':<62} {'steps':>6} {'median ms':>10} {'p90 ms':>8} {'min ms':>7}")
    for name, values in rows:
        if values:
            print(f"{name:<62} {len(values):>6} {statistics.median(values):>10.1f} {percentile(values, 90):>8.1f} "
                  f"{min(values):>7.1f}")


if __name__ == "__main__":
    main()
