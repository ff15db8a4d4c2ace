// An RSM texel on a surface you tilt: the window's figure (explorer/ui/figures/
// rsm_texel.py). The footprint is where the texel's four corner rays (light along −y)
// meet the tilted plane, its area the vector area of that quad; the irradiance is
// ⟨n, −l⟩; their product, the flux the texel stands for, stays Φ0.
import { drag, el, fixed, radians, degrees, readout, show, slider, svg } from "lpv/figures/common.js";

const TEXEL = 0.5;            // the texel's edge in the side view (rsm_texel.TEXEL)
const LIGHT_HEIGHT = 1.5;
const CURVE_SAMPLES = 171;

function surfaceNormal(thetaDeg) {
  const t = radians(thetaDeg);
  return [Math.sin(t), Math.cos(t), 0];
}

// rsm_texel.footprint: the corners (4, 3) on the plane y = −(n_x·x + n_z·z)/n_y.
export function footprint(thetaDeg, texel = 1) {
  const n = surfaceNormal(thetaDeg);
  const half = texel / 2;
  return [[-half, -half], [half, -half], [half, half], [-half, half]]
    .map(([x, z]) => [x, -(n[0] * x + n[2] * z) / n[1], z]);
}

// rsm_texel.quad_area: half the norm of the summed cross products of consecutive corners.
function quadArea(c) {
  const sum = [0, 0, 0];
  for (let i = 0; i < 4; i++) {
    const a = c[i];
    const b = c[(i + 1) % 4];
    sum[0] += a[1] * b[2] - a[2] * b[1];
    sum[1] += a[2] * b[0] - a[0] * b[2];
    sum[2] += a[0] * b[1] - a[1] * b[0];
  }
  return Math.hypot(...sum.map((v) => 0.5 * v));
}

export function numbers(thetaDeg) {
  const area = quadArea(footprint(thetaDeg, 1));
  const n = surfaceNormal(thetaDeg);
  const light = [0, -1, 0];
  const irradiance = Math.max(-(n[0] * light[0] + n[1] * light[1] + n[2] * light[2]), 0);
  return { theta_deg: thetaDeg, footprint: area, irradiance, flux: area * irradiance };
}

export function mount(root, params) {
  const maxTilt = params.max_tilt;
  const state = { theta: params.theta_deg };
  const body = el("div", { class: "live-body texel" }, root);
  const views = el("div", { class: "live-views" }, body);
  const side = svg("svg", { class: "live-svg", viewBox: "-1.5 -1.8 3 3", role: "img" }, views);
  const plot = params.plot ? svg("svg", { class: "live-svg plot-svg", viewBox: "0 0 300 260", role: "img",
                                         "aria-label": "Footprint 1/cos θ, irradiance cos θ and flux against the tilt θ" }, views) : null;
  const controls = el("div", { class: "live-controls" }, body);
  const tilt = slider(controls, { label: "tilt θ", min: 0, max: maxTilt, step: 1, value: state.theta,
    speak: (v) => `θ = ${fixed(v, 0)}°`, change: (v) => { state.theta = v; update(); } });
  const wrap = el("div", { class: "table-wrap" }, body);
  const table = el("table", { class: "live-table" }, wrap);
  const head = el("tr", {}, el("thead", {}, table));
  el("th", { scope: "col" }, head, "");
  const thetaHead = el("th", { scope: "col" }, head);
  thetaHead.append("θ = ");
  const thetaCell = readout(thetaHead, "theta_deg");
  thetaHead.append("°");
  const tbody = el("tbody", {}, table);
  const cells = {};
  for (const [key, title, unit] of [["footprint", "footprint A", "A0"], ["irradiance", "irradiance E", "E0"],
                                    ["flux", "flux E·A", "Φ0"]]) {
    const tr = el("tr", {}, tbody);
    el("th", { scope: "row" }, tr, title);
    const td = el("td", {}, tr);
    cells[key] = readout(td, key);
    td.append(` ${unit}`);
  }
  // the side view's fixed parts: the light's rays and the texel
  for (let i = 0; i < 12; i++) {
    const x = -1.1 + 2.2 * i / 11;
    svg("line", { x1: x, y1: -(LIGHT_HEIGHT + 0.2), x2: x, y2: 1, class: "ray" }, side);
  }
  svg("line", { x1: -TEXEL / 2, y1: -LIGHT_HEIGHT, x2: TEXEL / 2, y2: -LIGHT_HEIGHT, class: "texel" }, side);
  const texelLabel = svg("text", { x: 0, y: -LIGHT_HEIGHT - 0.1, class: "svg-label middle" }, side);
  texelLabel.textContent = "RSM texel, A0";
  const beam = svg("polygon", { class: "beam" }, side);
  const rays = [0, 1].map(() => svg("line", { class: "corner-ray" }, side));
  const surface = svg("line", { class: "surface" }, side);
  const foot = svg("line", { class: "footprint" }, side);
  const normal = svg("line", { x1: 0, y1: 0, class: "normal" }, side);
  svg("line", { x1: 0, y1: 0, x2: 0, y2: -0.45, class: "toward-light" }, side);
  const arc = svg("polyline", { class: "arc" }, side);
  const angleLabel = svg("text", { class: "svg-label" }, side);
  const handle = svg("circle", { r: 0.09, class: "handle" }, side);
  const grab = svg("circle", { r: 0.24, class: "grab", "data-handle": "tilt" }, side);   // ~44 px
  let plotMarks = null;
  if (plot) { plotMarks = drawPlot(plot, maxTilt); }

  function update() {
    const values = numbers(state.theta);
    const c = footprint(state.theta, TEXEL);
    const t = radians(state.theta);
    beam.setAttribute("points", `${-TEXEL / 2},${-LIGHT_HEIGHT} ${TEXEL / 2},${-LIGHT_HEIGHT} `
      + `${TEXEL / 2},${-c[1][1]} ${-TEXEL / 2},${-c[0][1]}`);
    [0, 1].forEach((k) => {
      rays[k].setAttribute("x1", c[k][0]); rays[k].setAttribute("x2", c[k][0]);
      rays[k].setAttribute("y1", -LIGHT_HEIGHT); rays[k].setAttribute("y2", -c[k][1]);
    });
    const tangent = [Math.cos(t), -Math.sin(t)];
    surface.setAttribute("x1", -tangent[0]); surface.setAttribute("y1", tangent[1]);
    surface.setAttribute("x2", tangent[0]); surface.setAttribute("y2", -tangent[1]);
    foot.setAttribute("x1", c[0][0]); foot.setAttribute("y1", -c[0][1]);
    foot.setAttribute("x2", c[1][0]); foot.setAttribute("y2", -c[1][1]);
    normal.setAttribute("x2", 0.7 * Math.sin(t)); normal.setAttribute("y2", -0.7 * Math.cos(t));
    const arcPoints = [];
    for (let k = 0; k <= 24; k++) {
      const a = t * k / 24;
      arcPoints.push(`${(0.35 * Math.sin(a)).toFixed(4)},${(-0.35 * Math.cos(a)).toFixed(4)}`);
    }
    arc.setAttribute("points", arcPoints.join(" "));
    angleLabel.setAttribute("x", 0.6 * Math.sin(t / 2) + 0.12);
    angleLabel.setAttribute("y", -0.6 * Math.cos(t / 2));
    angleLabel.textContent = `θ = ${fixed(state.theta, 0)}°`;
    for (const circle of [handle, grab]) {
      circle.setAttribute("cx", tangent[0]);
      circle.setAttribute("cy", -tangent[1]);
    }
    side.setAttribute("aria-label", `Side view: the light through one texel onto a surface tilted by ${fixed(state.theta, 0)}°; `
      + `the footprint is ${fixed(values.footprint, 3)} texel areas`);
    show(thetaCell, values.theta_deg, fixed(values.theta_deg, 1));
    show(cells.footprint, values.footprint, fixed(values.footprint, 3));
    show(cells.irradiance, values.irradiance, fixed(values.irradiance, 3));
    show(cells.flux, values.flux, fixed(values.flux, 3));
    if (plotMarks) { plotMarks(values); }
  }
  // rsm_texel's handle: the surface's end; θ from its position, within [0, MAX_TILT].
  drag(side, grab, (x, y) => {
    if (x <= 0) { return; }
    state.theta = Math.min(Math.max(degrees(Math.atan2(y, x)), 0), maxTilt);
    tilt.set(Math.round(state.theta));
    update();
  });
  update();
}

