#version 460
// One level of the specular prefiltered cube (Karis 2013): radiance around each texel's
// direction R weighted by the GGX lobe of the level's roughness with n = v = R, by GGX
// importance sampling with n·l weights, each sample read from the source mip matching
// its pdf (filtered importance sampling) but never finer than min_lod.
#include "env_math.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0) uniform samplerCube source;
layout(set = 0, binding = 1, rgba16f) uniform writeonly image2DArray target;
layout(push_constant) uniform PrefilterPush {
    float roughness;
    float source_texel_solid_angle;
    float min_lod;
    uint samples;
} level;

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    ivec2 size = imageSize(target).xy;
    if (any(greaterThanEqual(texel.xy, size))) return;
    vec2 ab = (vec2(texel.xy) + 0.5) / vec2(size) * 2.0 - 1.0;
    mat3 frame = tangent_frame(cube_direction(uint(texel.z), ab));
    float alpha = clamp_alpha(level.roughness * level.roughness);
    const vec3 v = vec3(0.0, 0.0, 1.0);
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint i = 0u; i < level.samples; ++i) {
        vec3 h = sample_ggx_vndf(v, alpha, hammersley(i, level.samples));
        vec3 l = reflect(-v, h);
        if (l.z <= 0.0) continue;
        float n_pdf = float(level.samples) * pdf_ggx_vndf(alpha, 1.0, h.z, dot(h.xy, h.xy));
        float lod = max(filtered_lod(n_pdf, level.source_texel_solid_angle), level.min_lod);
        sum += textureLod(source, frame * l, lod).rgb * l.z;
        weight += l.z;
    }
    imageStore(target, texel, vec4(sum / max(weight, 1e-30), 1.0));
}
