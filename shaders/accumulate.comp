#version 460
// The running mean of a still view's frames, in linear HDR before the display transform:
// mean_k = mean_{k-1} + (frame_k − mean_{k-1}) / (k + 1) (Welford 1962; twin: running_mean
// in src/render/accumulate.rs). The mean is written back over the frame too, so the tone
// map and every read-back show it.

layout(local_size_x = 8, local_size_y = 8) in;
// This frame's radiance in, the mean of it and the frames before out.
layout(set = 0, binding = 0, rgba32f) uniform image2D frame;
// The mean of the frames before this one (ignored for the first), then with this one.
layout(set = 0, binding = 1, rgba32f) uniform image2D mean;
layout(push_constant) uniform Push {
    uint frames_before;  // or HOLD
} push;
// The mean is full (src/render/accumulate.rs): the frame shows it without joining it.
const uint HOLD = 0xFFFFFFFFu;

vec4 running_mean(vec4 mean_before, vec4 value, uint frames_before) {
    return mean_before + (value - mean_before) / float(frames_before + 1u);
}

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(frame)))) return;
    if (push.frames_before == HOLD) {
        imageStore(frame, p, imageLoad(mean, p));
        return;
    }
    vec4 value = imageLoad(frame, p);
    vec4 result = push.frames_before == 0u ? value : running_mean(imageLoad(mean, p), value, push.frames_before);
    imageStore(mean, p, result);
    imageStore(frame, p, result);
}
