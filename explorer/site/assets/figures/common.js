// What the live figures share: SVG and HTML helpers, sliders that speak their value,
// pointer dragging (mouse, pen and touch alike), the number formats of the window's
// figures (explorer/ui/figures/style.py) and the SH basis and lobe of the numpy twin
// (explorer/lpv/twin.py), every constant from the generated module.
import {
  SH_C0, SH_C1, SH_L2_C2, SH_L2_C3, SH_L2_C4, SH_COSLOBE_C0, SH_COSLOBE_C1,
  SH_L2_LOBE_C2, SH_L2_LOBE_C3, SH_L2_LOBE_C4, PI,
} from "lpv/generated/constants.js";

const SVG_NS = "http://www.w3.org/2000/svg";
const MINUS = "\u2212";

export function svg(tag, attrs = {}, parent = null) {
  const node = document.createElementNS(SVG_NS, tag);
  for (const [key, value] of Object.entries(attrs)) { node.setAttribute(key, value); }
  if (parent) { parent.appendChild(node); }
  return node;
}

export function el(tag, attrs = {}, parent = null, text = null) {
  const node = document.createElement(tag);
  for (const [key, value] of Object.entries(attrs)) {
    if (key === "class") { node.className = value; } else { node.setAttribute(key, value); }
  }
  if (text !== null) { node.textContent = text; }
  if (parent) { parent.appendChild(node); }
  return node;
}

// --- numbers as the window prints them (style.num, style.percent, style.watts) ---------

export function fixed(value, digits) {
  return value.toFixed(digits).replace("-", MINUS);
}

// Python's format(value, ".Ng"): N significant digits, exponent form below 1e-4 or from
// 10^N on, trailing zeros dropped.
export function general(value, digits) {
  if (value === 0) { return "0"; }
  const exponent = Math.floor(Math.log10(Math.abs(Number(value.toPrecision(digits)))));
  let text;
  if (exponent < -4 || exponent >= digits) {
    const [mantissa, power] = value.toExponential(digits - 1).split("e");
    const sign = power[0] === "-" ? "-" : "+";
    const magnitude = power.replace(/^[+-]/, "").padStart(2, "0");
    text = trimZeros(mantissa) + "e" + sign + magnitude;
  } else {
    text = trimZeros(value.toFixed(Math.max(0, digits - 1 - exponent)));
  }
  return text.replace(/-/g, MINUS);
}

function trimZeros(text) {
  return text.includes(".") ? text.replace(/0+$/, "").replace(/\.$/, "") : text;
}

export function exponential(value, digits) {
  const [mantissa, power] = value.toExponential(digits).split("e");
  const sign = power[0] === "-" ? "-" : "+";
  return (mantissa + "e" + sign + power.replace(/^[+-]/, "").padStart(2, "0"))
    .replace(/-/g, MINUS);
}

export function percent(fraction, digits = 1) {
  const value = 100 * fraction;
  if (value !== 0 && Math.abs(value) < 10 ** -digits) { return general(value, 2) + " %"; }
  return fixed(value, digits) + " %";
}

export function watts(value) {
  if (value === 0) { return "0 W"; }
  const magnitude = Math.abs(value);
  return (magnitude >= 1e-3 && magnitude < 1e4 ? general(value, 3) : exponential(value, 2))
    + " W";
}

export function shareOf(value, reference) {
  if (reference === 0 || !Number.isFinite(reference)) { return "–"; }
  const ratio = value / reference;
  return Math.abs(ratio) >= 2 ? general(ratio, 3) + "×" : percent(ratio);
}

// A number the figure shows: its text, and its full double in data-value for whoever
// checks it (the tests read it; a reader sees the text).
export function readout(parent, name, tag = "span") {
  return el(tag, { class: "readout", "data-readout": name }, parent);
}

export function show(node, value, text) {
  node.setAttribute("data-value", String(value));
  node.textContent = text;
}

// ``parent``'s content replaced by ``parts``: strings, and [name, value, text] readouts.
export function sentence(parent, parts) {
  parent.replaceChildren();
  for (const part of parts) {
    if (typeof part === "string") { parent.append(part); continue; }
    const [name, value, text] = part;
    show(readout(parent, name), value, text);
  }
}

// --- controls ---------------------------------------------------------------------------

// A labelled range input; ``speak(value)`` is its aria-valuetext, ``change(value)`` runs
// on every input (mouse, touch and the arrow keys alike).
export function slider(parent, { label, min, max, step, value, speak, change }) {
  const row = el("label", { class: "live-control" }, parent);
  el("span", { class: "live-label" }, row, label);
  const input = el("input", { type: "range", min: String(min), max: String(max),
                              step: String(step), value: String(value) }, row);
  const output = el("output", { "aria-hidden": "true" }, row);
  const speakNow = () => {
    const text = speak(Number(input.value));
    input.setAttribute("aria-valuetext", text);
    output.textContent = text;
  };
  input.addEventListener("input", () => { speakNow(); change(Number(input.value)); });
  speakNow();
  return {
    input,
    set(v) { input.value = String(v); speakNow(); },
  };
}

