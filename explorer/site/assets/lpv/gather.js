// The final gather on the G-buffer with WebGL2 (shaders/gather.glsl's indirect half):
// E = clamp+(<s(x), lobe(−n)>)/h² (irradiance_gather; off: the DX11 shader's clamp+(<s, Y(−n)>),
// no lobe and no cell area) from a trilinear lookup of the accumulated grid
// (three RGBA32F 3D textures, r, g and b, one texel per cell; the weights computed in
// float32 from eight texelFetch, as sh_grid.glsl's SH_SHADER_FILTER 1 does), times the
// directional-derivative damping when asked; radiance albedo/π·E and the flux the pixel's
// surface receives, E·area, into two RGBA32F targets read back for the display and the
// audit. The constants come from the generated module.
import * as K from "../generated/constants.js";

function glslFloat(value) {
  const text = String(value);
  return /[.eE]/.test(text) ? text : text + ".0";
}

const VERTEX = `#version 300 es
void main() {
  vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
  gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}`;

const FRAGMENT = `#version 300 es
precision highp float;
precision highp int;
precision highp sampler2D;
precision highp sampler3D;
const float SH_COSLOBE_C0 = ${glslFloat(K.SH_COSLOBE_C0)};
const float SH_COSLOBE_C1 = ${glslFloat(K.SH_COSLOBE_C1)};
const float INV_PI = ${glslFloat(K.INV_PI)};
const float SH_C0 = ${glslFloat(K.SH_C0)};
const float SH_C1 = ${glslFloat(K.SH_C1)};
uniform sampler2D u_position;   // xyz, w = 1 where a surface is seen
uniform sampler2D u_normal;     // xyz, w = the surface's area under the pixel
uniform sampler2D u_albedo;
uniform sampler3D u_lpv_r;
uniform sampler3D u_lpv_g;
uniform sampler3D u_lpv_b;
uniform vec3 u_grid_origin;
uniform float u_grid_cell_size;
uniform int u_grid_resolution;
uniform int u_damping;
uniform int u_irradiance_gather;
layout(location = 0) out vec4 out_indirect;
layout(location = 1) out vec4 out_received;

vec4 lobe(vec3 n) {
  return vec4(SH_COSLOBE_C0, -SH_COSLOBE_C1 * n.y, SH_COSLOBE_C1 * n.z, -SH_COSLOBE_C1 * n.x);
}

vec4 basis(vec3 d) {
  return vec4(SH_C0, -SH_C1 * d.y, SH_C1 * d.z, -SH_C1 * d.x);
}

// The grid is uploaded in the twin's order (z fastest), so texel (i, j, k) holds cell
// (k, j, i): fetch with the cell reversed.
vec4 cell(sampler3D tex, ivec3 c) {
  return texelFetch(tex, c.zyx, 0);
}

vec4 trilinear(sampler3D tex, ivec3 lo, ivec3 hi, vec3 f) {
  return mix(mix(mix(cell(tex, ivec3(lo.x, lo.y, lo.z)), cell(tex, ivec3(hi.x, lo.y, lo.z)), f.x),
                 mix(cell(tex, ivec3(lo.x, hi.y, lo.z)), cell(tex, ivec3(hi.x, hi.y, lo.z)), f.x),
                 f.y),
             mix(mix(cell(tex, ivec3(lo.x, lo.y, hi.z)), cell(tex, ivec3(hi.x, lo.y, hi.z)), f.x),
                 mix(cell(tex, ivec3(lo.x, hi.y, hi.z)), cell(tex, ivec3(hi.x, hi.y, hi.z)), f.x),
                 f.y),
             f.z);
}

// E(x) for normal n: texel centres at i + 1/2, clamped to the grid's edge.
vec3 irradiance(vec3 x, vec3 n) {
  int size = u_grid_resolution;
  vec3 g = (x - u_grid_origin) / u_grid_cell_size;
  vec3 t = clamp(g - 0.5, vec3(0.0), vec3(float(size - 1)));
  ivec3 lo = ivec3(floor(t));
  ivec3 hi = min(lo + 1, ivec3(size - 1));
  vec3 f = t - vec3(lo);
  vec4 kernel = u_irradiance_gather == 1 ? lobe(-n) : basis(-n);
  vec3 intensity = vec3(dot(trilinear(u_lpv_r, lo, hi, f), kernel),
                        dot(trilinear(u_lpv_g, lo, hi, f), kernel),
                        dot(trilinear(u_lpv_b, lo, hi, f), kernel));
  float area = u_irradiance_gather == 1 ? u_grid_cell_size * u_grid_cell_size : 1.0;
  return max(intensity, vec3(0.0)) / area;
}

// clamp(E(p + h/2·n) / E(p − h/2·n), 0, 1) per channel, 1 where nothing comes from behind.
vec3 damping(vec3 p, vec3 n) {
  vec3 half_cell = 0.5 * u_grid_cell_size * n;
  vec3 front = irradiance(p + half_cell, n);
  vec3 back = irradiance(p - half_cell, n);
  vec3 ratio = vec3(1.0);
  for (int c = 0; c < 3; ++c) {
    if (back[c] > 0.0) {
      ratio[c] = clamp(front[c] / back[c], 0.0, 1.0);
    }
  }
  return ratio;
}

void main() {
  ivec2 pixel = ivec2(gl_FragCoord.xy);
  vec4 position = texelFetch(u_position, pixel, 0);
  if (position.w < 0.5) {
    out_indirect = out_received = vec4(0.0);
    return;
  }
  vec4 normal_area = texelFetch(u_normal, pixel, 0);
  vec3 n = normal_area.xyz;
  vec3 e = irradiance(position.xyz, n);
  if (u_damping == 1) {
    e *= damping(position.xyz, n);
  }
  out_indirect = vec4(texelFetch(u_albedo, pixel, 0).rgb * INV_PI * e, 1.0);
  out_received = vec4(e * normal_area.w, 0.0);
}`;

