#version 460
// Forward shading of one object: every point light through the material's BRDF, plus the
// environment's light when the scene has one, occluded by the ambient visibility, plus
// the material's emission. The
// models, maps, debug view, environment kind, reflection mode and occlusion are
// specialization constants (src/render/forward.rs), so each
// pipeline holds only the code its frame needs.
// DEBUG_VIEWS 0 (build.rs's forward_shaded.frag) leaves the debug views out of the module:
// a quarter of its SPIR-V, which the creation of every shaded image's pipeline would read.
// GBUFFER (forward_gbuffer.frag) writes a solid's surface into the G-buffer instead of its
// light; DEFERRED (forward_deferred.frag) reads it at each pixel once and shades it: the
// deferred pass (src/render/deferred.rs), where lavapipe would otherwise shade a pixel once
// for every small triangle that touches its block.
#ifndef DEBUG_VIEWS
#define DEBUG_VIEWS 1
#endif
#include "scene_data.glsl"
#include "shading.glsl"
#include "material_maps.glsl"
#include "lights.glsl"
#include "environment.glsl"
#if DEBUG_VIEWS
#include "debug_views.glsl"
#endif
#include "specular_aa.glsl"
#include "occlusion_map.glsl"
#include "bounce.glsl"
#include "object_occlusion.glsl"
#include "ground_occlusion.glsl"
#include "ground_environment.glsl"
#include "deferred.glsl"

layout(constant_id = 0) const uint DIFFUSE_MODEL = 0;
layout(constant_id = 1) const uint SPECULAR_MODEL = 0;
layout(constant_id = 2) const uint DISTRIBUTION = 0;
layout(constant_id = 3) const uint GEOMETRY = 0;
// Horizon of the shading normal: 0 smooth (brdf_cos), 1 the report's cutoff (brdf_cos_seed).
layout(constant_id = 6) const uint HORIZON = 0;
const uint HORIZON_SEED = 1u;
layout(constant_id = 7) const uint SUBSURFACE = 0;
// The debug view (debug_views.glsl), or FROM_UNIFORM for FrameData.counts.y.
layout(constant_id = 8) const uint DEBUG_VIEW = FROM_UNIFORM;
// Whether the lobes' roughness is widened by the shading normal's change across the pixel
// (specular_aa.glsl): the scene's [antialiasing] specular.
layout(constant_id = 11) const bool SPECULAR_AA = false;

#ifndef DEFERRED
layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;
layout(location = 4) in float in_curvature;
layout(location = 5) in vec2 in_map_uv[MAP_COUNT];
layout(location = 5 + MAP_COUNT) in vec3 in_objects_take;
layout(location = 6 + MAP_COUNT) in vec3 in_bounce;
layout(location = 7 + MAP_COUNT) in mat3 in_bounce_gradient;
#endif

// What the light at a surface point is found from: the material as its maps make it there,
// the point, its normals and what its vertices hold.
struct Surface {
    Material m;
    // The roughness of the microsurface, before specular anti-aliasing widens m's.
    float microsurface_roughness;
    vec3 position;
    // The mapped normal, and the surface's on the viewer's side.
    vec3 n_mapped;
    vec3 n_geometric;
    // cross(dFdx(p), dFdy(p)): the triangle's plane, for the shadow maps.
    vec3 face_normal;
    float curvature;
    // What the other objects take of the environment's light, from the vertices.
    vec3 objects_take;
    // The occlusion map's visibility, and the noise map's value.
    float map_visibility;
    float noise;
    vec3 bounced;
    vec3 emission;
};

// The models of this pipeline's material.
ShadingModels shading_models() {
    return ShadingModels(DIFFUSE_MODEL, SPECULAR_MODEL, DISTRIBUTION, GEOMETRY, SUBSURFACE);
}

// The normal the light is found with: the mapped one, turned towards the viewer unless the
// report's horizon is asked for.
vec3 shading_normal(vec3 n_mapped, vec3 v) {
    return HORIZON == HORIZON_SEED ? n_mapped : view_facing_normal(n_mapped, v);
}

#ifndef DEFERRED
// The unit interpolated normal on the viewer's side of the surface; a zero interpolated
// normal (degenerate mesh data) falls back to the triangle's geometric normal.
vec3 surface_normal(vec3 interpolated, vec3 world_position, bool front_facing) {
    float len2 = dot(interpolated, interpolated);
    if (len2 > MIN_NORMAL_LENGTH2) {
        vec3 n = interpolated * inversesqrt(len2);
        return front_facing ? n : -n;
    }
    // With the y-flipped projection, dFdx × dFdy points away from the viewer.
    vec3 g = -cross(dFdx(world_position), dFdy(world_position));
    float g2 = dot(g, g);
    return g2 > 0.0 ? g * inversesqrt(g2) : vec3(0.0, 0.0, 1.0);
}

