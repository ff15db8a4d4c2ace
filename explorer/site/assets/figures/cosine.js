// The clamped cosine around a normal n you drag, against its L1 and L2 projections: the
// window's figure (explorer/ui/figures/clamped_cosine.py) computed here the same way: the
// slice sampled every 0.5° from n, the tail's flux by the window's Gauss–Legendre rule in
// μ = ⟨n, ω⟩, the energy shares from the derivations.
import {
  BAND0_ENERGY_FRACTION, BAND1_ENERGY_FRACTION, BAND2_ENERGY_FRACTION,
  CLAMPED_COSINE_ENERGY, L1_ENERGY_FRACTION, L2_ENERGY_FRACTION, PI,
} from "lpv/generated/constants.js";
import {
  cosineLobe, degrees, dot, drag, el, fixed, gaussLegendre, percent, radians, readout,
  shBasis, show, slider, svg,
} from "lpv/figures/common.js";

const MU_NODES = 64;          // as clamped_cosine._MU_NODES
const CURVE_SAMPLES = 721;    // as clamped_cosine._CURVE_SAMPLES: 0.5° steps
const RADIUS = 1.25;
const BANDS = [BAND0_ENERGY_FRACTION, BAND1_ENERGY_FRACTION, BAND2_ENERGY_FRACTION];
const KEPT = { 0: 1, 1: L1_ENERGY_FRACTION, 2: L2_ENERGY_FRACTION };
const KEYS = { 0: "exact", 1: "l1", 2: "l2" };

export function sliceDirection(deg) {
  const a = radians(deg);
  return [Math.sin(a), Math.cos(a), 0];
}

function frame(n) {
  // clamped_cosine.sphere_quadrature's tangent: n × helper, normalised
  const helper = Math.abs(n[2]) < 0.9 ? [0, 0, 1] : [1, 0, 0];
  const t = [n[1] * helper[2] - n[2] * helper[1], n[2] * helper[0] - n[0] * helper[2],
             n[0] * helper[1] - n[1] * helper[0]];
  const length = Math.hypot(...t);
  return t.map((v) => v / length);
}

const [GL_NODES, GL_WEIGHTS] = gaussLegendre(MU_NODES);

// ∫ min(projection, 0) dω over the sphere, in the normal's frame: the projection depends
// on μ alone, so the window's rule (Gauss–Legendre on [−1, 0] and [0, 1], uniform in φ)
// sums to 2π times its μ part.
function negativeFlux(lobe, n, order) {
  const t = frame(n);
  const count = (order + 1) ** 2;
  let sum = 0;
  for (const half of [-1, 1]) {
    for (let i = 0; i < MU_NODES; i++) {
      const mu = (GL_NODES[i] + half) / 2;
      const s = Math.sqrt(Math.max(1 - mu * mu, 0));
      const direction = [0, 1, 2].map((k) => mu * n[k] + s * t[k]);
      const value = dot(shBasis(direction, 2).slice(0, count), lobe.slice(0, count));
      sum += (GL_WEIGHTS[i] / 2) * Math.min(value, 0);
    }
  }
  return 2 * PI * sum;
}

function evaluate(lobe, direction, order) {
  if (order === 0) { return Math.max(dot(direction, lobe.normal), 0); }
  const count = (order + 1) ** 2;
  return dot(shBasis(direction, 2).slice(0, count), lobe.coefficients.slice(0, count));
}

// Every number of the window's readouts() for this normal and probe.
export function numbers(normalDeg, probeDeg) {
  const n = sliceDirection(normalDeg);
  const lobe = { normal: n, coefficients: cosineLobe(n, 2) };
  const probe = sliceDirection(probeDeg);
  const start = Math.atan2(n[0], n[1]);
  const angles = [];
  for (let i = 0; i < CURVE_SAMPLES; i++) {
    angles.push(start + (2 * PI) * i / (CURVE_SAMPLES - 1));
  }
  const dirs = angles.map((a) => [Math.sin(a), Math.cos(a), 0]);
  const values = {
    normal_deg: normalDeg, probe_deg: probeDeg,
    probe_angle_deg: degrees(Math.acos(Math.min(Math.max(dot(probe, n), -1), 1))),
    lobe_energy: CLAMPED_COSINE_ENERGY, lobe_flux: PI,
  };
  BANDS.forEach((share, band) => { values[`band${band}_energy`] = share; });
  const curves = { angles, dirs };
  for (const order of [0, 1, 2]) {
    const key = KEYS[order];
    const along = dirs.map((d) => evaluate(lobe, d, order));
    curves[key] = along;
    const least = Math.min(...along);
    const lowest = along.findIndex((v) => v <= least + 1e-12);
    const turn = angles[lowest] - angles[0] + PI;
    const wrapped = ((turn % (2 * PI)) + 2 * PI) % (2 * PI) - PI;
    values[`${key}_energy`] = KEPT[order];
    values[`${key}_at_normal`] = along[0];
    values[`${key}_min`] = along[lowest];
    values[`${key}_min_angle_deg`] = Math.abs(degrees(wrapped));
    values[`${key}_negative_flux`] = order === 0 ? 0 : negativeFlux(lobe.coefficients, n, order) / PI;
    values[`${key}_probe`] = evaluate(lobe, probe, order);
  }
  return { values, curves };
}

