// The float64 twin of injection, geometry-volume injection and propagation, ported from
// explorer/lpv/twin/light_grid.py line by line so that the page's LPV is the desktop's twin: the
// same scatter form (every source cell sends through the five faces of each of its six
// neighbours, or with 26 neighbours through the outer faces of each neighbour on its 3×3×3
// block), the same order of the directions and faces, the same correction switches
// (derivations/correction_registry.py), in float64 (JavaScript numbers). Grids are flat
// Float64Arrays in the twin's (3, N, N, N, 4) order: ((c·N + x)·N + y)·N + z, then the
// four L1 coefficients. Every constant comes from the derivations through the code
// generator (the constants module); docs/MODEL.md is the math contract.
import * as K from "../generated/constants.js";

const COEFFS = 4;   // L1: the page's LPV is the twin's L1 path
/** Every colour channel. The channels never mix (the grid's r, g and b propagate apart),
 * so a run over some of them leaves the others zero and runs over disjoint channels add
 * up, exactly, to the run over all: what lets the page spread a run over Workers. */
export const ALL_CHANNELS = [0, 1, 2];

/** π as the formulas use it: the DX11 article's decimals unless exact constants. */
export function formulaPi(c) {
  return c.exact_constants ? K.PI : K.PUBLISHED_PI;
}

/** k_I = 1/π (corrected) or 1 (published). */
export function injectionFactor(c) {
  return c.injection_pi ? 1.0 / formulaPi(c) : 1.0;
}

/** k_P = 1 (corrected) or 1/(4π) (published). */
export function propagationFactor(c) {
  return c.propagation_4pi ? 1.0 : 1.0 / (4.0 * formulaPi(c));
}

/** k_R = 1 (corrected) or 1/π (published). */
export function reprojectionFactor(c) {
  return c.reprojection_pi ? 1.0 : 1.0 / formulaPi(c);
}

/** [front, side] solid angles: exact, or the DX11 article's decimals. */
export function faceSolidAngles(c) {
  if (c.exact_constants) {
    return [K.FRONT_FACE_SOLID_ANGLE, K.SIDE_FACE_SOLID_ANGLE];
  }
  return [K.PUBLISHED_FRONT_FACE_SOLID_ANGLE, K.PUBLISHED_SIDE_FACE_SOLID_ANGLE];
}

/**
 * [front, side]: a face's whole factor k_R·k_I·k_P·Δω_f, or with model_face_weights off
 * the DX11 shader's Δω_front/(2π) and Δω_side/(3π) (twin.face_weights).
 */
export function faceWeights(c) {
  const [frontAngle, sideAngle] = faceSolidAngles(c);
  if (!c.model_face_weights) {
    const pi = formulaPi(c);
    return [K.DX11_FRONT_SHARE / pi * frontAngle, K.DX11_SIDE_SHARE / pi * sideAngle];
  }
  const scale = reprojectionFactor(c) * injectionFactor(c) * propagationFactor(c);
  return [scale * frontAngle, scale * sideAngle];
}

/** Y(ω) = (c0, −c1·ω.y, c1·ω.z, −c1·ω.x). */
export function shBasis(d) {
  return [K.SH_C0, -K.SH_C1 * d[1], K.SH_C1 * d[2], -K.SH_C1 * d[0]];
}

/** The SH projection of clamp+(<n, ω>). */
export function cosineLobe(n) {
  return [K.SH_COSLOBE_C0, -K.SH_COSLOBE_C1 * n[1], K.SH_COSLOBE_C1 * n[2],
          -K.SH_COSLOBE_C1 * n[0]];
}

/** [r, g, b] flux of a grid: 2√π times the sum of coefficient 0 per channel. */
export function flux(grid, n) {
  const cells = n * n * n;
  const out = [0, 0, 0];
  for (let c = 0; c < 3; c++) {
    let sum = 0.0;
    const base = c * cells * COEFFS;
    for (let i = 0; i < cells; i++) {
      sum += grid[base + i * COEFFS];
    }
    out[c] = K.SH_FLUX_FACTOR * sum;
  }
  return out;
}

function checkOffset(offsetCells) {
  if (!(Number.isFinite(offsetCells) && offsetCells >= 0)) {
    throw new Error("the injection offset must be a finite number of cells >= 0, got "
                    + offsetCells);
  }
}

