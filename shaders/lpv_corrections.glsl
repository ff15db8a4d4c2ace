#version 430 core
// The factors the Corrections switches select (docs/MODEL.md "Corrections": k_I, k_P, k_R
// and the published versus exact constants). The switches themselves (one uniform bool
// u_<name> each, Corrections.as_uniforms()) are declared by the generated file, from the
// corrections registry derivations/correction_registry.py.
#ifndef LPV_CORRECTIONS_GLSL
#define LPV_CORRECTIONS_GLSL 1

#include "sh.glsl"
#include "generated/corrections.glsl"

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

// k_R: 1 (corrected) or 1/pi (as published) in Phi_lobe = k_R * Phi_f.
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
