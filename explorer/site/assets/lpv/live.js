// The live LPV of a lesson step (explorer/site/live_lpv.py writes its figure and data):
// controls for every correction switch, both presets, iterations, the grid sizes and
// lights the build baked, the geometry volume, 6 or 26 neighbours and the gather
// damping; the page runs
// injection and propagation in a Worker (twin.js, float64), gathers with WebGL2
// (gather.js) and shows the picture with the window's tone map (display.js), the
// step's numbers, the flux in flight per step and a slice of the grid. Without WebGL2 or
// float render targets it keeps the baked picture and says why.
import * as K from "../generated/constants.js";
import {autoExposureScale, encode} from "./display.js";
import {Gatherer, unsupportedReason} from "./gather.js";

const GEOMETRY_MODES = ["off", "one-sided", "double-sided"];
const AXES = ["x", "y", "z"];
const SVG = "http://www.w3.org/2000/svg";

function element(tag, attributes = {}, children = []) {
  const node = document.createElement(tag);
  for (const [name, value] of Object.entries(attributes)) {
    if (name === "text") {
      node.textContent = value;
    } else {
      node.setAttribute(name, value);
    }
  }
  children.forEach((child) => node.append(child));
  return node;
}

function svgElement(tag, attributes = {}) {
  const node = document.createElementNS(SVG, tag);
  for (const [name, value] of Object.entries(attributes)) {
    node.setAttribute(name, value);
  }
  return node;
}

function sum3(v) {
  return v[0] + v[1] + v[2];
}

function watts(value) {
  if (!Number.isFinite(value)) {
    return String(value);
  }
  const magnitude = Math.abs(value);
  if (magnitude !== 0 && (magnitude < 1e-3 || magnitude >= 1e5)) {
    return value.toExponential(2) + " W";
  }
  return value.toPrecision(3) + " W";
}

async function fetchFloats(url) {
  const response = await fetch(url);
  if (!response.ok) {
    throw new Error(`${url}: ${response.status} ${response.statusText}`);
  }
  return new Float32Array(await response.arrayBuffer());
}

function slice(floats, place) {
  return floats.subarray(place[0], place[0] + place[1]);
}

let uid = 0;

/** One live LPV figure. */
export class LiveLpv {
  constructor(root) {
    this.root = root;
    this.d = JSON.parse(root.querySelector("script.live-description").textContent);
    this.id = `live-lpv-${++uid}`;
    const step = this.d.step;
    this.state = {corrections: {...step.corrections}, iterations: step.iterations,
                  grid: String(step.grid_size), light: 0, geometry: step.geometry_volume,
                  damping: step.gather_damping, neighbours: step.neighbours || 6,
                  view: step.indirect_only ? "indirect" : this.d.view || "final",
                  sliceAxis: 1, sliceLayer: null};
    this.status = root.querySelector(".live-status");
    this.canvas = root.querySelector("canvas.live-canvas");
    this.baked = root.querySelector("img.live-baked");
    this.loading = null;
    this.busy = false;
    this.pending = false;
    this.waiters = [];
    this.messages = new Map();
    this.nextMessage = 0;
    this.result = null;
    this.lights = [];
    this.build();
  }