/**
 * grid[c, cell(p + δ·h·n)] += k_I·Φ[c]·lobe(n) for every VPL inside the grid, in VPL
 * order (numpy's add.at). vpls: {count, positions, normals, flux} (flat, 3 per VPL);
 * spec: {origin: [x, y, z], cellSize, resolution}.
 */
export function inject(vpls, spec, c, offsetCells = 0.0, channels = ALL_CHANNELS) {
  checkOffset(offsetCells);
  const n = spec.resolution;
  const h = spec.cellSize;
  const o = spec.origin;
  const grid = new Float64Array(3 * n * n * n * COEFFS);
  const shift = offsetCells * h;
  const kI = injectionFactor(c);
  const p = vpls.positions;
  const nn = vpls.normals;
  const f = vpls.flux;
  const channelStride = n * n * n * COEFFS;
  for (let i = 0; i < vpls.count; i++) {
    const nx = nn[3 * i];
    const ny = nn[3 * i + 1];
    const nz = nn[3 * i + 2];
    const ix = Math.floor((p[3 * i] + shift * nx - o[0]) / h);
    const iy = Math.floor((p[3 * i + 1] + shift * ny - o[1]) / h);
    const iz = Math.floor((p[3 * i + 2] + shift * nz - o[2]) / h);
    if (ix < 0 || iy < 0 || iz < 0 || ix >= n || iy >= n || iz >= n) {
      continue;
    }
    const lobe = [kI * K.SH_COSLOBE_C0, kI * (-K.SH_COSLOBE_C1 * ny),
                  kI * (K.SH_COSLOBE_C1 * nz), kI * (-K.SH_COSLOBE_C1 * nx)];
    const cell = ((ix * n + iy) * n + iz) * COEFFS;
    for (const ch of channels) {
      const w = f[3 * i + ch];
      const at = ch * channelStride + cell;
      for (let k = 0; k < COEFFS; k++) {
        grid[at + k] += w * lobe[k];
      }
    }
  }
  return grid;
}

/**
 * The geometry volume (N+1)³×4 of one VPL set: each surfel adds A/h²·lobe(n)
 * (one-sided) or A/h²·(lobe(n) + lobe(−n)) to geometry cell round(g). vpls also holds
 * depth (1 per VPL), texelArea and projection ("perspective" | "orthographic").
 */
export function injectGeometry(vpls, spec, c, mode) {
  if (mode !== "one-sided" && mode !== "double-sided") {
    throw new Error("geometry mode must be 'one-sided' or 'double-sided', got " + mode);
  }
  const size = spec.resolution + 1;
  const h = spec.cellSize;
  const o = spec.origin;
  const volume = new Float64Array(size * size * size * 4);
  const p = vpls.positions;
  const nn = vpls.normals;
  for (let i = 0; i < vpls.count; i++) {
    const gx = Math.floor((p[3 * i] - o[0]) / h + 0.5);
    const gy = Math.floor((p[3 * i + 1] - o[1]) / h + 0.5);
    const gz = Math.floor((p[3 * i + 2] - o[2]) / h + 0.5);
    if (gx < 0 || gy < 0 || gz < 0 || gx >= size || gy >= size || gz >= size) {
      continue;
    }
    const normal = [nn[3 * i], nn[3 * i + 1], nn[3 * i + 2]];
    let lobe = cosineLobe(normal);
    if (mode === "double-sided") {
      const back = cosineLobe([-normal[0], -normal[1], -normal[2]]);
      lobe = lobe.map((v, k) => v + back[k]);
    }
    const depth = vpls.depth[i];
    let area;
    if (vpls.projection === "orthographic") {
      area = vpls.texelArea;
    } else {
      area = vpls.texelArea * (c.surfel_area_squared ? depth * depth : depth);
    }
    area = area / (h * h);
    const at = ((gx * size + gy) * size + gz) * 4;
    for (let k = 0; k < 4; k++) {
      volume[at + k] += area * lobe[k];
    }
  }
  return volume;
}

/**
 * Several RSM views' volumes merged as shaders/geometry_merge.glsl does: per geometry
 * cell the view with the larger band-0 coefficient (one view: its volume).
 */