function points(radii, dirs) {
  return radii.map((r, i) => `${(r * dirs[i][0]).toFixed(4)},${(-r * dirs[i][1]).toFixed(4)}`)
    .join(" ");
}

export function mount(root, params) {
  const orders = params.orders === "both" ? [1, 2] : [Number(params.orders[1])];
  const state = { normal: params.normal_deg, probe: params.probe_deg };
  const body = el("div", { class: "live-body cosine" }, root);
  const views = el("div", { class: "live-views" }, body);
  const picture = svg("svg", { class: "live-svg", viewBox: `${-RADIUS} ${-RADIUS} ${2 * RADIUS} ${2 * RADIUS}`,
                               role: "img" }, views);
  if (params.view === "3d") { picture.style.display = "none"; }
  const solid = params.view === "polar" ? null : threeD(views, orders[0]);
  svg("circle", { cx: 0, cy: 0, r: 1, class: "unit" }, picture);
  const layers = {};
  for (const order of orders) {
    layers[`neg${order}`] = svg("polygon", { class: `negative l${order}` }, picture);
    layers[`l${order}`] = svg("polyline", { class: `curve l${order}` }, picture);
  }
  layers.exact = svg("polyline", { class: "curve exact" }, picture);
  const normalLine = svg("line", { x1: 0, y1: 0, class: "handle-line" }, picture);
  const probeLine = svg("line", { x1: 0, y1: 0, class: "probe-line" }, picture);
  const normalTip = svg("circle", { r: 0.07, class: "handle" }, picture);
  const probeTip = svg("circle", { r: 0.06, class: "handle probe" }, picture);
  // what a finger or the pointer grabs: a circle about 44 px across around each tip
  const normalGrab = svg("circle", { r: 0.2, class: "grab", "data-handle": "n" }, picture);
  const probeGrab = svg("circle", { r: 0.2, class: "grab", "data-handle": "ω" }, picture);
  const normalText = svg("text", { class: "handle-label" }, picture);
  normalText.textContent = "n";
  const probeText = svg("text", { class: "handle-label" }, picture);
  probeText.textContent = "ω";
  const legend = el("p", { class: "live-legend" }, body);
  legend.innerHTML = '<span class="key exact"></span>max(cos, 0), exact ' + orders.map((o) =>
    `<span class="key l${o}"></span>L${o} (${(o + 1) ** 2} coefficients)`).join(" ")
    + ' <span class="key negative"></span>below 0, drawn as |value|';
  const controls = el("div", { class: "live-controls" }, body);
  const speak = (what) => (v) => `${what} ${fixed(v, 0)}° from up toward +x`;
  const normalSlider = slider(controls, { label: "normal n", min: -180, max: 180, step: 1,
    value: state.normal, speak: speak("n at"),
    change: (v) => { state.normal = v; update(); } });
  const probeSlider = slider(controls, { label: "probe ω", min: -180, max: 180, step: 1,
    value: state.probe, speak: speak("ω at"),
    change: (v) => { state.probe = v; update(); } });
  const wrap = el("div", { class: "table-wrap" }, body);
  const table = el("table", { class: "live-table" }, wrap);
  const head = el("tr", {}, el("thead", {}, table));
  el("th", { scope: "col" }, head, "");
  el("th", { scope: "col" }, head, "max(cos, 0)");
  orders.forEach((o) => el("th", { scope: "col" }, head, `L${o} (${(o + 1) ** 2} coeff.)`));
  const tbody = el("tbody", {}, table);
  const columns = [0, ...orders].map((o) => KEYS[o]);
  const rows = {};
  const rowTitles = { energy: "energy kept", at_normal: "toward n", min: "lowest",
                      negative_flux: "flux in the tail", probe: "toward ω" };
  for (const [row, title] of Object.entries(rowTitles)) {
    const tr = el("tr", {}, tbody);
    const th = el("th", { scope: "row" }, tr, title);
    if (row === "probe") {            // toward ω (its angle from n)
      th.appendChild(document.createTextNode(" ("));
      rows.probeAngle = readout(th, "probe_angle_deg");
      th.appendChild(document.createTextNode("° from n)"));
    }
    for (const key of columns) {
      const td = el("td", {}, tr);
      rows[`${key}_${row}`] = readout(td, `${key}_${row === "energy" ? "energy" : row}`);
      if (row === "min") {
        td.appendChild(document.createTextNode(" at "));
        rows[`${key}_min_angle`] = readout(td, `${key}_min_angle_deg`);
        td.appendChild(document.createTextNode("° from n"));
      }
      if (row === "negative_flux") { td.appendChild(document.createTextNode(" of the lobe's")); }
    }
  }
  const bandsWrap = el("div", { class: "table-wrap" }, body);
  const bandTable = el("table", { class: "live-table bands" }, bandsWrap);
  el("caption", {}, bandTable, "The lobe's energy by SH band (the same for every n)");
  const bandHead = el("tr", {}, el("thead", {}, bandTable));
  el("th", { scope: "col" }, bandHead, "band");
  el("th", { scope: "col" }, bandHead, "share of the energy");
  const bandBody = el("tbody", {}, bandTable);
  const bandCells = [0, 1, 2, 3].map((band) => {
    const tr = el("tr", {}, bandBody);
    el("th", { scope: "row" }, tr, band < 3 ? String(band) : "3 and up");
    return readout(el("td", {}, tr), band < 3 ? `band${band}_energy` : "rest_energy");
  });
  const stateCells = { normal_deg: readout(legend, "normal_deg"), probe_deg: readout(legend, "probe_deg") };
  Object.values(stateCells).forEach((node) => { node.hidden = true; });

  let update = () => {
    const { values, curves } = numbers(state.normal, state.probe);
    for (const order of orders) {
      const along = curves[`l${order}`];
      layers[`l${order}`].setAttribute("points", points(along.map((v) => Math.max(v, 0)), curves.dirs));
      layers[`neg${order}`].setAttribute("points", points(along.map((v) => Math.max(-v, 0)), curves.dirs));
    }
    layers.exact.setAttribute("points", points(curves.exact, curves.dirs));
    const n = sliceDirection(state.normal);
    const p = sliceDirection(state.probe).map((v) => 1.1 * v);
    for (const [line, tip, grab, text, d] of [[normalLine, normalTip, normalGrab, normalText, n],
                                              [probeLine, probeTip, probeGrab, probeText, p]]) {
      line.setAttribute("x2", d[0]);
      line.setAttribute("y2", -d[1]);
      for (const circle of [tip, grab]) {
        circle.setAttribute("cx", d[0]);
        circle.setAttribute("cy", -d[1]);
      }
      text.setAttribute("x", d[0] * 1.12);
      text.setAttribute("y", -d[1] * 1.12);
    }
    picture.setAttribute("aria-label", `Polar slice: the clamped cosine around n at `
      + `${fixed(state.normal, 0)}° and its projections; probe ω at ${fixed(state.probe, 0)}°`);
    for (const key of columns) {
      show(rows[`${key}_energy`], values[`${key}_energy`], percent(values[`${key}_energy`], 2));
      show(rows[`${key}_at_normal`], values[`${key}_at_normal`], fixed(values[`${key}_at_normal`], 4));
      show(rows[`${key}_min`], values[`${key}_min`], fixed(values[`${key}_min`], 3));
      show(rows[`${key}_min_angle`], values[`${key}_min_angle_deg`], fixed(values[`${key}_min_angle_deg`], 0));
      show(rows[`${key}_negative_flux`], values[`${key}_negative_flux`],
           percent(values[`${key}_negative_flux`], 1));
      show(rows[`${key}_probe`], values[`${key}_probe`], fixed(values[`${key}_probe`], 3));
    }
    show(rows.probeAngle, values.probe_angle_deg, fixed(values.probe_angle_deg, 0));
    show(stateCells.normal_deg, values.normal_deg, fixed(values.normal_deg, 1));
    show(stateCells.probe_deg, values.probe_deg, fixed(values.probe_deg, 1));
    BANDS.forEach((share, band) => { show(bandCells[band], share, percent(share, 1)); });
    const rest = 1 - BANDS.reduce((sum, share) => sum + share, 0);
    show(bandCells[3], rest, percent(rest, 2));
  };
  const aim = (set, slide) => (x, y) => {
    if (x === 0 && y === 0) { return; }
    const deg = degrees(Math.atan2(x, -y));
    set(deg);
    slide.set(Math.round(deg));
    update();
  };
  drag(picture, normalGrab, aim((v) => { state.normal = v; }, normalSlider));
  drag(picture, probeGrab, aim((v) => { state.probe = v; }, probeSlider));
  if (solid) {
    const draw3d = update;
    update = () => { draw3d(); solid.draw(state.normal); };
    solid.onTurn(() => solid.draw(state.normal));
  }
  update();
}

