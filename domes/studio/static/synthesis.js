// The synthesis panel: a sketched path matched by four-bars (domes curves match), and precision positions of a
// body guided by four-bars (domes synthesize, rigid-body guidance), with the Burmester curves.
"use strict";

(function () {
  var W = 640, H = 420;
  var state = {path: {raw: [], points: [], view: {cx: W / 2, cy: H / 2, s: 1}, answer: null, shown: 0},
               pos: {list: [], view: {cx: 5, cy: 3.5, s: 50}, answer: null, shown: -1, picking: 0, picks: []}};
  // What the tests (and the curious) can read: the last request and answer of each part.
  var exposed = window.studioSynthesis = {last: null, lastPositions: null, state: state};

  function fmt(x, digits) {
    if (x === null || x === undefined) return "—";
    if (x !== 0 && (Math.abs(x) < 1e-3 || Math.abs(x) >= 1e5)) return x.toExponential((digits || 3) - 1);
    return String(Number(x.toPrecision(digits || 4)));
  }
  function toSvg(view, p) { return [W / 2 + view.s * (p[0] - view.cx), H / 2 - view.s * (p[1] - view.cy)]; }
  function toWorld(view, svgEl, event) {      // the pointer in the pad's own units (its border and scaling undone)
    var q = new DOMPoint(event.clientX, event.clientY).matrixTransform(svgEl.getScreenCTM().inverse());
    return [view.cx + (q.x - W / 2) / view.s, view.cy - (q.y - H / 2) / view.s];
  }
  function fitView(view, pts) {
    if (!pts.length) return;
    var xs = pts.map(function (p) { return p[0]; }), ys = pts.map(function (p) { return p[1]; });
    var x0 = Math.min.apply(null, xs), x1 = Math.max.apply(null, xs), y0 = Math.min.apply(null, ys), y1 = Math.max.apply(null, ys);
    view.cx = (x0 + x1) / 2; view.cy = (y0 + y1) / 2;
    view.s = 0.75 * Math.min(W / Math.max(x1 - x0, 1e-9), H / Math.max(y1 - y0, 1e-9));
  }
  function polyline(view, pts, attrs, closed) {
    var d = pts.map(function (p, i) { var q = toSvg(view, p); return (i ? "L" : "M") + q[0].toFixed(2) + " " + q[1].toFixed(2); }).join("");
    return Studio.svg("path", Object.assign({d: d + (closed ? "Z" : ""), fill: "none"}, attrs));
  }
  function dot(view, p, r, cls) { var q = toSvg(view, p); return Studio.svg("circle", {cx: q[0], cy: q[1], r: r, class: cls}); }
  function clear(node) { while (node.firstChild) node.removeChild(node.firstChild); }
  function numbers(text) {
    return text.split(/[\s,;]+/).filter(function (t) { return t !== ""; }).map(Number);
  }
  // Progress shown in place while the server works: what it is doing and for how long.
  function busy(box, text) {
    var started = Date.now();
    box.className = "synthesis-status busy";
    box.textContent = text + "…";
    var timer = setInterval(function () { box.textContent = text + "… " + Math.round((Date.now() - started) / 1000) + " s"; }, 500);
    return function () { clearInterval(timer); box.className = "synthesis-status"; };
  }
  function failed(box, err) { box.className = "synthesis-status error"; box.textContent = err.message; }

  // Points resampled by arc length: n points along the stroke (closed: the closing chord included).
  function resample(raw, n, closed) {
    var pts = closed ? raw.concat([raw[0]]) : raw.slice(), s = [0];
    for (var i = 1; i < pts.length; i++) s.push(s[i - 1] + Math.hypot(pts[i][0] - pts[i - 1][0], pts[i][1] - pts[i - 1][1]));
    var total = s[s.length - 1], out = [], j = 0;
    if (!(total > 0)) return raw.slice(0, 1);
    for (var k = 0; k < n; k++) {
      var t = closed ? total * k / n : total * k / (n - 1);
      while (j < s.length - 2 && s[j + 1] < t) j++;
      var f = s[j + 1] > s[j] ? (t - s[j]) / (s[j + 1] - s[j]) : 0;
      out.push([pts[j][0] + f * (pts[j + 1][0] - pts[j][0]), pts[j][1] + f * (pts[j + 1][1] - pts[j][1])]);
    }
    return out;
  }

  // -- the path: sketch, match, results ----------------------------------------------------------------------
  var P = {};
  function buildPath(root) {
    P.pad = Studio.svg("svg", {viewBox: "0 0 " + W + " " + H, class: "synthesis-pad", id: "synthesis-path-pad",
                               role: "img", "aria-label": "Sketch pad: draw the wanted path"});
    P.count = Studio.el("input", {type: "number", min: 9, max: 400, value: 48, id: "synthesis-count"});
    P.closed = Studio.el("input", {type: "checkbox", checked: true, id: "synthesis-closed"});
    P.results = Studio.el("input", {type: "number", min: 1, max: 20, value: 5, id: "synthesis-results"});
    P.drawn = Studio.el("input", {type: "checkbox", checked: true, id: "synthesis-drawn",
                                  title: "a path drawn by hand: read as a sketch (its scatter, corners), every candidate fitted, "
                                         + "the errors measured against your points"});
    P.tol = Studio.el("input", {type: "number", min: 0, step: "any", placeholder: "auto", id: "synthesis-tol",
                                title: "largest distance accepted, relative to the path's size (auto: four times a sketch's "
                                       + "scatter when drawn by hand, else 1e-6 of the size)"});
    P.atlas = Studio.el("select", {id: "synthesis-atlas"},
      Studio.el("option", {value: "auto"}, "auto: the data folder's small atlas if built, else the quick one"),
      Studio.el("option", {value: "quick"}, "quick (in memory)"),
      Studio.el("option", {value: "small"}, "small (built in the data folder on first use)"));
    P.text = Studio.el("textarea", {rows: 6, id: "synthesis-points", placeholder: "x, y per line", spellcheck: "false"});
    P.file = Studio.el("input", {type: "file", accept: ".csv,.txt,.json", id: "synthesis-file"});
    P.status = Studio.el("div", {class: "synthesis-status", id: "synthesis-path-status", role: "status"});
    P.list = Studio.el("ol", {class: "synthesis-results", id: "synthesis-fits"});
    P.match = Studio.el("button", {id: "synthesis-match", class: "primary", onclick: matchPath}, "Match four-bars");
    root.appendChild(Studio.el("div", {class: "synthesis-part"},
      Studio.el("h2", {}, "Path generation: which four-bar traces this path?"),
      Studio.el("p", {class: "synthesis-hint"}, "Draw the path on the pad with the mouse (or paste or load points, x, y per line), then match: "
        + "the atlas of coupler curves is looked up and the nearest four-bars refined by least squares, each checked by the kinematics kernel."),
      Studio.el("div", {class: "synthesis-row"},
        Studio.el("div", {class: "synthesis-left"}, P.pad,
          Studio.el("div", {class: "synthesis-controls"},
            Studio.el("label", {}, "points ", P.count), Studio.el("label", {}, P.closed, " closed"),
            Studio.el("label", {}, P.drawn, " drawn by hand"),
            Studio.el("label", {}, "results ", P.results), Studio.el("label", {}, "tolerance ", P.tol),
            Studio.el("label", {}, "atlas ", P.atlas)),
          Studio.el("div", {class: "synthesis-controls"}, P.match,
            Studio.el("button", {onclick: function () { setPoints([], true); }}, "Clear"))),
        Studio.el("div", {class: "synthesis-right"},
          Studio.el("label", {for: "synthesis-points"}, "Points"), P.text,
          Studio.el("div", {class: "synthesis-controls"},
            Studio.el("button", {id: "synthesis-use", onclick: usePoints}, "Use these points"), P.file),
          P.status, P.list))));
    var drawing = false;
    P.pad.addEventListener("pointerdown", function (e) {
      if (e.button !== 0) return;
      drawing = true; state.path.raw = [toWorld(state.path.view, P.pad, e)];
      P.pad.setPointerCapture(e.pointerId); e.preventDefault();
    });
    P.pad.addEventListener("pointermove", function (e) {
      if (!drawing) return;
      var evs = e.getCoalescedEvents ? e.getCoalescedEvents() : [e];
      (evs.length ? evs : [e]).forEach(function (ev) { state.path.raw.push(toWorld(state.path.view, P.pad, ev)); });
      drawPath();
    });
    function finish() {
      if (!drawing) return;
      drawing = false;
      var raw = state.path.raw;
      if (raw.length < 3) { state.path.raw = []; drawPath(); return; }
      setPoints(resample(raw, Math.max(9, Math.min(400, parseInt(P.count.value, 10) || 48)), P.closed.checked), false);
      P.drawn.checked = true;
    }
    P.pad.addEventListener("pointerup", finish);
    P.pad.addEventListener("pointercancel", finish);
    P.file.addEventListener("change", function () {
      var f = P.file.files[0];
      if (!f) return;
      f.text().then(function (text) { P.text.value = fromFile(text); usePoints(); });
    });
    drawPath();
  }
  function fromFile(text) {
    var t = text.trim();
    if (t[0] === "[" || t[0] === "{") {
      try {
        var v = JSON.parse(t), pts = Array.isArray(v) ? v : v.points;
        if (v && v.closed === false) P.closed.checked = false;
        return pts.map(function (p) { return p.join(", "); }).join("\n");
      } catch (e) { return text; }
    }
    return text;
  }
  function setPoints(points, refit) {
    state.path.points = points;
    state.path.raw = refit ? [] : state.path.raw;
    state.path.answer = null;
    P.text.value = points.map(function (p) { return p[0].toPrecision(8) + ", " + p[1].toPrecision(8); }).join("\n");
    if (refit) fitView(state.path.view, points);
    clear(P.list); P.status.textContent = ""; P.status.className = "synthesis-status";
    drawPath();
  }
  function usePoints() {
    var pts = [], bad = null;
    P.text.value.split(/\n/).forEach(function (line, i) {
      var t = line.trim();
      if (!t || t[0] === "#" || /^[a-z_ ,;]+$/i.test(t)) return;        // blank, comment or a header (x, y)
      var v = numbers(t);
      if (v.length !== 2 || !v.every(isFinite)) bad = bad || "line " + (i + 1) + ": '" + t + "' is not x, y";
      else pts.push(v);
    });
    if (bad) { failed(P.status, new Error(bad)); return; }
    P.drawn.checked = false;            // points typed or loaded: taken as exact unless "drawn by hand" is ticked
    setPoints(pts, true);
  }
  function drawPath() {
    var v = state.path.view, a = state.path.answer;
    clear(P.pad);
    P.pad.appendChild(Studio.svg("rect", {x: 0, y: 0, width: W, height: H, class: "synthesis-paper"}));
    if (a) a.fits.forEach(function (f, k) {
      if (f.nearest === null) return;
      P.pad.appendChild(polyline(v, f.curves[f.nearest], {class: "synthesis-curve" + (k === state.path.shown ? " shown" : ""),
                                                          "data-rank": k + 1}, true));
    });
    if (state.path.raw.length > 1) P.pad.appendChild(polyline(v, state.path.raw, {class: "synthesis-stroke"}, false));
    state.path.points.forEach(function (p) { P.pad.appendChild(dot(v, p, 3, "synthesis-point")); });
    if (a && a.fits[state.path.shown] && a.fits[state.path.shown].mechanism) drawLinkage(P.pad, v, a.fits[state.path.shown].mechanism);
  }
  function drawLinkage(pad, view, mech) {
    var at = {};
    mech.joints.forEach(function (j) { at[j.name] = j.at; });
    var P_ = (mech.points || []).filter(function (p) { return p.name === "P"; })[0];
    var g = Studio.svg("g", {class: "synthesis-linkage"});
    [["A", "B"], ["B", "C"], ["C", "D"]].forEach(function (e) {
      if (at[e[0]] && at[e[1]]) g.appendChild(polyline(view, [at[e[0]], at[e[1]]], {}, false));
    });
    if (P_ && at.B && at.C) g.appendChild(polyline(view, [at.B, P_.at, at.C], {class: "coupler"}, true));
    ["A", "D"].forEach(function (n) { if (at[n]) g.appendChild(dot(view, at[n], 5, "pivot")); });
    pad.appendChild(g);
  }
  function matchPath() {
    var points = state.path.points;
    if (points.length < 9) { failed(P.status, new Error("draw a path first (or use points): a four-bar needs at least 9 points")); return; }
    var body = {points: points, closed: P.closed.checked, drawn: P.drawn.checked,
                results: parseInt(P.results.value, 10) || 5, atlas: P.atlas.value};
    var tol = parseFloat(P.tol.value);
    if (tol > 0) body.tol = tol;
    var done = busy(P.status, "Looking the path up in the atlas and refining the nearest four-bars");
    P.match.disabled = true; clear(P.list);
    exposed.last = {request: body, answer: null, error: null, pending: true};
    Studio.api("/api/synthesis/path", body).then(function (answer) {
      done(); P.match.disabled = false;
      exposed.last = {request: body, answer: answer, error: null, pending: false};
      state.path.answer = answer; state.path.shown = 0;
      P.status.textContent = (answer.sketch ? "Read as a sketch: " + answer.sketch.read + ", scatter "
                              + (100 * answer.sketch.noise).toFixed(2) + "% of its size. " : "")
                             + answer.message + " — atlas: " + answer.atlas + ".";
      showFits(answer); drawPath();
    }).catch(function (err) {
      done(); P.match.disabled = false;
      exposed.last = {request: body, answer: null, error: err.message, pending: false};
      failed(P.status, err);
    });
  }
  function showFits(answer) {
    clear(P.list);
    if (!answer.fits.length) P.list.appendChild(Studio.el("li", {class: "error"}, "no candidate could be refined"));
    answer.fits.forEach(function (f, k) {
      var L = f.lengths;
      var item = Studio.el("li", {class: "synthesis-fit" + (k === state.path.shown ? " shown" : ""), "data-rank": k + 1,
                                  "data-error-max": f.error.max, "data-error-rms": f.error.rms},
        Studio.el("div", {class: "synthesis-fit-head"},
          Studio.el("span", {class: f.success ? "ok" : "muted"}, f.success ? "fits" : "nearest"), " ",
          Studio.el("span", {class: "synthesis-error"}, "largest ", Studio.el("b", {class: "error-max"}, fmt(f.error.max, 3)),
                    ", RMS ", Studio.el("span", {class: "error-rms"}, fmt(f.error.rms, 3)), " of the path's size")),
        Studio.el("div", {}, "crank " + fmt(L.crank) + ", coupler " + fmt(L.coupler) + ", rocker " + fmt(L.rocker)
                  + ", frame " + fmt(L.frame) + "; " + f.grashof + "; input " + (f.input_turns ? "turns fully" : "only rocks")),
        f.merged.length ? Studio.el("div", {class: "synthesis-hint"}, f.merged.length + " more of the same curve: "
          + f.merged.map(function (m) { return m.relation; }).join("; ")) : null,
        Studio.el("div", {class: "synthesis-controls"},
          Studio.el("button", {onclick: function () { state.path.shown = k; showFits(answer); drawPath(); }}, "Show"),
          f.mechanism ? Studio.el("button", {class: "open", onclick: function () { Studio.openInEditor(f.mechanism, f.name); }},
                                  "Open in editor") : null));
      P.list.appendChild(item);
    });
  }

  // -- precision positions: Burmester curves, dyads and four-bars -----------------------------------------------
  var Q = {};
  function buildPositions(root) {
    Q.pad = Studio.svg("svg", {viewBox: "0 0 " + W + " " + H, class: "synthesis-pad", id: "synthesis-positions-pad",
                               role: "img", "aria-label": "Precision positions: click to place, drag to move, drag the handle to turn"});
    Q.table = Studio.el("tbody", {});
    Q.choices = Studio.el("input", {type: "text", id: "synthesis-choices", size: 28});
    Q.choiceLabel = Studio.el("span", {}, "");
    Q.status = Studio.el("div", {class: "synthesis-status", id: "synthesis-positions-status", role: "status"});
    Q.dyads = Studio.el("ul", {class: "synthesis-dyads", id: "synthesis-dyads"});
    Q.list = Studio.el("ol", {class: "synthesis-results", id: "synthesis-fourbars"});
    Q.run = Studio.el("button", {id: "synthesis-guide", class: "primary", onclick: synthesizePositions}, "Synthesize");
    Q.pick = Studio.el("button", {id: "synthesis-pick", onclick: function () { state.pos.picking = 2; state.pos.picks = [];
      Q.status.className = "synthesis-status"; Q.status.textContent = "click two circle points on the pad"; }}, "Pick on the pad");
    root.appendChild(Studio.el("div", {class: "synthesis-part"},
      Studio.el("h2", {}, "Rigid-body guidance: precision positions"),
      Studio.el("p", {class: "synthesis-hint"}, "Click on the pad to place 3 to 5 positions of the body, drag one to move it, drag its handle to turn it "
        + "(or type x, y and angle). Four positions give the circle-point and centre-point curves; five, the Burmester points."),
      Studio.el("div", {class: "synthesis-row"},
        Studio.el("div", {class: "synthesis-left"}, Q.pad,
          Studio.el("div", {class: "synthesis-controls"}, Q.run,
            Studio.el("button", {onclick: function () { state.pos.list = []; state.pos.answer = null; renderPositions(); }}, "Clear"))),
        Studio.el("div", {class: "synthesis-right"},
          Studio.el("table", {class: "synthesis-positions"},
            Studio.el("thead", {}, Studio.el("tr", {}, Studio.el("th", {}, "#"), Studio.el("th", {}, "x"), Studio.el("th", {}, "y"),
                                             Studio.el("th", {}, "angle °"), Studio.el("th", {}, ""))), Q.table),
          Studio.el("div", {class: "synthesis-controls"},
            Studio.el("button", {id: "synthesis-add", onclick: function () {
              var last = state.pos.list[state.pos.list.length - 1] || [state.pos.view.cx - 1, state.pos.view.cy, 0];
              addPosition([last[0] + 1, last[1], last[2]]); }}, "Add position")),
          Studio.el("label", {class: "synthesis-choice"}, Q.choiceLabel, Q.choices, Q.pick),
          Q.status, Q.dyads, Q.list))));
    var drag = null;
    Q.pad.addEventListener("pointerdown", function (e) {
      if (e.button !== 0) return;
      var w = toWorld(state.pos.view, Q.pad, e), target = e.target.closest("[data-index]");
      if (state.pos.picking) { pickChoice(w); return; }
      if (target) drag = {index: +target.dataset.index, turn: target.dataset.part === "handle"};
      else if (state.pos.list.length < 5) { addPosition([w[0], w[1], state.pos.list.length ? state.pos.list[state.pos.list.length - 1][2] : 0]); return; }
      else { failed(Q.status, new Error("five positions at most: remove one first")); return; }
      Q.pad.setPointerCapture(e.pointerId); e.preventDefault();
    });
    Q.pad.addEventListener("pointermove", function (e) {
      if (!drag) return;
      var w = toWorld(state.pos.view, Q.pad, e), p = state.pos.list[drag.index];
      if (drag.turn) p[2] = Math.round(Math.atan2(w[1] - p[1], w[0] - p[0]) * 180 / Math.PI * 10) / 10;
      else { p[0] = Math.round(w[0] * 1000) / 1000; p[1] = Math.round(w[1] * 1000) / 1000; }
      state.pos.answer = null; renderPositions();
    });
    ["pointerup", "pointercancel"].forEach(function (t) { Q.pad.addEventListener(t, function () { drag = null; }); });
    renderPositions();
  }
  function addPosition(p) { state.pos.list.push(p.map(function (v) { return Math.round(v * 1000) / 1000; })); state.pos.answer = null; renderPositions(); }
  function pickChoice(w) {
    state.pos.picks.push(w);
    if (--state.pos.picking > 0) { drawPositions(); return; }
    var n = state.pos.list.length;
    Q.choices.value = state.pos.picks.map(function (p) {
      return n === 4 ? fmt(p[0], 6) : fmt(p[0], 6) + ", " + fmt(p[1], 6); }).join("; ");
    state.pos.picks = [];
    synthesizePositions();
  }
  function renderPositions() {
    clear(Q.table);
    state.pos.list.forEach(function (p, i) {
      function cell(k) {
        return Studio.el("td", {}, Studio.el("input", {type: "number", step: "any", value: p[k], "data-index": i, "data-k": k,
          onchange: function (e) {     // the pad redrawn, not the table (the field being left keeps its place)
            var v = parseFloat(e.target.value);
            if (isFinite(v)) { p[k] = v; state.pos.answer = null; drawPositions(); } else e.target.value = p[k]; }}));
      }
      Q.table.appendChild(Studio.el("tr", {}, Studio.el("td", {}, String(i + 1)), cell(0), cell(1), cell(2),
        Studio.el("td", {}, Studio.el("button", {title: "remove", onclick: function () {
          state.pos.list.splice(i, 1); state.pos.answer = null; renderPositions(); }}, "×"))));
    });
    var n = state.pos.list.length;
    Q.choiceLabel.textContent = n === 3 ? "two circle points (x1, y1; x2, y2) " : n === 4 ? "two circle-point abscissas (x1; x2) " : "";
    Q.choices.hidden = Q.pick.hidden = !(n === 3 || n === 4);
    drawPositions();
  }
  function drawPositions() {
    var v = state.pos.view, a = state.pos.answer;
    clear(Q.pad);
    Q.pad.appendChild(Studio.svg("rect", {x: 0, y: 0, width: W, height: H, class: "synthesis-paper"}));
    if (a) {
      a.curves.forEach(function (c, k) {
        c.circle.forEach(function (p) { Q.pad.appendChild(dot(v, p, 1.6, "synthesis-circle-curve c" + k)); });
        c.centre.forEach(function (p) { Q.pad.appendChild(dot(v, p, 1.6, "synthesis-centre-curve c" + k)); });
      });
      a.dyads.forEach(function (d) {
        Q.pad.appendChild(polyline(v, [d.centre, d.circle], {class: "synthesis-dyad"}, false));
        Q.pad.appendChild(dot(v, d.circle, 4, "synthesis-circle-point"));
        Q.pad.appendChild(dot(v, d.centre, 4, "synthesis-centre-point"));
      });
      var s = a.solutions[state.pos.shown];
      if (s) drawLinkage(Q.pad, v, s.mechanism);
    }
    state.pos.list.forEach(function (p, i) {
      var q = toSvg(v, [p[0], p[1]]), t = p[2] * Math.PI / 180, L = 34;
      var tip = [q[0] + L * Math.cos(t), q[1] - L * Math.sin(t)], side = [q[0] - 12 * Math.sin(t), q[1] - 12 * Math.cos(t)];
      var g = Studio.svg("g", {class: "synthesis-body"});
      g.appendChild(Studio.svg("polygon", {points: [q, tip, side].map(function (r) { return r[0] + "," + r[1]; }).join(" "),
                                          "data-index": i, "data-part": "body"}));
      g.appendChild(Studio.svg("circle", {cx: tip[0], cy: tip[1], r: 6, class: "handle", "data-index": i, "data-part": "handle"}));
      var label = Studio.svg("text", {x: q[0] - 14, y: q[1] + 16});
      label.textContent = String(i + 1);
      g.appendChild(label);
      Q.pad.appendChild(g);
    });
    state.pos.picks.forEach(function (p) { Q.pad.appendChild(dot(v, p, 4, "synthesis-pick")); });
  }
  function synthesizePositions() {
    var n = state.pos.list.length, body = {positions: state.pos.list.map(function (p) { return p.slice(); })};
    var vals = numbers(Q.choices.value);
    if (Q.choices.value.trim() && (n === 3 || n === 4)) {
      if (vals.some(function (x) { return !isFinite(x); })) { failed(Q.status, new Error("free choices: numbers only")); return; }
      if (n === 3) body.circle_points = [vals.slice(0, 2), vals.slice(2, 4)].concat(vals.length > 4 ? [vals.slice(4)] : []);
      else body.circle_x = vals;
    }
    var done = busy(Q.status, "Synthesizing");
    Q.run.disabled = true;
    exposed.lastPositions = {request: body, answer: null, error: null, pending: true};
    Studio.api("/api/synthesis/positions", body).then(function (answer) {
      done(); Q.run.disabled = false;
      exposed.lastPositions = {request: body, answer: answer, error: null, pending: false};
      state.pos.answer = answer; state.pos.shown = answer.solutions.length ? 0 : -1;
      // the positions and the pivots found in view (the curves run on beyond them)
      var seen = state.pos.list.map(function (p) { return p.slice(0, 2); });
      answer.dyads.forEach(function (d) { seen.push(d.centre, d.circle); });
      fitView(state.pos.view, seen);
      Q.status.textContent = answer.needs || answer.message;
      showSolutions(answer); drawPositions();
    }).catch(function (err) {
      done(); Q.run.disabled = false;
      exposed.lastPositions = {request: body, answer: null, error: err.message, pending: false};
      failed(Q.status, err);
    });
  }
  function showSolutions(answer) {
    clear(Q.dyads); clear(Q.list);
    answer.dyads.forEach(function (d) {
      Q.dyads.appendChild(Studio.el("li", {}, "crank: centre point (" + fmt(d.centre[0]) + ", " + fmt(d.centre[1]) + "), circle point ("
        + fmt(d.circle[0]) + ", " + fmt(d.circle[1]) + "), length " + fmt(d.radius)));
    });
    answer.solutions.forEach(function (s, k) {
      var L = s.lengths;
      Q.list.appendChild(Studio.el("li", {class: "synthesis-fit" + (k === state.pos.shown ? " shown" : ""), "data-rank": k + 1},
        Studio.el("div", {class: "synthesis-fit-head"}, Studio.el("span", {class: s.usable ? "ok" : "error"}, s.usable ? "usable" : "rejected"),
          " " + Object.keys(L).map(function (n) { return n + " " + fmt(L[n]); }).join(", ")),
        Studio.el("div", {}, s.grashof + "; smallest transmission angle " + fmt(s.min_transmission_deg, 3) + "°"),
        s.defects.length ? Studio.el("div", {class: "error"}, s.defects.join("; ")) : null,
        s.warnings.length ? Studio.el("div", {class: "synthesis-hint"}, s.warnings.join("; ")) : null,
        Studio.el("div", {class: "synthesis-controls"},
          Studio.el("button", {onclick: function () { state.pos.shown = k; showSolutions(answer); drawPositions(); }}, "Show"),
          Studio.el("button", {class: "open", onclick: function () { Studio.openInEditor(s.mechanism, s.name); }}, "Open in editor"))));
    });
  }

  document.addEventListener("DOMContentLoaded", function () {
    var root = document.getElementById("panel-synthesis");
    if (!root) return;
    buildPath(root);
    buildPositions(root);
    var prepared = false;
    window.addEventListener("domes:shown", function (e) {
      if (e.detail !== "synthesis" || prepared) return;
      prepared = true;        // the atlas is loaded (or the quick one built) in the server's worker meanwhile
      Studio.api("/api/synthesis/prepare", {closed: true, atlas: "auto"}).catch(function () { prepared = false; });
    });
  });
})();