  // --- controls -------------------------------------------------------------------------
  build() {
    const controls = this.root.querySelector(".live-controls");
    const d = this.d;
    const switches = element("fieldset", {class: "live-switches"},
                             [element("legend", {text: "Corrections"})]);
    this.boxes = {};
    for (const entry of d.corrections) {
      const box = element("input", {type: "checkbox", id: `${this.id}-${entry.name}`,
                                    "data-correction": entry.name});
      box.checked = this.state.corrections[entry.name];
      box.addEventListener("change", () => {
        this.state.corrections[entry.name] = box.checked;
        this.changed();
      });
      const label = element("label", {for: box.id, title: entry.why}, [box, " " + entry.title]);
      switches.append(label);
      this.boxes[entry.name] = box;
    }
    const presets = element("div", {class: "live-presets"});
    for (const [name, text] of [["original", "As published"], ["corrected", "Corrected"]]) {
      const button = element("button", {type: "button", class: "secondary",
                                        "data-preset": name, text});
      button.addEventListener("click", () => {
        Object.assign(this.state.corrections, d.presets[name]);
        for (const [key, box] of Object.entries(this.boxes)) {
          box.checked = this.state.corrections[key];
        }
        this.changed();
      });
      presets.append(button);
    }
    switches.append(presets);

    const settings = element("fieldset", {class: "live-settings"},
                             [element("legend", {text: "Settings"})]);
    const iterations = element("input", {type: "range", min: "0", max: String(d.max_iterations),
                                         step: "1", value: String(this.state.iterations),
                                         id: `${this.id}-iterations`, "data-control": "iterations"});
    const iterationsOut = element("output", {for: iterations.id,
                                             text: String(this.state.iterations)});
    const speak = () => iterations.setAttribute(
      "aria-valuetext", `${iterations.value} propagation steps`);
    speak();
    iterations.addEventListener("input", () => {
      this.state.iterations = parseInt(iterations.value, 10);
      iterationsOut.textContent = iterations.value;
      speak();
      this.changed();
    });
    settings.append(element("label", {for: iterations.id}, ["Iterations ", iterationsOut]),
                    iterations);
    settings.append(this.select("Grid size", "grid", Object.keys(d.grids).map(
      (size) => [size, `${size}³ cells`])));
    settings.append(this.select("Light", "light", d.lights.map((light, i) => [String(i),
                                                                               light.label])));
    settings.append(this.select("Geometry volume", "geometry",
                                GEOMETRY_MODES.map((mode) => [mode, mode])));
    settings.append(this.select("Neighbours", "neighbours",
                                [["6", "6: faces"],
                                 ["26", "26: also edges, corners"]]));
    const damping = element("input", {type: "checkbox", id: `${this.id}-damping`,
                                      "data-control": "damping"});
    damping.checked = this.state.damping;
    damping.addEventListener("change", () => {
      this.state.damping = damping.checked;
      this.changed();
    });
    settings.append(element("label", {for: damping.id}, [damping, " Gather damping"]));
    settings.append(this.select("Picture", "view", [["final", "final (direct + indirect)"],
                                                    ["indirect", "indirect light only"]]));

    this.numbers = element("dl", {class: "live-numbers"});
    this.timing = element("p", {class: "live-timing"});
    this.plot = element("figure", {class: "live-plot"});
    this.sliceCanvas = element("canvas", {class: "live-slice", width: "16", height: "16",
                                          role: "img"});
    const sliceControls = element("div", {class: "live-slice-controls"});
    sliceControls.append(this.select("Slice across", "sliceAxis",
                                     AXES.map((axis, i) => [String(i), axis])));
    const cells = d.step.grid_size;
    this.layer = element("input", {type: "range", min: "0", max: String(cells - 1), step: "1",
                                   value: String(Math.floor(cells / 2)),
                                   id: `${this.id}-layer`, "data-control": "layer"});
    this.layer.addEventListener("input", () => {
      this.state.sliceLayer = parseInt(this.layer.value, 10);
      if (this.result === null) {
        this.changed();
      } else {
        this.drawSlice();
      }
    });
    sliceControls.append(element("label", {for: this.layer.id, text: "Layer "}), this.layer);
    const sliceFigure = element("figure", {class: "live-slice-figure"},
                                [this.sliceCanvas, sliceControls,
                                 element("figcaption", {text: "The accumulated grid's flux per " +
                                   "cell in one layer, log scale over three decades (white: " +
                                   "the brightest cell)."})]);
    const readouts = element("div", {class: "live-readouts"},
                             [element("div", {}, [this.numbers, this.timing]),
                              element("div", {class: "live-figures"},
                                                    [this.plot, sliceFigure])]);
    controls.append(switches, settings, readouts);
    controls.hidden = false;
    const reason = unsupportedReason();
    this.unsupported = reason;
    this.say(reason ? `The live LPV is off: ${reason}; the picture is the baked one.`
      : `Change any control to run this LPV in the page (it loads ${this.megabytes()} MB).`);
    if (reason) {
      controls.querySelectorAll("input, select, button").forEach((c) => { c.disabled = true; });
    }
  }