// The plot beside: the three terms against θ on a log axis (their span passes two
// decades, where the window's plots go log), with the current tilt marked.
function drawPlot(plot, maxTilt) {
  const left = 44; const right = 290; const top = 12; const bottom = 222;
  const low = -2; const high = 2;                 // 10^-2 .. 10^2
  const x = (deg) => left + (right - left) * deg / 90;
  const y = (v) => bottom - (bottom - top) * (Math.log10(v) - low) / (high - low);
  svg("rect", { x: left, y: top, width: right - left, height: bottom - top, class: "axes" }, plot);
  for (let e = low; e <= high; e++) {
    svg("line", { x1: left, x2: right, y1: y(10 ** e), y2: y(10 ** e), class: "grid" }, plot);
    const label = svg("text", { x: left - 4, y: y(10 ** e) + 4, class: "tick end" }, plot);
    label.textContent = e === 0 ? "1" : `10${e < 0 ? "⁻" : ""}${"⁰¹²³⁴"[Math.abs(e)]}`;
  }
  for (let deg = 0; deg <= 90; deg += 30) {
    const label = svg("text", { x: x(deg), y: bottom + 14, class: "tick middle" }, plot);
    label.textContent = String(deg);
  }
  const title = svg("text", { x: (left + right) / 2, y: bottom + 32, class: "axis-title middle" }, plot);
  title.textContent = "θ [degrees]";
  const keys = [["footprint", "footprint A/A0 = 1/cos θ"], ["irradiance", "irradiance E/E0 = cos θ"],
                ["flux", "flux E·A/Φ0"]];
  const marks = {};
  keys.forEach(([key, label], index) => {
    const points = [];
    for (let i = 0; i < CURVE_SAMPLES; i++) {
      const deg = maxTilt * i / (CURVE_SAMPLES - 1);
      points.push(`${x(deg).toFixed(2)},${y(numbers(deg)[key]).toFixed(2)}`);
    }
    svg("polyline", { points: points.join(" "), class: `curve ${key}` }, plot);
    marks[key] = svg("circle", { r: 4, class: `mark ${key}` }, plot);
    const text = svg("text", { x: left + 6, y: top + 14 + 14 * index, class: `legend ${key}` }, plot);
    text.textContent = label;
  });
  const now = svg("line", { y1: top, y2: bottom, class: "now" }, plot);
  return (values) => {
    now.setAttribute("x1", x(values.theta_deg)); now.setAttribute("x2", x(values.theta_deg));
    for (const [key] of keys) {
      marks[key].setAttribute("cx", x(values.theta_deg));
      marks[key].setAttribute("cy", y(values[key]));
    }
  };
}
