#version 460
// Ground-truth ambient occlusion (Jimenez et al. 2016, "Practical Realtime Strategies for
// Accurate Indirect Occlusion") from the occlusion prepass's depth (src/render/occlusion.rs):
// per pixel, `slices` planes through the view direction, in each the highest horizon on
// either side among `steps` depth samples within `radius` (world units) of the point,
// and the cosine-weighted visible arc between them (occlusion.glsl). The normal is the
// depth's own (the plane of the nearer neighbours), so a convex object cannot occlude
// itself. The sum over slices is divided by the same sum with open horizons, so a point
// that nothing occludes has visibility 1 exactly, whatever the slice count. The slices'
// rotation and the steps' offset cycle over 4×4 pixels (16 combinations, once each),
// which gtao_denoise.comp averages.
#include "occlusion.glsl"
#include "gtao_frame.glsl"

layout(local_size_x = 8, local_size_y = 8) in;
layout(set = 0, binding = 1, r32f) uniform writeonly image2D raw_visibility;

// Occluders between this fraction of the radius and the radius fade out, so the
// visibility does not jump where one crosses it (XeGTAO's falloff).
const float FALLOFF_START = 0.6;
// A 4×4 Bayer matrix: every value 0..15 once in any 4×4 block of pixels.
const uint BAYER[16] = uint[16](0u, 8u, 2u, 10u, 12u, 4u, 14u, 6u, 3u, 11u, 1u, 9u, 15u, 7u, 13u, 5u);

// Of the two neighbours along `axis`, the offset to the one nearer in depth (the same
// surface, most likely); none if both are background.
vec3 neighbour_offset(ivec2 pixel, float depth, vec3 p, ivec2 axis, out bool found) {
    ivec2 a = pixel + axis, b = pixel - axis;
    ivec2 limit = size() - 1;
    bool a_in = all(greaterThanEqual(a, ivec2(0))) && all(lessThanEqual(a, limit)) && depth_at(a) < 1.0;
    bool b_in = all(greaterThanEqual(b, ivec2(0))) && all(lessThanEqual(b, limit)) && depth_at(b) < 1.0;
    found = a_in || b_in;
    bool use_a = a_in && (!b_in || abs(depth_at(a) - depth) <= abs(depth_at(b) - depth));
    if (use_a) return world_position(vec2(a), depth_at(a)) - p;
    return p - world_position(vec2(b), depth_at(b));
}

const int OUTSIDE = 0;
const int BACKGROUND = 1;
const int SURFACE = 2;

// The world point seen at `position` (pixel units, centres at integers) on the slice's
// line, its depth interpolated between the four nearest pixels: a plane's depth is affine
// in screen space, so a point of the tangent plane stays on the open horizon, and a convex
// surface's chords lie behind it. Next to the background there is none: what would be
// interpolated there is no surface.
int slice_sample(vec2 position, out vec3 world) {
    vec2 base = floor(position);
    if (any(lessThan(base, vec2(0.0))) || any(greaterThan(base + 1.0, vec2(size() - 1)))) return OUTSIDE;
    vec4 d = textureGather(depth_map, (base + 1.0) / vec2(size()));
    if (any(greaterThanEqual(d, vec4(1.0)))) return BACKGROUND;
    // textureGather's order: (x0, y1), (x1, y1), (x1, y0), (x0, y0).
    vec2 f = position - base;
    world = world_position(position, mix(mix(d.w, d.z, f.x), mix(d.x, d.y, f.x), f.y));
    return SURFACE;
}

void main() {
    ivec2 pixel = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(pixel, size()))) return;
    float depth = depth_at(pixel);
    if (depth >= 1.0) {
        imageStore(raw_visibility, pixel, vec4(1.0));
        return;
    }
    vec3 p = world_position(vec2(pixel), depth);
    vec3 v = normalize(push.camera.xyz - p);
    bool found_x, found_y;
    vec3 dx = neighbour_offset(pixel, depth, p, ivec2(1, 0), found_x);
    vec3 dy = neighbour_offset(pixel, depth, p, ivec2(0, 1), found_y);
    vec3 n = cross(dx, dy);
    if (!found_x || !found_y || dot(n, n) == 0.0) {
        imageStore(raw_visibility, pixel, vec4(1.0));
        return;
    }
    n = normalize(n);
    n = dot(n, v) < 0.0 ? -n : n;

    float radius = push.camera.w;
    uint slices = push.settings.x;
    uint steps = push.settings.y;
    uint k = BAYER[(pixel.y & 3) * 4 + (pixel.x & 3)];
    float slice_offset = (float(k & 3u) + 0.5) / 4.0;
    float step_offset = (float(k >> 2u) + 0.5) / 4.0;
    float visible = 0.0;
    float open = 0.0;
    for (uint s = 0u; s < slices; ++s) {
        float phi = PI * (float(s) + slice_offset) / float(slices);
        vec2 direction = vec2(cos(phi), sin(phi));
        // A pixel's step along the slice in the plane of constant depth: the slice's
        // tangent, and the world length of one pixel there.
        vec3 step_world = world_position(vec2(pixel) + direction, depth) - p;
        float pixels = radius / length(step_world);
        vec3 tangent = normalize(step_world - v * dot(step_world, v));
        vec3 axis = normalize(cross(tangent, v));
        vec3 projected = n - axis * dot(n, axis);
        float projected_length = length(projected);
        if (projected_length == 0.0) continue;
        float cos_gamma = clamp(dot(projected, v) / projected_length, -1.0, 1.0);
        float gamma = sign(dot(tangent, projected)) * acos(cos_gamma);
        // The lowest horizons: the tangent plane on each side.
        float horizon_cos[2] = float[2](cos(gamma + HALF_PI), cos(gamma - HALF_PI));
        for (int side = 0; side < 2; ++side) {
            float low = horizon_cos[side];
            float sign_side = side == 0 ? 1.0 : -1.0;
            for (uint j = 0u; j < steps; ++j) {
                float t = max(pixels * (float(j) + step_offset) / float(steps), 1.0);
                vec3 q;
                int seen = slice_sample(vec2(pixel) + sign_side * direction * t, q);
                if (seen == OUTSIDE) break;
                if (seen == BACKGROUND) continue;
                vec3 w = q - p;
                float distance = length(w);
                if (distance == 0.0) continue;
                float weight = clamp((radius - distance) / ((1.0 - FALLOFF_START) * radius), 0.0, 1.0);
                float c = mix(low, dot(w, v) / distance, weight);
                horizon_cos[side] = max(horizon_cos[side], c);
            }
        }
        // Side 0 runs along +tangent (angles > 0), side 1 along −tangent.
        float h1 = gamma + min(acos(clamp(horizon_cos[0], -1.0, 1.0)) - gamma, HALF_PI);
        float h0 = gamma + max(-acos(clamp(horizon_cos[1], -1.0, 1.0)) - gamma, -HALF_PI);
        visible += projected_length * gtao_slice_visibility(h0, h1, gamma);
        open += projected_length * gtao_slice_visibility(gamma - HALF_PI, gamma + HALF_PI, gamma);
    }
    imageStore(raw_visibility, pixel, vec4(open > 0.0 ? clamp(visible / open, 0.0, 1.0) : 1.0));
}
