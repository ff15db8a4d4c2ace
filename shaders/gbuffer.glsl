#version 430 core
// G-buffer from the camera. Targets: 0 = world position (w = 1 where a surface was seen),
// 1 = normal facing the camera (w = world area of the surface under the pixel),
// 2 = linear albedo, the base-colour texture sampled per pixel (w = 1).

uniform mat4 u_view;
uniform mat4 u_projection;

#include "surface.glsl"

#if defined VERTEX_SHADER
void main() {
    pass_surface();
    gl_Position = u_projection * u_view * vec4(in_position, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
layout(location = 0) out vec4 out_position;
layout(location = 1) out vec4 out_normal;
layout(location = 2) out vec4 out_albedo;

void main() {
    vec3 normal = surface_normal();  // sidedness as in the RSM pass
    // The pixel's footprint on the surface: the parallelogram spanned by the position's
    // screen derivatives (within one triangle they are exact). The energy audit sums
    // irradiance × this area.
    float pixel_area = length(cross(dFdx(v_position), dFdy(v_position)));
    out_position = vec4(v_position, 1.0);
    out_normal = vec4(normal, pixel_area);
    out_albedo = vec4(surface_albedo(), 1.0);
}
#endif
