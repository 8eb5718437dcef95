#version 460
// Forward shading of one object: every point light through the material's BRDF, plus the
// environment's light when the scene has one, occluded by the ambient visibility, plus
// the material's emission. The
// models, maps, debug view, environment kind, reflection mode and occlusion are
// specialization constants (src/render/forward.rs), so each
// pipeline holds only the code its frame needs.
// DEBUG_VIEWS 0 (build.rs's forward_shaded.frag) leaves the debug views out of the module:
// a quarter of its SPIR-V, which the creation of every shaded image's pipeline would read.
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

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;
layout(location = 4) in float in_curvature;
layout(location = 5) in vec2 in_map_uv[MAP_COUNT];
layout(location = 5 + MAP_COUNT) in vec3 in_objects_take;
layout(location = 6 + MAP_COUNT) in vec3 in_bounce;
layout(location = 7 + MAP_COUNT) in mat3 in_bounce_gradient;

layout(location = 0) out vec4 out_radiance;

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

void main() {
    Material m = materials[object.material_index];
    ShadingModels models = ShadingModels(DIFFUSE_MODEL, SPECULAR_MODEL, DISTRIBUTION, GEOMETRY, SUBSURFACE);
    vec3 v = normalize(frame.camera_position.xyz - in_world_position);
    m.base_color.rgb = mapped_base_color(m, in_map_uv[MAP_BASE_COLOR]);
    m = mapped_properties(m, in_map_uv);
    vec3 n_geometric = surface_normal(in_normal, in_world_position, gl_FrontFacing);
    // The tangent frame follows the normal to the viewer's side.
    vec4 tangent = gl_FrontFacing ? in_tangent : vec4(in_tangent.xyz, -in_tangent.w);
    vec3 n_mapped = mapped_normal(m, n_geometric, tangent, in_map_uv[MAP_NORMAL], in_map_uv[MAP_DETAIL]);
    bool seed_horizon = HORIZON == HORIZON_SEED;
    vec3 n = seed_horizon ? n_mapped : view_facing_normal(n_mapped, v);
    m.specular_color.rgb = compensated_specular_color(models, m, max(dot(n, v), MIN_N_DOT_V));
    // Specular anti-aliasing widens the lobes that gather light over the pixel's normals;
    // the microsurface itself, whose albedo the split sum's table holds, keeps its own.
    float microsurface_roughness = m.roughness;
    if (SPECULAR_AA) {
        vec3 dx = dFdx(n_mapped);
        vec3 dy = dFdy(n_mapped);
        m.roughness = specular_aa_roughness(m.roughness, dot(dx, dx) + dot(dy, dy));
    }

    float visibility = ambient_visibility(gl_FragCoord.xy);
    vec4 occlusion = environment_occlusion(visibility, m.base_color.rgb);
    if (OBJECT_OCCLUSION) {
        uint from = OBJECTS_OCCLUSION_FROM;
        occlusion.rgb *= from == OBJECTS_OCCLUSION_FROM_GROUND_MAP ? ground_map_occlusion(in_world_position)
                         : from == OBJECTS_OCCLUSION_FROM_VERTICES
                             ? 1.0 - in_objects_take
                             : object_occlusion(in_world_position, n, own_occluders());
    }
    // The occlusion map's baked visibility multiplies the environment's light, occluded by
    // the screen-space visibility already, as glTF 2.0 applies it; the point lights it
    // micro-shadows (lights.glsl) where the material asks.
    float map_visibility = mapped_occlusion(m, in_map_uv[MAP_OCCLUSION]);
    float light_visibility = m.micro_shadowing != 0.0 ? map_visibility : 1.0;
    vec3 environment = environment_light(models, m, microsurface_roughness, n, n_geometric, v, in_curvature,
                                         mapped_noise(m, in_map_uv[MAP_NOISE]), gl_FragCoord.xy, frame.counts.z,
                                         occlusion)
                       * map_visibility;
    vec3 radiance = point_lights_radiance(models, m, n, n_geometric, v, in_world_position, in_curvature,
                                          seed_horizon, light_visibility) + environment;
    // The bounced light, gathered by a Lambertian lobe.
    vec3 bounced = vec3(0.0);
    if (BOUNCE && models.diffuse != DIFFUSE_NONE) {
        vec3 irradiance = BOUNCE_AT_VERTICES ? bounce_at_pixel(in_bounce, in_bounce_gradient, n, n_geometric)
                                             : ground_bounce_irradiance(in_world_position, n);
        bounced = m.base_color.rgb / PI * irradiance;
    }
    radiance += bounced;
    // The surface's own light, which no light, occlusion or shadow changes.
    out_radiance = vec4(radiance + mapped_emission(m, in_map_uv[MAP_EMISSION]), 1.0);
#if DEBUG_VIEWS
    uint debug_view = DEBUG_VIEW == FROM_UNIFORM ? frame.counts.y : DEBUG_VIEW;
    if (debug_view != DEBUG_VIEW_SHADED) {
        out_radiance.rgb = debug_view_radiance(debug_view, models, m, n, n_geometric, v, in_world_position,
                                               in_normal, in_uv, in_tangent, environment, bounced, radiance,
                                               in_curvature, visibility, light_visibility);
    }
#endif
}
