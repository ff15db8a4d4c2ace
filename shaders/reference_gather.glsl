#version 430 core
// One-bounce reference: the instant-radiosity sum over every VPL at every G-buffer pixel
// (explorer/truth/reference.py drives it tile by tile and holds a numpy twin).
//
// A diffuse VPL j (position x_j, normal n_j, flux Phi_j) has the intensity
//   I_j(w) = Phi_j / pi * clamp+<n_j, w>                  (docs/MODEL.md "Injection", corrected)
// and gives a receiver p with normal n the irradiance
//   E_j = I_j(w_jp) * clamp+<n, -w_jp> / max(|p - x_j|^2, r_min^2) * V(x_j, p)
// with w_jp the unit vector from x_j to p and V the binary visibility (1 when u_visibility
// is 0). One invocation owns one pixel of the tile, so adding into the result image with
// imageLoad/imageStore is race free across the VPL chunks of one tile (dispatched in order).

#if defined COMPUTE_SHADER
#include "generated/constants.glsl"

#define LOCAL_SIZE 8
#define BVH_STACK_SIZE 64

layout(local_size_x = LOCAL_SIZE, local_size_y = LOCAL_SIZE) in;

// G-buffer: world position (w = 1 where a surface was seen), world normal.
uniform sampler2D u_gbuffer_position;
uniform sampler2D u_gbuffer_normal;
// VPLs as VplTextures: position (w = 1 valid), normal (w = light depth), flux (rgb).
uniform sampler2D u_vpl_position;
uniform sampler2D u_vpl_normal;
uniform sampler2D u_vpl_flux;

uniform ivec2 u_tile_origin;     // first pixel of this tile
uniform ivec2 u_image_size;      // G-buffer size
uniform int u_vpl_begin;         // VPL texel range [begin, end) of this chunk, row-major
uniform int u_vpl_end;
uniform float u_min_distance_sq; // r_min^2: clamps the 1/r^2 singularity
uniform int u_visibility;        // 1: trace a shadow ray per VPL-pixel pair
uniform float u_ray_offset;      // world distance the ray ends are pushed along their normals
uniform int u_node_count;        // BVH nodes (0: the scene has no triangles)

layout(rgba32f, binding = 0) uniform image2D u_irradiance;

// Triangles in BVH leaf order, three vec4 corners each (w unused).
layout(std430, binding = 0) readonly buffer Triangles { vec4 tri_corners[]; };
// Flattened BVH: an inner node keeps its left child at index+1 and its right child at
// `left_or_first`; a leaf (count > 0) holds triangles [left_or_first, left_or_first+count).
struct Node {
    vec3 lo;
    int left_or_first;
    vec3 hi;
    int count;
};
layout(std430, binding = 1) readonly buffer Nodes { Node nodes[]; };

// Moller-Trumbore, both faces: the parameter t of the hit along origin + t*dir, or -1.
float hit_triangle(vec3 origin, vec3 dir, int tri) {
    vec3 a = tri_corners[3 * tri].xyz;
    vec3 e1 = tri_corners[3 * tri + 1].xyz - a;
    vec3 e2 = tri_corners[3 * tri + 2].xyz - a;
    vec3 pv = cross(dir, e2);
    float det = dot(e1, pv);
    if (abs(det) < 1e-12) return -1.0;
    float inv_det = 1.0 / det;
    vec3 tv = origin - a;
    float u = dot(tv, pv) * inv_det;
    if (u < 0.0 || u > 1.0) return -1.0;
    vec3 qv = cross(tv, e1);
    float v = dot(dir, qv) * inv_det;
    if (v < 0.0 || u + v > 1.0) return -1.0;
    return dot(e2, qv) * inv_det;
}

// Slab test of the segment origin + t*dir, t in [0, t_max], against a box.
bool hit_box(vec3 origin, vec3 inv_dir, float t_max, vec3 lo, vec3 hi) {
    vec3 t0 = (lo - origin) * inv_dir;
    vec3 t1 = (hi - origin) * inv_dir;
    vec3 near = min(t0, t1);
    vec3 far = max(t0, t1);
    float enter = max(max(near.x, near.y), max(near.z, 0.0));
    float leave = min(min(far.x, far.y), min(far.z, t_max));
    return enter <= leave;
}

