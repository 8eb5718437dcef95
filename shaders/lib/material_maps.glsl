// A material's texture maps (set 1 of the forward pass), and what they change: base
// colour, the shading normal (seed eqs. 13–16), the reflection noise (eq. 17), the
// property maps of glTF 2.0 (roughness, metallic, occlusion), the scatter map and the
// emission map. Which maps
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
const uint MAP_ROUGHNESS = 4u;
const uint MAP_ROUGHNESS_CHANNEL = 1u;
const uint MAP_METALLIC = 5u;
const uint MAP_METALLIC_CHANNEL = 2u;
const uint MAP_OCCLUSION = 6u;
const uint MAP_OCCLUSION_CHANNEL = 0u;
const uint MAP_SCATTER = 7u;
const uint MAP_SCATTER_CHANNEL = 0u;
const uint MAP_EMISSION = 8u;

const bool HAS_BASE_COLOR_MAP = (MAPS & (1u << MAP_BASE_COLOR)) != 0u;
const bool HAS_NORMAL_MAP = (MAPS & (1u << MAP_NORMAL)) != 0u;
const bool HAS_DETAIL_MAP = (MAPS & (1u << MAP_DETAIL)) != 0u;
const bool HAS_NOISE_MAP = (MAPS & (1u << MAP_NOISE)) != 0u;
const bool HAS_ROUGHNESS_MAP = (MAPS & (1u << MAP_ROUGHNESS)) != 0u;
const bool HAS_METALLIC_MAP = (MAPS & (1u << MAP_METALLIC)) != 0u;
const bool HAS_OCCLUSION_MAP = (MAPS & (1u << MAP_OCCLUSION)) != 0u;
const bool HAS_SCATTER_MAP = (MAPS & (1u << MAP_SCATTER)) != 0u;
const bool HAS_EMISSION_MAP = (MAPS & (1u << MAP_EMISSION)) != 0u;

layout(set = 1, binding = 0) uniform sampler2D base_color_map_texture;
layout(set = 1, binding = 1) uniform sampler2D normal_map_texture;
layout(set = 1, binding = 2) uniform sampler2D detail_map_texture;
layout(set = 1, binding = 3) uniform sampler2D noise_map_texture;
layout(set = 1, binding = 4) uniform sampler2D roughness_map_texture;
layout(set = 1, binding = 5) uniform sampler2D metallic_map_texture;
layout(set = 1, binding = 6) uniform sampler2D occlusion_map_texture;
layout(set = 1, binding = 7) uniform sampler2D scatter_map_texture;
layout(set = 1, binding = 8) uniform sampler2D emission_map_texture;

// base_color · mix(1, map, strength).
vec3 mapped_base_color(Material m, vec2 uv) {
    if (!HAS_BASE_COLOR_MAP) return m.base_color.rgb;
    vec3 texel = texture(base_color_map_texture, uv).rgb;
    return m.base_color.rgb * mix(vec3(1.0), texel, m.map_strength[MAP_BASE_COLOR]);
}

// emission · mix(1, map, strength), glTF 2.0's emissive factor times its texture.
vec3 mapped_emission(Material m, vec2 uv) {
    if (!HAS_EMISSION_MAP) return m.emission.rgb;
    vec3 texel = texture(emission_map_texture, uv).rgb;
    return m.emission.rgb * mix(vec3(1.0), texel, m.map_strength[MAP_EMISSION]);
}

// The shading normal: the normal map, with the detail map blended over it, through the
// vertex's tangent frame. `normal` is the unit surface normal on the viewer's side.
vec3 mapped_normal(Material m, vec3 normal, vec4 tangent, vec2 normal_uv, vec2 detail_uv) {
    if (!HAS_NORMAL_MAP && !HAS_DETAIL_MAP) return normal;
    vec3 n = vec3(0.0, 0.0, 1.0);
    if (HAS_NORMAL_MAP) {
        n = decode_normal(texture(normal_map_texture, normal_uv).rgb, m.green_down.x != 0u, m.map_strength[MAP_NORMAL]);
    }
    if (HAS_DETAIL_MAP) {
        vec3 d = decode_normal(texture(detail_map_texture, detail_uv).rgb, m.green_down.y != 0u, m.map_strength[MAP_DETAIL]);
        n = HAS_NORMAL_MAP ? blend_detail(DETAIL_BLEND, n, d) : d;
    }
    return tangent_to_world(n, normal, tangent);
}

// mix(1, noise, strength), from the noise map's red channel; 1 without a map.
float mapped_noise(Material m, vec2 uv) {
    if (!HAS_NOISE_MAP) return 1.0;
    return mix(1.0, texture(noise_map_texture, uv)[MAP_NOISE_CHANNEL], m.map_strength[MAP_NOISE]);
}

// A property map's factor, mix(1, its channel, strength): glTF 2.0 multiplies the
// material's value by the texture's channel. Twin: `map_factor` in src/reference/world.rs.
float map_factor(sampler2D map, uint channel, float strength, vec2 uv) {
    return mix(1.0, texture(map, uv)[channel], strength);
}

// The material with its roughness, metallic and scatter maps applied (roughness × G,
// metallic × B, scatter colour and wrap × R); `uv` is every map's.
Material mapped_properties(Material m, vec2 uv[MAP_COUNT]) {
    if (HAS_ROUGHNESS_MAP) {
        m.roughness *= map_factor(roughness_map_texture, MAP_ROUGHNESS_CHANNEL, m.map_strength[MAP_ROUGHNESS],
                                  uv[MAP_ROUGHNESS]);
    }
    if (HAS_METALLIC_MAP) {
        m.metallic *= map_factor(metallic_map_texture, MAP_METALLIC_CHANNEL, m.map_strength[MAP_METALLIC], uv[MAP_METALLIC]);
    }
    if (HAS_SCATTER_MAP) {
        float s = map_factor(scatter_map_texture, MAP_SCATTER_CHANNEL, m.map_strength[MAP_SCATTER], uv[MAP_SCATTER]);
        m.scatter.rgb *= s;
        m.wrap *= s;
    }
    return m;
}

// The occlusion map's visibility: of the environment's light, and the point lights'
// micro-shadowing (lights.glsl); 1 without the map.
float mapped_occlusion(Material m, vec2 uv) {
    if (!HAS_OCCLUSION_MAP) return 1.0;
    return map_factor(occlusion_map_texture, MAP_OCCLUSION_CHANNEL, m.map_strength[MAP_OCCLUSION], uv);
}

#endif
