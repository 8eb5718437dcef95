#version 460
// The mean of gtao.comp's visibility over the 4×4 pixels whose jitters cover all 16
// combinations, among those at nearly the same distance from the eye (the same surface),
// so the pattern averages away without bleeding across silhouettes. A block that is all
// 1 stays exactly 1.
#include "gtao_frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1, r32f) uniform readonly image2D raw_visibility;
layout(set = 0, binding = 2, r32f) uniform writeonly image2D visibility_map;

// Neighbours further than this fraction of the pixel's own distance belong to another
// surface.
const float SAME_SURFACE = 0.05;

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, size()))) return;
    float depth = depth_at(pixel);
    if (depth >= 1.0) {
        imageStore(visibility_map, pixel, vec4(1.0));
        return;
    }
    float distance = length(world_position(vec2(pixel), depth) - push.camera.xyz);
    float sum = 0.0;
    float count = 0.0;
    for (int y = -1; y <= 2; ++y) {
        for (int x = -1; x <= 2; ++x) {
            ivec2 q = pixel + ivec2(x, y);
            if (any(lessThan(q, ivec2(0))) || any(greaterThanEqual(q, size()))) continue;
            float q_depth = depth_at(q);
            if (q_depth >= 1.0) continue;
            float q_distance = length(world_position(vec2(q), q_depth) - push.camera.xyz);
            if (abs(q_distance - distance) > SAME_SURFACE * distance) continue;
            sum += imageLoad(raw_visibility, q).r;
            count += 1.0;
        }
    }
    imageStore(visibility_map, pixel, vec4(sum / count));
}
