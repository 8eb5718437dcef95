// Fixed tap patterns of the filters and gathers (shadows.glsl, bounce.glsl); the f64 twins,
// and the test of the gather they give, are in src/brdf/bounce.rs.
#ifndef ARGIL_SAMPLING_GLSL
#define ARGIL_SAMPLING_GLSL

const float GOLDEN_ANGLE = 2.39996323;

// Tap k of n on a Vogel disk of unit radius turned by `rotation` (Vogel 1979: radius
// √((k + ½)/n), angle k × the golden angle).
vec2 vogel_disk(uint k, uint n, float rotation) {
    float radius = sqrt((float(k) + 0.5) / float(n));
    float angle = float(k) * GOLDEN_ANGLE + rotation;
    return radius * vec2(cos(angle), sin(angle));
}

// The turn by the golden angle from one tap's angle to the next, (cos, sin).
const vec2 GOLDEN_TURN = vec2(cos(GOLDEN_ANGLE), sin(GOLDEN_ANGLE));

// vogel_disk's taps in order, for loops that lavapipe does not unroll: tap k of n, with
// `direction` (cos, sin) of its angle, which starts at the rotation's and is turned here
// for tap k + 1 by a complex product. Its cos and sin at every tap, polynomials on
// lavapipe, were a ninth of the default scene's frame in a soft shadow's 32 taps.
vec2 vogel_disk_step(uint k, uint n, inout vec2 direction) {
    vec2 tap = sqrt((float(k) + 0.5) / float(n)) * direction;
    direction = vec2(direction.x * GOLDEN_TURN.x - direction.y * GOLDEN_TURN.y,
                     direction.x * GOLDEN_TURN.y + direction.y * GOLDEN_TURN.x);
    return tap;
}

// Tap k of n spread evenly over the hemisphere below the horizon (−y), each standing for
// the solid angle 2π/n: heights evenly spaced in (−1, 0), each turned from the last by the
// golden angle (a spherical Fibonacci set, González 2010).
vec3 lower_hemisphere_tap(uint k, uint n) {
    float y = -(float(k) + 0.5) / float(n);
    float r = sqrt(max(1.0 - y * y, 0.0));
    float angle = float(k) * GOLDEN_ANGLE;
    return vec3(r * cos(angle), y, r * sin(angle));
}

// Tap k of n of a cosine-weighted hemisphere about +z: Vogel disk point k lifted onto the
// hemisphere (Malley's method, pbrt-v4 §A.5.3).
vec3 cosine_hemisphere_tap(uint k, uint n) {
    vec2 d = vogel_disk(k, n, 0.0);
    return vec3(d, sqrt(max(1.0 - dot(d, d), 0.0)));
}

#endif
