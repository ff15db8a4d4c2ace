#version 430 core
// Vertex stage of the full-screen passes (downsample, gather): one triangle that covers the
// viewport, drawn from 3 vertices with no vertex buffer. gl_VertexID 0, 1, 2 map to the
// clip-space corners (-1, -1), (3, -1), (-1, 3). Include it inside the VERTEX_SHADER section.
#ifndef FULLSCREEN_GLSL
#define FULLSCREEN_GLSL 1

void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}

#endif
