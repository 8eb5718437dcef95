// Shadows of the point lights: a cube depth map per shadowed light, rendered by
// src/render/shadow.rs (shaders/shadow.vert), its six faces layers of one 2D array.
// Soft by the light's radius with PCSS (Fernando 2005); the receiver's plane comes from
// the fragment shader's derivatives (point_light_shadow's `face_normal`). The f64 twins
// are in src/brdf/shadow.rs.
#ifndef ARGIL_SHADOWS_GLSL
#define ARGIL_SHADOWS_GLSL
#extension GL_EXT_control_flow_attributes : require
#include "scene_data.glsl"
#include "env_math.glsl"
#include "sampling.glsl"

struct ShadowLight {
    // x: the layer of its face +x (faces +x, −x, +y, −y, +z, −z follow), < 0 without a
    // map; y: the light's radius; z, w: the near and far planes of its faces.
    vec4 map;
};

layout(set = 3, binding = 0, std140) uniform ShadowData {
    uvec4 settings;  // x: texels on a side of a face
    ShadowLight lights[MAX_POINT_LIGHTS];
    // The ground's rectangle that objects can shadow (ground_shadow.glsl): its centre's x
    // and z in xy, half its extent in zw; all 0 where nothing can.
    vec4 ground;
} shadow_data;
layout(set = 3, binding = 1) uniform sampler2DArray shadow_maps;

// Every comparison is exact in principle: a texel stores the depth of the surface along
// the ray through its centre, and it is compared with where that same ray meets the
// receiver's own plane (receiver_plane_depth), so a lit plane compares equal to itself at
// any slope, and no normal offset is needed. What the bias covers is rounding, relative
// to the distance: the stored depth's, 2⁻²⁴ · far/near = 6e-5 with far/near = 1000
// (src/render/shadow.rs), ×8; and the receiver's normal from derivatives, whose fp32
// error (≤ 1e-5) the plane's depth amplifies by 1/cos of the ray's angle to it
// (the slope-scaled term), ×10. At 7 m the constant term is 3.5 mm, far below a texel.
const float SHADOW_DEPTH_BIAS = 5e-4;
const float SHADOW_SLOPE_BIAS = 1e-4;
// Taps of the blocker search and of the filter when the light has a radius ([shadows]
// taps): a constant, so that the compiler folds the taps' radii (src/render/forward.rs).
layout(constant_id = 18) const uint SHADOW_TAPS = 16u;
// Whether a light that may shadow the draw's object has a radius (src/render/forward.rs).
// Off, the pipeline holds the hard shadow's one tap alone: lavapipe would set up the
// search and filter at every pixel (the disk's frame, its turn, the loops) for none.
layout(constant_id = 22) const bool SOFT_SHADOWS = true;

// The face that direction d falls in and (a, b) on it: the inverse of cube_direction.
uint cube_face(vec3 d, out vec2 ab) {
    vec3 m = abs(d);
    if (m.x >= m.y && m.x >= m.z) {
        ab = (d.x > 0.0 ? vec2(-d.z, -d.y) : vec2(d.z, -d.y)) / m.x;
        return d.x > 0.0 ? 0u : 1u;
    }
    if (m.y >= m.z) {
        ab = (d.y > 0.0 ? vec2(d.x, d.z) : vec2(d.x, -d.z)) / m.y;
        return d.y > 0.0 ? 2u : 3u;
    }
    ab = (d.z > 0.0 ? vec2(d.x, -d.y) : vec2(-d.x, -d.y)) / m.z;
    return d.z > 0.0 ? 4u : 5u;
}

// The major-axis distance of a stored depth: n f / (f − d (f − n)).
float shadow_linear_depth(float depth, float near, float far) {
    return near * far / (far - depth * (far - near));
}

// Where the ray along c (major component 1) meets the receiver's plane through q with
// normal n, as a major-axis distance, c·n given, and no further than `receiver`, the
// ray's point as far from the light as the receiver: what lies beyond cannot stand
// between them (a ray past the plane's horizon, or grazing it, passes the receiver there).
float receiver_plane_depth(float c_dot_n, float q_dot_n, float receiver) {
    float depth = q_dot_n / c_dot_n;
    return depth > 0.0 && depth < receiver ? depth : receiver;
}

// PCSS's penumbra, r (d − d_b)/d_b on the receiver, as an angle from the light (÷ d).
float penumbra_angle(float radius, float receiver, float blocker) {
    return radius * max(receiver - blocker, 0.0) / (blocker * receiver);
}

// What one light's comparisons share.
struct ShadowReceiver {
    int layer;
    float near;
    float far;
    vec3 n;        // the receiver's plane normal
    float q_dot_n;  // q the receiver relative to the light
    float distance; // |q|
};

