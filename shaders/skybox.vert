#version 460
// One triangle covering the viewport at depth 1 (the far plane), so the skybox shows only
// where the forward pass drew nothing; passes its NDC on to find the view ray.
layout(location = 0) out vec2 out_ndc;

void main() {
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2) * 2.0 - 1.0;
    out_ndc = p;
    gl_Position = vec4(p, 1.0, 1.0);
}