  select(text, key, options) {
    const id = `${this.id}-${key}`;
    const node = element("select", {id, "data-control": key});
    for (const [value, label] of options) {
      node.append(element("option", {value, text: label}));
    }
    node.value = String(this.state[key]);
    node.addEventListener("change", () => {
      const numeric = key === "light" || key === "sliceAxis" || key === "neighbours";
      this.state[key] = numeric ? parseInt(node.value, 10) : node.value;
      if (this.result !== null && key === "sliceAxis") {
        this.drawSlice();
      } else if (this.result !== null && key === "view") {
        this.show();
      } else {
        this.changed();   // the first change of any control starts the live LPV
      }
    });
    return element("label", {for: id, class: "live-select"}, [text + " ", node]);
  }

  megabytes() {
    const bytes = this.d.gbuffer.bytes + this.d.lights[0].bytes;
    return (bytes / 2 ** 20).toFixed(1);
  }

  say(text) {
    this.status.textContent = " " + text;
  }

  // --- data -----------------------------------------------------------------------------
  /** Send a message to every worker; a promise of their answers, in worker order. */
  post(message) {
    return Promise.all(this.workers.map(({worker, channels}) => {
      const id = ++this.nextMessage;
      return new Promise((resolve, reject) => {
        this.messages.set(id, {resolve, reject});
        const body = message.type === "run"
          ? {...message, request: {...message.request, channels}} : message;
        worker.postMessage({id, ...body});
      });
    }));
  }

  /** A run spread over the workers, as one: the channels never mix, so the grids and
   * the audit terms of disjoint channels add up exactly; a time is the slowest worker's. */
  async run(request) {
    const answers = await this.post({type: "run", request});
    const [first, ...rest] = answers;
    const audit = first.audit;
    for (const other of rest) {
      for (let i = 0; i < first.accumulated.length; i++) {
        first.accumulated[i] += other.accumulated[i];
      }
      for (const [name, value] of Object.entries(other.audit)) {
        const rows = name === "injected" || name === "accumulated" ? [[audit[name], value]]
          : audit[name].map((row, t) => [row, value[t]]);
        rows.forEach(([mine, theirs]) => mine.forEach((_, c) => { mine[c] += theirs[c]; }));
      }
      for (const [name, ms] of Object.entries(other.ms)) {
        first.ms[name] = Math.max(first.ms[name], ms);
      }
      first.continued = first.continued && other.continued;
    }
    return first;
  }

  /** Load the G-buffer, start the workers and the gather (once). */
  start() {
    if (this.loading === null) {
      this.loading = (async () => {
        if (this.unsupported) {
          throw new Error(this.unsupported);
        }
        this.say("loading the G-buffer and the VPLs…");
        // up to one worker per colour channel, as many as the machine has cores
        const count = Math.max(1, Math.min(3, navigator.hardwareConcurrency || 1));
        this.workers = Array.from({length: count}, (_, i) => ({
          worker: new Worker(new URL("./worker.js", import.meta.url), {type: "module"}),
          channels: [0, 1, 2].filter((c) => c % count === i)}));
        for (const {worker} of this.workers) {
          worker.onmessage = (event) => {
            const waiter = this.messages.get(event.data.id);
            this.messages.delete(event.data.id);
            if (event.data.error) {
              waiter.reject(new Error(event.data.error));
            } else {
              waiter.resolve(event.data);
            }
          };
        }
        const g = this.d.gbuffer;
        const floats = await fetchFloats(new URL(g.url, document.baseURI));
        this.gbuffer = {position: slice(floats, g.arrays.position),
                        normal: slice(floats, g.arrays.normal),
                        albedo: slice(floats, g.arrays.albedo)};
        this.mask = new Uint8Array(this.d.width * this.d.height);
        for (let i = 0; i < this.mask.length; i++) {
          this.mask[i] = this.gbuffer.position[4 * i + 3] > 0.5 ? 1 : 0;
        }
        this.gatherer = new Gatherer(this.d.width, this.d.height, this.gbuffer);
      })();
    }
    return this.loading;
  }