// Whether the surface that texel `texel` of face `face` stores at depth `depth` lies in
// front of the receiver's plane along that texel's ray, and its distance from the light:
// the bilinear filter, which asks only whether, leaves that division for the compiler to
// drop.
bool shadow_depth_blocks(ShadowReceiver r, uint face, ivec2 texel, float depth, out float distance) {
    float size = float(shadow_data.settings.x);
    vec2 ab = (vec2(texel) + 0.5) / size * 2.0 - 1.0;
    // The texel's ray, at major-axis distance 1: the depth its face stores is along it.
    vec3 c = cube_face_point(face, ab);
    float inv_length = inversesqrt(dot(c, c));
    float c_dot_n = dot(c, r.n);
    float plane = receiver_plane_depth(c_dot_n, r.q_dot_n, r.distance * inv_length);
    float stored = shadow_linear_depth(depth, r.near, r.far);
    float cos_to_plane = abs(c_dot_n) * inv_length;
    float bias = SHADOW_DEPTH_BIAS + SHADOW_SLOPE_BIAS / max(cos_to_plane, 1e-4);
    distance = stored / inv_length;
    return stored * (1.0 + bias) < plane;
}

// The distance from the light of what texel `texel` stores at `depth` where it blocks the
// receiver (shadow_depth_blocks), 0 where nothing does.
float shadow_depth_blocker(ShadowReceiver r, uint face, ivec2 texel, float depth) {
    float distance;
    return shadow_depth_blocks(r, face, texel, depth, distance) ? distance : 0.0;
}

// shadow_depth_blocker of what texel `texel` of face `face` stores.
float shadow_texel_blocker(ShadowReceiver r, uint face, ivec2 texel) {
    float depth = texelFetch(shadow_maps, ivec3(texel, r.layer + int(face)), 0).r;
    return shadow_depth_blocker(r, face, texel, depth);
}

// The texel direction w (of any length: the face's axes divide it) falls in, and its
// fractional position from the texel centre below and left of it (for bilinear weights).
ivec2 shadow_texel(vec3 w, out uint face, out vec2 fraction) {
    vec2 ab;
    face = cube_face(w, ab);
    vec2 st = (ab * 0.5 + 0.5) * float(shadow_data.settings.x) - 0.5;
    vec2 base = floor(st);
    fraction = st - base;
    return ivec2(base);
}

// The fraction of the light's point arriving along w: the texels' comparisons weighted
// bilinearly (percentage-closer filtering, Reeves et al. 1987), clamped at the face's edge.
// One gather reads the 2×2 texels, at the corner they share: the sampler's clamp to the
// edge picks the same texels as clamping their indices, and sampling at the footprint's
// centre leaves no rounding to move it.
float shadow_bilinear(ShadowReceiver r, vec3 w) {
    uint face;
    vec2 f;
    ivec2 base = shadow_texel(w, face, f);
    int last = int(shadow_data.settings.x) - 1;
    vec2 corner = (vec2(base) + 1.0) / float(shadow_data.settings.x);
    // Gather order is (0, 1), (1, 1), (1, 0), (0, 0) from base; wzxy puts it in rows.
    vec4 depths = textureGather(shadow_maps, vec3(corner, float(r.layer + int(face)))).wzxy;
    float lit = 0.0;
    uint blocked = 0u;
    for (int j = 0; j < 2; ++j) {
        for (int i = 0; i < 2; ++i) {
            float weight = (i == 0 ? 1.0 - f.x : f.x) * (j == 0 ? 1.0 - f.y : f.y);
            ivec2 texel = clamp(base + ivec2(i, j), ivec2(0), ivec2(last));
            float distance;
            bool blocker = shadow_depth_blocks(r, face, texel, depths[2 * j + i], distance);
            lit += blocker ? 0.0 : weight;
            blocked += blocker ? 1u : 0u;
        }
    }
    // The weights' fp32 sum need not be 1: all lit is exactly lit, all blocked exactly dark.
    return blocked == 0u ? 1.0 : blocked == 4u ? 0.0 : lit;
}

// Interleaved gradient noise (Jimenez 2014): a per-pixel rotation of the taps, which
// turns the banding of a fixed pattern into fine noise. An image-space term, no twin.
float interleaved_gradient_noise(vec2 pixel) {
    return fract(52.9829189 * fract(dot(pixel, vec2(0.06711056, 0.00583715))));
}

