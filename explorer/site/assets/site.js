// lpv-explorer course site: swipe comparisons, image sequences with Play, predict-then-
// press and tap-to-show tooltips. No framework; the pages read without it.
(function () {
  "use strict";

  function swipe(root) {
    var range = root.querySelector("input[type=range]");
    function show() { root.style.setProperty("--pos", range.value + "%"); }
    range.addEventListener("input", show);
    show();
  }

  function sequence(root) {
    var frames = root.querySelectorAll(".frames img");
    var range = root.querySelector("input[type=range]");
    var output = root.querySelector("output");
    var play = root.querySelector("button.play");
    var rate = parseFloat(root.getAttribute("data-rate") || "3");
    var timer = null;
    function show(index) {
      for (var i = 0; i < frames.length; i++) { frames[i].hidden = i !== index; }
      range.value = String(index);
      output.textContent = frames[index].getAttribute("data-label");
    }
    function stop() {
      if (timer !== null) { clearInterval(timer); timer = null; }
      play.textContent = "Play";
    }
    range.addEventListener("input", function () { stop(); show(parseInt(range.value, 10)); });
    play.addEventListener("click", function () {
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

  // A tooltip that also works by touch and keyboard: the live numbers' title text.
  var tip = null;
  function hideTip() { if (tip) { tip.remove(); tip = null; } }
  function showTip(target) {
    hideTip();
    var text = target.getAttribute("data-tip") || target.getAttribute("title");
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
    if (target.closest && target.closest("svg.plot") && showTitle(target)) { return; }
    hideTip();
  });
  document.addEventListener("focusin", function (event) {
    if (event.target.classList && event.target.classList.contains("live")) {
      showTip(event.target);
    }
  });
  document.addEventListener("keydown", function (event) {
    if (event.key === "Escape") { hideTip(); }
  });

  document.querySelectorAll("[data-swipe]").forEach(swipe);
  document.querySelectorAll("[data-sequence]").forEach(sequence);
  document.querySelectorAll("[data-predict]").forEach(predict);
})();
