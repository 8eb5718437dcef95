#version 460
// The BRDF tables (see env_tables.glsl): for n·v = lut_n_dot_v(x) and roughness = y, x
// and y being each texel's lut_parameter, ∫ f_s cos split as F0 A + B by evaluating the
// specular lobe at F0 = 1 and F0 = 0 (Schlick's F is linear in F0), with the angle of each
// part's mean direction ∫ l f_s cos, by GGX normal sampling; and the Oren-Nayar
// directional albedo by cosine sampling. The very lobes the forward pass shades with.
// shading.glsl's surface_normal falls back on derivatives, which compute shaders only
// have with this extension; it is not called here, so no derivative reaches the SPIR-V.
#extension GL_NV_compute_shader_derivatives : enable
#include "env_math.glsl"
#include "env_tables.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 0, rgba16f) uniform writeonly image2DArray table;
layout(push_constant) uniform LutPush {
    uint samples;
} lut;

// The angle from n of a mean direction given as (towards the mirror direction, along n); 0
// for none (the Oren-Nayar layer), where atan is undefined.
float mean_angle(vec2 mean) {
    return mean == vec2(0.0) ? 0.0 : atan(mean.x, mean.y);
}

void main() {
    ivec3 texel = ivec3(gl_GlobalInvocationID);
    ivec2 size = imageSize(table).xy;
    if (any(greaterThanEqual(texel.xy, size))) return;
    uvec2 t = uvec2(texel.xy);
    vec2 xy = vec2(lut_parameter(t.x, uint(size.x)), lut_parameter(t.y, uint(size.y)));
    float n_dot_v = lut_n_dot_v(xy.x);
    const vec3 n = vec3(0.0, 0.0, 1.0);
    vec3 v = vec3(sqrt(1.0 - n_dot_v * n_dot_v), 0.0, n_dot_v);
    // A white material: roughness and σ are the table's y; F0 is set per evaluation.
    Material m;
    m.base_color = vec4(1.0);
    m.specular_color = vec4(1.0);
    m.wrap_color = vec4(0.0);
    m.roughness = xy.y;
    m.diffuse_roughness = xy.y;
    m.metallic = 0.0;
    uint layer = uint(texel.z);
    vec2 sum = vec2(0.0);
    // Each part's ∫ l f_s cos in the plane of incidence, as (towards the mirror direction, n).
    vec2 mean_a = vec2(0.0);
    vec2 mean_b = vec2(0.0);
    if (layer == LUT_LAYER_OREN_NAYAR) {
        for (uint i = 0u; i < lut.samples; ++i) {
            vec3 l = sample_cosine(hammersley(i, lut.samples));
            // f cos / (cos/π)
            sum.x += PI * diffuse_lobe(DIFFUSE_OREN_NAYAR, m, n, v, l, n_dot_v, l.z).r;
        }
    } else {
        ShadingModels models = lut_layer_models(layer);
        float alpha = clamp_alpha(xy.y * xy.y);
        // Torrance-Sparrow's V-cavity masking bounds the weights of normals drawn by
        // D(h)(n·h) (those visible from n), not of those visible from a grazing v.
        bool by_d = layer == LUT_LAYER_TORRANCE_SPARROW;
        for (uint i = 0u; i < lut.samples; ++i) {
            vec3 h = sample_ggx_vndf(by_d ? n : v, alpha, hammersley(i, lut.samples));
            vec3 l = reflect(-v, h);
            if (l.z <= 0.0) continue;
            float pdf = by_d ? pdf_ggx_vndf(alpha, 1.0, h.z, dot(h.xy, h.xy)) * h.z / dot(v, h)
                             : pdf_ggx_vndf(alpha, n_dot_v, h.z, dot(h.xy, h.xy));
            m.f0 = 0.0;
            float b = specular_lobe(models, m, n, v, l, n_dot_v, l.z).r;
            m.f0 = 1.0;
            float a_plus_b = specular_lobe(models, m, n, v, l, n_dot_v, l.z).r;
            vec2 weights = vec2(a_plus_b - b, b) * (l.z / pdf);
            sum += weights;
            mean_a += weights.x * vec2(-l.x, l.z);
            mean_b += weights.y * vec2(-l.x, l.z);
        }
    }
    imageStore(table, texel, vec4(sum / float(lut.samples), mean_angle(mean_a), mean_angle(mean_b)));
}
