// Debug views of the forward pass, selected by FrameData.counts.y: geometry as colours, or
// one term of the shading alone. The values are `as u32` of DebugView in
// src/render/debug_view.rs. Lobes are isolated by calling the shading code itself with the
// other terms switched off, so a lobe view shows exactly what the shaded image adds up.
#ifndef ARGIL_DEBUG_VIEWS_GLSL
#define ARGIL_DEBUG_VIEWS_GLSL
#include "scene_data.glsl"
#include "shading.glsl"
#include "lights.glsl"
#include "shadows.glsl"

const uint DEBUG_VIEW_SHADED = 0u;
const uint DEBUG_VIEW_NORMALS = 1u;
const uint DEBUG_VIEW_TANGENTS = 2u;
const uint DEBUG_VIEW_BITANGENTS = 3u;
const uint DEBUG_VIEW_UVS = 4u;
const uint DEBUG_VIEW_N_DOT_L = 5u;
const uint DEBUG_VIEW_DIFFUSE = 6u;
const uint DEBUG_VIEW_SPECULAR = 7u;
const uint DEBUG_VIEW_SUBSURFACE = 8u;
const uint DEBUG_VIEW_ENVIRONMENT = 9u;
const uint DEBUG_VIEW_NAN = 10u;
const uint DEBUG_VIEW_CURVATURE = 11u;
const uint DEBUG_VIEW_OCCLUSION = 12u;
const uint DEBUG_VIEW_SHADOWS = 13u;
const uint DEBUG_VIEW_BOUNCE = 14u;
const uint DEBUG_VIEW_SHADOW_MAP = 15u;

// The curvature view's brightness is 1 - exp(-|κ| · CURVATURE_VIEW_SCALE): a sphere of
// radius 1 shows at 0.39, of radius 0.35 (the builtin torus's tube) at 0.76, of radius
// 0.1 at 0.99; a plane is black.
const float CURVATURE_VIEW_SCALE = 0.5;

// The shadow-map view darkens every other texel of the map by this factor.
const float SHADOW_MAP_VIEW_CHECKER = 0.8;

// The model value that turns a lobe off (DiffuseModel::None, SpecularModel::None).
const uint MODEL_NONE = 3u;

// A direction as a colour: [-1, 1] → [0, 1] per component.
vec3 direction_color(vec3 d) {
    return unit_or_zero(d) * 0.5 + 0.5;
}

// The first shadowed light's cube map projected onto p, grey: at the map's texel nearest
// to p's direction, the distance it stores over p's (< 1 in front of p), 1 where its
// comparison passes; × SHADOW_MAP_VIEW_CHECKER on every other texel, so the map's
// resolution shows. 1 where the map says nothing (shadow_receiver) or without a map.
// `face_normal` is cross(dFdx(p), dFdy(p)), taken in uniform control flow.
vec3 shadow_map_view(vec3 p, vec3 face_normal) {
    for (uint i = 0u; i < frame.counts.x; ++i) {
        if (shadow_data.lights[i].map.x < 0.0) continue;
        ShadowReceiver r;
        vec3 w;
        if (!shadow_receiver(i, p, face_normal, frame.camera_position.xyz - p, r, w)) return vec3(1.0);
        uint face;
        ivec2 texel = shadow_nearest_texel(w, face);
        float blocker = shadow_texel_blocker(r, face, texel);
        float ratio = blocker > 0.0 ? min(blocker / r.distance, 1.0) : 1.0;
        bool odd = ((texel.x + texel.y + int(face)) & 1) == 1;
        return vec3(ratio * (odd ? SHADOW_MAP_VIEW_CHECKER : 1.0));
    }
    return vec3(1.0);
}