  /** The light choice's direct light and VPLs (fetched once each). */
  async light(index) {
    if (!this.lights[index]) {
      this.lights[index] = (async () => {
        const entry = this.d.lights[index];
        const floats = await fetchFloats(new URL(entry.url, document.baseURI));
        const views = entry.views.map((view) => ({
          count: view.count, texelArea: view.texelArea, projection: view.projection,
          positions: slice(floats, view.positions), normals: slice(floats, view.normals),
          flux: slice(floats, view.flux), depth: slice(floats, view.depth)}));
        await this.post({type: "light", index, views});
        return {direct: slice(floats, entry.direct)};
      })();
    }
    return this.lights[index];
  }

  request() {
    const s = this.state;
    return {light: s.light, spec: this.d.grids[s.grid], corrections: {...s.corrections},
            iterations: s.iterations, offset: this.d.step.injection_offset_cells,
            geometry: s.geometry, neighbours: s.neighbours};
  }

  /** Any control changed: compute again (coalescing changes that come while it runs). */
  changed() {
    if (this.unsupported) {
      return;
    }
    if (this.busy) {
      this.pending = true;
      return;
    }
    this.busy = true;
    this.compute().catch((error) => {
      this.say(`The live LPV stopped: ${error.message}`);
      this.failed = error;
    }).finally(() => {
      this.busy = false;
      if (this.pending) {
        this.pending = false;
        this.changed();
      } else {
        this.waiters.splice(0).forEach((resolve) => resolve(this.result));
      }
    });
  }

  /** A promise of the result once every change made so far is computed and shown. */
  settled() {
    if (!this.busy && !this.pending) {
      return Promise.resolve(this.result);
    }
    return new Promise((resolve) => this.waiters.push(resolve));
  }

  /** Run the twin in the worker on a request of the test's (views instead of a light). */
  async twin(request) {
    await this.start();
    return this.run(request);
  }

  async compute() {
    await this.start();
    const request = this.request();
    const light = await this.light(request.light);
    this.say("propagating…");
    const answer = await this.run(request);
    const spec = request.spec;
    const began = performance.now();
    this.gatherer.uploadGrid(answer.accumulated, spec.resolution);
    const gathered = this.gatherer.gather(spec, this.state.damping,
                                          request.corrections.irradiance_gather !== false);
    const gatherMs = performance.now() - began;
    let received = 0.0;
    for (let i = 0; i < gathered.received.length; i += 4) {
      received += gathered.received[i] + gathered.received[i + 1] + gathered.received[i + 2];
    }
    this.result = {request, audit: answer.audit, ms: {...answer.ms, gather: gatherMs},
                   accumulated: answer.accumulated, continued: answer.continued,
                   indirect: gathered.indirect, direct: light.direct, gathered: received};
    this.show();
    this.report();
    this.drawPlot();
    this.drawSlice();
  }

