#version 430 core
// The spot cone's angular falloff (docs/MODEL.md "Spot cone"): one function shared by the
// RSM (each texel's flux) and the final gather (the direct light), so both see the same
// light. Numpy twin: explorer/scene/lights.py spot_falloff. Include it once, in the
// fragment section.
#ifndef SPOT_GLSL
#define SPOT_GLSL 1

uniform int u_spot_cone;          // 0: the 90° square frustum, f = 1; 1: a cone
uniform float u_spot_cos_inner;   // cos of the inner half-angle (f = 1 inside it)
uniform float u_spot_cos_outer;   // cos of the outer half-angle (f = 0 outside it)

// f at the angle θ from the spot's axis, given as cos θ: smoothstep(cos θ_o, cos θ_i, cos θ)
// = 3t² − 2t³, t = clamp((cos θ − cos θ_o) / (cos θ_i − cos θ_o), 0, 1); a hard step at
// the outer angle when the two angles are equal (GLSL's smoothstep is undefined there);
// 1 without a cone. The gather passes each light's own cone (docs/MODEL.md "Several
// lights"); the RSM the uniforms' (spot_falloff below).
float spot_falloff_of(float cos_axis, bool cone, float cos_inner, float cos_outer) {
    if (!cone) {
        return 1.0;
    }
    if (cos_inner <= cos_outer) {
        return cos_axis >= cos_outer ? 1.0 : 0.0;
    }
    float t = clamp((cos_axis - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0);
    return t * t * (3.0 - 2.0 * t);
}

float spot_falloff(float cos_axis) {
    return spot_falloff_of(cos_axis, u_spot_cone != 0, u_spot_cos_inner, u_spot_cos_outer);
}

#endif
