/* xnavlab: load the ipywidgets embed scripts only if the network allows.
 * myst-nb would put require.js and @jupyter-widgets/html-manager (from CDNs) in the
 * page head; offline that leaves nothing rendered and, once require.js half-loads,
 * JavaScript errors. Here they are optional: online, the stored widget state renders
 * (without a kernel); offline, nothing is fetched and the page is complete without them
 * (the book's kernel-free scrubbers carry the interactivity). See book/_ext/xnav_offline.py.
 */
(function () {
  "use strict";
  var REQUIRE = "https://cdnjs.cloudflare.com/ajax/libs/require.js/2.3.4/require.min.js";
  var EMBED = "https://cdn.jsdelivr.net/npm/@jupyter-widgets/html-manager@1.0.6/dist/embed-amd.js";
  var CDN = "https://cdn.jsdelivr.net/npm/";
  function add(src, attrs, onload) {
    var s = document.createElement("script");
    s.src = src;
    s.crossOrigin = "anonymous";
    for (var k in attrs) { s.setAttribute(k, attrs[k]); }
    s.onload = onload || null;
    s.onerror = function () { /* offline or blocked: the page does not need it */ };
    document.head.appendChild(s);
  }
  try {
    if (!navigator.onLine || window.location.protocol === "file:") { return; }
    add(REQUIRE, {}, function () {
      if (typeof window.define !== "function") { return; }
      add(EMBED, { "data-jupyter-widgets-cdn": CDN });
    });
  } catch (e) { /* never break the page */ }
})();
