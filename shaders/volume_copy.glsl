#version 430 core
// Copy one RGBA volume into a 3D image, texel for texel: from a layered 2D-array render
// target (SOURCE_LAYERED 1, layer = z) or from another 3D texture (SOURCE_LAYERED 0).
#define SOURCE_LAYERED 0
#define IMAGE_FORMAT rgba32f

#if defined COMPUTE_SHADER

layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

#if SOURCE_LAYERED
uniform sampler2DArray u_source;
#else
uniform sampler3D u_source;
#endif
layout(IMAGE_FORMAT, binding = 0) uniform writeonly image3D u_target;  // image unit 0

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    if (any(greaterThanEqual(texel, imageSize(u_target)))) {
        return;
    }
    imageStore(u_target, texel, texelFetch(u_source, texel, 0));
}

#endif
