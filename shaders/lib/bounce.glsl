// Light bounced once off the ground onto what stands above it ([shadows] bounce;
// src/render/gpu_scene.rs picks the ground: the largest builtin:plane). The environment's
// light (environment.glsl) arrives from every direction, the ground's too; the ground is
// instead a Lambertian emitter of radiance ρ_g/π (E_lights(x) + E_env), E_lights the point
// lights' irradiance at x as their shadow maps see it (the ground's light map,
// ground_light.glsl) and E_env the environment's on an open upward plane. A surface point
// above it gathers the difference of the two radiances over its hemisphere with
// cosine-weighted taps (the estimator E = π/K Σ ΔL(x_k), pbrt-v4 §13.2), each tap where
// its ray meets the ground, none where it misses the ground's square; the environment's
// radiance along a tap is its cosine-blurred irradiance E(d)/π, which its diffuse light
// is made of. Occlusion of the ground by other objects is not traced. The f64 twin is in
// src/brdf/bounce.rs; the gather measured in docs/scene-format.md.
#ifndef ARGIL_BOUNCE_GLSL
#define ARGIL_BOUNCE_GLSL
#include "scene_data.glsl"
#include "shading.glsl"
#include "ground_light.glsl"
#include "environment.glsl"

// Taps of the gather (sampling.glsl's cosine_hemisphere_tap): src/brdf/bounce.rs's
// BOUNCE_TAPS.
const uint BOUNCE_TAPS = 8u;

// Whether the pipeline holds the gather (src/render/forward.rs). Off, a frame without a
// bounce holds none of it, which lavapipe would otherwise run behind the uniform flag
// below; the generic pipeline holds it and reads the flag.
layout(constant_id = 15) const bool BOUNCE = false;

// The ground's light map (ground_light.glsl), E_lights over the ground's square.
layout(set = 5, binding = 0) uniform sampler2D ground_light_map;

// The environment's irradiance over π on a surface facing d (its blurred radiance along d).
vec3 bounce_environment(vec3 d) {
    if (env_kind() == ENV_NONE) return vec3(0.0);
    return env_irradiance_over_pi(d);
}

// The irradiance that the ground below p, of unit normal n, adds to the environment's (or
// takes from it, where the ground is darker than the sky); 0 on the ground itself and
// below it, or without a bounce.
vec3 ground_bounce_irradiance(vec3 p, vec3 n) {
    float height = p.y - frame.ground.y;
    if (!BOUNCE || frame.ground_albedo.a <= 0.0 || height <= 0.0 || n.y >= 1.0) return vec3(0.0);
    mat3 basis = tangent_frame(n);
    vec3 ground_environment = PI * bounce_environment(vec3(0.0, 1.0, 0.0));
    vec3 lights = vec3(0.0);
    vec3 environment = vec3(0.0);
    for (uint k = 0u; k < BOUNCE_TAPS; ++k) {
        vec3 d = basis * cosine_hemisphere_tap(k, BOUNCE_TAPS);
        if (d.y >= 0.0) continue;
        vec3 x = p + d * (height / -d.y);
        vec2 offset = abs(x.xz - frame.ground.xz);
        if (max(offset.x, offset.y) > frame.ground.w) continue;
        lights += ground_environment + textureLod(ground_light_map, ground_light_uv(x), 0.0).rgb;
        environment += PI * bounce_environment(d);
    }
    return (frame.ground_albedo.rgb * lights - environment) / float(BOUNCE_TAPS);
}

#endif
