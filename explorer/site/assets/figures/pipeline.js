// The LPV pipeline at a glance: the window's figure (explorer/ui/figures/
// pipeline_overview.py) with the step's frame's numbers, which the build measured and
// baked into the page; hover, tap or focus a stage to read what it does.
import { el, shareOf, watts } from "lpv/figures/common.js";

// pipeline_overview._lines: what each stage holds, its flux, that flux as a share of
// the flux the shadow map reflects.
export function lines(values) {
  const n = Math.round(Math.cbrt(values.cells));
  const rsm = values.rsm_flux;
  const share = (name) => (rsm > 0 ? `${shareOf(values[name], rsm)} of RSM` : "");
  return {
    light: ["a spot light", "direct light", "+ one LPV bounce"],
    rsm: [`${Math.trunc(Math.sqrt(values.rsm_texels))}² texels`, watts(rsm), "reflected"],
    inject: [`${Math.trunc(values.vpls).toLocaleString("en-US")} VPLs → ${n}³`, watts(values.injected),
             share("injected")],
    propagate: [`×${Math.trunc(values.iterations)} steps`, `Σ ${watts(values.accumulated)}`, share("accumulated")],
    gather: ["pixels read the grid", watts(values.gathered), share("gathered")],
  };
}

export function mount(root, params) {
  const values = params.readouts;
  const body = el("div", { class: "live-body pipeline" }, root);
  const chain = el("ol", { class: "pipeline-chain" }, body);
  const text = el("p", { class: "pipeline-text", "aria-live": "polite" }, body);
  const state = { pinned: params.highlight, hovered: null };
  const stageLines = Object.keys(values).length ? lines(values) : null;
  const boxes = params.stages.map(([key, title, doc]) => {
    const item = el("li", {}, chain);
    const box = el("button", { type: "button", class: "stage", "data-stage": key }, item);
    el("strong", {}, box, title);
    (stageLines ? stageLines[key] : ["", "", ""]).forEach((line, index) => {
      el("span", { class: `line line${index}`, "data-line": String(index) }, box, line);
    });
    box.addEventListener("pointerenter", () => { state.hovered = key; update(); });
    box.addEventListener("pointerleave", () => { state.hovered = null; update(); });
    box.addEventListener("focus", () => { state.pinned = key; update(); });
    box.addEventListener("click", () => { state.pinned = key; update(); });
    box.addEventListener("keydown", (event) => {
      const step = { ArrowRight: 1, ArrowDown: 1, ArrowLeft: -1, ArrowUp: -1 }[event.key];
      if (!step) { return; }
      event.preventDefault();
      const keys = params.stages.map(([k]) => k);
      const next = (keys.indexOf(key) + step + keys.length) % keys.length;
      chain.querySelector(`[data-stage="${keys[next]}"]`).focus();
    });
    return [key, title, doc, box];
  });
  function update() {
    const shown = state.hovered || state.pinned;
    let said = "Hover, tap or focus a stage to read what it does.";
    for (const [key, title, doc, box] of boxes) {
      const lit = key === shown;
      box.classList.toggle("lit", lit);
      box.setAttribute("aria-pressed", String(key === state.pinned));
      if (lit) { said = `${title}: ${doc}`; }
    }
    text.textContent = said;
    if (!stageLines) { text.textContent += " The numbers fill in once the pipeline has run."; }
  }
  update();
}
