// Propagation, step by step: one VPL in a small grid, injected and propagated in the
// page, in float64, as the window's figure does it (explorer/ui/figures/
// propagation_stepper.py, which runs the numpy twin, explorer/lpv/twin.py: inject, then
// propagate_audited, in scatter form with every correction switch). One colour channel is
// computed (the VPL's three channels are equal) and the channel sums are three times it.
import {
  FRONT_FACE_SOLID_ANGLE, PI, PUBLISHED_FRONT_FACE_SOLID_ANGLE, PUBLISHED_PI,
  PUBLISHED_SIDE_FACE_SOLID_ANGLE, SH_C1, SH_FLUX_FACTOR, SIDE_EVAL_BIG, SIDE_EVAL_SMALL,
  SIDE_FACE_SOLID_ANGLE,
} from "lpv/generated/constants.js";
import { cosineLobe, el, general, percent, sentence, shBasis, slider, svg, watts } from "lpv/figures/common.js";

const CHANNELS = 3;
const K = 4;                              // L1: four SH coefficients per cell

// twin.formula_pi, injection_factor, propagation_factor, reprojection_factor,
// face_solid_angles
function factors(c) {
  const pi = c.exact_constants ? PI : PUBLISHED_PI;
  const kI = c.injection_pi ? 1 / pi : 1;
  const kP = c.propagation_4pi ? 1 : 1 / (4 * pi);
  const kR = c.reprojection_pi ? 1 : 1 / pi;
  const [front, side] = c.exact_constants ? [FRONT_FACE_SOLID_ANGLE, SIDE_FACE_SOLID_ANGLE]
    : [PUBLISHED_FRONT_FACE_SOLID_ANGLE, PUBLISHED_SIDE_FACE_SOLID_ANGLE];
  return { kI, scale: kR * kI * kP, front, side };
}

// twin._faces: (evaluation, reprojection, is front) of the cell one step along ±e_axis.
function faces(axis, sign, sideFaces) {
  const forward = [0, 0, 0];
  forward[axis] = sign;
  const list = [[forward, forward, true]];
  if (sideFaces) {
    for (const other of [(axis + 1) % 3, (axis + 2) % 3]) {
      for (const sideSign of [1, -1]) {
        const sideDir = [0, 0, 0];
        sideDir[other] = sideSign;
        const evaluation = [0, 1, 2].map((k) => sideDir[k] * SIDE_EVAL_SMALL + forward[k] * SIDE_EVAL_BIG);
        list.push([evaluation, sideDir, false]);
      }
    }
  }
  return list;
}

const DIRECTIONS = [[0, 1], [0, -1], [1, 1], [1, -1], [2, 1], [2, -1]];

// One step P(grid) of one channel (twin.propagation_step without a geometry volume), its
// border loss and front-face clamp gain in watts.
export function propagationStep(grid, n, c) {
  const { scale, front, side } = factors(c);
  const out = new Float64Array(grid.length);
  let borderLoss = 0;
  let clampGain = 0;
  const index = (x, y, z) => ((x * n + y) * n + z) * K;
  for (const [axis, sign] of DIRECTIONS) {
    for (const [evaluation, reprojection, isFront] of faces(axis, sign, c.side_faces)) {
      const weight = scale * (isFront ? front : side);
      const lobe = cosineLobe(reprojection, 1);
      const fluxPerIntensity = weight * SH_FLUX_FACTOR * lobe[0];
      const basis = shBasis(evaluation, 1);
      for (let x = 0; x < n; x++) {
        for (let y = 0; y < n; y++) {
          for (let z = 0; z < n; z++) {
            const i = index(x, y, z);
            const raw = grid[i] * basis[0] + grid[i + 1] * basis[1] + grid[i + 2] * basis[2]
              + grid[i + 3] * basis[3];
            if (raw === 0) { continue; }
            const used = isFront && c.clamp_front_face ? Math.max(raw, 0) : raw;
            const sent = weight * used;
            clampGain += fluxPerIntensity * (used - raw);
            const target = [x, y, z];
            target[axis] += sign;
            if (target[axis] < 0 || target[axis] >= n) {
              borderLoss += SH_FLUX_FACTOR * lobe[0] * sent;
              continue;
            }
            const j = index(...target);
            for (let k = 0; k < K; k++) { out[j + k] += sent * lobe[k]; }
          }
        }
      }
    }
  }
  return { out, borderLoss, clampGain };
}

