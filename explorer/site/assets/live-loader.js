// Starts the live figures (assets/figures/live.js and the ES modules it imports). Pages
// read from file:// cannot fetch modules (browsers refuse cross-origin module loads from
// file URLs), so there the modules the build packed into LPV_MODULES are imported from
// data: URLs through an import map; from a web server the import map points at the
// module files themselves. Either way the specifiers are "lpv/<path under assets/>".
(function () {
  "use strict";
  if (!document.querySelector("[data-live-kind]") || !window.HTMLScriptElement
      || !HTMLScriptElement.supports || !HTMLScriptElement.supports("importmap")) {
    return;                               // the baked pictures stay
  }
  var here = document.currentScript.src.replace(/[^/]*$/, "");
  var imports = {};
  if (location.protocol === "file:") {
    Object.keys(LPV_MODULES).forEach(function (name) {
      imports["lpv/" + name] = "data:text/javascript;charset=utf-8,"
        + encodeURIComponent(LPV_MODULES[name]);
    });
  } else {
    imports["lpv/"] = here;
  }
  var style = document.createElement("link");
  style.rel = "stylesheet";
  style.href = here + "live-figures.css";
  window.LPV_STYLE_READY = new Promise(function (done) {
    style.onload = style.onerror = done;
  });
  document.head.appendChild(style);
  var map = document.createElement("script");
  map.type = "importmap";
  map.textContent = JSON.stringify({ imports: imports });
  document.head.appendChild(map);
  var entry = document.createElement("script");
  entry.type = "module";
  entry.textContent = 'import "lpv/figures/live.js";';
  document.body.appendChild(entry);
})();