export function mergeGeometry(volumes) {
  const merged = new Float64Array(volumes[0].length);
  for (const volume of volumes) {
    for (let at = 0; at < merged.length; at += 4) {
      if (volume[at] > merged[at]) {
        for (let k = 0; k < 4; k++) {
          merged[at + k] = volume[at + k];
        }
      }
    }
  }
  return merged;
}

/** The faces of the neighbour one step along sign·e_axis: {evaluation, reprojection, front}. */
function faces(axis, sign, sideFaces) {
  const forward = [0, 0, 0];
  forward[axis] = sign;
  const list = [{evaluation: forward, reprojection: forward, front: true}];
  if (sideFaces) {
    const root5 = Math.sqrt(5.0);
    for (const other of [(axis + 1) % 3, (axis + 2) % 3]) {
      for (const sideSign of [1.0, -1.0]) {
        const side = [0, 0, 0];
        side[other] = sideSign;
        const evaluation = side.map((v, k) => v / root5 + (2.0 * forward[k]) / root5);
        list.push({evaluation, reprojection: side, front: false});
      }
    }
  }
  return list;
}

/**
 * (N³×4) the mean geometry SH of the face each source cell s shares with s + sign·e_axis
 * (corners s_axis + 1 for sign > 0, s_axis for sign < 0), summed in the twin's order:
 * corners (u, v), (u + 1, v), (u, v + 1), (u + 1, v + 1) of the two other axes.
 */
function faceBlockers(geometry, n, axis, sign) {
  const size = n + 1;
  const out = new Float64Array(n * n * n * 4);
  const [u, v] = [0, 1, 2].filter((a) => a !== axis);   // the other two, in axis order
  const strides = [size * size * 4, size * 4, 4];
  const du = strides[u];
  const dv = strides[v];
  const lift = sign > 0 ? strides[axis] : 0;
  for (let x = 0; x < n; x++) {
    for (let y = 0; y < n; y++) {
      for (let z = 0; z < n; z++) {
        const a = ((x * size + y) * size + z) * 4 + lift;
        const o = ((x * n + y) * n + z) * 4;
        for (let k = 0; k < 4; k++) {
          out[o + k] = 0.25 * (geometry[a + k] + geometry[a + du + k]
                               + geometry[a + dv + k] + geometry[a + du + dv + k]);
        }
      }
    }
  }
  return out;
}

const visibilityCache = new WeakMap();

/** Every source cell's visibility through `face`: 1 − clip(<blockers, Y(−evaluation)>, 0, 1)
 * (docs/MODEL.md "Geometry volume"), the blockers four SH coefficients a cell. */
function faceVisibility(blockers, face, n) {
  const o = shBasis(face.evaluation.map((value) => -value));
  const seen = new Float64Array(n * n * n);
  for (let i = 0; i < seen.length; i++) {
    const b = blockers[4 * i] * o[0] + blockers[4 * i + 1] * o[1]
      + blockers[4 * i + 2] * o[2] + blockers[4 * i + 3] * o[3];
    seen[i] = 1.0 - Math.min(Math.max(b, 0.0), 1.0);
  }
  return seen;
}

/**
 * For one geometry volume, per direction (DIRECTIONS order) and face (all five), the
 * visibility 1 − clip(<blockers, Y(−e_f)>, 0, 1) of every source cell: the volume does
 * not change while the light propagates, so it is computed once per volume.
 */
function visibilities(geometry, n) {
  let found = visibilityCache.get(geometry);
  if (found === undefined) {
    found = [];
    for (let axis = 0; axis < 3; axis++) {
      for (const sign of [1, -1]) {
        const blockers = faceBlockers(geometry, n, axis, sign);
        found.push(faces(axis, sign, true).map((face) => faceVisibility(blockers, face, n)));
      }
    }
    visibilityCache.set(geometry, found);
  }
  return found;
}

/** Indices and values of the non-zero entries of an SH vector: skipping a zero term
 * changes no sum (x + 0·y = x), so the sparse sums equal the twin's dense ones. */
function sparse(vector) {
  const index = [];
  const value = [];
  vector.forEach((v, k) => {
    if (v !== 0) {
      index.push(k);
      value.push(v);
    }
  });
  return {index, value};
}

