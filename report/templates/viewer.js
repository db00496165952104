// scatterbench report: metric switch, in-place image viewer, self-test. Inlined into the page
// (no network; works from file://). Must not contain the CDATA end marker.
"use strict";

// ---- metric switch: the body's class picks which "mv-<metric>" elements show (CSS) ----
document.addEventListener("click", function (e) {
  var b = e.target.closest ? e.target.closest("button[data-metric]") : null;
  if (!b) return;
  document.body.className = document.body.className.replace(/metric-[a-z_]+/, "metric-" + b.dataset.metric);
  document.querySelectorAll("button[data-metric]").forEach(function (x) { x.classList.toggle("on", x === b); });
});

// ---- image data: half floats, delta-coded planes, zlib, base64 (see report/src/viewer.rs) ----
var HALF = (function () {
  var t = new Float32Array(65536);
  for (var h = 0; h < 65536; h++) {
    var s = h & 0x8000 ? -1 : 1, e = (h >> 10) & 31, m = h & 1023;
    t[h] = e === 0 ? s * m * Math.pow(2, -24) : e === 31 ? (m ? NaN : s * Infinity) : s * (1 + m / 1024) * Math.pow(2, e - 15);
  }
  return t;
})();

var decoded = {};
function decodeImage(id) {
  if (decoded[id]) return decoded[id];
  var el = document.getElementById(id);
  if (!el) return (decoded[id] = Promise.resolve(null));
  var w = +el.dataset.w, h = +el.dataset.h, scale = Math.pow(2, +el.dataset.k);
  var bin = atob(el.textContent.trim());
  var bytes = new Uint8Array(bin.length);
  for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
  var stream = new Blob([bytes]).stream().pipeThrough(new DecompressionStream("deflate"));
  decoded[id] = new Response(stream).arrayBuffer().then(function (buf) {
    var b = new Uint8Array(buf), n = 3 * w * h;
    if (b.length !== 2 * n) throw new Error(id + ": " + b.length + " bytes, expected " + 2 * n);
    var rgb = new Float32Array(n); // interleaved RGB, row-major
    var k = 0;
    for (var c = 0; c < 3; c++) {
      for (var y = 0; y < h; y++) {
        var acc = 0;
        for (var x = 0; x < w; x++, k++) {
          acc = (acc + (b[k] | (b[n + k] << 8))) & 0xffff;
          rgb[3 * (y * w + x) + c] = HALF[acc] * scale;
        }
      }
    }
    return { w: w, h: h, rgb: rgb };
  });
  return decoded[id];
}

// ---- display transforms ----
function srgb(x) { return x <= 0.0031308 ? 12.92 * x : 1.055 * Math.pow(x, 1 / 2.4) - 0.055; }
function tone(v, gain) {
  // Same as harness ToneMap::apply: exposure, Reinhard, sRGB; non-finite shows magenta.
  if (!isFinite(v)) return -1;
  var x = Math.max(v * gain, 0);
  x = isFinite(x) ? x / (1 + x) : 1;
  return Math.round(Math.min(Math.max(srgb(x), 0), 1) * 255);
}
var VIRIDIS = [[68, 1, 84], [72, 40, 120], [62, 73, 137], [49, 104, 142], [38, 130, 142], [31, 158, 137], [53, 183, 121], [110, 206, 88], [181, 222, 43], [253, 231, 37]];
function viridis(t) {
  t = Math.min(Math.max(t, 0), 1) * (VIRIDIS.length - 1);
  var i = Math.min(Math.floor(t), VIRIDIS.length - 2), f = t - i;
  return [0, 1, 2].map(function (c) { return Math.round(VIRIDIS[i][c] + (VIRIDIS[i + 1][c] - VIRIDIS[i][c]) * f); });
}
function lum(r, g, b) { return 0.2126 * r + 0.7152 * g + 0.0722 * b; }