  // --- what is shown --------------------------------------------------------------------
  show() {
    const r = this.result;
    if (r === null) {
      return;
    }
    const s = this.d.step;
    const pixels = this.d.width * this.d.height;
    const indirectOnly = this.state.view === "indirect";
    const unexposed = new Float64Array(pixels * 3);
    for (let i = 0; i < pixels; i++) {
      for (let c = 0; c < 3; c++) {
        const indirect = r.indirect[4 * i + c];
        unexposed[3 * i + c] = indirectOnly ? indirect
          : Math.fround(r.direct[3 * i + c] + indirect);
      }
    }
    const scale = s.auto_exposure ? autoExposureScale(this.d.display, unexposed, this.mask)
      : 1.0;
    const exposure = Math.fround(s.exposure);
    const exposed = unexposed.map((v) => Math.fround(exposure * v));
    const bytes = encode(this.d.display, exposed, scale, s.tone_map, pixels);
    this.canvas.width = this.d.width;
    this.canvas.height = this.d.height;
    this.canvas.getContext("2d").putImageData(new ImageData(bytes, this.d.width,
                                                            this.d.height), 0, 0);
    this.canvas.hidden = false;
    this.canvas.setAttribute("role", "img");
    this.canvas.setAttribute("aria-label", this.describe());
    this.baked.hidden = true;
    r.scale = scale;
    r.bytes = bytes;
  }

  describe() {
    const off = this.d.corrections.filter((e) => !this.state.corrections[e.name])
      .map((e) => e.title);
    const view = this.state.view === "indirect" ? "The indirect light" : "The final image";
    return `${view} of the live LPV, ${this.state.iterations} propagation steps on a ` +
      `${this.state.grid}³ grid over ${this.state.neighbours} neighbours, ` + (off.length ? `switched off: ${off.join("; ")}.`
        : "every correction on.");
  }

  report() {
    const r = this.result;
    const a = r.audit;
    const steps = a.per_step.map(sum3);
    const total = (list) => list.reduce((acc, v) => acc + sum3(v), 0.0);
    const rows = [
      ["injected", watts(sum3(a.injected))],
      [`in flight after step ${steps.length - 1}`, watts(steps[steps.length - 1])],
      ["one step keeps", steps.length > 1 && steps[0] !== 0 ? (steps[1] / steps[0]).toFixed(4)
        : "no step"],
      ["accumulated", watts(sum3(a.accumulated))],
      ["left through the border", watts(total(a.border_loss))],
      ["made by the front-face clamp", watts(total(a.clamp_gain))],
      ["stopped by the geometry volume", watts(total(a.occluded))],
      ["gathered by the visible surfaces", watts(r.gathered)],
    ];
    this.numbers.replaceChildren(...rows.flatMap(([name, value]) => [
      element("dt", {text: name}), element("dd", {text: value, "data-q": name})]));
    this.timing.textContent = `Measured in this browser: injection and propagation ` +
      `${r.ms.total.toFixed(0)} ms` + (r.continued ? " (continued from the last run)" : "") +
      `, gather ${r.ms.gather.toFixed(0)} ms.`;
    this.say(`${steps.length - 1} steps on ${this.state.grid}³ cells: ` +
             `${watts(sum3(a.accumulated))} accumulated.`);
  }

