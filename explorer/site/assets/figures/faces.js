// A cell's neighbour, its five faces and their solid angles: the window's figure
// (explorer/ui/figures/cell_faces.py). Cells have side 2, the source centred at the
// origin; the exact solid angles are the derived constants, and each face's quadrature
// of cos θ/r² is the window's (Gauss–Legendre, 24² nodes).
import {
  CUBE_FACE_SOLID_ANGLE, FOUR_PI, FRONT_FACE_SOLID_ANGLE, PUBLISHED_SIDE_FACE_SOLID_ANGLE,
  SIDE_FACE_SOLID_ANGLE,
} from "lpv/generated/constants.js";
import { el, fixed, gaussLegendre, percent, radians, readout, sentence, show, svg } from "lpv/figures/common.js";

export const DIRECTIONS = ["+x", "-x", "+y", "-y", "+z", "-z"];
const AXES = "xyz";
const QUADRATURE_NODES = 24;      // as cell_faces._QUADRATURE_NODES
const PATCH_STEPS = 10;
const MINUS = "\u2212";

// cell_faces.neighbour_faces: front first, then the four sides.
export function neighbourFaces(direction) {
  const axis = AXES.indexOf(direction[1]);
  const sign = direction[0] === "+" ? 1 : -1;
  const others = [0, 1, 2].filter((k) => k !== axis);
  const span = [Math.min(sign, 3 * sign), Math.max(sign, 3 * sign)];
  const faces = [{ name: "front", axis, plane: 3 * sign, low: [-1, -1], high: [1, 1], front: true }];
  for (const sideAxis of others) {
    for (const sideSign of [1, -1]) {
      const spans = [0, 1, 2].filter((k) => k !== sideAxis).map((k) => (k === axis ? span : [-1, 1]));
      faces.push({ name: `side ${sideSign > 0 ? "+" : MINUS}${AXES[sideAxis]}`, axis: sideAxis,
                   plane: sideSign, low: [spans[0][0], spans[1][0]],
                   high: [spans[0][1], spans[1][1]], front: false });
    }
  }
  return faces;
}

function facePoint(face, u, v) {
  const [a, b] = [0, 1, 2].filter((k) => k !== face.axis);
  const p = [0, 0, 0];
  p[face.axis] = face.plane;
  p[a] = face.low[0] + u * (face.high[0] - face.low[0]);
  p[b] = face.low[1] + v * (face.high[1] - face.low[1]);
  return p;
}

const [NODES, WEIGHTS] = gaussLegendre(QUADRATURE_NODES);

// cell_faces.face_solid_angle_numeric: ∫ |plane| / r³ dA over the face.
export function numericSolidAngle(face) {
  const area = (face.high[0] - face.low[0]) * (face.high[1] - face.low[1]);
  let sum = 0;
  for (let i = 0; i < QUADRATURE_NODES; i++) {
    for (let j = 0; j < QUADRATURE_NODES; j++) {
      const p = facePoint(face, (NODES[i] + 1) / 2, (NODES[j] + 1) / 2);
      const r = Math.hypot(...p);
      sum += (WEIGHTS[i] * WEIGHTS[j] / 4 * area) * Math.abs(face.plane) / r ** 3;
    }
  }
  return sum;
}

