#version 460
// The resolve of the multisampled HDR frame into the single-sampled one: radiance as the
// mean of the samples weighted by resolve_weight (msaa_resolve.glsl), alpha (coverage)
// as their plain mean.
#extension GL_EXT_samplerless_texture_functions : require
#include "msaa_resolve.glsl"

layout(constant_id = 0) const int SAMPLES = 4;

layout(set = 0, binding = 0) uniform texture2DMS multisampled;

layout(location = 0) out vec4 out_radiance;

void main() {
    ivec2 pixel = ivec2(gl_FragCoord.xy);
    vec3 weighted = vec3(0.0);
    float weights = 0.0;
    float coverage = 0.0;
    for (int i = 0; i < SAMPLES; ++i) {
        vec4 s = texelFetch(multisampled, pixel, i);
        float w = resolve_weight(s.rgb);
        weighted += s.rgb * w;
        weights += w;
        coverage += s.a;
    }
    out_radiance = vec4(weighted / weights, coverage / float(SAMPLES));
}
