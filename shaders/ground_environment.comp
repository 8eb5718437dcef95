#version 460
// The ground's environment map (ground_environment.glsl): per texel, the split sum's
// diffuse and specular light of the ground's material towards the texel's direction of
// view (hemisphere_direction) on the ground, whose normal is +y and whose curvature is 0.
// Set 0 is the forward pass's (the materials), set 2 the environment's, the push constants
// the ground's draw's; the models are its pipeline's constants (src/render/ground_maps.rs).
#define GROUND_ENVIRONMENT_MAP_WRITER
#include "scene_data.glsl"
#include "shading.glsl"
#include "ground_environment.glsl"

layout(constant_id = 0) const uint DIFFUSE_MODEL = 0;
layout(constant_id = 1) const uint SPECULAR_MODEL = 0;
layout(constant_id = 2) const uint DISTRIBUTION = 0;
layout(constant_id = 3) const uint GEOMETRY = 0;
layout(constant_id = 7) const uint SUBSURFACE = 0;

layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 1, binding = 0, rgba32f) uniform writeonly image2DArray ground_environment_out;

void main() {
    uvec2 texel = gl_GlobalInvocationID.xy;
    uint size = uint(imageSize(ground_environment_out).x);
    if (any(greaterThanEqual(texel, uvec2(size)))) return;
    ShadingModels models = ShadingModels(DIFFUSE_MODEL, SPECULAR_MODEL, DISTRIBUTION, GEOMETRY, SUBSURFACE);
    Material m = materials[object.material_index];
    vec3 n = vec3(0.0, 1.0, 0.0);
    vec3 v = hemisphere_direction((vec2(texel) + 0.5) / float(size));
    float n_dot_v = max(dot(n, v), MIN_N_DOT_V);
    // As forward.frag's `reflected` tints it: a flat ground's lobe is not widened.
    m.specular_color.rgb = compensated_specular_color(models, m, n_dot_v);
    vec3 diffuse = split_sum_diffuse(models, m, n, n_dot_v, 0.0);
    vec3 specular = vec3(0.0);
    if (models.specular != SPECULAR_NONE)
        specular = split_sum_specular(models, m, m.roughness, n, v, n_dot_v, clamp_alpha(m.roughness * m.roughness));
    imageStore(ground_environment_out, ivec3(texel, 0), vec4(diffuse, 1.0));
    imageStore(ground_environment_out, ivec3(texel, 1), vec4(specular, 1.0));
}
