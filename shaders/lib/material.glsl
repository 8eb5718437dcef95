// A material's parameters as the shaders read them; mirrored by MaterialData in
// src/render/gpu_scene.rs (std430).
#ifndef ARGIL_MATERIAL_GLSL
#define ARGIL_MATERIAL_GLSL

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

#endif
