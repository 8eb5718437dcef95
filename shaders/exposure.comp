#version 460
// The histogram of the HDR frame's luminance over the pixels objects cover, for the
// viewer's auto exposure (src/render/exposure.rs, which picks a percentile from it): bins
// of log2 Y, BINS_PER_STOP a stop from LOG2_MIN, the ends open. Each workgroup counts in
// shared memory, then adds its counts to the buffer.
#extension GL_EXT_samplerless_texture_functions : require

layout(local_size_x = 16, local_size_y = 16) in;
layout(constant_id = 0) const uint BINS = 64;
layout(set = 0, binding = 0) uniform texture2D hdr_frame;
layout(set = 0, binding = 1, std430) buffer Histogram {
    uint bins[];
} histogram;
layout(push_constant) uniform Push {
    float log2_min;
    float bins_per_stop;
} push;

shared uint local_bins[BINS];

// Linear Rec. 709 luminance (twin: brdf::tonemap::luminance).
float luminance(vec3 c) {
    return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
}

// The bin of luminance y > 0: ⌊(log2 y − log2_min) · bins_per_stop⌋ within the bins
// (twin: exposure::luminance_bin).
uint luminance_bin(float y) {
    return uint(clamp(floor((log2(y) - push.log2_min) * push.bins_per_stop), 0.0, float(BINS - 1u)));
}

void main() {
    const uint threads = gl_WorkGroupSize.x * gl_WorkGroupSize.y;
    for (uint b = gl_LocalInvocationIndex; b < BINS; b += threads) local_bins[b] = 0u;
    barrier();
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (all(lessThan(p, textureSize(hdr_frame, 0)))) {
        vec4 c = texelFetch(hdr_frame, p, 0);
        float y = luminance(c.rgb);
        // Covered (alpha 1; the background and the sky have 0), lit, finite (NaN fails y > 0).
        if (c.a > 0.5 && y > 0.0 && !isinf(y)) atomicAdd(local_bins[luminance_bin(y)], 1u);
    }
    barrier();
    for (uint b = gl_LocalInvocationIndex; b < BINS; b += threads) {
        if (local_bins[b] != 0u) atomicAdd(histogram.bins[b], local_bins[b]);
    }
}
