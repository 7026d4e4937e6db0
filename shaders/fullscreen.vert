// shaders/fullscreen.vert - one triangle covering the viewport: vertices 0, 1, 2 at clip (-1,-1), (3,-1), (-1,3).
// Draw with 3 vertices and no vertex input.
#version 450

void main() {
    const vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);
}
