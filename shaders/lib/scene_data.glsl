// Per-frame and per-object data of the forward pass. The Rust side mirrors these
// layouts in src/render/gpu_scene.rs (FrameData, MaterialData, ObjectPush).
#ifndef ARGIL_SCENE_DATA_GLSL
#define ARGIL_SCENE_DATA_GLSL
#include "material.glsl"
#include "specialization.glsl"

#define MAX_POINT_LIGHTS 16
// src/scene/limits.rs's MAX_OCCLUDERS.
#define MAX_OCCLUDERS 64

// A sphere of an object that hides the environment's light (object_occlusion.glsl).
struct Occluder {
    vec4 sphere;  // xyz centre, w radius
    vec4 albedo;  // rgb the light it reflects of what it receives
};

struct PointLight {
    vec4 position;   // xyz world position
    vec4 intensity;  // rgb radiant intensity (W/sr)
};

layout(set = 0, binding = 0, std140) uniform FrameData {
    mat4 view_proj;
    vec4 camera_position;
    uvec4 counts;           // x = number of point lights, y = debug view (debug_views.glsl),
                            // z = the sampled reflection's sample set (environment.glsl),
                            // w = occluders in use (object_occlusion.glsl)
    PointLight lights[MAX_POINT_LIGHTS];
    vec4 ground;         // the ground, the largest builtin:plane (ground_light.glsl): xyz
                         // its centre, w its half side, 0 without a ground
    vec4 ground_albedo;  // rgb its albedo, a 1 where it bounces light (bounce.glsl), else 0
    Occluder occluders[MAX_OCCLUDERS];
} frame;

layout(set = 0, binding = 1, std430) readonly buffer Materials {
    Material materials[];
};

layout(push_constant) uniform ObjectPush {
    mat4 model;
    vec4 normal_matrix[3];  // columns of the inverse-transpose of model's 3x3
    uint material_index;
    uint shadowing_lights;  // bit i: point light i may shadow it (Scene::shadowing_lights)
    uint own_occluders;  // the run of frame.occluders that is this object: first | count << 16
    uint vertex_light_first;  // its first vertex in what the draws read there (vertex_light.rs)
} object;

// A mesh normal of the object in the world, by the inverse-transpose of its model matrix
// (not at unit length).
vec3 object_normal(vec3 mesh_normal) {
    return mat3(object.normal_matrix[0].xyz, object.normal_matrix[1].xyz, object.normal_matrix[2].xyz) * mesh_normal;
}

// The run of frame.occluders that is the object: (first, count).
uvec2 own_occluders() {
    return uvec2(object.own_occluders & 0xffffu, object.own_occluders >> 16);
}

#endif
