// The scene's point lights at a surface point.
#ifndef ARGIL_LIGHTS_GLSL
#define ARGIL_LIGHTS_GLSL
#include "scene_data.glsl"
#include "shading.glsl"
#include "shadows.glsl"
#include "occlusion.glsl"
#include "ground_shadow.glsl"
#include "vertex_light.glsl"

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

#ifdef DEFERRED
// The deferred pass reads no vertex shadows: a draw that reads them is not deferred.
vec4 in_vertex_shadows[MAX_VERTEX_SHADOW_LAYERS];
#else
// The soft lights' shadows at the draw's vertices (vertex_light.glsl), interpolated.
layout(location = 10 + MAP_COUNT) in vec4 in_vertex_shadows[MAX_VERTEX_SHADOW_LAYERS];
#endif

// Soft light i's shadow interpolated from the vertices. The constant conditions leave the
// pipeline reading only the layers its lights fill: each input read is interpolated.
float interpolated_vertex_shadow(uint i) {
    vec4 layer = in_vertex_shadows[0];
    layer = VERTEX_SHADOW_LAYERS > 1u && i >= 4u ? in_vertex_shadows[1] : layer;
    layer = VERTEX_SHADOW_LAYERS > 2u && i >= 8u ? in_vertex_shadows[2] : layer;
    layer = VERTEX_SHADOW_LAYERS > 3u && i >= 12u ? in_vertex_shadows[3] : layer;
    return layer[i % 4u];
}

// Soft light i's shadow at p, interpolated from the vertices; 1 where the light is behind
// the triangle seen from the eye, where no map is read (shadow_receiver) and the subsurface
// term alone lights p: the triangle's vertices on the lit side would darken it.
float vertex_shadow_at_pixel(uint i, vec3 p, vec3 face_normal) {
    vec3 q = p - frame.lights[i].position.xyz;
    bool behind = dot(face_normal, q) * dot(face_normal, frame.camera_position.xyz - p) >= 0.0;
    return behind ? 1.0 : interpolated_vertex_shadow(i);
}

// The fraction of point light i that reaches p: 1 without shadows; where the draw reads the
// soft lights' shadows elsewhere, from the ground's map (GROUND_SHADOWS) or its vertices
// (VERTEX_SHADOW_LAYERS), a soft light's from there and a hard one's (HARD_SHADOWS_AT_PIXELS)
// looked up at the pixel; else point_light_shadow with the receiver's triangle's normal
// `face_normal`, for the lights that may shadow the draw's object.
float point_light_visibility(uint i, vec3 p, vec3 face_normal) {
    if (!SHADOWS) return 1.0;
    bool may_shadow = ((object.shadowing_lights >> i) & 1u) != 0u;
    if (!GROUND_SHADOWS && VERTEX_SHADOW_LAYERS == 0u) {
        return point_light_shadow(i, p, face_normal, frame.camera_position.xyz - p, gl_FragCoord.xy, may_shadow);
    }
    float soft = GROUND_SHADOWS ? ground_map_shadow(i, p) : vertex_shadow_at_pixel(i, p, face_normal);
    if (!HARD_SHADOWS_AT_PIXELS) return soft;
    // Lavapipe runs both for every light: the hard lookup is one tap, the other one read.
    float at_pixel = may_shadow ? hard_light_shadow(i, p, face_normal) : 1.0;
    return shadow_data.lights[i].map.y > 0.0 ? soft : at_pixel;
}

// Radiance from the point lights through brdf_cos with the given models and material, or
// through the report's composition (brdf_cos_seed) when `seed_horizon`; each light
// micro-shadowed by the occlusion map's visibility `ao` (1 without the map: unchanged).
// `face_normal` is cross(dFdx(p), dFdy(p)), taken in uniform control flow.
vec3 point_lights_radiance(ShadingModels models, Material m, vec3 n, vec3 n_geometric, vec3 v, vec3 p,
                           vec3 face_normal, float curvature, bool seed_horizon, float ao) {
    vec3 radiance = vec3(0.0);
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
