#version 430 core
// SH glyph overlay: per instance (a cell) the polar surface r(ω) = |f(ω)|, f the cell's
// intensity SH (docs/MODEL.md "Notation and storage"; L1 instances carry zero band 2),
// drawn from a unit-sphere mesh of directions. Positive lobes orange, negative blue (the
// diverging colour map's ends). Flat shading from the screen derivatives of the position,
// times |f(ω)| over the glyph's peak, so that the lobe's axis reads from any camera: bright
// where the lobe is strong, dark on its weak side (head-on, a bright centre).

#include "sh.glsl"

uniform mat4 u_view_projection;

#if defined VERTEX_SHADER
in vec3 in_direction;             // mesh: a unit direction
in vec3 in_centre;                // instance: cell centre
in float in_scale;                // instance: world units per W/sr
in vec4 in_sh0;                   // instance: coefficients 0..3
in vec4 in_sh1;                   // instance: coefficients 4..7 (L2; else 0)
in float in_sh2;                  // instance: coefficient 8 (L2; else 0)
in float in_peak;                 // instance: largest |f| over the mesh's directions

out vec3 v_world;
out float v_value;
out float v_strength;

void main() {
    ShL2 f = ShL2(in_sh0, in_sh1, vec4(in_sh2, 0.0, 0.0, 0.0));
    float value = sh_dot(f, sh2_eval(in_direction));
    v_value = value;
    v_strength = in_peak > 0.0 ? abs(value) / in_peak : 1.0;
    v_world = in_centre + in_scale * abs(value) * in_direction;
    gl_Position = u_view_projection * vec4(v_world, 1.0);
}
#endif

#if defined FRAGMENT_SHADER
uniform vec3 u_light_direction;   // towards the viewer-side light, unit
const vec3 POSITIVE = vec3(1.0, 0.6, 0.15);
const vec3 NEGATIVE = vec3(0.2, 0.55, 1.0);

in vec3 v_world;
in float v_value;
in float v_strength;
out vec4 out_colour;

void main() {
    vec3 normal = normalize(cross(dFdx(v_world), dFdy(v_world)));
    float shade = 0.45 + 0.55 * abs(dot(normal, u_light_direction));
    float strength = 0.2 + 0.8 * pow(clamp(v_strength, 0.0, 1.0), 3.0);  // contrast
    out_colour = vec4((v_value >= 0.0 ? POSITIVE : NEGATIVE) * shade * strength, 1.0);
}
#endif