// The pixel's surface from the draw's vertices and the material's maps.
Surface surface() {
    Surface s;
    Material m = materials[object.material_index];
    vec3 v = normalize(frame.camera_position.xyz - in_world_position);
    m.base_color.rgb = mapped_base_color(m, in_map_uv[MAP_BASE_COLOR]);
    m = mapped_properties(m, in_map_uv);
    s.n_geometric = surface_normal(in_normal, in_world_position, gl_FrontFacing);
    // The tangent frame follows the normal to the viewer's side.
    vec4 tangent = gl_FrontFacing ? in_tangent : vec4(in_tangent.xyz, -in_tangent.w);
    s.n_mapped = mapped_normal(m, s.n_geometric, tangent, in_map_uv[MAP_NORMAL], in_map_uv[MAP_DETAIL]);
    // Specular anti-aliasing widens the lobes that gather light over the pixel's normals;
    // the microsurface itself, whose albedo the split sum's table holds, keeps its own.
    s.microsurface_roughness = m.roughness;
    if (SPECULAR_AA) {
        vec3 dx = dFdx(s.n_mapped);
        vec3 dy = dFdy(s.n_mapped);
        m.roughness = specular_aa_roughness(m.roughness, dot(dx, dx) + dot(dy, dy));
    }
    s.m = m;
    s.position = in_world_position;
    s.face_normal = cross(dFdx(in_world_position), dFdy(in_world_position));
    s.curvature = in_curvature;
    s.objects_take = in_objects_take;
    s.map_visibility = mapped_occlusion(m, in_map_uv[MAP_OCCLUSION]);
    s.noise = mapped_noise(m, in_map_uv[MAP_NOISE]);
    // The bounced light, gathered by a Lambertian lobe.
    s.bounced = vec3(0.0);
    if (BOUNCE && DIFFUSE_MODEL != DIFFUSE_NONE) {
        vec3 n = shading_normal(s.n_mapped, v);
        vec3 irradiance = BOUNCE_AT_VERTICES ? bounce_at_pixel(in_bounce, in_bounce_gradient, n, s.n_geometric)
                                             : ground_bounce_irradiance(in_world_position, n);
        s.bounced = m.base_color.rgb / PI * irradiance;
    }
    // The surface's own light, which no light, occlusion or shadow changes.
    s.emission = mapped_emission(m, in_map_uv[MAP_EMISSION]);
    return s;
}
#endif

// The light the surface sends the viewer but its own, and (for the debug views) its parts;
// s.m takes the specular tint the material's compensation gives it.
vec3 reflected(inout Surface s, out vec3 environment, out float visibility, out float light_visibility, out vec3 n) {
    ShadingModels models = shading_models();
    Material m = s.m;
    vec3 v = normalize(frame.camera_position.xyz - s.position);
    n = shading_normal(s.n_mapped, v);
    // The table's tint follows the microsurface, before specular anti-aliasing.
    float roughness = m.roughness;
    m.roughness = s.microsurface_roughness;
    m.specular_color.rgb = compensated_specular_color(models, m, max(dot(n, v), MIN_N_DOT_V));
    m.roughness = roughness;
    s.m = m;

    visibility = ambient_visibility(gl_FragCoord.xy);
    vec4 occlusion = environment_occlusion(visibility, m.base_color.rgb);
    if (OBJECT_OCCLUSION) {
        uint from = OBJECTS_OCCLUSION_FROM;
        occlusion.rgb *= from == OBJECTS_OCCLUSION_FROM_GROUND_MAP ? ground_map_occlusion(s.position)
                         : from == OBJECTS_OCCLUSION_FROM_VERTICES
                             ? 1.0 - s.objects_take
                             : object_occlusion(s.position, n, own_occluders());
    }
    // The occlusion map's baked visibility multiplies the environment's light, occluded by
    // the screen-space visibility already, as glTF 2.0 applies it; the point lights it
    // micro-shadows (lights.glsl) where the material asks.
    light_visibility = m.micro_shadowing != 0.0 ? s.map_visibility : 1.0;
    environment = GROUND_ENVIRONMENT ? ground_environment_light(m, v, occlusion)
                                     : environment_light(models, m, s.microsurface_roughness, n, s.n_geometric, v,
                                                         s.curvature, s.noise, gl_FragCoord.xy, frame.counts.z,
                                                         occlusion);
    environment *= s.map_visibility;
    vec3 radiance = point_lights_radiance(models, m, n, s.n_geometric, v, s.position, s.face_normal, s.curvature,
                                          HORIZON == HORIZON_SEED, light_visibility) + environment;
    return radiance + s.bounced;
}

