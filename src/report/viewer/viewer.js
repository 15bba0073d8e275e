// hemilab's comparison viewer: two images of one view side by side under a split, with zoom to
// single pixels, pan, the frames of a real-time sequence and the image / signed-error / FLIP layers.
// It reads window.HEMILAB_VIEWER (viewer/manifest.js, written by the run) and shows plain <img>
// elements scaled by CSS (`image-rendering: pixelated`): nothing is read back from a canvas, so the
// page works opened from disk (file://), where a browser refuses to read pixels of local images.
// The whole view lives in the URL's hash, so a link reproduces it (and opens the viewer over the
// whole window); a state that does not parse falls back to the defaults, field by field, and says
// which fields it ignored.
(function () {
  "use strict";
  var M = window.HEMILAB_VIEWER;
  var $ = function (id) { return document.getElementById(id); };
  var root = $("viewer");
  if (!M || !root || !M.views || !M.views.length) {
    if (root) { $("viewer-note").textContent = "No images were exported for the viewer."; }
    return;
  }
  var LAYERS = ["image", "error", "flip"];
  var MIN_ZOOM = 0.05, MAX_ZOOM = 64;
  var st = null; // {v, a, b, f, l, z, x, y, s}; z = 0: fit the image to the stage
  var stage = $("viewer-stage"), imgA = $("viewer-img-a"), imgB = $("viewer-img-b");
  var clipB = $("viewer-clip-b"), line = $("viewer-split");

  function view() { return M.views[st.v]; }
  function series(i) { return i < 0 ? null : view().series[i]; }
  function byId(list, id) {
    for (var i = 0; i < list.length; i++) { if (list[i].id === id) { return i; } }
    return -1;
  }
  // The frame of `list` (entries with .frame) shown at frame f: f itself, else the last before it,
  // else the first (a single-frame pipeline beside an accumulating one).
  function at(list, f) {
    var best = list[0];
    for (var i = 0; i < list.length; i++) { if (list[i].frame <= f) { best = list[i]; } }
    return best;
  }
  function defaults(v) {
    var V = M.views[v], a = 0;
    for (var i = 0; i < V.series.length; i++) { if (V.series[i].paper) { a = i; break; } }
    return { v: v, a: a, b: -1, f: V.frames[V.frames.length - 1], l: "image", z: 0, x: V.width / 2, y: V.height / 2, s: 0.5 };
  }

  // The state a hash names; every field that is missing or does not parse takes its default.
  function parse(hash) {
    var p = new URLSearchParams(hash.replace(/^#/, "")), bad = [];
    var v = p.has("v") ? byId(M.views, p.get("v")) : 0;
    if (v < 0) { bad.push("v"); v = 0; }
    var s = defaults(v), V = M.views[v];
    var num = function (k, lo, hi) {
      if (!p.has(k)) { return null; }
      var x = Number(p.get(k));
      if (p.get(k) === "" || !isFinite(x) || x < lo || x > hi) { bad.push(k); return null; }
      return x;
    };
    if (p.has("a")) { var a = byId(V.series, p.get("a")); if (a < 0) { bad.push("a"); } else { s.a = a; } }
    if (p.has("b")) {
      var b = p.get("b") === "ref" ? -1 : byId(V.series, p.get("b"));
      if (b < 0 && p.get("b") !== "ref") { bad.push("b"); } else { s.b = b; }
    }
    var f = num("f", 1, 1e9);
    if (f !== null) { if (V.frames.indexOf(f) < 0) { bad.push("f"); } else { s.f = f; } }
    if (p.has("l")) { if (LAYERS.indexOf(p.get("l")) < 0) { bad.push("l"); } else { s.l = p.get("l"); } }
    if (p.has("z") && p.get("z") !== "fit") { var z = num("z", MIN_ZOOM, MAX_ZOOM); if (z !== null) { s.z = z; } }
    var x = num("x", 0, V.width), y = num("y", 0, V.height), sp = num("s", 0, 1);
    if (x !== null) { s.x = x; }
    if (y !== null) { s.y = y; }
    if (sp !== null) { s.s = sp; }
    if (s.l === "flip" && !hasFlip(s, V)) { bad.push("l"); s.l = "image"; }
    s.bad = bad;
    return s;
  }
  function hasFlip(s, V) { return V.series.length > 0 && !!at(V.series[s.a].frames, s.f).flip; }
  function hash() {
    var V = view(), r = function (x) { return Math.round(x * 100) / 100; };
    return "#v=" + encodeURIComponent(V.id) + "&a=" + encodeURIComponent(V.series[st.a].id) +
      "&b=" + (st.b < 0 ? "ref" : encodeURIComponent(V.series[st.b].id)) + "&f=" + st.f + "&l=" + st.l +
      "&z=" + (st.z ? r(st.z) : "fit") + "&x=" + r(st.x) + "&y=" + r(st.y) + "&s=" + r(st.s);
  }
  function save() {
    var h = hash();
    if (location.hash !== h) { history.replaceState(null, "", h); }
    $("viewer-link").href = h;
  }

  // What one side shows: its file and its caption.
  function side(i) {
    var V = view(), ref = at(V.reference, st.f);
    if (i < 0) { return { src: ref.image, text: "reference" + (V.reference.length > 1 ? ", frame " + ref.frame : "") }; }
    var S = V.series[i], F = at(S.frames, st.f), layer = st.l === "flip" && !F.flip ? "image" : st.l;
    var text = S.label + (V.frames.length > 1 ? ", frame " + F.frame : "") + ": RMSE " + F.rmse.toFixed(4);
    if (F.flip_mean !== null && F.flip_mean !== undefined) { text += ", FLIP " + F.flip_mean.toFixed(4); }
    return { src: F[layer], text: text + (layer !== "image" ? " (" + layer + ")" : "") };
  }

  function fitZoom() {
    var V = view();
    return Math.min(stage.clientWidth / V.width, stage.clientHeight / V.height);
  }
  function zoom() { return st.z || fitZoom(); }
  function place() {
    var V = view();
    // Over the whole window the stage takes what the controls leave; on the page 80 % of its height.
    var room = root.classList.contains("focus") ? window.innerHeight - (stage.getBoundingClientRect().top - root.getBoundingClientRect().top) - 70 : 0.8 * window.innerHeight;
    stage.style.height = Math.round(Math.max(120, Math.min(room, stage.clientWidth * V.height / V.width))) + "px";
    var z = zoom(), W = stage.clientWidth, H = stage.clientHeight;
    var x = st.z ? st.x : V.width / 2, y = st.z ? st.y : V.height / 2;
    [imgA, imgB].forEach(function (img) {
      img.style.width = V.width * z + "px";
      img.style.height = V.height * z + "px";
      img.style.left = W / 2 - x * z + "px";
      img.style.top = H / 2 - y * z + "px";
    });
    var sx = Math.round(st.s * W);
    clipB.style.clipPath = "inset(0 0 0 " + sx + "px)";
    line.style.left = sx - 1 + "px";
    $("viewer-zoom").textContent = st.z ? (z >= 1 ? z.toFixed(1) + " screen px per pixel" : (100 * z).toFixed(0) + " %") : "fit";
  }
  function legend() {
    var V = view(), L = $("viewer-legend");
    var fa = at(V.series[st.a].frames, st.f), fb = st.b < 0 ? fa : at(V.series[st.b].frames, st.f);
    var e = fa.error_scale.toPrecision(3), eb = fb.error_scale.toPrecision(3);
    var bar = { image: M.gradients.image, error: M.gradients.error, flip: M.gradients.flip }[st.l];
    var ends = {
      image: ["0 (occluded)", "1 (open)"],
      error: ["−" + e + " (too dark)", "+" + e + " (too bright)" + (eb !== e ? "; right: ±" + eb : "")],
      flip: ["0 (no visible difference)", "1"]
    }[st.l];
    $("viewer-bar").style.background = bar;
    $("viewer-lo").textContent = ends[0];
    $("viewer-hi").textContent = ends[1];
    L.setAttribute("data-layer", st.l);
    $("viewer-legend-text").textContent = {
      image: "AO, linear grey; slate = no surface.",
      error: "image − reference, one symmetric scale for every image of this view at this frame (the 99th percentile of |error|); slate = no surface.",
      flip: M.flip_note + " against the reference; slate = no surface."
    }[st.l];
  }
  function options(sel, list, withRef) {
    sel.innerHTML = "";
    list.forEach(function (x, i) { sel.add(new Option(x.label || x.title, String(i))); });
    if (withRef) { sel.add(new Option("reference", "-1")); }
  }
  function render() {
    var V = view(), A = side(st.a), B = side(st.b);
    if (imgA.getAttribute("src") !== A.src) { imgA.src = A.src; }
    if (imgB.getAttribute("src") !== B.src) { imgB.src = B.src; }
    imgA.alt = A.text;
    imgB.alt = B.text;
    $("viewer-label-a").textContent = "◀ " + A.text;
    $("viewer-label-b").textContent = B.text + " ▶";
    $("viewer-view").value = String(st.v);
    $("viewer-a").value = String(st.a);
    $("viewer-b").value = String(st.b);
    var fi = V.frames.indexOf(st.f);
    $("viewer-frame").textContent = V.frames.length > 1 ? "frame " + st.f + " (" + (fi + 1) + " of " + V.frames.length + ")" : "one frame";
    $("viewer-prev").disabled = fi <= 0;
    $("viewer-next").disabled = fi >= V.frames.length - 1;
    var flip = hasFlip(st, V);
    document.querySelectorAll("input[name=viewer-layer]").forEach(function (r) {
      r.checked = r.value === st.l;
      r.disabled = r.value === "flip" && !flip;
    });
    stage.setAttribute("data-state", hash().slice(1));
    place();
    legend();
    save();
  }
  function setView(v) {
    st = defaults(v);
    options($("viewer-a"), view().series, false);
    options($("viewer-b"), view().series, true);
  }

  // Start from the URL's hash.
  options($("viewer-view"), M.views, false);
  st = parse(location.hash);
  var start = st;
  setView(st.v);
  st = start;
  if (st.bad.length) {
    $("viewer-note").textContent = "The link's " + st.bad.join(", ") + " did not name anything here; shown with the defaults instead.";
  }
  // A link to a view opens it over the whole window (the page is long; a link is sent for the view).
  var focus = function (on) { root.classList.toggle("focus", on); $("viewer-focus").textContent = on ? "back to the page" : "whole window"; place(); };
  $("viewer-focus").onclick = function () { focus(!root.classList.contains("focus")); };
  if (/(^|[#&])v=/.test(location.hash)) { focus(true); }

  $("viewer-view").onchange = function () { setView(Number(this.value)); render(); };
  $("viewer-a").onchange = function () { st.a = Number(this.value); render(); };
  $("viewer-b").onchange = function () { st.b = Number(this.value); render(); };
  document.querySelectorAll("input[name=viewer-layer]").forEach(function (r) {
    r.onchange = function () { st.l = this.value; render(); };
  });
  var step = function (d) {
    var F = view().frames, i = F.indexOf(st.f) + d;
    if (i >= 0 && i < F.length) { st.f = F[i]; render(); }
  };
  $("viewer-prev").onclick = function () { step(-1); };
  $("viewer-next").onclick = function () { step(1); };
  // Zooms by `k` keeping the image point under (px, py) of the stage where it is.
  function zoomBy(k, px, py) {
    var z = zoom(), V = view(), W = stage.clientWidth, H = stage.clientHeight;
    var x = st.z ? st.x : V.width / 2, y = st.z ? st.y : V.height / 2;
    var ix = x + (px - W / 2) / z, iy = y + (py - H / 2) / z;
    var nz = Math.min(MAX_ZOOM, Math.max(MIN_ZOOM, z * k));
    st.z = nz;
    st.x = Math.min(V.width, Math.max(0, ix - (px - W / 2) / nz));
    st.y = Math.min(V.height, Math.max(0, iy - (py - H / 2) / nz));
    render();
  }
  $("viewer-zoom-in").onclick = function () { zoomBy(2, stage.clientWidth / 2, stage.clientHeight / 2); };
  $("viewer-zoom-out").onclick = function () { zoomBy(0.5, stage.clientWidth / 2, stage.clientHeight / 2); };
  $("viewer-zoom-fit").onclick = function () { st.z = 0; render(); };
  stage.addEventListener("wheel", function (e) {
    e.preventDefault();
    var r = stage.getBoundingClientRect();
    zoomBy(e.deltaY < 0 ? 1.25 : 0.8, e.clientX - r.left, e.clientY - r.top);
  }, { passive: false });
  // Dragging near the split moves it; anywhere else it pans the zoomed image.
  var drag = null;
  stage.addEventListener("pointerdown", function (e) {
    var r = stage.getBoundingClientRect(), px = e.clientX - r.left;
    drag = { split: Math.abs(px - st.s * stage.clientWidth) < 12 || !st.z, x: e.clientX, y: e.clientY };
    stage.setPointerCapture(e.pointerId);
    if (drag.split) { st.s = Math.min(1, Math.max(0, px / stage.clientWidth)); place(); }
  });
  stage.addEventListener("pointermove", function (e) {
    var r = stage.getBoundingClientRect(), V = view();
    var px = Math.floor((st.z ? st.x : V.width / 2) + (e.clientX - r.left - stage.clientWidth / 2) / zoom());
    var py = Math.floor((st.z ? st.y : V.height / 2) + (e.clientY - r.top - stage.clientHeight / 2) / zoom());
    $("viewer-pixel").textContent = px >= 0 && py >= 0 && px < V.width && py < V.height ? "pixel (" + px + ", " + py + ")" : "";
    if (!drag) { return; }
    if (drag.split) {
      st.s = Math.min(1, Math.max(0, (e.clientX - r.left) / stage.clientWidth));
    } else {
      st.x = Math.min(V.width, Math.max(0, st.x - (e.clientX - drag.x) / zoom()));
      st.y = Math.min(V.height, Math.max(0, st.y - (e.clientY - drag.y) / zoom()));
      drag.x = e.clientX;
      drag.y = e.clientY;
    }
    place();
  });
  var end = function () { if (drag) { drag = null; render(); } };
  stage.addEventListener("pointerup", end);
  stage.addEventListener("pointercancel", end);
  window.addEventListener("resize", place);
  window.addEventListener("hashchange", function () {
    if (location.hash === hash()) { return; }
    var s = parse(location.hash);
    setView(s.v);
    st = s;
    render();
  });
  render();
})();