// Whether any triangle crosses the open segment from `from` to `to` (any-hit traversal).
bool segment_blocked(vec3 from, vec3 to) {
    if (u_node_count == 0) return false;
    vec3 dir = to - from;
    // Parameters are along the unnormalised segment, so t in (0, 1) is strictly between.
    const float t_lo = 1e-6;
    const float t_hi = 1.0 - 1e-6;
    // A zero component would give 0 * inf = NaN in the slab test: nudge it instead.
    vec3 safe_dir = mix(dir, vec3(1e-30), equal(dir, vec3(0.0)));
    vec3 inv_dir = 1.0 / safe_dir;
    int stack[BVH_STACK_SIZE];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        int index = stack[--top];
        Node node = nodes[index];
        if (!hit_box(from, inv_dir, t_hi, node.lo, node.hi)) continue;
        if (node.count > 0) {
            for (int k = 0; k < node.count; ++k) {
                float t = hit_triangle(from, dir, node.left_or_first + k);
                if (t > t_lo && t < t_hi) return true;
            }
        } else {
            // The builder bounds the depth well below the stack size (explorer/truth/bvh.py).
            stack[top++] = index + 1;
            stack[top++] = node.left_or_first;
        }
    }
    return false;
}

void main() {
    ivec2 pixel = u_tile_origin + ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, u_image_size))) return;
    vec4 receiver = texelFetch(u_gbuffer_position, pixel, 0);
    if (receiver.w < 0.5) return;
    vec3 p = receiver.xyz;
    vec3 n = normalize(texelFetch(u_gbuffer_normal, pixel, 0).xyz);
    vec3 receiver_end = p + u_ray_offset * n;

    int vpl_width = textureSize(u_vpl_position, 0).x;
    vec3 irradiance = vec3(0.0);
    // Counted in a float the compiler cannot relate to the loop bound (it would fold an
    // integer check after the loop to "true"); exact up to 2^24 VPLs per chunk.
    float visited = 0.0;
    for (int i = u_vpl_begin; i < u_vpl_end; ++i) {
        visited += 1.0;
        ivec2 texel = ivec2(i % vpl_width, i / vpl_width);
        vec4 source = texelFetch(u_vpl_position, texel, 0);
        if (source.w < 0.5) continue;
        vec3 to_receiver = p - source.xyz;
        float dist_sq = dot(to_receiver, to_receiver);
        if (dist_sq <= 0.0) continue;  // direction undefined: the pair carries no light
        vec3 w = to_receiver * inversesqrt(dist_sq);
        vec3 n_j = texelFetch(u_vpl_normal, texel, 0).xyz;
        float cos_source = max(dot(n_j, w), 0.0);
        float cos_receiver = max(dot(n, -w), 0.0);
        float geometry = cos_source * cos_receiver / max(dist_sq, u_min_distance_sq);
        if (geometry <= 0.0) continue;
        if (u_visibility != 0 && segment_blocked(source.xyz + u_ray_offset * n_j, receiver_end))
            continue;
        irradiance += texelFetch(u_vpl_flux, texel, 0).rgb * (INV_PI * geometry);
    }
    // Mesa's llvmpipe stops every loop of an invocation after 65535 back-edges in total
    // (LP_MAX_TGSI_LOOP_ITERATIONS) without an error; the host keeps chunks under that
    // budget, and w = 0 records a chunk that was cut short anyway so the host can refuse
    // the result instead of returning too little light.
    float complete = visited >= float(u_vpl_end - u_vpl_begin) ? 1.0 : 0.0;
    vec4 sum = imageLoad(u_irradiance, pixel);
    imageStore(u_irradiance, pixel, vec4(sum.rgb + irradiance, min(sum.w, complete)));
}
#endif
