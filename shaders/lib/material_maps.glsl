// A material's texture maps (set 1 of the forward pass), and what they change: base
// colour, the shading normal (seed eqs. 13–16) and the reflection noise (eq. 17). Which maps
// a material samples is the MAPS specialization constant, one bit per slot of
// src/scene/map_slots.rs (its index, binding and bit are the same number), so a material
// without maps samples nothing. Each function takes its map's uv, already transformed by
// map_uv in forward.vert.
#ifndef ARGIL_MATERIAL_MAPS_GLSL
#define ARGIL_MATERIAL_MAPS_GLSL
#include "material.glsl"
#include "normal_mapping.glsl"

layout(constant_id = 4) const uint MAPS = 0u;
layout(constant_id = 5) const uint DETAIL_BLEND = 0u;

const uint MAP_BASE_COLOR = 0u;
const uint MAP_NORMAL = 1u;
const uint MAP_DETAIL = 2u;
const uint MAP_NOISE = 3u;
const uint MAP_NOISE_CHANNEL = 0u;

const bool HAS_BASE_COLOR_MAP = (MAPS & (1u << MAP_BASE_COLOR)) != 0u;
const bool HAS_NORMAL_MAP = (MAPS & (1u << MAP_NORMAL)) != 0u;
const bool HAS_DETAIL_MAP = (MAPS & (1u << MAP_DETAIL)) != 0u;
const bool HAS_NOISE_MAP = (MAPS & (1u << MAP_NOISE)) != 0u;

layout(set = 1, binding = 0) uniform sampler2D base_color_map;
layout(set = 1, binding = 1) uniform sampler2D normal_map;
layout(set = 1, binding = 2) uniform sampler2D detail_map;
layout(set = 1, binding = 3) uniform sampler2D noise_map;

// base_color · mix(1, map, strength).
vec3 mapped_base_color(Material m, vec2 uv) {
    if (!HAS_BASE_COLOR_MAP) return m.base_color.rgb;
    vec3 texel = texture(base_color_map, uv).rgb;
    return m.base_color.rgb * mix(vec3(1.0), texel, m.map_strength[MAP_BASE_COLOR]);
}

// The shading normal: the normal map, with the detail map blended over it, through the
// vertex's tangent frame. `normal` is the unit surface normal on the viewer's side.
vec3 mapped_normal(Material m, vec3 normal, vec4 tangent, vec2 normal_uv, vec2 detail_uv) {
    if (!HAS_NORMAL_MAP && !HAS_DETAIL_MAP) return normal;
    vec3 n = vec3(0.0, 0.0, 1.0);
    if (HAS_NORMAL_MAP) {
        n = decode_normal(texture(normal_map, normal_uv).rgb, m.green_down.x != 0u, m.map_strength[MAP_NORMAL]);
    }
    if (HAS_DETAIL_MAP) {
        vec3 d = decode_normal(texture(detail_map, detail_uv).rgb, m.green_down.y != 0u, m.map_strength[MAP_DETAIL]);
        n = HAS_NORMAL_MAP ? blend_detail(DETAIL_BLEND, n, d) : d;
    }
    return tangent_to_world(n, normal, tangent);
}

// mix(1, noise, strength), from the noise map's red channel; 1 without a map.
float mapped_noise(Material m, vec2 uv) {
    if (!HAS_NOISE_MAP) return 1.0;
    return mix(1.0, texture(noise_map, uv)[MAP_NOISE_CHANNEL], m.map_strength[MAP_NOISE]);
}

#endif
