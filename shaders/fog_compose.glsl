#version 430 core
// The surfaces seen through the fog and the fog's own in-scattered light (docs/MODEL.md
// "Fog"), composed before the exposure: T·surfaces + fog_lpv + fog_direct, where the fog
// pass (fog.glsl) wrote the direct light's in-scattering with the transmittance T in its
// alpha, and the LPV's in-scattering. With indirect only the direct light's in-scattering
// is left out, as the surfaces' direct light is. Functions only, no uniforms: the display
// stage (display.glsl) and the window's view pass (view.glsl) include it. Numpy twin:
// explorer/lpv/passes/display.py exposed_image.
#ifndef FOG_COMPOSE_GLSL
#define FOG_COMPOSE_GLSL 1

vec3 seen_through_fog(vec3 surfaces, vec4 fog_direct, vec3 fog_lpv, bool indirect_only) {
    return fog_direct.a * surfaces + fog_lpv + (indirect_only ? vec3(0.0) : fog_direct.rgb);
}

#endif
