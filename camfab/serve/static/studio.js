// camfab studio: the page's side of `camfab serve` (camfab/serve/app.py holds the API).
//
// An edit in the page is sent at once (the newest wins while one is on its way) and its answer,
// the report page of the new analysis, is put in place of the report shown (its body, its
// scripts run again over it), at the same cam angle and scroll: the measured time from the
// edit to the frame that paints it is kept in window.camfabLatencies (and as a Performance API
// measure "camfab-redraw"). When the files are made and read back (a moment after the edits
// stop), the verified report replaces it and the 3-D view gets the part's STL.

const body = document.body;
const token = body.dataset.token;
const headers = { "X-Camfab-Token": token, "Content-Type": "application/json" };
let shown = 0;            // the version shown
let verifiedShown = 0;    // the version whose verified report and scene are shown
let frame = 0;            // the report's cam-angle frame
let fieldPaths = "";
let view3d = null;
let verifiedReady = 0;    // the newest version the server has made the files of
window.camfabLatencies = [];
// per redraw (ms): until the answer came, then until it was drawn; the server's own time
window.camfabParts = [];
let serverMs = null;

function el(id) { return document.getElementById(id); }

async function call(path, method, data) {
  const response = await fetch(path, {
    method: method || "GET", headers: headers,
    body: data === undefined ? undefined : JSON.stringify(data) });
  let answer = null;
  try { answer = await response.json(); } catch (e) { answer = { error: response.statusText }; }
  return [response.ok, answer, response.status, response.headers.get("Server-Timing")];
}

function notice(nodes) {
  const box = el("notice");
  box.replaceChildren(...nodes);
  box.hidden = nodes.length === 0;
}

function text(tag, words) { const node = document.createElement(tag); node.textContent = words; return node; }

// --- the report ------------------------------------------------------------------------------

const report = document.getElementById("report-frame");
// the report's sections below the fold laid out only when scrolled to: a redraw costs what
// the screen shows
const LAZY = "<style>main > section { content-visibility: auto; " +
  "contain-intrinsic-size: auto 40em; }</style>";
let loaded = false;       // the frame holds a report (later ones are put in its place)
let drawing = Promise.resolve();

function followFrame() {
  // the report's own script moves its drawing; the 3-D view follows its body's data-frame
  const doc = report.contentDocument;
  const watch = new MutationObserver(function () {
    const now = +(doc.body.getAttribute("data-frame") || 0);
    if (now === frame) { return; }
    frame = now;
    if (view3d) { view3d.show(frame); }
  });
  watch.observe(doc.body, { attributes: true, attributeFilter: ["data-frame"] });
}

function draw(html, version, started, kind) {
  // one draw at a time, in order; a view older than the one shown is dropped
  drawing = drawing.then(function () {
    if (version < shown || (version === shown && kind === body.dataset.shown)) { return null; }
    return loaded ? patch(html, version, started, kind) : first(html, version, started, kind);
  });
  return drawing;
}

function first(html, version, started, kind) {
  // the first report: a document of its own in the frame
  const answered = performance.now();
  return new Promise(function (done) {
    report.onload = function () {
      report.onload = null;
      loaded = true;
      followFrame();
      drawn(version, started, answered, kind).then(done);
    };
    report.srcdoc = html.replace("</head>", LAZY + "</head>");
  });
}

function patch(html, version, started, kind) {
  // a later report put in place of the one shown: its body (the page around it, its styles and
  // the scroll stay), then its scripts run again over it, at the cam angle shown
  const answered = performance.now();
  const doc = report.contentDocument;
  const parsed = new DOMParser().parseFromString(html, "text/html");
  const keep = frame;
  const nodes = Array.from(parsed.body.childNodes);  // a copy: adopting a node moves it
  doc.body.replaceChildren(...nodes.map(function (node) { return doc.adoptNode(node); }));
  doc.body.querySelectorAll("script:not([type])").forEach(function (old) {
    const script = doc.createElement("script");
    script.textContent = old.textContent;
    old.replaceWith(script);
  });
  const slider = doc.getElementById("angle");
  if (slider) {
    slider.value = String(Math.min(keep, +slider.max));
    slider.dispatchEvent(new Event("input"));
  }
  return drawn(version, started, answered, kind);
}

