// The live figures' entry: every figure the build marked live (data-live-kind) gets its
// module mounted in place of the baked picture, which stays the page's picture without
// JavaScript (or where a module fails to load).
const MODULES = {
  "clamped-cosine": "cosine", "cell-faces": "faces", "rsm-texel": "texel",
  "pipeline": "pipeline", "propagation-stepper": "stepper",
};

async function start(root) {
  const name = MODULES[root.dataset.liveKind];
  if (!name) { return; }
  const module = await import(`lpv/figures/${name}.js`);
  const params = JSON.parse(root.dataset.params);
  const figure = root.closest("figure");
  root.hidden = false;                    // shown first: a figure measures its width
  try {
    module.mount(root.querySelector(".live-mount"), params);
  } catch (error) {
    root.hidden = true;
    throw error;
  }
  const baked = figure ? figure.querySelector(":scope > .baked") : null;
  if (baked) { baked.remove(); }
  if (figure) { figure.classList.add("is-live"); }
}

await window.LPV_STYLE_READY;             // the figures measure their width once styled
for (const root of document.querySelectorAll("[data-live-kind]")) {
  start(root).catch((error) => { console.warn("live figure not started:", error); });
}
