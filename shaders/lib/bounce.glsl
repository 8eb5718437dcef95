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
// is made of. Occlusion of the ground by other objects is not traced. On a finely
// tessellated mesh the gather runs at the vertices, at the mesh's normal, with its change
// with the normal to first order, which carries it to each pixel's mapped normal
// (bounce_at_pixel): shaders/vertex_light.comp gathers them once for every frame that
// reads them (forward.vert). On a coarse mesh it runs at the pixels. The f64 twin is in
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

// Whether the draw gathers at its vertices (vertex_light.comp, then bounce_at_pixel) or at its
// pixels: src/scene/mod.rs's Scene::bounce_at_vertices, by the mesh's tessellation.
layout(constant_id = 23) const bool BOUNCE_AT_VERTICES = false;

// The ground's light map (ground_light.glsl), E_lights over the ground's square.
layout(set = 5, binding = 0) uniform sampler2D ground_light_map;

// The environment's irradiance over π on a surface facing d (its blurred radiance along d).
vec3 bounce_environment(vec3 d) {
    if (env_kind() == ENV_NONE) return vec3(0.0);
    return env_irradiance_over_pi(d);
}

// π ΔL along the downward direction d from p, `height` above the ground: the ground's
// radiance where d meets it, ρ_g (E_lights + E_env(+y))/π with ground_environment =
// E_env(+y), less the environment's E_env(d)/π that it hides, times π; 0 where d misses
// the ground's square.
vec3 ground_tap(vec3 p, vec3 d, float height, vec3 ground_environment) {
    vec3 x = p + d * (height / -d.y);
    vec2 offset = abs(x.xz - frame.ground.xz);
    if (max(offset.x, offset.y) > frame.ground.w) return vec3(0.0);
    vec3 lit = ground_environment + textureLod(ground_light_map, ground_light_uv(x), 0.0).rgb;
    return frame.ground_albedo.rgb * lit - PI * bounce_environment(d);
}

// Whether the frame has a bounce.
bool bounces() {
    return BOUNCE && frame.ground_albedo.a > 0.0;
}

// src/brdf/bounce.rs's MIN_BOUNCE_HEIGHT.
const float MIN_BOUNCE_HEIGHT = 1e-4;

// p's height above the ground for the gather. A vertex on the ground (where a ball rests
// on it) or below it (a mesh sunk into it) gathers as the surface just above it, where
// its triangles' pixels are seen: at the ground itself every tap would meet it at p.
float bounce_height(vec3 p) {
    return max(p.y - frame.ground.y, MIN_BOUNCE_HEIGHT);
}

// The irradiance that the ground below p, of unit normal n, adds to the environment's (or
// takes from it, where the ground is darker than the sky); 0 facing straight up, or
// without a bounce.
vec3 ground_bounce_irradiance(vec3 p, vec3 n) {
    if (!bounces() || n.y >= 1.0) return vec3(0.0);
    float height = bounce_height(p);
    mat3 basis = tangent_frame(n);
    vec3 ground_environment = PI * bounce_environment(vec3(0.0, 1.0, 0.0));
    vec3 sum = vec3(0.0);
    for (uint k = 0u; k < BOUNCE_TAPS; ++k) {
        vec3 d = basis * cosine_hemisphere_tap(k, BOUNCE_TAPS);
        if (d.y < 0.0) sum += ground_tap(p, d, height, ground_environment);
    }
    return sum / float(BOUNCE_TAPS);
}

// Taps of the gradient (sampling.glsl's lower_hemisphere_tap): src/brdf/bounce.rs's
// BOUNCE_GRADIENT_TAPS.
const uint BOUNCE_GRADIENT_TAPS = 32u;

// How ground_bounce_irradiance at p changes with the normal, to first order: dE/dn, a
// column per channel. The radiance the ground adds, ΔL, to first order in spherical
// harmonics gives E(n) ≈ Φ/4 + D·n/2 (Ramamoorthi & Hanrahan 2001, eq. 8: Â₀ = π, Â₁ =
// 2π/3), Φ = ∫ ΔL and D = ∫ ΔL l dl over the directions below the horizon, exact for a
// uniform ground; D/2 is the gradient, from taps of 2π/32 sr each.
mat3 ground_bounce_gradient(vec3 p) {
    if (!bounces()) return mat3(0.0);
    float height = bounce_height(p);
    vec3 ground_environment = PI * bounce_environment(vec3(0.0, 1.0, 0.0));
    mat3 sum = mat3(0.0);
    // Run once a vertex, when the bounce changes: a loop compiles in a fraction of the time.
    [[dont_unroll]]
    for (uint k = 0u; k < BOUNCE_GRADIENT_TAPS; ++k) {
        vec3 d = lower_hemisphere_tap(k, BOUNCE_GRADIENT_TAPS);
        sum += outerProduct(d, ground_tap(p, d, height, ground_environment));
    }
    // D/2 = ½ Σ ΔL_k d_k 2π/K, each tap π ΔL_k.
    return sum / float(BOUNCE_GRADIENT_TAPS);
}

// The gather at a vertex and its gradient as vertex_light.comp stores them and forward.vert
// reads them: per channel c, (E_c, dE_c/dn).
struct BounceAtVertex {
    vec4 channels[3];
};

BounceAtVertex bounce_at_vertex(vec3 irradiance, mat3 gradient) {
    return BounceAtVertex(vec4[3](vec4(irradiance.r, gradient[0]), vec4(irradiance.g, gradient[1]),
                                  vec4(irradiance.b, gradient[2])));
}

vec3 gathered_irradiance(BounceAtVertex b) {
    return vec3(b.channels[0].x, b.channels[1].x, b.channels[2].x);
}

mat3 gathered_gradient(BounceAtVertex b) {
    return mat3(b.channels[0].yzw, b.channels[1].yzw, b.channels[2].yzw);
}

// The bounce at a pixel of shading normal n: the gather at the mesh's normal, interpolated
// from the vertices with its gradient (forward.vert), moved along the gradient from the
// interpolated normal n_geometric to n, which a normal map bends. On a back face, whose
// n_geometric is the front's turned over, the move is the first-order difference of the
// two sides.
vec3 bounce_at_pixel(vec3 at_mesh_normal, mat3 gradient, vec3 n, vec3 n_geometric) {
    return at_mesh_normal + (n - n_geometric) * gradient;
}

#endif
