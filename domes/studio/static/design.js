// DOMES Studio, the design panel: the design dialogue of `domes design` as a conversation. The expert's lines,
// the question asked (its default filled in, '?' shows its help), a rejected answer's reason under the box, the
// progress of a long stage with Cancel, the funnel of candidates with the atlas of their sketches, and at the
// end the session's report. The server runs the dialogue (/api/design/...); this script only shows it.
"use strict";

(function () {
  var el = Studio.el;
  var POLL = 300;          // ms between polls while the expert works
  var state = {session: null, next: 0, timer: null, funnelKey: null, status: null};
  var ui = {};
  // The embedded page's own `body` rule does not reach into a shadow root: its wrapper takes it.
  var EMBEDDED = ":host { display: block; } .embedded-page { font-family: sans-serif; color: #1d3557; " +
    "background: #fafafa; padding: .8em; } .embedded-page h1 { font-size: 1.3em; }";

  function build(section) {
    ui.section = section;
    ui.replay = el("select", {class: "design-replay", "aria-label": "recorded session or answers file"});
    ui.keep = el("input", {type: "checkbox", class: "design-keep"});
    ui.start = el("button", {type: "button", class: "design-start", onclick: function () { start(null); }}, "New problem");
    ui.replayButton = el("button", {type: "button", class: "design-replay-start", onclick: function () {
      if (ui.replay.value) start(ui.replay.value);
    }}, "Replay");
    ui.cancel = el("button", {type: "button", class: "design-cancel", hidden: true, onclick: cancel}, "Cancel");
    ui.status = el("span", {class: "design-status"});
    var bar = el("div", {class: "design-bar"}, ui.start, ui.replay, ui.replayButton,
      el("label", {class: "design-keep-label", title: "unchecked: a dry run on a scratch copy of the case base"},
        ui.keep, " keep the result in the case base"), ui.cancel, ui.status);

    ui.lines = el("ol", {class: "design-lines", "aria-live": "polite"});
    ui.progressText = el("span", {class: "design-progress-text"});
    ui.progress = el("div", {class: "design-progress", hidden: true}, el("span", {class: "design-spinner"}),
      ui.progressText, el("button", {type: "button", class: "design-cancel-stage", onclick: cancel}, "Cancel"));
    ui.prompt = el("label", {class: "design-prompt", for: "design-answer"});
    ui.input = el("input", {type: "text", id: "design-answer", class: "design-answer", autocomplete: "off",
      spellcheck: "false"});
    ui.helpButton = el("button", {type: "button", class: "design-help-button", title: "help on this question",
      "aria-label": "help on this question", onclick: toggleHelp}, "?");
    ui.rejected = el("p", {class: "design-rejected error", hidden: true});
    ui.help = el("div", {class: "design-help", hidden: true});
    ui.ask = el("form", {class: "design-ask", hidden: true, onsubmit: submit}, ui.prompt,
      el("div", {class: "design-answer-row"}, ui.input, el("button", {type: "submit", class: "design-send"}, "Answer"),
        ui.helpButton), ui.rejected, ui.help);
    ui.talk = el("div", {class: "design-talk"}, ui.lines, ui.progress, ui.ask);

    ui.funnel = el("div", {class: "design-funnel"}, el("p", {class: "design-muted"}, "No design run yet."));
    ui.atlas = el("div", {class: "design-atlas"});
    ui.atlasBox = el("details", {class: "design-atlas-box", hidden: true}, el("summary", {}, "Candidates, sketched"),
      ui.atlas);
    ui.side = el("aside", {class: "design-side"}, el("h3", {}, "Funnel of candidates"), ui.funnel, ui.atlasBox);

    ui.reportLink = el("a", {class: "design-report-link", target: "_blank", rel: "noopener"}, "open in a new tab");
    ui.reportBody = el("div", {class: "design-report-body"});
    ui.report = el("div", {class: "design-report", hidden: true},
      el("h3", {}, "Report ", ui.reportLink), ui.reportBody);
    section.appendChild(el("div", {class: "design-panel"}, bar,
      el("div", {class: "design-main"}, ui.talk, ui.side), ui.report));
    ui.lines.appendChild(el("li", {class: "design-muted"},
      "Start a new problem, or replay a recorded session or an answers file; the expert asks its questions here, " +
      "as `domes design` does on the terminal."));
    loadRecorded();
  }

  function loadRecorded() {
    Studio.api("/api/design/sessions").then(function (data) {
      var kept = ui.replay.value;
      ui.replay.textContent = "";
      ui.replay.appendChild(el("option", {value: ""}, "replay ..."));
      var groups = {transcript: "recorded sessions", interrupted: "interrupted sessions", answers: "answers files",
                    case: "shipped cases"};
      Object.keys(groups).forEach(function (kind) {
        var items = data.sessions.filter(function (s) { return s.kind === kind; });
        if (!items.length) return;
        var group = el("optgroup", {label: groups[kind]});
        items.forEach(function (s) {
          var label = s.problem + (s.date ? " (" + s.date + ")" : "") + (s.kind === "answers" ? " — " + s.name : "");
          group.appendChild(el("option", {value: s.name}, label));
        });
        ui.replay.appendChild(group);
      });
      ui.replay.value = kept;
      if (!state.session && data.live.length) attach(data.live[data.live.length - 1]);
    }).catch(function (e) { Studio.toast(e.message, "error"); });
  }

  function start(answers) {
    var body = {dry_run: !ui.keep.checked};
    if (answers) body.answers = answers;
    ui.start.disabled = ui.replayButton.disabled = true;
    Studio.api("/api/design/start", body).then(function (view) {
      clearTimeout(state.timer);
      state = {session: view.session, next: 0, timer: null, funnelKey: null, status: null};
      ui.lines.textContent = "";
      ui.funnel.textContent = "";
      ui.funnel.appendChild(el("p", {class: "design-muted"}, "No design run yet."));
      ui.atlasBox.hidden = true;
      ui.report.hidden = true;
      ui.lines.appendChild(el("li", {class: "design-muted"}, "Session " + view.session +
        (answers ? ", replaying " + answers : ", a new problem") +
        (view.dry_run ? " (dry run: the case base is not changed)" : " (the result is kept in the case base)") + "."));
      show(view);
    }).catch(function (e) {
      ui.start.disabled = ui.replayButton.disabled = false;
      Studio.toast(e.message, "error");
    });
  }

  // Show a session that is still running on the server (the page was loaded again): from its first line on.
  function attach(sid) {
    state = {session: sid, next: 0, timer: null, funnelKey: null, status: null};
    ui.lines.textContent = "";
    ui.lines.appendChild(el("li", {class: "design-muted"}, "Session " + sid + ", still running on the server."));
    poll();
  }

  function poll() {
    if (!state.session) return;
    var sid = state.session;
    Studio.api("/api/design/events?session=" + encodeURIComponent(sid) + "&since=" + state.next).then(function (view) {
      if (state.session === sid) show(view);
    }).catch(function (e) {
      Studio.toast(e.message, "error");
      state.timer = setTimeout(poll, 2000);
    });
  }

  function line(event) {
    if (event.kind === "answer") {
      return el("li", {class: "design-you"}, el("span", {class: "design-who"}, "you"),
        event.text === "" ? el("em", {}, "(the default)") : event.text);
    }
    if (event.kind === "error") return el("li", {class: "design-failed error"}, event.text);
    var text = event.text;
    var cls = /^\s*not accepted: /.test(text) ? "design-said design-not-accepted" : "design-said";
    return el("li", {class: cls}, text);
  }

  function show(view) {
    clearTimeout(state.timer);
    view.events.forEach(function (e) { if (e.kind !== "line" || e.text) ui.lines.appendChild(line(e)); });
    state.next = view.next;
    state.status = view.status;
    ui.section.dataset.status = view.status;
    ui.section.dataset.session = view.session;
    var live = view.status === "running" || view.status === "asking";
    ui.cancel.hidden = !live;
    ui.start.disabled = ui.replayButton.disabled = live;
    ui.status.textContent = {running: "the expert is working ...", asking: "your answer, please",
      done: "ended", failed: "stopped: " + (view.error || ""), cancelled: "cancelled"}[view.status] || view.status;
    ui.status.className = "design-status " + view.status;
    ui.progress.hidden = !(view.status === "running" && view.progress);
    ui.progressText.textContent = view.progress || "";
    ask(view.question);
    funnel(view);
    if (view.status === "done" && !state.finished) finish(view);
    if (!live) loadRecorded();
    if (view.status === "running") state.timer = setTimeout(poll, POLL);
    ui.lines.scrollTop = ui.lines.scrollHeight;
  }

  function ask(q) {
    if (!q) {
      ui.ask.hidden = true;
      delete ui.ask.dataset.question;
      return;
    }
    ui.ask.hidden = false;
    ui.ask.dataset.question = q.id;
    ui.prompt.textContent = q.prompt;
    // a rejected answer stays in the box, selected, to be corrected; otherwise the default is filled in
    if (!q.rejected) ui.input.value = q.default === null ? "" : q.default;
    ui.input.placeholder = q.default === null ? "" : "default: " + q.default;
    ui.rejected.hidden = !q.rejected;
    ui.rejected.textContent = q.rejected ? "not accepted: " + q.rejected : "";
    ui.help.textContent = q.help || "No help for this question: answer " + q.prompt;
    ui.help.hidden = true;
    ui.input.focus();
    if (q.rejected) ui.input.select();
  }

  function toggleHelp() { ui.help.hidden = !ui.help.hidden; }

  function submit(event) {
    event.preventDefault();
    if (!state.session || ui.ask.hidden) return;
    var text = ui.input.value;
    ui.ask.hidden = true;
    Studio.api("/api/design/answer", {session: state.session, text: text}).then(function () {
      poll();
    }).catch(function (e) {
      ui.ask.hidden = false;
      Studio.toast(e.message, "error");
    });
  }

  function cancel() {
    if (!state.session) return;
    Studio.api("/api/design/cancel", {session: state.session}).then(function () { poll(); })
      .catch(function (e) { Studio.toast(e.message, "error"); });
  }

  function reportUrl(name) {
    return "/api/design/report/" + encodeURIComponent(state.session) + "/" + name;
  }

  // The funnel: each level's count as a bar, what removed the others, then every rejected candidate with its
  // criterion and reason; the atlas (the server's drawings of the candidates) below.
  function funnel(view) {
    var f = view.funnel;
    if (!f) return;
    var key = JSON.stringify([f.rows, f.kept]);
    if (key === state.funnelKey) return;
    state.funnelKey = key;
    var top = Math.max.apply(null, f.rows.map(function (r) { return r.count; }).concat([1]));
    var rows = f.rows.map(function (r) {
      return el("li", {class: "design-level"},
        el("span", {class: "design-stage"}, r.stage),
        el("span", {class: "design-bar-track"}, el("span", {class: "design-bar-fill",
          style: "width:" + Math.max(1, 100 * r.count / top).toFixed(1) + "%"})),
        el("span", {class: "design-count"}, String(r.count)),
        r.removed.length ? el("span", {class: "design-removed"}, r.removed.map(function (x) {
          return x[1] + " removed by " + x[0];
        }).join("; ")) : null);
    });
    var rejected = f.rejected.map(function (r) {
      return el("li", {}, el("b", {}, "candidate " + r.candidate), ": rejected by ", el("code", {}, r.criterion),
        " (level " + r.level + ")" + (r.explanation ? ", " + r.explanation : "") + (r.reason ? ": " + r.reason : ""));
    });
    ui.funnel.textContent = "";
    ui.funnel.appendChild(el("ol", {class: "design-levels"}, rows));
    ui.funnel.appendChild(el("p", {class: "design-kept"}, f.kept.length ? "kept: candidate " + f.kept.join(", ") :
      "no candidate kept"));
    if (rejected.length) {
      ui.funnel.appendChild(el("details", {class: "design-rejections", open: rejected.length <= 12},
        el("summary", {}, rejected.length + " rejected"), el("ul", {}, rejected)));
    }
    if (f.atlas) {
      ui.atlasBox.hidden = false;
      embed(ui.atlas, reportUrl(f.atlas));
    }
  }

  function finish(view) {
    var o = view.outcome || {};
    state.finished = true;
    var said = o.relation === "same" ? "the same problem as " + o.case + ", answered from the case base" :
      (o.kept + " candidate(s) kept" + (o.feasible ? ", " + o.feasible + " feasible" : "") +
       (o.retained ? "; retained as case " + o.retained : ""));
    ui.lines.appendChild(el("li", {class: "design-end ok"}, "The session ended: " + said + "."));
    if (!o.report) return;
    ui.report.hidden = false;
    ui.reportLink.href = reportUrl(o.report);
    embed(ui.reportBody, reportUrl(o.report));
    ui.report.scrollIntoView({block: "start"});
  }

  // A page the session wrote (the report, the atlas: self-contained HTML with inline SVG and CSS, no script),
  // shown inside `box` in a shadow root of its own, so that its styles and the studio's stay apart.
  function embed(box, url) {
    var root = box.shadowRoot || box.attachShadow({mode: "open"});
    fetch(url).then(function (response) {
      if (!response.ok) throw new Error(url + ": HTTP " + response.status);
      return response.text();
    }).then(function (html) {
      var doc = new DOMParser().parseFromString(html, "text/html");
      doc.querySelectorAll("script").forEach(function (s) { s.remove(); });
      root.textContent = "";
      doc.head.querySelectorAll("style").forEach(function (s) { root.appendChild(document.importNode(s, true)); });
      root.appendChild(el("style", {}, EMBEDDED));
      var page = el("div", {class: "embedded-page"});
      Array.prototype.forEach.call(doc.body.childNodes, function (n) { page.appendChild(document.importNode(n, true)); });
      page.querySelectorAll("a[href]").forEach(function (a) { link(a, url); });
      root.appendChild(page);
      box.dataset.loaded = url;
    }).catch(function (e) { Studio.toast(e.message, "error"); });
  }

  // A link of an embedded page: relative to that page's address; a design's mechanism file opens in the editor.
  function link(a, base) {
    var href = a.getAttribute("href");
    if (href.charAt(0) === "#") return;
    var target = new URL(href, new URL(base, window.location.href));
    a.href = target.href;
    if (target.origin !== window.location.origin || !/\.json$/.test(target.pathname)) return;
    a.title = "open in the mechanism editor";
    a.addEventListener("click", function (event) {
      event.preventDefault();
      fetch(target.href).then(function (r) {
        if (!r.ok) throw new Error(target.pathname + ": HTTP " + r.status);
        return r.json();
      }).then(function (mechanism) {
        Studio.openInEditor(mechanism, decodeURIComponent(target.pathname.split("/").pop()));
      }).catch(function (e) { Studio.toast(e.message, "error"); });
    });
  }

  document.addEventListener("DOMContentLoaded", function () {
    var section = document.getElementById("panel-design");
    if (section) build(section);
  });
  window.addEventListener("domes:shown", function (e) { if (e.detail === "design" && ui.replay) loadRecorded(); });
})();
