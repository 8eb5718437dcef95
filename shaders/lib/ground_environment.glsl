// The ground's environment light read from its environment map (src/render/ground_maps.rs):
// on a flat ground of one material under an environment at infinity, the split sum's
// diffuse and specular light (environment.glsl) depend on the direction of view alone, so
// shaders/ground_environment.comp computes them at the texel centres of a map over the
// upper hemisphere's directions once per change of the material or the environment, and
// the ground reads them bilinearly at its pixels rather than the split sum's tables,
// lookups and taps at every one of them.
#ifndef ARGIL_GROUND_ENVIRONMENT_GLSL
#define ARGIL_GROUND_ENVIRONMENT_GLSL
#include "environment.glsl"

// Whether the draw reads its environment light from the map (src/render/forward.rs): the
// ground's.
layout(constant_id = 25) const bool GROUND_ENVIRONMENT = false;

#ifndef GROUND_ENVIRONMENT_MAP_WRITER
// Layer 0 the diffuse and subsurface light, layer 1 the specular, towards each direction
// of view (hemisphere_uv).
layout(set = 5, binding = 4) uniform sampler2DArray ground_environment_map;

// environment_split_sum of the ground's material towards v on the ground, whose normal is
// +y, occluded as it occludes.
vec3 ground_environment_light(Material m, vec3 v, vec4 occlusion) {
    vec2 uv = hemisphere_uv(v);
    vec3 diffuse = textureLod(ground_environment_map, vec3(uv, 0.0), 0.0).rgb;
    vec3 specular = textureLod(ground_environment_map, vec3(uv, 1.0), 0.0).rgb;
    float specular_visibility = 1.0;
    float alpha = clamp_alpha(m.roughness * m.roughness);
    if (occlusion.a < 1.0) specular_visibility = specular_occlusion(max(v.y, MIN_N_DOT_V), occlusion.a, alpha);
    return diffuse * occlusion.rgb + specular_visibility * specular;
}
#endif

#endif
