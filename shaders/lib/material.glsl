// A material's parameters as the shaders read them: MaterialData of
// src/render/material_data.rs (std430), and what the shaders derive from them.
#ifndef ARGIL_MATERIAL_GLSL
#define ARGIL_MATERIAL_GLSL

// The material map slots of src/scene/map_slots.rs.
const int MAP_COUNT = 9;

// struct Material and material_zero(), written by build.rs from MaterialData.
#include "material_struct.glsl"

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

// A map's uv from the mesh's: scaled, turned counter-clockwise by `turn` = (cos, sin) and
// offset (`transform` = (scale, offset) is one of map_uv, `turn` of map_uv_turn). Twin:
// MapRef::uv in src/scene/material.rs.
vec2 map_uv(vec4 transform, vec2 turn, vec2 uv) {
    vec2 scaled = uv * transform.xy;
    return vec2(turn.x * scaled.x - turn.y * scaled.y, turn.y * scaled.x + turn.x * scaled.y) + transform.zw;
}

#endif