// The window's readouts() for a direction and a highlighted face (−1: none).
export function numbers(direction, highlighted) {
  const faces = neighbourFaces(direction);
  const numeric = faces.map(numericSolidAngle);
  const every = DIRECTIONS.flatMap((d) => neighbourFaces(d).map(numericSolidAngle));
  const values = {
    front: FRONT_FACE_SOLID_ANGLE, side: SIDE_FACE_SOLID_ANGLE,
    front_numeric: numeric[0], side_numeric: numeric[1],
    five_faces: FRONT_FACE_SOLID_ANGLE + 4 * SIDE_FACE_SOLID_ANGLE,
    five_faces_numeric: numeric.reduce((s, v) => s + v, 0),
    cube_face: CUBE_FACE_SOLID_ANGLE,
    thirty_faces: 6 * (FRONT_FACE_SOLID_ANGLE + 4 * SIDE_FACE_SOLID_ANGLE),
    thirty_faces_numeric: every.reduce((s, v) => s + v, 0), sphere: FOUR_PI,
    published_side: PUBLISHED_SIDE_FACE_SOLID_ANGLE,
  };
  if (highlighted >= 0 && highlighted < faces.length) {
    values.highlighted = faces[highlighted].front ? FRONT_FACE_SOLID_ANGLE : SIDE_FACE_SOLID_ANGLE;
    values.highlighted_numeric = numeric[highlighted];
  }
  return { values, faces, numeric };
}

// A fixed view: turned about the vertical, then tilted toward the reader (orthographic).
const YAW = radians(-35);
const PITCH = radians(22);
function project([x, y, z]) {
  const x1 = Math.cos(YAW) * x + Math.sin(YAW) * z;
  const z1 = -Math.sin(YAW) * x + Math.cos(YAW) * z;
  const y2 = Math.cos(PITCH) * y - Math.sin(PITCH) * z1;
  const depth = Math.sin(PITCH) * y + Math.cos(PITCH) * z1;
  return [x1, -y2, depth];
}

function polygon(points3d) {
  return points3d.map((p) => project(p)).map(([x, y]) => `${x.toFixed(4)},${y.toFixed(4)}`).join(" ");
}

function corners(face) {
  return [[0, 0], [1, 0], [1, 1], [0, 1]].map(([u, v]) => facePoint(face, u, v));
}

function outlineOnSphere(face) {
  const points = [];
  const t = [...Array(PATCH_STEPS + 1).keys()].map((k) => k / PATCH_STEPS);
  t.forEach((s) => points.push(facePoint(face, s, 0)));
  t.forEach((s) => points.push(facePoint(face, 1, s)));
  t.forEach((s) => points.push(facePoint(face, 1 - s, 1)));
  t.forEach((s) => points.push(facePoint(face, 0, 1 - s)));
  return points.map((p) => { const r = Math.hypot(...p); return p.map((v) => v / r); });
}

function cubeEdges(centre, parent, css) {
  const lines = [];
  for (const axis of [0, 1, 2]) {
    const [a, b] = [0, 1, 2].filter((k) => k !== axis);
    for (const sa of [-1, 1]) {
      for (const sb of [-1, 1]) {
        const p = [0, 0, 0];
        const q = [0, 0, 0];
        p[axis] = -1; q[axis] = 1; p[a] = q[a] = sa; p[b] = q[b] = sb;
        const [x1, y1] = project(p.map((v, k) => v + centre[k]));
        const [x2, y2] = project(q.map((v, k) => v + centre[k]));
        lines.push(svg("line", { x1, y1, x2, y2, class: css }, parent));
      }
    }
  }
  return lines;
}