// What light i's comparisons at p share, and w the unit direction from the light to p;
// false where its map says nothing: without a map, outside the faces' depth range, or
// with the light behind the triangle seen from the eye, towards `to_eye` (then only the
// subsurface term lights p, through its own object, which does not shadow it, as `argil
// reference` has it: the map, which cannot tell that object from others, is not read).
// `face_normal` is the receiver's triangle's, from derivatives taken before any branch.
bool shadow_receiver(uint i, vec3 p, vec3 face_normal, vec3 to_eye, out ShadowReceiver r, out vec3 w) {
    ShadowLight s = shadow_data.lights[i];
    if (s.map.x < 0.0) return false;
    vec3 q = p - frame.lights[i].position.xyz;
    vec3 m = abs(q);
    float q_major = max(max(m.x, m.y), m.z);
    if (q_major <= s.map.z || q_major >= s.map.w) return false;
    float d = length(q);
    w = q / d;
    float n2 = dot(face_normal, face_normal);
    vec3 n = n2 > 0.0 ? face_normal * inversesqrt(n2) : w;
    if (n2 > 0.0 && dot(n, q) * dot(n, to_eye) >= 0.0) return false;
    r = ShadowReceiver(int(s.map.x), s.map.z, s.map.w, n, dot(q, n), d);
    return true;
}

// The texel of the map nearest to direction w, on face `face`.
ivec2 shadow_nearest_texel(vec3 w, out uint face) {
    vec2 f;
    ivec2 texel = shadow_texel(w, face, f);
    return clamp(texel + ivec2(greaterThan(f, vec2(0.5))), ivec2(0), ivec2(int(shadow_data.settings.x) - 1));
}

// The hard shadow of point light i at the pixel's point p, 1 without a map:
// point_light_shadow's one tap at a light of radius 0, for the draws that read the soft
// lights' shadows elsewhere.
float hard_light_shadow(uint i, vec3 p, vec3 face_normal) {
    ShadowReceiver r;
    vec3 w;
    return shadow_receiver(i, p, face_normal, frame.camera_position.xyz - p, r, w) ? shadow_bilinear(r, w) : 1.0;
}

// The fraction of point light i that reaches p, 1 without a map or where the light
// `may_shadow` nothing at p (as ObjectPush.shadowing_lights says of a draw's object): PCSS,
// the blockers' mean distance searched in the cone from p towards the light's sphere, then
// the comparisons filtered over the penumbra they give; 1 where the search finds none. A
// light of radius 0 has the hard shadow of one bilinear lookup, the filter's one tap at
// w. `face_normal` is the receiver's plane, its triangle's at a pixel, which is what the
// map stores: cross(dFdx(p), dFdy(p)), taken in uniform control flow; `to_eye` the side
// it is seen from; `pixel` turns the taps.
// The hard shadow is the filter's tap rather than a branch of its own: lavapipe runs both
// sides of a branch, so its lookup would run for every pixel beside PCSS's. The loops'
// counts vary by pixel; kept as loops, each stops once no pixel of its batch has an
// iteration left.
float point_light_shadow(uint i, vec3 p, vec3 face_normal, vec3 to_eye, vec2 pixel, bool may_shadow) {
    ShadowReceiver r;
    vec3 w;
    bool receives = shadow_receiver(i, p, face_normal, to_eye, r, w) && may_shadow;
    float d = r.distance;
    float radius = shadow_data.lights[i].map.y;
    bool soft = SOFT_SHADOWS && radius > 0.0;

    mat3 tangent = tangent_frame(w);
    float texel_angle = 2.0 / float(shadow_data.settings.x);
    float rotation = TWO_PI * interleaved_gradient_noise(pixel);
    vec2 rotated = vec2(cos(rotation), sin(rotation));
    // Blockers a third of the way from the light or further: their penumbra is at most
    // 2r/d wide seen from it.
    float search = max(2.0 * radius / d, texel_angle);
    float blockers = 0.0;
    float count = 0.0;
    vec2 direction = rotated;
    [[dont_unroll]]
    for (uint k = 0u; k < (receives && soft ? SHADOW_TAPS : 0u); ++k) {
        vec2 o = vogel_disk_step(k, SHADOW_TAPS, direction) * search;
        uint face;
        ivec2 nearest = shadow_nearest_texel(w + tangent[0] * o.x + tangent[1] * o.y, face);
        float blocker = shadow_texel_blocker(r, face, nearest);
        blockers += blocker;
        count += blocker > 0.0 ? 1.0 : 0.0;
    }
    uint taps = !receives ? 0u : !soft ? 1u : count > 0.0 ? SHADOW_TAPS : 0u;
    float filter_radius = soft ? max(penumbra_angle(radius, d, blockers / count), texel_angle) : 0.0;
    float lit = 0.0;
    direction = rotated;
    [[dont_unroll]]
    for (uint k = 0u; k < taps; ++k) {
        vec2 o = vogel_disk_step(k, taps, direction) * filter_radius;
        lit += shadow_bilinear(r, w + tangent[0] * o.x + tangent[1] * o.y);
    }
    return taps == 0u ? 1.0 : lit / float(taps);
}

#endif
