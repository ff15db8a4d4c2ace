#version 430 core
// GENERATED FILE, do not edit. Written by `python -m derivations.codegen` from the
// corrections registry (derivations/correction_registry.py); `python -m derivations.codegen --check`
// and the test suite fail when it is stale. One switch per uniform: true = corrected,
// false = as published (Corrections.as_uniforms()). lpv_corrections.glsl includes it.

#ifndef LPV_GENERATED_CORRECTIONS
#define LPV_GENERATED_CORRECTIONS

uniform bool u_injection_pi;  // Injection: intensity = flux / π  [read by: inject, propagate]
uniform bool u_propagation_4pi;  // Propagation: no 1/(4π) per face  [read by: propagate]
uniform bool u_reprojection_pi;  // Reprojection: face flux kept as is  [read by: propagate]
uniform bool u_exact_constants;  // Exact solid angles  [read by: inject, propagate]
uniform bool u_side_faces;  // Side faces  [read by: propagate]
uniform bool u_surfel_area_squared;  // Occluder area grows with depth squared  [read by: geometry]
uniform bool u_ping_pong;  // Ping-pong propagation  [read by: propagate]
uniform bool u_clamp_front_face;  // Clamp the front face  [read by: propagate]
uniform bool u_model_face_weights;  // Face weights of the model  [read by: propagate]
uniform bool u_irradiance_gather;  // Gather the irradiance  [read by: gather]

#endif  // LPV_GENERATED_CORRECTIONS
