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

// Tap k of n of a cosine-weighted hemisphere about +z: Vogel disk point k lifted onto the
// hemisphere (Malley's method, pbrt-v4 §A.5.3).
vec3 cosine_hemisphere_tap(uint k, uint n) {
    vec2 d = vogel_disk(k, n, 0.0);
    return vec3(d, sqrt(max(1.0 - dot(d, d), 0.0)));
}

#endif