  drawPlot() {
    const steps = this.result.audit.per_step.map(sum3);
    // the window's GPU frame of the step as it opens (the build's), under every run
    const opening = this.d.window_per_step;
    const series = [["opening", opening], ["series", steps]];
    const every = series.flatMap(([, values]) => values);
    const last = Math.max(...series.map(([, values]) => values.length)) - 1;
    const width = 320;
    const height = 150;
    const pad = {left: 60, right: 8, top: 8, bottom: 24};
    const positive = every.filter((v) => v > 0);
    const top = Math.max(...every, 0);
    const low = positive.length ? Math.min(...positive) : 0;
    const log = positive.length === every.length && low > 0 && top / low > 100;
    const yOf = (v) => {
      const f = log ? Math.log10(Math.max(v, low) / low) / Math.log10(top / low)
        : v / (top || 1);
      return (pad.top + (1 - f) * (height - pad.top - pad.bottom)).toFixed(1);
    };
    const xOf = (t) => (pad.left + (last > 0 ? t / last : 0)
      * (width - pad.left - pad.right)).toFixed(1);
    const svg = svgElement("svg", {viewBox: `0 0 ${width} ${height}`, role: "img",
                                   "aria-label": "Flux in flight after each step: " +
                                     steps.map((v, t) => `step ${t}: ${watts(v)}`).join(", ")});
    svg.append(svgElement("line", {x1: pad.left, y1: height - pad.bottom, x2: width - pad.right,
                                   y2: height - pad.bottom, class: "axis"}));
    svg.append(svgElement("line", {x1: pad.left, y1: pad.top, x2: pad.left,
                                   y2: height - pad.bottom, class: "axis"}));
    for (const [css, values] of series) {
      svg.append(svgElement("polyline", {class: css, points: values.map(
        (v, t) => `${xOf(t)},${yOf(v)}`).join(" ")}));
    }
    steps.forEach((v, t) => {
      const dot = svgElement("circle", {cx: xOf(t), cy: yOf(v), r: "2.5", class: "point"});
      const title = svgElement("title");
      title.textContent = `step ${t}: ${watts(v)}`;
      dot.append(title);
      svg.append(dot);
    });
    const label = (x, y, text, anchor) => {
      const node = svgElement("text", {x, y, "text-anchor": anchor});
      node.textContent = text;
      svg.append(node);
    };
    label(pad.left - 4, pad.top + 8, watts(top), "end");
    label(pad.left - 4, height - pad.bottom, log ? watts(low) : "0 W", "end");
    label(pad.left, height - 6, "step 0", "start");
    label(width - pad.right, height - 6, `step ${last}`, "end");
    this.plot.replaceChildren(svg, element("figcaption", {
      text: `Flux in flight after each step (${log ? "log" : "linear"} scale); dashed: ` +
        "the step as it opens, rendered by the explorer's GPU pipeline."}));
  }

  drawSlice() {
    if (this.result === null) {
      return;
    }
    const n = this.result.request.spec.resolution;
    const axis = this.state.sliceAxis;
    if (this.state.sliceLayer === null || this.state.sliceLayer >= n) {
      this.state.sliceLayer = Math.floor(n / 2);
    }
    this.layer.max = String(n - 1);
    this.layer.value = String(this.state.sliceLayer);
    this.layer.setAttribute("aria-valuetext", `layer ${this.state.sliceLayer} of ${n}`);
    const grid = this.result.accumulated;
    const stride = n * n * n * 4;
    const values = new Float64Array(n * n);
    let peak = 0.0;
    for (let a = 0; a < n; a++) {
      for (let b = 0; b < n; b++) {
        const cell = [0, 0, 0];
        const others = [0, 1, 2].filter((k) => k !== axis);
        cell[axis] = this.state.sliceLayer;
        cell[others[0]] = a;
        cell[others[1]] = b;
        const at = ((cell[0] * n + cell[1]) * n + cell[2]) * 4;
        const v = K.SH_FLUX_FACTOR * (grid[at] + grid[stride + at] + grid[2 * stride + at]);
        values[(n - 1 - b) * n + a] = v;   // the second axis up
        peak = Math.max(peak, v);
      }
    }
    const image = new ImageData(n, n);
    for (let i = 0; i < n * n; i++) {
      const f = peak > 0 && values[i] > 0
        ? Math.max(0, 1 + Math.log10(values[i] / peak) / 3) : 0;
      image.data[4 * i] = Math.round(255 * Math.min(1, 1.6 * f));
      image.data[4 * i + 1] = Math.round(255 * Math.max(0, Math.min(1, 1.6 * f - 0.45)));
      image.data[4 * i + 2] = Math.round(255 * Math.max(0, 2.2 * f - 1.2));
      image.data[4 * i + 3] = 255;
    }
    this.sliceCanvas.width = n;
    this.sliceCanvas.height = n;
    this.sliceCanvas.getContext("2d").putImageData(image, 0, 0);
    this.sliceCanvas.setAttribute("aria-label", `Layer ${this.state.sliceLayer} across ` +
      `${AXES[axis]} of the accumulated grid; brightest cell ${watts(peak)}.`);
  }
}

for (const root of document.querySelectorAll("[data-live-lpv]")) {
  root.lpvLive = new LiveLpv(root);
}