// The first order's lobe in 3D (clamped_cosine._three_d): the surface r(ω)·ω with
// r = max(±value, 0) as a wireframe of 19 elevations × 37 azimuths, the slice plane
// faint; drag it (or focus it and press the arrow keys) to turn it.
const ELEVATIONS = 19;
const AZIMUTHS = 37;

function threeD(parent, order) {
  const node = svg("svg", { class: "live-svg solid", viewBox: "-1.3 -1.3 2.6 2.6", role: "img",
                            tabindex: "0" }, parent);
  node.setAttribute("aria-label", `The L${order} projection in 3D; drag or use the arrow keys to turn it`);
  const view = { yaw: radians(-20), pitch: radians(15) };
  const project = ([x, y, z]) => {
    const x1 = Math.cos(view.yaw) * x + Math.sin(view.yaw) * z;
    const z1 = -Math.sin(view.yaw) * x + Math.cos(view.yaw) * z;
    return [x1, -(Math.cos(view.pitch) * y - Math.sin(view.pitch) * z1)];
  };
  const grid = [];
  for (let i = 0; i < ELEVATIONS; i++) {
    const row = [];
    for (let j = 0; j < AZIMUTHS; j++) {
      const elevation = PI * i / (ELEVATIONS - 1);
      const az = 2 * PI * j / (AZIMUTHS - 1);
      row.push([Math.sin(elevation) * Math.cos(az), Math.cos(elevation), Math.sin(elevation) * Math.sin(az)]);
    }
    grid.push(row);
  }
  let turned = () => {};
  let last = null;
  node.style.touchAction = "none";
  node.addEventListener("pointerdown", (event) => {
    last = [event.clientX, event.clientY];
    node.setPointerCapture(event.pointerId);
  });
  node.addEventListener("pointermove", (event) => {
    if (!last) { return; }
    view.yaw += radians(event.clientX - last[0]) * 0.8;
    view.pitch = Math.max(Math.min(view.pitch + radians(event.clientY - last[1]) * 0.8, PI / 2), -PI / 2);
    last = [event.clientX, event.clientY];
    turned();
  });
  node.addEventListener("pointerup", () => { last = null; });
  node.addEventListener("keydown", (event) => {
    const turn = { ArrowLeft: [-1, 0], ArrowRight: [1, 0], ArrowUp: [0, -1], ArrowDown: [0, 1] }[event.key];
    if (!turn) { return; }
    event.preventDefault();
    view.yaw += radians(10 * turn[0]);
    view.pitch = Math.max(Math.min(view.pitch + radians(10 * turn[1]), PI / 2), -PI / 2);
    turned();
  });
  return {
    onTurn(callback) { turned = callback; },
    draw(normalDeg) {
      const n = sliceDirection(normalDeg);
      const lobe = { normal: n, coefficients: cosineLobe(n, 2) };
      node.replaceChildren();
      const plane = [[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]].map(project);
      svg("polygon", { points: plane.map((p) => p.join(",")).join(" "), class: "slice-plane" }, node);
      for (const [key, sign, css] of [[order, 1, `l${order}`], [order, -1, "negative"], [0, 1, "exact"]]) {
        const radius = grid.map((row) => row.map((d) => Math.max(sign * evaluate(lobe, d, key), 0)));
        const lines = [];
        grid.forEach((row, i) => lines.push(row.map((d, j) => [d, radius[i][j]])));
        for (let j = 0; j < AZIMUTHS; j += 3) { lines.push(grid.map((row, i) => [row[j], radius[i][j]])); }
        for (const line of lines) {
          if (line.every(([, r]) => r <= 0)) { continue; }
          const points = line.map(([d, r]) => project(d.map((v) => v * r)));
          svg("polyline", { points: points.map((p) => `${p[0].toFixed(4)},${p[1].toFixed(4)}`).join(" "),
                            class: `wire ${css}` }, node);
        }
      }
      const tip = project(n);
      svg("line", { x1: 0, y1: 0, x2: tip[0], y2: tip[1], class: "handle-line" }, node);
    },
  };
}
