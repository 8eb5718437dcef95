// Per-frame and per-object data of the forward pass. The Rust side mirrors these
// layouts in src/render/gpu_scene.rs (FrameData, MaterialData, ObjectPush).
#ifndef ARGIL_SCENE_DATA_GLSL
#define ARGIL_SCENE_DATA_GLSL

#define MAX_POINT_LIGHTS 16

struct PointLight {
    vec4 position;   // xyz world position
    vec4 intensity;  // rgb radiant intensity (W/sr)
};

struct Material {
    vec4 base_color;      // rgb linear albedo
    vec4 specular_color;  // rgb tint of the specular lobe
    vec4 wrap_color;      // rgb colour of the wrap term, a = its intensity
    float roughness;      // perceptual; alpha = roughness^2
    float f0;             // Schlick reflectance at normal incidence
    float diffuse_roughness;
    float wrap;
    float wrap_width;
    float pad0;
    float pad1;
    float pad2;
};

layout(set = 0, binding = 0, std140) uniform FrameData {
    mat4 view_proj;
    vec4 camera_position;
    vec4 ambient_radiance;  // rgb radiance of a uniform environment (0 when none)
    uvec4 counts;           // x = number of point lights, y = debug view (debug_views.glsl)
    PointLight lights[MAX_POINT_LIGHTS];
} frame;

layout(set = 0, binding = 1, std430) readonly buffer Materials {
    Material materials[];
};

layout(push_constant) uniform ObjectPush {
    mat4 model;
    vec4 normal_matrix[3];  // columns of the inverse-transpose of model's 3x3
    uint material_index;
} object;

#endif