export function mount(root, params) {
  const state = { direction: params.direction,
                  highlighted: { none: -1, front: 0, side: 1 }[params.highlight] };
  const body = el("div", { class: "live-body faces" }, root);
  const picker = el("div", { class: "live-controls", role: "radiogroup",
                             "aria-label": "Which neighbour" }, body);
  el("span", { class: "live-label" }, picker, "neighbour");
  const directionButtons = DIRECTIONS.map((d) => {
    const button = el("button", { type: "button", class: "secondary choice-button",
                                  role: "radio", "data-direction": d }, picker, d.replace("-", MINUS));
    button.addEventListener("click", () => { state.direction = d; draw(); });
    return button;
  });
  const views = el("div", { class: "live-views" }, body);
  const showCells = params.view !== "sphere";
  const showSphere = params.view !== "cells";
  const cellsSvg = showCells ? svg("svg", { class: "live-svg", viewBox: "-4.2 -4.2 8.4 8.4", role: "img" }, views) : null;
  const sphereSvg = showSphere ? svg("svg", { class: "live-svg", viewBox: "-1.15 -1.15 2.3 2.3", role: "img" }, views) : null;
  const wrap = el("div", { class: "table-wrap" }, body);
  const table = el("table", { class: "live-table faces-table" }, wrap);
  const head = el("tr", {}, el("thead", {}, table));
  const firstHead = el("th", { scope: "col" }, head);
  ["solid angle (derived)", "quadrature ∫cos θ/r² dA", "share of the sphere"]
    .forEach((title) => el("th", { scope: "col" }, head, title));
  const tbody = el("tbody", {}, table);
  const note = el("p", { class: "live-note" }, body);
  const highlightedNote = el("p", { class: "live-note", "aria-live": "polite" }, body);

  function cellsFor(tr, exactName, numericName) {
    const cells = [exactName, numericName, `${exactName}_share`].map((name) => readout(el("td", {}, tr), name));
    return cells;
  }
  function setCells(cells, exact, numeric) {
    show(cells[0], exact, `${fixed(exact, 6)} sr`);
    show(cells[1], numeric, `${fixed(numeric, 6)} sr`);
    show(cells[2], exact / FOUR_PI, percent(exact / FOUR_PI, 2));
  }
  function select(index) { state.highlighted = index; draw(); }

  let rows = [];
  let tableDirection = null;
  // the face rows, made once per neighbour (a highlight only restyles them, so a focused
  // row keeps its focus)
  function buildTable(faces, values, numeric) {
    tableDirection = state.direction;
    firstHead.textContent = `face of the ${state.direction.replace("-", MINUS)} neighbour`;
    tbody.replaceChildren();
    rows = faces.map((face, index) => {
      const tr = el("tr", {}, tbody);
      const th = el("th", { scope: "row" }, tr);
      const button = el("button", { type: "button", class: `face-row ${face.front ? "front" : "side"}`,
                                    "data-face": String(index) }, th, face.name);
      button.addEventListener("click", () => select(index));
      button.addEventListener("pointerenter", () => { if (state.highlighted !== index) { select(index); } });
      button.addEventListener("keydown", (event) => {
        const step = { ArrowDown: 1, ArrowRight: 1, ArrowUp: -1, ArrowLeft: -1 }[event.key];
        if (!step) { return; }
        event.preventDefault();
        const next = (index + step + faces.length) % faces.length;
        select(next);
        rows[next].button.focus();
      });
      const name = ["front", "side"][index] || `face${index}`;     // as readouts() names them
      setCells(cellsFor(tr, name, `${name}_numeric`),
               face.front ? FRONT_FACE_SOLID_ANGLE : SIDE_FACE_SOLID_ANGLE, numeric[index]);
      return { tr, button };
    });
    for (const [title, exact, num, key] of [["the five together", values.five_faces, values.five_faces_numeric, "five_faces"],
                                            ["all 30 faces", values.thirty_faces, values.thirty_faces_numeric, "thirty_faces"]]) {
      const tr = el("tr", { class: "total" }, tbody);
      el("th", { scope: "row" }, tr, title);
      setCells(cellsFor(tr, key, `${key}_numeric`), exact, num);
    }
  }

  function draw() {
    const { values, faces, numeric } = numbers(state.direction, state.highlighted);
    directionButtons.forEach((b) => b.setAttribute("aria-checked", String(b.dataset.direction === state.direction)));
    if (tableDirection !== state.direction) { buildTable(faces, values, numeric); }
    rows.forEach(({ tr, button }, index) => {
      tr.classList.toggle("selected", index === state.highlighted);
      button.setAttribute("aria-pressed", String(index === state.highlighted));
    });
    const sr = (name, digits) => [name, values[name], fixed(values[name], digits)];
    sentence(note, [
      "The five faces of one neighbour cover what a face of the source cell covers seen from "
      + "its centre (", sr("cube_face", 6), " sr), so the 30 faces cover the whole sphere, 4π = ",
      sr("sphere", 6), " sr, exactly once. The DX11 article prints the side face as ",
      sr("published_side", 10), " sr; the derivation gives ", sr("side", 10), " sr."]);
    if ("highlighted" in values) {
      sentence(highlightedNote, [
        `Highlighted: the ${faces[state.highlighted].name} face, `, sr("highlighted", 6),
        " sr (quadrature ", sr("highlighted_numeric", 6), " sr)."]);
    } else {
      sentence(highlightedNote, ["Hover, tap or focus a face to highlight it."]);
    }
    if (cellsSvg) { drawCells(faces); }
    if (sphereSvg) { drawSphere(faces); }
  }
  function facePolygon(parent, points, css, index) {
    const shape = svg("polygon", { points, class: css }, parent);
    if (index !== null) {
      shape.addEventListener("pointerenter", () => { if (state.highlighted !== index) { select(index); } });
      shape.addEventListener("click", () => select(index));
      shape.setAttribute("data-face", String(index));
    }
    return shape;
  }
  function drawCells(faces) {
    cellsSvg.replaceChildren();
    const axis = AXES.indexOf(state.direction[1]);
    const sign = state.direction[0] === "+" ? 1 : -1;
    const centre = [0, 0, 0];
    centre[axis] = 2 * sign;
    cubeEdges([0, 0, 0], cellsSvg, "edge source");
    cubeEdges(centre, cellsSvg, "edge neighbour");
    const order = faces.map((face, index) => [index, corners(face).reduce((s, p) => s + project(p)[2], 0)])
      .sort((a, b) => a[1] - b[1]);
    for (const [index] of order) {
      const face = faces[index];
      const css = `face ${face.front ? "front" : "side"}${index === state.highlighted ? " lit" : ""}`;
      facePolygon(cellsSvg, polygon(corners(face)), css, index);
    }
    const [x, y] = project([0, 0, 0]);
    svg("circle", { cx: x, cy: y, r: 0.12, class: "source-dot" }, cellsSvg);
    // the view box fits the two cells: a square around what was drawn
    const box = cellsSvg.getBBox();
    const side = Math.max(box.width, box.height) + 0.4;
    cellsSvg.setAttribute("viewBox", `${box.x + box.width / 2 - side / 2} `
      + `${box.y + box.height / 2 - side / 2} ${side} ${side}`);
    cellsSvg.setAttribute("aria-label", `The source cell and its ${state.direction} neighbour with the neighbour's five faces`);
  }
  function drawSphere(faces) {
    sphereSvg.replaceChildren();
    svg("circle", { cx: 0, cy: 0, r: 1, class: "sphere" }, sphereSvg);
    const shown = params.tiling ? DIRECTIONS : [state.direction];
    const patches = [];
    for (const d of shown) {
      neighbourFaces(d).forEach((face, index) => {
        const outline = outlineOnSphere(face);
        const depth = outline.reduce((s, p) => s + project(p)[2], 0) / outline.length;
        patches.push({ d, index, face, outline, depth });
      });
    }
    patches.sort((a, b) => a.depth - b.depth);
    for (const patch of patches) {
      const mine = patch.d === state.direction;
      const lit = mine && patch.index === state.highlighted;
      const css = `patch n${DIRECTIONS.indexOf(patch.d)} ${patch.face.front ? "front" : "side"}`
        + `${mine ? " mine" : ""}${lit ? " lit" : ""}${patch.depth < 0 ? " back" : ""}`;
      facePolygon(sphereSvg, polygon(patch.outline), css, mine ? patch.index : null);
    }
    sphereSvg.setAttribute("aria-label", params.tiling ? "The 30 faces of the six neighbours on the unit sphere"
      : "The five faces projected on the unit sphere");
  }
  draw();
}
