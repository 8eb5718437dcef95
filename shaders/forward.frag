#version 460
// Forward shading of one object: every point light through the material's BRDF, plus the
// environment's light when the scene has one. The models are specialization constants,
// so each pipeline holds only the code its materials need.
#include "scene_data.glsl"
#include "shading.glsl"
#include "environment.glsl"

layout(constant_id = 0) const uint DIFFUSE_MODEL = 0;
layout(constant_id = 1) const uint SPECULAR_MODEL = 0;
layout(constant_id = 2) const uint DISTRIBUTION = 0;
layout(constant_id = 3) const uint GEOMETRY = 0;

layout(location = 0) in vec3 in_world_position;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;

layout(location = 0) out vec4 out_radiance;

void main() {
    Material m = materials[object.material_index];
    ShadingModels models = ShadingModels(DIFFUSE_MODEL, SPECULAR_MODEL, DISTRIBUTION, GEOMETRY);
    vec3 v = normalize(frame.camera_position.xyz - in_world_position);
    vec3 n_geometric = surface_normal(in_normal, in_world_position, gl_FrontFacing);
    vec3 n = view_facing_normal(n_geometric, v);

    vec3 radiance = vec3(0.0);
    for (uint i = 0; i < frame.counts.x; ++i) {
        vec3 to_light = frame.lights[i].position.xyz - in_world_position;
        float distance2 = max(dot(to_light, to_light), MIN_LIGHT_DISTANCE2);
        vec3 l = to_light * inversesqrt(distance2);
        // Point light irradiance on a surface facing it: I / d^2.
        vec3 irradiance = frame.lights[i].intensity.rgb / distance2;
        radiance += irradiance * brdf_cos(models, m, n, n_geometric, v, l);
    }
    radiance += environment_light(models, m, n, n_geometric, v, in_uv, gl_FragCoord.xy);
    out_radiance = vec4(radiance, 1.0);
}
