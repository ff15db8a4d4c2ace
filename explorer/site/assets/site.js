// lpv-explorer course site: swipe comparisons, image sequences with Play, predict-then-
// press, tap-to-show tooltips and glossary popovers. No framework; the pages read without
// it (the stylesheet lays a swipe's pictures side by side under .no-js).
(function () {
  "use strict";
  document.documentElement.classList.remove("no-js");
  document.documentElement.classList.add("js");

  function swipe(root) {
    var range = root.querySelector("input[type=range]");
    var labels = root.querySelectorAll(".tag");
    var before = labels[0].textContent, after = labels[1].textContent;
    function show() {
      root.style.setProperty("--pos", range.value + "%");
      var v = parseInt(range.value, 10);
      range.setAttribute("aria-valuetext", v <= 0 ? "all " + after : v >= 100 ? "all " + before
        : v + " % " + before + " on the left, the rest " + after);
    }
    range.addEventListener("input", show);
    show();
  }

  // A sequence's frames are fetched when the reader first uses it (data-src -> src).
  function fetchFrames(frames) {
    frames.forEach(function (img) {
      var src = img.getAttribute("data-src");
      if (src) {
        if (img.getAttribute("data-srcset")) { img.srcset = img.getAttribute("data-srcset"); }
        img.src = src;
        img.removeAttribute("data-src");
        img.removeAttribute("data-srcset");
      }
    });
  }

  function sequence(root) {
    var frames = root.querySelectorAll(".frames img");
    var range = root.querySelector("input[type=range]");
    var output = root.querySelector("output");
    var play = root.querySelector("button.play");
    var rate = parseFloat(root.getAttribute("data-rate") || "3");
    var timer = null;
    var all = Array.prototype.slice.call(frames);
    play.hidden = false;
    function show(index) {
      fetchFrames([frames[index]]);
      for (var i = 0; i < frames.length; i++) { frames[i].hidden = i !== index; }
      range.value = String(index);
      var label = frames[index].getAttribute("data-label");
      output.textContent = label;
      range.setAttribute("aria-valuetext", label);
    }
    function warm() { fetchFrames(all); }
    range.addEventListener("focus", warm);
    range.addEventListener("pointerdown", warm);
    play.addEventListener("pointerenter", warm);
    function stop() {
      if (timer !== null) { clearInterval(timer); timer = null; }
      play.textContent = "Play";
    }
    range.addEventListener("input", function () { stop(); show(parseInt(range.value, 10)); });
    play.addEventListener("click", function () {
      warm();
      if (timer !== null) { stop(); return; }
      var index = parseInt(range.value, 10);
      if (index >= frames.length - 1) { index = 0; show(0); }
      play.textContent = "Pause";
      timer = setInterval(function () {
        index += 1;
        show(index);
        if (index >= frames.length - 1) { stop(); }
      }, 1000 / rate);
    });
    show(parseInt(range.value, 10));
  }

  // "Predict, then press": the change and what it did show once a choice is picked.
  function predict(root) {
    var reveal = root.querySelector(".reveal");
    var verdict = root.querySelector(".verdict");
    var buttons = root.querySelectorAll("button.choice");
    var answer = parseInt(root.getAttribute("data-answer"), 10);
    var right = buttons[answer - 1].textContent;
    reveal.hidden = true;
    buttons.forEach(function (button) {
      button.addEventListener("click", function () {
        var guess = parseInt(button.getAttribute("data-choice"), 10);
        verdict.textContent = guess === answer ? "You predicted " + right + ": right."
          : "You predicted " + button.textContent + "; the answer is " + right + ".";
        buttons.forEach(function (other) { other.disabled = true; });
        button.classList.add("chosen");
        reveal.hidden = false;
      });
    });
  }

  // A tooltip that also works by touch and keyboard: the live numbers' title text, a
  // glossary term's definition (the <dd> its aria-describedby names).
  var tip = null;
  function hideTip() { if (tip) { tip.remove(); tip = null; } }
  function showTip(target) {
    hideTip();
    var described = target.getAttribute("aria-describedby");
    var definition = described ? document.getElementById(described) : null;
    var text = target.getAttribute("data-tip") || target.getAttribute("title") ||
      (definition ? target.textContent.trim() + ": " + definition.textContent : "");
    if (!text) { return; }
    target.setAttribute("data-tip", text);
    target.removeAttribute("title");
    tip = document.createElement("div");
    tip.className = "tip";
    tip.setAttribute("role", "tooltip");
    tip.textContent = text;
    document.body.appendChild(tip);
    var box = target.getBoundingClientRect();
    var width = tip.offsetWidth;
    var left = Math.max(8, Math.min(window.scrollX + box.left,
                                    window.scrollX + document.documentElement.clientWidth - width - 8));
    tip.style.left = left + "px";
    tip.style.top = (window.scrollY + box.bottom + 6) + "px";
  }
  // A plot's point or bar: its <title> (what a mouse shows on hover) on a tap too.
  function showTitle(target) {
    var title = target.querySelector("title");
    if (!title) { return false; }
    target.setAttribute("data-tip", title.textContent);
    showTip(target);
    return true;
  }
  document.addEventListener("click", function (event) {
    var target = event.target;
    var live = target.closest ? target.closest(".live") : null;
    if (live) { showTip(live); return; }
    var term = target.closest ? target.closest("a.term") : null;
    if (term) { event.preventDefault(); showTip(term); return; }
    if (target.closest && target.closest("svg.plot") && showTitle(target)) { return; }
    hideTip();
  });
  document.addEventListener("focusin", function (event) {
    var classes = event.target.classList;
    if (classes && (classes.contains("live") || classes.contains("term"))) {
      showTip(event.target);
    } else if (tip) { hideTip(); }
  });
  document.addEventListener("mouseover", function (event) {
    var term = event.target.closest ? event.target.closest("a.term") : null;
    if (term) { showTip(term); }
  });
  // Display math and tables wider than the column scroll: make those reachable from the
  // keyboard (arrow keys scroll a focused region).
  function scrollable() {
    document.querySelectorAll(".display-math, .long-math, .table-wrap").forEach(function (box) {
      if (box.scrollWidth > box.clientWidth + 1) {
        box.setAttribute("tabindex", "0");
        box.setAttribute("role", "region");
        box.setAttribute("aria-label", box.classList.contains("table-wrap")
          ? "Table, scrolls sideways" : "Formula, scrolls sideways");
      } else if (box.getAttribute("role") === "region") {
        box.removeAttribute("tabindex");
        box.removeAttribute("role");
        box.removeAttribute("aria-label");
      }
    });
  }
  window.addEventListener("resize", scrollable);
  window.addEventListener("load", scrollable);
  document.addEventListener("keydown", function (event) {
    if (event.key === "Escape") { hideTip(); }
  });

  document.querySelectorAll("[data-swipe]").forEach(swipe);
  document.querySelectorAll("[data-sequence]").forEach(sequence);
  document.querySelectorAll("[data-predict]").forEach(predict);
})();