function drawn(version, started, answered, kind) {
  // the new report is in place: the next frame paints it (measured when it has)
  shown = version;
  body.dataset.version = String(version);
  body.dataset.shown = kind;
  return new Promise(function (done) {
    if (started === null) { done(); return; }
    // the frame after next begins once the next one (its style, layout and paint) is done
    requestAnimationFrame(function () { requestAnimationFrame(function () {
      const ms = performance.now() - started;
      window.camfabLatencies.push(ms);
      window.camfabParts.push([answered - started, ms - (answered - started), serverMs]);
      try { performance.measure("camfab-redraw", { start: started, end: started + ms }); }
      catch (e) { /* an older browser without measure options */ }
      done();
    }); });
  });
}

// --- the state ---------------------------------------------------------------------------------

function status(state) {
  el("edited").hidden = !state.edited;
  el("conflict").hidden = !state.conflict;
  const error = el("error");
  error.textContent = state.error || "";
  error.hidden = !state.error;
  body.dataset.error = state.error || "";
}

async function apply(state, started) {
  status(state);
  if (state.fields) { fields(state.fields); }
  if (state.error) { body.dataset.version = String(state.version); return; }
  if (state.html && state.version > shown) { await draw(state.html, state.version, started, "view"); }
  if (verifiedReady === shown) { verified(shown); }
}

// --- the editor --------------------------------------------------------------------------------

function fields(list) {
  const paths = list.map(function (f) { return f.path + ":" + f.kind; }).join(",");
  const editor = el("editor");
  if (paths !== fieldPaths) {
    fieldPaths = paths;
    editor.replaceChildren(...list.map(field));
    return;
  }
  list.forEach(function (f) {  // new values from disk; not the one being edited
    editor.querySelectorAll('[data-path="' + f.path + '"]').forEach(function (input) {
      if (document.activeElement !== input && input.dataset.busy !== "yes") {
        input.value = String(f.value);
      }
    });
  });
}

function field(f) {
  const box = document.createElement("div");
  box.className = "field";
  const id = "f-" + f.path.replace(/[^A-Za-z0-9_-]/g, "_");
  const label = text("label", f.path);
  label.htmlFor = id;
  box.append(label);
  const row = document.createElement("div");
  row.className = "row";
  box.append(row);
  if (f.kind === "number") {
    const range = document.createElement("input");
    range.type = "range";
    range.min = String(Math.min(f.low, f.value));
    range.max = String(Math.max(f.high, f.value));
    range.step = String(f.step);
    range.value = String(f.value);
    range.dataset.path = f.path;
    range.setAttribute("aria-label", f.path + " slider");
    const number = document.createElement("input");
    number.type = "number";
    number.id = id;
    number.step = "any";
    number.value = String(f.value);
    number.dataset.path = f.path;
    range.addEventListener("input", function () {
      number.value = range.value;
      edit(f.path, +range.value);
    });
    range.addEventListener("pointerdown", function () { range.dataset.busy = "yes"; });
    range.addEventListener("pointerup", function () { range.dataset.busy = "no"; });
    number.addEventListener("change", function () {
      if (number.value === "" || !isFinite(+number.value)) { return; }
      range.value = number.value;
      edit(f.path, +number.value);
    });
    row.append(range, number);
  } else if (f.choices) {
    const select = document.createElement("select");
    select.id = id;
    select.dataset.path = f.path;
    const choices = f.choices.indexOf(f.value) < 0 ? [f.value].concat(f.choices) : f.choices;
    choices.forEach(function (c) { const o = text("option", c); o.value = c; select.append(o); });
    select.value = f.value;
    select.addEventListener("change", function () { edit(f.path, select.value); });
    row.append(select);
  } else {
    const input = document.createElement("input");
    input.type = "text";
    input.id = id;
    input.value = String(f.value);
    input.dataset.path = f.path;
    input.addEventListener("change", function () { edit(f.path, input.value); });
    row.append(input);
  }
  return box;
}

let sending = false;
let queued = null;

function edit(path, value) {
  queued = { path: path, value: value, started: performance.now() };
  pump();
}

async function pump() {
  if (sending || queued === null) { return; }
  const next = queued;
  queued = null;
  sending = true;
  body.dataset.busy = "yes";
  try {
    const [ok, answer, , timing] = await call("/api/edit?respond=view", "POST",
                                              { path: next.path, value: next.value });
    const spent = /dur=([0-9.]+)/.exec(timing || "");
    serverMs = spent ? +spent[1] : null;
    if (ok) { await apply(answer, next.started); }
    else { status({ error: answer.error, edited: true, conflict: false }); }
  } finally {
    sending = false;
    body.dataset.busy = queued === null ? "no" : "yes";
    pump();
  }
}

// --- the files made and read back: the verified report and the 3-D part -----------------------

let verifying = 0;        // the version whose verified report is being fetched

