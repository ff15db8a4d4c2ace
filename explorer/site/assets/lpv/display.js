// The window's display encoding, ported from explorer/lpv/twin/tonemap.py and
// explorer/lpv/passes/display.py: the auto exposure's log-average luminance over the surface
// pixels between two percentiles of theirs, the filmic curve (Narkowicz's ACES fit) or a
// clip, and sRGB; bytes as explorer/site/frames.py to_bytes makes them. Its numbers (the
// fit, the key, the percentiles, the floor, the luma weights) come in the live LPV's
// description, written by the build from explorer/lpv/twin/tonemap.py.

/** float32 rounding, where tonemap.py casts to float32. */
const f32 = Math.fround;

function luminance(d, r, g, b) {
  return r * d.luma[0] + g * d.luma[1] + b * d.luma[2];
}

/** exp(mean(log(δ + L))) over the surface pixels ranked between the two percentiles. */
export function logAverageLuminance(d, linear, mask) {
  const values = [];
  for (let i = 0; i < mask.length; i++) {
    if (mask[i]) {
      const l = luminance(d, linear[3 * i], linear[3 * i + 1], linear[3 * i + 2]);
      values.push(Number.isFinite(l) ? Math.max(l, 0.0) : 0.0);
    }
  }
  const count = values.length;
  let peak = 0.0;
  for (const v of values) {
    peak = Math.max(peak, v);
  }
  if (!(peak > 0.0)) {
    return 0.0;
  }
  const sorted = Float64Array.from(values).sort();
  const first = Math.min(Math.floor(count * d.percentiles[0] / 100.0), count - 1);
  const stop = Math.max(Math.ceil(count * d.percentiles[1] / 100.0), first + 1);
  const delta = d.floor * peak;
  let sum = 0.0;
  for (let i = first; i < stop; i++) {
    sum += Math.log(delta + sorted[i]);
  }
  return Math.exp(sum / (stop - first));
}

/** key/L̄ of the unexposed image (1 when nothing is lit). */
export function autoExposureScale(d, linear, mask) {
  const average = logAverageLuminance(d, linear, mask);
  return average > 0.0 ? d.key / average : 1.0;
}

function filmic(d, x) {
  const [a, b, c, dd, e] = d.aces_fit;
  return Math.min(Math.max(x * (a * x + b) / (x * (c * x + dd) + e), 0.0), 1.0);
}

function srgb(value) {
  const c = f32(Math.min(Math.max(Number.isNaN(value) ? 0.0 : value, 0.0), 1.0));
  return c <= f32(0.0031308) ? f32(f32(12.92) * c)
    : f32(f32(f32(1.055) * f32(Math.pow(c, f32(1.0 / 2.4)))) - f32(0.055));
}

/**
 * The shown picture as RGBA bytes: srgb(curve(max(scale·exposed, 0))), each channel
 * clip(v)·255 + ½ truncated.
 */
export function encode(d, exposed, scale, toneMap, pixels) {
  const film = toneMap === "filmic";
  const out = new Uint8ClampedArray(pixels * 4);
  for (let i = 0; i < pixels; i++) {
    for (let c = 0; c < 3; c++) {
      const v = exposed[3 * i + c];
      let x = Math.max((Number.isFinite(v) ? v : 0.0) * scale, 0.0);
      if (film) {
        x = filmic(d, x);
      }
      out[4 * i + c] = Math.floor(Math.min(Math.max(srgb(x), 0.0), 1.0) * 255.0 + 0.5);
    }
    out[4 * i + 3] = 255;
  }
  return out;
}
