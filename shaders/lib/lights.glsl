// The scene's point lights at a surface point.
#ifndef ARGIL_LIGHTS_GLSL
#define ARGIL_LIGHTS_GLSL
#include "scene_data.glsl"
#include "shading.glsl"
#include "shadows.glsl"
#include "occlusion.glsl"
#include "ground_shadow.glsl"

// Unit direction l from p towards point light i, and its irradiance on a surface facing
// it, E⊥ = I / d² (the scene format's radiant intensity I).
vec3 point_light_irradiance(uint i, vec3 p, out vec3 l) {
    vec3 to_light = frame.lights[i].position.xyz - p;
    float distance2 = max(dot(to_light, to_light), MIN_LIGHT_DISTANCE2);
    l = to_light * inversesqrt(distance2);
    return frame.lights[i].intensity.rgb / distance2;
}

// Whether any light of the frame has a shadow map (src/render/forward.rs). Off, the
// pipeline holds no shadow code: a light without a map is whole at every point, and
// lavapipe would still run what the lookups share before finding that out.
layout(constant_id = 20) const bool SHADOWS = true;

// The fraction of point light i that reaches p: 1 without shadows; on the ground that reads
// its shadows from its map (GROUND_SHADOWS), a soft light's from the map and a hard one's
// (GROUND_HARD_SHADOWS) looked up at the pixel; else point_light_shadow with the receiver's
// triangle's normal `face_normal`, for the lights that may shadow the draw's object.
float point_light_visibility(uint i, vec3 p, vec3 face_normal) {
    if (!SHADOWS) return 1.0;
    bool may_shadow = ((object.shadowing_lights >> i) & 1u) != 0u;
    if (!GROUND_SHADOWS) return point_light_shadow(i, p, face_normal, gl_FragCoord.xy, may_shadow);
    if (!GROUND_HARD_SHADOWS) return ground_map_shadow(i, p);
    // Lavapipe runs both for every light: the hard lookup is one tap, the map's one read.
    float at_pixel = hard_light_shadow(i, p, face_normal);
    return shadow_data.lights[i].map.y > 0.0 ? ground_map_shadow(i, p) : at_pixel;
}

// Radiance from the point lights through brdf_cos with the given models and material, or
// through the report's composition (brdf_cos_seed) when `seed_horizon`; each light
// micro-shadowed by the occlusion map's visibility `ao` (1 without the map: unchanged).
vec3 point_lights_radiance(ShadingModels models, Material m, vec3 n, vec3 n_geometric, vec3 v, vec3 p,
                           float curvature, bool seed_horizon, float ao) {
    vec3 radiance = vec3(0.0);
    vec3 face_normal = cross(dFdx(p), dFdy(p));
    for (uint i = 0; i < frame.counts.x; ++i) {
        vec3 l;
        vec3 irradiance = point_light_irradiance(i, p, l) * point_light_visibility(i, p, face_normal)
                        * micro_shadowing(dot(n, l), ao);
#if SEED_COMPOSITION
        vec3 f = seed_horizon ? brdf_cos_seed(models, m, n, v, l, curvature)
                              : brdf_cos(models, m, n, n_geometric, v, l, curvature);
#else
        vec3 f = brdf_cos(models, m, n, n_geometric, v, l, curvature);
#endif
        radiance += irradiance * f;
    }
    return radiance;
}

#endif