// ---- one viewer per scene ----
function Viewer(root) {
  this.root = root;
  this.canvas = root.querySelector("canvas");
  this.ctx = this.canvas.getContext("2d");
  this.gain = Math.pow(2, +root.dataset.exposure || 0);
  this.errScale = +root.dataset.errorScale || 0;
  this.items = Array.prototype.map.call(root.querySelectorAll(".vlist li"), function (li) { return li; });
  this.scene = root.parentNode.id;
  this.aov = 0; this.a = 0; this.b = Math.min(1, this.items.length - 1); this.errorMode = false;
  this.zoom = 0; this.ox = 0; this.oy = 0; // display px per image px; image coords at the canvas origin
  this.cursor = null; this.images = {};
  var v = this;
  root.querySelector(".va").addEventListener("change", function (e) { v.show(+e.target.value, v.b); });
  root.querySelector(".vb").addEventListener("change", function (e) { v.show(v.a, +e.target.value); });
  root.querySelector(".vaov").addEventListener("change", function (e) { v.aov = +e.target.value; v.show(v.a, v.b); });
  this.items.forEach(function (li) { li.addEventListener("click", function () { v.pick(+li.dataset.i); root.focus(); }); });
  root.addEventListener("keydown", function (e) { if (v.key(e.key)) e.preventDefault(); });
  this.canvas.addEventListener("mousemove", function (e) { v.move(e); });
  this.canvas.addEventListener("mouseleave", function () { v.cursor = null; v.readout(); });
  this.canvas.addEventListener("wheel", function (e) { e.preventDefault(); v.zoomAt(e.deltaY < 0 ? 2 : 0.5, v.local(e)); }, { passive: false });
  this.canvas.addEventListener("mousedown", function (e) { v.drag = { x: e.clientX, y: e.clientY, ox: v.ox, oy: v.oy }; root.focus(); });
  window.addEventListener("mouseup", function () { v.drag = null; });
  window.addEventListener("mousemove", function (e) {
    if (!v.drag) return;
    v.ox = v.drag.ox - (e.clientX - v.drag.x) / v.zoom; v.oy = v.drag.oy - (e.clientY - v.drag.y) / v.zoom; v.draw();
  });
}
Viewer.prototype.id = function (i, aov) { return this.scene + "-img" + i + "-" + aov; };
Viewer.prototype.load = function (i) {
  var v = this, key = i + ":" + this.aov;
  if (!this.images[key]) this.images[key] = decodeImage(this.id(i, this.aov)).then(function (img) { return img; });
  return this.images[key];
};
// Shows image a (with b as the comparison); resolves when drawn.
Viewer.prototype.show = function (a, b) {
  var v = this;
  this.a = a; this.b = b;
  this.root.querySelector(".va").value = a; this.root.querySelector(".vb").value = b;
  this.items.forEach(function (li, i) { li.classList.toggle("a", i === a); li.classList.toggle("b", i === b); });
  return Promise.all([this.load(a), this.load(b)]).then(function (imgs) {
    v.imgA = imgs[0]; v.imgB = imgs[1];
    if (v.imgA && !v.zoom) v.fit();
    v.render(); v.draw(); v.readout();
  });
};
Viewer.prototype.pick = function (i) {
  if (i < 0 || i >= this.items.length) return Promise.resolve();
  this.errorMode = false;
  return i === this.a ? this.show(this.a, this.b) : this.show(i, this.a);
};
Viewer.prototype.key = function (k) {
  if (k === "r" || k === "R") { this.pick(0); return true; }
  if (/^[1-9]$/.test(k)) { this.pick(+k); return true; }
  if (k === "f" || k === "F" || k === " ") { this.show(this.b, this.a); return true; }
  if (k === "e" || k === "E") { this.errorMode = !this.errorMode; this.render(); this.draw(); this.readout(); return true; }
  if (k === "+" || k === "=") { this.zoomAt(2, this.cursor || this.center()); return true; }
  if (k === "-") { this.zoomAt(0.5, this.cursor || this.center()); return true; }
  if (k === "0") { this.fit(); this.draw(); return true; }
  return false;
};
Viewer.prototype.fit = function () {
  var img = this.imgA; if (!img) return;
  var z = Math.min(this.canvas.width / img.w, this.canvas.height / img.h);
  this.zoom = z >= 1 ? Math.floor(z) : z;
  this.ox = -(this.canvas.width / this.zoom - img.w) / 2; this.oy = -(this.canvas.height / this.zoom - img.h) / 2;
};
Viewer.prototype.center = function () { return { x: this.canvas.width / 2, y: this.canvas.height / 2 }; };
Viewer.prototype.local = function (e) {
  var r = this.canvas.getBoundingClientRect();
  return { x: (e.clientX - r.left) * this.canvas.width / r.width, y: (e.clientY - r.top) * this.canvas.height / r.height };
};
// Zooms by factor f keeping the image point under canvas position p fixed.
Viewer.prototype.zoomAt = function (f, p) {
  var z = Math.min(Math.max(this.zoom * f, 0.25), 64);
  var ix = this.ox + p.x / this.zoom, iy = this.oy + p.y / this.zoom;
  this.zoom = z; this.ox = ix - p.x / z; this.oy = iy - p.y / z;
  this.draw(); this.readout();
};
// The shown image (A, or the error map |A - B|) tone-mapped into an offscreen canvas.
Viewer.prototype.render = function () {
  var A = this.imgA, B = this.imgB; if (!A) return;
  var off = this.off || (this.off = document.createElement("canvas"));
  off.width = A.w; off.height = A.h;
  var octx = off.getContext("2d"), id = octx.createImageData(A.w, A.h), d = id.data;
  for (var p = 0; p < A.w * A.h; p++) {
    var r = A.rgb[3 * p], g = A.rgb[3 * p + 1], b = A.rgb[3 * p + 2], out;
    if (this.errorMode && B) {
      var e = lum(Math.abs(r - B.rgb[3 * p]), Math.abs(g - B.rgb[3 * p + 1]), Math.abs(b - B.rgb[3 * p + 2]));
      out = isFinite(e) ? viridis(this.errScale > 0 ? e / this.errScale : (e > 0 ? 1 : 0)) : [255, 255, 255];
    } else {
      out = [tone(r, this.gain), tone(g, this.gain), tone(b, this.gain)];
      if (out[0] < 0 || out[1] < 0 || out[2] < 0) out = [255, 0, 255];
    }
    d[4 * p] = out[0]; d[4 * p + 1] = out[1]; d[4 * p + 2] = out[2]; d[4 * p + 3] = 255;
  }
  octx.putImageData(id, 0, 0);
  var lbl = this.items[this.a].textContent.trim();
  this.root.querySelector(".vshown").textContent = this.errorMode ? "error |A − B|" : "showing A: " + lbl;
};
Viewer.prototype.draw = function () {
  var c = this.ctx;
  c.setTransform(1, 0, 0, 1, 0, 0);
  c.fillStyle = "#333"; c.fillRect(0, 0, this.canvas.width, this.canvas.height);
  if (!this.off) return;
  c.imageSmoothingEnabled = false;
  c.setTransform(this.zoom, 0, 0, this.zoom, -this.ox * this.zoom, -this.oy * this.zoom);
  c.drawImage(this.off, 0, 0);
  c.setTransform(1, 0, 0, 1, 0, 0);
  this.root.querySelector(".vzoom").textContent = (this.zoom >= 1 ? this.zoom.toFixed(0) : this.zoom.toFixed(2)) + "×";
};
Viewer.prototype.pixelAt = function (p) {
  return { x: Math.floor(this.ox + p.x / this.zoom), y: Math.floor(this.oy + p.y / this.zoom) };
};
Viewer.prototype.move = function (e) { this.cursor = this.local(e); this.readout(); };
function fmt(v) { return isFinite(v) ? v.toPrecision(5) : String(v); }
Viewer.prototype.readout = function () {
  var el = this.root.querySelector(".readout");
  if (!this.cursor || !this.imgA) { el.textContent = "move the cursor over the image"; this.last = null; return; }
  var q = this.pixelAt(this.cursor), A = this.imgA, B = this.imgB;
  if (q.x < 0 || q.y < 0 || q.x >= A.w || q.y >= A.h) { el.textContent = "outside the image"; this.last = null; return; }
  var i = 3 * (q.y * A.w + q.x);
  var va = [A.rgb[i], A.rgb[i + 1], A.rgb[i + 2]], vb = B ? [B.rgb[i], B.rgb[i + 1], B.rgb[i + 2]] : null;
  var la = this.items[this.a].textContent.trim().split(" ")[1] || "", lb = this.items[this.b].textContent.trim().split(" ")[1] || "";
  this.last = { x: q.x, y: q.y, a: va, b: vb, labelA: this.items[this.a].textContent, labelB: this.items[this.b].textContent };
  el.textContent = "pixel (" + q.x + ", " + q.y + ")  linear RGB\nA " + va.map(fmt).join(" ") + "  " + la +
    (vb ? "\nB " + vb.map(fmt).join(" ") + "  " + lb : "");
};