/**
 * One step P(grid) in scatter form and its audit terms ([r, g, b] watts each):
 * clamp_gain, occluded, border_loss. geometry: the merged (N+1)³×4 volume or null;
 * neighbours: 6 (five faces of each face neighbour) or 26 (neighbours26Step).
 */
export function propagationStep(grid, n, c, geometry = null, channels = ALL_CHANNELS,
                                neighbours = 6) {
  if (checkNeighbours(neighbours, c) === 26) {
    return neighbours26Step(grid, n, c, geometry, channels);
  }
  return geometry === null ? linearSideStep(grid, n, c, channels)
    : faceStep(grid, n, c, geometry, channels);
}

/** The switches the 26-neighbour step has no form without (explorer/lpv/neighbours.py). */
const NEEDED_BY_26 = ["ping_pong", "side_faces", "model_face_weights"];

/** neighbours (6 or 26), or the twin's one-line error for a switch 26 cannot do without. */
export function checkNeighbours(neighbours, c) {
  if (neighbours !== 6 && neighbours !== 26) {
    throw new Error("neighbours must be 6 or 26, got " + neighbours);
  }
  const missing = neighbours === 26 ? NEEDED_BY_26.filter((name) => !c[name]) : [];
  if (missing.length) {
    throw new Error("26-neighbour propagation needs the corrections " + missing.join(", ")
                    + " on (no published form of it exists)");
  }
  return neighbours;
}

/** The 26 neighbour offsets in the twin's order (OFFSETS_26: x outermost, −1, 0, 1). */
const OFFSETS_26 = [];
for (const a of [-1, 0, 1]) {
  for (const b of [-1, 0, 1]) {
    for (const d of [-1, 0, 1]) {
      if (a !== 0 || b !== 0 || d !== 0) {
        OFFSETS_26.push([a, b, d]);
      }
    }
  }
}

/**
 * The faces of neighbour ``offset`` on the surface of the source's 3×3×3 block, one per
 * non-zero component (twin.outer_faces_26): {evaluation, reprojection, angle, front}. The
 * evaluation direction points at the face's centre, 2·offset with 3·offset on the face's
 * axis, normalised: the generated (big, small) components of derivations/neighbours26.py.
 */
function outerFaces26(offset) {
  const kind = offset.filter((v) => v !== 0).length;   // 1 face, 2 edge, 3 corner
  const angle = [K.FRONT_FACE_SOLID_ANGLE, K.EDGE_FACE_SOLID_ANGLE,
                 K.CORNER_FACE_SOLID_ANGLE][kind - 1];
  const [big, small] = [[1.0, 0.0], [K.EDGE_EVAL_BIG, K.EDGE_EVAL_SMALL],
                        [K.CORNER_EVAL_BIG, K.CORNER_EVAL_SMALL]][kind - 1];
  const list = [];
  for (let axis = 0; axis < 3; axis++) {
    if (offset[axis] === 0) {
      continue;
    }
    const evaluation = offset.map((o, k) => (k === axis ? big : small) * o);
    const reprojection = [0, 0, 0];
    reprojection[axis] = offset[axis];
    list.push({evaluation, reprojection, angle, front: kind === 1});
  }
  return list;
}

/**
 * (N³×4) for every source cell s the mean geometry SH over the corners s shares with
 * s + offset (twin._shared_corner_blockers: 4 for a face, 2 for an edge, 1 for a corner
 * neighbour), summed in the twin's order (x's corners outermost).
 */
function sharedCornerBlockers(geometry, n, offset) {
  const size = n + 1;
  const picks = offset.map((o) => (o > 0 ? [1] : o < 0 ? [0] : [0, 1]));
  const corners = [];
  for (const a of picks[0]) {
    for (const b of picks[1]) {
      for (const d of picks[2]) {
        corners.push(((a * size + b) * size + d) * 4);
      }
    }
  }
  const out = new Float64Array(n * n * n * 4);
  for (let x = 0; x < n; x++) {
    for (let y = 0; y < n; y++) {
      for (let z = 0; z < n; z++) {
        const base = ((x * size + y) * size + z) * 4;
        const o = ((x * n + y) * n + z) * 4;
        for (let k = 0; k < 4; k++) {
          let sum = 0.0;
          for (const corner of corners) {
            sum += geometry[base + corner + k];
          }
          out[o + k] = sum / corners.length;
        }
      }
    }
  }
  return out;
}