// Drag inside an SVG: ``move(x, y)`` gets the pointer in the SVG's user units while a
// pointer that went down on ``handle`` (or the whole SVG, when ``handle`` is null) moves.
export function drag(svgNode, handle, move) {
  const target = handle || svgNode;
  target.style.touchAction = "none";
  // Chrome ignores touch-action inside an SVG: a touch that starts on the handle must not
  // scroll the page (which would cancel the drag); elsewhere the page still scrolls.
  target.addEventListener("touchstart", (event) => event.preventDefault(), { passive: false });
  let active = null;
  const point = (event) => {
    const matrix = svgNode.getScreenCTM().inverse();
    const p = new DOMPoint(event.clientX, event.clientY).matrixTransform(matrix);
    return [p.x, p.y];
  };
  target.addEventListener("pointerdown", (event) => {
    active = event.pointerId;
    target.setPointerCapture(event.pointerId);
    event.preventDefault();
    move(...point(event));
  });
  target.addEventListener("pointermove", (event) => {
    if (event.pointerId === active) { move(...point(event)); }
  });
  const end = (event) => { if (event.pointerId === active) { active = null; } };
  target.addEventListener("pointerup", end);
  target.addEventListener("pointercancel", end);
}

// --- numerics ---------------------------------------------------------------------------

// Gauss–Legendre nodes and weights on [−1, 1] (numpy.polynomial.legendre.leggauss):
// Newton's method on P_n from Chebyshev guesses, to double precision.
export function gaussLegendre(n) {
  const nodes = new Float64Array(n);
  const weights = new Float64Array(n);
  for (let i = 0; i < n; i++) {
    let x = Math.cos(PI * (i + 0.75) / (n + 0.5));
    let derivative = 0;
    for (let iteration = 0; iteration < 100; iteration++) {
      let p0 = 1;
      let p1 = x;
      for (let k = 2; k <= n; k++) { [p0, p1] = [p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k]; }
      derivative = n * (x * p1 - p0) / (x * x - 1);
      const step = p1 / derivative;
      x -= step;
      if (Math.abs(step) < 1e-17) { break; }
    }
    let p0 = 1;
    let p1 = x;
    for (let k = 2; k <= n; k++) { [p0, p1] = [p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k]; }
    derivative = n * (x * p1 - p0) / (x * x - 1);
    nodes[n - 1 - i] = x;
    weights[n - 1 - i] = 2 / ((1 - x * x) * derivative * derivative);
  }
  return [nodes, weights];
}

// Y(ω) of twin.sh_basis: (c0, −c1·y, c1·z, −c1·x), then band 2 for order 2.
export function shBasis([x, y, z], order = 1) {
  const band01 = [SH_C0, -SH_C1 * y, SH_C1 * z, -SH_C1 * x];
  if (order === 1) { return band01; }
  return band01.concat([SH_L2_C2 * x * y, -SH_L2_C2 * y * z, SH_L2_C3 * (3 * z * z - 1),
                        -SH_L2_C2 * x * z, SH_L2_C4 * (x * x - y * y)]);
}

// The SH projection of clamp⁺⟨n, ω⟩ (twin.cosine_lobe; band 2 with the generated
// coefficients of lobe_L2(n), docs/MODEL.md "L2 option").
export function cosineLobe([x, y, z], order = 1) {
  const band01 = [SH_COSLOBE_C0, -SH_COSLOBE_C1 * y, SH_COSLOBE_C1 * z, -SH_COSLOBE_C1 * x];
  if (order === 1) { return band01; }
  return band01.concat([SH_L2_LOBE_C2 * x * y, -SH_L2_LOBE_C2 * y * z,
                        SH_L2_LOBE_C3 * (3 * z * z - 1), -SH_L2_LOBE_C2 * x * z,
                        SH_L2_LOBE_C4 * (x * x - y * y)]);
}

export function dot(a, b) {
  let sum = 0;
  for (let k = 0; k < a.length; k++) { sum += a[k] * b[k]; }
  return sum;
}

// As Python's math.degrees and math.radians compute them (one product each).
const RAD_TO_DEG = 180 / PI;
const DEG_TO_RAD = PI / 180;
export function degrees(angle) { return angle * RAD_TO_DEG; }
export function radians(angle) { return angle * DEG_TO_RAD; }
