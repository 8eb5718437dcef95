// A material's parameters as the shaders read them; mirrored by MaterialData in
// src/render/gpu_scene.rs (std430).
#ifndef ARGIL_MATERIAL_GLSL
#define ARGIL_MATERIAL_GLSL

// The material map slots of src/scene/map_slots.rs.
const int MAP_COUNT = 8;

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
    float metallic;       // 0 dielectric, 1 metal (glTF 2.0 metallic-roughness)
    float energy_compensation; // 1: the specular lobe is energy-compensated (environment.glsl)
    float micro_shadowing; // 1: the occlusion map micro-shadows the point lights (lights.glsl)
    // Material maps (material_maps.glsl), by the slot indices of src/scene/map_slots.rs.
    vec4 map_uv[MAP_COUNT];          // xy scale, zw offset: uv · scale + offset
    float map_strength[MAP_COUNT];
    uvec4 green_down;     // x normal map, y detail map: 1 for DirectX-style maps
};

// glTF 2.0's metallic-roughness blend (glTF 2.0 specification, appendix B): the albedo
// of the diffuse lobes and subsurface terms, base_color · (1 − metallic) ...
vec3 diffuse_color(Material m) {
    return m.base_color.rgb * (1.0 - m.metallic);
}

// ... and the specular lobe's F0, mix(f0, base_color, metallic): a metal reflects its base
// colour. Twins: ShadingParams::diffuse_color and specular_f0 in src/brdf/shading.rs.
vec3 specular_f0(Material m) {
    return mix(vec3(m.f0), m.base_color.rgb, m.metallic);
}

// A map's uv from the mesh's: uv · scale + offset (`transform` is one of map_uv).
vec2 map_uv(vec4 transform, vec2 uv) {
    return uv * transform.xy + transform.zw;
}

#endif