const visibility26Cache = new WeakMap();

/** Per offset (OFFSETS_26 order) and outer face, every source cell's visibility
 * 1 − clip(<blockers, Y(−evaluation)>, 0, 1), once per geometry volume. */
function visibilities26(geometry, n) {
  let found = visibility26Cache.get(geometry);
  if (found === undefined) {
    found = OFFSETS_26.map((offset) => {
      const blockers = sharedCornerBlockers(geometry, n, offset);
      return outerFaces26(offset).map((face) => faceVisibility(blockers, face, n));
    });
    visibility26Cache.set(geometry, found);
  }
  return found;
}

/**
 * The 26-neighbour step (twin._offset_step per offset, docs/MODEL.md "26 neighbours"):
 * every source cell sends to each neighbour through that neighbour's outer faces, each
 * face weighted k_R·k_I·k_P·Δω (the exact face, edge or corner solid angle), the front
 * faces of the six face neighbours clamped when clamp_front_face is on, each face seen
 * through the geometry volume's corners the two cells share.
 */
function neighbours26Step(grid, n, c, geometry, channels) {
  const out = new Float64Array(grid.length);
  const terms = {clamp_gain: [0, 0, 0], occluded: [0, 0, 0], border_loss: [0, 0, 0]};
  const scale = reprojectionFactor(c) * injectionFactor(c) * propagationFactor(c);
  const stride = n * n * n * COEFFS;
  const seen = geometry === null ? null : visibilities26(geometry, n);
  OFFSETS_26.forEach((offset, index) => {
    const shift = ((offset[0] * n + offset[1]) * n + offset[2]) * COEFFS;
    const list = outerFaces26(offset).map((face, f) => {
      const weight = scale * face.angle;
      const lobe = cosineLobe(face.reprojection);
      const sparseLobe = sparse(lobe);   // coefficient 0 and one of band 1
      return {weight, basis: shBasis(face.evaluation), lobe0: lobe[0],
              li: sparseLobe.index[0], lv: sparseLobe.value[0],
              lj: sparseLobe.index[1], lw: sparseLobe.value[1],
              fluxPerIntensity: weight * K.SH_FLUX_FACTOR * lobe[0],
              clamp: face.front && c.clamp_front_face,
              visibility: seen === null ? null : seen[index][f]};
    });
    const [ox, oy, oz] = offset;
    for (const ch of channels) {
      const sums = [0.0, 0.0, 0.0];    // border, gain, occluded
      for (let x = 0; x < n; x++) {
        const insideX = x + ox >= 0 && x + ox < n;
        for (let y = 0; y < n; y++) {
          const insideXY = insideX && y + oy >= 0 && y + oy < n;
          for (let z = 0; z < n; z++) {
            const inside = insideXY && z + oz >= 0 && z + oz < n;
            const cell = (x * n + y) * n + z;
            sendFaces(list, grid, out, ch * stride + cell * COEFFS, shift, cell, inside, sums);
          }
        }
      }
      terms.border_loss[ch] += sums[0];
      terms.clamp_gain[ch] += sums[1];
      terms.occluded[ch] += sums[2];
    }
  });
  return {grid: out, terms};
}

/**
 * propagationStep without a geometry volume: the four side faces of a direction are
 * neither clamped nor occluded, so their sum is one linear map M = Σ w·lobe(r) ⊗ Y(e) of
 * the source's coefficients (the twin adds the faces one by one: the same sum, rounded
 * in another order, a few ulp). The front face stays a face of its own (its clamp).
 */
