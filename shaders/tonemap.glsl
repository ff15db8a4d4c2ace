#version 430 core
// Display encoding: exposure scale, tone curve, sRGB (docs/MODEL.md "Display"). Functions
// only, no uniforms: include it in any pass that writes a display image. Numpy twin:
// explorer/lpv/twin/tonemap.py (tested against each other in tests/lpv/test_display.py).
#ifndef TONEMAP_GLSL
#define TONEMAP_GLSL 1

const int TONE_MAP_LINEAR_CLIP = 0;   // explorer/lpv/twin/tonemap.py TONE_MAPS[0]
const int TONE_MAP_FILMIC = 1;        // TONE_MAPS[1]

// Narkowicz's fit of the ACES filmic reference tone curve (2015):
// x(2.51x + 0.03) / (x(2.43x + 0.59) + 0.14), clamped to [0, 1]. Slope 0.03/0.14 at 0, a
// shoulder that reaches 1 at x = 7/2 + √14 ≈ 7.24 instead of clipping at x = 1.
vec3 tone_map_filmic(vec3 x) {
    return clamp(x * (2.51 * x + 0.03) / (x * (2.43 * x + 0.59) + 0.14), 0.0, 1.0);
}

// The sRGB transfer function (IEC 61966-2-1) of linear values clamped to [0, 1].
vec3 linear_to_srgb(vec3 linear) {
    vec3 c = clamp(linear, 0.0, 1.0);
    return mix(c * 12.92, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(0.0031308, c));
}

// A linear colour as shown: scaled (exposure), tone-mapped (`mode`: TONE_MAP_*), encoded.
vec3 display_encode(vec3 linear, float scale, int mode) {
    vec3 x = max(linear * scale, vec3(0.0));
    return linear_to_srgb(mode == TONE_MAP_FILMIC ? tone_map_filmic(x) : x);
}

#endif
