// DOMES Studio: what every panel shares. The panels' scripts (design.js, editor.js, synthesis.js,
// knowledge.js) each fill their own <section id="panel-NAME"> and use only what is defined here.
"use strict";

var Studio = (function () {
  // POST body (an object) as JSON to path, or GET when body is undefined; resolves to the answer's JSON,
  // rejects with an Error whose message is the server's "error" (what was wrong and where).
  function api(path, body, options) {
    var init = {method: body === undefined ? "GET" : "POST", headers: {}};
    if (body !== undefined) {
      init.headers["content-type"] = "application/json";
      init.body = JSON.stringify(body);
    }
    if (options && options.signal) init.signal = options.signal;
    return fetch(path, init).then(function (response) {
      return response.json().catch(function () { return {error: "the server's answer is not JSON (" + response.status + ")"}; })
        .then(function (data) {
          if (!response.ok || (data && data.error)) {
            var err = new Error(data && data.error ? data.error : "HTTP " + response.status);
            err.status = response.status;
            throw err;
          }
          return data;
        });
    });
  }

  // An element: el("div", {class: "x", onclick: f}, child, "text", ...).
  function el(tag, attrs) {
    var node = document.createElement(tag);
    Object.keys(attrs || {}).forEach(function (key) {
      var value = attrs[key];
      if (key.slice(0, 2) === "on" && typeof value === "function") node.addEventListener(key.slice(2), value);
      else if (value !== undefined && value !== null && value !== false) node.setAttribute(key, value === true ? "" : value);
    });
    for (var i = 2; i < arguments.length; i++) append(node, arguments[i]);
    return node;
  }
  function append(node, child) {
    if (child === undefined || child === null || child === false) return;
    if (Array.isArray(child)) { child.forEach(function (c) { append(node, c); }); return; }
    node.appendChild(typeof child === "string" || typeof child === "number" ? document.createTextNode(String(child)) : child);
  }

  var SVG_NS = "http://www.w3.org/2000/svg";
  // An SVG element: svg("circle", {cx: 1, cy: 2, r: 3}).
  function svg(tag, attrs) {
    var node = document.createElementNS(SVG_NS, tag);
    Object.keys(attrs || {}).forEach(function (key) { node.setAttribute(key, attrs[key]); });
    for (var i = 2; i < arguments.length; i++) if (arguments[i]) node.appendChild(arguments[i]);
    return node;
  }

  // A short message at the bottom of the page (kind: "info" or "error").
  function toast(text, kind) {
    var box = document.getElementById("toast");
    box.textContent = text;
    box.className = "show " + (kind || "info");
    clearTimeout(toast.timer);
    toast.timer = setTimeout(function () { box.className = ""; }, 6000);
  }

  // Show panel NAME ("design", "editor", "synthesis", "knowledge").
  function show(name) {
    document.querySelectorAll("#tabs button").forEach(function (b) { b.classList.toggle("active", b.dataset.panel === name); });
    document.querySelectorAll(".panel").forEach(function (p) { p.classList.toggle("active", p.id === "panel-" + name); });
    window.dispatchEvent(new CustomEvent("domes:shown", {detail: name}));
  }

  // Open a mechanism (the JSON of a mechanism file) in the editor: synthesis results and design candidates
  // call this; editor.js listens for "domes:open".
  function openInEditor(mechanism, name) {
    show("editor");
    window.dispatchEvent(new CustomEvent("domes:open", {detail: {mechanism: mechanism, name: name || null}}));
  }

  document.addEventListener("DOMContentLoaded", function () {
    document.querySelectorAll("#tabs button").forEach(function (b) {
      b.addEventListener("click", function () { show(b.dataset.panel); });
    });
    api("/api/about").then(function (a) {
      document.getElementById("about").textContent = "v" + a.version + " · data folder " + a.home;
    }).catch(function (e) { toast(e.message, "error"); });
  });

  return {api: api, el: el, svg: svg, toast: toast, show: show, openInEditor: openInEditor};
})();