function channelFlux(grid) {
  let sum = 0;
  for (let i = 0; i < grid.length; i += K) { sum += grid[i]; }
  return SH_FLUX_FACTOR * sum;
}

// propagation_stepper._run: the VPL at the source cell's centre (no offset), its normal
// ±e_axis, then propagate_audited; fluxes summed over the three channels.
export function run(params, switches) {
  const n = params.grid_size;
  const source = [params.source_x, params.source_y, Math.floor(n / 2)];
  const axis = "xyz".indexOf(params.normal[1]);
  const normal = [0, 0, 0];
  normal[axis] = params.normal[0] === "+" ? 1 : -1;
  const grid = new Float64Array(n * n * n * K);
  const { kI } = factors(switches);
  const lobe = cosineLobe(normal, 1);
  const at = ((source[0] * n + source[1]) * n + source[2]) * K;
  for (let k = 0; k < K; k++) { grid[at + k] += params.source_flux * (kI * lobe[k]); }
  const steps = [grid];
  let accumulated = grid.slice();
  const borderLoss = [];
  const clampGain = [];
  for (let t = 0; t < params.iterations; t++) {
    const from = switches.ping_pong ? steps[steps.length - 1] : accumulated;
    const step = propagationStep(from, n, switches);
    borderLoss.push(CHANNELS * step.borderLoss);
    clampGain.push(CHANNELS * step.clampGain);
    steps.push(step.out);
    const next = accumulated.slice();
    for (let i = 0; i < next.length; i++) { next[i] += step.out[i]; }
    accumulated = next;
  }
  const flux = steps.map((g) => CHANNELS * channelFlux(g));
  return { n, source, steps, flux, borderLoss, clampGain, injected: flux[0] };
}

// propagation_stepper.readouts at step t.
export function numbers(result, step) {
  const t = Math.min(step, result.steps.length - 1);
  const inFlight = result.flux[t];
  const lost = result.borderLoss.slice(0, t).reduce((s, v) => s + v, 0);
  const gained = result.clampGain.slice(0, t).reduce((s, v) => s + v, 0);
  return { step: t, injected: result.injected, in_flight: inFlight,
           in_flight_share: inFlight / result.injected, border_loss: lost, clamp_gain: gained,
           balance: inFlight + lost - gained,
           accumulated: result.flux.slice(0, t + 1).reduce((s, v) => s + v, 0) };
}

function heatColour(stops, value) {
  const t = Math.min(Math.max(value, 0), 1);
  const pos = t * (stops.length - 1);
  const low = Math.min(Math.floor(pos), stops.length - 2);
  const frac = pos - low;
  const rgb = [0, 1, 2].map((k) => stops[low][k] * (1 - frac) + stops[low + 1][k] * frac);
  return `rgb(${rgb.map((v) => Math.round(255 * v)).join(",")})`;
}

