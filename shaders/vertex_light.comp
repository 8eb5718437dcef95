#version 460
// What one object's draw reads at its vertices (vertex_light.glsl): at each vertex of its
// mesh (set 1, binding 0), moved into the world as forward.vert moves it (the push
// constants are the draw's, ObjectPush), the ground's bounce at the mesh's normal and its
// gradient in the normal, each soft light's shadow, and with OBJECT_OCCLUSION what the
// other objects' spheres (frame.occluders but the object's own) take of the environment's
// light, into the object's run of the buffer that forward.vert reads (set 1, binding 1,
// from object.vertex_light_first on). src/render/vertex_light.rs runs it when what it is
// made of changes. Set 0 is the forward pass's (FrameData, the occluders among it), 2 its
// environment's, 3 its shadows', 5 its ground maps'.
#include "vertex_light.glsl"

layout(local_size_x = 64) in;

// src/scene/mesh.rs's Vertex, 13 floats: position, normal, uv, tangent, curvature.
const uint VERTEX_FLOATS = 13u;

layout(set = 1, binding = 0, std430) readonly buffer Vertices {
    float vertex_floats[];
};

layout(set = 1, binding = 1, std430) writeonly buffer VertexLight {
    LightAtVertex light_out[];
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
    LightAtVertex light;
    light.bounce = bounce_at_vertex(ground_bounce_irradiance(world, n), ground_bounce_gradient(world));
    for (uint k = 0u; k < MAX_VERTEX_SHADOW_LAYERS; ++k) {
        light.shadows[k] = vec4(1.0);
    }
    for (uint i = 0u; i < VERTEX_SHADOW_LAYERS * 4u && i < frame.counts.x; ++i) {
        light.shadows[i / 4u][i % 4u] = vertex_shadow(i, world, n, vertex);
    }
    light.objects_take = vec4(1.0 - object_occlusion(world, n, own_occluders()), 0.0);
    light_out[object.vertex_light_first + vertex] = light;
}