function linearSideStep(grid, n, c, channels) {
  const out = new Float64Array(grid.length);
  const terms = {clamp_gain: [0, 0, 0], occluded: [0, 0, 0], border_loss: [0, 0, 0]};
  const [frontWeight, sideWeight] = faceWeights(c);
  const stride = n * n * n * COEFFS;
  const clamp = c.clamp_front_face;
  for (let axis = 0; axis < 3; axis++) {
    for (const sign of [1, -1]) {
      const [front, ...sides] = faces(axis, sign, c.side_faces);
      const wF = frontWeight;
      const lobeF = cosineLobe(front.reprojection);
      const [b0, b1, b2, b3] = shBasis(front.evaluation);
      const fpiF = wF * K.SH_FLUX_FACTOR * lobeF[0];
      const m = new Float64Array(16);   // M[k·4 + j]: the side faces' map
      for (const side of sides) {
        const lobe = cosineLobe(side.reprojection);
        const basis = shBasis(side.evaluation);
        for (let k = 0; k < 4; k++) {
          for (let j = 0; j < 4; j++) {
            m[k * 4 + j] += sideWeight * lobe[k] * basis[j];
          }
        }
      }
      const [l0, l1, l2, l3] = lobeF.map((v) => wF * v);
      const step = [0, 0, 0];
      step[axis] = sign;
      const offset = ((step[0] * n + step[1]) * n + step[2]) * COEFFS;
      // the cells whose neighbour along the direction lies outside: the first or last
      // layer along the axis
      const lastLayer = sign > 0 ? n - 1 : 0;
      for (const ch of channels) {
        let border = 0.0;
        let gain = 0.0;
        for (let x = 0; x < n; x++) {
          for (let y = 0; y < n; y++) {
            const row = axis === 0 ? x : y;
            for (let z = 0; z < n; z++) {
              const inside = (axis === 2 ? z : row) !== lastLayer;
              const at = ch * stride + ((x * n + y) * n + z) * COEFFS;
              const s0 = grid[at];
              const s1 = grid[at + 1];
              const s2 = grid[at + 2];
              const s3 = grid[at + 3];
              // zero basis entries add exact zeros: the twin's sums, term for term
              const r = s0 * b0 + s1 * b1 + s2 * b2 + s3 * b3;
              const used = clamp && r < 0.0 ? 0.0 : r;
              const d0 = used * l0 + (m[0] * s0 + m[1] * s1 + m[2] * s2 + m[3] * s3);
              const d1 = used * l1 + (m[4] * s0 + m[5] * s1 + m[6] * s2 + m[7] * s3);
              const d2 = used * l2 + (m[8] * s0 + m[9] * s1 + m[10] * s2 + m[11] * s3);
              const d3 = used * l3 + (m[12] * s0 + m[13] * s1 + m[14] * s2 + m[15] * s3);
              if (inside) {
                const to = at + offset;
                out[to] += d0;
                out[to + 1] += d1;
                out[to + 2] += d2;
                out[to + 3] += d3;
              } else {
                border += K.SH_FLUX_FACTOR * d0;   // the flux of what left: 2√π times c0
              }
              gain += fpiF * (used - r);
            }
          }
        }
        terms.border_loss[ch] += border;
        if (clamp) {
          terms.clamp_gain[ch] += gain;
        }
      }
    }
  }
  return {grid: out, terms};
}

/**
 * One source cell's SH (grid[at..at+3]) sent through the faces of `list` to the cell
 * `shift` coefficients away, or out of the grid when not `inside`; adds to `sums` the flux
 * that left through the border, the flux the front-face clamp created and the flux the
 * geometry volume removed (docs/MODEL.md "Propagation", "Propagation audit").
 */
function sendFaces(list, grid, out, at, shift, cell, inside, sums) {
  const s0 = grid[at];
  const s1 = grid[at + 1];
  const s2 = grid[at + 2];
  const s3 = grid[at + 3];
  for (const face of list) {
    const b = face.basis;
    const r = s0 * b[0] + s1 * b[1] + s2 * b[2] + s3 * b[3];
    const used = face.clamp && r < 0.0 ? 0.0 : r;
    const visibility = face.visibility === null ? 1.0 : face.visibility[cell];
    const sent = face.weight * used * visibility;
    if (inside) {
      out[at + shift + face.li] += sent * face.lv;
      out[at + shift + face.lj] += sent * face.lw;
    } else {
      sums[0] += K.SH_FLUX_FACTOR * face.lobe0 * sent;
    }
    sums[1] += face.fluxPerIntensity * (used - r);
    sums[2] += face.fluxPerIntensity * used * (1.0 - visibility);
  }
}

