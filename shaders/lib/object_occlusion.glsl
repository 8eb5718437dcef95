// Occlusion of the environment's light by the other objects, beyond GTAO's screen-space
// radius ([occlusion] objects): each object is spheres (src/scene/occluders.rs) in
// FrameData.occluders. A sphere hides the environment's light of the cone it subtends
// and sends back what it reflects of the light it receives itself. The cap's cosine-
// weighted share of the hemisphere is Snyder 1996's form factor (occlusion.glsl's
// sphere_cap_irradiance, twin in src/brdf/object_occlusion.rs).
#ifndef ARGIL_OBJECT_OCCLUSION_GLSL
#define ARGIL_OBJECT_OCCLUSION_GLSL
#include "scene_data.glsl"
#include "environment.glsl"

// Whether the frame has occluders (src/render/forward.rs); off, no code reads them.
layout(constant_id = 13) const bool OBJECT_OCCLUSION = false;

// Where a draw's occlusion by the other objects comes from (src/render/gpu_scene.rs's
// ObjectsOcclusionFrom): every pixel's spheres, its vertices' (forward.vert), or the
// ground's occlusion map (ground_occlusion.glsl). A constant, so that a pipeline holds
// one of the three: lavapipe runs every branch, and each of the others reads the
// environment, spheres or a map.
layout(constant_id = 14) const uint OBJECTS_OCCLUSION_FROM = 0u;
const uint OBJECTS_OCCLUSION_FROM_PIXELS = 0u;
const uint OBJECTS_OCCLUSION_FROM_VERTICES = 1u;
const uint OBJECTS_OCCLUSION_FROM_GROUND_MAP = 2u;

// The environment's radiance averaged over the cone of angular radius α about d: the
// radiance map's mip whose texels have the cone's solid angle, 2π (1 − cos α), with
// 1 − cos α written sin²α/(1 + cos α), exact for small cones.
vec3 env_cone_radiance(vec3 d, float sin_alpha) {
    if (env_kind() == ENV_UNIFORM) return env.radiance.rgb;
    float sin2 = sin_alpha * sin_alpha;
    float solid_angle = TWO_PI * sin2 / (1.0 + sqrt(max(1.0 - sin2, 0.0)));
    return env_radiance(d, filtered_lod(1.0 / solid_angle, env.texel.x));
}

// What the occluders make of the environment's diffuse irradiance at p, of normal n, as
// a factor per channel: each sphere takes π F (L_cone − L_sphere) from the open
// irradiance E(n), F its cap's form factor, L_cone the environment's mean radiance over
// the cap and L_sphere = ρ E(−w)/π the radiance of its side facing p (the environment's
// light on that side, reflected by its albedo; what lights that side is not occluded in
// turn). Spheres combine by multiplying their visibilities, 1 − π F ΔL / E(n): exact for
// disjoint caps of a uniform environment taking little each, and overlapping caps (the
// torus's neighbouring spheres) count their overlap twice. Spheres of the object p is on,
// the run `own` (first, count) of frame.occluders, take nothing: the object's own occlusion
// is GTAO's; skipped by the loop, they cost nothing. A point inside another object's
// sphere (the ground under the torus's spheres, which reach below its tube) sees it as
// touching, as on its surface, so that the occlusion is continuous there.
vec3 object_occlusion(vec3 p, vec3 n, uvec2 own) {
    vec3 factor = vec3(1.0);
    if (!OBJECT_OCCLUSION || env_kind() == ENV_NONE) return factor;
    vec3 open = PI * env_irradiance_over_pi(n);
    for (uint k = 0u; k < frame.counts.w - own.y; ++k) {
        Occluder o = frame.occluders[k < own.x ? k : k + own.y];
        vec3 to_centre = o.sphere.xyz - p;
        float d2 = dot(to_centre, to_centre);
        if (d2 == 0.0) continue;
        float inv_d = inversesqrt(d2);
        vec3 w = to_centre * inv_d;
        float sin_alpha = min(o.sphere.w * inv_d, 1.0);
        float f = sphere_cap_irradiance(dot(n, w), sin_alpha);
        if (f <= 0.0) continue;
        vec3 hidden = env_cone_radiance(w, sin_alpha) - o.albedo.rgb * env_irradiance_over_pi(-w);
        factor *= max(vec3(1.0) - PI * f * hidden / max(open, vec3(1e-6)), vec3(0.0));
    }
    return factor;
}

#endif