function compile(gl, type, source) {
  const shader = gl.createShader(type);
  gl.shaderSource(shader, source);
  gl.compileShader(shader);
  if (!gl.getShaderParameter(shader, gl.COMPILE_STATUS)) {
    throw new Error("gather shader: " + gl.getShaderInfoLog(shader));
  }
  return shader;
}

/** Why this browser cannot gather (no WebGL2, no float render targets), or null. */
export function unsupportedReason() {
  const canvas = document.createElement("canvas");
  const gl = canvas.getContext("webgl2");
  if (!gl) {
    return "this browser has no WebGL2";
  }
  if (!gl.getExtension("EXT_color_buffer_float")) {
    return "this browser's WebGL2 cannot render to float textures";
  }
  return null;
}

/** A WebGL2 context holding one G-buffer and gathering grids on it. */
export class Gatherer {
  constructor(width, height, gbuffer) {
    this.width = width;
    this.height = height;
    this.canvas = document.createElement("canvas");
    this.canvas.width = width;
    this.canvas.height = height;
    const gl = this.canvas.getContext("webgl2", {antialias: false, depth: false});
    if (!gl || !gl.getExtension("EXT_color_buffer_float")) {
      throw new Error(unsupportedReason() || "no WebGL2");
    }
    this.gl = gl;
    const program = gl.createProgram();
    gl.attachShader(program, compile(gl, gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(program, compile(gl, gl.FRAGMENT_SHADER, FRAGMENT));
    gl.linkProgram(program);
    if (!gl.getProgramParameter(program, gl.LINK_STATUS)) {
      throw new Error("gather program: " + gl.getProgramInfoLog(program));
    }
    this.program = program;
    this.vao = gl.createVertexArray();
    this.textures2d = {
      position: this.texture2d(gbuffer.position, 4),
      normal: this.texture2d(gbuffer.normal, 4),
      albedo: this.texture2d(gbuffer.albedo, 3),
    };
    this.grid = [0, 1, 2].map(() => gl.createTexture());
    this.targets = [0, 1].map(() => {
      const texture = gl.createTexture();
      gl.bindTexture(gl.TEXTURE_2D, texture);
      gl.texStorage2D(gl.TEXTURE_2D, 1, gl.RGBA32F, width, height);
      return texture;
    });
    this.framebuffer = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.framebuffer);
    this.targets.forEach((texture, i) => gl.framebufferTexture2D(
      gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0 + i, gl.TEXTURE_2D, texture, 0));
    gl.drawBuffers([gl.COLOR_ATTACHMENT0, gl.COLOR_ATTACHMENT1]);
    if (gl.checkFramebufferStatus(gl.FRAMEBUFFER) !== gl.FRAMEBUFFER_COMPLETE) {
      throw new Error("this browser's WebGL2 cannot render to two float targets");
    }
  }

  texture2d(data, channels) {
    const gl = this.gl;
    const texture = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, texture);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    const format = channels === 4 ? gl.RGBA : gl.RGB;
    const internal = channels === 4 ? gl.RGBA32F : gl.RGB32F;
    gl.texImage2D(gl.TEXTURE_2D, 0, internal, this.width, this.height, 0, format, gl.FLOAT,
                  data);
    for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) {
      gl.texParameteri(gl.TEXTURE_2D, p, gl.NEAREST);
    }
    return texture;
  }

  /** Upload an accumulated grid (Float64Array, the twin's order) as float32 texels. */
  uploadGrid(accumulated, n) {
    const gl = this.gl;
    const block = n * n * n * 4;
    for (let c = 0; c < 3; c++) {
      gl.bindTexture(gl.TEXTURE_3D, this.grid[c]);
      const texels = new Float32Array(accumulated.subarray(c * block, (c + 1) * block));
      gl.texImage3D(gl.TEXTURE_3D, 0, gl.RGBA32F, n, n, n, 0, gl.RGBA, gl.FLOAT, texels);
      for (const p of [gl.TEXTURE_MIN_FILTER, gl.TEXTURE_MAG_FILTER]) {
        gl.texParameteri(gl.TEXTURE_3D, p, gl.NEAREST);
      }
    }
  }

  /**
   * Gather the uploaded grid of spec {origin, cellSize, resolution}: {indirect, received}
   * Float32Arrays (RGBA per pixel, row 0 the top row as the G-buffer's).
   */
  gather(spec, damping, irradianceGather = true) {
    const gl = this.gl;
    gl.bindFramebuffer(gl.FRAMEBUFFER, this.framebuffer);
    gl.viewport(0, 0, this.width, this.height);
    gl.useProgram(this.program);
    const units = [["u_position", gl.TEXTURE_2D, this.textures2d.position],
                   ["u_normal", gl.TEXTURE_2D, this.textures2d.normal],
                   ["u_albedo", gl.TEXTURE_2D, this.textures2d.albedo],
                   ["u_lpv_r", gl.TEXTURE_3D, this.grid[0]],
                   ["u_lpv_g", gl.TEXTURE_3D, this.grid[1]],
                   ["u_lpv_b", gl.TEXTURE_3D, this.grid[2]]];
    units.forEach(([name, target, texture], unit) => {
      gl.activeTexture(gl.TEXTURE0 + unit);
      gl.bindTexture(target, texture);
      gl.uniform1i(gl.getUniformLocation(this.program, name), unit);
    });
    gl.uniform3fv(gl.getUniformLocation(this.program, "u_grid_origin"), spec.origin);
    gl.uniform1f(gl.getUniformLocation(this.program, "u_grid_cell_size"), spec.cellSize);
    gl.uniform1i(gl.getUniformLocation(this.program, "u_grid_resolution"), spec.resolution);
    gl.uniform1i(gl.getUniformLocation(this.program, "u_damping"), damping ? 1 : 0);
    gl.uniform1i(gl.getUniformLocation(this.program, "u_irradiance_gather"),
                 irradianceGather ? 1 : 0);
    gl.bindVertexArray(this.vao);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
    const read = (i) => {
      const pixels = new Float32Array(this.width * this.height * 4);
      gl.readBuffer(gl.COLOR_ATTACHMENT0 + i);
      gl.readPixels(0, 0, this.width, this.height, gl.RGBA, gl.FLOAT, pixels);
      return pixels;
    };
    return {indirect: read(0), received: read(1)};
  }
}
