#version 460
// The ground's bounce at the vertices of one object (bounce.glsl): at each vertex of its mesh
// (set 1, binding 0), moved into the world as forward.vert moves it (the push constants are
// the draw's, ObjectPush), the gather at the mesh's normal and its gradient in the normal,
// into the object's run of the buffer that forward.vert reads (set 1, binding 1, from
// object.bounce_first on). src/render/vertex_bounce.rs runs it when what it is made of
// changes. Set 0 is the forward pass's (FrameData), 2 its environment's, 5 its ground maps'.
#include "bounce.glsl"

layout(local_size_x = 64) in;

// src/scene/mesh.rs's Vertex, 13 floats: position, normal, uv, tangent, curvature.
const uint VERTEX_FLOATS = 13u;

layout(set = 1, binding = 0, std430) readonly buffer Vertices {
    float vertex_floats[];
};

layout(set = 1, binding = 1, std430) writeonly buffer Bounce {
    BounceAtVertex bounce_out[];
};

void main() {
    uint vertex = gl_GlobalInvocationID.x;
    if (vertex >= uint(vertex_floats.length()) / VERTEX_FLOATS) return;
    uint at = vertex * VERTEX_FLOATS;
    vec3 position = vec3(vertex_floats[at], vertex_floats[at + 1u], vertex_floats[at + 2u]);
    vec3 normal = vec3(vertex_floats[at + 3u], vertex_floats[at + 4u], vertex_floats[at + 5u]);
    vec3 world = (object.model * vec4(position, 1.0)).xyz;
    // At the mesh's own normal, the side a closed mesh shows.
    vec3 n = unit_or_zero(object_normal(normal));
    bounce_out[object.bounce_first + vertex] = bounce_at_vertex(ground_bounce_irradiance(world, n),
                                                                ground_bounce_gradient(world));
}