// What debug view `view` shows at a surface point; `shaded` is the normal result there.
// `n` is the shading normal, `n_geometric` the surface's, `normal`, `tangent` and
// `curvature` the interpolated vertex attributes (curvature in 1/world length),
// `environment` the environment's term, `bounced` the ground's bounce, `visibility` the
// ambient occlusion's, `ao` the occlusion map's (point_lights_radiance).
vec3 debug_view_radiance(uint view, ShadingModels models, Material m, vec3 n, vec3 n_geometric,
                         vec3 v, vec3 p, vec3 normal, vec2 uv, vec4 tangent, vec3 environment,
                         vec3 bounced, vec3 shaded, float curvature, float visibility, float ao) {
    vec3 face_normal = cross(dFdx(p), dFdy(p));
    if (view == DEBUG_VIEW_NORMALS) return direction_color(n);
    if (view == DEBUG_VIEW_TANGENTS) return direction_color(tangent.xyz);
    if (view == DEBUG_VIEW_BITANGENTS) {
        return direction_color(cross(normal, tangent.xyz) * (tangent.w < 0.0 ? -1.0 : 1.0));
    }
    if (view == DEBUG_VIEW_UVS) return vec3(fract(uv), 0.0);
    if (view == DEBUG_VIEW_CURVATURE) {
        // Red where convex, blue where concave.
        float strength = 1.0 - exp(-abs(curvature) * CURVATURE_VIEW_SCALE);
        return curvature > 0.0 ? vec3(strength, 0.0, 0.0) : vec3(0.0, 0.0, strength);
    }
    if (view == DEBUG_VIEW_N_DOT_L) {
        float sum = 0.0;
        for (uint i = 0; i < frame.counts.x; ++i) {
            vec3 l;
            point_light_irradiance(i, p, l);
            sum += max(dot(n, l), 0.0);
        }
        return vec3(min(sum, 1.0));
    }
    if (view == DEBUG_VIEW_DIFFUSE) {
        ShadingModels diffuse_only = models;
        diffuse_only.specular = MODEL_NONE;
        diffuse_only.subsurface = SUBSURFACE_NONE;
        return point_lights_radiance(diffuse_only, m, n, n_geometric, v, p, face_normal, curvature, false, ao);
    }
    if (view == DEBUG_VIEW_SPECULAR) {
        ShadingModels specular_only = models;
        specular_only.diffuse = MODEL_NONE;
        specular_only.subsurface = SUBSURFACE_NONE;
        return point_lights_radiance(specular_only, m, n, n_geometric, v, p, face_normal, curvature, false, ao);
    }
    if (view == DEBUG_VIEW_SUBSURFACE) {
        // The subsurface term alone: the report's wrap, or what a redistributing model adds
        // to the diffuse lobe, negative (black) where it takes light away.
        ShadingModels diffuse_only = models;
        diffuse_only.specular = MODEL_NONE;
        vec3 with_subsurface = point_lights_radiance(diffuse_only, m, n, n_geometric, v, p, face_normal, curvature, false, ao);
        diffuse_only.subsurface = SUBSURFACE_NONE;
        return with_subsurface - point_lights_radiance(diffuse_only, m, n, n_geometric, v, p, face_normal, curvature, false, ao);
    }
    if (view == DEBUG_VIEW_ENVIRONMENT) return environment;
    if (view == DEBUG_VIEW_OCCLUSION) return vec3(visibility);
    if (view == DEBUG_VIEW_SHADOWS) {
        // The shadow factors of the point lights (shadows.glsl), weighted by the luminance
        // of their irradiance on a surface facing them: white lit, black in every umbra.
        float lit = 0.0;
        float total = 0.0;
        for (uint i = 0; i < frame.counts.x; ++i) {
            vec3 l;
            float e = dot(point_light_irradiance(i, p, l), vec3(0.2126, 0.7152, 0.0722));
            total += e;
            lit += e * point_light_visibility(i, p, face_normal);
        }
        return vec3(total > 0.0 ? lit / total : 1.0);
    }
    if (view == DEBUG_VIEW_BOUNCE) {
        // The light bounced off the ground alone (bounce.glsl), `bounced`; where the ground
        // is darker than the sky it takes light away, shown in red by the luminance it takes.
        float taken = max(-dot(bounced, vec3(0.2126, 0.7152, 0.0722)), 0.0);
        return max(bounced, vec3(0.0)) + vec3(taken, 0.0, 0.0);
    }
    if (view == DEBUG_VIEW_SHADOW_MAP) return shadow_map_view(p, face_normal);
    if (view == DEBUG_VIEW_NAN) {
        return any(isnan(shaded)) || any(isinf(shaded)) ? vec3(1.0, 0.0, 1.0) : shaded;
    }
    return shaded;
}

#endif
