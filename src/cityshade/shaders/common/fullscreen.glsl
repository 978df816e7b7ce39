// Vertex stage of a full-screen pass: one triangle covering the viewport (draw 3 vertices with
// cityshade.gl.draw_fullscreen). v_ndc: normalised device coordinates; v_uv: texture coordinates.
// FULLSCREEN_AT_FAR: the triangle lies on the far plane (the sky, drawn where nothing else was).
#if defined VERTEX_SHADER
out vec2 v_ndc;
out vec2 v_uv;
void main() {
    vec2 corner = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    v_ndc = corner * 2.0 - 1.0;
    v_uv = corner;
#if defined FULLSCREEN_AT_FAR
    gl_Position = vec4(v_ndc, 1.0, 1.0);
#else
    gl_Position = vec4(v_ndc, 0.0, 1.0);
#endif
}
#endif
