// A material's parameters as the shaders read them; mirrored by MaterialData in
// src/render/gpu_scene.rs (std430).
#ifndef ARGIL_MATERIAL_GLSL
#define ARGIL_MATERIAL_GLSL

struct Material {
    vec4 base_color;      // rgb linear albedo
    vec4 specular_color;  // rgb tint of the specular lobe
    vec4 wrap_color;      // rgb colour of the report's wrap term, a = its intensity
    vec4 scatter;         // rgb scatter_color (per-channel reach), a = scatter_radius
    float roughness;      // perceptual; alpha = roughness^2
    float f0;             // Schlick reflectance at normal incidence
    float diffuse_roughness;
    float wrap;
    float wrap_width;
    float pad0;
    float pad1;
    float pad2;
    // Material maps (material_maps.glsl): uv · scale + offset, strengths, conventions.
    vec4 base_color_uv;   // xy scale, zw offset
    vec4 normal_uv;
    vec4 detail_uv;
    vec4 noise_uv;
    vec4 map_strength;    // base colour, normal, detail, noise
    uvec4 green_down;     // x normal map, y detail map: 1 for DirectX-style maps
};

// A map's uv from the mesh's: uv · scale + offset (`transform` is one of the *_uv fields).
vec2 map_uv(vec4 transform, vec2 uv) {
    return uv * transform.xy + transform.zw;
}

#endif
