#version 460
#include "scene_data.glsl"
#include "object_occlusion.glsl"
#include "vertex_light.glsl"

layout(location = 0) in vec3 in_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;
layout(location = 4) in float in_curvature;

layout(location = 0) out vec3 out_world_position;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv;
layout(location = 3) out vec4 out_tangent;
layout(location = 4) out float out_curvature;
// Each map's uv (material_maps.glsl), transformed here rather than per fragment: the result
// interpolates the same, and lavapipe's helper invocations read storage buffers as zero,
// which gave fragment-side uvs wrong derivatives, so wrong mip levels, along triangle edges.
layout(location = 5) out vec2 out_map_uv[MAP_COUNT];
// What the draw reads at its vertices (vertex_light.glsl), which shaders/vertex_light.comp
// computed for the object's vertices, from object.vertex_light_first on, when what they
// are made of changed: what the other objects take of the environment's light, where the
// draw reads it there (OBJECTS_OCCLUSION_FROM_VERTICES, src/scene/occluders.rs's
// Scene::occlusion_at_vertices), the ground's bounce at the mesh's normal and its gradient
// in the normal, where the draw gathers it there (bounce.glsl), and the soft lights'
// shadows.
layout(location = 5 + MAP_COUNT) out vec3 out_objects_take;
layout(location = 6 + MAP_COUNT) out vec3 out_bounce;
layout(location = 7 + MAP_COUNT) out mat3 out_bounce_gradient;
layout(location = 10 + MAP_COUNT) out vec4 out_vertex_shadows[MAX_VERTEX_SHADOW_LAYERS];
// The draw's instance: the object's number in the deferred pass (deferred.glsl), which
// the G-buffer's pipelines, shared by the objects of the same constants, write; 0 in the
// forward draws.
layout(location = 10 + MAP_COUNT + MAX_VERTEX_SHADOW_LAYERS) flat out uint out_deferred_object;

layout(set = 5, binding = 3, std430) readonly buffer VertexLight {
    LightAtVertex vertex_light[];
};

void main() {
    out_deferred_object = gl_InstanceIndex;
    vec4 world = object.model * vec4(in_position, 1.0);
    out_world_position = world.xyz;
    out_normal = object_normal(in_normal);
    out_uv = in_uv;
    Material m = materials[object.material_index];
    for (int i = 0; i < MAP_COUNT; i++) {
        out_map_uv[i] = map_uv(m.map_uv[i], m.map_uv_turn[i], in_uv);
    }
    out_tangent = vec4(mat3(object.model) * in_tangent.xyz, in_tangent.w);
    // Curvature is 1/length, so it shrinks as the object grows: divide by the model's
    // scale, the cube root of its volume scale. Exact for a uniform scale (all objects
    // have one); under a non-uniform scale it is only an average.
    float scale = pow(abs(determinant(mat3(object.model))), 1.0 / 3.0);
    out_curvature = scale > 0.0 ? in_curvature / scale : 0.0;
    uint light_at = object.vertex_light_first + gl_VertexIndex;
    if (OBJECT_OCCLUSION && OBJECTS_OCCLUSION_FROM == OBJECTS_OCCLUSION_FROM_VERTICES) {
        out_objects_take = vertex_light[light_at].objects_take.xyz;
    }
    if (BOUNCE && BOUNCE_AT_VERTICES) {
        BounceAtVertex gathered = vertex_light[light_at].bounce;
        out_bounce = gathered_irradiance(gathered);
        out_bounce_gradient = gathered_gradient(gathered);
    }
    for (uint k = 0u; k < VERTEX_SHADOW_LAYERS; ++k) {
        out_vertex_shadows[k] = vertex_light[light_at].shadows[k];
    }
    gl_Position = frame.view_proj * world;
}