export function mount(root, params) {
  const state = { step: params.step, corrections: params.corrections, glyph: params.glyph,
                  scale: params.scale, timer: null };
  const cache = {};
  const result = () => {
    if (!cache[state.corrections]) { cache[state.corrections] = run(params, params.switches[state.corrections]); }
    return cache[state.corrections];
  };
  const body = el("div", { class: "live-body stepper" }, root);
  const controls = el("div", { class: "live-controls" }, body);
  const play = el("button", { type: "button", class: "play" }, controls, "Play");
  const scrub = slider(controls, { label: "step t", min: 0, max: params.iterations, step: 1, value: state.step,
    speak: (v) => `step t = ${v} of ${params.iterations}`,
    change: (v) => { stop(); state.step = v; draw(); } });
  const options = el("div", { class: "live-controls" }, body);
  const choose = (label, values, current, change) => {
    const row = el("label", { class: "live-control" }, options);
    el("span", { class: "live-label" }, row, label);
    const select = el("select", {}, row);
    for (const [value, text] of values) {
      const option = el("option", { value }, select, text);
      option.selected = value === current;
    }
    select.addEventListener("change", () => change(select.value));
    return select;
  };
  choose("formulas", params.choices.map((name) => [name, name]), state.corrections,
         (v) => { state.corrections = v; draw(); });
  choose("glyph", [["arrow", "arrows"], ["lobe", "lobes"], ["none", "none"]], state.glyph,
         (v) => { state.glyph = v; draw(); });
  choose("axis", [["auto", "auto"], ["linear", "linear"], ["log", "log"]], state.scale,
         (v) => { state.scale = v; draw(); });
  const views = el("div", { class: "live-views" }, body);
  const canvasWrap = el("div", { class: "canvas-wrap" }, views);
  const canvas = el("canvas", { class: "live-canvas", role: "img" }, canvasWrap);
  const plot = svg("svg", { class: "live-svg plot-svg", viewBox: "0 0 320 252", role: "img" }, views);
  const hover = el("p", { class: "live-note cell-note" }, body, "Hover or tap a cell to read its flux.");
  const balance = el("p", { class: "live-balance" }, body);
  const legend = el("p", { class: "live-note" }, body);

  function stop() {
    if (state.timer !== null) { clearInterval(state.timer); state.timer = null; }
    play.textContent = "Play";
  }
  play.addEventListener("click", () => {
    if (state.timer !== null) { stop(); return; }
    if (state.step >= params.iterations) { state.step = 0; }
    play.textContent = "Pause";
    draw();
    state.timer = setInterval(() => {
      state.step += 1;
      if (state.step >= params.iterations) { state.step = params.iterations; stop(); }
      draw();
    }, 1000 / params.rate);
  });

  function sliceFlux(r, t) {
    const n = r.n;
    const z = r.source[2];
    const grid = r.steps[t];
    const values = [];
    for (let x = 0; x < n; x++) {
      for (let y = 0; y < n; y++) {
        const i = ((x * n + y) * n + z) * K;
        values.push({ x, y, flux: CHANNELS * SH_FLUX_FACTOR * grid[i],
                      vector: [-SH_C1 * grid[i + 3], -SH_C1 * grid[i + 1]] });
      }
    }
    return values;
  }

  function drawSlice(r, t) {
    const side = Math.min(canvasWrap.clientWidth || 300, 440);
    const ratio = window.devicePixelRatio || 1;
    canvas.width = Math.round(side * ratio);
    canvas.height = Math.round(side * ratio);
    canvas.style.width = `${side}px`;
    canvas.style.height = `${side}px`;
    const g = canvas.getContext("2d");
    g.setTransform(ratio, 0, 0, ratio, 0, 0);
    const n = r.n;
    const cell = side / n;
    const cells = sliceFlux(r, t);
    const top = Math.max(...cells.map((c) => Math.abs(c.flux)));
    const longest = Math.max(...cells.map((c) => Math.hypot(...c.vector)));
    for (const c of cells) {
      g.fillStyle = top > 0 ? heatColour(params.heat, 0.8 * Math.sqrt(Math.min(Math.max(c.flux / top, 0), 1)))
        : "rgb(0,0,0)";
      g.fillRect(c.x * cell, (n - 1 - c.y) * cell, cell + 0.5, cell + 0.5);
      g.strokeStyle = "rgba(255,255,255,0.08)";
      g.strokeRect(c.x * cell, (n - 1 - c.y) * cell, cell, cell);
    }
    if (state.glyph === "lobe") { drawLobes(g, r.steps[t], n, r.source[2], cell); }
    if (state.glyph === "arrow" && longest > 0) {
      g.strokeStyle = g.fillStyle = "rgba(240,240,240,0.9)";
      g.lineWidth = 1.5;
      for (const c of cells) {
        const length = Math.hypot(...c.vector);
        const half = cell / 2;
        const reach = length / longest * half * 0.9;
        if (reach < 1.2) { continue; }
        const [ux, uy] = c.vector.map((v) => v / length);
        const cx = (c.x + 0.5) * cell;
        const cy = (n - 1 - c.y + 0.5) * cell;
        const tip = [cx + ux * reach, cy - uy * reach];
        g.beginPath(); g.moveTo(cx - ux * reach, cy + uy * reach); g.lineTo(...tip); g.stroke();
        const head = Math.min(0.45 * reach, 6);
        g.beginPath(); g.moveTo(...tip);
        g.lineTo(tip[0] - head * (ux + 0.5 * uy), tip[1] + head * (uy - 0.5 * ux));
        g.lineTo(tip[0] - head * (ux - 0.5 * uy), tip[1] + head * (uy + 0.5 * ux));
        g.closePath(); g.fill();
      }
    }
    g.strokeStyle = "#ffd54a";
    g.lineWidth = 2;
    g.strokeRect(r.source[0] * cell, (n - 1 - r.source[1]) * cell, cell, cell);
    g.fillStyle = "rgba(240,240,240,0.9)";
    g.font = "12px system-ui, sans-serif";
    g.fillText(`grid_${t}, slice z = ${r.source[2]}`, 6, 15);
    canvas.setAttribute("aria-label", `The slice z = ${r.source[2]} at step ${t}: each cell coloured by `
      + "the flux it holds, with an arrow where its light is heading");
    return { cells, cell, n };
  }

  // glyphs.draw_lobe_glyphs: each cell's intensity toward the slice's directions as a
  // polar curve, relative to the slice's largest |value|; negative parts in red.
  const around = [...Array(params.glyph_samples).keys()].map((i) => {
    const a = 2 * PI * i / params.glyph_samples;
    return shBasis([Math.cos(a), Math.sin(a), 0], 1).concat([Math.cos(a), Math.sin(a)]);
  });
  function drawLobes(g, grid, n, z, cell) {
    const lobes = [];
    let top = 0;
    for (let x = 0; x < n; x++) {
      for (let y = 0; y < n; y++) {
        const i = ((x * n + y) * n + z) * K;
        const values = around.map((b) => grid[i] * b[0] + grid[i + 1] * b[1] + grid[i + 2] * b[2]
          + grid[i + 3] * b[3]);
        values.forEach((v) => { top = Math.max(top, Math.abs(v)); });
        lobes.push([x, y, values]);
      }
    }
    if (top <= 0) { return; }
    g.lineWidth = 1;
    for (const [sign, colour] of [[1, "rgba(240,240,240,0.9)"], [-1, "rgba(230,80,80,0.95)"]]) {
      g.strokeStyle = colour;
      for (const [x, y, values] of lobes) {
        const radius = values.map((v) => Math.max(sign * v, 0) / top * cell / 2);
        if (Math.max(...radius) < 0.6) { continue; }
        const cx = (x + 0.5) * cell;
        const cy = (n - 1 - y + 0.5) * cell;
        g.beginPath();
        radius.forEach((rad, k) => {
          const px = cx + rad * around[k][4];
          const py = cy - rad * around[k][5];
          if (k === 0) { g.moveTo(px, py); } else { g.lineTo(px, py); }
        });
        g.closePath();
        g.stroke();
      }
    }
  }

  let sliceNow = null;
  const pick = (event) => {
    if (!sliceNow) { return; }
    const box = canvas.getBoundingClientRect();
    const { cell, n } = sliceNow;
    const cx = Math.min(Math.max(Math.floor((event.clientX - box.left) / cell), 0), n - 1);
    const cy = Math.min(Math.max(n - 1 - Math.floor((event.clientY - box.top) / cell), 0), n - 1);
    const found = sliceNow.cells.find((c) => c.x === cx && c.y === cy);
    hover.textContent = `cell (${cx}, ${cy}, ${result().source[2]}) at step ${state.step}: ${watts(found.flux)}`;
  };
  canvas.addEventListener("pointermove", pick);
  canvas.addEventListener("pointerdown", pick);

  function drawPlot(r, t) {
    plot.replaceChildren();
    const left = 52; const right = 310; const top = 12; const bottom = 196;
    const positive = r.flux.filter((v) => Number.isFinite(v) && v > 0);
    let scale = state.scale;
    if (scale === "auto") {
      scale = positive.length >= 2 && Math.log10(Math.max(...positive) / Math.min(...positive)) > 2 ? "log" : "linear";
    }
    const highest = Math.max(...r.flux, r.injected);
    let y;
    let ticks;
    if (scale === "log" && positive.length) {
      const low = Math.floor(Math.log10(Math.min(...positive)));
      const high = Math.ceil(Math.log10(highest * 1.0000001));
      y = (v) => bottom - (bottom - top) * (Math.log10(Math.max(v, 10 ** low)) - low) / Math.max(high - low, 1);
      ticks = [];
      for (let e = low; e <= high; e++) { ticks.push(10 ** e); }
    } else {
      y = (v) => bottom - (bottom - top) * v / (highest * 1.1);
      ticks = [0, highest * 0.5, highest];
    }
    const x = (s) => left + (right - left) * s / Math.max(params.iterations, 1);
    svg("rect", { x: left, y: top, width: right - left, height: bottom - top, class: "axes" }, plot);
    for (const v of ticks) {
      svg("line", { x1: left, x2: right, y1: y(v), y2: y(v), class: "grid" }, plot);
      svg("text", { x: left - 4, y: y(v) + 4, class: "tick end" }, plot).textContent = watts(v);
    }
    for (const s of [0, Math.round(params.iterations / 2), params.iterations]) {
      svg("text", { x: x(s), y: bottom + 14, class: "tick middle" }, plot).textContent = String(s);
    }
    svg("text", { x: (left + right) / 2, y: bottom + 32, class: "axis-title middle" }, plot)
      .textContent = "propagation step t";
    svg("line", { x1: left, x2: right, y1: y(r.injected), y2: y(r.injected), class: "reference" }, plot);
    svg("polyline", { points: r.flux.map((v, s) => `${x(s).toFixed(2)},${y(v).toFixed(2)}`).join(" "),
                      class: "curve flux" }, plot);
    r.flux.forEach((v, s) => {
      const point = svg("circle", { cx: x(s), cy: y(v), r: s === t ? 5 : 2.5, class: `point${s === t ? " now" : ""}` }, plot);
      svg("title", {}, point).textContent = `step ${s}: ${watts(v)} in flight`;
    });
    svg("line", { x1: x(t), x2: x(t), y1: top, y2: bottom, class: "now" }, plot);
    svg("text", { x: left, y: bottom + 48, class: "legend" }, plot).textContent =
      "flux in flight per step (dashed: injected)";
    plot.setAttribute("aria-label", `Flux in flight per step, ${scale} axis, step ${t} marked`);
  }

  function draw() {
    const r = result();
    const values = numbers(r, state.step);
    scrub.set(values.step);
    sliceNow = drawSlice(r, values.step);
    drawPlot(r, values.step);
    const kept = Math.abs(values.balance - values.injected) <= 1e-9 * values.injected;
    const w = (name) => [name, values[name], watts(values[name])];
    sentence(balance, [
      "Step t = ", ["step", values.step, String(values.step)], ": ", w("in_flight"),
      " in flight (", ["in_flight_share", values.in_flight_share, percent(values.in_flight_share)],
      " of the injected ", w("injected"), "). In flight + left through the border ",
      w("border_loss"), " − added by the front-face clamp ", w("clamp_gain"), " = ", w("balance"),
      kept ? ", the injected flux: these formulas conserve it."
        : `, not the injected ${watts(values.injected)}: these formulas change the flux at every step.`,
      " Summed over steps 0..t (what the gather reads): ", w("accumulated"), "."]);
    legend.textContent = `${params.labels[state.corrections]}. Colour: flux per cell relative to this step's `
      + `brightest cell (square root, so the faint front shows); ${general(params.source_flux, 3)} W per colour channel injected.`;
  }
  window.addEventListener("resize", () => draw());
  draw();
  if (params.play) { play.click(); }
}
