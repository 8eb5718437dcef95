// What the occlusion pass's compute shaders share (src/render/occlusion.rs): the
// prepass's depth, the push constants, and the world position of a pixel.
#ifndef ARGIL_GTAO_FRAME_GLSL
#define ARGIL_GTAO_FRAME_GLSL

layout(set = 0, binding = 0) uniform sampler2D depth_map;

// Mirrored by GtaoPush in src/render/occlusion.rs.
layout(push_constant) uniform GtaoPush {
    mat4 world_from_clip;
    vec4 camera;       // xyz: the eye; w: radius in world units
    uvec4 settings;    // x: slices, y: steps per side
} push;

const float PI = 3.14159265358979;
const float HALF_PI = 1.57079632679490;

ivec2 size() {
    return textureSize(depth_map, 0);
}

float depth_at(ivec2 pixel) {
    return texelFetch(depth_map, pixel, 0).r;
}

// The world position of pixel `pixel` (centre) at depth `depth`.
vec3 world_position(vec2 pixel, float depth) {
    vec2 ndc = (pixel + 0.5) / vec2(size()) * 2.0 - 1.0;
    vec4 world = push.world_from_clip * vec4(ndc, depth, 1.0);
    return world.xyz / world.w;
}

#endif
