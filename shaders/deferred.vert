#version 460
// One triangle over the viewport at the depth of the instance's object (deferred.glsl): a
// solid's shading draw, which the depth test keeps to the pixels that show it.
#include "deferred.glsl"

// The solid's number, for its shading to tell its own pixels from the others it runs beside.
layout(location = 0) flat out uint out_deferred_object;

void main() {
    out_deferred_object = gl_InstanceIndex;
    vec2 p = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    gl_Position = vec4(p * 2.0 - 1.0, deferred_object_depth(uint(gl_InstanceIndex)), 1.0);
}