#ifdef GBUFFER
// The G-buffer (src/render/deferred.rs, G_ATTACHMENTS of them): the surface at each pixel in
// full fp32, so that the deferred pass shades what the forward pass would (the surface's
// own light is added to the bounce's before, rather than after), and which object it is.
layout(location = 0) out vec4 out_g[7];
// The object's number (forward.rs's deferred_object), the draw's instance.
layout(location = 10 + MAP_COUNT + MAX_VERTEX_SHADOW_LAYERS) flat in uint in_deferred_object;

void main() {
    Surface s = surface();
    out_g[0] = vec4(s.position, s.curvature);
    out_g[1] = vec4(s.n_mapped, s.m.roughness);
    out_g[2] = vec4(s.n_geometric, s.microsurface_roughness);
    out_g[3] = vec4(s.m.base_color.rgb, s.m.metallic);
    out_g[4] = vec4(s.face_normal, s.map_visibility);
    out_g[5] = vec4(s.bounced + s.emission, s.noise);
    out_g[6] = vec4(s.objects_take, deferred_object_depth(in_deferred_object));
}
#elif defined(DEFERRED)
layout(set = 6, binding = 0) uniform sampler2D g0;
layout(set = 6, binding = 1) uniform sampler2D g1;
layout(set = 6, binding = 2) uniform sampler2D g2;
layout(set = 6, binding = 3) uniform sampler2D g3;
layout(set = 6, binding = 4) uniform sampler2D g4;
layout(set = 6, binding = 5) uniform sampler2D g5;
layout(set = 6, binding = 6) uniform sampler2D g6;
layout(location = 0) flat in uint in_deferred_object;
layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec4 g[7] = vec4[](texelFetch(g0, pixel, 0), texelFetch(g1, pixel, 0), texelFetch(g2, pixel, 0),
                       texelFetch(g3, pixel, 0), texelFetch(g4, pixel, 0), texelFetch(g5, pixel, 0),
                       texelFetch(g6, pixel, 0));
    // Lavapipe shades the pixels beside the solid's in the same batch and discards them.
    // Where no surface of this solid was written, what they read is undefined (deferred.rs
    // clears none), and it moved the last bits of the solid's own pixels from one frame to
    // the next (tests/emission.rs): they read none.
    if (g[6].w != deferred_object_depth(in_deferred_object)) {
        for (int i = 0; i < 7; ++i) g[i] = vec4(0.0);
    }
    Surface s;
    s.m = materials[object.material_index];
    s.position = g[0].xyz;
    s.curvature = g[0].w;
    s.n_mapped = g[1].xyz;
    s.m.roughness = g[1].w;
    s.n_geometric = g[2].xyz;
    s.microsurface_roughness = g[2].w;
    s.m.base_color.rgb = g[3].rgb;
    s.m.metallic = g[3].a;
    s.face_normal = g[4].xyz;
    s.map_visibility = g[4].w;
    // The bounce with the surface's own light already added.
    s.bounced = g[5].rgb;
    s.emission = vec3(0.0);
    s.noise = g[5].w;
    s.objects_take = g[6].rgb;
    vec3 environment, n;
    float visibility, light_visibility;
    out_radiance = vec4(reflected(s, environment, visibility, light_visibility, n) + s.emission, 1.0);
}
#else
layout(location = 0) out vec4 out_radiance;

void main() {
    Surface s = surface();
    vec3 environment, n;
    float visibility, light_visibility;
    vec3 radiance = reflected(s, environment, visibility, light_visibility, n);
    out_radiance = vec4(radiance + s.emission, 1.0);
#if DEBUG_VIEWS
    uint debug_view = DEBUG_VIEW == FROM_UNIFORM ? frame.counts.y : DEBUG_VIEW;
    if (debug_view != DEBUG_VIEW_SHADED) {
        out_radiance.rgb = debug_view_radiance(debug_view, shading_models(), s.m, n, s.n_geometric,
                                               normalize(frame.camera_position.xyz - in_world_position),
                                               in_world_position, in_normal, in_uv, in_tangent, environment,
                                               s.bounced, radiance, in_curvature, visibility,
                                               light_visibility);
    }
#endif
}
#endif