var viewers = [];
function setup() {
  document.querySelectorAll(".viewer").forEach(function (root) {
    var v = new Viewer(root);
    viewers.push(v);
    // Decode a scene's images only when its viewer comes near the screen: the page opens fast.
    var io = new IntersectionObserver(function (es) {
      if (es.some(function (e) { return e.isIntersecting; })) { io.disconnect(); v.show(v.a, v.b); }
    }, { rootMargin: "400px" });
    io.observe(root);
  });
  // #timing: how long the page took to open (navigation start to the load event's end).
  if (location.hash === "#timing") window.addEventListener("load", function () {
    setTimeout(function () { report({ ok: true, timing: openTiming() }); }, 0);
  });
  if (/^#selftest/.test(location.hash)) selftest(location.hash).catch(function (e) { report({ ok: false, failures: ["exception: " + e] }); });
}

// ---- self-test: drives the first viewer like a user and writes a JSON verdict into the DOM ----
function openTiming() {
  var t = performance.timing;
  return { domContentLoaded: t.domContentLoadedEventEnd - t.navigationStart, load: t.loadEventEnd - t.navigationStart };
}
function canvasRGB(v, q) {
  // The displayed colour at the centre of image pixel q.
  var cx = Math.floor((q.x + 0.5 - v.ox) * v.zoom), cy = Math.floor((q.y + 0.5 - v.oy) * v.zoom);
  var d = v.ctx.getImageData(cx, cy, 1, 1).data;
  return [d[0], d[1], d[2]];
}
function hover(v, q) {
  // A synthetic mouse move over the centre of image pixel q, through the real event path.
  var r = v.canvas.getBoundingClientRect();
  var cx = (q.x + 0.5 - v.ox) * v.zoom, cy = (q.y + 0.5 - v.oy) * v.zoom;
  v.canvas.dispatchEvent(new MouseEvent("mousemove", { clientX: r.left + cx * r.width / v.canvas.width, clientY: r.top + cy * r.height / v.canvas.height, bubbles: true }));
}
function press(v, k) { v.root.dispatchEvent(new KeyboardEvent("keydown", { key: k, bubbles: true })); }
function settle() { return new Promise(function (res) { setTimeout(res, 0); }); }
async function selftest(hash) {
  var m = /#selftest=(\d+),(\d+)/.exec(hash), fails = [], steps = [];
  var v = viewers[0];
  if (!v) return report({ ok: false, failures: ["no viewer on the page"] });
  var q = m ? { x: +m[1], y: +m[2] } : { x: 0, y: 0 };
  await v.show(0, 1);
  v.root.scrollIntoView();
  // Zoom 4× twice at the pixel: it must stay under the cursor (pixel-exact, nearest).
  var z0 = v.zoom;
  var at = { x: (q.x + 0.5 - v.ox) * v.zoom, y: (q.y + 0.5 - v.oy) * v.zoom };
  hover(v, q);
  v.canvas.dispatchEvent(new WheelEvent("wheel", { deltaY: -100, clientX: v.canvas.getBoundingClientRect().left + at.x, clientY: v.canvas.getBoundingClientRect().top + at.y, bubbles: true, cancelable: true }));
  press(v, "+");
  var z1 = v.zoom;
  if (!(z1 === 4 * z0)) fails.push("zoom went " + z0 + " -> " + z1 + ", expected 4x");
  var under = v.pixelAt(at);
  if (under.x !== q.x || under.y !== q.y) fails.push("zoom moved the pixel under the cursor to " + JSON.stringify(under));
  steps.push({ zoom: [z0, z1] });
  // Reference shown; read it out.
  hover(v, q);
  var ref = v.last, refShown = canvasRGB(v, q);
  // Flip to method 1 with its key.
  press(v, "1");
  await v.show(v.a, v.b);
  hover(v, q);
  var m1 = v.last, m1Shown = canvasRGB(v, q);
  if (v.a !== 1 || v.b !== 0) fails.push("key 1 gave A=" + v.a + " B=" + v.b);
  // F flips back to the reference in place.
  press(v, "F");
  await v.show(v.a, v.b);
  hover(v, q);
  var flipped = v.last, flippedShown = canvasRGB(v, q);
  if (v.a !== 0) fails.push("F did not flip back to the reference");
  // R and E: error mode toggles and leaves the selection.
  press(v, "E");
  var errShown = canvasRGB(v, q);
  press(v, "E");
  var readoutText = v.root.querySelector(".readout").textContent;
  report({
    ok: fails.length === 0, failures: fails, steps: steps, pixel: q, zoom: v.zoom,
    scene: v.scene, exposure: +v.root.dataset.exposure || 0, aov: v.root.querySelector(".vaov").selectedOptions[0].textContent,
    reference: { label: ref && ref.labelA, rgb: ref && ref.a, shown: refShown },
    method1: { label: m1 && m1.labelA, rgb: m1 && m1.a, comparedWith: m1 && m1.b, shown: m1Shown },
    flippedBack: { rgb: flipped && flipped.a, shown: flippedShown },
    errorShown: errShown, readout: readoutText,
    timing: openTiming()
  });
}
if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", setup); else setup();
