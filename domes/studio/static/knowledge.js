// The knowledge panel: the criteria of the case base (enable, disable, remove), an editor that parses a criterion
// as it is written and marks a fault at its column, the history of changes with Undo, and browsers of the design
// scenes and the solved problems. Every change goes through the server's /api/kb/* routes (one transaction each).
"use strict";

(function () {
  var el = Studio.el;
  var PARSE_DELAY = 200;  // ms of quiet typing before the text is parsed
  var root, state = {criteria: [], history: [], editing: null, loaded: false, scenes: null, cases: null};
  var ui = {};

  // POST body to path; rejects with an Error carrying the server's whole answer (field, column) as .detail.
  function call(path, body, signal) {
    var init = {method: "POST", headers: {"content-type": "application/json"}, body: JSON.stringify(body)};
    if (signal) init.signal = signal;
    return fetch(path, init).then(function (response) {
      return response.json().catch(function () { return {error: "the server's answer is not JSON (" + response.status + ")"}; })
        .then(function (data) {
          if (!response.ok || data.error) {
            var err = new Error(data.error || "HTTP " + response.status);
            err.detail = data;
            throw err;
          }
          return data;
        });
    });
  }

  // ---- the parse of a text, shown as it is typed -------------------------------------------------------------

  // The text with the character at 0-based code-point position `pos` marked (the end of the text: a marked space).
  function marked(text, pos) {
    var chars = Array.from(text);
    var at = chars[pos] === undefined ? "\u00a0" : chars[pos];
    return el("pre", {class: "kb-mark-line"}, chars.slice(0, pos).join(""),
      el("mark", {class: "kb-fault", title: "column " + (pos + 1)}, at), chars.slice(pos + 1).join(""));
  }

  // A parse tree (the JSON of domes.language.tree) as nested lists.
  function tree(node) {
    if (node === null || typeof node !== "object") return el("span", {class: "kb-leaf"}, JSON.stringify(node));
    if (Array.isArray(node)) return el("ol", {class: "kb-tree"}, node.map(function (n) { return el("li", {}, tree(n)); }));
    var items = Object.keys(node).filter(function (k) { return k !== "node"; }).map(function (k) {
      return el("li", {}, el("span", {class: "kb-key"}, k + ": "), tree(node[k]));
    });
    return el("span", {class: "kb-node"}, el("b", {}, node.node || "object"), items.length ? el("ul", {class: "kb-tree"}, items) : null);
  }

  // A live parse of one input: `relevance` parses a relevance condition; `box` shows the reading or the fault.
  function liveParse(input, box, relevance) {
    var timer = null, seq = 0, controller = null;
    function show(text) {
      var mine = ++seq;
      if (controller) controller.abort();
      if (!text.trim()) {
        box.replaceChildren(el("span", {class: "kb-muted"}, relevance ? "derived from the criterion's names when empty" : "write a criterion"));
        input.classList.remove("kb-invalid");
        input.removeAttribute("aria-invalid");
        return;
      }
      controller = new AbortController();
      call("/api/kb/parse", {text: text, relevance: relevance}, controller.signal).then(function (parsed) {
        if (mine !== seq) return;
        input.classList.remove("kb-invalid");
        input.removeAttribute("aria-invalid");
        var parts = [el("div", {class: "kb-reading"}, el("span", {class: "kb-muted"}, "reads: "), parsed.reading)];
        if (parsed.category) parts.push(el("div", {class: "kb-muted"}, "category (" + parsed.category + ")"));
        var was = box.querySelector("details.kb-tree-box");  // the tree stays open while the text changes
        parts.push(el("details", {class: "kb-tree-box", open: !!(was && was.open)}, el("summary", {}, "parse tree"),
          tree(parsed.criterion || parsed.relevance)));
        box.replaceChildren.apply(box, parts);
      }).catch(function (err) {
        if (mine !== seq || err.name === "AbortError") return;
        var d = err.detail || {};
        input.classList.add("kb-invalid");
        input.setAttribute("aria-invalid", "true");
        box.replaceChildren(el("div", {class: "kb-parse-error error", role: "alert"}, err.message),
          typeof d.position === "number" ? marked(text, d.position) : null);
      });
    }
    input.addEventListener("input", function () {
      clearTimeout(timer);
      timer = setTimeout(function () { show(input.value); }, PARSE_DELAY);
    });
    return function () { clearTimeout(timer); show(input.value); };
  }

  // ---- the editor --------------------------------------------------------------------------------------------

  function field(label, input, note) {
    return el("label", {class: "kb-field"}, el("span", {}, label), input, note ? el("small", {class: "kb-muted"}, note) : null);
  }

  function buildEditor() {
    ui.id = el("input", {id: "kb-id", type: "text", placeholder: "three-pins", autocomplete: "off", spellcheck: "false"});
    ui.text = el("textarea", {id: "kb-text", rows: 3, placeholder: "every vertex must have degree at most 3", spellcheck: "false"});
    ui.textParse = el("div", {id: "kb-text-parse", class: "kb-parse", "aria-live": "polite"});
    ui.relevance = el("input", {id: "kb-relevance", type: "text", placeholder: "the problem has “piston” (optional)", spellcheck: "false"});
    ui.relevanceParse = el("div", {id: "kb-relevance-parse", class: "kb-parse"});
    ui.explanation = el("input", {id: "kb-explanation", type: "text"});
    ui.keywords = el("input", {id: "kb-keywords", type: "text", placeholder: "comma, separated"});
    ui.level = el("input", {id: "kb-level", type: "number", min: 1, max: 9, placeholder: "cheapest"});
    ui.source = el("input", {id: "kb-source", type: "text"});
    ui.date = el("input", {id: "kb-date", type: "text", placeholder: "today (YYYY-MM-DD)"});
    ui.why = el("input", {id: "kb-why", type: "text", placeholder: "kept in the history"});
    ui.disabled = el("input", {id: "kb-disabled", type: "checkbox"});
    ui.add = el("button", {id: "kb-add", type: "button", onclick: addCriterion}, "Add");
    ui.save = el("button", {id: "kb-save", type: "button", disabled: true, onclick: saveCriterion}, "Save changes");
    ui.clear = el("button", {id: "kb-clear", type: "button", onclick: clearEditor}, "New");
    ui.formStatus = el("div", {id: "kb-form-status", role: "status"});
    ui.editing = el("span", {id: "kb-editing", class: "kb-muted"}, "a new criterion");
    ui.parseText = liveParse(ui.text, ui.textParse, false);
    ui.parseRelevance = liveParse(ui.relevance, ui.relevanceParse, true);
    ui.parseText();
    ui.parseRelevance();
    return el("form", {id: "kb-editor", class: "kb-card", onsubmit: function (e) { e.preventDefault(); }, oninput: disarm},
      el("h3", {}, "Criterion ", ui.editing),
      field("id", ui.id),
      field("criterion", ui.text, "near-English; parsed as you type"), ui.textParse,
      field("relevance", ui.relevance), ui.relevanceParse,
      el("div", {class: "kb-row"}, field("explanation", ui.explanation), field("keywords", ui.keywords)),
      el("div", {class: "kb-row"}, field("level", ui.level), field("source", ui.source), field("date", ui.date)),
      el("div", {class: "kb-row"}, field("why", ui.why),
        el("label", {class: "kb-check"}, ui.disabled, " add it disabled")),
      el("div", {class: "kb-buttons"}, ui.add, ui.save, ui.clear), ui.formStatus);
  }

  // The editor's fields as a route body; `only` keeps those that differ from the criterion being edited.
  function formBody(only) {
    var body = {id: ui.id.value.trim(), text: ui.text.value, explanation: ui.explanation.value, keywords: ui.keywords.value,
                relevance: ui.relevance.value, source: ui.source.value};
    if (ui.level.value !== "") body.level = Number(ui.level.value);
    if (ui.date.value.trim() !== "") body.date = ui.date.value.trim();
    if (only) {
      var was = {text: only.text, explanation: only.explanation, keywords: only.keywords.join(", "), relevance: only.relevance,
                 source: only.source, level: only.level, date: only.date};
      Object.keys(was).forEach(function (k) { if (body[k] !== undefined && String(body[k]) === String(was[k])) delete body[k]; });
    } else {
      ["explanation", "relevance", "source"].forEach(function (k) { if (body[k] === "") delete body[k]; });
      if (ui.disabled.checked) body.disabled = true;
    }
    if (ui.why.value.trim()) body.why = ui.why.value.trim();
    return body;
  }

  function status(text, kind) {
    ui.formStatus.className = kind === "error" ? "error" : "ok";
    ui.formStatus.setAttribute("role", kind === "error" ? "alert" : "status");
    ui.formStatus.textContent = text;
  }

  // A refused edit: its message under the buttons, and a parse fault marked at its place in its field.
  function refused(err) {
    status(err.message, "error");
    var d = err.detail || {};
    var input = d.field === "relevance" ? ui.relevance : d.field === "text" ? ui.text : null;
    var box = d.field === "relevance" ? ui.relevanceParse : ui.textParse;
    if (input && typeof d.position === "number") {
      input.classList.add("kb-invalid");
      input.setAttribute("aria-invalid", "true");
      box.replaceChildren(el("div", {class: "kb-parse-error error", role: "alert"}, err.message), marked(input.value, d.position));
    }
  }

  function addCriterion() {
    call("/api/kb/add", formBody(null)).then(function (done) {
      status(done.message, "ok");
      ui.why.value = "";
      edit(done.criterion);
      return refresh();
    }).catch(refused);
  }

  function saveCriterion() {
    if (!state.editing) return;
    var body = formBody(state.editing);
    body.id = state.editing.id;
    call("/api/kb/edit", body).then(function (done) {
      status(done.message, "ok");
      ui.why.value = "";
      edit(done.criterion);
      return refresh();
    }).catch(refused);
  }

  // Whether the editor holds something not yet added or saved.
  function dirty() {
    if (state.editing) return Object.keys(formBody(state.editing)).some(function (k) { return k !== "id" && k !== "why"; });
    return [ui.id, ui.text, ui.relevance, ui.explanation, ui.keywords, ui.level, ui.source, ui.date]
      .some(function (i) { return i.value.trim() !== ""; });
  }

  // Edit `c` unless that would drop what the editor holds.
  function editKeeping(c) {
    if (dirty() && !(state.editing && state.editing.id === c.id)) {
      status("the editor holds changes not yet " + (state.editing ? "saved to " + state.editing.id : "added") +
        ": save or add them, or press New to drop them, before editing " + c.id, "error");
      return;
    }
    edit(c);
    ui.text.focus();
  }

  // Put a criterion in the editor, to change it (its id is then fixed).
  function edit(c) {
    disarm();
    state.editing = c;
    ui.id.value = c.id;
    ui.id.readOnly = true;
    ui.text.value = c.text;
    ui.relevance.value = c.relevance;
    ui.explanation.value = c.explanation;
    ui.keywords.value = c.keywords.join(", ");
    ui.level.value = c.level;
    ui.source.value = c.source;
    ui.date.value = c.date;
    ui.save.disabled = false;
    ui.editing.textContent = c.id + " (editing)";
    ui.parseText();
    ui.parseRelevance();
  }

  function disarm() {
    delete ui.clear.dataset.armed;
    ui.clear.textContent = "New";
  }

  function clearEditor() {
    if (dirty() && !ui.clear.dataset.armed) {  // a second press drops them
      ui.clear.dataset.armed = "1";
      ui.clear.textContent = "Drop changes?";
      status("press again to drop what the editor holds", "error");
      return;
    }
    disarm();
    state.editing = null;
    ui.id.readOnly = false;
    [ui.id, ui.text, ui.relevance, ui.explanation, ui.keywords, ui.level, ui.source, ui.date, ui.why].forEach(function (i) { i.value = ""; });
    ui.disabled.checked = false;
    ui.save.disabled = true;
    ui.editing.textContent = "a new criterion";
    ui.formStatus.textContent = "";
    ui.parseText();
    ui.parseRelevance();
  }

  // ---- the criteria table ------------------------------------------------------------------------------------

  // A change from the table or the history: its outcome said above the table, and the lists read again.
  function change(path, body) {
    return call(path, body).then(function (done) {
      ui.changeStatus.className = "ok";
      ui.changeStatus.textContent = done.message;
      return refresh();
    }).catch(function (err) {
      ui.changeStatus.className = "error";
      ui.changeStatus.textContent = err.message;
      Studio.toast(err.message, "error");
      return refresh();
    });
  }

  // A button that asks once more, in place, before it acts.
  function confirming(label, question, act) {
    var box = el("span", {class: "kb-confirm"});
    function initial() {
      box.replaceChildren(el("button", {type: "button", class: "kb-danger", onclick: ask}, label));
    }
    function ask() {
      var why = el("input", {type: "text", class: "kb-why-inline", placeholder: "why (optional)"});
      box.replaceChildren(el("span", {}, question + " "), why,
        el("button", {type: "button", class: "kb-danger kb-yes", onclick: function () { act(why.value.trim()); }}, "Yes"),
        el("button", {type: "button", class: "kb-no", onclick: initial}, "No"));
    }
    initial();
    return box;
  }

  function criteriaTable() {
    var rows = state.criteria.map(function (c) {
      var toggle = el("input", {type: "checkbox", class: "kb-enabled", checked: c.enabled, title: c.enabled ? "enabled: click to disable" : "disabled: click to enable"});
      toggle.addEventListener("change", function () {
        toggle.disabled = true;
        change(toggle.checked ? "/api/kb/enable" : "/api/kb/disable", {id: c.id});
      });
      return el("tr", {"data-id": c.id, class: c.enabled ? "" : "kb-off"},
        el("td", {class: "kb-num"}, String(c.number)), el("td", {class: "kb-cid"}, c.id), el("td", {}, c.category),
        el("td", {class: "kb-num"}, String(c.level)), el("td", {}, toggle),
        el("td", {class: "kb-text-cell"}, el("div", {}, c.reading), c.explanation ? el("div", {class: "kb-muted"}, c.explanation) : null,
          el("div", {class: "kb-muted kb-small"}, "relevant when " + c.relevance_reading)),
        el("td", {class: "kb-actions"}, el("button", {type: "button", class: "kb-edit", onclick: function () { editKeeping(c); }}, "Edit"),
          confirming("Remove", "Remove " + c.id + "?", function (why) { change("/api/kb/remove", {id: c.id, why: why}); })));
    });
    return el("table", {id: "kb-criteria", class: "kb-table"},
      el("thead", {}, el("tr", {}, ["#", "id", "cat", "level", "on", "criterion", ""].map(function (h) { return el("th", {}, h); }))),
      el("tbody", {}, rows));
  }

  // ---- the history -------------------------------------------------------------------------------------------

  function historyList() {
    var entries = state.history.slice().reverse();
    var undo = el("button", {id: "kb-undo", type: "button", disabled: !entries.length, onclick: function () {
      undo.disabled = true;
      change("/api/kb/undo", {});
    }}, "Undo last change");
    var items = entries.map(function (e, i) {
      return el("li", {"data-entry": e.number},
        el("div", {}, el("b", {}, e.number + " "), e.action + " " + e.target),
        el("div", {class: "kb-muted kb-small"}, e.time + " · " + e.session),
        e.why ? el("div", {class: "kb-small"}, "why: " + e.why) : null,
        el("div", {class: "kb-small"}, e.summary),
        i > 0 ? confirming("Undo from here", "Undo entries " + e.number + " to " + entries[0].number + "?",
          function () { change("/api/kb/undo", {entry: e.number}); }) : null);
    });
    return el("div", {id: "kb-history", class: "kb-card"}, el("h3", {}, "History"), undo,
      items.length ? el("ul", {class: "kb-history-list"}, items) : el("p", {class: "kb-muted", id: "kb-no-history"}, "no recorded change"));
  }

  function refresh() {
    return Promise.all([Studio.api("/api/kb/criteria"), Studio.api("/api/kb/history")]).then(function (r) {
      state.criteria = r[0].criteria;
      state.history = r[1].history;
      ui.where.textContent = "case base: " + r[0].db + " · " + r[0].criteria.length + " criteria, " + r[0].enabled + " enabled";
      ui.table.replaceChildren(criteriaTable());
      ui.history.replaceChildren(historyList());
      root.dataset.loaded = String(Date.now());
    }).catch(function (err) {
      ui.where.replaceChildren(el("span", {class: "error"}, err.message));
    });
  }

  // ---- scenes and cases --------------------------------------------------------------------------------------

  function kv(pairs) {
    return el("dl", {class: "kb-kv"}, pairs.filter(function (p) { return p[1] !== "" && p[1] !== null && p[1] !== undefined; })
      .map(function (p) { return [el("dt", {}, p[0]), el("dd", {}, String(p[1]))]; }));
  }

  function sceneDetail(s) {
    var stages = el("table", {class: "kb-table"},
      el("thead", {}, el("tr", {}, ["#", "stage", "kind", "role", "gives out", "rules", "book"].map(function (h) { return el("th", {}, h); }))),
      el("tbody", {}, s.stages.map(function (st) {
        return el("tr", {}, el("td", {}, String(st.number)), el("td", {}, st.name),
          el("td", {}, st.kind + (st.change ? " (" + st.change + ")" : "")), el("td", {}, st.role || "—"), el("td", {}, st.select),
          el("td", {}, st.rules.length ? el("ul", {}, st.rules.map(function (r) { return el("li", {title: r.text}, r.reading); })) : "—"),
          el("td", {}, st.book === null ? "—" : String(st.book)));
      })));
    return el("div", {class: "kb-detail"}, el("h3", {}, s.title + " [" + s.name + "]"),
      kv([["source", s.source], ["chains", s.links + " links, DOF " + s.dof + (s.include_fractionated ? ", fractionated too" : "") + (s.clamping ? ", clamping" : "")],
          ["roles", s.roles.join(", ")], ["existing designs", s.existing], ["book", s.book_note]]),
      el("h4", {}, "Stages"), stages,
      s.particularize.length ? [el("h4", {}, "Particularization"), el("ul", {}, s.particularize.map(function (p) { return el("li", {}, p.between.join(" – ") + " → " + p.joint); }))] : null,
      s.requirements.length ? [el("h4", {}, "Requirements"), el("table", {class: "kb-table"},
        el("thead", {}, el("tr", {}, ["id", "what", "kind", "unit", "default"].map(function (h) { return el("th", {}, h); }))),
        el("tbody", {}, s.requirements.map(function (r) {
          return el("tr", {title: r.help}, el("td", {}, r.id), el("td", {}, r.label), el("td", {}, r.kind), el("td", {}, r.unit), el("td", {}, r.default));
        })))] : null,
      s.checks.length ? [el("h4", {}, "Checks"), el("ul", {}, s.checks.map(function (c) { return el("li", {}, el("code", {}, c.check), " — " + c.why); }))] : null);
  }

  // A list of `kind` read from listPath (again each time it is shown when `fresh`), and the one chosen in detail.
  function browser(kind, listPath, row, detail, fresh) {
    var list = el("div", {class: "kb-list"}), view = el("div", {class: "kb-view"}, el("p", {class: "kb-muted"}, "choose one"));
    var box = el("div", {id: "kb-" + kind, class: "kb-browser"}, list, view);
    box.load = function () {
      if (box.dataset.loaded && !fresh) return;
      box.dataset.loaded = "1";
      if (!list.firstChild) list.replaceChildren(el("p", {class: "kb-muted"}, "reading…"));
      Studio.api(listPath).then(function (data) {
        var chosen = list.querySelector(".kb-item.active");
        chosen = chosen && chosen.dataset.key;
        list.replaceChildren(el("ul", {}, data[kind].map(function (item) {
          var button = el("button", {type: "button", onclick: function () {
            list.querySelectorAll(".kb-item").forEach(function (b) { b.classList.toggle("active", b === button); });
            view.replaceChildren(el("p", {class: "kb-muted"}, "reading…"));
            detail(item).then(function (node) { view.replaceChildren(node); })
              .catch(function (err) { view.replaceChildren(el("p", {class: "error"}, err.message)); });
          }, "data-key": item.id || item.name, class: "kb-item" + ((item.id || item.name) === chosen ? " active" : "")}, row(item));
          return el("li", {}, button);
        })));
      }).catch(function (err) { delete box.dataset.loaded; list.replaceChildren(el("p", {class: "error"}, err.message)); });
    };
    return box;
  }

  function scenesBrowser() {
    return browser("scenes", "/api/kb/scenes", function (s) {
      return s.error ? [el("b", {}, s.name), el("div", {class: "error kb-small"}, s.error)]
        : [el("b", {}, s.name), el("div", {class: "kb-small"}, s.title), el("div", {class: "kb-muted kb-small"}, s.links + " links, DOF " + s.dof + ", " + s.stages + " stages")];
    }, function (s) {
      return Studio.api("/api/kb/scenes?name=" + encodeURIComponent(s.name)).then(function (d) { return sceneDetail(d.scene); });
    });
  }

  function casesBrowser() {
    return browser("cases", "/api/kb/cases", function (c) {
      return [el("b", {}, c.id), el("div", {class: "kb-small"}, c.problem_class.replace(/_/g, " ")),
        el("div", {class: "kb-muted kb-small"}, "DOF " + c.dof + ", " + c.loops + " loops, " + c.kept + " kept")];
    }, function (c) {
      return Studio.api("/api/kb/cases?id=" + encodeURIComponent(c.id)).then(function (d) {
        return el("div", {class: "kb-detail"}, el("h3", {}, d.case.id), el("pre", {class: "kb-frame-text"}, d.text),
          el("details", {}, el("summary", {}, "the whole frame (JSON)"), el("pre", {class: "kb-json"}, JSON.stringify(d.case, null, 1))));
      });
    }, true);
  }

  // ---- the panel ---------------------------------------------------------------------------------------------

  function build() {
    root = document.getElementById("panel-knowledge");
    if (!root) return;
    ui.where = el("span", {id: "kb-where", class: "kb-muted"});
    ui.changeStatus = el("div", {id: "kb-change-status", role: "status"});
    ui.table = el("div", {class: "kb-table-box"});
    ui.history = el("div", {});
    var views = {criteria: el("div", {class: "kb-criteria-view"}, el("div", {class: "kb-main"}, buildEditor(), ui.changeStatus, ui.table), ui.history),
                 scenes: scenesBrowser(), cases: casesBrowser()};
    var tabs = el("nav", {class: "kb-tabs"}, Object.keys(views).map(function (name) {
      return el("button", {type: "button", "data-view": name, class: name === "criteria" ? "active" : "", onclick: function () {
        tabs.querySelectorAll("button").forEach(function (b) { b.classList.toggle("active", b.dataset.view === name); });
        Object.keys(views).forEach(function (v) { views[v].hidden = v !== name; });
        if (views[name].load) views[name].load();
      }}, name.charAt(0).toUpperCase() + name.slice(1));
    }));
    views.scenes.hidden = views.cases.hidden = true;
    root.replaceChildren(el("div", {class: "kb-head"}, el("h2", {}, "Knowledge base"), ui.where), tabs,
      views.criteria, views.scenes, views.cases);
  }

  document.addEventListener("DOMContentLoaded", function () {
    build();
    if (root && root.classList.contains("active")) { state.loaded = true; refresh(); }
  });
  window.addEventListener("domes:shown", function (e) {
    if (e.detail === "knowledge" && root) { state.loaded = true; refresh(); }
  });
})();
