#version 430 core
// Merging the geometry volumes of several RSM views (docs/MODEL.md "Several lights"): per
// geometry cell keep the view whose surfels cover the most area there (the larger band-0
// coefficient: every surfel adds A/cell_size² · √π/2 to it, or √π double-sided), with its
// area-weighted albedo. A surface two lights both see is then counted once, not twice;
// two different surfaces in one cell, each seen by another light only, count as the
// larger of the two.
// MERGE_ADD 1 adds the volume instead: the camera occluders' surfels (docs/MODEL.md
// "Camera occluders"), which no view holds, so adding them counts no surface twice.
#define IMAGE_FORMAT rgba32f
#ifndef MERGE_ADD
#define MERGE_ADD 0
#endif

#if defined COMPUTE_SHADER

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

uniform sampler3D u_view_blocker;     // the new view's volume
uniform sampler3D u_view_albedo;
layout(IMAGE_FORMAT, binding = 0) uniform image3D u_merged_blocker;   // image unit 0
layout(IMAGE_FORMAT, binding = 1) uniform image3D u_merged_albedo;    // image unit 1

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(texel, imageSize(u_merged_blocker)))) {
        return;
    }
    vec4 blocker = texelFetch(u_view_blocker, texel, 0);
#if MERGE_ADD
    imageStore(u_merged_blocker, texel, imageLoad(u_merged_blocker, texel) + blocker);
    imageStore(u_merged_albedo, texel,
               imageLoad(u_merged_albedo, texel) + texelFetch(u_view_albedo, texel, 0));
#else
    if (blocker.x > imageLoad(u_merged_blocker, texel).x) {
        imageStore(u_merged_blocker, texel, blocker);
        imageStore(u_merged_albedo, texel, texelFetch(u_view_albedo, texel, 0));
    }
#endif
}

#endif
