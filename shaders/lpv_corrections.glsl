#version 430 core
// The Corrections switches (Corrections.as_uniforms()) and the factors they select
// (docs/MODEL.md "Corrections": k_I, k_P, k_R and the published versus exact constants).
#ifndef LPV_CORRECTIONS_GLSL
#define LPV_CORRECTIONS_GLSL 1

#include "sh.glsl"

uniform bool u_injection_pi;
uniform bool u_propagation_4pi;
uniform bool u_reprojection_pi;
uniform bool u_exact_constants;
uniform bool u_side_faces;
uniform bool u_surfel_area_squared;
uniform bool u_ping_pong;
uniform bool u_clamp_front_face;

// pi as the formulas use it: the DX11 article's decimals when exact constants are off.
float lpv_pi() {
    return u_exact_constants ? PI : PUBLISHED_PI;
}

// k_I: intensity per watt of a Lambertian VPL, 1/pi (corrected) or 1 (as published).
float lpv_injection_factor() {
    return u_injection_pi ? 1.0 / lpv_pi() : 1.0;
}

// k_P: 1 (corrected) or 1/(4 pi) (as published) in Phi_f = k_P * dw_f * I(w_c).
float lpv_propagation_factor() {
    return u_propagation_4pi ? 1.0 : 1.0 / (4.0 * lpv_pi());
}

// k_R: 1 (corrected) or 1/pi (as published) in Phi_l = k_R * Phi_f.
float lpv_reprojection_factor() {
    return u_reprojection_pi ? 1.0 : 1.0 / lpv_pi();
}

float lpv_front_solid_angle() {
    return u_exact_constants ? FRONT_FACE_SOLID_ANGLE : PUBLISHED_FRONT_FACE_SOLID_ANGLE;
}

float lpv_side_solid_angle() {
    return u_exact_constants ? SIDE_FACE_SOLID_ANGLE : PUBLISHED_SIDE_FACE_SOLID_ANGLE;
}

#endif
