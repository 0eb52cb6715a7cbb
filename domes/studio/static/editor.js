// DOMES Studio, the mechanism editor: a linkage drawn to scale, its joints, pivots and coupler points dragged
// with the pointer, re-solved over its input's sweep by /api/mechanism/solve on every move (one request in
// flight, the latest position wins), played, switched between assembly modes, opened and saved.
// window.studioEditor exposes the state (the last solve's numbers) and the drag timings.
"use strict";

(function () {
  var W = 880, H = 560, PAD = 36, HIT = 9;
  var COLOURS = ["#c1121f", "#2a9d8f", "#e76f51", "#6a4c93", "#1982c4"];
  // A new four-bar: a crank-rocker (crank 1.44, coupler 2.6, rocker 2.2, frame 3) with a point on its coupler.
  var NEW_FOUR_BAR = {
    name: "new four-bar", angle_unit: "deg", ground: "frame", links: ["frame", "crank", "coupler", "rocker"],
    joints: [{name: "A", type: "R", links: ["frame", "crank"], at: [0, 0]},
             {name: "B", type: "R", links: ["crank", "coupler"], at: [0.8, 1.2]},
             {name: "C", type: "R", links: ["coupler", "rocker"], at: [3.2, 2.2]},
             {name: "D", type: "R", links: ["rocker", "frame"], at: [3, 0]}],
    inputs: [{joint: "A", speed: 60}], points: [{name: "P", link: "coupler", at: [2.4, 3.4]}]
  };

  var S = {
    mechanism: null,   // the mechanism file's JSON being edited
    name: null,        // its file name in the data folder, if any
    solved: null,      // the last good answer of /api/mechanism/solve (arrays decoded)
    good: null,        // the mechanism that answer is for
    failed: null,      // the error of the last solve (null when it solved)
    step: 0, playing: false, timer: null, direction: 1,
    view: null,        // {k, x0, y0}: model -> screen
    inflight: false, pending: null, drag: null,
    spatial: null,     // the spatial view's state (azimuth, elevation, step)
    trace: []          // the joints and points whose curves are drawn
  };
  var timings = [], phases = [];
  var ui = {};

  // -- numbers -----------------------------------------------------------------------------------------

  function unpack(text) {
    var bytes = atob(text), n = bytes.length, buf = new ArrayBuffer(n), u8 = new Uint8Array(buf);
    for (var i = 0; i < n; i++) u8[i] = bytes.charCodeAt(i);
    return new Float64Array(buf);
  }

  function decode(answer) {
    var positions = {};
    Object.keys(answer.positions).forEach(function (name) { positions[name] = unpack(answer.positions[name]); });
    answer.positions = positions;
    answer.curves.forEach(function (c) { c.points = positions[c.point]; });
    answer.inputs = unpack(answer.inputs);
    answer.steps = answer.inputs.length;
    return answer;
  }

  function at(name, k) {
    if (k === null) return S.solved.drawn[name];
    var a = S.solved.positions[name];
    return a ? [a[2 * k], a[2 * k + 1]] : null;
  }

  function toScreen(p) { return [PAD + (p[0] - S.view.x0) * S.view.k, H - PAD - (p[1] - S.view.y0) * S.view.k]; }
  function toModel(sx, sy) { return [S.view.x0 + (sx - PAD) / S.view.k, S.view.y0 + (H - PAD - sy) / S.view.k]; }
  function fmt(x) { return Math.abs(x) >= 1e5 || (Math.abs(x) < 1e-3 && x !== 0) ? x.toExponential(3) : (+x.toFixed(4)).toString(); }

  function fit() {
    var lo = [Infinity, Infinity], hi = [-Infinity, -Infinity];
    function take(x, y) {
      if (!isFinite(x) || !isFinite(y)) return;
      lo = [Math.min(lo[0], x), Math.min(lo[1], y)]; hi = [Math.max(hi[0], x), Math.max(hi[1], y)];
    }
    Object.keys(S.solved.positions).forEach(function (name) {
      var a = S.solved.positions[name];
      for (var i = 0; i < a.length; i += 2) take(a[i], a[i + 1]);
    });
    Object.keys(S.solved.drawn).forEach(function (name) { take(S.solved.drawn[name][0], S.solved.drawn[name][1]); });
    var span = Math.max(hi[0] - lo[0], hi[1] - lo[1], 1e-9 * S.solved.size), margin = 0.08 * span;
    lo = [lo[0] - margin, lo[1] - margin]; hi = [hi[0] + margin, hi[1] + margin];
    var k = Math.min((W - 2 * PAD) / (hi[0] - lo[0]), (H - 2 * PAD) / (hi[1] - lo[1]));
    S.view = {k: k, x0: lo[0] - ((W - 2 * PAD) / k - (hi[0] - lo[0])) / 2, y0: lo[1] - ((H - 2 * PAD) / k - (hi[1] - lo[1])) / 2};
  }

  // -- drawing -----------------------------------------------------------------------------------------

  function links() {
    var m = S.mechanism, out = {};
    m.links.forEach(function (l) { out[typeof l === "string" ? l : l.name] = []; });
    (m.joints || []).forEach(function (j) {
      if (j.type !== "R" && j.type !== "P") return;
      j.links.forEach(function (l, i) {
        if (!out[l]) return;
        var guide = j.type === "P" && i === 0 && S.solved.guides[j.name];
        out[l].push(guide ? S.solved.guides[j.name][0] : j.name);
      });
    });
    (m.points || []).forEach(function (p) { if (out[p.link]) out[p.link].push(p.name); });
    return out;
  }

  function outline(pts) {
    var unique = [];
    pts.forEach(function (p) {
      if (p && isFinite(p[0]) && unique.every(function (u) { return Math.hypot(u[0] - p[0], u[1] - p[1]) > 0.5; })) unique.push(p);
    });
    if (unique.length > 2) {
      var cx = 0, cy = 0;
      unique.forEach(function (p) { cx += p[0] / unique.length; cy += p[1] / unique.length; });
      unique.sort(function (a, b) { return Math.atan2(a[1] - cy, a[0] - cx) - Math.atan2(b[1] - cy, b[0] - cx); });
    }
    return unique;
  }

  function draw() {
    var svg = ui.svg, m = S.mechanism, k = S.step;
    while (svg.firstChild) svg.removeChild(svg.firstChild);
    if (!S.solved) return;
    var g = Studio.svg;
    svg.appendChild(g("defs", {}, g("pattern", {id: "editor-hatch", width: 6, height: 6, patternUnits: "userSpaceOnUse",
      patternTransform: "rotate(45)"}, g("line", {x1: 0, y1: 0, x2: 0, y2: 6, stroke: "#5b6677", "stroke-width": 1.2}))));
    var layer = {curves: g("g", {class: "curves"}), links: g("g", {class: "links"}), marks: g("g", {class: "marks"}),
                 joints: g("g", {class: "joints"})};
    // coupler curves
    S.solved.curves.forEach(function (c, i) {
      var pts = [], model = [];
      for (var n = 0; n < c.points.length; n += 2) {
        model.push([c.points[n], c.points[n + 1]]);
        if (isFinite(c.points[n])) pts.push(toScreen([c.points[n], c.points[n + 1]]).map(function (v) { return v.toFixed(2); }).join(","));
      }
      if (c.closed && pts.length) pts.push(pts[0]);
      var line = g("polyline", {class: "coupler-curve" + (c.closed ? " closed" : ""), "data-point": c.point, points: pts.join(" "),
                   stroke: COLOURS[i % COLOURS.length], fill: "none"});
      line.dataset.points = JSON.stringify(model);
      layer.curves.appendChild(line);
    });
    // links
    var groups = links(), ground = m.ground;
    Object.keys(groups).forEach(function (l) {
      var pts = outline(groups[l].map(function (n) { return at(n, k); }).map(function (p) { return p && toScreen(p); }));
      if (l === ground || pts.length < 2) return;
      var d = pts.map(function (p) { return p[0].toFixed(2) + "," + p[1].toFixed(2); }).join(" ");
      layer.links.appendChild(g(pts.length > 2 ? "polygon" : "polyline", {class: "link", "data-link": l, points: d}));
    });
    // the ground: pivots hatched, slide rails
    (m.joints || []).forEach(function (j) {
      if (j.type === "P" && S.solved.guides[j.name]) {
        var pair = S.solved.guides[j.name], o = at(pair[0], k), a = at(pair[1], k), p = at(j.name, k);
        if (!o || !a || !p) return;
        var so = toScreen(o), sa = toScreen(a), sp = toScreen(p), ux = sa[0] - so[0], uy = sa[1] - so[1], len = Math.hypot(ux, uy) || 1;
        ux /= len; uy /= len;
        var t = (sp[0] - so[0]) * ux + (sp[1] - so[1]) * uy, lo = Math.min(0, t) - 30, hi = Math.max(0, t) + 30;
        layer.links.appendChild(g("line", {class: j.links[0] === ground ? "rail ground" : "rail", x1: so[0] + lo * ux,
          y1: so[1] + lo * uy, x2: so[0] + hi * ux, y2: so[1] + hi * uy}));
        if (j.links[0] === ground) layer.links.appendChild(g("rect", {class: "hatch", x: so[0] + lo * ux, y: so[1] + lo * uy,
          width: hi - lo, height: 7, transform: "rotate(" + (Math.atan2(uy, ux) * 180 / Math.PI) + " " + (so[0] + lo * ux) + " " + (so[1] + lo * uy) + ")"}));
        layer.joints.appendChild(g("rect", {class: "slider" + (k === null ? " handle" : ""), "data-name": j.name,
          x: sp[0] - 11, y: sp[1] - 7, width: 22, height: 14,
          transform: "rotate(" + (Math.atan2(uy, ux) * 180 / Math.PI) + " " + sp[0] + " " + sp[1] + ")"}));
      } else if (j.type === "R" && j.links.indexOf(ground) >= 0) {
        var q = at(j.name, k);
        if (!q) return;
        var s = toScreen(q);
        layer.links.appendChild(g("path", {class: "pivot", d: "M" + s[0] + "," + s[1] + " l-10,16 h20 z"}));
        layer.links.appendChild(g("rect", {class: "hatch", x: s[0] - 14, y: s[1] + 16, width: 28, height: 7}));
      }
    });
    // dead points and branch points
    S.solved.dead_points.forEach(function (d) {
      Object.keys(d.at || {}).forEach(function (name) {
        if (!S.solved.curves.some(function (c) { return c.point === name; })) return;
        var s = toScreen(d.at[name]), title = g("title");
        title.textContent = d.kind + " at input " + fmt(d.input) + ": " + d.message;
        var mark = d.kind === "bifurcation" ?
          g("path", {class: "branch-point", d: "M" + s[0] + "," + (s[1] - 7) + " l7,7 l-7,7 l-7,-7 z"}, title) :
          g("path", {class: "dead-point " + d.kind, d: "M" + (s[0] - 6) + "," + (s[1] - 6) + " l12,12 m0,-12 l-12,12"}, title);
        mark.dataset.input = d.input;
        layer.marks.appendChild(mark);
      });
    });
    // joints and coupler points (draggable at the drawn pose)
    var handles = k === null;
    (m.joints || []).forEach(function (j) {
      if (j.type !== "R" && j.type !== "P") return;
      var q = at(j.name, k);
      if (!q) return;
      var s = toScreen(q);
      if (j.type === "R") layer.joints.appendChild(g("circle", {class: "joint" + (handles ? " handle" : ""), "data-name": j.name, cx: s[0], cy: s[1], r: 5}));
      var label = g("text", {x: s[0] + 8, y: s[1] - 8, class: "label"});
      label.textContent = j.name;
      layer.joints.appendChild(label);
    });
    (m.points || []).forEach(function (p) {
      var q = at(p.name, k);
      if (!q) return;
      var s = toScreen(q);
      layer.joints.appendChild(g("circle", {class: "point" + (handles ? " handle" : ""), "data-name": p.name, cx: s[0], cy: s[1], r: 4}));
      var label = g("text", {x: s[0] + 7, y: s[1] - 7, class: "label point-label"});
      label.textContent = p.name;
      layer.joints.appendChild(label);
    });
    if (S.drag && S.failed) {
      var ds = toScreen(S.drag.where);
      layer.joints.appendChild(g("circle", {class: "refused", cx: ds[0], cy: ds[1], r: 7}));
    }
    svg.appendChild(layer.curves); svg.appendChild(layer.links); svg.appendChild(layer.marks); svg.appendChild(layer.joints);
    ui.where.textContent = k === null ? "drawn pose, input " + S.solved.input.joint + " = " + fmt(S.solved.input.drawn) + " " + unit() :
      "input " + S.solved.input.joint + " = " + fmt(S.solved.inputs[k]) + " " + unit() + " (step " + (k + 1) + " of " + S.solved.steps + ")";
  }

  function unit() { return S.solved.input.unit === "deg" ? "°" : ""; }

  function summary() {
    var a = S.solved, box = ui.info;
    while (box.firstChild) box.removeChild(box.firstChild);
    var el = Studio.el;
    var range = a.full_turn ? "turns fully" : "moves from " + fmt(a.reachable[0]) + " to " + fmt(a.reachable[1]) + " " + unit();
    box.appendChild(el("p", {class: "turning"}, el("strong", {}, a.name), ": input " + a.input.joint + " " + range +
                       " (" + a.status + ", " + a.steps + " steps, largest residual " + a.max_residual.toExponential(1) + ")"));
    if (a.dead_points.length) {
      box.appendChild(el("ul", {class: "dead-points"}, a.dead_points.map(function (d) {
        return el("li", {class: d.kind}, el("strong", {}, d.kind + " at " + fmt(d.input) + " " + unit()), " ", d.message);
      })));
    } else {
      box.appendChild(el("p", {class: "muted"}, "no dead points or branch points on the sweep"));
    }
    box.appendChild(traceBox());
    var sel = ui.mode, modes = a.modes;
    while (sel.firstChild) sel.removeChild(sel.firstChild);
    (modes.available.length ? modes.available : [modes.current || "—"]).forEach(function (key) {
      sel.appendChild(el("option", {value: key, selected: key === modes.current}, key + (key === modes.current ? " (drawn)" : "")));
    });
    sel.disabled = modes.available.length < 2;
    sel.title = modes.dyads.map(function (d, i) { return "position " + (i + 1) + ": " + d.group + " (" + d.joints.join(", ") + ")"; }).join("\n") ||
      "no dyad with two assembly modes";
    ui.slider.max = Math.max(a.steps - 1, 0);
  }

  function status(text, bad) {
    ui.status.textContent = text;
    ui.status.className = "status" + (bad ? " error" : "");
  }

  // -- solving -----------------------------------------------------------------------------------------

  // Solve `mechanism` (the latest wins while one request is in flight). `since`: when the change was asked for.
  function request(mechanism, since, options) {
    var job = {mechanism: mechanism, since: since, options: options || {}};
    if (S.inflight) { S.pending = job; return Promise.resolve(); }
    return send(job);
  }

  function send(job) {
    S.inflight = true;
    var body = {mechanism: job.mechanism, encoding: "f64", trace: S.trace};
    if (job.options.mode) body.mode = job.options.mode;
    var sent = performance.now();
    return Studio.api("/api/mechanism/solve", body).then(function (answer) {
      if (answer.space === "spatial") { showSpatial(answer, job.mechanism); return; }
      var answered = performance.now();
      S.solved = decode(answer);
      S.mechanism = answer.mechanism || job.mechanism;
      S.good = S.mechanism;
      S.failed = null;
      if (!S.view || job.options.fit) fit();
      if (S.step !== null && S.step >= S.solved.steps) S.step = S.solved.steps - 1;
      spatialShown(false);
      summary();
      draw();
      status(job.options.fit ? "opened" : "re-solved", false);
      if (job.since !== undefined) {
        var done = performance.now();
        timings.push(done - job.since);
        phases.push({waited: sent - job.since, answered: answered - sent, drawn: done - answered});
      }
    }).catch(function (e) {
      S.failed = e.message;
      status(e.message + (S.good ? " (the drawing shows the last position that solved)" : ""), true);
      if (S.solved) draw();
      if (job.since !== undefined) timings.push(performance.now() - job.since);
    }).then(function () {
      S.inflight = false;
      var next = S.pending;
      S.pending = null;
      if (next) return send(next);
    });
  }

  function open(mechanism, name) {
    pause();
    if (S.spatial && S.spatial.timer) playSpatial();
    S.spatial = null;
    S.name = name || null;
    S.view = null; S.solved = null; S.good = null; S.step = null;
    ui.name.value = name || ("mechanisms/" + String(mechanism && mechanism.name || "mechanism").toLowerCase().replace(/[^a-z0-9]+/g, "-").replace(/^-|-$/g, "") + ".json");
    S.mechanism = mechanism;
    S.trace = defaultTrace(mechanism);
    return request(mechanism, undefined, {fit: true});
  }

  // The coupler points; without any, the joints that move (not those on the ground).
  function defaultTrace(m) {
    if (!m || m.space === "spatial") return undefined;
    if ((m.points || []).length) return m.points.map(function (p) { return p.name; });
    return (m.joints || []).filter(function (j) {
      return (j.type === "R" || j.type === "P") && j.links.indexOf(m.ground) < 0;
    }).map(function (j) { return j.name; });
  }

  function traceBox() {
    var el = Studio.el, m = S.mechanism, names = [];
    (m.joints || []).concat(m.points || []).forEach(function (x) {
      if ((!x.type || x.type === "R" || x.type === "P") && names.indexOf(x.name) < 0) names.push(x.name);
    });
    return el("p", {class: "trace"}, "trace: ", names.map(function (n) {
      return el("label", {}, el("input", {type: "checkbox", value: n, checked: S.trace.indexOf(n) >= 0, onchange: function (e) {
        S.trace = e.target.checked ? S.trace.concat([n]) : S.trace.filter(function (t) { return t !== n; });
        request(S.good, undefined, {});
      }}), n);
    }));
  }

  // -- dragging ----------------------------------------------------------------------------------------

  function copy(x) { return JSON.parse(JSON.stringify(x)); }

  // `base` with the joint or coupler point `name` moved to `where`. The joints drawn at the same place as a joint
  // move with it (a compound hinge, a pin on its slider; a slide's origin keeps its place on the line).
  function moved(base, name, where) {
    var m = copy(base), tol = 1e-9 * S.solved.size;
    var point = (m.points || []).filter(function (p) { return p.name === name; })[0];
    if (point) { point.at = where.slice(); return m; }
    var from = (m.joints || []).filter(function (j) { return j.name === name; })[0].at.slice();
    var dx = where[0] - from[0], dy = where[1] - from[1];
    (m.joints || []).forEach(function (j) {
      if ((j.type === "R" || j.type === "P") && Math.hypot(j.at[0] - from[0], j.at[1] - from[1]) <= tol) {
        j.at = [j.at[0] + dx, j.at[1] + dy];
        if (j.origin) j.origin = [j.origin[0] + dx, j.origin[1] + dy];
      }
    });
    return m;
  }

  function pointer(e) {
    var pt = ui.svg.createSVGPoint();
    pt.x = e.clientX; pt.y = e.clientY;
    var s = pt.matrixTransform(ui.svg.getScreenCTM().inverse());
    return toModel(s.x, s.y);
  }

  function down(e) {
    var target = e.target.closest && e.target.closest(".handle");
    if (!target || !S.solved) return;
    e.preventDefault();
    pause();
    var name = target.getAttribute("data-name"), start = S.solved.drawn[name];
    var grab = pointer(e);
    S.drag = {name: name, offset: [start[0] - grab[0], start[1] - grab[1]], base: S.good, where: start, id: e.pointerId};
    ui.svg.setPointerCapture(e.pointerId);
    ui.svg.classList.add("dragging");
  }

  function move(e) {
    if (!S.drag) return;
    var now = performance.now(), p = pointer(e);
    S.drag.where = snap([p[0] + S.drag.offset[0], p[1] + S.drag.offset[1]]);
    request(moved(S.drag.base, S.drag.name, S.drag.where), now);
  }

  // A position within a few pixels of another joint or point is taken as that one's (exactly).
  function snap(where) {
    var drawn = S.solved.drawn, from = drawn[S.drag.name], s = toScreen(where), best = null, dist = HIT;
    Object.keys(drawn).forEach(function (name) {
      var q = drawn[name];
      if (Math.hypot(q[0] - from[0], q[1] - from[1]) <= 1e-9 * S.solved.size || name.indexOf("/") >= 0) return;
      var d = Math.hypot(toScreen(q)[0] - s[0], toScreen(q)[1] - s[1]);
      if (d < dist) { dist = d; best = q; }
    });
    return best ? best.slice() : where;
  }

  function up() {
    if (!S.drag) return;
    var drag = S.drag;
    S.drag = null;
    ui.svg.classList.remove("dragging");
    var settle = function () {
      if (S.inflight || S.pending) { setTimeout(settle, 20); return; }
      if (S.failed && S.good) {
        status(S.failed + " — back to the last position that solved", true);
        S.mechanism = S.good;
        S.failed = null;
      }
      draw();
    };
    settle();
    return drag;
  }

  // -- playing -----------------------------------------------------------------------------------------

  function frame(k) {
    if (!S.solved) return;
    S.step = Math.max(0, Math.min(S.solved.steps - 1, k));
    ui.slider.value = S.step;
    draw();
  }

  function play() {
    if (!S.solved || S.playing) return;
    S.playing = true;
    ui.play.textContent = "pause";
    if (S.step === null) S.step = 0;
    var last = performance.now();
    function tick(now) {
      if (!S.playing) return;
      var n = S.solved.steps, advance = Math.max(1, Math.round((now - last) / (4000 / n)));
      if (now - last >= 4000 / n) {
        last = now;
        var k = S.step + S.direction * advance;
        if (S.solved.full_turn) k = ((k % n) + n) % n;
        else if (k >= n - 1 || k <= 0) { k = Math.max(0, Math.min(n - 1, k)); S.direction = -S.direction; }
        frame(k);
      }
      S.timer = requestAnimationFrame(tick);
    }
    S.timer = requestAnimationFrame(tick);
  }

  function pause() {
    S.playing = false;
    if (S.timer) cancelAnimationFrame(S.timer);
    S.timer = null;
    if (ui.play) ui.play.textContent = "play";
  }

  function drawnPose() { pause(); S.step = null; draw(); }

  // -- spatial mechanisms ------------------------------------------------------------------------------

  function spatialShown(on) {
    ui.planar.hidden = on;
    ui.spatialBox.hidden = !on;
  }

  function showSpatial(answer, mechanism) {
    S.mechanism = mechanism;
    S.solved = null;
    var was = S.spatial || {};
    S.spatial = {azimuth: answer.azimuth, elevation: answer.elevation, step: answer.step, steps: answer.steps,
                 busy: was.busy || false, again: was.again || false, timer: was.timer || null};
    spatialShown(true);
    var doc = new DOMParser().parseFromString(answer.svg, "image/svg+xml").documentElement;
    while (ui.spatialView.firstChild) ui.spatialView.removeChild(ui.spatialView.firstChild);
    ui.spatialView.appendChild(document.importNode(doc, true));
    ui.spatialStep.max = answer.steps - 1;
    ui.spatialStep.value = answer.step;
    ui.azimuth.value = answer.azimuth;
    ui.elevation.value = answer.elevation;
    ui.spatialInfo.textContent = answer.name + ": " + answer.message;
    status("a spatial mechanism: its turning view (turn with the sliders; the page of domes draw is downloadable)", false);
  }

  function turnSpatial() {
    var sp = S.spatial;
    if (!sp) return;
    if (sp.busy) { sp.again = true; return; }
    sp.busy = true;
    var mechanism = S.mechanism;
    Studio.api("/api/mechanism/solve", {mechanism: mechanism, azimuth: +ui.azimuth.value, elevation: +ui.elevation.value,
                                        step: +ui.spatialStep.value})
      .then(function (answer) { if (S.mechanism === mechanism && S.spatial) showSpatial(answer, mechanism); })
      .catch(function (e) { status(e.message, true); })
      .then(function () {
        var again = S.spatial && S.spatial.again;
        if (S.spatial) { S.spatial.busy = false; S.spatial.again = false; }
        if (again) turnSpatial();
      });
  }

  // The page of `domes draw --format html` (it turns and plays by its own script: saved, opened from the disk).
  function playSpatial() {
    if (S.spatial && S.spatial.timer) { clearInterval(S.spatial.timer); S.spatial.timer = null; ui.spatialPlay.textContent = "play"; return; }
    if (!S.spatial) return;
    ui.spatialPlay.textContent = "pause";
    S.spatial.timer = setInterval(function () {
      if (!S.spatial || ui.spatialBox.hidden) return;
      if (S.spatial.busy) return;
      ui.spatialStep.value = (+ui.spatialStep.value + 1) % (+ui.spatialStep.max + 1);
      turnSpatial();
    }, 80);
  }

  function downloadPage() {
    if (!S.spatial) return;
    Studio.api("/api/mechanism/solve", {mechanism: S.mechanism, azimuth: +ui.azimuth.value, elevation: +ui.elevation.value,
                                        step: +ui.spatialStep.value, page: true}).then(function (answer) {
      var a = Studio.el("a", {href: URL.createObjectURL(new Blob([answer.html], {type: "text/html"})),
                              download: (S.mechanism.name || "mechanism").replace(/[^A-Za-z0-9]+/g, "-") + ".html"});
      document.body.appendChild(a); a.click(); a.remove();
    }).catch(function (e) { status(e.message, true); });
  }

  // -- files -------------------------------------------------------------------------------------------

  var examples = [];

  function listFiles() {
    var sel = ui.open, el = Studio.el;
    return Promise.all([Studio.api("/api/files").catch(function () { return {files: []}; }),
                        Studio.api("/api/mechanism/examples").catch(function () { return {examples: []}; })])
      .then(function (both) {
        examples = both[1].examples;
        while (sel.firstChild) sel.removeChild(sel.firstChild);
        sel.appendChild(el("option", {value: ""}, "open…"));
        sel.appendChild(el("option", {value: "new"}, "a new four-bar"));
        sel.appendChild(el("optgroup", {label: "data folder"}, both[0].files.filter(function (f) {
          return f !== "casebase.db"; }).map(function (f) { return el("option", {value: "file:" + f}, f); })));
        sel.appendChild(el("optgroup", {label: "examples"}, examples.map(function (x, i) {
          return el("option", {value: "example:" + i, title: x.source}, x.name); })));
      });
  }

  function chosen() {
    var v = ui.open.value;
    ui.open.value = "";
    if (v === "new") return open(copy(NEW_FOUR_BAR), null);
    if (v.indexOf("example:") === 0) { var x = examples[+v.slice(8)]; return open(copy(x.mechanism), null); }
    if (v.indexOf("file:") === 0) {
      var name = v.slice(5);
      return Studio.api("/api/open", {name: name}).then(function (f) { return open(f.content, name); })
        .catch(function (e) { status(e.message, true); });
    }
  }

  function saveAs() {
    if (!S.mechanism) return;
    var name = ui.name.value.trim();
    Studio.api("/api/mechanism/save", {name: name, mechanism: S.good || S.mechanism}).then(function (r) {
      S.name = r.name;
      status("saved " + r.path, false);
      Studio.toast("saved " + r.name, "info");
      listFiles();
    }).catch(function (e) { status(e.message, true); });
  }

  // -- the panel ---------------------------------------------------------------------------------------

  function build() {
    var section = document.getElementById("panel-editor"), el = Studio.el;
    ui.open = el("select", {class: "open", "aria-label": "open a mechanism", onchange: chosen});
    ui.name = el("input", {class: "file-name", type: "text", size: 32, "aria-label": "file name to save as"});
    ui.play = el("button", {type: "button", class: "play", onclick: function () { S.playing ? pause() : play(); }}, "play");
    ui.slider = el("input", {type: "range", class: "input-slider", min: 0, max: 0, value: 0, "aria-label": "input",
                             oninput: function () { pause(); frame(+ui.slider.value); }});
    ui.mode = el("select", {class: "mode", "aria-label": "assembly mode", onchange: function () {
      pause(); request(S.good, undefined, {mode: ui.mode.value, fit: true}); }});
    ui.status = el("p", {class: "status", role: "status"});
    ui.where = el("span", {class: "where"});
    ui.svg = Studio.svg("svg", {class: "editor-canvas", viewBox: "0 0 " + W + " " + H, width: W, height: H});
    ui.info = el("div", {class: "editor-info"});
    ui.planar = el("div", {class: "editor-planar"},
                   el("div", {class: "editor-controls"}, ui.play, ui.slider,
                      el("button", {type: "button", class: "drawn", onclick: drawnPose}, "drawn pose"),
                      el("button", {type: "button", class: "fit", onclick: function () { if (S.solved) { fit(); draw(); } }}, "fit"),
                      el("label", {}, "assembly mode ", ui.mode), ui.where),
                   el("div", {class: "editor-body"}, ui.svg, ui.info));
    ui.spatialView = el("div", {class: "spatial-view"});
    ui.spatialInfo = el("p", {class: "spatial-info"});
    ui.azimuth = el("input", {type: "range", min: -180, max: 180, value: -35, class: "azimuth", oninput: turnSpatial});
    ui.elevation = el("input", {type: "range", min: -89, max: 89, value: 25, class: "elevation", oninput: turnSpatial});
    ui.spatialStep = el("input", {type: "range", min: 0, max: 0, value: 0, class: "spatial-step", oninput: turnSpatial});
    ui.spatialPlay = el("button", {type: "button", class: "spatial-play", onclick: playSpatial}, "play");
    ui.spatialBox = el("div", {class: "editor-spatial", hidden: true}, ui.spatialInfo,
                       el("div", {class: "editor-controls"}, ui.spatialPlay, el("label", {}, "azimuth ", ui.azimuth),
                          el("label", {}, "elevation ", ui.elevation), el("label", {}, "step ", ui.spatialStep),
                          el("button", {type: "button", onclick: downloadPage}, "download the turning page")),
                       ui.spatialView);
    section.appendChild(el("div", {class: "editor-toolbar"}, ui.open, ui.name,
                           el("button", {type: "button", class: "save", onclick: saveAs}, "save as"), ui.status));
    section.appendChild(ui.planar);
    section.appendChild(ui.spatialBox);
    ui.svg.addEventListener("pointerdown", down);
    ui.svg.addEventListener("pointermove", move);
    ui.svg.addEventListener("pointerup", up);
    ui.svg.addEventListener("pointercancel", up);
    status("open a mechanism, or start from a new four-bar; drag joints, pivots and coupler points", false);
    listFiles();
  }

  document.addEventListener("DOMContentLoaded", build);
  window.addEventListener("domes:open", function (e) { open(e.detail.mechanism, e.detail.name); });
  window.addEventListener("domes:shown", function (e) {
    if (e.detail !== "editor" || S.mechanism || !ui.open) return;
    listFiles();
    open(copy(NEW_FOUR_BAR), null);     // something to drag at once; "open…" lists the files and examples
  });

  window.studioEditor = {
    get state() { return S; },
    timings: timings,   // ms from a pointer move to the linkage redrawn, per drag step
    phases: phases,     // the same steps: waiting for the request before, the request, decoding and drawing
    open: open, play: play, pause: pause, frame: frame, drawnPose: drawnPose,
    toScreen: function (p) { return toScreen(p); },
    idle: function () { return !S.inflight && !S.pending; }
  };
})();