/** propagationStep face by face, each face's visibility through the geometry volume. */
function faceStep(grid, n, c, geometry, channels) {
  const out = new Float64Array(grid.length);
  const terms = {clamp_gain: [0, 0, 0], occluded: [0, 0, 0], border_loss: [0, 0, 0]};
  const [frontWeight, sideWeight] = faceWeights(c);
  const cells = n * n * n;
  const stride = cells * COEFFS;
  const seen = visibilities(geometry, n);
  let direction = 0;
  for (let axis = 0; axis < 3; axis++) {
    for (const sign of [1, -1]) {
      const step = [0, 0, 0];
      step[axis] = sign;
      const offset = ((step[0] * n + step[1]) * n + step[2]) * COEFFS;
      const lastLayer = sign > 0 ? n - 1 : 0;
      const list = faces(axis, sign, c.side_faces).map((face, f) => {
        const weight = face.front ? frontWeight : sideWeight;
        const lobe = cosineLobe(face.reprojection);
        const {index, value} = sparse(lobe);   // coefficient 0 and one of band 1
        return {weight, basis: shBasis(face.evaluation), lobe0: lobe[0],
                li: index[0], lv: value[0], lj: index[1], lw: value[1],
                fluxPerIntensity: weight * K.SH_FLUX_FACTOR * lobe[0],
                clamp: face.front && c.clamp_front_face, visibility: seen[direction][f]};
      });
      direction += 1;
      for (const ch of channels) {
        const sums = [0.0, 0.0, 0.0];    // border, gain, occluded
        for (let x = 0; x < n; x++) {
          for (let y = 0; y < n; y++) {
            const row = axis === 0 ? x : y;
            for (let z = 0; z < n; z++) {
              const inside = (axis === 2 ? z : row) !== lastLayer;
              const cell = (x * n + y) * n + z;
              sendFaces(list, grid, out, ch * stride + cell * COEFFS, offset, cell, inside,
                        sums);
            }
          }
        }
        terms.border_loss[ch] += sums[0];
        terms.clamp_gain[ch] += sums[1];
        terms.occluded[ch] += sums[2];
      }
    }
  }
  return {grid: out, terms};
}

/**
 * grid_0..grid_N's flux, acc_N and the audit, as explorer/lpv/twin/light_grid.py
 * propagate_audited: ping-pong grid_t = P(grid_{t−1}); in place grid_t = P(acc_{t−1}).
 * Returns {accumulated, last, audit: {injected, per_step, border_loss, clamp_gain,
 * occluded, accumulated}} (per-step terms one [r, g, b] per step).
 */
export function propagateAudited(grid, n, c, iterations, geometry = null,
                                 channels = ALL_CHANNELS, neighbours = 6) {
  checkNeighbours(neighbours, c);   // as the twin: refused before any step
  const state = {last: grid, accumulated: Float64Array.from(grid),
                 audit: {injected: flux(grid, n), per_step: [flux(grid, n)], border_loss: [],
                         clamp_gain: [], occluded: [], accumulated: flux(grid, n)}};
  return continuePropagation(state, n, c, iterations, geometry, channels, neighbours);
}

/**
 * ``more`` further steps of a state propagateAudited returned (its accumulated grid is
 * updated in place): the same operations in the same order as one longer run.
 */
export function continuePropagation(state, n, c, more, geometry = null,
                                    channels = ALL_CHANNELS, neighbours = 6) {
  if (!(Number.isInteger(more) && more >= 0)) {
    throw new Error("iterations must be an integer >= 0, got " + more);
  }
  const {audit, accumulated} = state;
  let last = state.last;
  for (let t = 0; t < more; t++) {
    const source = c.ping_pong ? last : accumulated;
    const {grid: step, terms} = propagationStep(source, n, c, geometry, channels,
                                                neighbours);
    for (const name of ["border_loss", "clamp_gain", "occluded"]) {
      audit[name].push(terms[name]);
    }
    audit.per_step.push(flux(step, n));
    for (let i = 0; i < accumulated.length; i++) {   // the step is whole: add it in place
      accumulated[i] += step[i];
    }
    last = step;
  }
  audit.accumulated = flux(accumulated, n);
  return {accumulated, last, audit};
}