async function verified(version) {
  if (version !== shown || version <= verifiedShown || version === verifying) { return; }
  verifying = version;
  try { await verifiedNow(version); } finally { if (verifying === version) { verifying = 0; } }
}

async function verifiedNow(version) {
  const [ok, answer] = await call("/api/verified?version=" + version);
  if (!ok || answer.version !== shown) { return; }
  el("verifying").hidden = true;
  const verdict = el("verdict");
  verdict.textContent = answer.exit_code === 0 ? "PASS" : "FAIL";
  verdict.className = "badge " + (answer.exit_code === 0 ? "ok" : "fail");
  await draw(answer.html, version, null, "verified");
  verifiedShown = version;
  body.dataset.verified = String(version);
  if (answer.scene) { await scene(answer.scene, version); }
}

let viewer = null;         // the 3-D view, made once (its module loaded when first needed)

async function scene(data, version) {
  try {
    if (viewer === null) {
      viewer = import("./view3d.js").then(function (module) {
        view3d = new module.View3D(el("view3d"));
        return view3d;
      });
    }
    await viewer;
    const buffers = await Promise.all(data.parts.map(function (part, i) {
      return fetch("/api/part/" + i + "?version=" + version, { headers: headers })
        .then(function (r) { return r.arrayBuffer(); });
    }));
    if (version !== shown) { return; }
    view3d.setScene(data, buffers);
    view3d.show(frame);
  } catch (e) {
    el("view3d").textContent = "3-D view: " + e;
  }
}

// --- the buttons -------------------------------------------------------------------------------

el("save").addEventListener("click", async function () {
  const [ok, answer] = await call("/api/save", "POST", {});
  notice([text("span", ok ? "saved " + answer.saved : answer.error)]);
  if (ok) { el("edited").hidden = true; }
});

el("reload").addEventListener("click", async function () {
  const [ok, answer] = await call("/api/reload", "POST", {});
  if (ok) { notice([]); fieldPaths = ""; await apply(answer, null); }
  else { notice([text("span", answer.error)]); }
});

el("size").addEventListener("click", async function () {
  notice([text("span", "sizing…")]);
  const [ok, answer] = await call("/api/size", "POST", {});
  if (!ok) { notice([text("span", answer.error)]); return; }
  const nodes = [text("pre", answer.lines.join("\n"))];
  if (answer.edits.length) {
    const take = text("button", "Apply: " + answer.edits.map(function (e) {
      return e.path + " = " + e.value; }).join(", "));
    take.id = "apply-size";
    take.addEventListener("click", function () {
      answer.edits.forEach(function (e) {
        document.querySelectorAll('[data-path="' + e.path + '"]').forEach(function (input) {
          input.value = String(e.value); });
        edit(e.path, e.value);
      });
      notice([]);
    });
    nodes.push(take);
  }
  notice(nodes);
});

el("build").addEventListener("click", async function () {
  notice([text("span", "building…")]);
  const [ok, answer] = await call("/api/build", "POST", {});
  if (!ok) { notice([text("span", answer.error)]); return; }
  notice([text("span", "built " + answer.folder + "/ (" + (answer.exit_code === 0 ? "PASS" : "FAIL") + ")")]);
  el("folder").textContent = answer.folder + "/";
  el("files").replaceChildren(...answer.files.map(function (name) { return text("li", name); }));
  el("files-box").hidden = false;
});

// --- changes from elsewhere: the file saved in an editor, another page ------------------------

const events = new EventSource("/api/events?token=" + encodeURIComponent(token));
events.addEventListener("state", async function (e) {
  const data = JSON.parse(e.data);
  status(data);
  if (!data.error && data.version > verifiedShown) { el("verifying").hidden = false; }
  if (data.version > shown && !sending && queued === null && !data.error) {
    const [ok, answer] = await call("/api/state");
    if (ok) { await apply(answer, null); }
  } else if (data.error) {
    body.dataset.version = String(data.version);
    if (data.origin !== "edit") {  // the file broken on disk: its values as they are now
      const [ok, answer] = await call("/api/state");
      if (ok) { fields(answer.fields); }
    }
  }
});
events.addEventListener("verified", function (e) {
  verifiedReady = JSON.parse(e.data).version;
  verified(verifiedReady);
});
events.addEventListener("fault", function (e) {
  el("verifying").hidden = true;
  notice([text("span", "the files were not made: " + JSON.parse(e.data).error)]);
});

(async function () {
  const [ok, answer] = await call("/api/state");
  if (ok) { await apply(answer, null); }
  body.dataset.ready = "yes";
  if (ok && !answer.error) { verifiedReady = answer.version; await verified(answer.version); }
})();
