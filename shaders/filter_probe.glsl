#version 430 core
// How precisely does the texture unit weight a linear-filtered lookup? Samples a 3D texture
// of 2×1×1 texels holding 0 and 1 (linear filter, clamped to the edge, as the light grids)
// at fractions t between the two texel centres; a filter with exact weights returns t.
// Mesa's llvmpipe computes the weights in float32 (error ~1e-7); texture units of GPUs
// use 8 fractional bits (error up to 1/512). explorer/lpv/passes/gather.py measures this once per
// context and lets the final gather interpolate in the shader when it is not exact
// (sh_grid.glsl, SH_SHADER_FILTER).

#if defined COMPUTE_SHADER
layout(local_size_x = 64) in;

uniform sampler3D u_ramp;
uniform int u_count;

layout(std430, binding = 0) buffer Samples { float samples[]; };

void main() {
    int i = int(gl_GlobalInvocationID.x);
    if (i >= u_count) {
        return;
    }
    float t = (float(i) + 0.37) / float(u_count);   // clear of multiples of 1/256
    samples[i] = textureLod(u_ramp, vec3((0.5 + t) / 2.0, 0.5, 0.5), 0.0).x;
}
#endif
