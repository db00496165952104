// Shared by every page (the report and compare), inlined first in <head>.
// Installed first so the self-tests see every error of the page's scripts.
window.__pageErrors = [];
window.addEventListener("error", function (e) { window.__pageErrors.push("error: " + e.message); });
window.addEventListener("unhandledrejection", function (e) { window.__pageErrors.push("unhandled rejection: " + e.reason); });
(function () { var ce = console.error; console.error = function () { window.__pageErrors.push("console.error: " + Array.prototype.join.call(arguments, " ")); ce.apply(console, arguments); }; })();

// A self-test's verdict as JSON in a pre element (id selftest-result), which `chromium --dump-dom`
// prints for the browser tests; any error the page logged makes it a failure.
function report(result) {
  result.pageErrors = window.__pageErrors.slice();
  if (result.pageErrors.length) { result.ok = false; }
  var pre = document.createElement("pre");
  pre.id = "selftest-result";
  pre.textContent = JSON.stringify(result);
  document.body.appendChild(pre);
}

// Whether an element sits in a container that scrolls or clips sideways (a wide table may
// scroll inside its own box; the page itself must not).
function clipped(el) {
  for (var p = el.parentElement; p && p !== document.body; p = p.parentElement) {
    if (getComputedStyle(p).overflowX !== "visible") return true;
  }
  return false;
}
function describe(el) {
  return el.tagName.toLowerCase() + (el.id ? "#" + el.id : "") + (el.className && typeof el.className === "string" ? "." + el.className.trim().split(/\s+/).join(".") : "");
}
// #layout: does the page fit the window without scrolling sideways? Lists the elements that
// stick out (outermost first), the boxes that scroll sideways inside the page (named by their
// first child), and counts the selectors named in <body data-selfcheck="…">.
function layoutCheck() {
  var de = document.documentElement, width = de.clientWidth, out = [];
  document.querySelectorAll("body *").forEach(function (el) {
    var r = el.getBoundingClientRect();
    if (r.right > width + 0.5 && out.length < 12 && !clipped(el)) out.push(describe(el) + " right " + Math.round(r.right));
  });
  // Boxes that scroll inside the page (allowed where a table cannot fit, but listed).
  var scrolling = [];
  document.querySelectorAll("body *").forEach(function (el) {
    var o = getComputedStyle(el).overflowX;
    if ((o === "auto" || o === "scroll") && el.scrollWidth > el.clientWidth) scrolling.push(describe(el.firstElementChild || el));
  });
  var counts = {};
  (document.body.dataset.selfcheck || "").split(",").filter(Boolean).forEach(function (s) { counts[s] = document.querySelectorAll(s).length; });
  return {
    scrollWidth: de.scrollWidth, clientWidth: width, innerWidth: window.innerWidth,
    fits: de.scrollWidth <= width && de.scrollWidth <= window.innerWidth,
    overflowing: out, scrolling: scrolling, counts: counts
  };
}
if (location.hash === "#layout") window.addEventListener("load", function () {
  setTimeout(function () { var l = layoutCheck(); report({ ok: l.fits, layout: l }); }, 0);
});
